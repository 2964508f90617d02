//! Models that predict the measured output one step ahead, with the observer's chain.
//!
//! A [`Predictor`] owns the model state x̂, the extended state(s) and the placement of the
//! correction increments of a [`crate::law::Correction`] on its three chain levels:
//!
//! | predictor | level 1 | level 2 | level 3 |
//! |---|---|---|---|
//! | [`SecondOrderPredictor`] (physics mode, eqs 2.26, 3.8) | X̂₁ (measured) | T·X̂₂ | T²·d̂ (lumped uncertainty/fault in the X₂ equation) |
//! | [`ArxLaguerrePredictor`] (eqs 2.28, 4.11) | state along the fault direction f | d̂ (fault, enters along f) | χ̂ (rate of d̂) |
//!
//! Levels are scaled so that one sample is one unit of time: all laws act on a chain that is
//! close to a discrete integrator chain, and a single set of per-sample gains and bounds applies
//! to every model (see `docs/equations/observers.md`).

use crate::law::Correction;

/// A one-step-ahead output predictor with output injection and an extended state.
pub trait Predictor {
    /// ŷ(k), the prediction of the measured output from data up to k − 1.
    fn output(&self) -> f64;
    /// Advance to k + 1 given the measurement y(k), input u(k), error e(k) = y(k) − ŷ(k) and
    /// the law's increments.
    fn advance(&mut self, y: f64, u: f64, e: f64, c: Correction);
    /// The fault / lumped-uncertainty estimate d̂(k) in the model's physical units.
    fn fault_estimate(&self) -> f64;
    /// The fault-equivalent of one sample's increments (Utkin's equivalent output injection), in
    /// the units of [`Predictor::fault_estimate`]: the part of the lumped uncertainty the law
    /// is cancelling directly rather than through the extended state.
    fn equivalent_fault(&self, c: &Correction) -> f64;
    /// Largest magnitude among ŷ and the extended states, in output units (for divergence
    /// detection).
    fn magnitude(&self) -> f64;
    /// Return to the initial state.
    fn reset(&mut self);
    /// Number of model states (not counting extended states).
    fn order(&self) -> usize;
}

mod arx;
mod fal;
mod mode;
mod model;

pub use arx::ArxLaguerrePredictor;
pub use fal::FalPredictor;
pub use mode::{ModalParams, SecondOrderPredictor, discretize_mode};
#[allow(deprecated)]
pub use model::LinearModel;
pub use model::{LAGUERRE_STRUCTURE_TOLERANCE, LaguerreStructure, StateSpace};
