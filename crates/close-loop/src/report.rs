//! The ledger: what the loop found, in order, with the error before and after each effect.
//! Its JSON schema is documented in the crate README.

use crate::effect::{EffectKind, Placement};
use bearing_data::SampleUnit;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Name of the primary metric in the JSON.
pub const PRIMARY_METRIC: &str = "floor_regularised_lsd_db";
/// Name of the secondary metric in the JSON.
pub const SECONDARY_METRIC: &str = "residual_rms_ratio";

/// One accepted effect.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffectEntry {
    /// Effect kind.
    pub kind: EffectKind,
    /// Tone, harmonic, resonance or modulation frequency, Hz; `null` for a speed offset.
    pub frequency_hz: Option<f64>,
    /// Fitted parameters by name (`ratio` for a speed offset, `order` for a shaft harmonic, …).
    pub parameters: BTreeMap<String, f64>,
    /// Physics or measurement channel.
    pub placement: Placement,
    /// Human-readable summary.
    pub description: String,
    /// Held-out primary error before this effect.
    pub error_before: f64,
    /// Held-out primary error after this effect.
    pub error_after: f64,
    /// Held-out secondary error before.
    pub secondary_before: f64,
    /// Held-out secondary error after.
    pub secondary_after: f64,
    /// Fitting-segment primary error before.
    pub fit_error_before: f64,
    /// Fitting-segment primary error after.
    pub fit_error_after: f64,
    /// Held-out RMS of the observer residual before this effect (`null` if the observer failed).
    pub residual_rms_before: Option<f64>,
    /// Held-out RMS of the observer residual after this effect.
    pub residual_rms_after: Option<f64>,
    /// For a setting of the model (speed ratio, slip, structural path) taken again: the 1-based
    /// step whose value this one replaces (`null` otherwise).
    #[serde(default)]
    pub replaces_step: Option<usize>,
    /// Which held-out test kept the effect (`null` in reports written before it was recorded).
    #[serde(default)]
    pub accepted_on: Option<AcceptedOn>,
    /// A tone within [`crate::KINEMATIC_LINE_TOLERANCE`] of harmonic 1–3 of one of the bearing's
    /// kinematic rates at the measured shaft speed: that rate (`"BPFI"`, `"3xBPFO"`, `"FTF"`,
    /// `"2xball-defect"`), what the line physically sits at (absent otherwise). The CWRU drive
    /// end's ~160 Hz line, on the healthy record too, is BPFI's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kinematic_rate: Option<String>,
}

/// Relative distance within which a tone is said to sit at a kinematic rate of the bearing
/// ([`EffectEntry::kinematic_rate`]): 0.5 %, the frequency accuracy the loop is held to.
pub const KINEMATIC_LINE_TOLERANCE: f64 = 0.005;

/// The held-out test an effect passed (`docs/equations/close-loop.md`, "Acceptance").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AcceptedOn {
    /// It lowered the held-out spectral error by the margin and the minimum improvement.
    SpectralError,
    /// A coherent line that removed at least `min_line_power` of the held-out signal's power from
    /// the time-domain residual without raising the spectral error.
    CoherentLine,
    /// A speed step the held-out envelope confirms by itself (its own estimate within
    /// two steps of its search grid, strong lines), without raising the spectral error.
    HeldOutEnvelope,
}

/// A candidate that was evaluated in the last round and not kept.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RejectedCandidate {
    /// Effect kind.
    pub kind: EffectKind,
    /// Its frequency, if it has one.
    pub frequency_hz: Option<f64>,
    /// Fitting-segment error with it.
    pub fit_error: f64,
    /// Held-out error with it (`null` if it did not even lower the fitting error).
    pub held_out_error: Option<f64>,
}

/// What the model was told.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Declared {
    /// Model name.
    pub model: String,
    /// Declared speed, rpm.
    pub rpm: f64,
    /// Bearing designation, or the normalised spec (what machine models compare).
    pub bearing: String,
    /// The bearing spec as the user gave it, case kept (`BearingSpec::echo`): what the Markdown
    /// echoes (empty in a ledger written before it was kept).
    #[serde(default)]
    pub bearing_spec: String,
    /// Declared fault ("none", "outer", "inner+ball", …).
    pub fault: String,
    /// Sampling frequency, Hz.
    pub fs: f64,
}

/// How the recording was split and scored (the ledger's `protocol`: fitting and held-out
/// samples, the spectral estimator, the acceptance margin). Not an evaluation protocol
/// (`classify::Protocol`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeldOutSplit {
    /// Fitting samples `[start, end)`.
    pub fit_samples: [usize; 2],
    /// Held-out samples `[start, end)`.
    pub held_out_samples: [usize; 2],
    /// Welch segment length.
    pub nperseg: usize,
    /// Welch bin width, Hz.
    pub df_hz: f64,
    /// Scored band, Hz.
    pub band_hz: [f64; 2],
    /// Stop-rule margin (relative held-out improvement an effect must bring).
    pub margin: f64,
    /// Floor of the regularised LSD, dB re the measurement's mean PSD over the band.
    pub floor_db: f64,
    /// The same floor in units²/Hz.
    pub floor_psd: f64,
    /// The error a correct model would show from estimation variance alone, dB.
    pub estimation_lsd_db: f64,
}

/// The full report written as JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Ledger {
    /// "log_spectral_distance_db".
    pub error_metric: String,
    /// Held-out error of the declared model.
    pub error_before: f64,
    /// Held-out error after all effects.
    pub error_after: f64,
    /// "residual_rms_ratio".
    pub secondary_metric: String,
    /// Secondary error of the declared model.
    pub secondary_before: f64,
    /// Secondary error after all effects.
    pub secondary_after: f64,
    /// The observer behind `residual_rms_*` (see `close_loop::observe`).
    pub observer: String,
    /// Held-out RMS of the observer residual of the declared model (`null` if it failed).
    pub residual_rms_before: Option<f64>,
    /// Held-out RMS of the observer residual after all effects.
    pub residual_rms_after: Option<f64>,
    /// RMS of the measurement on the held-out segment (the scale of `residual_rms_*`).
    pub held_out_signal_rms: f64,
    /// Unit of the recording's samples as the input layer knows it: every amplitude of the
    /// ledger (`held_out_signal_rms`, `residual_rms_*`, effect amplitudes and gains,
    /// `structural_modes`) is in it, PSDs (`protocol.floor_psd`) in its square per Hz. The loop
    /// itself does not know it (`unknown`); the command sets the recording's.
    #[serde(default)]
    pub unit: SampleUnit,
    /// Accepted effects, in the order they were added.
    pub effects: Vec<EffectEntry>,
    /// Candidates of the last round that did not pass the stop rule.
    pub rejected: Vec<RejectedCandidate>,
    /// Why the loop stopped.
    pub stop_reason: String,
    /// What the model was told.
    pub declared: Declared,
    /// Split and scoring.
    pub protocol: HeldOutSplit,
    /// Modes of the structural path in the final model (empty without one).
    #[serde(default)]
    pub structural_modes: Vec<crate::path::PathMode>,
    /// A calibration's verification passes ([`crate::machine::calibrate_with`]): the loop run
    /// again on the same recording from the machine model as saved. Absent for a plain run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub verification: Vec<VerificationPass>,
}

/// One verification pass of a calibration: the loop on the calibration recording started from
/// the machine model as it would be saved (JSON round trip).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerificationPass {
    /// 1-based pass number.
    pub pass: usize,
    /// Held-out error of the saved model on the calibration recording (the pass's start), dB.
    pub error_start: f64,
    /// Held-out error at the pass's end, dB.
    pub error_end: f64,
    /// Effects the pass added (0: the saved model is the calibration's fixed point).
    pub effects_added: usize,
}

/// Held-out spectra for plotting (not part of the JSON).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Spectra {
    /// Bin frequencies, Hz.
    pub frequency_hz: Vec<f64>,
    /// Measured held-out PSD.
    pub measured: Vec<f64>,
    /// Model PSD before any effect.
    pub model_before: Vec<f64>,
    /// Model PSD after all effects.
    pub model_after: Vec<f64>,
}

impl Ledger {
    /// The ledger as Markdown.
    pub fn to_markdown(&self, title: &str) -> String {
        let mut s = String::new();
        s.push_str(&format!("# Closed loop: {title}\n\n"));
        let bearing = if self.declared.bearing_spec.is_empty() {
            &self.declared.bearing
        } else {
            &self.declared.bearing_spec
        };
        s.push_str(&format!(
            "Declared model `{}` at {:.1} rpm, bearing `{bearing}`, fault `{}`, fs = {} Hz.\n\n",
            self.declared.model, self.declared.rpm, self.declared.fault, self.declared.fs
        ));
        let u = self.unit.label();
        s.push_str(&format!(
            "Recording unit: {}. Amplitudes (RMS, line amplitudes, modal gains) are in {u}, PSDs in ({u})²/Hz.\n\n",
            self.unit
        ));
        s.push_str(&format!(
            "Fitted on samples {}..{}, scored on held-out samples {}..{}; Welch {} samples ({:.3} Hz bins), band {:.1}–{:.1} Hz; stop margin {:.1} %.\n\n",
            self.protocol.fit_samples[0],
            self.protocol.fit_samples[1],
            self.protocol.held_out_samples[0],
            self.protocol.held_out_samples[1],
            self.protocol.nperseg,
            self.protocol.df_hz,
            self.protocol.band_hz[0],
            self.protocol.band_hz[1],
            100.0 * self.protocol.margin
        ));
        s.push_str(&format!(
            "Held-out {}: {:.3} dB → {:.3} dB; {}: {:.4} → {:.4}.\n\n",
            self.error_metric,
            self.error_before,
            self.error_after,
            self.secondary_metric,
            self.secondary_before,
            self.secondary_after
        ));
        let opt = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.4e}"));
        let opt_u = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.4e} {u}"));
        s.push_str(&format!(
            "Held-out observer residual RMS ({}): {} → {} (held-out signal RMS {:.4e} {u}).\n\n",
            self.observer,
            opt_u(self.residual_rms_before),
            opt_u(self.residual_rms_after),
            self.held_out_signal_rms
        ));
        s.push_str(&format!("| # | kind | frequency (Hz) | where | effect (amplitudes in {u}) | LSD before (dB) | LSD after (dB) | observer RMS before ({u}) | observer RMS after ({u}) | RMS ratio before | RMS ratio after |\n"));
        s.push_str("|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (i, e) in self.effects.iter().enumerate() {
            s.push_str(&format!(
                "| {} | {} | {} | {:?} | {} | {:.3} | {:.3} | {} | {} | {:.4} | {:.4} |\n",
                i + 1,
                e.kind.as_str(),
                e.frequency_hz
                    .map_or("–".to_string(), |f| format!("{f:.3}")),
                e.placement,
                e.description,
                e.error_before,
                e.error_after,
                opt(e.residual_rms_before),
                opt(e.residual_rms_after),
                e.secondary_before,
                e.secondary_after
            ));
        }
        if self.effects.is_empty() {
            s.push_str("| – | (no effect found) | | | | | | | | | |\n");
        }
        s.push_str(&format!("\nStop: {}\n", self.stop_reason));
        for v in &self.verification {
            s.push_str(&format!(
                "\nVerification pass {} (the loop again from the machine model as saved): {:.3} dB → {:.3} dB, {} effect(s) added{}\n",
                v.pass,
                v.error_start,
                v.error_end,
                v.effects_added,
                if v.effects_added == 0 {
                    " — the saved model is the calibration's end state"
                } else {
                    " (listed above, after the first loop's)"
                }
            ));
        }
        if !self.rejected.is_empty() {
            s.push_str("\nCandidates of the last round that were not kept:\n\n");
            for r in &self.rejected {
                s.push_str(&format!(
                    "- {} at {}: fitting LSD {:.3} dB, held-out LSD {}\n",
                    r.kind.as_str(),
                    r.frequency_hz
                        .map_or("–".to_string(), |f| format!("{f:.3} Hz")),
                    r.fit_error,
                    r.held_out_error
                        .map_or("not scored".to_string(), |h| format!("{h:.3} dB"))
                ));
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ledger(unit: SampleUnit) -> Ledger {
        let mut parameters = BTreeMap::new();
        parameters.insert("order".to_string(), 2.0);
        parameters.insert("amplitude".to_string(), 0.012);
        Ledger {
            error_metric: PRIMARY_METRIC.into(),
            error_before: 3.0,
            error_after: 2.0,
            secondary_metric: SECONDARY_METRIC.into(),
            secondary_before: 1.0,
            secondary_after: 0.9,
            observer: "ALPIO".into(),
            residual_rms_before: Some(0.25),
            residual_rms_after: Some(0.2),
            held_out_signal_rms: 0.5,
            unit,
            effects: vec![EffectEntry {
                kind: EffectKind::ShaftHarmonic,
                frequency_hz: Some(59.9),
                parameters,
                placement: Placement::Measurement,
                description: "shaft harmonic 2x at 59.900 Hz, amplitude 1.2000e-2".into(),
                error_before: 3.0,
                error_after: 2.0,
                secondary_before: 1.0,
                secondary_after: 0.9,
                fit_error_before: 3.0,
                fit_error_after: 2.0,
                residual_rms_before: Some(0.25),
                residual_rms_after: Some(0.2),
                replaces_step: None,
                accepted_on: Some(AcceptedOn::SpectralError),
                kinematic_rate: None,
            }],
            rejected: vec![],
            verification: vec![],
            stop_reason: "done".into(),
            declared: Declared {
                model: "physics".into(),
                rpm: 1797.0,
                bearing: "multiples bpfo=3.5848 bpfi=5.4152 ftf=0.39828 bsf=4.7135".into(),
                bearing_spec: "BPFO=3.5848,BPFI=5.4152,FTF=0.39828,BSF=4.7135".into(),
                fault: "outer".into(),
                fs: 12_000.0,
            },
            protocol: HeldOutSplit {
                fit_samples: [0, 100],
                held_out_samples: [100, 200],
                nperseg: 64,
                df_hz: 187.5,
                band_hz: [0.0, 6000.0],
                margin: 0.02,
                floor_db: -60.0,
                floor_psd: 1e-9,
                estimation_lsd_db: 0.5,
            },
            structural_modes: vec![],
        }
    }

    #[test]
    fn the_report_states_the_unit_of_its_amplitudes() {
        let l = ledger(SampleUnit::cwru());
        let md = l.to_markdown("130.mat");
        assert!(md.contains(bearing_data::CWRU_STATEMENT), "{md}");
        assert!(
            md.contains("held-out signal RMS 5.0000e-1 file units"),
            "{md}"
        );
        assert!(
            md.contains("2.5000e-1 file units → 2.0000e-1 file units"),
            "{md}"
        );
        assert!(md.contains("observer RMS before (file units)"), "{md}");
        let md = ledger(SampleUnit::from_code("m/s^2").unwrap()).to_markdown("sim");
        assert!(md.contains("Recording unit: m/s²."), "{md}");
        // the unit is an added key: the keys users script against are all still there
        let v = serde_json::to_value(&l).unwrap();
        assert_eq!(v["unit"]["code"], "g");
        assert_eq!(v["unit"]["statement"], bearing_data::CWRU_STATEMENT);
        for key in [
            "error_before",
            "error_after",
            "held_out_signal_rms",
            "effects",
        ] {
            assert!(v.get(key).is_some(), "{key}");
        }
        let e = &v["effects"][0];
        assert_eq!(e["kind"], "shaft_harmonic");
        assert_eq!(e["parameters"]["order"], 2.0);
        for key in ["frequency_hz", "placement", "error_before", "error_after"] {
            assert!(e.get(key).is_some(), "{key}");
        }
        // a ledger written before the unit and the typed spec were kept still reads
        let mut old = v.clone();
        let obj = old.as_object_mut().unwrap();
        obj.remove("unit");
        obj["declared"]
            .as_object_mut()
            .unwrap()
            .remove("bearing_spec");
        let back: Ledger = serde_json::from_value(old).unwrap();
        assert!(back.unit.is_unknown());
        assert!(
            back.to_markdown("old")
                .contains("bearing `multiples bpfo=3.5848")
        );
    }

    #[test]
    fn the_bearing_is_echoed_as_typed() {
        let l = ledger(SampleUnit::unknown());
        let v = serde_json::to_value(&l).unwrap();
        assert_eq!(
            v["declared"]["bearing"],
            "multiples bpfo=3.5848 bpfi=5.4152 ftf=0.39828 bsf=4.7135"
        );
        let md = l.to_markdown("x");
        assert!(
            md.contains("bearing `BPFO=3.5848,BPFI=5.4152,FTF=0.39828,BSF=4.7135`"),
            "{md}"
        );
        assert!(!md.contains("bpfo="), "{md}");
    }
}
