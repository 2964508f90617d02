//! Calibration of a rig on measured records (module docs of [`super`]): the healthy machine,
//! the contact preload, the impact paths, the severities, the sensor's horizontal sensitivity and
//! the measurement chain.

use super::{
    BURST_PERIODS, DEPTH_M, EXCITATION_HOUSING_HZ, Excitation, FORMAT, ImpactPath, Location,
    RigModel, RigProvenance, SLIP_FRACTION, Severity, Synthesis, VERSION, WARMUP, apply_fir,
    background_of, excitation, fault_rate_of, gated, line_prominence_db, mean_square, mix,
};
use super::{nearest_path, nearest_path_at};
use bearing_model::{Bearing, FaultClass};
use close_loop::CloseLoopError;
use close_loop::machine::{MachineLine, MachineModel};
use close_loop::path::StructuralPath;
use close_loop::spectrum::Welch;
use std::f64::consts::PI;

mod chain;
mod load_sensor;
mod paths;
mod run;

pub use paths::{IMPACT_PATH_ORDER, PATH_REFINEMENTS};
pub use run::calibrate_rig;

use chain::{background_chain, background_remainder, chain_response, chain_tones};
use load_sensor::{fit_horizontal, fit_radial_load};
use paths::{
    PathFit, SMOOTH_HZ, excess_log_ratio, fit_paths, impact_path_of, measured_excess, refine_paths,
    smooth,
};

/// Preloads the calibration tries, m (the same the loop's preload candidate tries).
pub use close_loop::PRELOADS_M;

/// Radial loads on the shaft the calibration tries, N (0 up to about the static rating of a
/// 6205's most loaded ball at the calibrated preloads).
pub const RADIAL_LOADS_N: &[f64] = &[0.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0, 3200.0];

/// Strike fractions the calibration chooses from, per training record, by the prominence of its
/// fault line in the envelope spectrum (1 = every impact strikes). The smallest, 0.05, still
/// leaves a 10 s record of a 100–160 Hz fault rate 12–20 bursts (its level then varies by some
/// 20 % from burst pattern to burst pattern, as a measured CWRU ball-fault record's own 4 s
/// stretches do).
pub const STRIKE_FRACTIONS: [f64; 9] = [1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.12, 0.08, 0.05];

fn variance(y: &[f64]) -> f64 {
    let m = y.iter().sum::<f64>() / y.len().max(1) as f64;
    y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / y.len().max(1) as f64
}

/// Kurtosis (`residual-features`'); NaN for a constant signal, which calibration never feeds it
/// (records with no excess power are refused before).
fn kurtosis(y: &[f64]) -> f64 {
    residual_features::kurtosis(y).unwrap_or(f64::NAN)
}

/// A measured or simulated training record for [`calibrate_rig`].
#[derive(Debug, Clone, Copy)]
pub struct TrainingRecord<'a> {
    /// Name (for the provenance).
    pub name: &'a str,
    /// Fault location.
    pub location: Location,
    /// Spall width, mm.
    pub size_mm: f64,
    /// Outer-race spall position, rad (6 o'clock = −π/2).
    pub outer_angle_rad: f64,
    /// Nominal speed, rpm.
    pub rpm: f64,
    /// The samples (rig units), at the rig's sampling rate.
    pub y: &'a [f64],
}
