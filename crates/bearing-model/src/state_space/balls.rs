//! Ball kinematics of [`BearingModel`]: each ball's direction (cage angle plus slip), the
//! race and ball spalls' drops and the time-only [`BallFrame`] built from them.

use super::angles::{floor_i64, sin_cos, wrap, wrap_fast};
use super::{BallFrame, BearingModel, MAX_BALLS, SLIP_REVS};
use std::f64::consts::{PI, TAU};

impl BearingModel {
    /// Visit every ball: `(j, cos θ_j, sin θ_j, a_j)` with `θ_j = θ_c(t) + a_j`, `a_j` the
    /// ball's angular offset from ball 0's nominal position (2πj/n plus slip).
    #[inline(always)]
    pub(super) fn for_each_ball(&self, t: f64, mut f: impl FnMut(usize, f64, f64, f64)) {
        let th = self.cage_angle(t);
        let (s0, c0) = sin_cos(th);
        self.for_each_ball_in_cage(th, |j, ca, sa, a| {
            f(j, c0 * ca - s0 * sa, s0 * ca + c0 * sa, a)
        });
    }

    /// What the slip offsets of all balls depend on at cage angle `th`: ball 0's revolution
    /// count `⌊b⌋` and the first ball `j*` whose count is one more (`frac(b) ≥ 1 − j/n` for
    /// `j ≥ j*`, see [`Self::for_each_ball_in_cage`]). `(0, 0)` without slip.
    #[inline(always)]
    fn slip_state(&self, th: f64) -> (i64, usize) {
        if self.slip.is_none() {
            return (0, 0);
        }
        let b = (th - self.slip_switch) * (1.0 / TAU);
        let r0 = floor_i64(b);
        let fr = b - r0 as f64;
        let first = self
            .slip_threshold
            .iter()
            .take_while(|&&thr| fr < thr)
            .count();
        (r0, first)
    }

    /// Visit every ball in the cage frame (rotated by `−θ_c`): `(j, cos a_j, sin a_j, a_j)`.
    ///
    /// Slip: ball `j`'s offset is redrawn when `θ_c + 2πj/n` crosses `slip_switch` (mod 2π),
    /// i.e. its revolution count is `⌊b + j/n⌋ = ⌊b⌋ + [frac(b) ≥ 1 − j/n]` with
    /// `b = (θ_c − slip_switch)/2π`: one floor per evaluation instead of one per ball.
    #[inline(always)]
    fn for_each_ball_in_cage(&self, th: f64, mut f: impl FnMut(usize, f64, f64, f64)) {
        match &self.slip {
            None => {
                for (j, (&(ca, sa), &a)) in
                    self.ball_offsets.iter().zip(&self.ball_nominal).enumerate()
                {
                    f(j, ca, sa, a);
                }
            }
            Some(tab) => {
                let b = (th - self.slip_switch) * (1.0 / TAU);
                let r0 = floor_i64(b);
                let fr = b - r0 as f64;
                for (j, (&a, &thr)) in self
                    .ball_nominal
                    .iter()
                    .zip(&self.slip_threshold)
                    .enumerate()
                {
                    let rev = r0 + i64::from(fr >= thr);
                    let k = (rev & (SLIP_REVS as i64 - 1)) as usize;
                    let (e, ca, sa) = tab[j * SLIP_REVS + k];
                    f(j, ca, sa, a + e);
                }
            }
        }
    }

    /// Per-evaluation fault phases: the cage angle relative to each race spall's entry edge
    /// (wrapped once), and the ball spall's spin angle. `NaN` = spall absent or not yet there.
    #[inline(always)]
    pub(super) fn fault_phases(&self, t: f64) -> [f64; 3] {
        let th = self.cage_angle(t);
        let mut ph = [f64::NAN; 3];
        if let Some(p) = &self.outer {
            if t >= p.onset {
                ph[0] = wrap(th - p.angle0);
            }
        }
        if let Some(p) = &self.inner {
            if t >= p.onset {
                ph[1] = wrap(th - p.angle0 - self.omega_s * t);
            }
        }
        if let Some((po, _)) = &self.ball {
            if t >= po.onset {
                ph[2] = wrap(po.angle0 + self.omega_spin * t);
            }
        }
        ph
    }

    /// Total spall drop β_j(t) for ball `j` with offset `a_j` (eqs. 2.16–2.24), given the
    /// phases of [`Self::fault_phases`].
    #[inline(always)]
    pub(super) fn spall_drop(&self, ph: &[f64; 3], j: usize, a: f64) -> f64 {
        let mut drop = 0.0;
        if let Some(p) = &self.outer {
            if !ph[0].is_nan() {
                drop += p.drop(wrap_fast(ph[0] + a));
            }
        }
        if let Some(p) = &self.inner {
            if !ph[1].is_nan() {
                drop += p.drop(wrap_fast(ph[1] + a));
            }
        }
        if j == 0 && !ph[2].is_nan() {
            if let Some((po, pi)) = &self.ball {
                drop += po.drop(ph[2]) + pi.drop(wrap_fast(ph[2] + PI));
            }
        }
        drop
    }

    #[inline(always)]
    fn has_faults(&self) -> bool {
        self.inner.is_some() || self.outer.is_some() || self.ball.is_some()
    }

    /// The time-only part of the model at `t` (ball directions, gaps, harmonic force).
    #[inline]
    pub fn frame(&self, t: f64) -> BallFrame {
        let mut f = BallFrame::default();
        self.frame_into(t, &mut f);
        f
    }

    /// [`Self::frame`] written into `f` (no 0.8 kB copy; only the first `n_balls` entries
    /// are touched). Bit-identical to [`Self::frame`].
    #[inline]
    pub fn frame_into(&self, t: f64, f: &mut BallFrame) {
        f.hx = 0.0;
        f.hy = 0.0;
        let clearance = self.clearance;
        let th = self.cage_angle(t);
        (f.s0, f.c0) = sin_cos(th);
        let key = (self.id, self.slip_state(th));
        if f.n != self.n_balls || (f.cache.0, (f.cache.1, f.cache.2)) != key {
            self.for_each_ball_in_cage(th, |j, ca, sa, a| {
                f.ca[j] = ca;
                f.sa[j] = sa;
                f.off[j] = a;
            });
            f.n = self.n_balls;
            f.cache = (key.0, key.1.0, key.1.1);
        }
        f.gap[..self.n_balls].fill(clearance);
        let offs = &f.off;
        if self.has_faults() {
            // Each spall's drop is added only to the balls that can be inside it; every other
            // ball's drop is exactly 0 (see `spall_candidates`), so the gaps are bit-identical
            // to summing every spall over every ball (unit test).
            let ph = self.fault_phases(t);
            let mut drop = [0.0; MAX_BALLS];
            let mut touched = 0u32;
            for (k, p) in [(0, &self.outer), (1, &self.inner)] {
                if let Some(p) = p {
                    if !ph[k].is_nan() {
                        let mut mask = self.spall_candidates(ph[k], p.width_rad);
                        touched |= mask;
                        while mask != 0 {
                            let j = mask.trailing_zeros() as usize;
                            mask &= mask - 1;
                            drop[j] += p.drop(wrap_fast(ph[k] + offs[j]));
                        }
                    }
                }
            }
            if let Some((po, pi)) = &self.ball {
                if !ph[2].is_nan() {
                    drop[0] += po.drop(ph[2]) + pi.drop(wrap_fast(ph[2] + PI));
                    touched |= 1;
                }
            }
            while touched != 0 {
                let j = touched.trailing_zeros() as usize;
                touched &= touched - 1;
                f.gap[j] = clearance + drop[j];
            }
        }
        for h in &self.harmonics {
            let (sn, cs) = (h.order as f64 * self.omega_s * t + h.phase_rad).sin_cos();
            f.hx += h.amplitude_n * cs;
            f.hy += h.amplitude_n * sn;
        }
    }

    /// Bit set of the balls that can be inside a race spall of angular width `width` at phase
    /// `ph ∈ [0, 2π)` (from [`Self::fault_phases`]). Ball `j` is inside iff
    /// `wrap(ph + a_j) < width` with `a_j = j·s + ε_j`, `s = 2π/n`, `|ε_j| ≤ f·s` (`f` the slip
    /// fraction, 0 without slip) and `width < s` (validated), i.e. (mod n)
    /// `j ∈ [q − f, q + width/s + f)` with `q = (2π − ph)/s`. The candidates
    /// `⌊q − f − 10⁻⁹⌋ ..= ⌊q + width/s + f + 10⁻⁹⌋` cover it (the 10⁻⁹ spacing absorbs
    /// rounding): usually one or two balls.
    #[inline(always)]
    fn spall_candidates(&self, ph: f64, width: f64) -> u32 {
        const MARGIN: f64 = 1e-9;
        let n = self.n_balls as i64;
        let per = self.n_balls as f64 * (1.0 / TAU);
        let q = (TAU - ph) * per;
        let lo = floor_i64(q - self.slip_fraction - MARGIN);
        let hi = floor_i64(q + width * per + self.slip_fraction + MARGIN).min(lo + n - 1);
        // q ∈ (0, n] and f ≤ 0.1, so lo ∈ [−1, n]
        let mut j = if lo < 0 {
            lo + n
        } else if lo >= n {
            lo - n
        } else {
            lo
        };
        let mut mask = 0u32;
        for _ in lo..=hi {
            mask |= 1 << j;
            j += 1;
            if j == n {
                j = 0;
            }
        }
        mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FaultClass, Scenario, Slip};

    /// The frame as first written: every spall summed over every ball, no candidate filter.
    fn gaps_all_balls(m: &BearingModel, t: f64) -> [f64; MAX_BALLS] {
        let mut gap = [m.clearance; MAX_BALLS];
        let ph = m.fault_phases(t);
        m.for_each_ball(t, |j, _, _, a| {
            gap[j] += m.spall_drop(&ph, j, a);
        });
        gap
    }

    #[test]
    fn candidate_filter_gives_bit_identical_gaps_and_cage_frame_the_same_directions() {
        for (class, size_in, slip) in [
            (FaultClass::InnerOuterBall, 0.021, 0.1),
            (FaultClass::InnerOuter, 0.007, 0.01),
            (FaultClass::Outer, 0.014, 0.0),
        ] {
            let mut sc = Scenario::cwru(class, size_in, 1797.0).unwrap();
            sc.spec.slip = if slip > 0.0 {
                Slip::Random { fraction: slip }
            } else {
                Slip::Off
            };
            let m = sc.model().unwrap();
            let mut f = BallFrame::default();
            let mut in_spall = 0;
            for i in 0..200_000 {
                let t = -0.05 + i as f64 * 1.37e-6;
                m.frame_into(t, &mut f);
                let g = gaps_all_balls(&m, t);
                let mut dirs = [(0.0, 0.0); MAX_BALLS];
                m.for_each_ball(t, |j, c, s, _| dirs[j] = (c, s));
                for j in 0..m.n_balls {
                    assert_eq!(f.gap[j].to_bits(), g[j].to_bits(), "{class} t {t} ball {j}");
                    let c = f.c0 * f.ca[j] - f.s0 * f.sa[j];
                    let s = f.s0 * f.ca[j] + f.c0 * f.sa[j];
                    assert_eq!(
                        (c.to_bits(), s.to_bits()),
                        (dirs[j].0.to_bits(), dirs[j].1.to_bits())
                    );
                    in_spall += usize::from(g[j] != m.clearance);
                }
            }
            assert!(
                in_spall > 1000,
                "{class}: the test crosses spalls ({in_spall})"
            );
        }
    }

    #[test]
    fn slip_revolution_count_is_the_per_ball_floor() {
        let sc = Scenario::cwru(FaultClass::None, 0.007, 1797.0).unwrap();
        let m = sc.model().unwrap();
        let n = m.n_balls as f64;
        for i in 0..100_000 {
            let th = -3.0 + i as f64 * 1.1e-3;
            let mut got = [0.0; MAX_BALLS];
            m.for_each_ball_in_cage(th, |j, _, _, a| got[j] = a);
            let tab = m.slip.as_ref().unwrap();
            for j in 0..m.n_balls {
                let a = TAU * j as f64 / n;
                let x = (th + a - m.slip_switch) / TAU;
                // away from the switching instant (within rounding) both counts agree
                if (x - x.round()).abs() > 1e-12 {
                    let k = (x.floor() as i64 & (SLIP_REVS as i64 - 1)) as usize;
                    assert_eq!(got[j], a + tab[j * SLIP_REVS + k].0, "th {th} ball {j}");
                }
            }
        }
    }
}
