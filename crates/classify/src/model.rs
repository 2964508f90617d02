//! The classifier choice as an enum, and a trained classifier that serialises with serde.

use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::Result;
use crate::svm::{LinearSvmParams, OvoLinearSvm};
use crate::tree::{GiniTree, GiniTreeParams};

/// Which classifier to train (ch. 2–4: one-vs-one linear SVM; ch. 5: Gini tree).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ClassifierSpec {
    /// One-against-one linear SVM on standardised features.
    LinearSvm(LinearSvmParams),
    /// Gini (CART) decision tree.
    GiniTree(GiniTreeParams),
}

impl ClassifierSpec {
    /// The dissertation's one-vs-one linear SVM with the pipelines' defaults
    /// ([`LinearSvmParams::default`]: C = 10, per-pair standardisation, balanced class weights,
    /// no feature transform).
    pub fn svm() -> Self {
        Self::LinearSvm(LinearSvmParams::default())
    }

    /// The SVM with explicit parameters, e.g.
    /// `ClassifierSpec::svm_with(LinearSvmParams::default().with_transform(FeatureTransform::Log10))`.
    pub fn svm_with(params: LinearSvmParams) -> Self {
        Self::LinearSvm(params)
    }

    /// scikit-learn's `StandardScaler` + `SVC(kernel='linear', C=1)` ([`LinearSvmParams::sklearn`]).
    pub fn svm_sklearn() -> Self {
        Self::LinearSvm(LinearSvmParams::sklearn())
    }

    /// The dissertation's tree with default parameters (grown until pure).
    pub fn tree() -> Self {
        Self::GiniTree(GiniTreeParams::default())
    }

    /// Short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            Self::LinearSvm(_) => "one-vs-one linear SVM",
            Self::GiniTree(_) => "Gini decision tree",
        }
    }

    /// Train on the windows `train` of `data`.
    ///
    /// # Errors
    /// As [`OvoLinearSvm::fit`] / [`GiniTree::fit`].
    pub fn fit(&self, data: &Dataset, train: &[usize]) -> Result<TrainedClassifier> {
        Ok(match self {
            Self::LinearSvm(p) => TrainedClassifier::LinearSvm(OvoLinearSvm::fit(p, data, train)?),
            Self::GiniTree(p) => TrainedClassifier::GiniTree(GiniTree::fit(p, data, train)?),
        })
    }
}

/// A trained classifier; save with `serde_json::to_string`, load with `serde_json::from_str`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum TrainedClassifier {
    /// A trained one-vs-one linear SVM.
    LinearSvm(OvoLinearSvm),
    /// A trained Gini tree.
    GiniTree(GiniTree),
}

impl TrainedClassifier {
    /// Predicted class of one raw feature row.
    ///
    /// # Errors
    /// Wrong row width or non-finite values.
    pub fn predict_row(&self, row: &[f64]) -> Result<usize> {
        match self {
            Self::LinearSvm(m) => m.predict_row(row),
            Self::GiniTree(m) => m.predict_row(row),
        }
    }

    /// Predicted classes of the windows `idx` of `data`.
    ///
    /// # Errors
    /// Empty/out-of-range indices, wrong row width.
    pub fn predict(&self, data: &Dataset, idx: &[usize]) -> Result<Vec<usize>> {
        data.check_indices(idx, "test indices")?;
        idx.iter().map(|&i| self.predict_row(data.row(i))).collect()
    }

    /// Serialise to JSON.
    ///
    /// # Errors
    /// [`crate::ClassifyError::Json`].
    pub fn to_json(&self) -> Result<String> {
        Ok(serde_json::to_string(self)?)
    }

    /// Deserialise from JSON.
    ///
    /// # Errors
    /// [`crate::ClassifyError::Json`].
    pub fn from_json(s: &str) -> Result<Self> {
        Ok(serde_json::from_str(s)?)
    }
}
