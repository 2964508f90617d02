//! The fault's excitation: the 5-DOF model's housing and pedestal accelerations under the
//! contact forces of the spalls ([`excitation`], [`Excitation`]) and the constants it is run at.

use super::{
    Bearing, CloseLoopError, FaultClass, FaultSet, Housing, ParamSet, Scenario, Slip, Spall, bad,
};

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
/// ([`crate::RigModel::excitation_housing_hz`]); those written before hold
/// [`LEGACY_EXCITATION_HOUSING_HZ`].
pub const EXCITATION_HOUSING_HZ: f64 = 12_000.0;
/// The excitation model's sprung-mass resonance of rig files written before it was stored, Hz.
pub const LEGACY_EXCITATION_HOUSING_HZ: f64 = 20_000.0;

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

/// Smallest spall width accepted, mm (1 nm: anything positive in practice, printable in an error).
const MIN_SIZE_MM: f64 = 1e-6;

/// The 5-DOF excitation of `class` (spalls of `size_mm` at depth [`DEPTH_M`], outer race at
/// `outer_angle_rad`, slip [`SLIP_FRACTION`], every ball preloaded by `preload_m`, the shaft
/// loaded by `radial_load_n` downwards): `n` samples of the housing acceleration (m/s²)
/// with the sprung-mass resonance moved to `housing_hz` (ζ 0.7; [`EXCITATION_HOUSING_HZ`] for a
/// new calibration, [`crate::RigModel::excitation_housing_hz`] for a rig's), and of the horizontal
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
