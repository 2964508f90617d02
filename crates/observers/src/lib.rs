//! State observers for bearing fault diagnosis (Piltan 2020): APIO, SMO, HOSTSMO, FLO, VSO,
//! PFLO, ALPIO, SMALPIO, ASMO, AFSMO.
//!
//! Every observer is the same loop (see `docs/equations/observers.md`):
//!
//! ```text
//! ŷ(k) = h(x̂(k)),  e(k) = y(k) − ŷ(k) = r(k)
//! x̂(k+1) = f(x̂(k), y(k), u(k)) + [c₁, c₂] + extended state d̂(k)
//! d̂(k+1) = d̂(k) + c₃ (or c₂ for ARX-Laguerre)
//! ```
//!
//! with a [`Predictor`] (the model: a physics mode or an ARX-Laguerre model) and a
//! [`CorrectionLaw`] (linear/PI, sign, super-twisting, Levant, fuzzy-scheduled) composed in an
//! [`Observer`]. The ten named observers are in [`named`]; [`build_observer`] builds any kind on
//! any model for the pipelines.
//!
//! Dependencies and why: `nalgebra` (small dense matrices and the matrix exponential for gain
//! design, the LMI check and exact discretisation, all off the per-sample path);
//! `bearing-model` (the housing mode of the 5-DOF model, [`ModalParams::from_bearing_model`]);
//! `laguerre-id` (the state-space type [`StateSpace`] the ARX-type observers run, and
//! its `MAX_STATES` bound for the fixed-size O(n) Laguerre cascade of
//! [`ArxLaguerrePredictor`]);
//! `fuzzy-ts` (the fuzzy ARX-Laguerre model and Table 5.1 inference, [`FalPredictor`]);
//! `serde` (parameter structs are serialisable for reports); `thiserror` (the one error enum).

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

pub mod design;
pub mod error;
pub mod law;
pub mod named;
pub mod observer;
pub mod predictor;
pub mod scenarios;

pub use design::{LinearDesign, estimate_bound, kalman_predictor_gain, verify_lmi_2_34};
pub use error::ObserverError;
pub use law::{
    Correction, CorrectionLaw, FuzzyScheduleParams, FuzzyScheduled, HomogeneousLaw, LawFamily,
};
pub use named::{
    AnyObserver, ArxObserver, FalObserver, FaultDirection, ModelConfig, NamedLaw, ObserverKind,
    ObserverSettings, PhysicsObserver, build_observer, design_innovations, design_path_linear,
    path_observer,
};
pub use observer::{Observer, ObserverOutput, RunObserver, StepOutput};
#[allow(deprecated)]
pub use predictor::LinearModel;
pub use predictor::{
    ArxLaguerrePredictor, FalPredictor, LAGUERRE_STRUCTURE_TOLERANCE, LaguerreStructure,
    ModalParams, Predictor, SecondOrderPredictor, StateSpace,
};
