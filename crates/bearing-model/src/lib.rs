//! 5-DOF Lagrange rolling-element bearing model, fault geometry and simulation
//! (Piltan 2020, chapters 2–3: eqs. (2.1)–(2.26), (3.1)–(3.8), Table 2.1).
//!
//! * [`geometry`]: bearing geometry and kinematics (BPFO, BPFI, FTF, ball spin and
//!   ball-defect rate, eq. 2.8), SKF 6205 and 6203 built in.
//! * [`catalog`]: common rolling bearings by designation (60xx/62xx/63xx, UC2xx inserts, the
//!   bearings of public data sets), each with the source of its geometry.
//! * [`params`]: the two parameter sets (Table 2.1 as printed, a consistent CWRU set) and the
//!   optional effects (radial load, shaft harmonics, speed offset, ΔM/ΔC/ΔK, slip).
//! * [`fault`]: spalls on the inner race, outer race and a ball, in any combination.
//! * [`state_space`]: the model as `ẋ = f(t, x, u)`, `y = H x + y₀`, an RK4 step, the linear
//!   parts `M, C, K`, a linearization: what an observer runs as its predictor.
//! * [`simulate()`]: recordings at any sampling rate (housing acceleration in m/s², all states
//!   on request).
//! * [`scenario`]: one-liners for CWRU-like and SHSE-like recordings.
//! * [`machine`]: phenomenological recordings of whole machines (m/s²; structure, shaft comb,
//!   once-per-rev impacts, gear mesh, electrical lines, sensor noise, ADC, a localized fault),
//!   fast enough for detector corpora of hundreds of recordings — no ODE.
//! * [`life`]: simulated degradation runs with known truth (a healthy stretch, a spall that
//!   appears at a known recording and grows; speed drift, load and sensor-gain steps before
//!   the onset too), seeded, each recording generated independently.
//!
//! # Dependencies and why
//!
//! * `nalgebra`: fixed-size `SVector<f64, 10>` states and 5×5 matrices live on the stack, so
//!   the integrator's inner loop allocates nothing.
//! * `rand`, `rand_chacha`, `rand_distr`: seeded, platform-independent streams (ChaCha8) for
//!   slip, ΔM/ΔC/ΔK and noise; separate streams so switching one effect does not shift another.
//! * `serde`: parameter structs can be written next to a recording.
//! * `thiserror`: the one typed error enum [`ModelError`].
//!
//! # Example
//!
//! ```
//! use bearing_model::{FaultClass, Scenario};
//! let rec = Scenario::cwru(FaultClass::Outer, 0.007, 1797.0)?
//!     .with_duration(0.1)
//!     .simulate()?;
//! assert_eq!(rec.accel.len(), 1200); // 12 kHz
//! # Ok::<(), bearing_model::ModelError>(())
//! ```

pub mod catalog;
pub mod error;
pub mod fault;
pub mod geometry;
pub mod life;
pub mod machine;
pub mod params;
pub mod scenario;
pub mod simulate;
pub mod spec;
pub mod state_space;

pub use catalog::{BearingKind, CatalogEntry, Length};
pub use error::{ModelError, Result};
pub use fault::{FaultClass, FaultLocation, FaultSet, Spall};
pub use geometry::{Bearing, BearingGeometry, FaultOrders};
pub use params::{
    Contact, G, Gravity, Housing, ModelSpec, ParamSet, ShaftHarmonic, ShaftSpeed, Slip, Structure,
    Uncertainty,
};
pub use scenario::Scenario;
#[allow(deprecated)]
pub use simulate::Recording;
pub use simulate::{Integrator, Noise, SimConfig, SimulatedRecording, simulate};
pub use spec::BearingSpec;
pub use state_space::{
    BallFrame, BearingModel, DofVector, Input, LinearParts, MAX_BALLS, N_DOF, STATE_DIM, State,
};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
