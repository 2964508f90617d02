//! One-against-one multi-class linear SVM (Piltan 2020, ch. 2–4, "one-against-one" [73]) on
//! `linfa-svm`.
//!
//! For `K` classes, `K(K−1)/2` binary C-SVMs with a linear kernel are trained, one per class pair
//! `(i, j)`, `i < j`, on the windows of those two classes. A window is classified by majority
//! vote; ties go to the lowest class index (libsvm's rule, hence scikit-learn's `SVC.predict`).
//!
//! Conditioning (see `docs/equations/classify.md`, "Conditioning of the pair machines"):
//! 1. an optional monotone [`FeatureTransform`] (`log10` of strictly positive features such as
//!    energy), applied to every row before anything else;
//! 2. standardisation fitted on the training windows only, either of each pair
//!    ([`Scaling::PerPair`], default) or of all classes ([`Scaling::Global`], scikit-learn's
//!    `StandardScaler` + `SVC`);
//! 3. per-pair class weights ([`ClassWeight::Balanced`], default: scikit-learn's
//!    `class_weight='balanced'` restricted to the pair) passed to linfa as `C₊`, `C₋`.
//!
//! Each fitted binary machine is stored as its own scaling plus its hyperplane `w·z + b`
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

/// Which windows the standardisation `(x − μ) / σ` of a pair machine is fitted on (always the
/// training split only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Scaling {
    /// Each pair machine `(i, j)` gets its own `μ, σ` from the training windows of classes `i`
    /// and `j`. Default: with features spanning orders of magnitude (raw energy) a global `σ` is
    /// dominated by the loudest class, and two quiet classes end up a tiny distance apart in
    /// scaled units, where a soft margin with moderate `C` gives up the smaller class.
    #[default]
    PerPair,
    /// One `μ, σ` from all training windows, shared by every pair machine (scikit-learn's
    /// `StandardScaler` followed by `SVC`); used to compare like with like.
    Global,
}

/// Per-class weights of the box constraint `C` in each pair machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ClassWeight {
    /// `C_i = C · n/(2 n_i)`, `C_j = C · n/(2 n_j)` with `n = n_i + n_j` the pair's training
    /// windows (scikit-learn's `class_weight='balanced'`; sklearn computes `N/(K n_k)` over all
    /// classes, which differs from ours only by a common factor per pair). The weights average 1
    /// over the pair's windows, so `C` keeps its meaning. Default: CWRU has 163 normal windows
    /// against 400 per fault class in the dissertation's set-up.
    #[default]
    Balanced,
    /// `C_i = C_j = C` (libsvm / scikit-learn default).
    Uniform,
}

/// Monotone transform applied to every feature before scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FeatureTransform {
    /// Features used as given. Default, because feature sets may contain signed features
    /// (skewness, mean) that `log10` cannot take.
    #[default]
    Identity,
    /// `log10(x)`; every feature must be strictly positive (energy, RMS, power), else
    /// [`ClassifyError::NonPositive`]. For a 1-D feature this does not change what a threshold
    /// classifier can express (the map is monotone); it only conditions the optimisation when
    /// the feature spans orders of magnitude.
    Log10,
}

impl FeatureTransform {
    /// Apply to one row.
    ///
    /// # Errors
    /// [`ClassifyError::NonPositive`] (row reported as 0) for `Log10` and a value `≤ 0`.
    pub fn apply(&self, row: &[f64]) -> Result<Vec<f64>> {
        match self {
            Self::Identity => Ok(row.to_vec()),
            Self::Log10 => row
                .iter()
                .enumerate()
                .map(|(j, &v)| {
                    if v > 0.0 {
                        Ok(v.log10())
                    } else {
                        Err(ClassifyError::NonPositive {
                            row: 0,
                            column: j,
                            value: v,
                        })
                    }
                })
                .collect(),
        }
    }
}

/// Hyper-parameters of the linear C-SVM.
///
/// Construct with [`LinearSvmParams::default`] (the pipelines' settings) or
/// [`LinearSvmParams::sklearn`] (libsvm / scikit-learn's `SVC` defaults), then adjust fields.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinearSvmParams {
    /// Box constraint `C` (> 0). Default 10 on standardised features: with per-pair scaling
    /// and balanced weights, `C = 1` already separates separable clusters, and 10 leaves margin
    /// for heavy-tailed windows without the slow convergence of a near-hard margin
    /// (scikit-learn's default is 1, see [`LinearSvmParams::sklearn`]).
    pub c: f64,
    /// SMO stopping tolerance on the maximal KKT violation (> 0). Default 1e-3 (libsvm's).
    pub tolerance: f64,
    /// Standardisation per pair (default) or global.
    #[serde(default = "legacy_scaling")]
    pub scaling: Scaling,
    /// Class weights per pair: balanced (default) or uniform.
    #[serde(default = "legacy_weight")]
    pub class_weight: ClassWeight,
    /// Transform applied to every feature before scaling. Default identity.
    #[serde(default)]
    pub transform: FeatureTransform,
}

/// Models saved before the conditioning options existed used global scaling.
fn legacy_scaling() -> Scaling {
    Scaling::Global
}

/// Models saved before the conditioning options existed used uniform weights.
fn legacy_weight() -> ClassWeight {
    ClassWeight::Uniform
}

impl Default for LinearSvmParams {
    fn default() -> Self {
        Self {
            c: 10.0,
            tolerance: 1e-3,
            scaling: Scaling::PerPair,
            class_weight: ClassWeight::Balanced,
            transform: FeatureTransform::Identity,
        }
    }
}

impl LinearSvmParams {
    /// scikit-learn's `StandardScaler` + `SVC(kernel='linear', C=1, tol=1e-3)`: global
    /// scaling, uniform class weights, no transform, `C = 1`.
    pub fn sklearn() -> Self {
        Self {
            c: 1.0,
            tolerance: 1e-3,
            scaling: Scaling::Global,
            class_weight: ClassWeight::Uniform,
            transform: FeatureTransform::Identity,
        }
    }

    /// The same parameters with `C` replaced.
    pub fn with_c(mut self, c: f64) -> Self {
        self.c = c;
        self
    }

    /// The same parameters with the scaling replaced.
    pub fn with_scaling(mut self, scaling: Scaling) -> Self {
        self.scaling = scaling;
        self
    }

    /// The same parameters with the class weights replaced.
    pub fn with_class_weight(mut self, class_weight: ClassWeight) -> Self {
        self.class_weight = class_weight;
        self
    }

    /// The same parameters with the feature transform replaced.
    pub fn with_transform(mut self, transform: FeatureTransform) -> Self {
        self.transform = transform;
        self
    }

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

/// One binary machine of the one-vs-one ensemble: votes `positive` when `w·z + b ≥ 0`, with
/// `z = (t(x) − μ) / σ` the pair's standardisation of the transformed features, else `negative`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairMachine {
    /// Class that wins on the non-negative side (the lower class index of the pair).
    pub positive: usize,
    /// Class that wins on the negative side.
    pub negative: usize,
    /// The standardisation this machine was trained with (the pair's own under
    /// [`Scaling::PerPair`], a copy of the global one under [`Scaling::Global`]).
    pub scaler: Standardizer,
    /// Hyperplane normal in standardised feature space.
    pub weights: Vec<f64>,
    /// Offset `b = −ρ`.
    pub bias: f64,
    /// Box constraints `(C₊, C₋)` used for the positive and negative class.
    pub c: (f64, f64),
}

impl PairMachine {
    /// Decision value `w·z + b` for an already standardised row `z`.
    pub fn decision(&self, z: &[f64]) -> f64 {
        self.weights.iter().zip(z).map(|(w, v)| w * v).sum::<f64>() + self.bias
    }

    /// Decision value for a transformed but unscaled row (applies this machine's scaling).
    pub fn decision_unscaled(&self, x: &[f64]) -> f64 {
        self.decision(&self.scaler.transform(x))
    }
}

/// A trained one-vs-one linear SVM, including its feature conditioning.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OvoLinearSvm {
    /// Parameters it was trained with.
    pub params: LinearSvmParams,
    /// Number of features per row.
    pub n_features: usize,
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
    /// Invalid parameters, empty/out-of-range indices, [`ClassifyError::SingleClass`],
    /// [`ClassifyError::NonPositive`] (log transform), linfa errors.
    pub fn fit(params: &LinearSvmParams, data: &Dataset, train: &[usize]) -> Result<Self> {
        params.validate()?;
        data.check_indices(train, "training indices")?;
        let d = data.n_features();
        let mut by_class: Vec<Vec<Vec<f64>>> = vec![Vec::new(); data.n_classes()];
        for &i in train {
            let row = params.transform.apply(data.row(i)).map_err(|e| match e {
                ClassifyError::NonPositive { column, value, .. } => ClassifyError::NonPositive {
                    row: i,
                    column,
                    value,
                },
                other => other,
            })?;
            by_class[data.label(i)].push(row);
        }
        let classes: Vec<usize> = (0..data.n_classes())
            .filter(|&c| !by_class[c].is_empty())
            .collect();
        if classes.len() < 2 {
            return Err(ClassifyError::SingleClass { class: classes[0] });
        }
        let global = match params.scaling {
            Scaling::Global => Some(Standardizer::fit_rows(
                d,
                classes.iter().flat_map(|&c| by_class[c].iter()),
            )),
            Scaling::PerPair => None,
        };
        let pairs: Vec<(usize, usize)> = classes
            .iter()
            .enumerate()
            .flat_map(|(a, &ci)| classes[a + 1..].iter().map(move |&cj| (ci, cj)))
            .collect();
        // Pairs are independent: train them in parallel, collect in pair order (deterministic).
        let machines = pairs
            .par_iter()
            .map(|&(ci, cj)| {
                let (ni, nj) = (by_class[ci].len(), by_class[cj].len());
                let scaler = match &global {
                    Some(s) => s.clone(),
                    None => Standardizer::fit_rows(d, by_class[ci].iter().chain(&by_class[cj])),
                };
                let n = ni + nj;
                let mut x = Array2::<f64>::zeros((n, d));
                let mut y = Array1::<bool>::from_elem(n, false);
                for (r, row) in by_class[ci].iter().chain(&by_class[cj]).enumerate() {
                    for (k, v) in scaler.transform(row).into_iter().enumerate() {
                        x[[r, k]] = v;
                    }
                    y[r] = r < ni;
                }
                let c = match params.class_weight {
                    ClassWeight::Uniform => (params.c, params.c),
                    ClassWeight::Balanced => (
                        params.c * n as f64 / (2.0 * ni as f64),
                        params.c * n as f64 / (2.0 * nj as f64),
                    ),
                };
                let model = Svm::<f64, bool>::params()
                    .pos_neg_weights(c.0, c.1)
                    .eps(params.tolerance)
                    .linear_kernel()
                    .fit(&linfa::Dataset::new(x, y))?;
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
                    scaler,
                    weights,
                    bias: -model.rho,
                    c,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            params: *params,
            n_features: d,
            n_classes: data.n_classes(),
            classes,
            machines,
        })
    }

    /// Votes per class for one raw (untransformed, unscaled) feature row.
    ///
    /// # Errors
    /// [`ClassifyError::LengthMismatch`] for a row of the wrong width, [`ClassifyError::NonFinite`],
    /// [`ClassifyError::NonPositive`] under [`FeatureTransform::Log10`].
    pub fn votes(&self, row: &[f64]) -> Result<Vec<usize>> {
        check_row(row, self.n_features)?;
        let x = self.params.transform.apply(row)?;
        let mut votes = vec![0usize; self.n_classes];
        for m in &self.machines {
            if m.decision_unscaled(&x) >= 0.0 {
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
