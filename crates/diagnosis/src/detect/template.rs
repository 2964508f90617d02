//! A fault hypothesis's lines as the detector reads them: the windows of its harmonics and
//! distinguishing sidebands at a speed, the lattice of lines the fault puts in the envelope
//! spectrum (kept out of its own null), and the family a confirmed fault explains in others.

use crate::{Hypothesis, SLIP_MAX, SPEED_OFFSET, SPEED_TOL};
use bearing_model::FaultOrders;

/// Shaft-rate shifts `j·fr` (|j| up to this) of a fault's harmonics kept out of its lines'
/// references (`Template::lattice`).
pub const LATTICE_SHAFT_ORDERS: i32 = 3;
/// Shaft-rate shifts `j·fr` (|j| up to this) of a confirmed fault's harmonics that explain other
/// hypotheses' lines (`Template::family`).
pub const FAMILY_SHAFT_ORDERS: i32 = 8;

/// Which sidebands a template reads around its fundamental.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sidebands {
    /// None (outer race: the defect does not move through the load zone).
    None,
    /// `f₁ ± fr` (inner race: the defect turns with the shaft through the load zone).
    Shaft,
    /// `f₁ ± FTF` (ball: the ball turns with the cage through the load zone).
    Cage,
}

/// What a line of the template is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Term {
    /// Harmonic k of the fault rate.
    Harmonic(usize),
    /// The lower (−) or upper (+) distinguishing sideband of harmonic 1.
    Sideband(i8),
}

/// One line of the template: what it is, its kinematic frequency and the window it is searched
/// in, Hz.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Window {
    pub term: Term,
    pub expected_hz: f64,
    pub lo_hz: f64,
    pub hi_hz: f64,
}

/// A hypothesis's line template at the speed used.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Template {
    pub hypothesis: Hypothesis,
    /// Kinematic fundamental at the speed used, Hz.
    pub fault_hz: f64,
    /// Window of the fundamental, as ratios of the kinematic rate (slip, speed tolerance).
    pub ratio: (f64, f64),
    pub harmonics: usize,
    pub sidebands: Sidebands,
    /// Shaft rate, Hz.
    pub fr: f64,
    /// Cage rate, Hz.
    pub ftf_hz: f64,
    /// Relative speed uncertainty the windows were widened by.
    pub speed_slack: f64,
}

impl Template {
    pub(crate) fn new(h: Hypothesis, o: &FaultOrders, fr: f64, harmonics: usize) -> Self {
        let order = match h {
            Hypothesis::Inner => o.bpfi,
            Hypothesis::Outer => o.bpfo,
            Hypothesis::Ball => o.ball_defect,
        };
        Self {
            hypothesis: h,
            fault_hz: order * fr,
            ratio: window_ratio(h, o),
            harmonics,
            sidebands: match h {
                Hypothesis::Outer => Sidebands::None,
                Hypothesis::Inner => Sidebands::Shaft,
                Hypothesis::Ball => Sidebands::Cage,
            },
            fr,
            ftf_hz: o.ftf * fr,
            speed_slack: 0.0,
        }
    }

    /// This template at `rho` × the speed (every rate scaled).
    pub(crate) fn at_speed(&self, rho: f64) -> Self {
        Self {
            fault_hz: self.fault_hz * rho,
            fr: self.fr * rho,
            ftf_hz: self.ftf_hz * rho,
            ..*self
        }
    }

    /// This template with its windows widened by a relative speed uncertainty `u`: the
    /// fundamental's window to `[lo (1 − u), hi (1 + u)]`, the sidebands' spacings by `± u`.
    pub(crate) fn widened(&self, u: f64) -> Self {
        Self {
            ratio: (self.ratio.0 * (1.0 - u), self.ratio.1 * (1.0 + u)),
            speed_slack: u,
            ..*self
        }
    }

    /// Spacing of the distinguishing sidebands, Hz.
    pub(crate) fn sideband_spacing(&self) -> Option<f64> {
        match self.sidebands {
            Sidebands::None => None,
            Sidebands::Shaft => Some(self.fr),
            Sidebands::Cage => Some(self.ftf_hz),
        }
    }

    /// The harmonics' windows `k·F·[lo, hi]`, k = 1..=K + 1, Hz: where this fault's own lines
    /// lie (a comb of shaft orders or mains multiples is recognised outside them).
    pub(crate) fn harmonic_windows(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        (1..=self.harmonics + 1).map(|k| {
            let e = k as f64 * self.fault_hz;
            (e * self.ratio.0, e * self.ratio.1)
        })
    }

    /// The windows of the template's lines, each widened by `pad_hz` on both sides: harmonic k
    /// over `k·F·[lo, hi]`, the sidebands over `F·[lo, hi] ± spacing` (a cage sideband's
    /// spacing slipping with the ball line).
    pub(crate) fn windows(&self, pad_hz: f64) -> Vec<Window> {
        let (lo, hi) = self.ratio;
        let mut out: Vec<Window> = (1..=self.harmonics)
            .map(|k| {
                let e = k as f64 * self.fault_hz;
                Window {
                    term: Term::Harmonic(k),
                    expected_hz: e,
                    lo_hz: e * lo - pad_hz,
                    hi_hz: e * hi + pad_hz,
                }
            })
            .collect();
        if let Some(s) = self.sideband_spacing() {
            for sign in [-1i8, 1] {
                let sg = f64::from(sign);
                let slack = self.speed_slack * s;
                let (a, b) = match self.sidebands {
                    Sidebands::Cage => {
                        ((self.fault_hz + sg * s) * lo, (self.fault_hz + sg * s) * hi)
                    }
                    _ => (
                        self.fault_hz * lo + sg * s - slack,
                        self.fault_hz * hi + sg * s + slack,
                    ),
                };
                out.push(Window {
                    term: Term::Sideband(sign),
                    expected_hz: self.fault_hz + sg * s,
                    lo_hz: a.min(b) - pad_hz,
                    hi_hz: a.max(b) + pad_hz,
                });
            }
        }
        out.retain(|w| w.lo_hz > 0.0);
        out
    }

    /// The lattice of lines this fault puts in the envelope spectrum, as windows `[low, high]`
    /// Hz: harmonics `k·F` (k = 1..=K + 1, below `top_hz`) over their slip windows, shifted by `j·fr`
    /// (|j| ≤ [`LATTICE_SHAFT_ORDERS`]: the load zone modulates an inner-race or ball defect at
    /// the shaft or cage rate, and a shaft's unbalance or runout modulates any fault's impacts
    /// at fr) and for a ball by `j·FTF` (|j| ≤ 2). The reference of a line of this template is
    /// read away from all of them: with a fault present, its own lattice would fill it.
    pub(crate) fn lattice(&self, top_hz: f64) -> Vec<(f64, f64)> {
        let (lo, hi) = self.ratio;
        let shaft = LATTICE_SHAFT_ORDERS;
        let mut out = Vec::new();
        // harmonics 1..=K + 1 only: the higher ones, with their shifts, would cover a band's
        // whole envelope spectrum and leave no reference (a fault's harmonics beyond them that
        // stand in the reference make its lines read less extreme: conservative)
        let top_k = (self.harmonics + 1)
            .min(((top_hz / (self.fault_hz * lo).max(f64::MIN_POSITIVE)) as usize).max(1));
        for k in 1..=top_k {
            let e = k as f64 * self.fault_hz;
            let (a, b) = (e * lo, e * hi);
            for j in -shaft..=shaft {
                let s = f64::from(j) * self.fr;
                let slack = self.speed_slack * s.abs();
                out.push((a + s - slack, b + s + slack));
            }
            if self.sidebands == Sidebands::Cage {
                for j in [-2i32, -1, 1, 2] {
                    let s = f64::from(j) * self.ftf_hz;
                    out.push(((e + s) * lo, (e + s) * hi));
                }
            }
        }
        out.retain(|&(l, h)| h > 0.0 && h > l);
        out
    }

    /// The number of rolling elements `Z` a race's template implies (`BPFO = Z·FTF`,
    /// `BPFI = Z·(fr − FTF)`); `None` for a ball, or a template without a cage rate.
    pub(crate) fn rolling_elements(&self) -> Option<f64> {
        let z = match self.hypothesis {
            Hypothesis::Outer if self.ftf_hz > 0.0 => self.fault_hz / self.ftf_hz,
            Hypothesis::Inner if self.ftf_hz > 0.0 && self.fr > self.ftf_hz => {
                self.fault_hz / (self.fr - self.ftf_hz)
            }
            _ => return None,
        }
        .round();
        (z >= 1.0).then_some(z)
    }

    /// This template's line family around the fundamental `f1` it found, as (frequency,
    /// half-width) pairs, for masking when this fault is confirmed: `k·f₁ ± j·fr` (k ≤ 6,
    /// |j| ≤ [`FAMILY_SHAFT_ORDERS`]; k = 0 for the inner race: the load zone's shaft lines),
    /// for a ball also `k·f₁ ± j·FTF` (|j| ≤ 2) and the cage harmonics, each over the cage's slip
    /// window (the cage slips on its own; BPFO = n·FTF is one of them). A fault's impacts
    /// modulated at fr put lines at every `k·f₁ + j·fr` the modulation reaches; on a bearing
    /// with `BPFI + BPFO = n·fr` the two races' families then meet (`BPFI = n·fr − BPFO`:
    /// an outer-race fault's `BPFO + 2fr` lies 2 % above a UC204's BPFI). `f₁` is read to the
    /// nearest bin of `df` Hz, so `k·f₁` is known to `± k·df/2`: each line's half-width.
    pub(crate) fn family(&self, f1: f64, df: f64) -> Vec<(f64, f64)> {
        let fr = self.fr;
        let shaft = FAMILY_SHAFT_ORDERS;
        let mut v: Vec<(f64, f64)> = Vec::new();
        let k0 = if self.hypothesis == Hypothesis::Inner {
            0
        } else {
            1
        };
        for k in k0..=6 {
            for j in -shaft..=shaft {
                v.push((k as f64 * f1 + f64::from(j) * fr, 0.5 * k as f64 * df));
            }
        }
        match self.hypothesis {
            Hypothesis::Outer | Hypothesis::Inner => {}
            Hypothesis::Ball => {
                let ftf = self.ftf_hz * f1 / self.fault_hz.max(f64::MIN_POSITIVE);
                for k in 1..=self.harmonics {
                    for j in [-2i32, -1, 1, 2] {
                        v.push((k as f64 * f1 + f64::from(j) * ftf, 0.5 * k as f64 * df));
                    }
                }
                let (lo, hi) = cage_window();
                let top = (self.harmonics as f64 + 1.0) * f1;
                let mut j = 1.0;
                while j * self.ftf_hz * lo <= top && self.ftf_hz > 0.0 {
                    let (a, b) = (j * self.ftf_hz * lo, j * self.ftf_hz * hi);
                    v.push((0.5 * (a + b), 0.5 * (b - a)));
                    j += 1.0;
                }
            }
        }
        v.retain(|(f, _)| *f > 0.0);
        v
    }
}

/// The cage's slip window `[lo, hi]` (found / kinematic): slip of up to [`SLIP_MAX`] lowers it,
/// the ~[`SPEED_OFFSET`] speed-reference offset raises it, ± [`SPEED_TOL`] for the speed.
pub(crate) fn cage_window() -> (f64, f64) {
    (1.0 - SLIP_MAX - SPEED_TOL, 1.0 + SPEED_OFFSET + SPEED_TOL)
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
        Hypothesis::Outer | Hypothesis::Ball => cage_window(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::HARMONICS;

    /// A confirmed fault's family, masked before a second fault is tested: `f₁` is read to the
    /// nearest bin, so its 3rd harmonic (and that harmonic's shaft sidebands) is placed to
    /// ± 1.5 bins — and no wider.
    #[test]
    fn a_family_s_harmonics_are_placed_to_their_fundamental_s_bin() {
        let o = bearing_model::BearingSpec::parse("6205").unwrap().orders;
        let (fr, df) = (30.0, 1.0);
        let t = Template::new(Hypothesis::Inner, &o, fr, HARMONICS);
        let f1 = t.fault_hz;
        let family = t.family(f1, df);
        let covers = |f: f64| family.iter().any(|&(c, h)| (f - c).abs() <= h.max(1e-9));
        // the 3rd harmonic and its −2fr sideband, read with f₁ half a bin off
        assert!(covers(3.0 * (f1 + 0.5 * df) - 0.01));
        assert!(covers(3.0 * (f1 - 0.5 * df) - 2.0 * fr + 0.01));
        assert!(!covers(3.0 * f1 + 2.0 * df));
    }
}
