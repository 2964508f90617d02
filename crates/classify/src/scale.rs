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
            .map(|(s, m)| {
                let sd = (s / n).sqrt();
                if sd > 1e-12 * m.abs().max(f64::MIN_POSITIVE) && sd > 0.0 {
                    sd
                } else {
                    1.0
                }
            })
            .collect();
        Ok(Self { mean, std })
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
