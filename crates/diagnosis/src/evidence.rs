//! Hypothesis evidence in a squared envelope spectrum as the report states it: each fault's
//! template lines where the detector ([`crate::detect`]) found them, and the search windows of
//! each fault's lines. The spectrum and its line search are in `lines.rs`, re-exported here.

use serde::{Deserialize, Serialize};

use crate::detect::Significance;
use crate::detect::linetest::BandReading;
use crate::detect::template::{Sidebands, Template, Term, Window};
use crate::detect::view::BandView;
pub use crate::lines::{EnvelopeSpectrum, PassedOver, SearchedLine};
use crate::{Hypothesis, LINE_THRESHOLD_DB};

/// The former name of [`SearchedLine`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed to `SearchedLine`: one searched line of the squared envelope spectrum \
            (other crates' lines are `bearing_model::machine::OrderTone` and \
            `close_loop::effect::CoherentLine`)"
)]
pub type Line = SearchedLine;

/// The evidence for one fault hypothesis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HypothesisEvidence {
    /// Which fault.
    pub hypothesis: Hypothesis,
    /// Kinematic fault frequency (harmonic 1) at the speed its lines were read at (the speed
    /// used, times [`crate::Significance::speed_ratio`] where the templates searched it), Hz.
    pub fault_hz: f64,
    /// The band this hypothesis reads strongest in (each hypothesis has its own).
    pub band_hz: [f64; 2],
    /// Spectral kurtosis of that band.
    pub band_spectral_kurtosis: f64,
    /// Harmonics 1..=3 of the fault frequency.
    pub harmonics: Vec<SearchedLine>,
    /// Sidebands around harmonic 1 that tell the faults apart: ± fr (inner), ± FTF (ball).
    pub sidebands: Vec<SearchedLine>,
    /// The detector's statistic `Σ_h E_h + ½ Σ_s E_s`, dB (E = a line's evidence ≥ 0, its
    /// prominence less the baseline's where the healthy machine holds the line; h harmonics, s
    /// sidebands).
    pub score_db: f64,
    /// Harmonics present (evidence ≥ `LINE_THRESHOLD_DB`).
    pub harmonics_present: usize,
    /// Sidebands present.
    pub sidebands_present: usize,
    /// The fault is part of the verdict (significant, not explained by a stronger fault).
    pub detected: bool,
    /// The detector's reading: statistic, probability under "healthy", band, masks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub significance: Option<Significance>,
}

/// The evidence of one hypothesis as the detector read it: its template's lines where the line
/// test found them, in the band where it reads strongest (lines whose windows are wholly masked
/// are shown at their kinematic frequency, without evidence).
pub(crate) fn from_detection(
    t: &Template,
    sig: &Significance,
    reading: &BandReading,
    view: &BandView,
    env: &EnvelopeSpectrum,
    confirmed: bool,
) -> HypothesisEvidence {
    let name = match t.hypothesis {
        Hypothesis::Inner => "BPFI",
        Hypothesis::Outer => "BPFO",
        Hypothesis::Ball => "BSF",
    };
    let line = |w: &Window| -> SearchedLine {
        let label = match w.term {
            Term::Harmonic(k) => format!("{name}×{k}"),
            Term::Sideband(s) => match (t.sidebands, s < 0) {
                (Sidebands::Cage, true) => format!("{name}×1−FTF"),
                (Sidebands::Cage, false) => format!("{name}×1+FTF"),
                (_, true) => format!("{name}×1−fr"),
                (_, false) => format!("{name}×1+fr"),
            },
        };
        let read = reading.terms.iter().find(|r| r.window.term == w.term);
        let k = read.map_or_else(
            || ((w.expected_hz / view.df).round() as usize).min(view.d.len().saturating_sub(1)),
            |r| r.bin,
        );
        let found_hz = read.map_or(w.expected_hz, |_| k as f64 * view.df);
        let evidence_db = read.map_or(0.0, |r| r.value);
        let j = (found_hz / t.fr).round();
        SearchedLine {
            label,
            expected_hz: w.expected_hz,
            search_hz: [w.lo_hz, w.hi_hz],
            found_hz,
            prominence_db: view.raw.get(k).copied().unwrap_or(0.0),
            baseline_prominence_db: (!view.base.is_empty())
                .then(|| view.base.get(k).copied().unwrap_or(0.0)),
            evidence_db,
            present: evidence_db >= LINE_THRESHOLD_DB,
            explained_by: sig.explained_by,
            consistent: true,
            shaft_order: (read.is_none() && view.masks.shaft_orders && j >= 1.0)
                .then_some(j as u32),
            passed_over: None,
        }
    };
    let windows = t.windows(0.5 * view.df);
    let harmonics: Vec<SearchedLine> = windows
        .iter()
        .filter(|w| matches!(w.term, Term::Harmonic(_)))
        .map(line)
        .collect();
    let sidebands: Vec<SearchedLine> = windows
        .iter()
        .filter(|w| matches!(w.term, Term::Sideband(_)))
        .map(line)
        .collect();
    let count = |v: &[SearchedLine]| v.iter().filter(|l| l.present).count();
    HypothesisEvidence {
        hypothesis: t.hypothesis,
        fault_hz: t.fault_hz,
        band_hz: env.band_hz,
        band_spectral_kurtosis: env.spectral_kurtosis,
        harmonics_present: count(&harmonics),
        sidebands_present: count(&sidebands),
        harmonics,
        sidebands,
        score_db: sig.statistic_db,
        detected: confirmed,
        significance: Some(sig.clone()),
    }
}
