//! One band's squared envelope spectrum as the detector reads it: the prominence of each local
//! maximum over the local median (dB, ≥ 0; 0 elsewhere), less what the healthy baseline already
//! holds there, with the lines of known non-bearing sources masked: the shaft's orders (and half
//! orders) when the band shows their comb, mains multiples when it shows theirs.

use serde::{Deserialize, Serialize};

use crate::{BACKGROUND_HALF_WIDTH_ORDERS, EnvelopeSpectrum, LINE_THRESHOLD_DB};

/// Shaft orders (and half orders, and mains multiples) looked at to decide whether a band shows
/// their comb.
pub const COMB_CHECK_ORDERS: usize = 10;
/// A comb is present in a band when at least this many of its first [`COMB_CHECK_ORDERS`] lines
/// (two of the first six mains multiples) stand [`LINE_THRESHOLD_DB`] over the local median.
pub const COMB_MIN_LINES: usize = 3;
/// Mains frequencies, Hz.
pub const MAINS_HZ: [f64; 2] = [50.0, 60.0];
/// A comb's lines are looked for, and masked, within ± this fraction of their frequency (or a
/// bin, whichever is wider): a shaft's speed wanders a few tenths of a per cent over a
/// recording, and its comb's high orders smear by as much. A fault line closer than this to a
/// shaft order cannot be told from the shaft's.
pub const COMB_TOLERANCE: f64 = 0.0025;

/// What was masked in a band, as reports state it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Masks {
    /// Integer shaft orders masked (the band's envelope holds a shaft comb).
    pub shaft_orders: bool,
    /// Half orders masked (a comb at (k + ½)·fr: looseness, a rub).
    pub half_orders: bool,
    /// Multiples of this mains frequency masked, Hz.
    pub mains_hz: Option<f64>,
}

/// A band's spectrum prepared for the template search.
#[derive(Debug, Clone)]
pub(crate) struct BandView {
    /// Bin spacing, Hz.
    pub df: f64,
    /// Prominence of each local maximum over the local median, dB (0 elsewhere).
    pub raw: Vec<f64>,
    /// The healthy baseline's prominence at each bin (the largest within ± 1.5 bins), dB; empty
    /// without a baseline spectrum of this band.
    pub base: Vec<f64>,
    /// Evidence: `raw` less `base` where the baseline holds a line (≥ [`LINE_THRESHOLD_DB`]),
    /// ≥ 0, and 0 at masked bins.
    pub d: Vec<f64>,
    /// The evidence before any mask.
    unmasked: Vec<f64>,
    /// Highest frequency read, Hz (the squared envelope of a band `B` wide holds difference
    /// frequencies up to `B`).
    pub top_hz: f64,
    /// What was masked.
    pub masks: Masks,
    /// Masked bins.
    pub masked: Vec<bool>,
    /// Power less the local median per bin (units²/Hz of the squared envelope; negative where
    /// the bin lies below its median).
    excess: Vec<f64>,
    /// Mean of the squared envelope.
    mean_square: f64,
    /// Relative tolerance of a comb's lines ([`COMB_TOLERANCE`], or the speed's uncertainty).
    comb_tolerance: f64,
}

impl BandView {
    /// Prepare `sp` (shaft at `fr` Hz), with the healthy baseline's spectrum of the same band at
    /// the same resolution when there is one.
    pub(crate) fn new(
        sp: &EnvelopeSpectrum,
        baseline: Option<&EnvelopeSpectrum>,
        fr: f64,
        comb_tolerance: f64,
        kinematic: &[(f64, f64)],
    ) -> Self {
        let df = sp.resolution_hz;
        let width = sp.band_hz[1] - sp.band_hz[0];
        let n = sp.power.len();
        let top_hz = (0.95 * width).min(df * n.saturating_sub(2) as f64);
        let (raw, median) = prominence(sp, fr);
        let excess: Vec<f64> = sp.power.iter().zip(&median).map(|(p, m)| p - m).collect();
        let base = match baseline {
            Some(b)
                if (b.resolution_hz - df).abs() <= 5e-3 * df
                    && !b.power.is_empty()
                    && b.power.len() >= 3 =>
            {
                let pb = prominence(b, fr).0;
                // the baseline's own bins: the largest prominence within ± 1.5 bins
                (0..n)
                    .map(|k| {
                        let c = k as f64 * df / b.resolution_hz;
                        let lo = (c - 1.5).ceil().max(1.0) as usize;
                        let hi = ((c + 1.5).floor() as usize).min(pb.len().saturating_sub(1));
                        (lo..=hi).map(|j| pb[j]).fold(0.0, f64::max)
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        let mut d: Vec<f64> = raw
            .iter()
            .enumerate()
            .map(|(k, &r)| match base.get(k) {
                Some(&b) if b >= LINE_THRESHOLD_DB => (r - b).max(0.0),
                _ => r,
            })
            .collect();
        let mut view = Self {
            df,
            raw,
            base,
            top_hz,
            masks: Masks::default(),
            masked: vec![false; n],
            d: Vec::new(),
            unmasked: d.clone(),
            comb_tolerance,
            excess,
            mean_square: sp.mean_square,
        };
        // the comb checks read the evidence before any mask
        let present = |f: f64, d: &[f64]| {
            !kinematic.iter().any(|&(a, b)| (a..=b).contains(&f))
                && view_max(d, df, f, (comb_tolerance * f / df).max(1.0)) >= LINE_THRESHOLD_DB
        };
        let count = |f0: f64, offset: f64, limit: usize, d: &[f64]| {
            (0..limit)
                .map(|j| (j as f64 + offset) * f0)
                .filter(|&f| f > 0.0 && f < top_hz)
                .filter(|&f| present(f, d))
                .count()
        };
        let shaft = count(fr, 1.0, COMB_CHECK_ORDERS, &d) >= COMB_MIN_LINES;
        let half = count(fr, 0.5, COMB_CHECK_ORDERS, &d) >= COMB_MIN_LINES;
        let mains = MAINS_HZ
            .iter()
            .copied()
            .filter(|&m| count(m, 1.0, 6, &d) >= 2)
            .max_by_key(|&m| count(m, 1.0, 6, &d));
        view.masks = Masks {
            shaft_orders: shaft,
            half_orders: half,
            mains_hz: mains,
        };
        if shaft {
            view.mask_comb(fr, 1.0);
        }
        if half {
            view.mask_comb(fr, 0.5);
        }
        if let Some(m) = mains {
            view.mask_comb(m, 1.0);
        }
        for (k, v) in d.iter_mut().enumerate() {
            if view.masked[k] {
                *v = 0.0;
            }
        }
        view.d = d;
        view.refresh();
        view
    }

    /// Zero the evidence of masked bins (after masks were added).
    pub(crate) fn refresh(&mut self) {
        for (d, &m) in self.d.iter_mut().zip(&self.masked) {
            if m {
                *d = 0.0;
            }
        }
    }

    /// Modulation depth of the squared envelope at the line nearest `f`: `√(2 P)/μ`, P the
    /// line's power above the local median summed over ± 1 bin (the Hann window's main lobe;
    /// noise above and below the median cancels in the sum) and clipped at 0, μ the squared
    /// envelope's mean (a squared envelope `μ(1 + m cos 2πft)` has depth m). 0 without a mean,
    /// and where the bin nearest `f` is no line of its own (no evidence there, or masked).
    pub(crate) fn depth(&self, f: f64) -> f64 {
        let n = self.excess.len();
        if n == 0 || self.mean_square.is_nan() || self.mean_square <= 0.0 {
            return 0.0;
        }
        let c = ((f / self.df).round() as usize).min(n - 1);
        if self.masked[c] || self.d[c].is_nan() || self.d[c] <= 0.0 {
            return 0.0;
        }
        let p: f64 = self.excess[c.saturating_sub(1)..=(c + 1).min(n - 1)]
            .iter()
            .sum::<f64>()
            .max(0.0)
            * self.df;
        (2.0 * p).sqrt() / self.mean_square
    }

    /// Mask the shaft's integer orders (when another band showed their comb: a comb in the
    /// envelope of one band makes the lines at shaft orders of every band the shaft's).
    pub(crate) fn mask_shaft_orders(&mut self, fr: f64) {
        if !self.masks.shaft_orders {
            self.masks.shaft_orders = true;
            self.mask_comb(fr, 1.0);
            self.refresh();
        }
    }

    /// Lines of the shaft comb `j·fr`, `j = 1..=`[`COMB_CHECK_ORDERS`], that this band's
    /// evidence holds (≥ [`LINE_THRESHOLD_DB`] within its comb tolerance), frequencies inside
    /// `kinematic` (the faults' harmonic windows) not counted: the check [`BandView::new`] makes
    /// at the speed used, at another speed.
    pub(crate) fn shaft_comb_lines(&self, fr: f64, kinematic: &[(f64, f64)]) -> usize {
        (1..=COMB_CHECK_ORDERS)
            .map(|j| j as f64 * fr)
            .filter(|&f| f < self.top_hz)
            .filter(|&f| !kinematic.iter().any(|&(a, b)| (a..=b).contains(&f)))
            .filter(|&f| {
                view_max(
                    &self.d,
                    self.df,
                    f,
                    (self.comb_tolerance * f / self.df).max(1.0),
                ) >= LINE_THRESHOLD_DB
            })
            .count()
    }

    /// Whether the bin nearest `f` is masked (its evidence unreadable).
    pub(crate) fn masked_at(&self, f: f64) -> bool {
        let i = (f / self.df).round();
        i >= 0.0 && self.masked.get(i as usize).copied().unwrap_or(false)
    }

    /// Whether the evidence holds a line (≥ [`LINE_THRESHOLD_DB`]) within `half_width` Hz of
    /// `f` (at least the nearest bin), below the band's top.
    pub(crate) fn holds_line(&self, f: f64, half_width: f64) -> bool {
        self.line_in(&self.d, f, half_width)
    }

    /// Whether the evidence before any mask holds a line (≥ [`LINE_THRESHOLD_DB`]) within
    /// `half_width` Hz of `f` (at least the nearest bin), below the band's top: a comb masked as
    /// the shaft's, or as a mains multiple's, is still a comb.
    pub(crate) fn holds_line_unmasked(&self, f: f64, half_width: f64) -> bool {
        self.line_in(&self.unmasked, f, half_width)
    }

    /// Whether `evidence` (this view's bins) holds a line within `half_width` Hz of `f`, below
    /// the band's top.
    fn line_in(&self, evidence: &[f64], f: f64, half_width: f64) -> bool {
        f < self.top_hz && view_max(evidence, self.df, f, half_width / self.df) >= LINE_THRESHOLD_DB
    }

    /// This view with the shaft's integer orders of `fr` masked besides what it masks already
    /// (a speed a template search tries: the shaft comb at that speed is the shaft's).
    pub(crate) fn with_shaft_orders_at(&self, fr: f64) -> Self {
        let mut w = self.clone();
        w.masks.shaft_orders = true;
        w.mask_comb(fr, 1.0);
        w.refresh();
        w
    }

    /// Mask `(j + offset)·f0`, `j ≥ 0`, up to the top: ± max(1 bin, [`COMB_TOLERANCE`] of the
    /// frequency).
    fn mask_comb(&mut self, f0: f64, offset: f64) {
        let mut j = 0.0;
        loop {
            let f = (j + offset) * f0;
            if f > self.top_hz + 2.0 * self.df {
                break;
            }
            if f > 0.0 {
                self.mask_around(f, self.df.max(self.comb_tolerance * f));
            }
            j += 1.0;
        }
    }

    /// Mask bins within `half_width` Hz of `f`.
    pub(crate) fn mask_around(&mut self, f: f64, half_width: f64) {
        let n = self.masked.len();
        if n == 0 {
            return;
        }
        let lo = ((f - half_width) / self.df).ceil().max(0.0) as usize;
        let hi = (((f + half_width) / self.df).floor().max(0.0) as usize).min(n - 1);
        for k in lo..=hi.max(lo).min(n - 1) {
            if (k as f64 * self.df - f).abs() <= half_width {
                self.masked[k] = true;
            }
        }
    }

    /// Whether the bin nearest `f` is masked.
    #[cfg(test)]
    pub(crate) fn is_masked(&self, f: f64) -> bool {
        let k = (f / self.df).round() as usize;
        self.masked.get(k).copied().unwrap_or(false)
    }
}

/// The largest value of `d` within `bins` bins of `f`.
fn view_max(d: &[f64], df: f64, f: f64, bins: f64) -> f64 {
    if d.is_empty() {
        return 0.0;
    }
    let lo = ((f / df - bins).ceil().max(0.0)) as usize;
    let hi = (((f / df + bins).floor().max(0.0)) as usize).min(d.len() - 1);
    if lo > hi {
        return 0.0;
    }
    d[lo..=hi].iter().copied().fold(0.0, f64::max)
}

/// Prominence of each local maximum of `sp` over the median within ±
/// [`BACKGROUND_HALF_WIDTH_ORDERS`] shaft orders, dB (≥ 0; 0 at other bins and at bin 0), and
/// that median at every bin. The median is taken every few bins and interpolated (a running
/// median at every bin cost as much as the rest of the diagnosis).
fn prominence(sp: &EnvelopeSpectrum, fr: f64) -> (Vec<f64>, Vec<f64>) {
    let p = &sp.power;
    let n = p.len();
    let df = sp.resolution_hz;
    let mut out = vec![0.0; n];
    if n < 3 || df.is_nan() || df <= 0.0 {
        return (out, p.clone());
    }
    let half = ((BACKGROUND_HALF_WIDTH_ORDERS * fr / df).round() as usize).max(2);
    let stride = (half / 8).max(1);
    // medians at bins 0, stride, 2·stride, … (and the last bin)
    let mut anchors: Vec<usize> = (0..n).step_by(stride).collect();
    if anchors.last() != Some(&(n - 1)) {
        anchors.push(n - 1);
    }
    let mut buf = Vec::with_capacity(2 * half + 1);
    let medians: Vec<f64> = anchors
        .iter()
        .map(|&c| {
            let lo = c.saturating_sub(half).max(1);
            let hi = (c + half).min(n - 1);
            buf.clear();
            buf.extend_from_slice(&p[lo..=hi.max(lo)]);
            let mid = buf.len() / 2;
            let (_, m, _) = buf.select_nth_unstable_by(mid, f64::total_cmp);
            *m
        })
        .collect();
    let median: Vec<f64> = (0..n)
        .map(|k| {
            // the anchors around k
            let i = (k / stride).min(anchors.len() - 1);
            let (a, b) = if anchors[i] >= k || i + 1 >= anchors.len() {
                (i, i)
            } else {
                (i, i + 1)
            };
            if a == b {
                medians[a]
            } else {
                let t = (k - anchors[a]) as f64 / (anchors[b] - anchors[a]) as f64;
                medians[a] * (1.0 - t) + medians[b] * t
            }
        })
        .collect();
    for k in 1..n - 1 {
        let v = p[k];
        if !(v >= p[k - 1] && v >= p[k + 1] && (v > p[k - 1] || v > p[k + 1])) {
            continue;
        }
        let m = median[k];
        if m > 0.0 && v > 0.0 {
            let db = 10.0 * (v / m).log10();
            if db.is_finite() && db > 0.0 {
                out[k] = db;
            }
        }
    }
    (out, median)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spectrum(lines: &[(f64, f64)], df: f64, n: usize, width: f64) -> EnvelopeSpectrum {
        let mut power = vec![1.0; n];
        // a gentle ripple so the noise has local maxima
        for (k, p) in power.iter_mut().enumerate() {
            *p *= 1.0 + 0.05 * ((k as f64) * 1.7).sin();
        }
        for &(f, a) in lines {
            let k = (f / df).round() as usize;
            power[k] = a;
        }
        EnvelopeSpectrum {
            band_hz: [1000.0, 1000.0 + width],
            resolution_hz: df,
            power,
            ..EnvelopeSpectrum::default()
        }
    }

    /// A line 10× the background reads 10 dB; a shaft comb (3 of the first 10 orders) is masked
    /// and a line 1.6 bins from an order survives; a mains comb is masked.
    #[test]
    fn prominence_and_masks() {
        let fr = 13.0;
        let df = fr / 32.0;
        let n = 4000;
        let lines = [
            (fr, 100.0),
            (2.0 * fr, 50.0),
            (3.0 * fr, 20.0),
            (4.95 * fr, 10.0),
            (100.0, 30.0),
            (200.0, 30.0),
        ];
        let v = BandView::new(
            &spectrum(&lines, df, n, 1200.0),
            None,
            fr,
            COMB_TOLERANCE,
            &[],
        );
        assert!(v.masks.shaft_orders);
        assert!(!v.masks.half_orders);
        assert_eq!(v.masks.mains_hz, Some(50.0));
        let k = (4.95 * fr / df).round() as usize;
        assert!((v.d[k] - 10.0).abs() < 0.5, "{}", v.d[k]);
        assert!(v.is_masked(2.0 * fr) && v.d[(2.0 * fr / df).round() as usize] == 0.0);
        assert!(v.is_masked(100.0));
        assert!(v.is_masked(3.0 * fr));
        assert!(!v.is_masked(4.95 * fr));
        // the same spectrum as its own baseline leaves nothing
        let sp = spectrum(&lines, df, n, 1200.0);
        let w = BandView::new(&sp, Some(&sp), fr, COMB_TOLERANCE, &[]);
        assert!(w.d[k] < 1e-9);
    }
}
