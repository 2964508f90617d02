//! The calibrated rig simulator: the 5-DOF bearing model behind the measured paths of a rig.
//!
//! A simulated recording of the rig is the sum of
//!
//! 1. **the healthy machine** — the [`MachineModel`] the loop calibrated on a healthy recording:
//!    its structural path `1/A(z)` driven by white excitation at the identified level, its white
//!    noise floor and its lines (shaft orders at the calibrated speed ratio, tones), each line with
//!    a seeded random phase;
//! 2. **the fault** — the 5-DOF model's (eqs. 2.12–2.25) housing acceleration with the spalls of
//!    the class, its sprung-mass resonance moved out of band ([`EXCITATION_HOUSING_HZ`], ζ 0.7) so
//!    that it is the bearing's local response to the contact forces, seen through the rig's
//!    *impact path* `1/A_i(z)` and scaled by a severity gain `g(location, size)`.
//!
//! [`calibrate_rig`] fits the free quantities on measured records: the healthy machine on a
//! healthy recording (the loop, [`crate::machine::calibrate`]); the impact path as the AR model
//! (Levinson) of the pooled ratio of the training fault records' excess PSD (measured minus
//! healthy) to the simulated excitation's PSD, both smoothed over ±150 Hz; the severity gain of
//! each training record in closed form from its excess mean square. Calibration uses signal
//! statistics only (PSDs and RMS), never a label beyond the catalogued fault location and size,
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
use crate::spectrum::Welch;
use bearing_model::{Bearing, FaultClass, FaultSet, Housing, ParamSet, Scenario, Slip, Spall};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The `format` string of a rig model file.
pub const FORMAT: &str = "hybrid-fdd/rig-model";
/// The current `version`.
pub const VERSION: u32 = 1;
/// Sprung-mass resonance of the excitation model, Hz: far above any output band, so that the
/// housing acceleration is the pedestal's response to the contacts (the rig's own resonances
/// come from the identified impact path).
pub const EXCITATION_HOUSING_HZ: f64 = 20_000.0;
/// Spall depth of the rig's faults (CWRU EDM depth 0.011 in), m.
pub const DEPTH_M: f64 = 0.011 * 0.0254;
/// Random slip of the rolling elements in the excitation model (fraction of the ball spacing).
pub const SLIP_FRACTION: f64 = 0.01;
/// Half width of the smoothing applied to the PSDs the impact path is fitted on, Hz.
const SMOOTH_HZ: f64 = 150.0;
/// AR order of the impact path.
pub const IMPACT_PATH_ORDER: usize = 48;
/// Settling samples discarded before a synthesized recording (path start-up).
const WARMUP: usize = 4096;

/// The committed calibration of the CWRU rig (`cargo xtask calibrate-rig`): 6205 drive end,
/// 12 kHz, units g.
pub const CWRU_RIG_JSON: &str = include_str!("../rig/cwru-12k.json");

/// The calibrated CWRU rig ([`CWRU_RIG_JSON`], validated).
///
/// # Errors
/// [`CloseLoopError::MachineModelFormat`] if the committed file is not a valid rig model.
pub fn cwru_rig() -> Result<RigModel, CloseLoopError> {
    RigModel::from_json(CWRU_RIG_JSON)
}

/// Where a fault sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Location {
    /// Inner race.
    Inner,
    /// Outer race.
    Outer,
    /// Rolling element.
    Ball,
}

impl Location {
    /// All three.
    pub const ALL: [Location; 3] = [Location::Inner, Location::Outer, Location::Ball];

    /// Name as reports spell it.
    pub fn name(self) -> &'static str {
        match self {
            Location::Inner => "inner",
            Location::Outer => "outer",
            Location::Ball => "ball",
        }
    }

    /// The single-location class.
    pub fn class(self) -> FaultClass {
        match self {
            Location::Inner => FaultClass::Inner,
            Location::Outer => FaultClass::Outer,
            Location::Ball => FaultClass::Ball,
        }
    }

    /// Whether `class` has a spall here.
    pub fn in_class(self, class: FaultClass) -> bool {
        match self {
            Location::Inner => class.has_inner(),
            Location::Outer => class.has_outer(),
            Location::Ball => class.has_ball(),
        }
    }
}

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
    /// The training record it was fitted on.
    pub record: String,
}

/// The path from one fault location to the sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImpactPath {
    /// Fault location.
    pub location: Location,
    /// AR path `1/A_i(z)`.
    pub path: StructuralPath,
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

/// The 5-DOF excitation of `class` (spalls of `size_mm` at depth [`DEPTH_M`], outer race at
/// `outer_angle_rad`, slip [`SLIP_FRACTION`], every ball preloaded by `preload_m`): `n` samples of the housing acceleration (m/s²)
/// with the sprung-mass resonance moved to [`EXCITATION_HOUSING_HZ`], and of the horizontal
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
    class: FaultClass,
    size_mm: f64,
    rpm: f64,
    outer_angle_rad: f64,
    fs: f64,
    n: usize,
    seed: u64,
) -> Result<Excitation, CloseLoopError> {
    if class == FaultClass::None {
        return Ok(Excitation {
            vertical: vec![0.0; n],
            horizontal: vec![0.0; n],
        });
    }
    if !(size_mm.is_finite() && size_mm > 0.0) {
        return Err(bad("size_mm", size_mm, f64::MIN_POSITIVE, 10.0));
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
        .with_housing(Housing {
            mass_kg: 1.0,
            resonance_hz: EXCITATION_HOUSING_HZ,
            damping_ratio: 0.7,
        });
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

use crate::metric::mean_square;

/// Moving average of a PSD over ±`half` bins (edges use what exists).
fn smooth(p: &[f64], half: usize) -> Vec<f64> {
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
        // (size, mean log gain, mean fraction) per calibrated size
        let mut pts: Vec<(f64, f64, f64)> = Vec::new();
        for s in self.severities.iter().filter(|s| s.location == location) {
            if pts.iter().any(|p| (p.0 - s.size_mm).abs() < 1e-9) {
                continue;
            }
            let same: Vec<&Severity> = self
                .severities
                .iter()
                .filter(|t| t.location == location && (t.size_mm - s.size_mm).abs() < 1e-9)
                .collect();
            let n = same.len() as f64;
            pts.push((
                s.size_mm,
                same.iter().map(|t| t.gain.max(1e-300).ln()).sum::<f64>() / n,
                same.iter().map(|t| t.random_fraction).sum::<f64>() / n,
            ));
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let out = |p: (f64, f64, f64)| Ok((p.1.exp(), p.2));
        let (first, last) = match (pts.first(), pts.last()) {
            (Some(f), Some(l)) => (*f, *l),
            _ => {
                return Err(CloseLoopError::Model {
                    reason: format!("the rig model holds no {} fault severity", location.name()),
                });
            }
        };
        if size_mm <= first.0 {
            return out(first);
        }
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            if size_mm <= b.0 {
                let t = (size_mm.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
                return out((size_mm, a.1 + t * (b.1 - a.1), a.2 + t * (b.2 - a.2)));
            }
        }
        out(last)
    }

    /// The healthy machine's signal: path noise, floor and lines (seeded), `n` samples at rig
    /// speed `rpm` (nominal; the calibrated speed ratio is applied).
    pub fn background(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        let lines = if self.chain_lines.is_empty() {
            &self.healthy.lines
        } else {
            &self.chain_lines
        };
        background_of(&self.healthy, lines, self.fs_hz, rpm, n, seed)
    }

    /// The healthy machine as its calibration recording holds it (lines at that recording's
    /// levels): what the healthy recording is compared with.
    pub fn background_as_calibrated(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        background_of(&self.healthy, &self.healthy.lines, self.fs_hz, rpm, n, seed)
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
            let (g, q) = self.severity(loc, s.size_mm)?;
            // each spall simulated alone (same seed, same slip draws) and seen through its own
            // path: combined faults are the superposition of the spalls' responses
            let e = excitation(
                bearing,
                self.preload_m,
                loc.class(),
                s.size_mm,
                s.rpm * self.healthy.speed_ratio,
                s.outer_angle_rad,
                self.fs_hz,
                s.n + WARMUP,
                s.seed,
            )?;
            let e = e.seen(self.sensor_horizontal);
            let x: Vec<f64> = mix(&e, q, s.seed ^ 0x5EED_0FF1)
                .iter()
                .map(|v| g * v)
                .collect();
            let f = self.impact_path(loc)?.filter(&x);
            for (a, b) in y.iter_mut().zip(&f[WARMUP..]) {
                *a += b;
            }
        }
        Ok(y)
    }

    /// The impact path of `location` (the pooled path when the rig holds none for it).
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

    /// A simulated recording of the rig (rig units, [`RigModel::units`]).
    ///
    /// # Errors
    /// [`CloseLoopError::InvalidRpm`], [`CloseLoopError::ParameterOutOfRange`] for `n` below
    /// 1024, and the errors of [`RigModel::fault_signal`].
    pub fn synthesize(&self, s: &Synthesis) -> Result<Vec<f64>, CloseLoopError> {
        if !(s.rpm.is_finite() && s.rpm > 0.0 && s.rpm <= 100_000.0) {
            return Err(CloseLoopError::InvalidRpm { rpm: s.rpm });
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
            })
        {
            return Err(fmt(
                "`impact_paths` is empty or holds a non-finite coefficient".into(),
            ));
        }
        if !(m.preload_m.is_finite() && (0.0..=1e-4).contains(&m.preload_m)) {
            return Err(fmt(format!(
                "`preload_m` must be in [0, 1e-4], got {}",
                m.preload_m
            )));
        }
        for s in &m.severities {
            if !(s.gain.is_finite() && s.gain >= 0.0 && s.size_mm.is_finite() && s.size_mm > 0.0) {
                return Err(fmt(format!(
                    "severity of {} must have size > 0 and gain >= 0",
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

/// `x` plus white noise carrying the fraction `q` of the sum's power: `x + √(q/(1−q))·RMS(x)·w`.
fn mix(x: &[f64], q: f64, seed: u64) -> Vec<f64> {
    let q = q.clamp(0.0, 0.99);
    if q == 0.0 {
        return x.to_vec();
    }
    let sd = (q / (1.0 - q) * mean_square(x)).sqrt();
    let mut g = Gaussian::new(seed);
    x.iter().map(|v| v + sd * g.sample()).collect()
}

/// Preloads the calibration tries, m.
pub const PRELOADS_M: &[f64] = &[0.0, 0.5e-6, 1e-6, 2e-6, 4e-6, 8e-6];

fn variance(y: &[f64]) -> f64 {
    let m = y.iter().sum::<f64>() / y.len().max(1) as f64;
    y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / y.len().max(1) as f64
}

/// Kurtosis (`residual-features`'); NaN for a constant signal, which calibration never feeds it
/// (records with no excess power are refused before).
fn kurtosis(y: &[f64]) -> f64 {
    residual_features::kurtosis(y).unwrap_or(f64::NAN)
}

/// The healthy machine's signal (see [`RigModel::background`]).
fn background_of(
    machine: &MachineModel,
    lines: &[MachineLine],
    fs: f64,
    rpm: f64,
    n: usize,
    seed: u64,
) -> Vec<f64> {
    let h = &machine;
    let mut g = Gaussian::new(seed ^ 0xB6C0_5EED);
    let mut y = vec![0.0; n];
    if let Some(p) = &h.path {
        let sd = (p.excitation_variance * h.path_level).max(0.0).sqrt();
        let e: Vec<f64> = (0..n + WARMUP).map(|_| sd * g.sample()).collect();
        let f = p.filter(&e);
        y.copy_from_slice(&f[WARMUP..]);
    }
    let floor_sd = (h.noise_floor_psd * fs / 2.0).max(0.0).sqrt();
    if floor_sd > 0.0 {
        y.iter_mut().for_each(|v| *v += floor_sd * g.sample());
    }
    let fr = rpm / 60.0 * h.speed_ratio;
    for l in lines {
        let (f, a) = match *l {
            MachineLine::ShaftHarmonic { order, amplitude } => (order * fr, amplitude),
            MachineLine::Tone {
                frequency_hz,
                amplitude,
            } => (frequency_hz, amplitude),
        };
        let ph = 2.0 * PI * g.uniform();
        if f > 0.0 && f < 0.5 * fs {
            for (k, v) in y.iter_mut().enumerate() {
                *v += a * (2.0 * PI * f * k as f64 / fs + ph).cos();
            }
        }
    }
    y
}

/// The tones of the healthy machine (lines fixed in Hz: the measurement chain's interference,
/// e.g. CWRU's ~4.2 kHz comb) belong to the recording chain, not to the machine, and differ
/// between the healthy recording and the fault records. Each tone's amplitude is rescaled by the
/// median, over the training records, of the square root of its peak excess (largest PSD within
/// ±2 bins over the median of ±50 Hz) relative to the healthy recording's.
fn chain_tones(
    machine: &MachineModel,
    healthy: &[f64],
    training: &[TrainingRecord<'_>],
    fs: f64,
) -> Result<Vec<MachineLine>, CloseLoopError> {
    let mut lines = machine.lines.clone();
    let welch = Welch::new(fs, ((fs / 3.0).log2().round().exp2() as usize).max(1024))?;
    let df = welch.df();
    let excess = |p: &[f64], f: f64| {
        let k = (f / df).round() as usize;
        let w = ((50.0 / df).round() as usize).max(4);
        if k + w >= p.len() || k < w {
            return None;
        }
        let peak = p[k - 2..=k + 2].iter().copied().fold(0.0, f64::max);
        let med = crate::spectrum::median(&p[k - w..=k + w]);
        Some((peak - med).max(0.0))
    };
    let p_h = welch.try_psd(healthy)?;
    let p_t: Vec<Vec<f64>> = training
        .iter()
        .map(|t| welch.try_psd(t.y))
        .collect::<Result<_, _>>()?;
    for l in lines.iter_mut() {
        if let MachineLine::Tone {
            frequency_hz,
            amplitude,
        } = l
        {
            let Some(h) = excess(&p_h, *frequency_hz).filter(|h| *h > 0.0) else {
                continue;
            };
            let mut r: Vec<f64> = p_t
                .iter()
                .filter_map(|p| excess(p, *frequency_hz))
                .map(|e| (e / h).sqrt())
                .collect();
            if !r.is_empty() {
                r.sort_by(f64::total_cmp);
                *amplitude *= r[r.len() / 2];
            }
        }
    }
    Ok(lines)
}

/// Zero-phase FIR (odd length, symmetric `h`), zero padding at the edges; `x` itself when `h`
/// is empty.
fn apply_fir(h: &[f64], x: &[f64]) -> Vec<f64> {
    if h.is_empty() {
        return x.to_vec();
    }
    let m = h.len() / 2;
    let n = x.len();
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(m);
            let hi = (i + m).min(n - 1);
            (lo..=hi).map(|j| h[j + m - i] * x[j]).sum()
        })
        .collect()
}

/// Half length of the chain FIR (taps = 2·CHAIN_HALF + 1).
const CHAIN_HALF: usize = 64;

/// The measurement chain: the median over the training records of the smoothed ratio of the
/// measured PSD to the rig's (no chain yet) simulated PSD, normalised to unit geometric mean over
/// 300 Hz–fs/3 and clamped at 1 — so it holds only what attenuates (the roll-off of the records'
/// anti-alias filter, which the all-pole paths cannot follow) — as a Hann-windowed zero-phase FIR
/// of `2·CHAIN_HALF + 1` taps by frequency sampling of its square root. Empty when nothing is
/// attenuated by more than 1 dB.
fn chain_response(
    rig: &RigModel,
    training: &[TrainingRecord<'_>],
    measured: &[(Vec<f64>, f64)],
    welch: &Welch,
    half: usize,
) -> Result<Vec<f64>, CloseLoopError> {
    let fs = rig.fs_hz;
    let nb = welch.n_bins();
    let mut logs: Vec<Vec<f64>> = Vec::new();
    for (i, t) in training.iter().enumerate() {
        let n = t.y.len().min((4.0 * fs) as usize);
        let mut syn = Synthesis::new(t.location.class(), t.size_mm, t.rpm, n, 3000 + i as u64);
        syn.outer_angle_rad = t.outer_angle_rad;
        let sim = rig.synthesize(&syn)?;
        let s_sim = smooth(&welch.try_psd(&sim)?, half);
        logs.push(
            measured[i]
                .0
                .iter()
                .zip(&s_sim)
                .map(|(a, b)| (a.max(1e-300) / b.max(1e-300)).ln())
                .collect(),
        );
    }
    if logs.is_empty() {
        return Ok(Vec::new());
    }
    let med: Vec<f64> = (0..nb)
        .map(|k| {
            let mut v: Vec<f64> = logs.iter().map(|l| l[k]).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        })
        .collect();
    let band: Vec<usize> = (0..nb)
        .filter(|&k| (300.0..=fs / 3.0).contains(&welch.frequency(k)))
        .collect();
    let mean = band.iter().map(|&k| med[k]).sum::<f64>() / band.len().max(1) as f64;
    let r: Vec<f64> = med.iter().map(|v| (v - mean).min(0.0).exp()).collect();
    if r.iter().all(|v| *v > 10f64.powf(-0.1)) {
        return Ok(Vec::new());
    }
    // frequency sampling of √R on an N-point grid, zero phase, Hann window
    let nfft = 1024usize;
    let amp = |f: f64| {
        let x = f / welch.df();
        let k = (x.floor() as usize).min(nb - 2);
        let t = (x - k as f64).clamp(0.0, 1.0);
        ((1.0 - t) * r[k] + t * r[k + 1]).sqrt()
    };
    let h_k: Vec<f64> = (0..=nfft / 2)
        .map(|k| amp(k as f64 * fs / nfft as f64))
        .collect();
    let mut h = vec![0.0; 2 * CHAIN_HALF + 1];
    for (j, v) in h.iter_mut().enumerate() {
        let m = j as f64 - CHAIN_HALF as f64;
        let mut acc = h_k[0];
        for (k, a) in h_k.iter().enumerate().skip(1) {
            let w = if k == nfft / 2 { 1.0 } else { 2.0 };
            acc += w * a * (2.0 * PI * k as f64 * m / nfft as f64).cos();
        }
        let win = 0.5 * (1.0 + (PI * m / (CHAIN_HALF as f64 + 1.0)).cos());
        *v = acc / nfft as f64 * win;
    }
    Ok(h)
}

/// Impact paths and gains fitted for one preload.
struct PathFit {
    paths: Vec<ImpactPath>,
    gains: Vec<f64>,
    sims: Vec<Excitation>,
}

impl PathFit {
    fn path_of(&self, loc: Location) -> &StructuralPath {
        &self
            .paths
            .iter()
            .find(|p| p.location == loc)
            .unwrap_or(&self.paths[0])
            .path
    }
}

/// For each location with training records: the AR path of the pooled log ratio of smoothed
/// excess PSD (measured minus healthy, at least a tenth of the measured) to smoothed excitation
/// PSD, each record's ratio normalised to zero mean log; then each record's gain from its excess
/// mean square.
#[allow(clippy::too_many_arguments)]
fn fit_paths(
    bearing: Bearing,
    preload_m: f64,
    fs: f64,
    machine: &MachineModel,
    training: &[TrainingRecord<'_>],
    measured: &[(Vec<f64>, f64)],
    s_h: &[f64],
    ms_h: f64,
    welch: &Welch,
    half: usize,
    len: usize,
) -> Result<PathFit, CloseLoopError> {
    let nb = welch.n_bins();
    let mut sims = Vec::with_capacity(training.len());
    let mut ratios = Vec::with_capacity(training.len());
    for (i, t) in training.iter().enumerate() {
        let x = excitation(
            bearing,
            preload_m,
            t.location.class(),
            t.size_mm,
            t.rpm * machine.speed_ratio,
            t.outer_angle_rad,
            fs,
            t.y.len().min(len) + WARMUP,
            1000 + i as u64,
        )?;
        let s_x = smooth(&welch.try_psd(&x.vertical)?, half);
        let r: Vec<f64> = measured[i]
            .0
            .iter()
            .zip(s_h)
            .zip(&s_x)
            .map(|((a, b), x)| ((a - b).max(0.1 * a) / x.max(1e-300)).max(1e-300).ln())
            .collect();
        let mean = r[1..].iter().sum::<f64>() / (nb - 1) as f64;
        ratios.push(r.iter().map(|v| v - mean).collect::<Vec<f64>>());
        sims.push(x);
    }
    let mut paths = Vec::new();
    for loc in Location::ALL {
        let idx: Vec<usize> = (0..training.len())
            .filter(|&i| training[i].location == loc && ratios[i].iter().all(|v| v.is_finite()))
            .collect();
        if idx.is_empty() {
            continue;
        }
        let shape: Vec<f64> = (0..nb)
            .map(|k| (idx.iter().map(|&i| ratios[i][k]).sum::<f64>() / idx.len() as f64).exp())
            .collect();
        let mut path = StructuralPath::from_psd(&shape, welch.df(), fs, IMPACT_PATH_ORDER)?;
        path.excitation_variance = 1.0;
        paths.push(ImpactPath {
            location: loc,
            path,
        });
    }
    if paths.is_empty() {
        return Err(CloseLoopError::Model {
            reason: "no training fault record carries a usable spectrum".into(),
        });
    }
    let mut fit = PathFit {
        paths,
        gains: Vec::new(),
        sims,
    };
    for (i, t) in training.iter().enumerate() {
        let through = fit.path_of(t.location).filter(&fit.sims[i].vertical);
        let ms_x = mean_square(&through[WARMUP.min(through.len() / 2)..]);
        if !(ms_x > 0.0 && ms_x.is_finite()) {
            return Err(CloseLoopError::Model {
                reason: format!("the excitation of {} is zero", t.name),
            });
        }
        fit.gains
            .push(((measured[i].1 - ms_h).max(0.0) / ms_x).sqrt());
    }
    Ok(fit)
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

/// Calibrate a rig: the healthy machine on `healthy` (at `fs`, `rpm`), the impact path and one
/// severity per training record (module docs). `rule` says how the training records were chosen.
///
/// # Errors
/// The errors of [`crate::machine::calibrate`], of the Welch PSD and of [`excitation`];
/// [`CloseLoopError::Model`] when no training record carries more power than the healthy
/// machine.
pub fn calibrate_rig(
    healthy: &[f64],
    fs: f64,
    rpm: f64,
    bearing: Bearing,
    training: &[TrainingRecord<'_>],
    cfg: &crate::CheckedConfig,
    rule: &str,
) -> Result<RigModel, CloseLoopError> {
    let machine = crate::machine::calibrate(healthy, fs, rpm, bearing, cfg)?;
    // outer-race records with the spall off the vertical (sensor) axis calibrate the sensor's
    // horizontal sensitivity; the rest calibrate paths and severities
    let off_axis = |t: &TrainingRecord<'_>| {
        t.location == Location::Outer && t.outer_angle_rad.sin().abs() < 0.5
    };
    let cross: Vec<TrainingRecord<'_>> = training.iter().copied().filter(off_axis).collect();
    let training: Vec<TrainingRecord<'_>> =
        training.iter().copied().filter(|t| !off_axis(t)).collect();
    let training = training.as_slice();
    if training.is_empty() {
        return Err(CloseLoopError::Model {
            reason: "no training fault record to calibrate the impact paths on".into(),
        });
    }
    let nperseg = ((fs / 12.0).log2().round().exp2() as usize).max(crate::MIN_NPERSEG);
    let welch = Welch::new(fs, nperseg)?;
    let half = ((SMOOTH_HZ / welch.df()).round() as usize).max(1);
    let s_h = smooth(&welch.try_psd(healthy)?, half);
    let ms_h = variance(healthy);
    let measured: Vec<(Vec<f64>, f64)> = training
        .iter()
        .map(|t| Ok((smooth(&welch.try_psd(t.y)?, half), variance(t.y))))
        .collect::<Result<_, CloseLoopError>>()?;
    let chain_lines = chain_tones(&machine, healthy, training, fs)?;
    let kurt: Vec<f64> = training.iter().map(|t| kurtosis(t.y)).collect();
    // the contact load: the preload whose fitted rig gives the training records' kurtosis best
    // (mean |ln(simulated / measured kurtosis)|), on 2 s excitations
    let short = (2.0 * fs) as usize;
    let mut best: Option<(f64, f64)> = None;
    for &preload in PRELOADS_M {
        let fit = fit_paths(
            bearing, preload, fs, &machine, training, &measured, &s_h, ms_h, &welch, half, short,
        )?;
        let mut err = 0.0;
        for (i, t) in training.iter().enumerate() {
            let (g, path) = (&fit.gains[i], fit.path_of(t.location));
            let through = path.filter(
                &fit.sims[i]
                    .vertical
                    .iter()
                    .map(|v| g * v)
                    .collect::<Vec<_>>(),
            );
            let bg = background_of(
                &machine,
                &chain_lines,
                fs,
                t.rpm,
                through.len(),
                7 + i as u64,
            );
            let y: Vec<f64> = through.iter().zip(&bg).map(|(a, b)| a + b).collect();
            err += (kurtosis(&y[WARMUP.min(y.len() / 2)..]) / kurt[i])
                .ln()
                .abs();
        }
        let err = err / training.len() as f64;
        if best.is_none_or(|b| err < b.1) {
            best = Some((preload, err));
        }
    }
    let preload_m = best.map_or(0.0, |b| b.0);
    let long = (4.0 * fs) as usize;
    let fit = fit_paths(
        bearing, preload_m, fs, &machine, training, &measured, &s_h, ms_h, &welch, half, long,
    )?;
    // severities (gain, random fraction) of every training record for a sensor κ
    let severities_for = |kappa: f64, chain: &[f64]| {
        let mut out = Vec::with_capacity(training.len());
        for (i, t) in training.iter().enumerate() {
            let path = fit.path_of(t.location);
            let seen = fit.sims[i].seen(kappa);
            let bg = apply_fir(
                chain,
                &background_of(
                    &machine,
                    &chain_lines,
                    fs,
                    t.rpm,
                    fit.sims[i].vertical.len(),
                    7 + i as u64,
                ),
            );
            let excess = (measured[i].1 - ms_h).max(0.0);
            // gain and kurtosis of the simulated record for a random fraction q
            let at = |q: f64| {
                let through = apply_fir(chain, &path.filter(&mix(&seen, q, 11 + i as u64)));
                let skip = WARMUP.min(through.len() / 2);
                let g = (excess / mean_square(&through[skip..]).max(1e-300)).sqrt();
                let y: Vec<f64> = through[skip..]
                    .iter()
                    .zip(&bg[skip..])
                    .map(|(a, b)| g * a + b)
                    .collect();
                (g, kurtosis(&y))
            };
            let (mut lo, mut hi) = (0.0, 0.99);
            let q = if at(lo).1 <= kurt[i] {
                0.0
            } else if at(hi).1 >= kurt[i] {
                hi
            } else {
                for _ in 0..14 {
                    let mid = 0.5 * (lo + hi);
                    if at(mid).1 > kurt[i] {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                0.5 * (lo + hi)
            };
            out.push(Severity {
                location: t.location,
                size_mm: t.size_mm,
                gain: at(q).0,
                random_fraction: q,
                record: t.name.to_string(),
            });
        }
        out
    };
    let severities = severities_for(0.0, &[]);
    let impact_paths = fit.paths.clone();
    let mut rig = RigModel {
        format: FORMAT.to_string(),
        version: VERSION,
        fs_hz: fs,
        units: "unknown".to_string(),
        bearing: machine.bearing.clone(),
        healthy: machine.clone(),
        chain_lines: chain_lines.clone(),
        impact_paths,
        preload_m,
        sensor_horizontal: 0.0,
        chain_fir: Vec::new(),
        depth_m: DEPTH_M,
        slip_fraction: SLIP_FRACTION,
        severities,
        provenance: RigProvenance {
            healthy_record: String::new(),
            training_records: training.iter().map(|t| t.name.to_string()).collect(),
            training_rule: rule.to_string(),
        },
    };
    rig.provenance
        .training_records
        .extend(cross.iter().map(|t| t.name.to_string()));
    // κ from the off-axis records with the κ = 0 severities, then the severities again with κ
    rig.sensor_horizontal = fit_horizontal(&rig, bearing, &cross, ms_h)?;
    if rig.sensor_horizontal > 0.0 {
        rig.severities = severities_for(rig.sensor_horizontal, &[]);
    }
    // the measurement chain's response (the fault records' anti-alias roll-off), then the
    // severities once more behind it
    rig.chain_fir = chain_response(&rig, training, &measured, &welch, half)?;
    if !rig.chain_fir.is_empty() {
        rig.severities = severities_for(rig.sensor_horizontal, &rig.chain_fir);
    }
    Ok(rig)
}

/// The sensor's horizontal sensitivity κ: for each off-axis outer-race record, the κ in [0, 20]
/// (bisection) at which the rig's simulated mean square — the 6 o'clock severity of its size —
/// matches the measured one; the geometric mean over the records (0 without any).
fn fit_horizontal(
    rig: &RigModel,
    bearing: Bearing,
    cross: &[TrainingRecord<'_>],
    ms_h: f64,
) -> Result<f64, CloseLoopError> {
    let mut logs = Vec::new();
    for (i, t) in cross.iter().enumerate() {
        let (g, q) = rig.severity(Location::Outer, t.size_mm)?;
        let e = excitation(
            bearing,
            rig.preload_m,
            FaultClass::Outer,
            t.size_mm,
            t.rpm * rig.healthy.speed_ratio,
            t.outer_angle_rad,
            rig.fs_hz,
            t.y.len().min((4.0 * rig.fs_hz) as usize) + WARMUP,
            2000 + i as u64,
        )?;
        let path = rig.impact_path(Location::Outer)?;
        let ms = |k: f64| {
            let f = path.filter(&mix(&e.seen(k), q, 13 + i as u64));
            g * g * mean_square(&f[WARMUP..])
        };
        let target = (variance(t.y) - ms_h).max(0.0);
        let (mut lo, mut hi) = (0.0f64, 20.0f64);
        if ms(hi) < target || ms(lo) > target {
            continue;
        }
        for _ in 0..30 {
            let mid = 0.5 * (lo + hi);
            if ms(mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        logs.push((0.5 * (lo + hi)).max(1e-6).ln());
    }
    Ok(if logs.is_empty() {
        0.0
    } else {
        (logs.iter().sum::<f64>() / logs.len() as f64).exp()
    })
}

/// Band edges of [`SignalStats::band_energy`], Hz (the last band ends at fs/2).
pub const BANDS_HZ: [f64; 4] = [0.0, 1000.0, 2000.0, 4000.0];

/// What a simulated and a measured recording are compared on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SignalStats {
    /// RMS (mean removed), recording units.
    pub rms: f64,
    /// Kurtosis (not excess; 3 for a Gaussian).
    pub kurtosis: f64,
    /// Crest factor max|y|/RMS.
    pub crest: f64,
    /// Mean square in 0–1, 1–2, 2–4 and 4 kHz–fs/2 (Welch PSD integrated), units².
    pub band_energy: [f64; 4],
    /// Prominence of the fault line in the envelope spectrum, dB: the largest envelope power
    /// within ±1.5 % of the fault frequency over the median power of ±20 % around it (`None`
    /// without a fault frequency).
    pub line_prominence_db: Option<f64>,
}

/// [`SignalStats`] of `y` at `fs`, with the envelope line at `fault_hz` when given.
///
/// # Errors
/// [`CloseLoopError::TooShort`] below 4096 samples, and the errors of the Welch PSD and the
/// envelope spectrum.
pub fn signal_stats(
    y: &[f64],
    fs: f64,
    fault_hz: Option<f64>,
) -> Result<SignalStats, CloseLoopError> {
    if y.len() < 4096 {
        return Err(CloseLoopError::TooShort {
            needed: 4096,
            found: y.len(),
        });
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let c: Vec<f64> = y.iter().map(|v| v - mean).collect();
    let stat = |r: Result<f64, residual_features::FeatureError>| match r {
        Ok(v) => Ok(v),
        Err(residual_features::FeatureError::ZeroSpread { .. }) => Err(CloseLoopError::ZeroSignal),
        Err(e) => Err(CloseLoopError::Spectral {
            reason: e.to_string(),
        }),
    };
    let (rms, kurtosis, crest) = (
        stat(residual_features::rms(&c))?,
        stat(residual_features::kurtosis(&c))?,
        stat(residual_features::crest_factor(&c))?,
    );
    let welch = Welch::new(fs, 1024)?;
    let p = welch.try_psd(y)?;
    let mut band = [0.0; 4];
    for (k, v) in p.iter().enumerate() {
        let f = welch.frequency(k);
        let b = BANDS_HZ.iter().rposition(|&e| f >= e).unwrap_or(0);
        band[b] += v * welch.df();
    }
    let line_prominence_db = match fault_hz {
        Some(f0) if f0 > 0.0 && 1.2 * f0 < 0.5 * fs => {
            let (e, de) = crate::spectrum::envelope_periodogram(y, fs)?;
            let idx = |f: f64| ((f / de).round() as usize).min(e.len() - 1);
            let peak = e[idx(0.985 * f0)..=idx(1.015 * f0)]
                .iter()
                .copied()
                .fold(0.0, f64::max);
            let around: Vec<f64> = e[idx(0.8 * f0)..=idx(1.2 * f0)].to_vec();
            let med = crate::spectrum::median(&around);
            Some(10.0 * (peak / med.max(1e-300)).log10())
        }
        _ => None,
    };
    Ok(SignalStats {
        rms,
        kurtosis,
        crest,
        band_energy: band,
        line_prominence_db,
    })
}

/// Simulated against measured statistics of one condition, and the calibration targets of
/// issue "A simulator calibrated to the measured rig": RMS and every band energy within a factor
/// [`Comparison::FACTOR`], kurtosis within [`Comparison::KURTOSIS_TOLERANCE`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// Of the measured recording.
    pub measured: SignalStats,
    /// Of the simulated one.
    pub simulated: SignalStats,
}

impl Comparison {
    /// Largest ratio (either way) of RMS and band energies that meets the target.
    pub const FACTOR: f64 = 1.5;
    /// Largest relative kurtosis error that meets the target.
    pub const KURTOSIS_TOLERANCE: f64 = 0.3;

    /// RMS simulated / measured.
    pub fn rms_ratio(&self) -> f64 {
        self.simulated.rms / self.measured.rms
    }
    /// Kurtosis simulated / measured − 1.
    pub fn kurtosis_error(&self) -> f64 {
        self.simulated.kurtosis / self.measured.kurtosis - 1.0
    }
    /// Band energies simulated / measured.
    pub fn band_ratios(&self) -> [f64; 4] {
        std::array::from_fn(|b| self.simulated.band_energy[b] / self.measured.band_energy[b])
    }
    /// Whether a ratio is within [`Comparison::FACTOR`] either way.
    pub fn within(ratio: f64) -> bool {
        (1.0 / Self::FACTOR..=Self::FACTOR).contains(&ratio)
    }
    /// (RMS, all four bands, kurtosis) targets met.
    pub fn meets(&self) -> (bool, bool, bool) {
        (
            Self::within(self.rms_ratio()),
            self.band_ratios().iter().all(|r| Self::within(*r)),
            self.kurtosis_error().abs() <= Self::KURTOSIS_TOLERANCE,
        )
    }
}
