//! Degradation runs on the **calibrated CWRU rig** (6205 drive end, 12 kHz, in g): the
//! schedule of `bearing_model::life` (onset, speed drift, load and gain steps, drawn from the
//! run's seed) rendered by the rig's synthesis with a spall whose **width grows** from the onset
//! on: `w(k) = w₀·(w₁/w₀)^u`, `u = (k − onset)/(K − 1 − onset)` — exponential in time.
//!
//! Each recording is [`RigModel::synthesize_parts`] at the recording's true speed and the
//! spall's width, with its own seed: the healthy machine `h` and the fault's contribution `f`,
//! recorded as `gain·load·(h + f)` (`f` absent before the onset). The rig's 5-DOF radial load is
//! its calibrated one (its severities were fitted there), so a load step scales the machine's
//! vibration as a whole; on the rig a load step and a gain step therefore differ only in when
//! they happen (the truth tells them apart). Widths outside the calibrated sizes hold the
//! nearest calibrated severity gain (the 5-DOF excitation still follows the width); the truth's
//! notes say which recordings are outside. `docs/equations/life.md` gives the reasons.

use super::RigModel;
use super::synthesis::Synthesis;
use bearing_model::FaultLocation;
use bearing_model::life::{
    LifeError, LifeRecording, LifeTruth, Plan, Schedule, plan_schedule, recording_rng,
};
use close_loop::CloseLoopError;
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Default spall width at the onset and at the last recording, mm: 0.02 mm (an incipient spall)
/// to 0.178 mm (0.007 in, the smallest calibrated CWRU size). Below 0.178 mm the rig holds the
/// 0.007 in severity gain and the level follows the 5-DOF excitation's growth with the width:
/// fault-over-healthy RMS about −19 → +17 dB (inner), −15 → +24 dB (outer), −30 → +8 dB (ball)
/// over this range, monotone. Not up to 0.533 mm: the calibrated levels are not monotone in
/// size (CWRU's 0.014 in records are quieter than its 0.007 in ones), so a growing width there
/// would not be a growing vibration (see `docs/equations/life.md`).
pub const DEFAULT_WIDTH_MM: (f64, f64) = (0.02, 0.1778);
/// Default nominal speed, rpm (CWRU's 0 hp speed, the rig's calibration).
pub const DEFAULT_RPM: f64 = 1797.0;
/// Fewest samples a rig recording may have (the rig's synthesis needs 1024).
pub const MIN_SAMPLES: usize = 1024;

/// A degradation run on the calibrated rig.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigLifeConfig {
    /// Where the spall is.
    pub location: FaultLocation,
    /// Spall width at the onset and at the last recording, mm (0 < start < end ≤ 2).
    pub width_mm: (f64, f64),
    /// Nominal shaft speed, rpm (the rig's calibrated speed ratio is applied by the rig).
    pub rpm: f64,
    /// Outer-race spall position, rad (6 o'clock, the load zone's centre, = −π/2).
    pub outer_angle_rad: f64,
    /// When things happen (its `duration_s` × the rig's rate must give ≥ 1024 samples).
    pub schedule: Schedule,
}

impl RigLifeConfig {
    /// A spall at `location`, [`DEFAULT_WIDTH_MM`], [`DEFAULT_RPM`], outer race at 6 o'clock,
    /// the default schedule.
    pub fn new(location: FaultLocation) -> Self {
        Self {
            location,
            width_mm: DEFAULT_WIDTH_MM,
            rpm: DEFAULT_RPM,
            outer_angle_rad: -PI / 2.0,
            schedule: Schedule::default(),
        }
    }

    /// The growth law, in words.
    pub fn width_law(&self) -> String {
        format!(
            "spall_width_mm = {}·({}/{})^u, u = (k - onset)/(K - 1 - onset): exponential in time",
            self.width_mm.0, self.width_mm.1, self.width_mm.0
        )
    }

    /// Check the schedule, widths, speed and length against `rig`.
    ///
    /// # Errors
    /// [`RigLifeError::Life`] for a bad schedule or width, [`RigLifeError::Rig`] for a speed
    /// or length the rig refuses.
    pub fn validate(&self, rig: &RigModel) -> Result<(), RigLifeError> {
        self.schedule.validate()?;
        let (a, b) = self.width_mm;
        if !(a.is_finite() && b.is_finite() && a > 0.0 && a < b && b <= 2.0) {
            return Err(LifeError::InvalidConfig {
                field: "width_mm",
                value: format!("({a}, {b})"),
                expected: "0 < start < end <= 2 mm",
            }
            .into());
        }
        let d = self.schedule.speed_drift;
        for f in [1.0 - d, 1.0 + d] {
            let r = self.rpm * f;
            if !(r.is_finite() && r > 0.0 && r <= 100_000.0) {
                return Err(CloseLoopError::InvalidRpm { rpm: r }.into());
            }
        }
        if !self.outer_angle_rad.is_finite() {
            return Err(LifeError::InvalidConfig {
                field: "outer_angle_rad",
                value: self.outer_angle_rad.to_string(),
                expected: "finite",
            }
            .into());
        }
        let n = (self.schedule.duration_s * rig.fs_hz).round();
        if n < MIN_SAMPLES as f64 {
            return Err(LifeError::InvalidConfig {
                field: "duration_s",
                value: self.schedule.duration_s.to_string(),
                expected: "at least 1024 samples at the rig's rate (0.0854 s at 12 kHz)",
            }
            .into());
        }
        Ok(())
    }
}

/// What can go wrong with a rig run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RigLifeError {
    /// The run's configuration (schedule, widths).
    #[error(transparent)]
    Life(#[from] LifeError),
    /// The rig's synthesis refused.
    #[error(transparent)]
    Rig(#[from] CloseLoopError),
}

/// Draw the run's schedule and its truth (no samples).
///
/// # Errors
/// [`RigLifeConfig::validate`]'s.
pub fn plan_rig_run(
    rig: &RigModel,
    cfg: &RigLifeConfig,
    seed: u64,
) -> Result<(Plan, LifeTruth), RigLifeError> {
    cfg.validate(rig)?;
    let plan = plan_schedule(&cfg.schedule, seed)?;
    let geometry = rig
        .bearing
        .parse::<bearing_model::Bearing>()
        .map_err(|_| CloseLoopError::UnknownBearing {
            name: rig.bearing.clone(),
        })?
        .geometry();
    let mut truth = LifeTruth::from_plan(
        &plan,
        &cfg.schedule,
        seed,
        &format!(
            "calibrated_rig::life (calibrated CWRU rig, {} at {} Hz; {})",
            rig.bearing, rig.fs_hz, rig.units
        ),
        &rig.bearing,
        geometry.orders(),
        cfg.location,
        rig.fs_hz,
        &rig.units,
        cfg.rpm,
        &cfg.width_law(),
    );
    let (w0, w1) = cfg.width_mm;
    for (t, g) in truth.recordings.iter_mut().zip(&plan.growth) {
        t.spall_width_mm = g.map(|u| w0 * (w1 / w0).powf(u));
    }
    if let Some(((lo, hi), _)) = rig.calibrated_range_mm_at(cfg.location, cfg.outer_angle_rad) {
        let outside: Vec<usize> = truth
            .recordings
            .iter()
            .filter(|t| {
                t.spall_width_mm
                    .is_some_and(|w| w < lo * (1.0 - 1e-9) || w > hi * (1.0 + 1e-9))
            })
            .map(|t| t.index)
            .collect();
        if !outside.is_empty() {
            truth.notes.push(format!(
                "recordings {outside:?}: spall width outside the calibrated {lo:.3}-{hi:.3} mm; the nearest calibrated severity gain is held (the 5-DOF excitation follows the width)"
            ));
        }
    }
    truth.notes.push(format!(
        "load scales the rig's whole recording (healthy machine and fault) at its calibrated radial load; gain scales it too; the shaft turns at the nominal speed x the calibrated speed ratio {}",
        rig.healthy.speed_ratio
    ));
    Ok((plan, truth))
}

fn render(
    rig: &RigModel,
    cfg: &RigLifeConfig,
    seed: u64,
    plan: &Plan,
    truth: &LifeTruth,
    index: usize,
    with_fault: bool,
) -> Result<LifeRecording, RigLifeError> {
    let t = truth.recording(index)?;
    let n = (cfg.schedule.duration_s * rig.fs_hz).round() as usize;
    let rec_seed: u64 = recording_rng(seed, index).random();
    let class = match (t.spall_width_mm, with_fault) {
        (Some(_), true) => cfg.location.class(),
        _ => bearing_model::FaultClass::None,
    };
    let mut s = Synthesis::new(
        class,
        t.spall_width_mm.unwrap_or(cfg.width_mm.0),
        t.rpm_true,
        n,
        rec_seed,
    );
    s.outer_angle_rad = cfg.outer_angle_rad;
    let (h, f) = rig.synthesize_parts(&s)?;
    let k = plan.gain[index] * plan.load[index];
    let samples = h.iter().zip(&f).map(|(a, b)| k * (a + b)).collect();
    let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
    Ok(LifeRecording {
        index,
        time_s: t.time_s,
        samples,
        fs_hz: rig.fs_hz,
        rpm_true: t.rpm_true,
        rpm_declared: truth.rpm_declared,
        unit: rig.units.clone(),
        healthy_rms: k * rms(&h),
        fault_rms: k * rms(&f),
    })
}

/// Render recording `index` of the rig run of `seed` (depends on `(rig, cfg, seed, index)`
/// only: recordings may be generated in any order or in parallel).
///
/// # Errors
/// As [`plan_rig_run`], [`LifeError::NoSuchRecording`] and the rig's synthesis errors.
pub fn simulate_rig_recording(
    rig: &RigModel,
    cfg: &RigLifeConfig,
    seed: u64,
    index: usize,
) -> Result<LifeRecording, RigLifeError> {
    let (plan, truth) = plan_rig_run(rig, cfg, seed)?;
    render(rig, cfg, seed, &plan, &truth, index, true)
}

/// Recording `index` with its spall left out (the same seed, speed, load and gain).
///
/// # Errors
/// As [`simulate_rig_recording`].
pub fn simulate_rig_recording_healthy(
    rig: &RigModel,
    cfg: &RigLifeConfig,
    seed: u64,
    index: usize,
) -> Result<LifeRecording, RigLifeError> {
    let (plan, truth) = plan_rig_run(rig, cfg, seed)?;
    render(rig, cfg, seed, &plan, &truth, index, false)
}

/// The whole rig run, in index order, and its truth.
///
/// # Errors
/// As [`simulate_rig_recording`].
pub fn simulate_rig_run(
    rig: &RigModel,
    cfg: &RigLifeConfig,
    seed: u64,
) -> Result<(Vec<LifeRecording>, LifeTruth), RigLifeError> {
    let (plan, truth) = plan_rig_run(rig, cfg, seed)?;
    let recs = (0..cfg.schedule.recordings)
        .map(|i| render(rig, cfg, seed, &plan, &truth, i, true))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((recs, truth))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cwru_rig;

    fn small(location: FaultLocation) -> RigLifeConfig {
        let mut c = RigLifeConfig::new(location);
        c.schedule.recordings = 8;
        c.schedule.duration_s = 0.2;
        c
    }

    #[test]
    fn rig_run_is_seeded_grows_and_is_healthy_before_onset() {
        let rig = cwru_rig().unwrap();
        for loc in FaultLocation::ALL {
            let mut c = small(loc);
            // 2 s: a ball spall strikes 8 % of the time (the calibrated strike gate, bursts of
            // 4 fault periods), so a short recording can be silent
            c.schedule.duration_s = 2.0;
            let (a, truth) = simulate_rig_run(&rig, &c, 4).unwrap();
            let (b, _) = simulate_rig_run(&rig, &c, 4).unwrap();
            assert_eq!(a, b);
            assert_eq!(simulate_rig_recording(&rig, &c, 4, 6).unwrap(), a[6]);
            assert_eq!(a[0].unit, "g");
            assert_eq!(a[0].samples.len(), 24_000);
            let on = truth.onset_index;
            let w: Vec<f64> = truth.recordings[on..]
                .iter()
                .map(|t| t.spall_width_mm.unwrap())
                .collect();
            assert!(w.windows(2).all(|p| p[1] > p[0]), "{w:?}");
            assert!((w[0] - c.width_mm.0).abs() < 1e-12);
            assert!((w.last().unwrap() - c.width_mm.1).abs() < 1e-12);
            for (i, r) in a.iter().enumerate() {
                let h = simulate_rig_recording_healthy(&rig, &c, 4, i).unwrap();
                if i < on {
                    assert_eq!(r.samples, h.samples);
                    assert_eq!(r.fault_rms, 0.0);
                } else {
                    // the strike gate may keep a small spall silent through a short recording
                    assert!(r.fault_rms >= 0.0, "{loc} {i}");
                }
            }
            assert!(a.last().unwrap().fault_rms > 0.0, "{loc}");
            eprintln!(
                "{loc}: fault/healthy dB per recording after onset: {:?}",
                a[on..]
                    .iter()
                    .map(|r| (20.0 * (r.fault_rms / r.healthy_rms).log10() * 10.0).round() / 10.0)
                    .collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn the_parts_sum_to_the_synthesis() {
        let rig = cwru_rig().unwrap();
        for class in [
            bearing_model::FaultClass::Outer,
            bearing_model::FaultClass::InnerBall,
        ] {
            let s = Synthesis::new(class, 0.1778, 1797.0, 4096, 9);
            let y = rig.synthesize(&s).unwrap();
            let (h, f) = rig.synthesize_parts(&s).unwrap();
            let none = Synthesis {
                class: bearing_model::FaultClass::None,
                ..s
            };
            assert_eq!(h, rig.synthesize(&none).unwrap());
            let top = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for ((a, b), c) in y.iter().zip(&h).zip(&f) {
                assert!((a - (b + c)).abs() <= 1e-9 * top, "{a} vs {}", b + c);
            }
        }
        let (_, f) = rig
            .synthesize_parts(&Synthesis::new(
                bearing_model::FaultClass::None,
                0.1,
                1797.0,
                2048,
                1,
            ))
            .unwrap();
        assert!(f.iter().all(|v| *v == 0.0));
    }

    #[test]
    fn bad_rig_configs_are_typed_errors() {
        let rig = cwru_rig().unwrap();
        let mut c = small(FaultLocation::Inner);
        c.width_mm = (0.5, 0.2);
        assert!(matches!(
            plan_rig_run(&rig, &c, 0),
            Err(RigLifeError::Life(LifeError::InvalidConfig { .. }))
        ));
        let mut c = small(FaultLocation::Inner);
        c.schedule.duration_s = 0.05;
        assert!(plan_rig_run(&rig, &c, 0).is_err());
        let mut c = small(FaultLocation::Inner);
        c.rpm = f64::NAN;
        assert!(matches!(
            plan_rig_run(&rig, &c, 0),
            Err(RigLifeError::Rig(_))
        ));
        let mut c = small(FaultLocation::Inner);
        c.schedule.recordings = 0;
        assert!(plan_rig_run(&rig, &c, 0).is_err());
    }
}
