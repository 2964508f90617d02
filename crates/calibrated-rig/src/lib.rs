//! The calibrated rig simulator: the 5-DOF bearing model behind the measured paths of a rig.
//!
//! A simulated recording of the rig is the sum of
//!
//! 1. **the healthy machine** — the [`MachineModel`] the loop calibrated on a healthy recording:
//!    its structural path `1/A(z)` driven by white excitation at the identified level, its white
//!    noise floor and its lines (shaft orders at the calibrated speed ratio, tones), each line with
//!    a seeded random phase; plus the healthy recording's *remainder*, the smoothed PSD the
//!    model's named effects leave, as shaped noise ([`RigModel::background_fir`]);
//! 2. **the fault** — the 5-DOF model's (eqs. 2.12–2.25) housing acceleration with the spalls of
//!    the class, its sprung-mass resonance moved out of band ([`EXCITATION_HOUSING_HZ`], ζ 0.7) so
//!    that it is the bearing's local response to the contact forces, seen through the rig's
//!    *impact path* `1/A_i(z)` and scaled by a severity gain `g(location, size)`. Two calibrated
//!    quantities make the impacts as irregular as measured ones: a *random fraction* of the
//!    excitation's power is replaced by a phase-randomised copy (rough contact without the impact
//!    timing), and a *strike gate* lets the impacts through only part of the time (the severity's
//!    *strike fraction*, in bursts of [`BURST_PERIODS`] fault periods on average): the defect
//!    does not strike every time — a spall's edges wear and clog, a ball's spin axis wanders and
//!    carries its defect off the rolling track — so measured fault lines stand 5–50 dB over their
//!    envelope-spectrum neighbours where a perfectly periodic train stands 30–60 dB.
//!
//! [`calibrate_rig`] fits the free quantities on measured records: the healthy machine on a
//! healthy recording (the loop, [`close_loop::machine::calibrate`]); one impact path per fault
//! location and spall size as the AR model (Levinson) of the mean ratio of that location's and
//! size's training records' excess PSD (measured minus healthy) to the simulated excitation's
//! PSD, both smoothed over ±150 Hz (each CWRU fault size is a separate bearing, seeded and
//! mounted on its own: its path differs from the other sizes' while the load barely changes
//! it); a spall of another size is seen through the nearest calibrated size's path; the severity gain of
//! each training record in closed form from its excess mean square, its random fraction from its
//! kurtosis and its strike fraction from its fault line's prominence in the envelope spectrum
//! (outer-race records off 6 o'clock get their own, used at their position:
//! [`Severity::outer_angle_rad`]).
//! Calibration uses signal statistics only (PSDs, RMS, kurtosis, line prominence), never a label beyond the catalogued fault location and size,
//! and never an accuracy. Between calibrated sizes the gain is interpolated log-log; outside
//! them the nearest calibrated gain is held (stated in every report).
//!
//! [`signal_stats`] gives what a simulated and a measured recording are compared on: RMS,
//! kurtosis, crest factor, band energies and the prominence of the fault line in the envelope
//! spectrum.
//!
//! # Dependencies and why
//! - `close-loop`: the healthy machine model a rig stands on (its calibration, structural path,
//!   lines), Welch and envelope spectra, and the one error enum the rig's functions return.
//! - `bearing-model`: the 5-DOF model whose contact forces excite the impact paths.
//! - `residual-features`: kurtosis (one implementation in the workspace).
//! - `rustfft`: phase randomisation of the random fraction; `rand` + `rand_xoshiro`: the seeded
//!   noise (SplitMix64, as the loop's); `rayon`: excitations simulated in parallel.
//! - `serde` / `serde_json`: the rig model's versioned JSON; `thiserror`: [`life::RigLifeError`].

use bearing_model::{Bearing, FaultClass, FaultSet, Housing, ParamSet, Scenario, Slip, Spall};
use close_loop::CloseLoopError;
use close_loop::machine::{MachineLine, MachineModel};
use close_loop::path::StructuralPath;
use close_loop::scenario::Gaussian;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

mod calibrate;
mod fault_excitation;
pub mod life;
mod lookup;
mod model;
mod stats;
mod synthesis;

pub use calibrate::{
    IMPACT_PATH_ORDER, PATH_REFINEMENTS, PRELOADS_M, RADIAL_LOADS_N, STRIKE_FRACTIONS,
    TrainingRecord, calibrate_rig,
};
pub use fault_excitation::{
    DEPTH_M, EXCITATION_HOUSING_HZ, EXCITATION_RTOL, Excitation, LEGACY_EXCITATION_HOUSING_HZ,
    SLIP_FRACTION, excitation, excitation_with,
};
pub use model::{
    CWRU_RIG_JSON, FORMAT, ImpactPath, POSITION_TOLERANCE_RAD, RigModel, RigProvenance, Severity,
    VERSION, cwru_rig,
};
pub use stats::{BANDS_HZ, Comparison, SignalStats, line_prominence_db, signal_stats};
pub use synthesis::{BURST_PERIODS, ExcitationCache, Synthesis, strike_gate};

use lookup::{fault_rate_of, nearest_path, nearest_path_at};
use model::same_position;
use synthesis::{WARMUP, apply_fir, background_of, gated, mix};

/// Where a fault sits: `bearing-model`'s [`bearing_model::FaultLocation`] (the workspace's one
/// fault-location type), under the name the rig's API has always used.
pub use bearing_model::FaultLocation as Location;

fn bad(name: &'static str, value: f64, min: f64, max: f64) -> CloseLoopError {
    CloseLoopError::ParameterOutOfRange {
        name,
        value,
        min,
        max,
    }
}

pub(crate) use close_loop::metric::mean_square;

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
