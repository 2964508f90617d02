//! Lines in a squared envelope spectrum: the spectrum, its search windows and a line's
//! prominence over the local median (re-exported by [`crate::evidence`]).

use serde::{Deserialize, Serialize};

use crate::{BACKGROUND_HALF_WIDTH_ORDERS, Hypothesis, LINE_THRESHOLD_DB};

/// Largest relative difference between the recording's and the baseline's envelope resolution
/// at which a baseline line is compared (the baseline's Welch segment is rounded to an even
/// length at its own envelope rate: ≤ 1 / segment ≈ 0.1 % at the shortest segment).
const BASELINE_RESOLUTION_TOL: f64 = 5e-3;

/// One searched line of the squared envelope spectrum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchedLine {
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
    /// resolution, dB; `null` without a healthy residual to read it in (self-referenced, or a
    /// machine-model baseline whose recording could not be synthesised).
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

/// A peak a [`SearchedLine`]'s search passed over because another fault's family explains it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PassedOver {
    /// Frequency of the passed-over peak, Hz.
    pub found_hz: f64,
    /// Its prominence, dB.
    pub prominence_db: f64,
    /// The fault whose family it belongs to.
    pub by: Hypothesis,
}

impl SearchedLine {
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
    /// Prominence at which a line is marked present in this spectrum, dB
    /// ([`LINE_THRESHOLD_DB`]).
    pub line_threshold_db: f64,
    /// Mean of the squared envelope (the band's power), whose lines' powers the modulation depth
    /// is taken against (units² of the input).
    #[serde(default)]
    pub mean_square: f64,
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
    /// resolution), measure the same line there too (see [`SearchedLine::evidence_db`]).
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
    ) -> SearchedLine {
        self.line_where(label, expected, lo, hi, fr, guard, baseline, &|_| false)
    }

    /// [`Self::line`] over the window's peaks for which `exclude` is false.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn line_where(
        &self,
        label: String,
        expected: f64,
        lo: f64,
        hi: f64,
        fr: f64,
        guard: bool,
        baseline: Option<&EnvelopeSpectrum>,
        exclude: &dyn Fn(f64) -> bool,
    ) -> SearchedLine {
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
        // the baseline's spectrum is computed at this resolution up to its segment's rounding
        // (< 0.1 %); its bins are its own
        let baseline_prominence_db = baseline
            .filter(|b| {
                (b.resolution_hz - df).abs() <= BASELINE_RESOLUTION_TOL * df && !b.power.is_empty()
            })
            .map(|b| {
                let k = found_hz / b.resolution_hz;
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
        SearchedLine {
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
}
