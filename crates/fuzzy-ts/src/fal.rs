//! The fuzzy ARX-Laguerre (FAL) model of eq. 5.19:
//!
//! ```text
//! J_s(k+1) = σ_s J_s(k) + σ_o y(k) + σ_i u(k) + σ_f J_f(k)
//! ŷ(k+1)   = λᵀ J_s(k+1)
//! ```
//!
//! Reading adopted (see `docs/equations/fuzzy-ts.md`): J_f(k) = infer(e(k), ė(k)) is the Table 5.1
//! inference on the ARX-Laguerre one-step error e(k) = y(k) − ŷ_AL(k) and its change
//! ė(k) = e(k) − e(k−1); σ_f is the input vector of a third Laguerre bank (pole ζ_f, order N_f,
//! eq. 4.15 form) that filters J_f, and its Fourier coefficients λ_f are appended to λ. Fitting is
//! two-stage: (1) the ARX-Laguerre model (eq. 4.11) by least squares; (2) λ_f by least squares on
//! the stage-1 residual, with λ of stage 1 held fixed, so the fuzzy term can only add accuracy on
//! the fitting data.

use crate::error::{FuzzyError, Result, check_finite};
use crate::inference::{FuzzyInference, FuzzyRanges, TNorm};
use crate::rules::RuleTable;
use laguerre_id::{
    ArxLaguerreConfig, ArxLaguerreModel, LaguerreBank, LaguerreState, MAX_ORDER, Pole,
};
use serde::{Deserialize, Serialize};

/// How the universes of e and ė are set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum FuzzyScaling {
    /// The dissertation's fixed universes (e ∈ ±0.3, ė ∈ ±0.1, J_f ∈ ±0.08), whatever the
    /// signal's units.
    Dissertation,
    /// Universes of ±`sigmas` standard deviations of the stage-1 residual e and of ė on the
    /// fitting data (output universe ±0.08; its scale is absorbed by λ_f).
    ResidualStd {
        /// Multiple of the standard deviation (> 0).
        sigmas: f64,
    },
}

/// Settings of the FAL model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FalConfig {
    /// The underlying ARX-Laguerre identification.
    pub base: ArxLaguerreConfig,
    /// Order N_f of the bank filtering J_f (1..=8).
    pub fuzzy_order: usize,
    /// Pole ζ_f of that bank (|ζ_f| < 1; 0 = plain delays J_f(k), J_f(k−1), …).
    pub fuzzy_pole: f64,
    /// Universes of the inputs.
    pub scaling: FuzzyScaling,
    /// The rule table (normally [`RuleTable::table_5_1`]).
    pub table: RuleTable,
    /// The "and" of the rules.
    pub tnorm: TNorm,
}

impl FalConfig {
    /// Defaults around a base configuration: N_f = 2, ζ_f = 0, ±3σ universes, corrected Table 5.1,
    /// product t-norm.
    pub fn with_base(base: ArxLaguerreConfig) -> Self {
        Self {
            base,
            fuzzy_order: 2,
            fuzzy_pole: 0.0,
            scaling: FuzzyScaling::ResidualStd { sigmas: 3.0 },
            table: RuleTable::table_5_1(),
            tnorm: TNorm::Product,
        }
    }

    fn validate(&self) -> Result<(LaguerreBank, ())> {
        if self.fuzzy_order == 0 || self.fuzzy_order > MAX_ORDER {
            return Err(FuzzyError::InvalidParameter {
                which: "fuzzy_order",
                value: self.fuzzy_order as f64,
            });
        }
        let pole = Pole::new(self.fuzzy_pole)?;
        if let FuzzyScaling::ResidualStd { sigmas } = self.scaling
            && !(sigmas.is_finite() && sigmas > 0.0)
        {
            return Err(FuzzyError::InvalidParameter {
                which: "sigmas",
                value: sigmas,
            });
        }
        Ok((LaguerreBank::new(pole, self.fuzzy_order)?, ()))
    }
}

/// State of the FAL predictor: the ARX-Laguerre state J_s, the J_f bank state and e(k−1).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct FalState {
    /// ARX-Laguerre state (y and u banks).
    pub base: LaguerreState,
    /// State of the bank filtering J_f.
    pub fuzzy: [f64; MAX_ORDER],
    /// Previous stage-1 error e(k−1).
    pub e_prev: f64,
}

/// An identified fuzzy ARX-Laguerre model (eq. 5.19).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FuzzyArxLaguerre {
    base: ArxLaguerreModel,
    bank_f: LaguerreBank,
    k_f: [f64; MAX_ORDER],
    inference: FuzzyInference,
}

impl FuzzyArxLaguerre {
    /// Two-stage identification (see the module docs). `u` must be `Some` exactly when N_b > 0.
    pub fn identify(y: &[f64], u: Option<&[f64]>, cfg: &FalConfig) -> Result<Self> {
        let (bank_f, ()) = cfg.validate()?;
        let base = ArxLaguerreModel::identify(y, u, &cfg.base)?;
        let yhat = base.predict(y, u)?;
        let e: Vec<f64> = y.iter().zip(&yhat).map(|(a, b)| a - b).collect();
        let ranges = match cfg.scaling {
            FuzzyScaling::Dissertation => FuzzyRanges::DISSERTATION,
            FuzzyScaling::ResidualStd { sigmas } => {
                let sd = |v: &[f64]| {
                    let m = v.iter().sum::<f64>() / v.len() as f64;
                    (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
                };
                let de: Vec<f64> = e.windows(2).map(|w| w[1] - w[0]).collect();
                let (se, sde) = (sd(&e), sd(&de));
                if !(se > 0.0 && sde > 0.0) {
                    // A perfect stage-1 fit leaves nothing for the fuzzy term to model.
                    return Err(FuzzyError::InvalidParameter {
                        which: "residual std",
                        value: se.min(sde),
                    });
                }
                FuzzyRanges {
                    error: sigmas * se,
                    change_of_error: sigmas * sde,
                    output: 0.08,
                }
            }
        };
        let inference = FuzzyInference::new(ranges, cfg.table, cfg.tnorm)?;
        // Regressors: the J_f bank state x_f(k) (J_f filtered up to k−1); target e(k).
        let nf = bank_f.order();
        let n = y.len();
        let mut gram = vec![0.0; nf * nf];
        let mut rhs = vec![0.0; nf];
        let mut xf = [0.0; MAX_ORDER];
        let mut e_prev = 0.0;
        for k in 0..n {
            for i in 0..nf {
                rhs[i] += xf[i] * e[k];
                for j in 0..nf {
                    gram[i * nf + j] += xf[i] * xf[j];
                }
            }
            let jf = inference.infer(e[k], e[k] - e_prev);
            e_prev = e[k];
            bank_f.step(&mut xf, jf);
        }
        let k_f = solve_small(nf, &mut gram, &mut rhs)?;
        Ok(Self {
            base,
            bank_f,
            k_f,
            inference,
        })
    }

    /// The underlying ARX-Laguerre model (A, b_y, b_u, λ, poles: eq. 4.11).
    pub fn base(&self) -> &ArxLaguerreModel {
        &self.base
    }
    /// The bank filtering J_f; its input vector is σ_f of eq. 5.19.
    pub fn fuzzy_bank(&self) -> LaguerreBank {
        self.bank_f
    }
    /// σ_f of eq. 5.19 (length N_f).
    pub fn sigma_f(&self) -> Vec<f64> {
        self.bank_f.b_vector()
    }
    /// Fourier coefficients λ_f of the J_f bank (length N_f).
    pub fn fuzzy_coefficients(&self) -> &[f64] {
        &self.k_f[..self.bank_f.order()]
    }
    /// The fitted rule-table inference J_f = infer(e, ė).
    pub fn inference(&self) -> &FuzzyInference {
        &self.inference
    }

    /// One step of eq. 5.19: from the state at time k and the measured y(k), u(k), return the state
    /// at k+1 and ŷ(k+1). Allocation free.
    #[inline]
    pub fn predict_next(&self, state: &FalState, y: f64, u: f64) -> (FalState, f64) {
        let mut next = *state;
        let e = y - self.base.output(&state.base);
        let jf = self.inference.infer(e, e - state.e_prev);
        next.e_prev = e;
        self.base.advance(&mut next.base, y, u);
        self.bank_f.step(&mut next.fuzzy, jf);
        let yhat = self.output(&next);
        (next, yhat)
    }

    /// ŷ = λᵀ J_s + λ_fᵀ x_f for a state.
    #[inline]
    pub fn output(&self, state: &FalState) -> f64 {
        let nf = self.bank_f.order();
        let mut s = self.base.output(&state.base);
        for i in 0..nf {
            s += self.k_f[i] * state.fuzzy[i];
        }
        s
    }

    /// One-step-ahead predictions ŷ(k) for every k (zero initial state).
    pub fn predict(&self, y: &[f64], u: Option<&[f64]>) -> Result<Vec<f64>> {
        check_finite("y", y)?;
        if let Some(u) = u {
            if u.len() != y.len() {
                return Err(FuzzyError::LengthMismatch {
                    expected: y.len(),
                    found: u.len(),
                });
            }
            check_finite("u", u)?;
        }
        if u.is_some() != (self.base.n_b() > 0) {
            return Err(laguerre_id::IdentError::InputMismatch {
                n_b: self.base.n_b(),
                has_input: u.is_some(),
            }
            .into());
        }
        let mut st = FalState::default();
        let mut out = Vec::with_capacity(y.len());
        for k in 0..y.len() {
            out.push(self.output(&st));
            st = self.predict_next(&st, y[k], u.map_or(0.0, |u| u[k])).0;
        }
        Ok(out)
    }
}

/// Solve the small SPD system G x = r (Gaussian elimination with partial pivoting, n ≤ 8).
fn solve_small(n: usize, g: &mut [f64], r: &mut [f64]) -> Result<[f64; MAX_ORDER]> {
    let scale = (0..n).map(|i| g[i * n + i].abs()).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return Err(FuzzyError::InvalidParameter {
            which: "fuzzy regressor energy",
            value: scale,
        });
    }
    for c in 0..n {
        let piv = (c..n)
            .max_by(|&a, &b| g[a * n + c].abs().total_cmp(&g[b * n + c].abs()))
            .unwrap_or(c);
        if g[piv * n + c].abs() <= 1e-12 * scale {
            return Err(FuzzyError::InvalidParameter {
                which: "fuzzy regressor rank",
                value: c as f64,
            });
        }
        if piv != c {
            for j in 0..n {
                g.swap(c * n + j, piv * n + j);
            }
            r.swap(c, piv);
        }
        for i in c + 1..n {
            let f = g[i * n + c] / g[c * n + c];
            for j in c..n {
                g[i * n + j] -= f * g[c * n + j];
            }
            r[i] -= f * r[c];
        }
    }
    let mut x = [0.0; MAX_ORDER];
    for i in (0..n).rev() {
        let mut s = r[i];
        for j in i + 1..n {
            s -= g[i * n + j] * x[j];
        }
        x[i] = s / g[i * n + i];
    }
    Ok(x)
}
