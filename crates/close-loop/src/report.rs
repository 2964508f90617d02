//! The ledger: what the loop found, in order, with the error before and after each effect.
//! Its JSON schema is documented in the crate README.

use crate::effect::{EffectKind, Placement};
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
    /// Bearing designation.
    pub bearing: String,
    /// Declared fault ("none", "outer", "inner+ball", …).
    pub fault: String,
    /// Sampling frequency, Hz.
    pub fs: f64,
}

/// How the recording was split and scored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Protocol {
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
    /// Accepted effects, in the order they were added.
    pub effects: Vec<EffectEntry>,
    /// Candidates of the last round that did not pass the stop rule.
    pub rejected: Vec<RejectedCandidate>,
    /// Why the loop stopped.
    pub stop_reason: String,
    /// What the model was told.
    pub declared: Declared,
    /// Split and scoring.
    pub protocol: Protocol,
    /// Modes of the structural path in the final model (empty without one).
    #[serde(default)]
    pub structural_modes: Vec<crate::path::PathMode>,
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

/// Ledger plus the spectra behind it.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The report.
    pub ledger: Ledger,
    /// Held-out spectra.
    pub spectra: Spectra,
    /// The augmented model as a reloadable machine model (declared model + everything added).
    pub machine: crate::machine::MachineModel,
}

impl Ledger {
    /// The ledger as Markdown.
    pub fn to_markdown(&self, title: &str) -> String {
        let mut s = String::new();
        s.push_str(&format!("# Closed loop: {title}\n\n"));
        s.push_str(&format!(
            "Declared model `{}` at {:.1} rpm, bearing {}, fault `{}`, fs = {} Hz.\n\n",
            self.declared.model,
            self.declared.rpm,
            self.declared.bearing,
            self.declared.fault,
            self.declared.fs
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
        s.push_str(&format!(
            "Held-out observer residual RMS ({}): {} → {} (held-out signal RMS {:.4e}).\n\n",
            self.observer,
            opt(self.residual_rms_before),
            opt(self.residual_rms_after),
            self.held_out_signal_rms
        ));
        s.push_str("| # | kind | frequency (Hz) | where | effect | LSD before (dB) | LSD after (dB) | observer RMS before | observer RMS after | RMS ratio before | RMS ratio after |\n");
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
