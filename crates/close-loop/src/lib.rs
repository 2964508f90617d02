//! Close the loop with measured data: run a declared model against a recording, find what the
//! residual holds, trace it to an effect the model lacks, add that effect, and report the held-out
//! error before and after, effect by effect (architecture brief, "Closing the loop").
//!
//! # Dependencies and why
//! - `residual-features`: the Welch PSD, Hilbert envelope and FFT (one implementation in the
//!   workspace); this crate adds only the zoom DFT, the band-pass mode and running medians.
//! - `rustfft`: its `Complex` type for the zoom DFT and the biquad response.
//! - `laguerre-id`: the ARX-Laguerre model (declared model `--model arx-laguerre`, and the model
//!   the ALPIO observer runs on).
//! - `observers`: ALPIO / HOSTSMO, which give the observer-residual RMS metric.
//! - `diagnosis`: the training-free verdict on the fitting and on the held-out segment, whose
//!   envelope evidence (on both) names the location of a fault nobody declared (one fault
//!   detector in the workspace; the loop's spectral error alone cannot tell a fault's location).
//! - `serde`: the ledger is written as JSON by `cargo xtask close-loop`.
//! - `serde_json`: the machine model ([`machine::MachineModel`]) reads and writes itself.
//! - `nalgebra`: eigenvalues of the AR companion matrix (the structural modes of [`path`]) and
//!   the small normal equations of the gain / path level / floor fit.
//! - `thiserror`: the crate's one error enum.
//! - `rand` + `rand_xoshiro`: SplitMix64, the seeded generator of the loop's and the rig's noise
//!   (the same generator `classify` splits windows with).
//! - `bearing-model`: the 5-DOF physics model behind [`physics::PhysicsModel`].
//! - `bearing-data`: [`SampleUnit`], the recording's unit the reports state (the input layer's
//!   one unit type).
//! - `sampled-signal`: [`Signal`], the checked recording (samples and rate) the entry points
//!   ([`close_loop`], [`close_loop_from`], [`machine::calibrate`]) take.
//!
//! The declared model comes in through the [`DeclaredModel`] trait, so this crate needs no
//! simulator of its own; [`scenario::PhenomenologicalModel`] is a small impact-train model used by
//! the tests, benches and as a fallback.

mod config;
mod declared;
pub mod effect;
mod engine;
mod error;
pub mod machine;
pub mod metric;
pub mod observe;
mod optimize;
pub mod path;
pub mod physics;
pub mod report;
mod runner;
pub mod scenario;
pub mod spectrum;

pub use bearing_data::SampleUnit;
pub use config::{CheckedConfig, LoopConfig};
pub use declared::{
    BearingSpec, DeclaredFault, DeclaredModel, OperatingPoint, impact_orders, parse_fault,
    response_ratio,
};
pub use effect::{Effect, EffectKind, Placement};
pub use error::CloseLoopError;
pub use report::{
    AcceptedOn, EffectEntry, KINEMATIC_LINE_TOLERANCE, Ledger, Spectra, VerificationPass,
};
pub use runner::{MIN_NPERSEG, Outcome, close_loop, close_loop_from, fit_len, min_samples};
/// A recording's samples at their rate, checked (`sampled-signal`, the workspace's one type).
pub use sampled_signal::{Signal, SignalError};

/// The README's examples, compiled as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// Contact preloads of the balls the loop's preload candidate tries, m (a negative clearance:
/// every ball loaded), and the calibrated rig's calibration too (`calibrated-rig`).
pub const PRELOADS_M: &[f64] = &[0.0, 0.5e-6, 1e-6, 2e-6, 4e-6, 8e-6];
