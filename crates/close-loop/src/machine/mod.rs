//! The calibrated machine model: the declared 5-DOF model plus everything the loop added on a
//! recording — speed ratio, the structural path from bearing to sensor (its modes), the excitation
//! and noise floor, shaft harmonics and tones, channel modes and modulations — saved as versioned
//! JSON, reloaded, validated against the recording it is used on, and taken by
//! [`crate::close_loop_from`] as its declared model.
//!
//! This file holds the model and its lines ([`MachineModel`], [`MachineLine`], [`Provenance`]) and
//! builds it from the loop's end state. `json` holds the file format (format, version,
//! validation, the checks against a recording), `predictor` the structural path and the
//! predictors built from the model, `synthesis` a recording of the model, `calibration` the
//! calibration entry points ([`calibrate`], [`calibrate_with`]).

use crate::effect::{Mode, Modulation};
use crate::engine::{Ctx, State};
use crate::path::{PathMode, StructuralPath};
use crate::report::EffectEntry;
use predictor::path_residual_stats;
use serde::{Deserialize, Serialize};

mod calibration;
mod json;
mod predictor;
mod synthesis;

pub use calibration::{CALIBRATE_MAX_EFFECTS, MAX_VERIFICATION_PASSES, calibrate, calibrate_with};
pub use json::parse_versioned;
pub use json::{FORMAT, VERSION};

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
            lines.push(match crate::effect::classify_line(*l, fr, ctx.cfg.get()) {
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

/// serde default of [`MachineModel::defect_rate_ratio`].
fn unit_ratio() -> f64 {
    1.0
}

/// A ratio of exactly 1 is not written ([`MachineModel::defect_rate_ratio`]).
fn is_unit_ratio(r: &f64) -> bool {
    *r == 1.0
}
