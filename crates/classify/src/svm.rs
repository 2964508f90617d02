//! One-against-one multi-class linear SVM (Piltan 2020, ch. 2–4, "one-against-one" [73]) on
//! `linfa-svm`.
//!
//! For `K` classes, `K(K−1)/2` binary C-SVMs with a linear kernel are trained, one per class pair
//! `(i, j)`, `i < j`, on the standardised windows of those two classes. A window is classified by
//! majority vote; ties go to the lowest class index (libsvm's rule, hence scikit-learn's
//! `SVC.predict`). Each fitted binary machine is stored as its hyperplane `w·x + b`
//! (`b = −ρ`), recovered from linfa's model, so a trained classifier is a few numbers that
//! serialise with serde.

use linfa::prelude::*;
use linfa_svm::Svm;
use ndarray::{Array1, Array2};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::{ClassifyError, Result};
use crate::scale::Standardizer;

/// Hyper-parameters of the linear C-SVM.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinearSvmParams {
    /// Box constraint `C` (> 0), the same for both classes of each pair. Default 1 (sklearn's).
    pub c: f64,
    /// SMO stopping tolerance on the maximal KKT violation (> 0). Default 1e-3 (libsvm's).
    pub tolerance: f64,
}

impl Default for LinearSvmParams {
    fn default() -> Self {
        Self {
            c: 1.0,
            tolerance: 1e-3,
        }
    }
}

impl LinearSvmParams {
    /// Check the ranges.
    ///
    /// # Errors
    /// [`ClassifyError::InvalidParameter`].
    pub fn validate(&self) -> Result<()> {
        if !(self.c.is_finite() && self.c > 0.0) {
            return Err(ClassifyError::InvalidParameter {
                name: "c",
                value: self.c,
                reason: "must be finite and > 0",
            });
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(ClassifyError::InvalidParameter {
                name: "tolerance",
                value: self.tolerance,
                reason: "must be finite and > 0",
            });
        }
        Ok(())
    }
}

/// One binary machine of the one-vs-one ensemble: votes `positive` when `w·z + b ≥ 0`
/// (`z` = standardised features), else `negative`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairMachine {
    /// Class that wins on the non-negative side (the lower class index of the pair).
    pub positive: usize,
    /// Class that wins on the negative side.
    pub negative: usize,
    /// Hyperplane normal in standardised feature space.
    pub weights: Vec<f64>,
    /// Offset `b = −ρ`.
    pub bias: f64,
}

impl PairMachine {
    /// Decision value `w·z + b`.
    pub fn decision(&self, z: &[f64]) -> f64 {
        self.weights.iter().zip(z).map(|(w, v)| w * v).sum::<f64>() + self.bias
    }
}

/// A trained one-vs-one linear SVM, including its feature scaling.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OvoLinearSvm {
    /// Standardisation fitted on the training windows.
    pub scaler: Standardizer,
    /// Number of declared classes (votes are counted over all of them).
    pub n_classes: usize,
    /// Classes present in training, ascending.
    pub classes: Vec<usize>,
    /// The `K(K−1)/2` pair machines, in `(i, j)` lexicographic order.
    pub machines: Vec<PairMachine>,
}

impl OvoLinearSvm {
    /// Train on the windows `train` of `data`.
    ///
    /// # Errors
    /// Invalid parameters, empty/out-of-range indices, [`ClassifyError::SingleClass`], linfa errors.
    pub fn fit(params: &LinearSvmParams, data: &Dataset, train: &[usize]) -> Result<Self> {
        params.validate()?;
        data.check_indices(train, "training indices")?;
        let scaler = Standardizer::fit(data, train)?;
        let d = data.n_features();
        let mut by_class: Vec<Vec<Vec<f64>>> = vec![Vec::new(); data.n_classes()];
        for &i in train {
            by_class[data.label(i)].push(scaler.transform(data.row(i)));
        }
        let classes: Vec<usize> = (0..data.n_classes())
            .filter(|&c| !by_class[c].is_empty())
            .collect();
        if classes.len() < 2 {
            return Err(ClassifyError::SingleClass { class: classes[0] });
        }
        let svm_params = Svm::<f64, bool>::params()
            .pos_neg_weights(params.c, params.c)
            .eps(params.tolerance)
            .linear_kernel();
        let pairs: Vec<(usize, usize)> = classes
            .iter()
            .enumerate()
            .flat_map(|(a, &ci)| classes[a + 1..].iter().map(move |&cj| (ci, cj)))
            .collect();
        // Pairs are independent: train them in parallel, collect in pair order (deterministic).
        let machines = pairs
            .par_iter()
            .map(|&(ci, cj)| {
                let n = by_class[ci].len() + by_class[cj].len();
                let mut x = Array2::<f64>::zeros((n, d));
                let mut y = Array1::<bool>::from_elem(n, false);
                for (r, row) in by_class[ci].iter().chain(&by_class[cj]).enumerate() {
                    for (k, v) in row.iter().enumerate() {
                        x[[r, k]] = *v;
                    }
                    y[r] = r < by_class[ci].len();
                }
                let ds = linfa::Dataset::new(x, y);
                let model = svm_params.fit(&ds)?;
                // Linear kernel: w_k = <w, e_k>.
                let weights = (0..d)
                    .map(|k| {
                        let mut e = Array1::<f64>::zeros(d);
                        e[k] = 1.0;
                        model.weighted_sum(&e)
                    })
                    .collect();
                Ok(PairMachine {
                    positive: ci,
                    negative: cj,
                    weights,
                    bias: -model.rho,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            scaler,
            n_classes: data.n_classes(),
            classes,
            machines,
        })
    }

    /// Votes per class for one raw (unscaled) feature row.
    ///
    /// # Errors
    /// [`ClassifyError::LengthMismatch`] for a row of the wrong width, [`ClassifyError::NonFinite`].
    pub fn votes(&self, row: &[f64]) -> Result<Vec<usize>> {
        check_row(row, self.scaler.mean.len())?;
        let z = self.scaler.transform(row);
        let mut votes = vec![0usize; self.n_classes];
        for m in &self.machines {
            if m.decision(&z) >= 0.0 {
                votes[m.positive] += 1;
            } else {
                votes[m.negative] += 1;
            }
        }
        Ok(votes)
    }

    /// Predicted class of one raw feature row (majority vote, ties to the lowest class index).
    ///
    /// # Errors
    /// As [`OvoLinearSvm::votes`].
    pub fn predict_row(&self, row: &[f64]) -> Result<usize> {
        let votes = self.votes(row)?;
        Ok(argmax_first(&votes))
    }
}

/// Index of the first maximum.
pub(crate) fn argmax_first(v: &[usize]) -> usize {
    let mut best = 0;
    for (i, &x) in v.iter().enumerate() {
        if x > v[best] {
            best = i;
        }
    }
    best
}

/// Width and finiteness check for a row given to a trained model.
pub(crate) fn check_row(row: &[f64], d: usize) -> Result<()> {
    if row.len() != d {
        return Err(ClassifyError::LengthMismatch {
            what: "feature row width",
            expected: d,
            found: row.len(),
        });
    }
    if let Some((j, &v)) = row.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(ClassifyError::NonFinite {
            row: 0,
            column: j,
            value: v,
        });
    }
    Ok(())
}
