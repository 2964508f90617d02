//! Golden-section search: the workspace's one copy (the Laguerre pole search here, the closed
//! loop's effect fits in `close-loop`).

/// 1/φ = (√5 − 1)/2, the golden-section interval ratio (also the closed loop's parabolic
/// refinement's fallback step, `1 − INV_PHI`).
pub const INV_PHI: f64 = 0.618_033_988_749_894_9;

/// Golden-section search for the maximum of a unimodal `f` on `[lo, hi]` (`iters` shrink
/// steps); returns `(x, f(x))` of the better of the two final interior points (the upper one on
/// a tie).
pub fn golden_max(mut f: impl FnMut(f64) -> f64, lo: f64, hi: f64, iters: usize) -> (f64, f64) {
    let (mut a, mut b) = (lo.min(hi), lo.max(hi));
    let mut c = b - INV_PHI * (b - a);
    let mut d = a + INV_PHI * (b - a);
    let mut fc = f(c);
    let mut fd = f(d);
    for _ in 0..iters {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - INV_PHI * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + INV_PHI * (b - a);
            fd = f(d);
        }
    }
    if fc > fd { (c, fc) } else { (d, fd) }
}

/// Golden-section search for the minimum of `f` on `[lo, hi]`; returns `(x, f(x))`.
pub fn golden_min(mut f: impl FnMut(f64) -> f64, lo: f64, hi: f64, iters: usize) -> (f64, f64) {
    let (x, v) = golden_max(|x| -f(x), lo, hi, iters);
    (x, -v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_extremum_of_a_parabola() {
        let (x, v) = golden_min(|x| (x - 0.3).powi(2) + 1.0, -1.0, 1.0, 60);
        assert!((x - 0.3).abs() < 1e-6 && (v - 1.0).abs() < 1e-12, "{x} {v}");
        let (x, _) = golden_max(|x| -(x + 0.5).powi(2), 1.0, -1.0, 60);
        assert!((x + 0.5).abs() < 1e-6, "bounds in either order: {x}");
    }
}
