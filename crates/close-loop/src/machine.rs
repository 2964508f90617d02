//! The calibrated machine model: the declared 5-DOF model plus everything the loop added on a
//! recording — speed ratio, the structural path from bearing to sensor (its modes), the excitation
//! and noise floor, shaft harmonics and tones, channel modes and modulations — saved as versioned
//! JSON, reloaded, validated against the recording it is used on, and taken by
//! [`crate::close_loop_from`] as its declared model.

use crate::CloseLoopError;
use crate::effect::{Mode, Modulation};
use crate::engine::{Ctx, State};
use crate::path::{PathMode, StructuralPath};
use crate::report::EffectEntry;
use serde::{Deserialize, Serialize};

/// Bins of the frequency grid (0 ..= fs/2) the path's and floor's autocorrelation is summed on
/// in [`MachineModel::predictor_model`]: 0.37 Hz at 12 kHz, finer than any calibrated mode's
/// half-power width.
const PREDICTOR_GRID_BINS: usize = 16_385;

/// Most effects `hybrid-fdd calibrate` (and `cargo xtask calibrate`) lets the loop add by
/// default: a healthy machine holds many lines (the shaft comb, mains and interference tones)
/// and channel modes. 97.mat at 12 kHz takes 17 (since channel modes shape the background too)
/// and stops on its own; 16 cut it short.
pub const CALIBRATE_MAX_EFFECTS: usize = 24;

/// Calibrate a machine model on a healthy recording `y` (sampled at `fs` Hz, shaft at `rpm`,
/// `bearing` of the 5-DOF model): the loop from the declared healthy 5-DOF physics with default
/// slip, verified from the model as saved ([`calibrate_with`]), and the [`MachineModel`] it ends
/// with (what `cargo xtask calibrate` writes). The loop fits on the first part of `y` and scores
/// on the rest ([`crate::fit_len`]); pass only data the caller may fit on.
///
/// # Errors
/// As [`crate::close_loop`].
pub fn calibrate(
    y: &[f64],
    fs: f64,
    rpm: f64,
    bearing: bearing_model::Bearing,
    cfg: &crate::CheckedConfig,
) -> Result<MachineModel, CloseLoopError> {
    let rates = crate::BearingSpec::designated(bearing);
    let op = crate::OperatingPoint::new(rpm, rates, bearing_model::FaultClass::None)?;
    let model = crate::physics::PhysicsModel {
        bearing,
        ..crate::physics::PhysicsModel::default()
    };
    Ok(calibrate_with(&model, y, fs, &op, cfg)?.machine)
}

/// Verification passes a calibration runs at most ([`calibrate_with`]).
pub const MAX_VERIFICATION_PASSES: usize = 2;

/// A calibration: the loop on `y` from the declared `model` ([`crate::close_loop`]; on a
/// recording declared healthy the model is given a structural path if the loop added none,
/// [`MachineModel::ensure_path`]), then a verification pass — the loop again on the same recording, started from the machine model
/// as it is saved (JSON round trip, [`crate::close_loop_from`]). A clean recording must add
/// nothing to its own model: when the pass adds nothing, the saved model's own held-out error on
/// the recording (the pass's start) becomes the calibration's end error (`error_after`,
/// `provenance.error_after`), so a run from the saved model starts where the calibration ended;
/// when it adds effects (the last round of the first loop was judged on the loop's own state,
/// which the saved model rebuilds only up to the lines' re-fit), they join the ledger (marked
/// "verification pass k"), the model is the pass's end state, and it is verified again, at most
/// [`MAX_VERIFICATION_PASSES`] times (the stop reason says when the last pass still added
/// something). Each pass is recorded in `ledger.verification`.
///
/// # Errors
/// As [`crate::close_loop`].
pub fn calibrate_with(
    model: &dyn crate::DeclaredModel,
    y: &[f64],
    fs: f64,
    op: &crate::OperatingPoint,
    cfg: &crate::CheckedConfig,
) -> Result<crate::Outcome, CloseLoopError> {
    let mut out = crate::close_loop(model, y, fs, op, cfg)?;
    if op.fault == bearing_model::FaultClass::None {
        // a healthy machine model always holds a path ([`MachineModel::ensure_path`]); it is
        // verified as it will be saved, path included
        let n_fit = crate::fit_len(y.len(), cfg);
        out.machine
            .ensure_path(&y[..n_fit], &y[n_fit..], cfg.get().max_path_order)?;
    }
    let declared_error = out.ledger.error_before;
    let mut converged = false;
    for pass in 1..=MAX_VERIFICATION_PASSES {
        let saved = MachineModel::from_json(&out.machine.to_json()?)?;
        let v = crate::close_loop_from(model, Some(&saved), y, fs, op, cfg)?;
        let added = v.ledger.effects.len();
        out.ledger.verification.push(crate::VerificationPass {
            pass,
            error_start: v.ledger.error_before,
            error_end: v.ledger.error_after,
            effects_added: added,
        });
        if added == 0 {
            out.ledger.error_after = v.ledger.error_before;
            out.ledger.secondary_after = v.ledger.secondary_before;
            out.ledger.residual_rms_after = v.ledger.residual_rms_before;
            out.machine.provenance.error_after = v.ledger.error_before;
            converged = true;
            break;
        }
        merge_pass(&mut out, v, pass, declared_error);
    }
    if !converged {
        out.ledger.stop_reason += &format!(
            "; the verification from the saved model still added effects after {MAX_VERIFICATION_PASSES} passes (the model is the last pass's end state)"
        );
    }
    Ok(out)
}

/// Append a verification pass's effects and end state to the calibration's outcome.
fn merge_pass(out: &mut crate::Outcome, v: crate::Outcome, pass: usize, declared_error: f64) {
    let offset = out.ledger.effects.len();
    let l = v.ledger;
    for mut e in l.effects {
        let own = e.replaces_step.map(|k| k + offset);
        if let (Some(k), Some(j)) = (own, e.replaces_step) {
            e.description = e.description.replace(
                &format!("replaces step {j}'s"),
                &format!("replaces step {k}'s"),
            );
        }
        let earlier = if own.is_none() && e.kind.is_setting() {
            out.ledger
                .effects
                .iter()
                .rposition(|p| p.kind == e.kind)
                .map(|i| i + 1)
        } else {
            None
        };
        if let Some(k) = earlier {
            e.description += &format!("; replaces step {k}'s value (a setting, not an added term)");
        }
        e.description += &format!(" (verification pass {pass})");
        e.replaces_step = own.or(earlier);
        out.ledger.effects.push(e);
    }
    out.ledger.error_after = l.error_after;
    out.ledger.secondary_after = l.secondary_after;
    out.ledger.residual_rms_after = l.residual_rms_after;
    out.ledger.rejected = l.rejected;
    out.ledger.stop_reason = l.stop_reason;
    out.ledger.structural_modes = l.structural_modes;
    out.spectra.model_after = v.spectra.model_after;
    out.machine = v.machine;
    out.machine.provenance.error_before = declared_error;
}

/// Parse one of this crate's versioned JSON files and check its `format` and `version`.
pub(crate) fn parse_versioned<T: serde::de::DeserializeOwned>(
    text: &str,
    format: &str,
    version: u32,
    head: impl Fn(&T) -> (&String, u32),
) -> Result<T, CloseLoopError> {
    let m: T = serde_json::from_str(text).map_err(|e| CloseLoopError::MachineModelFormat {
        reason: e.to_string(),
    })?;
    let (f, v) = head(&m);
    if f != format {
        return Err(CloseLoopError::MachineModelMismatch {
            what: "format",
            expected: format.to_string(),
            found: f.clone(),
        });
    }
    if v != version {
        return Err(CloseLoopError::MachineModelMismatch {
            what: "version",
            expected: version.to_string(),
            found: v.to_string(),
        });
    }
    Ok(m)
}

/// The `format` string of a machine model file.
pub const FORMAT: &str = "hybrid-fdd/machine-model";
/// The current `version`.
pub const VERSION: u32 = 1;

/// A line of the machine model: a shaft order (moves with the speed) or a tone (fixed in Hz).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum MachineLine {
    /// A line at `order` × fr.
    ShaftHarmonic {
        /// Shaft order (half orders allowed).
        order: f64,
        /// Amplitude on the calibration recording, recording units.
        amplitude: f64,
        /// The line's frequency on the calibration recording, Hz, as the loop fitted it (a
        /// shaft comb's lines sit at k·f̂r, f̂r refined from the comb itself, which need not be
        /// `order` × the model's fr exactly; at order 20 a 0.01 % difference is a quarter cycle
        /// over a 2.5 s fitting segment). At another speed the line moves with it:
        /// `frequency_hz` × fr / fr of the calibration. Absent in files written before it
        /// existed (the line then sits at `order` × fr).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        frequency_hz: Option<f64>,
    },
    /// A line at a fixed frequency.
    Tone {
        /// Frequency, Hz.
        frequency_hz: f64,
        /// Amplitude on the calibration recording, recording units.
        amplitude: f64,
    },
}

impl MachineLine {
    /// The line's frequency at shaft rate `fr_hz`, the model being calibrated at `fr_cal_hz`.
    pub fn frequency_at(&self, fr_hz: f64, fr_cal_hz: f64) -> f64 {
        match *self {
            MachineLine::ShaftHarmonic {
                frequency_hz: Some(f),
                ..
            } if fr_cal_hz > 0.0 => f * fr_hz / fr_cal_hz,
            MachineLine::ShaftHarmonic { order, .. } => order * fr_hz,
            MachineLine::Tone { frequency_hz, .. } => frequency_hz,
        }
    }

    /// Amplitude on the calibration recording.
    pub fn amplitude(&self) -> f64 {
        match *self {
            MachineLine::ShaftHarmonic { amplitude, .. } | MachineLine::Tone { amplitude, .. } => {
                amplitude
            }
        }
    }
}

/// Where a machine model came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Provenance {
    /// The recording it was calibrated on (a name; set by the caller).
    pub recording: String,
    /// Held-out error of the declared model on it, dB.
    pub error_before: f64,
    /// Held-out error of this machine model on it, dB.
    pub error_after: f64,
    /// Name of the error metric.
    pub error_metric: String,
    /// Fitting samples `[start, end)`.
    pub fit_samples: [usize; 2],
}

/// A calibrated machine model (JSON, `format` = [`FORMAT`], `version` = [`VERSION`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineModel {
    /// Always [`FORMAT`].
    pub format: String,
    /// Schema version ([`VERSION`]).
    pub version: u32,
    /// Sampling rate the model was identified at, Hz (the path is discrete-time at this rate).
    pub fs_hz: f64,
    /// Units of the recording it was calibrated on ("g", "m/s^2", or "unknown").
    pub units: String,
    /// Bearing designation.
    pub bearing: String,
    /// BPFO, BPFI, FTF, ball-defect rate as multiples of fr.
    pub bearing_orders: [f64; 4],
    /// Declared model name ("physics-5dof", …).
    pub model: String,
    /// Declared speed on the calibration recording, rpm.
    pub declared_rpm: f64,
    /// Declared fault on the calibration recording.
    pub declared_fault: String,
    /// True speed / declared speed.
    pub speed_ratio: f64,
    /// The declared fault's impact rate over the rate its geometry gives at the true speed (a
    /// `defect_rate` effect: the effective contact angle or pitch ratio differs from the
    /// catalogue's); 1 when the loop took none (and then not written).
    #[serde(default = "unit_ratio", skip_serializing_if = "is_unit_ratio")]
    pub defect_rate_ratio: f64,
    /// Gain on the declared physics output.
    pub physics_gain: f64,
    /// Housing mode of the physics model (Hz, ζ) when the loop moved it.
    pub housing_mode: Option<[f64; 2]>,
    /// Shaft forces put into the physics (order, amplitude N, phase rad).
    pub shaft_forces: Vec<[f64; 3]>,
    /// The structural path from bearing to sensor.
    pub path: Option<StructuralPath>,
    /// Level of the path's excitation relative to the identified σ² (1 = as identified).
    pub path_level: f64,
    /// The path's modes (derived from `path`, written for people and scripts).
    pub structural_modes: Vec<PathMode>,
    /// The path the declared physics (a fault's impacts) is seen through, when identified
    /// separately from the broadband path (`null`: the physics is seen through `path`).
    #[serde(default)]
    pub physics_path: Option<StructuralPath>,
    /// White noise floor, units²/Hz (one-sided).
    pub noise_floor_psd: f64,
    /// Lines.
    pub lines: Vec<MachineLine>,
    /// Channel modes on the physics output.
    pub channel_modes: Vec<Mode>,
    /// Amplitude modulations of the structural vibration: the physics output and the path's
    /// background (not the white floor nor the lines; before 2026-11-26, of the physics only).
    pub modulations: Vec<Modulation>,
    /// Random slip fraction of the declared physics at the end of the calibration, when the loop
    /// changed it (absent: the declared model's own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slip_fraction: Option<f64>,
    /// Radial preload of every ball in the declared physics at the end of the calibration, m,
    /// when the loop changed it (absent: the declared model's own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_preload_m: Option<f64>,
    /// Where it came from.
    pub provenance: Provenance,
    /// RMS of the calibration recording's held-out part through the path's prediction-error
    /// filter `A(z)` (what a diagnosis against this machine compares a recording's residual
    /// with); `null` when the model holds no path or was written before this field existed.
    #[serde(default)]
    pub path_residual_rms: Option<f64>,
    /// Kurtosis (not excess) of that residual.
    #[serde(default)]
    pub path_residual_kurtosis: Option<f64>,
    /// RMS of the calibration recording's held-out part through the whole model's one-step
    /// predictor ([`MachineModel::predictor_path`]: path, floor and lines), what a diagnosis
    /// against this machine compares with when it whitens with that predictor; absent in models
    /// written before it (a diagnosis then whitens with the path alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predictor_residual_rms: Option<f64>,
    /// Kurtosis (not excess) of that residual.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predictor_residual_kurtosis: Option<f64>,
}

impl MachineModel {
    pub(crate) fn from_state(
        ctx: &Ctx<'_>,
        st: &State,
        effects: &[EffectEntry],
        before: f64,
        after: f64,
    ) -> Self {
        let fr = ctx.op.shaft_hz() * st.shaft_ratio();
        let mut lines: Vec<MachineLine> = Vec::new();
        // a line the loop names a shaft harmonic (integer order up to `max_harmonic_order`,
        // half order up to 5½, within the harmonic tolerance) moves with the speed; any other
        // line — CWRU's ~4.2 kHz interference comb among them — is a tone fixed in Hz
        for l in &st.lines {
            lines.push(match crate::runner::classify_line(*l, fr, ctx.cfg.get()) {
                crate::Effect::ShaftHarmonic { order, .. } => MachineLine::ShaftHarmonic {
                    order,
                    amplitude: l.amplitude(),
                    frequency_hz: Some(l.frequency_hz),
                },
                _ => MachineLine::Tone {
                    frequency_hz: l.frequency_hz,
                    amplitude: l.amplitude(),
                },
            });
        }
        let mut housing_mode = None;
        let mut shaft_forces = Vec::new();
        for e in effects {
            let p = &e.parameters;
            match e.kind {
                crate::EffectKind::Resonance if p.get("housing_mode") == Some(&1.0) => {
                    housing_mode = e
                        .frequency_hz
                        .map(|f| [f, p.get("damping_ratio").copied().unwrap_or(0.05)]);
                }
                crate::EffectKind::ShaftHarmonic => {
                    if let (Some(o), Some(a), Some(ph)) = (
                        p.get("order"),
                        p.get("force_amplitude_n"),
                        p.get("force_phase_rad"),
                    ) {
                        shaft_forces.push([*o, *a, *ph]);
                    }
                }
                _ => {}
            }
        }
        let b = &ctx.op.bearing;
        let path = st.path.as_ref().map(|p| p.path.clone());
        let (path_residual_rms, path_residual_kurtosis) = path
            .as_ref()
            .and_then(|p| path_residual_stats(p, &ctx.y[ctx.n_fit..]))
            .unzip();
        let mut m = Self {
            format: FORMAT.to_string(),
            version: VERSION,
            fs_hz: ctx.fs,
            units: "unknown".to_string(),
            bearing: b.name.to_string(),
            bearing_orders: [
                b.orders.bpfo,
                b.orders.bpfi,
                b.orders.ftf,
                b.orders.ball_defect,
            ],
            model: ctx.model.name().to_string(),
            declared_rpm: ctx.op.rpm,
            declared_fault: ctx.op.fault.name().to_string(),
            speed_ratio: st.shaft_ratio(),
            defect_rate_ratio: st.defect_rate,
            physics_gain: st.log_gain.exp(),
            housing_mode,
            shaft_forces,
            path,
            path_level: if st.path.is_some() {
                st.log_bg.exp()
            } else {
                0.0
            },
            structural_modes: st
                .path
                .as_ref()
                .map(|p| p.modes.clone())
                .unwrap_or_default(),
            physics_path: st.phys_path.as_ref().map(|p| p.path.clone()),
            noise_floor_psd: st.log_floor.exp(),
            lines,
            channel_modes: st.modes.clone(),
            modulations: st.mods.clone(),
            slip_fraction: ctx
                .model_of(st)
                .slip_fraction()
                .filter(|s| Some(*s) != ctx.model.slip_fraction()),
            contact_preload_m: ctx
                .model_of(st)
                .contact_preload_m()
                .filter(|p| Some(*p) != ctx.model.contact_preload_m()),
            provenance: Provenance {
                recording: String::new(),
                error_before: before,
                error_after: after,
                error_metric: crate::report::PRIMARY_METRIC.to_string(),
                fit_samples: [0, ctx.n_fit],
            },
            path_residual_rms,
            path_residual_kurtosis,
            predictor_residual_rms: None,
            predictor_residual_kurtosis: None,
        };
        m.set_predictor_stats(&ctx.y[ctx.n_fit..]);
        m
    }

    /// Measure [`MachineModel::predictor_residual_rms`] and its kurtosis on `held_out` (left
    /// `None` without a path or when nothing finite is left).
    fn set_predictor_stats(&mut self, held_out: &[f64]) {
        let stats = self
            .predictor_path()
            .ok()
            .and_then(|p| path_residual_stats(&p, held_out));
        (
            self.predictor_residual_rms,
            self.predictor_residual_kurtosis,
        ) = stats.unzip();
    }

    /// Shaft rate of the calibration recording, Hz (declared speed × the calibrated ratio).
    pub fn calibration_shaft_hz(&self) -> f64 {
        self.declared_rpm / 60.0 * self.speed_ratio
    }

    /// The frequencies of the model's lines at shaft rate `fr_hz` (true, not declared, speed):
    /// a shaft line at its calibrated frequency scaled by `fr_hz` / the calibration's shaft
    /// rate (`order` × `fr_hz` for a file that does not state it), a tone where it is.
    pub fn line_frequencies(&self, fr_hz: f64) -> Vec<f64> {
        let fr_cal = self.calibration_shaft_hz();
        self.lines
            .iter()
            .map(|l| l.frequency_at(fr_hz, fr_cal))
            .collect()
    }

    /// The calibrated structural path as an observer model: the AR path `y = e / A(z)` in shift
    /// form ([`observers::LinearModel::from_ar`]), the model the physics observers (SMO,
    /// HOSTSMO, FLO, VSO, PFLO) run on once a machine has been calibrated
    /// ([`observers::ModelConfig::CalibratedPath`]).
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the machine model holds no structural path (the loop found
    /// no broadband structure to add), [`CloseLoopError::Observer`] for an invalid path.
    pub fn observer_model(&self) -> Result<observers::LinearModel, CloseLoopError> {
        let path = self.path.as_ref().ok_or_else(|| CloseLoopError::Model {
            reason: "the machine model holds no structural path to run an observer on".into(),
        })?;
        observers::LinearModel::from_ar(&path.ar).map_err(|e| CloseLoopError::Observer {
            reason: e.to_string(),
        })
    }

    /// The whole calibrated machine as a one-step predictor: the AR model (the structural
    /// path's order plus two per line, Levinson; its excitation variance the innovation
    /// variance) of the stationary process the machine model describes at its calibration
    /// speed — the structural path at its calibrated level, the white floor and every line
    /// (shaft harmonics and tones, each a sinusoid of its calibrated amplitude, whose
    /// autocorrelation `A²/2 · cos(2π f m / fs)` is added exactly). A linear predictor needs no
    /// line's phase: a sinusoid is predicted from its own past. The path alone is
    /// [`MachineModel::path`].
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the model holds no structural path or the recursion fails.
    pub fn predictor_path(&self) -> Result<StructuralPath, CloseLoopError> {
        let path = self.path.as_ref().ok_or_else(|| CloseLoopError::Model {
            reason: "the machine model holds no structural path to run an observer on".into(),
        })?;
        let fs = self.fs_hz;
        let n_bins = PREDICTOR_GRID_BINS;
        let df = fs / 2.0 / (n_bins - 1) as f64;
        // the channel modes shape the background as they shape the physics
        let mut bg = path.psd(n_bins, df);
        Mode::shape_psd(&self.channel_modes, &mut bg, df, fs);
        let psd: Vec<f64> = bg
            .iter()
            .map(|s| s * self.path_level + self.noise_floor_psd)
            .collect();
        // each line is one more pole pair: the path's order plus two per line
        let order = path.order() + 2 * self.lines.len();
        let mut r = crate::path::autocorrelation(&psd, df, fs, order);
        let fr = self.calibration_shaft_hz();
        for l in &self.lines {
            let (f, a) = (l.frequency_at(fr, fr), l.amplitude());
            for (m, v) in r.iter_mut().enumerate() {
                *v += 0.5 * a * a * (2.0 * std::f64::consts::PI * f * m as f64 / fs).cos();
            }
        }
        let (ar, e) = crate::path::levinson(&r)?;
        Ok(StructuralPath {
            fs_hz: fs,
            ar,
            excitation_variance: e,
        })
    }

    /// The whole calibrated machine as an observer model: [`MachineModel::predictor_path`] in
    /// shift form, what the physics observers (SMO, HOSTSMO, FLO, VSO, PFLO) run on
    /// ([`observers::ModelConfig::CalibratedPath`]). [`MachineModel::observer_model`] is the
    /// path alone.
    ///
    /// # Errors
    /// As [`MachineModel::predictor_path`]; [`CloseLoopError::Observer`] for an invalid model.
    pub fn predictor_model(&self) -> Result<observers::LinearModel, CloseLoopError> {
        observers::LinearModel::from_ar(&self.predictor_path()?.ar).map_err(|e| {
            CloseLoopError::Observer {
                reason: e.to_string(),
            }
        })
    }

    /// The model as pretty JSON.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] if a value cannot be written (non-finite number).
    pub fn to_json(&self) -> Result<String, CloseLoopError> {
        serde_json::to_string_pretty(self).map_err(|e| CloseLoopError::MachineModelFormat {
            reason: e.to_string(),
        })
    }

    /// Parse and validate a machine model (format, version, finite positive rates and levels).
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] or [`CloseLoopError::MachineModelMismatch`].
    pub fn from_json(text: &str) -> Result<Self, CloseLoopError> {
        let m: Self = parse_versioned(text, FORMAT, VERSION, |m: &Self| (&m.format, m.version))?;
        let positive = [
            ("fs_hz", m.fs_hz),
            ("speed_ratio", m.speed_ratio),
            ("defect_rate_ratio", m.defect_rate_ratio),
            ("declared_rpm", m.declared_rpm),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(CloseLoopError::MachineModelFormat {
                    reason: format!("`{name}` must be finite and > 0, got {v}"),
                });
            }
        }
        for (name, v) in [
            ("physics_gain", m.physics_gain),
            ("path_level", m.path_level),
            ("noise_floor_psd", m.noise_floor_psd),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(CloseLoopError::MachineModelFormat {
                    reason: format!("`{name}` must be finite and >= 0, got {v}"),
                });
            }
        }
        if let Some(p) = &m.path
            && ((p.fs_hz - m.fs_hz).abs() > 1e-9 * m.fs_hz
                || !p.ar.iter().all(|a| a.is_finite())
                || !(p.excitation_variance.is_finite() && p.excitation_variance > 0.0))
        {
            return Err(CloseLoopError::MachineModelFormat {
                reason: "`path` is not a finite AR model at the model's sampling rate".into(),
            });
        }
        Ok(m)
    }

    /// Check that the model fits a recording at `fs` Hz of bearing `bearing`.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelMismatch`] naming what differs.
    pub fn check_compatible(&self, fs: f64, bearing: &str) -> Result<(), CloseLoopError> {
        if (self.fs_hz - fs).abs() > 1e-6 * fs.abs().max(1.0) {
            return Err(CloseLoopError::MachineModelMismatch {
                what: "sampling rate",
                expected: format!("{fs} Hz"),
                found: format!("{} Hz", self.fs_hz),
            });
        }
        if !self.bearing.eq_ignore_ascii_case(bearing) {
            return Err(CloseLoopError::MachineModelMismatch {
                what: "bearing",
                expected: bearing.to_string(),
                found: self.bearing.clone(),
            });
        }
        Ok(())
    }

    /// Check the units the model was calibrated in against the recording's (`"unknown"` on
    /// either side is accepted).
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelMismatch`] when both are known and differ.
    pub fn check_units(&self, units: &str) -> Result<(), CloseLoopError> {
        if self.units != "unknown" && units != "unknown" && self.units != units {
            return Err(CloseLoopError::MachineModelMismatch {
                what: "units",
                expected: units.to_string(),
                found: self.units.clone(),
            });
        }
        Ok(())
    }

    /// The effects a machine model holds, as effects (for reports).
    pub fn effect_count(&self) -> usize {
        self.lines.len()
            + self.channel_modes.len()
            + self.modulations.len()
            + usize::from(self.path.is_some())
            + self.shaft_forces.len()
            + usize::from(self.housing_mode.is_some())
    }
}

/// RMS and kurtosis of `y` through the path's prediction-error filter `A(z)` (after its start-up
/// of `order` samples); `None` when nothing finite is left.
fn path_residual_stats(p: &StructuralPath, y: &[f64]) -> Option<(f64, f64)> {
    let e = p.prediction_error(y);
    let e = e.get(p.order()..)?;
    let n = e.len() as f64;
    let m2 = e.iter().map(|v| v * v).sum::<f64>() / n;
    let m4 = e.iter().map(|v| v.powi(4)).sum::<f64>() / n;
    (n > 0.0 && m2 > 0.0 && m2.is_finite() && m4.is_finite()).then(|| (m2.sqrt(), m4 / (m2 * m2)))
}

impl MachineModel {
    /// When the loop added no structural path — the declared model already explained the
    /// calibration recording — identify one from the recording directly
    /// ([`crate::path::identify_from_signal`] on `fit`, AR order up to `max_order`, residual
    /// statistics on `held_out`), so the model can still serve as a healthy baseline (a diagnosis
    /// whitens with its path). Returns whether a path was added; a model that holds one is left
    /// as it is.
    ///
    /// # Errors
    /// The identification's errors, and [`CloseLoopError::Model`] when the held-out segment
    /// leaves no finite residual statistics.
    pub fn ensure_path(
        &mut self,
        fit: &[f64],
        held_out: &[f64],
        max_order: usize,
    ) -> Result<bool, CloseLoopError> {
        if self.path.is_some() {
            return Ok(false);
        }
        let p = crate::path::identify_from_signal(fit, self.fs_hz, max_order)?;
        let (rms, kurtosis) =
            path_residual_stats(&p, held_out).ok_or_else(|| CloseLoopError::Model {
                reason: "the held-out segment leaves no finite path residual".into(),
            })?;
        self.structural_modes = p.modes();
        self.path_level = 1.0;
        self.path_residual_rms = Some(rms);
        self.path_residual_kurtosis = Some(kurtosis);
        self.path = Some(p);
        self.set_predictor_stats(held_out);
        Ok(true)
    }
}

/// Samples the structural path's filter runs before a synthesized recording starts (its
/// transient dies out).
const SYNTH_WARMUP: usize = 4096;

impl MachineModel {
    /// A recording of this machine model, `n` samples at its rate, shaft at `rpm` declared (the
    /// calibrated speed ratio applied), every random draw from `seed`: the structural path
    /// driven by white excitation at its calibrated level, the white floor, the lines at their
    /// calibrated amplitudes with seeded random phases, and the declared physics `model`
    /// (with the calibration's slip, housing mode and shaft forces and channel modes, scaled by
    /// the physics gain), the modulations acting on physics and background together — what the
    /// model says a recording of this machine is. A clean recording: the loop started from this model adds nothing to it (test
    /// `idempotence::simulated_recording_of_the_machine_model_48k`).
    ///
    /// # Errors
    /// The physics simulation's errors; [`CloseLoopError::Model`] when the physics is seen
    /// through a separately identified path (`physics_path`: its shaping is spectral, not a
    /// filter) or `rpm` is not finite and positive.
    pub fn simulate(
        &self,
        model: &dyn crate::DeclaredModel,
        rpm: f64,
        n: usize,
        seed: u64,
    ) -> Result<Vec<f64>, CloseLoopError> {
        use std::f64::consts::PI;
        if !(rpm.is_finite() && rpm > 0.0) {
            return Err(CloseLoopError::InvalidRpm { rpm });
        }
        let fs = self.fs_hz;
        let mut y = vec![0.0; n];
        if self.physics_gain > 0.0 {
            if self.physics_path.is_some() {
                return Err(CloseLoopError::Model {
                    reason: "a machine model whose physics is seen through its own path cannot \
                             be synthesised in the time domain"
                        .into(),
                });
            }
            let mut m: Option<Box<dyn crate::DeclaredModel>> = None;
            if let Some(frac) = self.slip_fraction {
                m = m.as_deref().unwrap_or(model).with_slip_fraction(frac).or(m);
            }
            if let Some(p) = self.contact_preload_m {
                m = m.as_deref().unwrap_or(model).with_contact_preload(p).or(m);
            }
            if let Some([f, z]) = self.housing_mode {
                m = m.as_deref().unwrap_or(model).with_housing_mode(f, z).or(m);
            }
            for &[order, amp, phase] in &self.shaft_forces {
                if order >= 1.0 && order.fract() == 0.0 {
                    m = m
                        .as_deref()
                        .unwrap_or(model)
                        .with_shaft_force(order as u32, amp, phase)
                        .or(m);
                }
            }
            let rates = crate::BearingSpec::designated(self.bearing.parse().map_err(|_| {
                CloseLoopError::UnknownBearing {
                    name: self.bearing.clone(),
                }
            })?);
            let fault = crate::parse_fault(&self.declared_fault)?;
            let op = crate::OperatingPoint::new(rpm, rates, fault)?
                .with_speed_ratio(self.speed_ratio * self.defect_rate_ratio);
            let mut x = m.as_deref().unwrap_or(model).simulate(&op, n, fs)?;
            for mode in &self.channel_modes {
                x = mode.apply(&x, fs);
            }
            let g = self.physics_gain.sqrt();
            for (a, b) in y.iter_mut().zip(&x) {
                *a += g * b;
            }
        }
        let mut g = crate::scenario::Gaussian::new(seed);
        if let Some(p) = &self.path {
            let sd = (p.excitation_variance * self.path_level).max(0.0).sqrt();
            let e: Vec<f64> = (0..n + SYNTH_WARMUP).map(|_| sd * g.sample()).collect();
            let mut f = p.filter(&e);
            // through the channel modes, as the physics
            for mode in &self.channel_modes {
                f = mode.apply(&f, fs);
            }
            for (a, b) in y.iter_mut().zip(&f[SYNTH_WARMUP..]) {
                *a += b;
            }
        }
        // the modulations act on the structural vibration (physics and background), not on the
        // white floor nor on the lines
        for md in &self.modulations {
            y = md.apply(&y, 0, fs);
        }
        let floor_sd = (self.noise_floor_psd * fs / 2.0).max(0.0).sqrt();
        y.iter_mut().for_each(|v| *v += floor_sd * g.sample());
        let fr = rpm / 60.0 * self.speed_ratio;
        for (l, f) in self.lines.iter().zip(self.line_frequencies(fr)) {
            let ph = 2.0 * PI * g.uniform();
            if f > 0.0 && f < 0.5 * fs {
                let w = 2.0 * PI * f / fs;
                let a = l.amplitude();
                for (k, v) in y.iter_mut().enumerate() {
                    *v += a * (w * k as f64 + ph).cos();
                }
            }
        }
        Ok(y)
    }
}

/// serde default of [`MachineModel::defect_rate_ratio`].
fn unit_ratio() -> f64 {
    1.0
}

/// A ratio of exactly 1 is not written ([`MachineModel::defect_rate_ratio`]).
fn is_unit_ratio(r: &f64) -> bool {
    *r == 1.0
}
