//! The line test of one hypothesis in one band: each line of its template against the same
//! band's windows of the same width away from the fault's lattice, and the lines' probabilities
//! combined by Fisher's method.
//!
//! A line's probability under "healthy" is the share of the band's **clear windows** — windows
//! of as many unmasked bins as the line's window holds, meeting no window of the hypothesis's
//! own lattice (`Template::lattice`), masked bins skipped (they hold no evidence on either side)
//! — whose strongest line is at least as prominent: whatever the band
//! holds besides this fault (noise, mains lines, beats, other machines' combs, other faults'
//! lattices) is in that reference, never taken below `1/(n' + 1)` (`n'` non-overlapping clear
//! windows: the dense windows overlap and read the same lines). Beyond every clear window, the
//! probability is a generalised Pareto tail fitted to the top fifth of the non-overlapping
//! windows' maxima (shape held at ≥ `1/√k`, so a few exceedances never claim a thin tail), and
//! no single line is taken below
//! [`P_LINE_FLOOR`]: one line, however strong, is one coincidence with a mains harmonic, a
//! neighbouring machine or a beat; a fault shows in several. The template's lines are at
//! different frequencies and their
//! references are the band's, so under "healthy" their probabilities are independent and
//! `X = −2 Σ ln p_k` is χ² with `2m` degrees of freedom (Fisher 1925): a fault needs several
//! lines to stand out, the way the kinematics say they should. Where the template's windows
//! overlap (widened windows), a line reads only the bins no earlier line read: one peak is one
//! line's evidence, never two.

use super::template::{Template, Term, Window};
use super::view::BandView;

/// Smallest probability one line is given: a fault needs two lines stronger than every clear
/// window to reach `p ≈ 1e-6` per band (`χ²₆(36.8)`), one such line alone `1e-3`.
pub const P_LINE_FLOOR: f64 = 1e-4;
/// Fraction of the non-overlapping clear windows above the tail threshold.
pub const TAIL_FRACTION: f64 = 0.2;
/// Fewest non-overlapping clear windows for a tail fit (fewer: the share alone, floored at
/// `1/(n + 1)`).
pub const MIN_TAIL_WINDOWS: usize = 25;

/// A line reference: the dense clear windows' maxima (sorted) and the tail fitted to the
/// non-overlapping ones.
#[derive(Debug, Clone)]
pub(crate) struct Reference {
    maxima: Vec<f64>,
    independent: usize,
    tail: Option<Tail>,
}

/// Generalised Pareto tail over `u`: `P(X > x) = rate (1 + ξ (x − u)/σ)^(−1/ξ)`.
#[derive(Debug, Clone, Copy)]
struct Tail {
    u: f64,
    rate: f64,
    xi: f64,
    sigma: f64,
}

impl Reference {
    /// `P(window maximum ≥ value)` under "healthy": the share of the clear windows at least as
    /// strong, never below `1/(n' + 1)` (`n'` non-overlapping windows: the dense windows overlap
    /// and read the same lines); beyond every clear window, the fitted tail, between
    /// [`P_LINE_FLOOR`] and `1/(n' + 1)`.
    pub(crate) fn p(&self, value: f64) -> f64 {
        let n = self.maxima.len();
        if n == 0 {
            return 1.0;
        }
        let edge = 1.0 / (1.0 + self.independent as f64);
        let count = n - self.maxima.partition_point(|m| *m < value);
        if count > 0 {
            return ((1.0 + count as f64) / (1.0 + n as f64)).max(edge).min(1.0);
        }
        match self.tail {
            Some(t) if value > t.u => {
                let y = value - t.u;
                let s = if t.xi > 1e-9 {
                    (1.0 + t.xi * y / t.sigma).powf(-1.0 / t.xi)
                } else {
                    (-y / t.sigma).exp()
                };
                // the floor never above the edge: a view with ≥ 10⁴ clear windows (an unmasked
                // band of a long record) has an edge below it, and `clamp` panicked there
                (t.rate * s).clamp(P_LINE_FLOOR.min(edge), edge)
            }
            _ => edge,
        }
    }

    fn new(dense: Vec<f64>, mut spaced: Vec<f64>) -> Self {
        let independent = spaced.len();
        spaced.sort_by(f64::total_cmp);
        let tail = (independent >= MIN_TAIL_WINDOWS)
            .then(|| {
                let k = ((TAIL_FRACTION * independent as f64).round() as usize)
                    .clamp(5, independent - 1);
                let u = spaced[independent - k - 1];
                let y: Vec<f64> = spaced[independent - k..].iter().map(|v| v - u).collect();
                let rate =
                    y.iter().filter(|v| **v > 0.0).count() as f64 / (1.0 + independent as f64);
                gpd_pwm(&y, 1.0 / (y.len() as f64).sqrt()).map(|(xi, sigma)| Tail {
                    u,
                    rate,
                    xi,
                    sigma,
                })
            })
            .flatten();
        Self {
            maxima: dense,
            independent,
            tail,
        }
    }
}

/// Generalised Pareto (ξ, σ) of exceedances `y` (≥ 0, sorted ascending) by probability-weighted
/// moments (Hosking & Wallis 1987, plotting positions `(i − 0.35)/n`), ξ clamped to
/// `[min_shape, ½]` with σ then from the mean (`E y = σ/(1 − ξ)`). `None` when the exceedances
/// carry no spread.
fn gpd_pwm(y: &[f64], min_shape: f64) -> Option<(f64, f64)> {
    let n = y.len() as f64;
    let a0 = y.iter().sum::<f64>() / n;
    if !(a0.is_finite() && a0 > 0.0) {
        return None;
    }
    let a1 = y
        .iter()
        .enumerate()
        .map(|(i, v)| (1.0 - (i as f64 + 0.65) / n) * v)
        .sum::<f64>()
        / n;
    let den = a0 - 2.0 * a1;
    let xi = if den > 0.0 { 2.0 - a0 / den } else { 0.5 };
    let xi = if xi.is_finite() {
        xi.clamp(min_shape.min(0.5), 0.5)
    } else {
        0.5
    };
    let sigma = a0 * (1.0 - xi);
    (sigma > 0.0).then_some((xi, sigma))
}

/// One line of the template as read in a band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TermReading {
    pub window: Window,
    /// The strongest bin in the window (its evidence is `value`).
    pub bin: usize,
    /// Its evidence, dB (0 when the window holds no line).
    pub value: f64,
    /// Its probability under "healthy".
    pub p: f64,
    /// Non-overlapping clear windows of its width in the band.
    pub null_size: usize,
}

/// A template read in one band.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BandReading {
    /// The lines read (a line whose window is wholly masked, or that has no clear window to
    /// compare with, is left out).
    pub terms: Vec<TermReading>,
    /// Fisher's statistic.
    pub fisher: f64,
    /// `P(χ²_{2m} ≥ fisher)`.
    pub p: f64,
    /// `Σ harmonics + ½ Σ sidebands` of the lines' evidence, dB (the report's score).
    pub statistic_db: f64,
}

/// A band's reference for the lines of one hypothesis: its clear bins (in range, unmasked, off
/// the lattice given, ± a bin) and, per window width, the maxima of every clear window of that
/// width (computed when first asked for).
pub(crate) struct LineTest<'a> {
    v: &'a BandView,
    /// The evidence of each run of clear bins (in range, off the lattice), its masked bins left
    /// out.
    runs: Vec<Vec<f64>>,
    top: usize,
    references: std::cell::RefCell<Vec<(usize, std::rc::Rc<Reference>)>>,
}

impl<'a> LineTest<'a> {
    /// The reference of band `v` for a hypothesis whose lattice (at every speed it is read at)
    /// is `lattice` (windows in Hz), shaft at `fr`.
    pub(crate) fn new(v: &'a BandView, lattice: &[(f64, f64)], fr: f64) -> Self {
        let n = v.d.len();
        let top = ((v.top_hz / v.df).floor() as usize).min(n.saturating_sub(1));
        let low = ((0.5 * fr / v.df).ceil() as usize).max(1);
        // masked bins do not end a run: they hold no evidence (0) in a line's window as in the
        // reference, and a reference window of `w` unmasked bins spans them (`runs`)
        let mut clear = vec![false; n];
        for c in clear.iter_mut().take(top + 1).skip(low) {
            *c = true;
        }
        for &(a, b) in lattice {
            let ka = ((a / v.df).floor().max(0.0) as usize).saturating_sub(1);
            let kb = ((b / v.df).ceil().max(0.0) as usize + 1).min(n.saturating_sub(1));
            for c in clear.iter_mut().take(kb + 1).skip(ka) {
                *c = false;
            }
        }
        Self {
            v,
            runs: clear_runs(&v.d, &clear, &v.masked),
            top,
            references: std::cell::RefCell::new(Vec::new()),
        }
    }

    fn reference(&self, width: usize) -> std::rc::Rc<Reference> {
        if let Some(r) = self.references.borrow().iter().find(|r| r.0 == width) {
            return r.1.clone();
        }
        let (dense, spaced) = clear_window_maxima(&self.runs, width);
        let r = std::rc::Rc::new(Reference::new(dense, spaced));
        self.references.borrow_mut().push((width, r.clone()));
        r
    }

    /// Read template `t`.
    pub(crate) fn read(&self, t: &Template) -> BandReading {
        self.read_windows(&t.windows(0.5 * self.v.df))
    }

    /// Read the lines of `windows` (each against the clear windows of its own width).
    pub(crate) fn read_windows(&self, windows: &[Window]) -> BandReading {
        let v = self.v;
        let top = self.top;
        let mut terms = Vec::new();
        let mut taken: Vec<(usize, usize)> = Vec::new();
        for &w in windows {
            let ka = ((w.lo_hz / v.df).ceil().max(1.0) as usize).min(top);
            let kb = ((w.hi_hz / v.df).floor().max(0.0) as usize).min(top);
            let (ka, kb) = if ka <= kb {
                (ka, kb)
            } else {
                let c = ((w.expected_hz / v.df).round() as usize).clamp(1, top.max(1));
                (c, c)
            };
            // the bins no earlier line of the template read: where windows overlap (a ball's
            // ± FTF beside its fundamental, widened windows) one peak would count twice, and
            // Fisher's method asks independent lines
            let free: Vec<usize> = (ka..=kb)
                .filter(|k| !taken.iter().any(|&(a, b)| (a..=b).contains(k)))
                .collect();
            if free.iter().all(|&k| v.masked[k]) {
                continue;
            }
            taken.push((ka, kb));
            let Some(bin) = free
                .iter()
                .copied()
                .max_by(|&a, &b| v.d[a].total_cmp(&v.d[b]).then(b.cmp(&a)))
            else {
                continue;
            };
            let value = v.d[bin];
            // its evidence is the strongest of its unmasked bins (masked ones hold 0): the
            // reference's windows hold as many unmasked bins
            let unmasked = free.iter().filter(|&&k| !v.masked[k]).count();
            let reference = self.reference(unmasked);
            if reference.maxima.is_empty() {
                continue;
            }
            terms.push(TermReading {
                window: w,
                bin,
                value,
                p: reference.p(value),
                null_size: reference.independent,
            });
        }
        let fisher = -2.0 * terms.iter().map(|r| r.p.ln()).sum::<f64>();
        let statistic_db = terms
            .iter()
            .map(|r| match r.window.term {
                Term::Harmonic(_) => r.value,
                Term::Sideband(_) => 0.5 * r.value,
            })
            .sum();
        BandReading {
            p: chi2_sf_even(fisher, 2 * terms.len()),
            fisher,
            terms,
            statistic_db,
        }
    }
}

/// Read template `t` in `v` (its reference off `t`'s own lattice).
#[cfg(test)]
pub(crate) fn read_band(v: &BandView, t: &Template) -> BandReading {
    LineTest::new(v, &t.lattice(v.top_hz), t.fr).read(t)
}

/// The runs of `clear` bins of `d` (maximal stretches), each with its `masked` bins left out:
/// a masked bin holds no evidence in a line's window and none in a reference window, and a
/// shaft comb masked at every order must not cut the reference into stretches shorter than a
/// widened line's window.
fn clear_runs(d: &[f64], clear: &[bool], masked: &[bool]) -> Vec<Vec<f64>> {
    let mut runs = Vec::new();
    let mut k = 0;
    while k < clear.len() {
        if !clear[k] {
            k += 1;
            continue;
        }
        let mut run = Vec::new();
        while k < clear.len() && clear[k] {
            if !masked[k] {
                run.push(d[k]);
            }
            k += 1;
        }
        if !run.is_empty() {
            runs.push(run);
        }
    }
    runs
}

/// The maxima of every window of `width` consecutive values lying wholly in one of `runs`
/// (sorted ascending), and the maxima of the non-overlapping ones (each run cut into windows
/// from its start).
fn clear_window_maxima(runs: &[Vec<f64>], width: usize) -> (Vec<f64>, Vec<f64>) {
    let mut maxima = Vec::new();
    let mut spaced = Vec::new();
    for run in runs {
        if width == 0 || run.len() < width {
            continue;
        }
        spaced.extend(
            run.chunks_exact(width)
                .map(|c| c.iter().copied().fold(0.0, f64::max)),
        );
        // sliding maximum over the run (monotone deque)
        let mut q: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
        for (i, &x) in run.iter().enumerate() {
            while q.back().is_some_and(|&j| run[j] <= x) {
                q.pop_back();
            }
            q.push_back(i);
            if q.front().is_some_and(|&j| j + width <= i) {
                q.pop_front();
            }
            if i + 1 >= width
                && let Some(&j) = q.front()
            {
                maxima.push(run[j]);
            }
        }
    }
    maxima.sort_by(f64::total_cmp);
    (maxima, spaced)
}

/// `P(χ² ≥ x)` for `dof` (even) degrees of freedom: `e^{−x/2} Σ_{i<dof/2} (x/2)^i / i!`; 1 for
/// no degrees of freedom.
pub(crate) fn chi2_sf_even(x: f64, dof: usize) -> f64 {
    let m = dof / 2;
    if m == 0 || x.is_nan() || x <= 0.0 {
        return 1.0;
    }
    let h = 0.5 * x;
    let mut term = 1.0;
    let mut sum = 1.0;
    for i in 1..m {
        term *= h / i as f64;
        sum += term;
    }
    ((-h).exp() * sum).clamp(0.0, 1.0)
}

/// `P(X ≥ k)` for `X` binomial with `n` trials of probability `q`: the chance that at least `k`
/// of `n` positions hold a line when each does with probability `q`, independently.
pub(crate) fn binomial_sf(n: usize, k: usize, q: f64) -> f64 {
    if k == 0 {
        return 1.0;
    }
    if k > n {
        return 0.0;
    }
    let q = q.clamp(0.0, 1.0);
    let mut c = 1.0; // C(n, i)
    let mut sum = 0.0;
    for i in 0..=n {
        if i >= k {
            sum += c * q.powi(i as i32) * (1.0 - q).powi((n - i) as i32);
        }
        c = c * (n - i) as f64 / (i + 1) as f64;
    }
    sum.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The binomial tail against its closed forms.
    #[test]
    fn binomial_tail_matches_closed_forms() {
        assert_eq!(binomial_sf(6, 0, 0.3), 1.0);
        assert_eq!(binomial_sf(6, 7, 0.3), 0.0);
        assert!((binomial_sf(6, 6, 0.3) - 0.3f64.powi(6)).abs() < 1e-15);
        assert!((binomial_sf(6, 1, 0.3) - (1.0 - 0.7f64.powi(6))).abs() < 1e-15);
        // P(X ≥ 4), n = 6, q = 0.1: 15·q⁴(1−q)² + 6·q⁵(1−q) + q⁶
        let want = 15.0 * 1e-4 * 0.81 + 6.0 * 1e-5 * 0.9 + 1e-6;
        assert!((binomial_sf(6, 4, 0.1) - want).abs() < 1e-15);
    }

    /// With more than 10⁴ non-overlapping clear windows the reference's edge `1/(n' + 1)` is
    /// below the line floor: a value beyond every window gets the edge, not a panic.
    #[test]
    fn a_reference_of_many_windows_gives_its_edge_beyond_them() {
        let n = 20_000;
        let spaced: Vec<f64> = (0..n).map(|i| (i % 997) as f64 * 1e-3).collect();
        let r = Reference::new(spaced.clone(), spaced);
        let p = r.p(1e3);
        assert!(p > 0.0 && p <= 1.0 / (1.0 + n as f64), "{p}");
    }

    #[test]
    fn chi2_survival_matches_closed_forms() {
        // 2 dof: e^{-x/2}
        assert!((chi2_sf_even(4.0, 2) - (-2.0f64).exp()).abs() < 1e-15);
        // 10 dof at 18.307: 0.05 (tables)
        assert!((chi2_sf_even(18.307, 10) - 0.05).abs() < 1e-4);
        assert_eq!(chi2_sf_even(0.0, 6), 1.0);
        assert_eq!(chi2_sf_even(5.0, 0), 1.0);
    }

    #[test]
    fn sliding_maxima_and_independent_count() {
        let d = [0.0, 3.0, 0.0, 1.0, 5.0, 0.0, 2.0, 0.0];
        let clear = [true, true, true, true, false, true, true, true];
        let runs = clear_runs(&d, &clear, &[false; 8]);
        let (m, spaced) = clear_window_maxima(&runs, 2);
        // run 0..4: windows [0,3], [3,0], [0,1]; run 5..8: [0,2], [2,0]
        assert_eq!(m, vec![1.0, 2.0, 2.0, 3.0, 3.0]);
        // non-overlapping: [0,3], [0,1]; [0,2]
        assert_eq!(spaced, vec![3.0, 1.0, 2.0]);
    }

    /// Masked bins are left out of a run without ending it: a window of `w` unmasked bins spans
    /// them, as a line's window holding masked bins reads its unmasked ones.
    #[test]
    fn masked_bins_are_skipped_not_run_ends() {
        let d = [0.0, 3.0, 0.0, 1.0, 0.0, 2.0, 4.0, 0.0];
        let clear = [true, true, true, true, true, true, true, false];
        let masked = [false, false, true, false, true, false, false, false];
        let runs = clear_runs(&d, &clear, &masked);
        assert_eq!(runs, vec![vec![0.0, 3.0, 1.0, 2.0, 4.0]]);
        let (m, spaced) = clear_window_maxima(&runs, 2);
        assert_eq!(m, vec![2.0, 3.0, 3.0, 4.0]);
        assert_eq!(spaced, vec![3.0, 2.0]);
    }
}
