//! Fit metrics of a prediction: RMSE, NRMSE, residual variance.

use crate::error::{IdentError, Result, check_finite};
use serde::{Deserialize, Serialize};

/// Prediction-error summary over a scored range.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitMetrics {
    /// Samples scored.
    pub n: usize,
    /// Root-mean-square error √(mean (y − ŷ)²).
    pub rmse: f64,
    /// Normalised RMSE ‖y − ŷ‖ / ‖y − ȳ‖ (0 = perfect, 1 = as good as the mean).
    pub nrmse: f64,
    /// Variance of the residual y − ŷ (about its own mean).
    pub residual_variance: f64,
    /// Variance of the measured signal over the scored range.
    pub signal_variance: f64,
}

impl FitMetrics {
    /// Metrics of `yhat` against `y` (same length ≥ 2, finite).
    pub fn compute(y: &[f64], yhat: &[f64]) -> Result<Self> {
        if y.len() != yhat.len() {
            return Err(IdentError::LengthMismatch {
                expected: y.len(),
                found: yhat.len(),
            });
        }
        if y.len() < 2 {
            return Err(IdentError::TooFewSamples {
                found: y.len(),
                needed: 2,
            });
        }
        check_finite("y", y)?;
        check_finite("yhat", yhat)?;
        let n = y.len() as f64;
        let ym = y.iter().sum::<f64>() / n;
        let sv = y.iter().map(|v| (v - ym).powi(2)).sum::<f64>() / n;
        let r: Vec<f64> = y.iter().zip(yhat).map(|(a, b)| a - b).collect();
        let rm = r.iter().sum::<f64>() / n;
        let mse = r.iter().map(|v| v * v).sum::<f64>() / n;
        let rv = r.iter().map(|v| (v - rm).powi(2)).sum::<f64>() / n;
        let nrmse = if sv > 0.0 {
            (mse / sv).sqrt()
        } else {
            f64::INFINITY
        };
        Ok(Self {
            n: y.len(),
            rmse: mse.sqrt(),
            nrmse,
            residual_variance: rv,
            signal_variance: sv,
        })
    }
}
