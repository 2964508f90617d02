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
//! healthy recording (the loop, [`crate::machine::calibrate`]); one impact path per fault
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

use crate::CloseLoopError;
use crate::machine::{MachineLine, MachineModel};
use crate::path::StructuralPath;
use crate::scenario::Gaussian;
use bearing_model::{Bearing, FaultClass, FaultSet, Housing, ParamSet, Scenario, Slip, Spall};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

mod calibrate;
mod stats;

pub use calibrate::{PATH_REFINEMENTS, PRELOADS_M, RADIAL_LOADS_N, TrainingRecord, calibrate_rig};
pub use stats::{BANDS_HZ, Comparison, SignalStats, line_prominence_db, signal_stats};

/// The `format` string of a rig model file.
pub const FORMAT: &str = "hybrid-fdd/rig-model";
/// The current `version`.
pub const VERSION: u32 = 1;
/// Sprung-mass resonance of the excitation model a calibration writes, Hz (ζ 0.7): above the
/// output band (12 kHz records: 6 kHz), so that the housing acceleration is the pedestal's
/// response to the contacts (the rig's own resonances come from the identified impact path).
/// The explicit integrator's step is held at the stability limit of this heavily damped pole
/// (the tolerance does not bind, [`EXCITATION_RTOL`]), so the resonance sets the cost: 12 kHz
/// takes about 0.68 of the CPU time of the former 20 kHz (`examples/excitation_tolerance.rs`).
/// In band its transmissibility is at most +1.2 dB (5 kHz), +0.25 dB at 3 kHz, and the impact
/// paths fitted afterwards hold whatever shape the excitation has: recalibrated at 12 and
/// 14 kHz the rig's held-out statistics equal those at 20 kHz (mean |ln| band-energy error per
/// band within 0.001; docs/equations/close-loop.md). Rig files store theirs
/// ([`RigModel::excitation_housing_hz`]); those written before hold
/// [`LEGACY_EXCITATION_HOUSING_HZ`].
pub const EXCITATION_HOUSING_HZ: f64 = 12_000.0;
/// The excitation model's sprung-mass resonance of rig files written before it was stored, Hz.
pub const LEGACY_EXCITATION_HOUSING_HZ: f64 = 20_000.0;

fn legacy_housing_hz() -> f64 {
    LEGACY_EXCITATION_HOUSING_HZ
}
/// Relative tolerance of the excitation model's integration ([`bearing_model::Integrator::Adaptive`],
/// atol the default's). With the sprung mass at [`EXCITATION_HOUSING_HZ`] the adaptive step is
/// held near the explicit scheme's stability limit (about 40 µs) long before the default
/// tolerance (2e-6) binds, so a looser one costs almost no accuracy: measured against the
/// same model integrated at 1e-8 (`examples/excitation_tolerance.rs`; inner, outer and ball,
/// 300 and 1797 rpm, 1 s at 12 kHz) the output differs by ≤ 2.8e-4 relative RMS at 2e-4
/// (≤ 7.0e-6 at 2e-6), at about 2/3 of the CPU time. The gate, the phase-randomised share
/// and the impact path that follow change the recording far more than that.
pub const EXCITATION_RTOL: f64 = 2e-4;
/// Spall depth of the rig's faults (CWRU EDM depth 0.011 in), m.
pub const DEPTH_M: f64 = 0.011 * 0.0254;
/// Random slip of the rolling elements in the excitation model (fraction of the ball spacing).
pub const SLIP_FRACTION: f64 = 0.01;
/// Half width of the smoothing applied to the PSDs the impact path is fitted on, Hz.
pub(super) const SMOOTH_HZ: f64 = 150.0;
/// AR order of the impact path.
pub const IMPACT_PATH_ORDER: usize = 48;
/// Mean length of a burst of the strike gate, in fault periods (1 / fault rate): a few impacts
/// strike in a row, then the defect is off the track for a while; the gate's on/off switching
/// spreads the fault line's power over a few hertz around it, where the envelope spectrum's
/// neighbours of the line are judged.
pub const BURST_PERIODS: f64 = 4.0;
/// Strike fractions the calibration chooses from, per training record, by the prominence of its
/// fault line in the envelope spectrum (1 = every impact strikes). The smallest, 0.05, still
/// leaves a 10 s record of a 100–160 Hz fault rate 12–20 bursts (its level then varies by some
/// 20 % from burst pattern to burst pattern, as a measured CWRU ball-fault record's own 4 s
/// stretches do).
pub const STRIKE_FRACTIONS: [f64; 9] = [1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.12, 0.08, 0.05];
/// Settling samples discarded before a synthesized recording (path start-up).
pub(super) const WARMUP: usize = 4096;

/// The committed calibration of the CWRU rig (`cargo xtask calibrate-rig`): 6205 drive end,
/// 12 kHz, units g.
pub const CWRU_RIG_JSON: &str = include_str!("../../rig/cwru-12k.json");

/// The calibrated CWRU rig ([`CWRU_RIG_JSON`], validated).
///
/// # Errors
/// [`CloseLoopError::MachineModelFormat`] if the committed file is not a valid rig model.
pub fn cwru_rig() -> Result<RigModel, CloseLoopError> {
    RigModel::from_json(CWRU_RIG_JSON)
}

/// Where a fault sits: `bearing-model`'s [`bearing_model::FaultLocation`] (the workspace's one
/// fault-location type), under the name the rig's API has always used.
pub use bearing_model::FaultLocation as Location;

/// One calibrated severity: the gain that puts the 5-DOF excitation of a spall of `size_mm` at
/// `location` at the level measured on `record`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Severity {
    /// Fault location.
    pub location: Location,
    /// Spall width, mm.
    pub size_mm: f64,
    /// Gain from the excitation (m/s²) to the impact path's input (rig units).
    pub gain: f64,
    /// Fraction of the fault excitation's power that is random (white, seeded) rather than the
    /// 5-DOF impacts: the rough contact in and around the spall the 5-DOF model does not hold.
    /// Fitted so the record's kurtosis is matched (0 when the impacts alone are not impulsive
    /// enough).
    #[serde(default)]
    pub random_fraction: f64,
    /// Fraction of the time the defect strikes ([`strike_gate`]; 1 = every impact, the rig files
    /// written before the gate existed). Chosen from [`STRIKE_FRACTIONS`] so that the record's
    /// fault-line prominence in the envelope spectrum is matched.
    #[serde(default = "every_impact")]
    pub strike_fraction: f64,
    /// The training record it was fitted on.
    pub record: String,
    /// `Some(angle)` (rad, 6 o'clock = −π/2) for an outer-race severity fitted on a record
    /// with the spall at that position off the load zone's centre: spalls at that position
    /// ([`POSITION_TOLERANCE_RAD`]) use these severities; `None` (the rig files written before,
    /// and every 6 o'clock, inner-race and ball severity) for the location's reference severity,
    /// which serves every other position through the 5-DOF model's load zone and the
    /// sensor's horizontal sensitivity. Each CWRU position is a separate bearing, seeded and
    /// mounted on its own (as each size is); the model's load zone and sensor direction alone
    /// left the 0.007 in records at 12 o'clock 2× too loud and those at 3 o'clock too
    /// impulsive (results/calibration/).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_angle_rad: Option<f64>,
}

/// Two outer-race positions within this angle (rad, about 6°; CWRU's are 90° apart) are the
/// same position for [`Severity::outer_angle_rad`].
pub const POSITION_TOLERANCE_RAD: f64 = 0.1;

fn same_position(a: f64, b: f64) -> bool {
    let d = (a - b).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d) <= POSITION_TOLERANCE_RAD
}

/// The path from one fault location — and, since each CWRU fault size is a separate bearing,
/// one spall size — to the sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImpactPath {
    /// Fault location.
    pub location: Location,
    /// Spall width of the training records it was fitted on, mm; `None` for a path pooled over
    /// every size of the location (rig files written before paths were fitted per size).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size_mm: Option<f64>,
    /// AR path `1/A_i(z)`.
    pub path: StructuralPath,
    /// `Some(angle)` for an outer-race path fitted on records with the spall at that position
    /// (as [`Severity::outer_angle_rad`]): the path from a defect at 3 or 12 o'clock to the
    /// sensor is not the one from 6 o'clock; `None` for the location's reference path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_angle_rad: Option<f64>,
}

/// The path of `location` for a spall of `size_mm` among `paths`: the one fitted on the nearest
/// size (in log size; a pooled path matches every size) among the reference paths, else the
/// first path of any location.
pub(super) fn nearest_path(
    paths: &[ImpactPath],
    location: Location,
    size_mm: f64,
) -> Option<&ImpactPath> {
    nearest_path_at(paths, location, size_mm, None)
}

/// [`nearest_path`] for an outer-race spall at `outer_angle_rad`: among the paths fitted at that
/// position when `paths` holds any, else among the reference paths.
pub(super) fn nearest_path_at(
    paths: &[ImpactPath],
    location: Location,
    size_mm: f64,
    outer_angle_rad: Option<f64>,
) -> Option<&ImpactPath> {
    let distance = |p: &ImpactPath| match p.size_mm {
        Some(s) if s > 0.0 && size_mm > 0.0 => (s.ln() - size_mm.ln()).abs(),
        Some(s) => (s - size_mm).abs(),
        None => 0.0,
    };
    let at = |p: &ImpactPath| match (p.outer_angle_rad, outer_angle_rad) {
        (Some(a), Some(b)) => location == Location::Outer && same_position(a, b),
        _ => false,
    };
    let positioned = paths.iter().any(|p| p.location == location && at(p));
    paths
        .iter()
        .filter(|p| p.location == location)
        .filter(|p| {
            if positioned {
                at(p)
            } else {
                p.outer_angle_rad.is_none()
            }
        })
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .or(paths.first())
}

/// Where a rig model came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct RigProvenance {
    /// The healthy recording the machine model was calibrated on.
    pub healthy_record: String,
    /// The fault records the impact path and the severities were fitted on.
    pub training_records: Vec<String>,
    /// How the training records were chosen (a sentence).
    pub training_rule: String,
}

/// A calibrated rig (JSON, `format` = [`FORMAT`], `version` = [`VERSION`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RigModel {
    /// Always [`FORMAT`].
    pub format: String,
    /// Schema version ([`VERSION`]).
    pub version: u32,
    /// Sampling rate of the calibration, Hz (the paths are discrete-time at this rate).
    pub fs_hz: f64,
    /// Units of the synthesized signal (those of the calibration records: "g", "m/s^2",
    /// "unknown").
    pub units: String,
    /// Bearing designation of the 5-DOF model.
    pub bearing: String,
    /// The healthy machine, as calibrated on the healthy recording (its lines at that
    /// recording's levels).
    pub healthy: MachineModel,
    /// The healthy machine's lines as the fault records' measurement chain sees them (tones —
    /// the chain's interference — rescaled to the training records; shaft orders unchanged):
    /// what [`RigModel::synthesize`] uses.
    #[serde(default)]
    pub chain_lines: Vec<MachineLine>,
    /// The paths the 5-DOF excitation of each fault location is seen through (unit excitation
    /// variance: the severity gains carry the level).
    pub impact_paths: Vec<ImpactPath>,
    /// Radial preload of every ball in the excitation model, m (the calibrated contact load:
    /// it sets how far round the bearing the balls stay loaded, hence the load-zone
    /// modulation of the impacts).
    pub preload_m: f64,
    /// Constant radial load on the shaft in the excitation model, N, downwards (beside the
    /// shaft's weight): it concentrates the contact load in the 6 o'clock load zone, so a
    /// spall at 12 o'clock strikes lighter than one at 6. Calibrated on outer-race records with
    /// the spall opposite the load zone against the 6 o'clock record of the same size (0
    /// without any, and in rig files written before it).
    #[serde(default)]
    pub radial_load_n: f64,
    /// Horizontal sensitivity of the sensor relative to vertical: the fault excitation is the
    /// vertical housing acceleration plus this times the horizontal pedestal acceleration
    /// (fitted on outer-race records with the spall off the sensor axis; 0 without any).
    #[serde(default)]
    pub sensor_horizontal: f64,
    /// The fault records' measurement chain (their anti-alias roll-off): a zero-phase FIR
    /// applied to every synthesized recording (empty = none). Identified from the training
    /// records (see [`calibrate_rig`]).
    #[serde(default)]
    pub chain_fir: Vec<f64>,
    /// The healthy recording's broadband remainder — the power of the healthy PSD (smoothed
    /// ±150 Hz) that the machine model's named effects do not carry — as a zero-phase FIR
    /// shaping unit-variance white noise; added to every background (empty = none; rig files
    /// written before it have none).
    #[serde(default)]
    pub background_fir: Vec<f64>,
    /// The fault records' chain seen on the healthy machine's broadband part (its path noise,
    /// floor and remainder; not its lines, which `chain_lines` already holds at the fault
    /// records' levels): a zero-phase FIR applied to that part of every background but the
    /// healthy recording's own (empty = none; rig files written before it have none). The
    /// healthy recording (97, 48 kHz decimated) carries 20–30 times the 4–6 kHz power of the
    /// 12 kHz fault records whose faults are weak; see [`calibrate_rig`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub background_chain_fir: Vec<f64>,
    /// Sprung-mass resonance of the excitation model, Hz (ζ 0.7; [`EXCITATION_HOUSING_HZ`] when
    /// calibrated now, [`LEGACY_EXCITATION_HOUSING_HZ`] in rig files written before it was
    /// stored): the paths and severities were fitted behind it, so a rig keeps its own.
    #[serde(default = "legacy_housing_hz")]
    pub excitation_housing_hz: f64,
    /// Spall depth used in the excitation model, m.
    pub depth_m: f64,
    /// Slip fraction used in the excitation model.
    pub slip_fraction: f64,
    /// Calibrated severities, one per training record.
    pub severities: Vec<Severity>,
    /// Where it came from.
    pub provenance: RigProvenance,
}

/// What to synthesize.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Synthesis {
    /// Fault class (any combination: the spalls superpose in the 5-DOF model).
    pub class: FaultClass,
    /// Spall width, mm (ignored for [`FaultClass::None`]).
    pub size_mm: f64,
    /// Nominal shaft speed, rpm (the rig's calibrated speed ratio is applied).
    pub rpm: f64,
    /// Outer-race spall position, rad from +x towards +y (6 o'clock = −π/2).
    pub outer_angle_rad: f64,
    /// Samples to produce.
    pub n: usize,
    /// Seed of every random draw (excitation noise, line phases, slip).
    pub seed: u64,
}

impl Synthesis {
    /// `class` with a spall of `size_mm` at `rpm`, outer race at 6 o'clock.
    pub fn new(class: FaultClass, size_mm: f64, rpm: f64, n: usize, seed: u64) -> Self {
        Self {
            class,
            size_mm,
            rpm,
            outer_angle_rad: -PI / 2.0,
            n,
            seed,
        }
    }
}

fn bad(name: &'static str, value: f64, min: f64, max: f64) -> CloseLoopError {
    CloseLoopError::ParameterOutOfRange {
        name,
        value,
        min,
        max,
    }
}

/// Smallest spall width accepted, mm (1 nm: anything positive in practice, printable in an error).
const MIN_SIZE_MM: f64 = 1e-6;

/// The 5-DOF excitation of `class` (spalls of `size_mm` at depth [`DEPTH_M`], outer race at
/// `outer_angle_rad`, slip [`SLIP_FRACTION`], every ball preloaded by `preload_m`, the shaft
/// loaded by `radial_load_n` downwards): `n` samples of the housing acceleration (m/s²)
/// with the sprung-mass resonance moved to `housing_hz` (ζ 0.7; [`EXCITATION_HOUSING_HZ`] for a
/// new calibration, [`RigModel::excitation_housing_hz`] for a rig's), and of the horizontal
/// pedestal acceleration, means removed. Zeros for
/// [`FaultClass::None`] (a healthy bearing's own response is part of the healthy machine).
///
/// # Errors
/// [`CloseLoopError::Model`] when the 5-DOF model rejects the parameters (a spall wider than the
/// ball, a speed out of range) or the simulation fails.
#[allow(clippy::too_many_arguments)] // the 5-DOF operating point, spelled out
pub fn excitation(
    bearing: Bearing,
    preload_m: f64,
    radial_load_n: f64,
    class: FaultClass,
    size_mm: f64,
    rpm: f64,
    outer_angle_rad: f64,
    fs: f64,
    n: usize,
    seed: u64,
    housing_hz: f64,
) -> Result<Excitation, CloseLoopError> {
    excitation_with(
        bearing,
        preload_m,
        radial_load_n,
        class,
        size_mm,
        rpm,
        outer_angle_rad,
        fs,
        n,
        seed,
        housing_hz,
        EXCITATION_RTOL,
    )
}

/// [`excitation`] integrated at relative tolerance `rtol` instead of [`EXCITATION_RTOL`] (for
/// the accuracy check of that choice).
///
/// # Errors
/// As [`excitation`]; also [`CloseLoopError::Model`] for an `rtol` outside `1e-14 ..= 1`.
#[allow(clippy::too_many_arguments)] // the 5-DOF operating point, spelled out
pub fn excitation_with(
    bearing: Bearing,
    preload_m: f64,
    radial_load_n: f64,
    class: FaultClass,
    size_mm: f64,
    rpm: f64,
    outer_angle_rad: f64,
    fs: f64,
    n: usize,
    seed: u64,
    housing_hz: f64,
    rtol: f64,
) -> Result<Excitation, CloseLoopError> {
    if class == FaultClass::None {
        return Ok(Excitation {
            vertical: vec![0.0; n],
            horizontal: vec![0.0; n],
        });
    }
    if !(size_mm.is_finite() && size_mm >= MIN_SIZE_MM) {
        return Err(bad("size_mm", size_mm, MIN_SIZE_MM, 10.0));
    }
    let model_err = |e: bearing_model::ModelError| CloseLoopError::Model {
        reason: e.to_string(),
    };
    let mut sc = Scenario::new(ParamSet::CwruRig, bearing, rpm)
        .with_fs(fs)
        .with_duration(n as f64 / fs)
        .with_seed(seed)
        .with_slip(Slip::Random {
            fraction: SLIP_FRACTION,
        })
        .with_radial_load(radial_load_n)
        .with_housing(Housing {
            mass_kg: 1.0,
            resonance_hz: housing_hz,
            damping_ratio: 0.7,
        });
    sc.sim.integrator = bearing_model::Integrator::adaptive(rtol);
    sc.spec.contact.clearance_m = -preload_m;
    sc.spec.faults = FaultSet::of_class(class, Spall::new(size_mm * 1e-3).with_depth(DEPTH_M));
    if let Some(o) = sc.spec.faults.outer.as_mut() {
        o.angle_rad = outer_angle_rad;
    }
    sc.spec.validate().map_err(model_err)?;
    let rec = sc.with_states(true).simulate().map_err(model_err)?;
    let (mut x, states) = (rec.accel, rec.states.unwrap_or_default());
    if x.len() < n || states.len() < n {
        return Err(CloseLoopError::ModelLength {
            expected: n,
            found: x.len().min(states.len()),
        });
    }
    x.truncate(n);
    // horizontal pedestal acceleration: central difference of its velocity (state 7)
    let v: Vec<f64> = states[..n].iter().map(|s| s[7]).collect();
    let mut h: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            (v[b] - v[a]) * fs / (b - a).max(1) as f64
        })
        .collect();
    for y in [&mut x, &mut h] {
        let m = y.iter().sum::<f64>() / n.max(1) as f64;
        y.iter_mut().for_each(|v| *v -= m);
    }
    Ok(Excitation {
        vertical: x,
        horizontal: h,
    })
}

/// The 5-DOF excitation seen by the sensor: vertical housing acceleration and horizontal
/// pedestal acceleration (m/s²).
#[derive(Debug, Clone, PartialEq)]
pub struct Excitation {
    /// Vertical (sprung-mass) acceleration, anti-alias filtered.
    pub vertical: Vec<f64>,
    /// Horizontal pedestal acceleration (central difference of the sampled velocity).
    pub horizontal: Vec<f64>,
}

impl Excitation {
    /// What a sensor with horizontal sensitivity `kappa` (relative to vertical) sees.
    pub fn seen(&self, kappa: f64) -> Vec<f64> {
        self.vertical
            .iter()
            .zip(&self.horizontal)
            .map(|(v, h)| v + kappa * h)
            .collect()
    }
}

pub(crate) use crate::metric::mean_square;

/// Moving average of a PSD over ±`half` bins (edges use what exists).
pub(super) fn smooth(p: &[f64], half: usize) -> Vec<f64> {
    let mut cum = vec![0.0; p.len() + 1];
    for (k, v) in p.iter().enumerate() {
        cum[k + 1] = cum[k] + v;
    }
    (0..p.len())
        .map(|k| {
            let lo = k.saturating_sub(half);
            let hi = (k + half + 1).min(p.len());
            (cum[hi] - cum[lo]) / (hi - lo) as f64
        })
        .collect()
}

impl RigModel {
    /// The calibrated severity at `location` for a spall of `size_mm`: gain and random
    /// fraction, interpolated between calibrated sizes (log gain and fraction linear in log
    /// size; equal sizes averaged), the nearest calibrated size's values outside them.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no severity for `location`.
    pub fn severity(&self, location: Location, size_mm: f64) -> Result<(f64, f64), CloseLoopError> {
        let [log_gain, fraction, _] = self.severity_point(location, size_mm, None)?;
        Ok((log_gain.exp(), fraction))
    }

    /// [`RigModel::severity`] for an outer-race spall at `outer_angle_rad`: the severities
    /// calibrated at that position ([`Severity::outer_angle_rad`]) where the rig holds any, the
    /// reference ones otherwise (and for inner-race and ball spalls).
    ///
    /// # Errors
    /// As [`RigModel::severity`].
    pub fn severity_at(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: f64,
    ) -> Result<(f64, f64), CloseLoopError> {
        let [log_gain, fraction, _] =
            self.severity_point(location, size_mm, Some(outer_angle_rad))?;
        Ok((log_gain.exp(), fraction))
    }

    /// [`RigModel::strike_fraction`] at an outer-race position, as [`RigModel::severity_at`].
    ///
    /// # Errors
    /// As [`RigModel::severity`].
    pub fn strike_fraction_at(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: f64,
    ) -> Result<f64, CloseLoopError> {
        Ok(self.severity_point(location, size_mm, Some(outer_angle_rad))?[2])
    }

    /// The calibrated strike fraction ([`Severity::strike_fraction`]) at `location` for a spall
    /// of `size_mm`, interpolated as [`RigModel::severity`] is (linear in log size; the nearest
    /// calibrated size's value outside them).
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no severity for `location`.
    pub fn strike_fraction(&self, location: Location, size_mm: f64) -> Result<f64, CloseLoopError> {
        Ok(self.severity_point(location, size_mm, None)?[2])
    }

    /// The severities that serve `location` at the outer-race position `outer_angle_rad`: those
    /// calibrated at that position when the rig holds any (`true`), else the reference ones.
    fn severity_set(
        &self,
        location: Location,
        outer_angle_rad: Option<f64>,
    ) -> (Vec<&Severity>, bool) {
        let at = |s: &Severity| match (s.outer_angle_rad, outer_angle_rad) {
            (Some(a), Some(b)) => location == Location::Outer && same_position(a, b),
            _ => false,
        };
        let of_location = || self.severities.iter().filter(|s| s.location == location);
        let positioned = of_location().any(at);
        let set = of_location()
            .filter(|s| {
                if positioned {
                    at(s)
                } else {
                    s.outer_angle_rad.is_none()
                }
            })
            .collect();
        (set, positioned)
    }

    /// [`RigModel::calibrated_range_mm`] of the severities that serve `location` at the
    /// outer-race position `outer_angle_rad` ([`RigModel::severity_at`]), and whether they were
    /// calibrated at that position.
    pub fn calibrated_range_mm_at(
        &self,
        location: Location,
        outer_angle_rad: f64,
    ) -> Option<((f64, f64), bool)> {
        let (set, positioned) = self.severity_set(location, Some(outer_angle_rad));
        set.iter()
            .map(|s| (s.size_mm, s.size_mm))
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
            .map(|r| (r, positioned))
    }

    /// The smallest and largest calibrated spall width of `location`'s reference severities,
    /// mm (`None` without any): outside them the nearest calibrated severity is held.
    pub fn calibrated_range_mm(&self, location: Location) -> Option<(f64, f64)> {
        self.severities
            .iter()
            .filter(|s| s.location == location && s.outer_angle_rad.is_none())
            .map(|s| (s.size_mm, s.size_mm))
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    }

    /// Fault rate of `location` at nominal speed `rpm`, Hz: BPFI, BPFO or the ball-defect rate
    /// (CWRU's "BSF") times the shaft rate at the calibrated speed ratio.
    pub fn fault_rate_hz(&self, location: Location, rpm: f64) -> f64 {
        fault_rate_of(&self.healthy, location, rpm)
    }

    /// (log gain, random fraction, strike fraction) at `location` for `size_mm`: per calibrated size
    /// the mean over its records, linear in log size between sizes, held beyond them. Among the
    /// severities calibrated at the outer-race position `outer_angle_rad` when the rig holds
    /// any, else among the reference ones.
    fn severity_point(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: Option<f64>,
    ) -> Result<[f64; 3], CloseLoopError> {
        let (set, _) = self.severity_set(location, outer_angle_rad);
        let mut pts: Vec<(f64, [f64; 3])> = Vec::new();
        for s in &set {
            if pts.iter().any(|p| (p.0 - s.size_mm).abs() < 1e-9) {
                continue;
            }
            let same: Vec<&Severity> = set
                .iter()
                .copied()
                .filter(|t| (t.size_mm - s.size_mm).abs() < 1e-9)
                .collect();
            let n = same.len() as f64;
            let mean = |f: &dyn Fn(&Severity) -> f64| same.iter().map(|t| f(t)).sum::<f64>() / n;
            pts.push((
                s.size_mm,
                [
                    mean(&|t| t.gain.max(1e-300).ln()),
                    mean(&|t| t.random_fraction),
                    mean(&|t| t.strike_fraction),
                ],
            ));
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (first, last) = match (pts.first(), pts.last()) {
            (Some(f), Some(l)) => (*f, *l),
            _ => {
                return Err(CloseLoopError::Model {
                    reason: format!("the rig model holds no {} fault severity", location.name()),
                });
            }
        };
        if size_mm <= first.0 {
            return Ok(first.1);
        }
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            if size_mm <= b.0 {
                let t = (size_mm.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
                return Ok(std::array::from_fn(|i| a.1[i] + t * (b.1[i] - a.1[i])));
            }
        }
        Ok(last.1)
    }

    /// The healthy machine's signal: path noise, floor and lines (seeded), `n` samples at rig
    /// speed `rpm` (nominal; the calibrated speed ratio is applied).
    pub fn background(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        let lines = if self.chain_lines.is_empty() {
            &self.healthy.lines
        } else {
            &self.chain_lines
        };
        background_of(
            &self.healthy,
            lines,
            &self.background_fir,
            &self.background_chain_fir,
            self.fs_hz,
            rpm,
            n,
            seed,
        )
    }

    /// The healthy machine as its calibration recording holds it (lines at that recording's
    /// levels): what the healthy recording is compared with.
    pub fn background_as_calibrated(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        background_of(
            &self.healthy,
            &self.healthy.lines,
            &self.background_fir,
            &[],
            self.fs_hz,
            rpm,
            n,
            seed,
        )
    }

    /// The fault's contribution: for each location of the class, the 5-DOF excitation of its
    /// spall (simulated alone) scaled by the calibrated gain and seen through the location's
    /// impact path; combined faults superpose these responses.
    ///
    /// # Errors
    /// As [`excitation`] and [`RigModel::severity`].
    pub fn fault_signal(&self, s: &Synthesis) -> Result<Vec<f64>, CloseLoopError> {
        let bearing: Bearing =
            self.bearing
                .parse()
                .map_err(|_| CloseLoopError::UnknownBearing {
                    name: self.bearing.clone(),
                })?;
        let mut y = vec![0.0; s.n];
        for loc in Location::ALL.into_iter().filter(|l| l.in_class(s.class)) {
            let (g, q) = self.severity_at(loc, s.size_mm, s.outer_angle_rad)?;
            // each spall simulated alone (same seed, same slip draws) and seen through its own
            // path: combined faults are the superposition of the spalls' responses
            let e = excitation(
                bearing,
                self.preload_m,
                self.radial_load_n,
                loc.class(),
                s.size_mm,
                s.rpm * self.healthy.speed_ratio,
                s.outer_angle_rad,
                self.fs_hz,
                s.n + WARMUP,
                s.seed,
                self.excitation_housing_hz,
            )?;
            let e = e.seen(self.sensor_horizontal);
            let tau = BURST_PERIODS * self.fs_hz / self.fault_rate_hz(loc, s.rpm).max(1e-9);
            let e = gated(
                &e,
                self.strike_fraction_at(loc, s.size_mm, s.outer_angle_rad)?,
                tau,
                s.seed ^ 0xB0B5_7000,
            );
            let x: Vec<f64> = mix(&e, q, s.seed ^ 0x5EED_0FF1)
                .iter()
                .map(|v| g * v)
                .collect();
            let f = self
                .impact_path_for_at(loc, s.size_mm, s.outer_angle_rad)?
                .path
                .filter(&x);
            for (a, b) in y.iter_mut().zip(&f[WARMUP..]) {
                *a += b;
            }
        }
        Ok(y)
    }

    /// The first impact path of `location` (the first path of any location when the rig holds
    /// none for it). A rig fitted per size holds one path per calibrated size:
    /// [`RigModel::impact_path_for`] picks the one for a spall.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no impact path at all.
    pub fn impact_path(&self, location: Location) -> Result<&StructuralPath, CloseLoopError> {
        self.impact_paths
            .iter()
            .find(|p| p.location == location)
            .or(self.impact_paths.first())
            .map(|p| &p.path)
            .ok_or_else(|| CloseLoopError::Model {
                reason: "the rig model holds no impact path".into(),
            })
    }

    /// The impact path of `location` for a spall of `size_mm`: the path fitted on the nearest
    /// calibrated size of that location (in log size; beyond the calibrated sizes the nearest
    /// one is held, as the severity is), a pooled path where the rig holds one, else the first
    /// path of any location.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no impact path at all.
    pub fn impact_path_for(
        &self,
        location: Location,
        size_mm: f64,
    ) -> Result<&ImpactPath, CloseLoopError> {
        nearest_path(&self.impact_paths, location, size_mm).ok_or_else(|| CloseLoopError::Model {
            reason: "the rig model holds no impact path".into(),
        })
    }

    /// [`RigModel::impact_path_for`] for an outer-race spall at `outer_angle_rad`: the path fitted
    /// at that position ([`ImpactPath::outer_angle_rad`]) where the rig holds one, the
    /// reference path otherwise (and for inner-race and ball spalls).
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no impact path at all.
    pub fn impact_path_for_at(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: f64,
    ) -> Result<&ImpactPath, CloseLoopError> {
        nearest_path_at(&self.impact_paths, location, size_mm, Some(outer_angle_rad)).ok_or_else(
            || CloseLoopError::Model {
                reason: "the rig model holds no impact path".into(),
            },
        )
    }

    /// A simulated recording of the rig (rig units, [`RigModel::units`]).
    ///
    /// # Errors
    /// [`CloseLoopError::InvalidRpm`], [`CloseLoopError::ParameterOutOfRange`] for a speed above
    /// 100 000 rpm or `n` below 1024, and the errors of [`RigModel::fault_signal`].
    pub fn synthesize(&self, s: &Synthesis) -> Result<Vec<f64>, CloseLoopError> {
        if !(s.rpm.is_finite() && s.rpm > 0.0) {
            return Err(CloseLoopError::InvalidRpm { rpm: s.rpm });
        }
        if s.rpm > 100_000.0 {
            return Err(bad("rpm", s.rpm, 0.0, 100_000.0));
        }
        if s.n < 1024 {
            return Err(bad("samples", s.n as f64, 1024.0, f64::INFINITY));
        }
        let mut y = self.background(s.rpm, s.n, s.seed);
        if s.class != FaultClass::None {
            let f = self.fault_signal(s)?;
            for (a, b) in y.iter_mut().zip(&f) {
                *a += b;
            }
        }
        let y = apply_fir(&self.chain_fir, &y);
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            return Err(CloseLoopError::NonFinite { index: i });
        }
        Ok(y)
    }

    /// Serialise (pretty JSON).
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] if serialisation fails.
    pub fn to_json(&self) -> Result<String, CloseLoopError> {
        serde_json::to_string_pretty(self).map_err(|e| CloseLoopError::MachineModelFormat {
            reason: e.to_string(),
        })
    }

    /// Parse and validate a rig model.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] for malformed JSON or values,
    /// [`CloseLoopError::MachineModelMismatch`] for another format or version.
    pub fn from_json(text: &str) -> Result<Self, CloseLoopError> {
        let m: Self = crate::machine::parse_versioned(text, FORMAT, VERSION, |m: &Self| {
            (&m.format, m.version)
        })?;
        let fmt = |reason: String| CloseLoopError::MachineModelFormat { reason };
        if !(m.fs_hz.is_finite() && m.fs_hz > 0.0) {
            return Err(fmt(format!("`fs_hz` must be > 0, got {}", m.fs_hz)));
        }
        // the healthy part goes through the machine model's own validation
        MachineModel::from_json(&m.healthy.to_json()?)?;
        if m.impact_paths.is_empty()
            || m.impact_paths.iter().any(|p| {
                p.path.ar.iter().any(|a| !a.is_finite())
                    || !(p.path.excitation_variance.is_finite() && p.path.excitation_variance > 0.0)
                    || p.size_mm.is_some_and(|s| !(s.is_finite() && s > 0.0))
            })
        {
            return Err(fmt(
                "`impact_paths` is empty or holds a non-finite coefficient or a size that is not > 0"
                    .into(),
            ));
        }
        if m.chain_fir
            .iter()
            .chain(&m.background_fir)
            .chain(&m.background_chain_fir)
            .any(|v| !v.is_finite())
        {
            return Err(fmt(
                "`chain_fir`, `background_fir` or `background_chain_fir` holds a non-finite tap"
                    .into(),
            ));
        }
        if !(m.preload_m.is_finite() && (0.0..=1e-4).contains(&m.preload_m)) {
            return Err(fmt(format!(
                "`preload_m` must be in [0, 1e-4], got {}",
                m.preload_m
            )));
        }
        if !(m.radial_load_n.is_finite() && (0.0..=1e5).contains(&m.radial_load_n)) {
            return Err(fmt(format!(
                "`radial_load_n` must be in [0, 1e5], got {}",
                m.radial_load_n
            )));
        }
        if !(m.excitation_housing_hz.is_finite()
            && (0.5 * m.fs_hz..=1e6).contains(&m.excitation_housing_hz))
        {
            return Err(fmt(format!(
                "`excitation_housing_hz` must be in [fs/2, 1e6] (above the output band), got {}",
                m.excitation_housing_hz
            )));
        }
        if m.impact_paths.iter().any(|p| {
            p.outer_angle_rad.is_some_and(|a| !a.is_finite())
                || (p.outer_angle_rad.is_some() && p.location != Location::Outer)
        }) {
            return Err(fmt(
                "an impact path's position must be finite and on the outer race".into(),
            ));
        }
        for s in &m.severities {
            if !(s.gain.is_finite() && s.gain >= 0.0 && s.size_mm.is_finite() && s.size_mm > 0.0)
                || s.outer_angle_rad.is_some_and(|a| !a.is_finite())
                || (s.outer_angle_rad.is_some() && s.location != Location::Outer)
            {
                return Err(fmt(format!(
                    "severity of {} must have size > 0, gain >= 0 and a finite position on the outer race only",
                    s.record
                )));
            }
        }
        Ok(m)
    }

    /// Check that the rig can produce a recording at `fs` for `bearing`.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelMismatch`] for another sampling rate or bearing.
    pub fn check_compatible(&self, fs: f64, bearing: &str) -> Result<(), CloseLoopError> {
        self.healthy.check_compatible(fs, bearing)
    }
}

/// Fault rate of `location` on `machine` at nominal speed `rpm`, Hz ([`RigModel::fault_rate_hz`]).
pub(super) fn fault_rate_of(machine: &MachineModel, location: Location, rpm: f64) -> f64 {
    let [bpfo, bpfi, _ftf, bsf] = machine.bearing_orders;
    let fr = rpm / 60.0 * machine.speed_ratio;
    fr * match location {
        Location::Inner => bpfi,
        Location::Outer => bpfo,
        Location::Ball => bsf,
    }
}

/// Serde default of [`Severity::strike_fraction`]: every impact strikes.
fn every_impact() -> f64 {
    1.0
}

/// The strike gate: `n` samples of a two-state Markov chain (seeded, started in its stationary
/// law) that is on a fraction `p` of the time, in bursts of `burst_samples` on average, and
/// off in between; on = 1/√p, off = 0, so the gate's mean square is 1 and its mean √p (the
/// periodic part of the impacts keeps a fraction p of their power). `p` ≥ 1 gives ones.
pub fn strike_gate(n: usize, p: f64, burst_samples: f64, seed: u64) -> Vec<f64> {
    if !(p.is_finite() && p > 0.0 && p < 1.0) {
        return vec![1.0; n];
    }
    let on_len = burst_samples.max(1.0);
    let off_len = (on_len * (1.0 - p) / p).max(1.0);
    let (leave_on, leave_off) = (1.0 / on_len, 1.0 / off_len);
    let level = 1.0 / p.sqrt();
    let mut g = Gaussian::new(seed);
    let mut on = g.uniform() < p;
    (0..n)
        .map(|_| {
            let v = if on { level } else { 0.0 };
            let u = g.uniform();
            on = if on { u >= leave_on } else { u < leave_off };
            v
        })
        .collect()
}

/// `x` times the strike gate of fraction `p` ([`strike_gate`]); `x` itself for p ≥ 1.
pub(super) fn gated(x: &[f64], p: f64, burst_samples: f64, seed: u64) -> Vec<f64> {
    if !(p.is_finite() && p > 0.0 && p < 1.0) {
        return x.to_vec();
    }
    strike_gate(x.len(), p, burst_samples, seed)
        .iter()
        .zip(x)
        .map(|(g, v)| g * v)
        .collect()
}

/// `x` plus a random part carrying the fraction `q` of the sum's power:
/// `x + √(q/(1−q))·r`, `r` a phase-randomised copy of `x` (every DFT bin keeps its magnitude,
/// its phase is drawn uniformly, seeded): the same power spectrum as the 5-DOF impacts, Gaussian
/// in distribution, so the random part lowers the kurtosis without changing the spectral shape
/// the impact path was fitted to (white noise would: the path divides the excess PSD by the
/// impacts' PSD, and white noise through it is over-weighted wherever the impacts are weak).
pub(super) fn mix(x: &[f64], q: f64, seed: u64) -> Vec<f64> {
    let q = q.clamp(0.0, 0.99);
    if q == 0.0 || x.is_empty() {
        return x.to_vec();
    }
    let r = phase_randomised(x, seed);
    let c = (q / (1.0 - q)).sqrt();
    x.iter().zip(&r).map(|(v, w)| v + c * w).collect()
}

/// A phase-randomised surrogate of `x`: the DFT magnitudes of `x` with seeded uniform phases
/// (Hermitian, so real; DC and, for even lengths, the Nyquist bin keep their values), hence the
/// same periodogram and mean square.
pub(super) fn phase_randomised(x: &[f64], seed: u64) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let n = x.len();
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    let mut planner = rustfft::FftPlanner::new();
    planner.plan_fft_forward(n).process(&mut buf);
    let mut g = Gaussian::new(seed);
    for k in 1..n.div_ceil(2) {
        let phase = 2.0 * PI * g.uniform();
        let m = buf[k].norm();
        buf[k] = Complex::from_polar(m, phase);
        buf[n - k] = buf[k].conj();
    }
    planner.plan_fft_inverse(n).process(&mut buf);
    buf.iter().map(|c| c.re / n as f64).collect()
}

/// The healthy machine's signal (see [`RigModel::background`]).
#[allow(clippy::too_many_arguments)] // the background's parts, spelled out
pub(super) fn background_of(
    machine: &MachineModel,
    lines: &[MachineLine],
    remainder: &[f64],
    broadband_chain: &[f64],
    fs: f64,
    rpm: f64,
    n: usize,
    seed: u64,
) -> Vec<f64> {
    let h = &machine;
    let mut y = if remainder.is_empty() {
        vec![0.0; n]
    } else {
        let mut g = Gaussian::new(seed ^ 0x2E3A_1DE4);
        let w: Vec<f64> = (0..n).map(|_| g.sample()).collect();
        apply_fir(remainder, &w)
    };
    let mut g = Gaussian::new(seed ^ 0xB6C0_5EED);
    if let Some(p) = &h.path {
        let sd = (p.excitation_variance * h.path_level).max(0.0).sqrt();
        let e: Vec<f64> = (0..n + WARMUP).map(|_| sd * g.sample()).collect();
        let f = p.filter(&e);
        for (a, b) in y.iter_mut().zip(&f[WARMUP..]) {
            *a += b;
        }
    }
    let floor_sd = (h.noise_floor_psd * fs / 2.0).max(0.0).sqrt();
    if floor_sd > 0.0 {
        y.iter_mut().for_each(|v| *v += floor_sd * g.sample());
    }
    let mut y = apply_fir(broadband_chain, &y);
    let fr = rpm / 60.0 * h.speed_ratio;
    for l in lines {
        let (f, a) = match *l {
            MachineLine::ShaftHarmonic {
                order, amplitude, ..
            } => (order * fr, amplitude),
            MachineLine::Tone {
                frequency_hz,
                amplitude,
            } => (frequency_hz, amplitude),
        };
        let ph = 2.0 * PI * g.uniform();
        if f > 0.0 && f < 0.5 * fs {
            add_cosine(&mut y, 2.0 * PI * f / fs, a, ph);
        }
    }
    y
}

/// Zero-phase FIR (odd length, symmetric `h`), zero padding at the edges; `x` itself when `h`
/// is empty.
pub(super) fn apply_fir(h: &[f64], x: &[f64]) -> Vec<f64> {
    if h.is_empty() {
        return x.to_vec();
    }
    let m = h.len() / 2;
    let n = x.len();
    if h.len() < FFT_FIR_MIN_TAPS || n < 8 * h.len() {
        return (0..n)
            .map(|i| {
                let lo = i.saturating_sub(m);
                let hi = (i + m).min(n - 1);
                (lo..=hi).map(|j| h[j + m - i] * x[j]).sum()
            })
            .collect();
    }
    // overlap-add: blocks of `b` samples convolved with h by FFTs of `nfft` ≥ b + len(h) − 1
    // points; the full convolution's samples m … m + n − 1 are the zero-phase output (the
    // same sums as above, the edges zero-padded, rounding aside)
    use rustfft::num_complex::Complex;
    let nfft = (4 * h.len()).next_power_of_two();
    let b = nfft - h.len() + 1;
    let mut planner = rustfft::FftPlanner::<f64>::new();
    let (fwd, inv) = (
        planner.plan_fft_forward(nfft),
        planner.plan_fft_inverse(nfft),
    );
    let mut hf: Vec<Complex<f64>> = (0..nfft)
        .map(|k| Complex::new(h.get(k).copied().unwrap_or(0.0), 0.0))
        .collect();
    fwd.process(&mut hf);
    let mut full = vec![0.0; n + h.len() - 1];
    let mut buf = vec![Complex::new(0.0, 0.0); nfft];
    for start in (0..n).step_by(b) {
        let len = b.min(n - start);
        buf.iter_mut().for_each(|v| *v = Complex::new(0.0, 0.0));
        for (v, xv) in buf.iter_mut().zip(&x[start..start + len]) {
            v.re = *xv;
        }
        fwd.process(&mut buf);
        for (v, hv) in buf.iter_mut().zip(&hf) {
            *v *= hv;
        }
        inv.process(&mut buf);
        for (o, v) in full[start..].iter_mut().zip(&buf[..len + h.len() - 1]) {
            *o += v.re / nfft as f64;
        }
    }
    full[m..m + n].to_vec()
}

/// Add `a·cos(w·k + φ)` to `y[k]` by a rotating phasor, re-anchored every 4096 samples to the
/// exact phase (within a few 1e-12 of the amplitude over 50 000 samples, test): one complex
/// multiplication per sample instead of a cosine.
fn add_cosine(y: &mut [f64], w: f64, a: f64, ph: f64) {
    let (sw, cw) = w.sin_cos();
    for (c, chunk) in y.chunks_mut(4096).enumerate() {
        let (mut s0, mut c0) = (w * (4096 * c) as f64 + ph).sin_cos();
        for v in chunk {
            *v += a * c0;
            (c0, s0) = (c0 * cw - s0 * sw, s0 * cw + c0 * sw);
        }
    }
}

/// Taps from which [`apply_fir`] convolves by FFT (overlap-add) rather than directly.
const FFT_FIR_MIN_TAPS: usize = 33;

#[cfg(test)]
mod tests {
    use super::*;

    fn kurt(x: &[f64]) -> f64 {
        let n = x.len() as f64;
        let m = x.iter().sum::<f64>() / n;
        let v = x.iter().map(|a| (a - m).powi(2)).sum::<f64>() / n;
        x.iter().map(|a| (a - m).powi(4)).sum::<f64>() / n / (v * v)
    }

    /// The random part keeps the impacts' spectrum (and so the mix keeps the shape the impact
    /// path was fitted to) while the mix loses impulsiveness; odd and even lengths.
    #[test]
    fn the_random_part_has_the_spectrum_of_the_impacts() {
        for n in [4095usize, 4096] {
            // a decaying ringing every 100 samples: impulsive, strongly coloured
            let x: Vec<f64> = (0..n)
                .map(|i| {
                    let t = (i % 100) as f64;
                    (-t / 6.0).exp() * (0.9 * t).sin()
                })
                .collect();
            let r = phase_randomised(&x, 7);
            let spec = |y: &[f64]| {
                let mut b: Vec<rustfft::num_complex::Complex<f64>> = y
                    .iter()
                    .map(|&v| rustfft::num_complex::Complex::new(v, 0.0))
                    .collect();
                rustfft::FftPlanner::new()
                    .plan_fft_forward(n)
                    .process(&mut b);
                b.iter().map(|c| c.norm()).collect::<Vec<f64>>()
            };
            let (sx, sr) = (spec(&x), spec(&r));
            let peak = sx.iter().cloned().fold(0.0, f64::max);
            for (a, b) in sx.iter().zip(&sr) {
                assert!((a - b).abs() <= 1e-9 * peak, "{a} vs {b}");
            }
            assert!((mean_square(&r) / mean_square(&x) - 1.0).abs() < 1e-9);
            assert!(kurt(&x) > 4.0, "input kurtosis {}", kurt(&x));
            assert!(kurt(&r) < 3.5, "surrogate kurtosis {}", kurt(&r));
            let m = mix(&x, 0.5, 3);
            assert!(kurt(&m) < kurt(&x));
            assert_eq!(mix(&x, 0.0, 3), x);
        }
    }

    /// The FFT (overlap-add) convolution of a long input agrees with the direct sums, edges
    /// included, and a line synthesized by the rotating phasor with the cosine it stands for.
    #[test]
    fn fft_fir_and_phasor_lines_match_their_direct_forms() {
        let mut g = Gaussian::new(5);
        let x: Vec<f64> = (0..20_011).map(|_| g.sample()).collect();
        let h: Vec<f64> = (0..129)
            .map(|k| {
                let t = (k as f64 - 64.0) / 64.0;
                (1.0 - t * t) * (3.0 * t).cos()
            })
            .collect();
        let fast = apply_fir(&h, &x);
        let m = h.len() / 2;
        let direct: Vec<f64> = (0..x.len())
            .map(|i| {
                let lo = i.saturating_sub(m);
                let hi = (i + m).min(x.len() - 1);
                (lo..=hi).map(|j| h[j + m - i] * x[j]).sum()
            })
            .collect();
        assert_eq!(fast.len(), direct.len());
        let worst = fast
            .iter()
            .zip(&direct)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{worst}");
        let mut y = vec![0.25; 50_000];
        let (w, a, ph) = (2.0 * PI * 1234.567 / 12_000.0, 0.5, 2.1);
        add_cosine(&mut y, w, a, ph);
        let worst = y
            .iter()
            .enumerate()
            .map(|(k, v)| (v - 0.25 - a * (w * k as f64 + ph).cos()).abs())
            .fold(0.0, f64::max);
        // the reference itself rounds its argument (w·k up to 3e4 rad): a few 1e-12
        assert!(worst < 1e-10 * a, "{worst}");
    }
}
