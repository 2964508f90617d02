//! The crate's single error type.

/// Everything that can go wrong in `laguerre-id`. Data problems are errors, never panics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum IdentError {
    /// A Laguerre pole outside the open unit interval (−1, 1) (eq. 4.5 needs |ζ| < 1).
    #[error("Laguerre pole {value} is outside the open interval (-1, 1)")]
    PoleOutOfRange {
        /// The rejected pole.
        value: f64,
    },
    /// A model order outside the supported range.
    #[error("order {which} = {found} is outside [{min}, {max}]")]
    OrderOutOfRange {
        /// Which order (`"n_a"`, `"n_b"`, ...).
        which: &'static str,
        /// The rejected order.
        found: usize,
        /// Smallest accepted value.
        min: usize,
        /// Largest accepted value.
        max: usize,
    },
    /// An input order was given without an input signal, or an input signal without an order.
    #[error("input order n_b = {n_b} does not match the input signal (present: {has_input})")]
    InputMismatch {
        /// Input order requested.
        n_b: usize,
        /// Whether an input signal was supplied.
        has_input: bool,
    },
    /// Output and input signals of different lengths.
    #[error("signal length mismatch: expected {expected}, found {found}")]
    LengthMismatch {
        /// Expected length (the output's).
        expected: usize,
        /// Length found.
        found: usize,
    },
    /// Too few samples to identify the requested number of parameters.
    #[error("too few samples: {found} usable, need at least {needed}")]
    TooFewSamples {
        /// Usable samples found.
        found: usize,
        /// Samples needed.
        needed: usize,
    },
    /// A NaN or infinite sample.
    #[error("non-finite value in {which} at index {index}")]
    NonFinite {
        /// Which signal (`"y"`, `"u"`, ...).
        which: &'static str,
        /// Index of the first offending sample.
        index: usize,
    },
    /// A numeric parameter outside its documented range.
    #[error("parameter {which} = {value} is out of range")]
    InvalidParameter {
        /// Parameter name.
        which: &'static str,
        /// Rejected value.
        value: f64,
    },
    /// The regression matrix is (numerically) rank deficient: the data do not excite the model.
    #[error("regression matrix is rank deficient: rank {rank} of {columns} (data not exciting)")]
    RankDeficient {
        /// Numerical rank found.
        rank: usize,
        /// Number of parameters.
        columns: usize,
    },
    /// A state vector of the wrong size was passed to a predictor.
    #[error("state dimension mismatch: expected {expected}, found {found}")]
    StateMismatch {
        /// Expected number of states.
        expected: usize,
        /// Number found.
        found: usize,
    },
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, IdentError>;

/// Index of the first non-finite value of `x` ([`sampled_signal::first_non_finite`]), as an
/// error.
pub(crate) fn check_finite(which: &'static str, x: &[f64]) -> Result<()> {
    match sampled_signal::first_non_finite(x) {
        Some((index, _)) => Err(IdentError::NonFinite { which, index }),
        None => Ok(()),
    }
}
