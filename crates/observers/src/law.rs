//! Correction laws: functions of the output error e = y − ŷ that drive the observer's chain.
//!
//! Every observer in the dissertation corrects a three-level chain
//! (level 1: the measured state, level 2: the next state or the lumped uncertainty,
//! level 3: the extended state, see [`crate::predictor`]). A law returns one increment per
//! level, **per sample** (discrete time; continuous gains are converted by the constructors in
//! [`crate::design`]). The laws are
//!
//! | family | level 1 | level 2 | level 3 | used by |
//! |---|---|---|---|---|
//! | [`LawFamily::Linear`] | l₁e | l₂e | l₃e | APIO/ALPIO (PI, eqs 2.33, 4.16–4.17), FLO (3.13–3.14) |
//! | [`LawFamily::Sign`] | + k₁ sgn e | + k₂ sgn e | + k₃ sgn e | SMO (2.36–2.37, 5.21–5.22), VSO (3.15) |
//! | [`LawFamily::SuperTwisting`] | + k₁\|e\|^½ sgn e | + k₂ sgn e | – | PFLO (3.16–3.18), SMALPIO (4.19) |
//! | [`LawFamily::Levant`] | + k₁\|e\|^⅔ sgn e | + k₂\|e₂\|^½ sgn e₂, e₂ = k₁\|e\|^⅔ sgn e | + k₃ sgn e | HOSTSMO (2.41–2.42), ASMO (5.25–5.26) |
//!
//! Each nonlinear family is added to the linear (PI / Luenberger) terms, which is how the
//! dissertation writes SMO (5.21), SMALPIO (4.19), PFLO (3.17–3.18) and ASMO (5.25).
//! [`FuzzyScheduled`] wraps any law with the T–S scheduled integral of eq. (5.29) (AFSMO).

use crate::error::ObserverError;

/// The per-sample increments a law applies to the three levels of the observer chain.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Correction {
    /// Increment on level 1 (the measured state / output direction).
    pub c1: f64,
    /// Increment on level 2 (velocity for physics models, fault estimate for ARX-Laguerre).
    pub c2: f64,
    /// Increment on level 3 (extended state: lumped uncertainty or its rate).
    pub c3: f64,
}

/// A correction law: maps the output error to chain increments.
pub trait CorrectionLaw {
    /// Increments for the output error `e` = y(k) − ŷ(k).
    fn correct(&mut self, e: f64) -> Correction;
    /// Return any internal state to its initial value.
    fn reset(&mut self) {}
}

/// sgn(e) with sgn(0) = 0.
#[inline(always)]
pub fn sgn(e: f64) -> f64 {
    if e > 0.0 {
        1.0
    } else if e < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// |e|^½ sgn(e).
#[inline(always)]
pub fn sig_half(e: f64) -> f64 {
    e.abs().sqrt().copysign(e)
}

/// |e|^⅔ sgn(e).
#[inline(always)]
pub fn sig_two_thirds(e: f64) -> f64 {
    let c = e.cbrt();
    c * c.abs()
}

/// Which nonlinear terms a [`HomogeneousLaw`] adds to its linear part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum LawFamily {
    /// Linear only (PI, Luenberger, FLO).
    Linear,
    /// First-order sliding mode: sgn e on every level with a non-zero gain.
    Sign,
    /// Super-twisting: |e|^½ sgn e on level 1, sgn e on level 2 (Levant 1993).
    SuperTwisting,
    /// Levant's second-order differentiator in recursive form: |e|^⅔, |e₂|^½, sgn.
    Levant,
}

/// Linear + homogeneous sliding-mode correction law (eqs 2.36–2.42, 3.13–3.18, 4.16–4.19,
/// 5.21–5.26 in one form). Gains are per sample; linear gains may have any sign (a Kalman
/// design on a fast mode gives negative components), nonlinear gains are non-negative.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(into = "HomogeneousLawRepr", try_from = "HomogeneousLawRepr")]
pub struct HomogeneousLaw {
    linear: [f64; 3],
    nonlinear: [f64; 3],
    family: LawFamily,
    /// k₂√k₁, the collapsed Levant level-2 gain.
    k2_sqrt_k1: f64,
}

/// Serialised form of [`HomogeneousLaw`] (the derived gain is recomputed and the gains
/// re-validated on deserialisation).
#[derive(serde::Serialize, serde::Deserialize)]
struct HomogeneousLawRepr {
    linear: [f64; 3],
    nonlinear: [f64; 3],
    family: LawFamily,
}

impl From<HomogeneousLaw> for HomogeneousLawRepr {
    fn from(l: HomogeneousLaw) -> Self {
        Self {
            linear: l.linear,
            nonlinear: l.nonlinear,
            family: l.family,
        }
    }
}

impl TryFrom<HomogeneousLawRepr> for HomogeneousLaw {
    type Error = ObserverError;
    fn try_from(r: HomogeneousLawRepr) -> Result<Self, ObserverError> {
        Self::new(r.linear, r.nonlinear, r.family)
    }
}

fn check_gains(name: &'static str, g: &[f64; 3], nonneg: bool) -> Result<(), ObserverError> {
    for &v in g {
        if !v.is_finite() || (nonneg && v < 0.0) {
            return Err(ObserverError::InvalidParameter {
                name,
                value: v,
                reason: "gains must be finite (nonlinear gains also >= 0)",
            });
        }
    }
    Ok(())
}

impl HomogeneousLaw {
    /// Build a law from linear gains `[l1, l2, l3]`, nonlinear gains `[k1, k2, k3]` and a family.
    ///
    /// For [`LawFamily::Linear`] the nonlinear gains are ignored (set to zero); for
    /// [`LawFamily::SuperTwisting`] `k3` is ignored.
    pub fn new(
        linear: [f64; 3],
        nonlinear: [f64; 3],
        family: LawFamily,
    ) -> Result<Self, ObserverError> {
        check_gains("linear gain", &linear, false)?;
        check_gains("nonlinear gain", &nonlinear, true)?;
        let nonlinear = match family {
            LawFamily::Linear => [0.0; 3],
            LawFamily::SuperTwisting => [nonlinear[0], nonlinear[1], 0.0],
            _ => nonlinear,
        };
        Ok(Self {
            linear,
            nonlinear,
            family,
            k2_sqrt_k1: nonlinear[1] * nonlinear[0].sqrt(),
        })
    }

    /// Pure linear law (PI when `l1 = 0`, eq. 4.17; Luenberger/FLO eqs 3.13–3.14).
    pub fn linear(linear: [f64; 3]) -> Result<Self, ObserverError> {
        Self::new(linear, [0.0; 3], LawFamily::Linear)
    }

    /// Linear gains.
    pub fn linear_gains(&self) -> [f64; 3] {
        self.linear
    }

    /// Nonlinear gains.
    pub fn nonlinear_gains(&self) -> [f64; 3] {
        self.nonlinear
    }

    /// The nonlinear family.
    pub fn family(&self) -> LawFamily {
        self.family
    }
}

impl CorrectionLaw for HomogeneousLaw {
    #[inline(always)]
    fn correct(&mut self, e: f64) -> Correction {
        let [l1, l2, l3] = self.linear;
        let [k1, k2, k3] = self.nonlinear;
        let (n1, n2, n3) = match self.family {
            LawFamily::Linear => (0.0, 0.0, 0.0),
            LawFamily::Sign => {
                let s = sgn(e);
                (k1 * s, k2 * s, k3 * s)
            }
            LawFamily::SuperTwisting => (k1 * sig_half(e), k2 * sgn(e), 0.0),
            LawFamily::Levant => {
                // Levant's recursive differentiator: e2 = k1|e|^⅔ sgn e is the level-1
                // injection, i.e. the "X̂1-dot − X̂2" of eq. (2.41); sgn(e2) = sgn(e), so
                // k2|e2|^½ sgn e2 = k2√k1 |e|^⅓ sgn e = k2√k1 ∛e: one cube root per sample
                // (√k1 is precomputed), the same value as the recursive form to rounding.
                let c = e.cbrt();
                (k1 * (c * c.abs()), self.k2_sqrt_k1 * c, k3 * sgn(e))
            }
        };
        Correction {
            c1: l1 * e + n1,
            c2: l2 * e + n2,
            c3: l3 * e + n3,
        }
    }
}

/// Parameters of the T–S scheduled integral of eq. (5.29).
///
/// The residual magnitude |r| is "normal" (TH_n) below `threshold_normal`, "faulty" (TH_f) above
/// `threshold_fault`, with complementary linear memberships in between (a partition of unity).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FuzzyScheduleParams {
    /// ζ_n, integral gain while the residual is normal.
    pub zeta_normal: f64,
    /// ζ_f, integral gain while the residual is faulty.
    pub zeta_fault: f64,
    /// TH_n: |r| at or below which the residual is fully normal.
    pub threshold_normal: f64,
    /// TH_f: |r| at or above which the residual is fully faulty (must exceed TH_n).
    pub threshold_fault: f64,
}

/// A law plus the fuzzy-scheduled integral α_f of eq. (5.29), added to level 2 (eq. 5.30
/// adds α_f to the state equation exactly where the fault estimate φ̂ enters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FuzzyScheduled<L> {
    inner: L,
    p: FuzzyScheduleParams,
    inv_width: f64,
}

impl<L: CorrectionLaw> FuzzyScheduled<L> {
    /// Wrap `inner` with the scheduled integral; validates the parameters.
    pub fn new(inner: L, p: FuzzyScheduleParams) -> Result<Self, ObserverError> {
        for (name, v) in [
            ("zeta_normal", p.zeta_normal),
            ("zeta_fault", p.zeta_fault),
            ("threshold_normal", p.threshold_normal),
        ] {
            if !v.is_finite() || v < 0.0 {
                return Err(ObserverError::InvalidParameter {
                    name,
                    value: v,
                    reason: "must be finite and >= 0",
                });
            }
        }
        if !p.threshold_fault.is_finite() || p.threshold_fault <= p.threshold_normal {
            return Err(ObserverError::InvalidParameter {
                name: "threshold_fault",
                value: p.threshold_fault,
                reason: "must be finite and > threshold_normal",
            });
        }
        Ok(Self {
            inner,
            p,
            inv_width: 1.0 / (p.threshold_fault - p.threshold_normal),
        })
    }

    /// Membership of |r| in TH_f (the faulty set); TH_n's membership is 1 minus this.
    #[inline(always)]
    pub fn fault_membership(&self, r: f64) -> f64 {
        ((r.abs() - self.p.threshold_normal) * self.inv_width).clamp(0.0, 1.0)
    }

    /// The scheduling parameters.
    pub fn params(&self) -> FuzzyScheduleParams {
        self.p
    }
}

impl<L: CorrectionLaw> CorrectionLaw for FuzzyScheduled<L> {
    #[inline(always)]
    fn correct(&mut self, e: f64) -> Correction {
        let mut c = self.inner.correct(e);
        let mu_f = self.fault_membership(e);
        let zeta = (1.0 - mu_f) * self.p.zeta_normal + mu_f * self.p.zeta_fault;
        c.c2 += zeta * e;
        c
    }
    fn reset(&mut self) {
        self.inner.reset();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_powers_closed_form() {
        assert_eq!(sgn(0.0), 0.0);
        assert_eq!(sig_half(0.0), 0.0);
        assert_eq!(sig_two_thirds(0.0), 0.0);
        assert!((sig_half(-4.0) + 2.0).abs() < 1e-15);
        assert!((sig_two_thirds(8.0) - 4.0).abs() < 1e-12);
        assert!((sig_two_thirds(-27.0) + 9.0).abs() < 1e-12);
    }

    #[test]
    fn levant_recursive_form_matches_collapsed_form() {
        // c2 = k2 |k1 |e|^{2/3}|^{1/2} sgn e = k2 sqrt(k1) |e|^{1/3} sgn e.
        let mut law = HomogeneousLaw::new([0.0; 3], [1.9, 1.5, 1.1], LawFamily::Levant).unwrap();
        for e in [-3.0, -0.01, 0.2, 5.0] {
            let c = law.correct(e);
            let expect = 1.5 * 1.9f64.sqrt() * e.abs().cbrt() * e.signum();
            assert!((c.c2 - expect).abs() < 1e-12);
            assert_eq!(c.c3, 1.1 * e.signum());
        }
    }

    #[test]
    fn negative_gain_is_rejected() {
        assert!(matches!(
            HomogeneousLaw::new([1.0, -1.0, 0.0], [0.0, -1.0, 0.0], LawFamily::Levant),
            Err(ObserverError::InvalidParameter { .. })
        ));
    }

    #[test]
    fn fuzzy_memberships_partition_unity_and_interpolate() {
        let law = HomogeneousLaw::linear([0.0; 3]).unwrap();
        let p = FuzzyScheduleParams {
            zeta_normal: 0.1,
            zeta_fault: 0.5,
            threshold_normal: 1.0,
            threshold_fault: 3.0,
        };
        let mut f = FuzzyScheduled::new(law, p).unwrap();
        assert_eq!(f.fault_membership(0.5), 0.0);
        assert_eq!(f.fault_membership(-2.0), 0.5);
        assert_eq!(f.fault_membership(9.0), 1.0);
        assert!((f.correct(2.0).c2 - 0.3 * 2.0).abs() < 1e-15);
        let bad = FuzzyScheduleParams {
            threshold_fault: 0.5,
            ..p
        };
        assert!(FuzzyScheduled::new(law, bad).is_err());
    }
}
