//! Per-feature standardisation `(x − μ) / σ`, fitted on the training split only.

use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::Result;

/// Mean and population standard deviation of each feature over the training windows.
/// A feature with zero spread keeps `σ = 1` (it is only centred).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Standardizer {
    /// Per-feature mean.
    pub mean: Vec<f64>,
    /// Per-feature standard deviation (1 where the spread is zero).
    pub std: Vec<f64>,
}

impl Standardizer {
    /// Fit on the windows `train` of `data`.
    ///
    /// # Errors
    /// Empty or out-of-range indices.
    pub fn fit(data: &Dataset, train: &[usize]) -> Result<Self> {
        data.check_indices(train, "training indices")?;
        let d = data.n_features();
        let n = train.len() as f64;
        let mut mean = vec![0.0; d];
        for &i in train {
            for (m, v) in mean.iter_mut().zip(data.row(i)) {
                *m += v;
            }
        }
        for m in &mut mean {
            *m /= n;
        }
        let mut var = vec![0.0; d];
        for &i in train {
            for ((s, v), m) in var.iter_mut().zip(data.row(i)).zip(&mean) {
                *s += (v - m) * (v - m);
            }
        }
        let std = var
            .into_iter()
            .zip(&mean)
            .map(|(s, m)| spread_or_one((s / n).sqrt(), *m))
            .collect();
        Ok(Self { mean, std })
    }

    /// Fit on rows of width `d` given directly (e.g. the transformed windows of one class pair).
    /// With no rows, the identity scaling (`μ = 0`, `σ = 1`).
    pub fn fit_rows<'a>(d: usize, rows: impl Iterator<Item = &'a Vec<f64>> + Clone) -> Self {
        let mut n = 0usize;
        let mut mean = vec![0.0; d];
        for r in rows.clone() {
            n += 1;
            for (m, v) in mean.iter_mut().zip(r) {
                *m += v;
            }
        }
        if n == 0 {
            return Self {
                mean,
                std: vec![1.0; d],
            };
        }
        let nf = n as f64;
        for m in &mut mean {
            *m /= nf;
        }
        let mut var = vec![0.0; d];
        for r in rows {
            for ((s, v), m) in var.iter_mut().zip(r).zip(&mean) {
                *s += (v - m) * (v - m);
            }
        }
        let std = var
            .into_iter()
            .zip(&mean)
            .map(|(s, m)| spread_or_one((s / nf).sqrt(), *m))
            .collect();
        Self { mean, std }
    }

    /// Scale one row.
    pub fn transform(&self, row: &[f64]) -> Vec<f64> {
        row.iter()
            .zip(self.mean.iter().zip(&self.std))
            .map(|(v, (m, s))| (v - m) / s)
            .collect()
    }

    /// Map a scaled value of feature `j` back to original units.
    pub fn inverse(&self, j: usize, scaled: f64) -> f64 {
        scaled * self.std[j] + self.mean[j]
    }
}

/// `sd` unless it is zero or negligible against the mean (then 1: the feature is only centred).
fn spread_or_one(sd: f64, mean: f64) -> f64 {
    if sd > 1e-12 * mean.abs().max(f64::MIN_POSITIVE) && sd > 0.0 {
        sd
    } else {
        1.0
    }
}
