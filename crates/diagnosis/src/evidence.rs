//! Hypothesis evidence in a squared envelope spectrum: the search windows of each fault's lines,
//! hypothesis scores and the cross-explanation of lines between hypotheses. The spectrum and its
//! line search are in `lines.rs`, re-exported here.

use serde::{Deserialize, Serialize};

pub use crate::lines::{EnvelopeSpectrum, Line, PassedOver};
use crate::{HARMONICS, Hypothesis, SLIP_MAX, SPEED_OFFSET, SPEED_TOL};
use bearing_model::FaultOrders;

/// The evidence for one fault hypothesis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HypothesisEvidence {
    /// Which fault.
    pub hypothesis: Hypothesis,
    /// Kinematic fault frequency (harmonic 1) at the declared speed, Hz.
    pub fault_hz: f64,
    /// The band this hypothesis was examined in (the common band of the verdict).
    pub band_hz: [f64; 2],
    /// Spectral kurtosis of that band.
    pub band_spectral_kurtosis: f64,
    /// Harmonics 1..=3 of the fault frequency.
    pub harmonics: Vec<Line>,
    /// Sidebands around harmonic 1 that tell the faults apart: ± fr (inner), ± FTF (ball).
    pub sidebands: Vec<Line>,
    /// `Σ_h max(0, P_h) + ½ Σ_s max(0, P_s)`, dB (P = a line's evidence, its prominence less
    /// the baseline's where the healthy machine holds the line; h harmonics, s sidebands).
    pub score_db: f64,
    /// Harmonics that count (present, not explained by another hypothesis).
    pub harmonics_present: usize,
    /// Sidebands that count.
    pub sidebands_present: usize,
    /// The decision rule holds (see the crate documentation).
    pub detected: bool,
}

impl HypothesisEvidence {
    /// Recount lines and apply the decision rule: at least two harmonics present, or harmonic 1
    /// present with at least one of its distinguishing sidebands.
    pub(crate) fn decide(&mut self, df: f64, fr: f64) {
        for l in &mut self.harmonics {
            let tol = (0.6 * df).max(0.0005 * l.found_hz);
            let k = (l.found_hz / fr).round();
            l.shaft_order = (k >= 1.0
                && (l.found_hz - k * fr).abs() <= tol
                && (l.expected_hz - k * fr).abs() > tol)
                .then_some(k as u32);
        }
        // one impact train has one fault frequency: a harmonic counts only when its found
        // frequency is h × the fundamental implied by the most prominent counting harmonic
        // (within max(1.5 bins, 0.3 %))
        let best = self
            .harmonics
            .iter()
            .enumerate()
            .filter(|(_, l)| l.present && l.explained_by.is_none() && l.shaft_order.is_none())
            .max_by(|a, b| a.1.evidence_db.total_cmp(&b.1.evidence_db))
            .map(|(i, l)| l.found_hz / (i + 1) as f64);
        for (i, l) in self.harmonics.iter_mut().enumerate() {
            let h = (i + 1) as f64;
            l.consistent = match best {
                Some(f) => (l.found_hz - h * f).abs() <= (1.5 * df).max(0.003 * h * f),
                None => true,
            };
        }
        self.harmonics_present = self.harmonics.iter().filter(|l| l.counts()).count();
        self.sidebands_present = self.sidebands.iter().filter(|l| l.counts()).count();
        let first = self.harmonics.first().is_some_and(Line::counts);
        self.detected =
            self.harmonics_present >= crate::MIN_LINES || (first && self.sidebands_present >= 1);
    }

    /// Frequencies of this hypothesis's line family (for explaining other hypotheses' lines).
    pub(crate) fn family(&self, fr: f64, ftf_hz: f64) -> Vec<f64> {
        self.family_spans(fr, ftf_hz)
            .into_iter()
            .map(|(f, _)| f)
            .collect()
    }

    /// This hypothesis's line family as (frequency, half-width) pairs: the half-width is 0 where
    /// the line is tied to the found fundamental and the shaft, and the slip window for the cage
    /// harmonics of a ball fault — the cage slips on its own, not by the ratio the ball-spin line
    /// shows (a simulated ball fault's 9th cage harmonic sat 1.4 % below the kinematic BPFO
    /// while its ball line sat 0.1 % below BSF, and read as an outer-race fault).
    pub(crate) fn family_spans(&self, fr: f64, ftf_hz: f64) -> Vec<(f64, f64)> {
        let f1 = self.harmonics.first().map_or(self.fault_hz, |l| l.found_hz);
        let mut v: Vec<(f64, f64)> = Vec::new();
        match self.hypothesis {
            Hypothesis::Outer => {
                for k in 1..=6 {
                    for j in -2i32..=2 {
                        v.push((k as f64 * f1 + f64::from(j) * fr, 0.0));
                    }
                }
            }
            Hypothesis::Inner => {
                for k in 0..=HARMONICS {
                    for j in -3i32..=3 {
                        v.push((k as f64 * f1 + f64::from(j) * fr, 0.0));
                    }
                }
            }
            Hypothesis::Ball => {
                // the cage rate as slipped by the same ratio as the found ball line
                let ftf = ftf_hz * f1 / self.fault_hz.max(f64::MIN_POSITIVE);
                for k in 1..=HARMONICS {
                    for j in -2i32..=2 {
                        v.push((k as f64 * f1 + f64::from(j) * ftf, 0.0));
                        v.push((k as f64 * f1 + f64::from(j) * fr, 0.0));
                    }
                }
                // a ball defect enters and leaves the load zone once per cage turn, so its
                // envelope holds cage harmonics; BPFO = n·FTF is one of them. The cage slips
                // independently of the ball spin: each harmonic spans the slip window of the
                // kinematic cage rate
                let (lo, hi) = (1.0 - SLIP_MAX - SPEED_TOL, 1.0 + SPEED_OFFSET + SPEED_TOL);
                let top = (HARMONICS as f64 + 1.0) * f1;
                let mut j = 1.0;
                while j * ftf_hz * lo <= top && ftf_hz > 0.0 {
                    let (a, b) = (j * ftf_hz * lo, j * ftf_hz * hi);
                    v.push((0.5 * (a + b), 0.5 * (b - a)));
                    j += 1.0;
                }
            }
        }
        v.retain(|(f, _)| *f > 0.0);
        v
    }
}

/// Search window ratios `[lo, hi]` (found / kinematic) for a hypothesis: slip of up to
/// [`SLIP_MAX`] lowers the cage, outer-race and ball rates and raises BPFI by
/// `SLIP_MAX · BPFO/BPFI`; the ~[`SPEED_OFFSET`] speed-reference offset raises all; ± [`SPEED_TOL`]
/// for speed measurement.
pub(crate) fn window_ratio(h: Hypothesis, o: &FaultOrders) -> (f64, f64) {
    match h {
        Hypothesis::Inner => (
            1.0 - SPEED_TOL,
            1.0 + SLIP_MAX * o.bpfo / o.bpfi + SPEED_OFFSET + SPEED_TOL,
        ),
        Hypothesis::Outer | Hypothesis::Ball => {
            (1.0 - SLIP_MAX - SPEED_TOL, 1.0 + SPEED_OFFSET + SPEED_TOL)
        }
    }
}

/// Evaluate hypothesis `h` in one band's envelope spectrum.
pub(crate) fn evaluate(
    h: Hypothesis,
    env: &EnvelopeSpectrum,
    baseline: Option<&EnvelopeSpectrum>,
    o: &FaultOrders,
    fr: f64,
) -> HypothesisEvidence {
    let (name, order) = match h {
        Hypothesis::Inner => ("BPFI", o.bpfi),
        Hypothesis::Outer => ("BPFO", o.bpfo),
        Hypothesis::Ball => ("BSF", o.ball_defect),
    };
    let f0 = order * fr;
    let (rlo, rhi) = window_ratio(h, o);
    let harmonics: Vec<Line> = (1..=HARMONICS)
        .map(|k| {
            let e = k as f64 * f0;
            env.line(
                format!("{name}×{k}"),
                e,
                e * rlo,
                e * rhi,
                fr,
                true,
                baseline,
            )
        })
        .collect();
    let f1 = harmonics[0].found_hz;
    let df = env.resolution_hz;
    let ftf_hz = o.ftf * fr;
    // sidebands f₁ ± spacing, searched within ± tol(centre)
    let pair = |spacing: f64, tags: [&str; 2], tol: &dyn Fn(f64) -> f64| -> Vec<Line> {
        [(-1.0, tags[0]), (1.0, tags[1])]
            .iter()
            .map(|&(s, tag)| {
                let c = f1 + s * spacing;
                let t = tol(c);
                env.line(
                    format!("{name}×1{tag}"),
                    c,
                    c - t,
                    c + t,
                    fr,
                    true,
                    baseline,
                )
            })
            .collect()
    };
    let sidebands: Vec<Line> = match h {
        Hypothesis::Outer => Vec::new(),
        Hypothesis::Inner => pair(fr, ["−fr", "+fr"], &|c| (0.6 * df).max(0.005 * c)),
        Hypothesis::Ball => pair(ftf_hz, ["−FTF", "+FTF"], &|c| {
            (0.6 * df).max(0.005 * c + (SLIP_MAX + SPEED_TOL) * ftf_hz)
        }),
    };
    let score_db = score(&harmonics, &sidebands);
    let mut ev = HypothesisEvidence {
        hypothesis: h,
        fault_hz: f0,
        band_hz: env.band_hz,
        band_spectral_kurtosis: env.spectral_kurtosis,
        harmonics,
        sidebands,
        score_db,
        harmonics_present: 0,
        sidebands_present: 0,
        detected: false,
    };
    ev.decide(df, fr);
    ev
}

/// `Σ_h max(0, P_h) + ½ Σ_s max(0, P_s)`, dB: a hypothesis's score from its lines' evidence.
fn score(harmonics: &[Line], sidebands: &[Line]) -> f64 {
    let sum = |v: &[Line]| v.iter().map(|l| l.evidence_db.max(0.0)).sum::<f64>();
    sum(harmonics) + 0.5 * sum(sidebands)
}

/// Mark the lines of `ev` that the family `fam` of hypothesis `by` explains: within
/// `max(1 bin, 0.1 %)` of one of its frequencies (unresolvable from it). An explained line's
/// window is searched again over the peaks the family does not explain; when one of them is
/// present it takes the line's place (the passed-over peak is kept in [`Line::passed_over`]),
/// so two faults whose rates lie within a search window of each other are both read.
fn mark_explained(
    ev: &mut HypothesisEvidence,
    families: &[(Hypothesis, Vec<(f64, f64)>)],
    env: &EnvelopeSpectrum,
    baseline: Option<&EnvelopeSpectrum>,
    fr: f64,
) {
    let df = env.resolution_hz;
    let explainer = |f: f64| {
        families
            .iter()
            .find(|(_, fam)| {
                fam.iter()
                    .any(|(g, w)| (f - g).abs() <= df.max(0.001 * f).max(*w))
            })
            .map(|(h, _)| *h)
    };
    let explains = |f: f64| explainer(f).is_some();
    let mut changed = false;
    for l in ev.harmonics.iter_mut().chain(ev.sidebands.iter_mut()) {
        let Some(by) = l
            .explained_by
            .is_none()
            .then(|| explainer(l.found_hz))
            .flatten()
        else {
            continue;
        };
        {
            let other = env.line_where(
                l.label.clone(),
                l.expected_hz,
                l.search_hz[0],
                l.search_hz[1],
                fr,
                true,
                baseline,
                &explains,
            );
            if other.present && other.found_hz != l.found_hz {
                let passed = PassedOver {
                    found_hz: l.found_hz,
                    prominence_db: l.prominence_db,
                    by,
                };
                *l = Line {
                    passed_over: Some(passed),
                    ..other
                };
                changed = true;
            } else {
                l.explained_by = Some(by);
            }
        }
    }
    if changed {
        ev.score_db = score(&ev.harmonics, &ev.sidebands);
    }
}

/// Mark the lines of `ev` that the families `by` (faults detected in another band, with their
/// family frequencies) explain, as [`cross_explain`] does within a band, and re-decide.
pub(crate) fn explain_by(
    ev: &mut HypothesisEvidence,
    by: &[(Hypothesis, Vec<(f64, f64)>)],
    env: &EnvelopeSpectrum,
    baseline: Option<&EnvelopeSpectrum>,
    fr: f64,
) {
    mark_explained(ev, by, env, baseline, fr);
    ev.decide(env.resolution_hz, fr);
}

/// Mark lines of weaker hypotheses that a stronger detected hypothesis's family explains, in
/// order of decreasing score, and re-decide. A line at `f` is explained by a family frequency
/// `g` when `|f − g| ≤ max(1 bin, 0.1 % of f)` (unresolvable from it). Families: outer `k f₁ + j fr`; inner
/// `k f₁ + j fr`; ball `k f₁ + j FTF`, `k f₁ + j fr` and the cage harmonics (shaft-rate
/// modulation of every line is ubiquitous on real machines).
pub(crate) fn cross_explain(
    ev: &mut [HypothesisEvidence],
    env: &EnvelopeSpectrum,
    baseline: Option<&EnvelopeSpectrum>,
    fr: f64,
    ftf_hz: f64,
) {
    let df = env.resolution_hz;
    let mut order: Vec<usize> = (0..ev.len()).collect();
    order.sort_by(|&a, &b| ev[b].score_db.total_cmp(&ev[a].score_db).then(a.cmp(&b)));
    let mut confirmed: Vec<(Hypothesis, Vec<(f64, f64)>)> = Vec::new();
    for &i in &order {
        mark_explained(&mut ev[i], &confirmed, env, baseline, fr);
        ev[i].decide(df, fr);
        if ev[i].detected {
            confirmed.push((ev[i].hypothesis, ev[i].family_spans(fr, ftf_hz)));
        }
    }
}
