//! Lines in a squared envelope spectrum: search windows, prominence over the local median,
//! hypothesis scores and the cross-explanation of lines between hypotheses.

use serde::{Deserialize, Serialize};

use crate::{
    BACKGROUND_HALF_WIDTH_ORDERS, CFAR_QUANTILE, HARMONICS, Hypothesis, LINE_THRESHOLD_DB,
    SLIP_MAX, SPEED_OFFSET, SPEED_TOL,
};
use bearing_model::FaultOrders;

/// One searched line of the squared envelope spectrum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Line {
    /// What it is, e.g. `BPFI×2`, `BPFI×1+fr`, `BSF×1−FTF`, `fr×1`.
    pub label: String,
    /// Kinematic frequency at the declared speed, Hz.
    pub expected_hz: f64,
    /// Searched window `[low, high]`, Hz.
    pub search_hz: [f64; 2],
    /// Frequency of the largest bin in the window, Hz.
    pub found_hz: f64,
    /// `10 log10(peak / local median)` of the squared envelope spectrum, dB.
    pub prominence_db: f64,
    /// Prominence of the same line (the largest local maximum within ± 1.5 bins of
    /// `found_hz`) in the healthy baseline's squared envelope spectrum of the same band and
    /// resolution, dB; `null` without a baseline recording (self-referenced, or a baseline
    /// from a machine model).
    #[serde(default)]
    pub baseline_prominence_db: Option<f64>,
    /// The line's evidence, dB: `prominence_db`, less `baseline_prominence_db` when the healthy
    /// machine already holds the line (baseline prominence ≥ `LINE_THRESHOLD_DB`) — a line the
    /// baseline has is not evidence of a fault unless it has grown.
    #[serde(default)]
    pub evidence_db: f64,
    /// `evidence_db ≥` the spectrum's line threshold (≥ `LINE_THRESHOLD_DB`).
    pub present: bool,
    /// A line of a stronger, detected hypothesis's family sits at `found_hz`; it does not count.
    pub explained_by: Option<Hypothesis>,
    /// For harmonics: `found_hz` agrees with h × the fundamental implied by the most prominent
    /// counting harmonic (always true for sidebands and shaft lines).
    pub consistent: bool,
    /// For a fault harmonic: the integer shaft order k when `found_hz` sits on k·fr (within
    /// max(0.6 bin, 0.05 %)) while the kinematic frequency does not — a shaft-order line (a
    /// fan, a coupling, a mesh sideband) that a fault rate close to an integer order (a 6203's
    /// ball-defect rate is 3.988 fr) would otherwise take in; it does not count.
    #[serde(default)]
    pub shaft_order: Option<u32>,
    /// The window's strongest peak when it belongs to the family of a stronger, detected fault
    /// (a 6203's ball-defect rate lies within 1 % of BPFI − fr): this line is then the strongest
    /// peak of the window that no such family explains. Absent when the line is the window's
    /// strongest peak.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passed_over: Option<PassedOver>,
}

/// A peak a [`Line`]'s search passed over because another fault's family explains it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PassedOver {
    /// Frequency of the passed-over peak, Hz.
    pub found_hz: f64,
    /// Its prominence, dB.
    pub prominence_db: f64,
    /// The fault whose family it belongs to.
    pub by: Hypothesis,
}

impl Line {
    /// Present, not explained by another hypothesis, consistent, and not a shaft-order line.
    pub fn counts(&self) -> bool {
        self.present && self.explained_by.is_none() && self.consistent && self.shaft_order.is_none()
    }
}

/// A Welch power spectrum of the squared envelope of one band, with the search helpers.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EnvelopeSpectrum {
    /// Demodulation band `[low, high]`, Hz.
    pub band_hz: [f64; 2],
    /// Bin spacing, Hz.
    pub resolution_hz: f64,
    /// Power per bin (arbitrary units²/Hz; only ratios are used).
    pub power: Vec<f64>,
    /// Spectral kurtosis of the band, `⟨|z|⁴⟩/⟨|z|²⟩² − 2`.
    pub spectral_kurtosis: f64,
    /// Welch segments averaged.
    pub segments: usize,
    /// Prominence a line needs in this spectrum, dB (see `set_threshold`).
    pub line_threshold_db: f64,
}

impl EnvelopeSpectrum {
    fn freq(&self, k: usize) -> f64 {
        k as f64 * self.resolution_hz
    }

    /// Within half a bin of a shaft harmonic `j·fr`, `j ≥ 1`: not eligible as a fault line
    /// (envelope lines at shaft harmonics have many causes).
    fn guarded(&self, k: usize, fr: f64) -> bool {
        let f = self.freq(k);
        let j = (f / fr).round();
        j >= 1.0 && (f - j * fr).abs() < 0.5 * self.resolution_hz
    }

    /// Median power within `± half_width` of `f` (bins ≥ 1).
    fn background(&self, f: f64, half_width: f64) -> f64 {
        let df = self.resolution_hz;
        let lo = ((f - half_width) / df).ceil().max(1.0) as usize;
        let hi = (((f + half_width) / df).floor().max(0.0) as usize)
            .min(self.power.len().saturating_sub(1));
        if lo > hi {
            return 0.0;
        }
        let mut v: Vec<f64> = self.power[lo..=hi].to_vec();
        let mid = v.len() / 2;
        let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
        *m
    }

    /// The largest eligible local maximum in bins `k0..=k1` and its prominence over the local
    /// median, dB (`None` when the window holds no local maximum).
    fn peak_in(
        &self,
        k0: usize,
        k1: usize,
        fr: f64,
        guard: bool,
        exclude: &dyn Fn(f64) -> bool,
    ) -> Option<(f64, f64)> {
        // a line is a local maximum of the spectrum: the largest bin of a window whose edge
        // cuts the skirt of a strong line outside it is not a line of its own
        let k1 = k1.min(self.power.len().saturating_sub(1));
        let best = (k0.max(1)..=k1)
            .filter(|&k| {
                k < self.power.len()
                    && !(guard && self.guarded(k, fr))
                    && self.is_peak(k)
                    && !exclude(self.freq(k))
            })
            .max_by(|&a, &b| self.power[a].total_cmp(&self.power[b]).then(b.cmp(&a)))?;
        let f = self.freq(best);
        let bg = self.background(f, BACKGROUND_HALF_WIDTH_ORDERS * fr);
        let p = self.power[best];
        let db = if bg > 0.0 && p > 0.0 {
            10.0 * (p / bg).log10()
        } else {
            0.0
        };
        Some((f, if db.is_finite() { db } else { 0.0 }))
    }

    /// Search `[lo, hi]` (widened to at least ± 0.6 bin around `expected`) for the largest
    /// eligible bin and measure its prominence; with a `baseline` spectrum (same band and
    /// resolution), measure the same line there too (see [`Line::evidence_db`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn line(
        &self,
        label: String,
        expected: f64,
        lo: f64,
        hi: f64,
        fr: f64,
        guard: bool,
        baseline: Option<&EnvelopeSpectrum>,
    ) -> Line {
        self.line_where(label, expected, lo, hi, fr, guard, baseline, &|_| false)
    }

    /// [`Self::line`] over the window's peaks for which `exclude` is false.
    #[allow(clippy::too_many_arguments)]
    fn line_where(
        &self,
        label: String,
        expected: f64,
        lo: f64,
        hi: f64,
        fr: f64,
        guard: bool,
        baseline: Option<&EnvelopeSpectrum>,
        exclude: &dyn Fn(f64) -> bool,
    ) -> Line {
        let df = self.resolution_hz;
        // when the kinematics put the line itself on a shaft harmonic (the 6203's ball-defect
        // rate is 3.987 fr), the guard would hide it: it applies only to lines clear of one
        let j = (expected / fr).round();
        let guard = guard && (j < 1.0 || (expected - j * fr).abs() > 1.5 * df);
        let lo = lo.min(expected - 0.6 * df).max(df);
        let hi = hi.max(expected + 0.6 * df);
        let k0 = (lo / df).ceil() as usize;
        let k1 = (hi / df).floor() as usize;
        let (found_hz, prominence_db) = self
            .peak_in(k0, k1, fr, guard, exclude)
            .unwrap_or((expected, 0.0));
        let baseline_prominence_db = baseline
            .filter(|b| (b.resolution_hz - df).abs() <= 1e-9 * df && !b.power.is_empty())
            .map(|b| {
                let k = found_hz / df;
                b.peak_in(
                    (k - 1.5).ceil().max(1.0) as usize,
                    (k + 1.5).floor() as usize,
                    fr,
                    false,
                    &|_| false,
                )
                .map_or(0.0, |(_, db)| db)
            });
        let evidence_db = match baseline_prominence_db {
            Some(b) if b >= LINE_THRESHOLD_DB => prominence_db - b,
            _ => prominence_db,
        };
        Line {
            label,
            expected_hz: expected,
            search_hz: [lo, hi],
            found_hz,
            prominence_db,
            baseline_prominence_db,
            evidence_db,
            present: evidence_db >= self.line_threshold_db,
            explained_by: None,
            shaft_order: None,
            consistent: true,
            passed_over: None,
        }
    }

    /// Bin `k` is a local maximum (≥ both neighbours, > at least one).
    fn is_peak(&self, k: usize) -> bool {
        let p = self.power[k];
        let l = if k > 0 {
            self.power[k - 1]
        } else {
            f64::NEG_INFINITY
        };
        let r = self.power.get(k + 1).copied().unwrap_or(f64::NEG_INFINITY);
        p >= l && p >= r && (p > l || p > r)
    }

    /// Set the line threshold of this spectrum: [`LINE_THRESHOLD_DB`], raised to the
    /// [`CFAR_QUANTILE`] of the prominences of the local maxima between fr/2 and `top_hz` that no
    /// bearing kinematics explains (none of the `kinematic` frequencies — every hypothesis's line
    /// family and the shaft harmonics — within a bin): a rank CFAR, so a fault line must stand
    /// out among the spectrum's unexplained lines (mains, interference), not only over its noise.
    pub(crate) fn set_threshold(&mut self, fr: f64, top_hz: f64, kinematic: &[f64]) {
        let df = self.resolution_hz;
        let k0 = ((0.5 * fr / df).ceil() as usize).max(1);
        let k1 = ((top_hz / df).floor() as usize).min(self.power.len().saturating_sub(2));
        let mut proms: Vec<f64> = (k0..=k1)
            .filter(|&k| self.is_peak(k))
            .filter(|&k| {
                let f = self.freq(k);
                !kinematic.iter().any(|g| (f - g).abs() <= df.max(0.001 * f))
            })
            .filter_map(|k| {
                let bg = self.background(self.freq(k), BACKGROUND_HALF_WIDTH_ORDERS * fr);
                let p = self.power[k];
                (bg > 0.0 && p > 0.0).then(|| 10.0 * (p / bg).log10())
            })
            .filter(|v| v.is_finite())
            .collect();
        self.line_threshold_db = LINE_THRESHOLD_DB;
        if proms.len() >= 10 {
            proms.sort_by(f64::total_cmp);
            let i = ((CFAR_QUANTILE * proms.len() as f64).ceil() as usize).min(proms.len()) - 1;
            self.line_threshold_db = LINE_THRESHOLD_DB.max(proms[i]);
        }
    }
}

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
