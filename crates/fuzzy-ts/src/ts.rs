//! The two-rule Takagi–Sugeno switching law of eq. 5.29:
//!
//! ```text
//! if r_x(k) is TH_n then α_f(k+1) = α_f(k) + ζ_n (y(k) − ŷ(k))
//! if r_x(k) is TH_f then α_f(k+1) = α_f(k) + ζ_f (y(k) − ŷ(k))
//! ```
//!
//! "r_x is TH_n" (normal) is read as |r_x| ≤ TH and "TH_f" (faulty) as |r_x| > TH. The crisp law
//! switches gains at the threshold; the smooth (Takagi–Sugeno) law blends them with a logistic
//! membership μ_f(r) = 1 / (1 + exp(−(|r| − TH)/w)) and μ_n = 1 − μ_f, giving the gain
//! μ_n ζ_n + μ_f ζ_f (the TS weighted average of the two rule consequents).

use crate::error::{FuzzyError, Result};
use serde::{Deserialize, Serialize};

/// Crisp or smooth switching between the two rules.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Switching {
    /// Hard switch at |r| = TH.
    Crisp,
    /// Logistic blend of width `width` (> 0) around |r| = TH.
    Smooth {
        /// Transition width w.
        width: f64,
    },
}

/// Parameters of eq. 5.29, validated on construction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TsSwitchingLaw {
    threshold: f64,
    gain_normal: f64,
    gain_faulty: f64,
    switching: Switching,
}

impl TsSwitchingLaw {
    /// Threshold TH ≥ 0, gains ζ_n, ζ_f (finite), and a switching mode.
    pub fn new(
        threshold: f64,
        gain_normal: f64,
        gain_faulty: f64,
        switching: Switching,
    ) -> Result<Self> {
        if !(threshold.is_finite() && threshold >= 0.0) {
            return Err(FuzzyError::InvalidParameter {
                which: "threshold",
                value: threshold,
            });
        }
        if !gain_normal.is_finite() {
            return Err(FuzzyError::InvalidParameter {
                which: "gain_normal",
                value: gain_normal,
            });
        }
        if !gain_faulty.is_finite() {
            return Err(FuzzyError::InvalidParameter {
                which: "gain_faulty",
                value: gain_faulty,
            });
        }
        if let Switching::Smooth { width } = switching
            && !(width.is_finite() && width > 0.0)
        {
            return Err(FuzzyError::InvalidParameter {
                which: "width",
                value: width,
            });
        }
        Ok(Self {
            threshold,
            gain_normal,
            gain_faulty,
            switching,
        })
    }
    /// Threshold TH.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }
    /// Degree μ_f ∈ [0, 1] to which residual r is "faulty" (TH_f).
    #[inline]
    pub fn faulty_degree(&self, r: f64) -> f64 {
        let a = r.abs();
        match self.switching {
            Switching::Crisp => {
                if a > self.threshold {
                    1.0
                } else {
                    0.0
                }
            }
            Switching::Smooth { width } => {
                let m = 1.0 / (1.0 + (-(a - self.threshold) / width).exp());
                if m.is_nan() { 1.0 } else { m }
            }
        }
    }
    /// The gain in force for residual r: μ_n ζ_n + μ_f ζ_f.
    #[inline]
    pub fn gain(&self, r: f64) -> f64 {
        let f = self.faulty_degree(r);
        (1.0 - f) * self.gain_normal + f * self.gain_faulty
    }
    /// Eq. 5.29: α_f(k+1) = α_f(k) + gain(r_x(k)) · e(k), with e(k) = y(k) − ŷ(k).
    #[inline]
    pub fn step(&self, alpha: f64, residual: f64, error: f64) -> f64 {
        alpha + self.gain(residual) * error
    }
}
