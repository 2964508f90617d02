//! Linear prediction (AR) pre-whitening: the residual of a healthy model.
//!
//! An AR model `x(k) ≈ Σ_{i=1}^{p} a_i x(k−i)` is fitted by least squares (`laguerre-id`'s ARX
//! identification in AR form, faer QR) on a healthy baseline, or on the recording itself when no
//! baseline is given (self-reference: the AR pre-whitening of Sawalhi & Randall 2007). Its
//! prediction-error filter `e(k) = x(k) − Σ a_i x(k−i)` removes what is predictable from the
//! past — the structural resonances, the shaft and mains lines the fitted signal holds — and
//! keeps what is not: the onsets of fault impacts. The order is chosen among [`ORDERS`] by the
//! one-step prediction error on a held-out part of the fitted signal.
//!
//! [`prediction_error`] is the workspace's one AR prediction-error filtering loop: the
//! whitener's [`ArWhitener::residual`] and the closed loop's structural path
//! (`close_loop::path::StructuralPath::prediction_error`) both run it.

use laguerre_id::{ArxModel, ArxOrders, IdentError};
use serde::{Deserialize, Serialize};

use crate::error::{DiagnosisError, Result};

/// Candidate AR orders.
pub const ORDERS: [usize; 6] = [8, 16, 24, 32, 48, 64];
/// At most this many samples (from the start) are used to fit and validate the model.
pub const MAX_FIT_SAMPLES: usize = 48_000;
/// Fewest samples a signal needs to fit the AR model.
pub const MIN_FIT_SAMPLES: usize = 2_000;
/// Parsimony: the smallest order whose held-out error is within this factor of the best wins.
pub const ORDER_TOLERANCE: f64 = 1.01;

/// Held-out score of one candidate order.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OrderScore {
    /// AR order.
    pub order: usize,
    /// Held-out one-step prediction error variance / held-out signal variance.
    pub heldout_error_ratio: f64,
}

/// A fitted AR prediction-error (whitening) filter.
///
/// The closed loop's structural path (`close_loop::path::StructuralPath`) is the other AR model
/// of the workspace. Both filter through the one [`prediction_error`] loop, and a path becomes a
/// whitener at the edge ([`ArWhitener::from_coefficients`] of its prediction coefficients
/// `a_i = −α_i`, as a machine-model baseline does); they stay two types because what they hold
/// and how they are fitted differ: this one is fitted by least squares on time samples with its
/// order chosen by held-out one-step error among [`ORDERS`], keeps prediction coefficients
/// `a_i` (x(k) ≈ Σ a_i x(k−i)) and its fit's record (samples, per-order scores), and its residual
/// starts at sample `p`; the path is fitted by Yule–Walker (Levinson–Durbin) on a line-free PSD
/// with its order chosen by a spectral score, keeps `A(z)` coefficients `α_i = −a_i` and an
/// excitation variance, and is also a spectrum, a set of modes and a synthesis filter `1/A(z)`.
/// Either fit on the other's data gives other numbers, and both are serialised in reports.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArWhitener {
    /// Chosen order `p`.
    pub order: usize,
    /// `a_1 … a_p`.
    pub coefficients: Vec<f64>,
    /// Sampling rate of the fitted signal, Hz.
    pub fs_hz: f64,
    /// Samples used to fit.
    pub fit_samples: usize,
    /// Samples used to choose the order (after the fitted ones).
    pub heldout_samples: usize,
    /// Every candidate's held-out score.
    pub selection: Vec<OrderScore>,
}

fn ident(what: &'static str) -> impl Fn(IdentError) -> DiagnosisError {
    move |e| DiagnosisError::Degenerate {
        what,
        reason: format!("AR fit failed: {e}"),
    }
}

impl ArWhitener {
    /// Fit on a recording's samples (at least [`MIN_FIT_SAMPLES`]; `what` names it in errors):
    /// the first two thirds of the first [`MAX_FIT_SAMPLES`] samples fit each order of
    /// [`ORDERS`], the last third scores it.
    ///
    /// # Errors
    /// [`DiagnosisError::BaselineTooShort`] below [`MIN_FIT_SAMPLES`];
    /// [`DiagnosisError::Degenerate`] for a constant or rank-deficient signal.
    pub fn fit(signal: &crate::Signal<'_>, what: &'static str) -> Result<Self> {
        // finite samples and a positive rate: a `Signal` is checked when it is made
        let (x, fs_hz) = (signal.samples(), signal.fs_hz());
        if x.len() < MIN_FIT_SAMPLES {
            return Err(DiagnosisError::BaselineTooShort {
                samples: x.len(),
                needed: MIN_FIT_SAMPLES,
            });
        }
        let l = x.len().min(MAX_FIT_SAMPLES);
        let n_fit = 2 * l / 3;
        let (fit, _) = x.split_at(n_fit);
        let held = &x[n_fit..l];
        let mean = held.iter().sum::<f64>() / held.len() as f64;
        let var = held.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / held.len() as f64;
        if var <= f64::MIN_POSITIVE {
            return Err(DiagnosisError::Degenerate {
                what,
                reason: "zero variance".into(),
            });
        }
        let mut best: Option<(usize, Vec<f64>, f64)> = None;
        let mut selection = Vec::new();
        let mut fits = Vec::new();
        for &p in ORDERS.iter().filter(|&&p| n_fit >= 20 * p) {
            let m = ArxModel::identify(fit, None, ArxOrders::new(p, 0).map_err(ident(what))?)
                .map_err(ident(what))?;
            // held-out one-step error, history from the samples before each predicted one
            let mut se = 0.0;
            for k in n_fit..l {
                let pred: f64 = m.a.iter().enumerate().map(|(i, a)| a * x[k - 1 - i]).sum();
                se += (x[k] - pred).powi(2);
            }
            let ratio = se / (held.len() as f64 * var);
            if !ratio.is_finite() {
                return Err(DiagnosisError::Degenerate {
                    what,
                    reason: "non-finite prediction error".into(),
                });
            }
            selection.push(OrderScore {
                order: p,
                heldout_error_ratio: ratio,
            });
            fits.push(m.a);
        }
        let min = selection
            .iter()
            .map(|s| s.heldout_error_ratio)
            .fold(f64::INFINITY, f64::min);
        for (s, a) in selection.iter().zip(fits) {
            if s.heldout_error_ratio <= ORDER_TOLERANCE * min {
                best = Some((s.order, a, s.heldout_error_ratio));
                break;
            }
        }
        let (order, coefficients, _) = best.ok_or_else(|| DiagnosisError::Degenerate {
            what,
            reason: "no AR order could be fitted".into(),
        })?;
        Ok(Self {
            order,
            coefficients,
            fs_hz,
            fit_samples: n_fit,
            heldout_samples: l - n_fit,
            selection,
        })
    }

    /// A whitener from given prediction coefficients `a_1 … a_p` (x(k) ≈ Σ a_i x(k−i)) at
    /// `fs_hz`, e.g. the structural path of a calibrated machine model (whose `A(z) = 1 + Σ α_i
    /// z⁻ⁱ` gives a_i = −α_i). No samples were fitted here: `fit_samples`, `heldout_samples` are
    /// 0 and `selection` is empty.
    ///
    /// # Errors
    /// [`DiagnosisError::Degenerate`] for no coefficient or a non-finite one.
    pub fn from_coefficients(
        coefficients: Vec<f64>,
        fs_hz: f64,
        what: &'static str,
    ) -> Result<Self> {
        if coefficients.is_empty() || coefficients.iter().any(|v| !v.is_finite()) {
            return Err(DiagnosisError::Degenerate {
                what,
                reason: "prediction coefficients must be non-empty and finite".into(),
            });
        }
        Ok(Self {
            order: coefficients.len(),
            coefficients,
            fs_hz,
            fit_samples: 0,
            heldout_samples: 0,
            selection: Vec::new(),
        })
    }

    /// The prediction error `e(k) = x(k) − Σ a_i x(k−i)` for `k = p … len−1` (the first `p`
    /// samples have no full history and are not returned): [`prediction_error`] with this
    /// whitener's coefficients.
    pub fn residual(&self, x: &[f64]) -> Vec<f64> {
        prediction_error(&self.coefficients, x)
    }
}

/// The AR prediction-error filter `e(k) = x(k) − Σ_{i=1}^{p} a_i x(k−i)` of prediction
/// coefficients `a_1 … a_p` (`p = coefficients.len()`), for `k = p … len−1` (the first `p`
/// samples have no full history and are not returned; empty when `x` has at most `p`). Each
/// `e(k)` is summed in the order `i = 1 … p`, so every output is the bits of
/// [`one_prediction_error`]. The one AR filtering loop of the workspace: [`ArWhitener::residual`]
/// and `close_loop::path::StructuralPath::prediction_error` (with `a_i = −α_i`) run it.
pub fn prediction_error(coefficients: &[f64], x: &[f64]) -> Vec<f64> {
    let p = coefficients.len();
    if x.len() <= p {
        return Vec::new();
    }
    // BLOCK outputs at a time: each keeps its own sum in the same order (the same bits as
    // one at a time), and the independent chains run side by side in vector registers
    // instead of each subtraction waiting on the one before (order 142 at 12 kHz: a CWRU
    // machine model)
    const BLOCK: usize = 16;
    let mut out = Vec::with_capacity(x.len() - p);
    let mut k = p;
    while k + BLOCK <= x.len() {
        let mut s = [0.0; BLOCK];
        s.copy_from_slice(&x[k..k + BLOCK]);
        for (i, a) in coefficients.iter().enumerate() {
            let past: &[f64; BLOCK] = x[k - 1 - i..k - 1 - i + BLOCK]
                .try_into()
                .expect("a slice of BLOCK samples");
            for (sj, xj) in s.iter_mut().zip(past) {
                *sj -= a * xj;
            }
        }
        out.extend_from_slice(&s);
        k += BLOCK;
    }
    out.extend((k..x.len()).map(|k| one_prediction_error(coefficients, x, k)));
    out
}

/// `e(k)` of [`prediction_error`] for one `k ≥ coefficients.len()`.
///
/// # Panics
/// When `k < coefficients.len()` or `k ≥ x.len()` (no full history or no sample).
pub fn one_prediction_error(coefficients: &[f64], x: &[f64], k: usize) -> f64 {
    let mut s = x[k];
    for (i, a) in coefficients.iter().enumerate() {
        s -= a * x[k - 1 - i];
    }
    s
}

#[cfg(test)]
mod residual_tests {
    use super::*;

    /// The blocked residual gives the bits of the one-at-a-time definition, for every length
    /// around the block size.
    #[test]
    fn blocked_residual_is_the_definition_bit_for_bit() {
        let coefficients: Vec<f64> = (0..7).map(|i| 0.3 / (i as f64 + 1.0) - 0.05).collect();
        let w = ArWhitener::from_coefficients(coefficients, 1000.0, "test").unwrap();
        for n in 8..60 {
            let x: Vec<f64> = (0..n)
                .map(|k| (0.7 * k as f64).sin() + 0.01 * k as f64)
                .collect();
            let blocked: Vec<u64> = w.residual(&x).iter().map(|v| v.to_bits()).collect();
            let one: Vec<u64> = (w.order..n)
                .map(|k| one_prediction_error(&w.coefficients, &x, k).to_bits())
                .collect();
            assert_eq!(blocked, one, "length {n}");
        }
        assert!(w.residual(&[1.0; 7]).is_empty());
    }
}
