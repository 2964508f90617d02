//! The crate's single error type.

/// Everything that can go wrong while building or running an observer.
///
/// Data problems (NaN/Inf input, divergence) and parameter problems are reported here;
/// the crate never panics on data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ObserverError {
    /// The measured series was empty.
    #[error("empty measurement series")]
    EmptyInput,
    /// The input series `u` does not have the length of the measurement series `y`.
    #[error("input length {found} does not match measurement length {expected}")]
    LengthMismatch {
        /// Length of `y`.
        expected: usize,
        /// Length of `u`.
        found: usize,
    },
    /// A vector or matrix has the wrong size.
    #[error("dimension mismatch: expected {expected}, found {found}")]
    DimensionMismatch {
        /// Expected size.
        expected: usize,
        /// Size found.
        found: usize,
    },
    /// A measured or input sample is NaN or infinite.
    #[error("non-finite input sample at index {index}")]
    NonFiniteInput {
        /// Sample index.
        index: usize,
    },
    /// The observer state became non-finite or exceeded the divergence limit.
    #[error("observer diverged at sample {index} (|value| = {value:e}, limit {limit:e})")]
    Diverged {
        /// Sample index at which divergence was detected.
        index: usize,
        /// Offending magnitude (may be NaN/Inf).
        value: f64,
        /// Divergence limit in force.
        limit: f64,
    },
    /// A parameter is outside its documented range.
    #[error("parameter `{name}` = {value} is out of range ({reason})")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Value supplied.
        value: f64,
        /// Short statement of the admissible range.
        reason: &'static str,
    },
    /// The fault direction has no direct effect on the predicted output (Kᵀf ≈ 0), so the
    /// extended state is not observable through one step.
    #[error("fault direction is invisible in the output: |K^T f| = {value:e}")]
    FaultDirectionInvisible {
        /// |Kᵀ f|.
        value: f64,
    },
    /// The gain design (Riccati iteration) did not converge.
    #[error("gain design did not converge after {iterations} iterations (residual {residual:e})")]
    DesignFailed {
        /// Iterations performed.
        iterations: usize,
        /// Last relative change of the Riccati iterate.
        residual: f64,
    },
    /// The designed gains do not satisfy the LMI of eq. (2.34) for the requested decay rate.
    #[error("LMI (2.34) not satisfied for decay rate gamma = {gamma}")]
    LmiNotSatisfied {
        /// Decay rate tried.
        gamma: f64,
    },
    /// A state-space model (`laguerre_id::StateSpace`) with a wrong shape, a non-finite entry
    /// or a Laguerre pole outside (−1, 1).
    #[error("invalid state-space model: {0}")]
    Model(#[from] laguerre_id::IdentError),
    /// A string did not name an observer kind.
    #[error("unknown observer kind (a string of {length} bytes)")]
    UnknownKind {
        /// Length of the string that failed to parse.
        length: usize,
    },
}
