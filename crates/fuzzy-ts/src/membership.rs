//! Gaussian membership functions and the seven linguistic terms NH … PH (section 5.3).
//!
//! Each universe [lo, hi] carries seven Gaussian sets with centres evenly spaced from lo to hi
//! (NH at lo, Z at the midpoint, PH at hi) and a common width σ = Δ / (2√(2 ln 2)), Δ the centre
//! spacing, so neighbouring sets cross at membership 0.5. Inputs are saturated to [lo, hi]
//! before evaluation, so the outer sets (NH, PH) extend to ±∞ as shoulders.

use crate::error::{FuzzyError, Result};
use serde::{Deserialize, Serialize};

/// The seven linguistic terms of Table 5.1, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Term {
    /// Negative high.
    NH,
    /// Negative medium.
    NM,
    /// Negative low.
    NL,
    /// Zero.
    Z,
    /// Positive low.
    PL,
    /// Positive medium.
    PM,
    /// Positive high.
    PH,
}

impl Term {
    /// All terms, NH first.
    pub const ALL: [Term; 7] = [
        Term::NH,
        Term::NM,
        Term::NL,
        Term::Z,
        Term::PL,
        Term::PM,
        Term::PH,
    ];

    /// Position 0 (NH) … 6 (PH).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Signed level −3 (NH) … +3 (PH).
    pub fn level(self) -> i32 {
        self as i32 - 3
    }

    /// The term at signed level −3..=3 (saturating outside).
    pub fn from_level(level: i32) -> Term {
        Term::ALL[(level.clamp(-3, 3) + 3) as usize]
    }

    /// Parse "NH", "NM", … (as printed in Table 5.1).
    pub fn parse(s: &str) -> Option<Term> {
        Term::ALL.into_iter().find(|t| t.name() == s)
    }

    /// The printed name.
    pub fn name(self) -> &'static str {
        ["NH", "NM", "NL", "Z", "PL", "PM", "PH"][self.index()]
    }
}

/// A Gaussian membership function μ(x) = exp(−(x − c)² / (2σ²)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gaussian {
    center: f64,
    sigma: f64,
}

impl Gaussian {
    /// Centre c (finite) and width σ > 0 (finite).
    pub fn new(center: f64, sigma: f64) -> Result<Self> {
        if !center.is_finite() {
            return Err(FuzzyError::InvalidParameter {
                which: "center",
                value: center,
            });
        }
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err(FuzzyError::InvalidParameter {
                which: "sigma",
                value: sigma,
            });
        }
        Ok(Self { center, sigma })
    }
    /// Centre c.
    pub fn center(&self) -> f64 {
        self.center
    }
    /// Width σ.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }
    /// Degree of membership in [0, 1]; NaN input gives 0.
    #[inline]
    pub fn degree(&self, x: f64) -> f64 {
        let d = (x - self.center) / self.sigma;
        let m = (-0.5 * d * d).exp();
        if m.is_nan() { 0.0 } else { m }
    }
}

/// Seven Gaussian terms NH … PH over a universe [lo, hi].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TermSet {
    lo: f64,
    hi: f64,
    sets: [Gaussian; 7],
}

impl TermSet {
    /// Evenly spaced terms over [lo, hi] (finite, lo < hi), neighbours crossing at 0.5.
    pub fn uniform(lo: f64, hi: f64) -> Result<Self> {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(FuzzyError::InvalidRange { lo, hi });
        }
        let spacing = (hi - lo) / 6.0;
        let sigma = spacing / (2.0 * (2.0 * std::f64::consts::LN_2).sqrt());
        let mut sets = [Gaussian { center: 0.0, sigma }; 7];
        for (i, s) in sets.iter_mut().enumerate() {
            *s = Gaussian::new(lo + spacing * i as f64, sigma)?;
        }
        Ok(Self { lo, hi, sets })
    }
    /// Symmetric universe [−half_width, half_width].
    pub fn symmetric(half_width: f64) -> Result<Self> {
        Self::uniform(-half_width, half_width)
    }
    /// The dissertation's error universe, [−0.3, 0.3] (section 5.3).
    pub fn dissertation_error() -> Self {
        Self::fixed(0.3)
    }
    /// The dissertation's change-of-error universe, [−0.1, 0.1].
    pub fn dissertation_change_of_error() -> Self {
        Self::fixed(0.1)
    }
    /// The dissertation's output (J_f) universe, [−0.08, 0.08].
    pub fn dissertation_output() -> Self {
        Self::fixed(0.08)
    }
    fn fixed(h: f64) -> Self {
        let spacing = 2.0 * h / 6.0;
        let sigma = spacing / (2.0 * (2.0 * std::f64::consts::LN_2).sqrt());
        let mut sets = [Gaussian { center: 0.0, sigma }; 7];
        for (i, s) in sets.iter_mut().enumerate() {
            s.center = -h + spacing * i as f64;
        }
        Self {
            lo: -h,
            hi: h,
            sets,
        }
    }
    /// Lower end of the universe.
    pub fn lo(&self) -> f64 {
        self.lo
    }
    /// Upper end of the universe.
    pub fn hi(&self) -> f64 {
        self.hi
    }
    /// The Gaussian of one term.
    pub fn set(&self, t: Term) -> Gaussian {
        self.sets[t.index()]
    }
    /// Centre of one term.
    pub fn center(&self, t: Term) -> f64 {
        self.sets[t.index()].center
    }
    /// Degrees of membership of x (saturated to [lo, hi]; NaN treated as the midpoint) in all
    /// seven terms, each in [0, 1], at least one ≥ 0.5.
    #[inline]
    pub fn degrees(&self, x: f64) -> [f64; 7] {
        let x = if x.is_nan() {
            0.5 * (self.lo + self.hi)
        } else {
            x.clamp(self.lo, self.hi)
        };
        // Equal widths and spacing Δ: μ_{i+1} = μ_i · a · q^i with a = exp(((x − c_0)Δ − Δ²/2)/σ²)
        // and q = exp(−Δ²/σ²), so two exponentials replace seven. Inputs are saturated, so the
        // smallest degree is exp(−0.5 (6Δ/σ)²) ≈ 5e−44: no underflow.
        let c0 = self.sets[0].center;
        let s2 = self.sets[0].sigma * self.sets[0].sigma;
        let d = self.sets[1].center - c0;
        let mut out = [0.0; 7];
        out[0] = self.sets[0].degree(x);
        let mut ratio = (((x - c0) * d - 0.5 * d * d) / s2).exp();
        let q = (-(d * d) / s2).exp();
        for i in 1..7 {
            out[i] = (out[i - 1] * ratio).min(1.0);
            ratio *= q;
        }
        out
    }
}
