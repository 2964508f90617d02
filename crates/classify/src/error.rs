//! The crate's single error type.

use thiserror::Error;

/// Everything that can go wrong while building a dataset, training, splitting or scoring.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ClassifyError {
    /// No samples (or no training/test samples where some are needed).
    #[error("empty dataset: {what}")]
    Empty {
        /// Which collection was empty.
        what: &'static str,
    },
    /// Training needs at least two classes.
    #[error("only one class ({class}) present in the training data")]
    SingleClass {
        /// The class index that was present.
        class: usize,
    },
    /// A feature value is NaN or infinite.
    #[error("non-finite feature {value} at row {row}, column {column}")]
    NonFinite {
        /// Row (window) index.
        row: usize,
        /// Column (feature) index.
        column: usize,
        /// The offending value.
        value: f64,
    },
    /// A feature value is zero or negative where a logarithm is taken
    /// ([`crate::FeatureTransform::Log10`]).
    #[error("non-positive feature {value} at row {row}, column {column} (log transform needs > 0)")]
    NonPositive {
        /// Row (window) index (0 for a single row given to a trained model).
        row: usize,
        /// Column (feature) index.
        column: usize,
        /// The offending value.
        value: f64,
    },
    /// Two collections that must have equal lengths do not.
    #[error("length mismatch for {what}: expected {expected}, found {found}")]
    LengthMismatch {
        /// What was being compared.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Found length.
        found: usize,
    },
    /// A class label is outside `0..n_classes`.
    #[error("class label {label} out of range for {n_classes} classes")]
    UnknownClass {
        /// The label found.
        label: usize,
        /// Number of declared classes.
        n_classes: usize,
    },
    /// A sample index is outside the dataset.
    #[error("sample index {index} out of range for {len} samples")]
    IndexOutOfRange {
        /// The index found.
        index: usize,
        /// Number of samples.
        len: usize,
    },
    /// A parameter is outside its documented range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// Valid range.
        reason: &'static str,
    },
    /// linfa-svm reported an error.
    #[error("linfa-svm: {0}")]
    Svm(#[from] linfa_svm::SvmError),
    /// linfa (trees or core) reported an error.
    #[error("linfa: {0}")]
    Linfa(#[from] linfa::Error),
    /// (De)serialisation of a model failed.
    #[error("serde_json: {0}")]
    Json(#[from] serde_json::Error),
}

/// Shorthand result type.
pub type Result<T> = std::result::Result<T, ClassifyError>;
