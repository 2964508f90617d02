//! Confusion matrix, per-class accuracy and the average classification accuracy of eq. (5.37).

use serde::{Deserialize, Serialize};

use crate::error::{ClassifyError, Result};

/// Counts of (true class, predicted class); rows are true classes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConfusionMatrix {
    /// `counts[t][p]` = windows of true class `t` predicted as `p`.
    pub counts: Vec<Vec<usize>>,
}

impl ConfusionMatrix {
    /// An all-zero matrix for `n_classes` classes.
    pub fn zeros(n_classes: usize) -> Self {
        Self {
            counts: vec![vec![0; n_classes]; n_classes],
        }
    }

    /// Tally predictions against the truth.
    ///
    /// # Errors
    /// [`ClassifyError::LengthMismatch`], [`ClassifyError::UnknownClass`].
    pub fn from_predictions(
        n_classes: usize,
        truth: &[usize],
        predicted: &[usize],
    ) -> Result<Self> {
        if truth.len() != predicted.len() {
            return Err(ClassifyError::LengthMismatch {
                what: "truth vs predictions",
                expected: truth.len(),
                found: predicted.len(),
            });
        }
        let mut m = Self::zeros(n_classes);
        for (&t, &p) in truth.iter().zip(predicted) {
            for label in [t, p] {
                if label >= n_classes {
                    return Err(ClassifyError::UnknownClass { label, n_classes });
                }
            }
            m.counts[t][p] += 1;
        }
        Ok(m)
    }

    /// Number of classes.
    pub fn n_classes(&self) -> usize {
        self.counts.len()
    }

    /// Total number of windows.
    pub fn total(&self) -> usize {
        self.counts.iter().flatten().sum()
    }

    /// Add another matrix of the same size (pooling folds).
    pub fn add(&mut self, other: &ConfusionMatrix) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        }
    }

    /// Per-class accuracy `TP_m / N_m` in percent (the rows of the dissertation's tables, i.e.
    /// recall); `None` for a class with no test windows.
    pub fn per_class_accuracy(&self) -> Vec<Option<f64>> {
        self.counts
            .iter()
            .enumerate()
            .map(|(m, row)| {
                let n: usize = row.iter().sum();
                (n > 0).then(|| 100.0 * row[m] as f64 / n as f64)
            })
            .collect()
    }

    /// Average classification accuracy, eq. (5.37): `ACA = Σ_m TP_m / N_samples × 100 %`;
    /// `None` when there are no windows.
    pub fn average_accuracy(&self) -> Option<f64> {
        let total = self.total();
        let tp: usize = (0..self.n_classes()).map(|m| self.counts[m][m]).sum();
        (total > 0).then(|| 100.0 * tp as f64 / total as f64)
    }
}
