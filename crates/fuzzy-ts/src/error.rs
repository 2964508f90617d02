//! The crate's single error type.

/// Everything that can go wrong in `fuzzy-ts`. Data problems are errors, never panics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FuzzyError {
    /// A universe of discourse [lo, hi] that is empty, inverted or not finite.
    #[error("invalid range [{lo}, {hi}]")]
    InvalidRange {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// A numeric parameter outside its documented range.
    #[error("parameter {which} = {value} is out of range")]
    InvalidParameter {
        /// Parameter name.
        which: &'static str,
        /// Rejected value.
        value: f64,
    },
    /// A NaN or infinite sample.
    #[error("non-finite value in {which} at index {index}")]
    NonFinite {
        /// Which signal.
        which: &'static str,
        /// Index of the first offending sample.
        index: usize,
    },
    /// Signals of different lengths.
    #[error("length mismatch: expected {expected}, found {found}")]
    LengthMismatch {
        /// Expected length.
        expected: usize,
        /// Found length.
        found: usize,
    },
    /// Too few samples.
    #[error("too few samples: {found}, need at least {needed}")]
    TooFewSamples {
        /// Samples found.
        found: usize,
        /// Samples needed.
        needed: usize,
    },
    /// An error of the underlying ARX-Laguerre identification.
    #[error("ARX-Laguerre identification: {0}")]
    Ident(#[from] laguerre_id::IdentError),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, FuzzyError>;

/// The first non-finite value of `x` ([`sampled_signal::first_non_finite`]), as this crate's
/// error.
pub(crate) fn check_finite(which: &'static str, x: &[f64]) -> Result<()> {
    match sampled_signal::first_non_finite(x) {
        Some((index, _)) => Err(FuzzyError::NonFinite { which, index }),
        None => Ok(()),
    }
}
