//! The crate's single error type.

/// Everything that can go wrong when closing the loop. Data problems are errors, never panics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CloseLoopError {
    /// The recording is shorter than the fitting plus held-out segments need.
    #[error(
        "recording has {found} samples; the fitting and held-out segments need at least {needed}"
    )]
    TooShort {
        /// Samples needed.
        needed: usize,
        /// Samples present.
        found: usize,
    },
    /// The sampling frequency is not finite and positive.
    #[error("sampling frequency must be finite and > 0 Hz, got {fs}")]
    InvalidSamplingRate {
        /// The value given.
        fs: f64,
    },
    /// The declared shaft speed is not finite and positive.
    #[error("declared speed must be finite and > 0 rpm, got {rpm}")]
    InvalidRpm {
        /// The value given.
        rpm: f64,
    },
    /// A sample of the recording (or of the model output) is NaN or infinite.
    #[error("sample {index} is not finite")]
    NonFinite {
        /// Index of the first bad sample.
        index: usize,
    },
    /// The recording has no samples.
    #[error("the recording has no samples")]
    EmptyRecording,
    /// The recording has zero variance.
    #[error("the recording is constant (zero variance)")]
    ZeroSignal,
    /// A configuration or effect parameter is outside its documented range.
    #[error("parameter `{name}` = {value} is outside [{min}, {max}]")]
    ParameterOutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
    /// The bearing designation is not in the built-in table.
    #[error("unknown bearing `{name}` (known: 6205, 6203)")]
    UnknownBearing {
        /// The designation given.
        name: String,
    },
    /// The fault name is not none or a `+`-joined set of outer|inner|ball.
    #[error("unknown fault `{name}` (none, or a +-joined set of outer|inner|ball)")]
    UnknownFault {
        /// The name given.
        name: String,
    },
    /// The fault names one location twice (`inner+inner`, `ball+inner+ball`).
    #[error(
        "fault `{name}` names {location} twice: give each of inner, outer, ball at most once (e.g. inner+outer)"
    )]
    RepeatedFault {
        /// The name given.
        name: String,
        /// The location named more than once.
        location: bearing_model::FaultLocation,
    },
    /// The declared model failed to produce an output.
    #[error("the declared model failed: {reason}")]
    Model {
        /// What the model reported.
        reason: String,
    },
    /// A spectral estimate (`residual-features`) failed.
    #[error("spectral estimate failed: {reason}")]
    Spectral {
        /// What `residual-features` reported.
        reason: String,
    },
    /// The observer residual (`laguerre-id` identification or an `observers` observer) failed.
    #[error("observer residual failed: {reason}")]
    Observer {
        /// What the identification or the observer reported.
        reason: String,
    },
    /// The declared model returned the wrong number of samples.
    #[error("the declared model returned {found} samples, {expected} were requested")]
    ModelLength {
        /// Samples requested.
        expected: usize,
        /// Samples returned.
        found: usize,
    },
    /// A machine model does not fit the recording or the run it is used in.
    #[error("machine model mismatch: {what} is {found}, the recording needs {expected}")]
    MachineModelMismatch {
        /// What differs ("sampling rate", "bearing", "units", "format", "version").
        what: &'static str,
        /// What the recording or run needs.
        expected: String,
        /// What the machine model holds.
        found: String,
    },
    /// A machine model file could not be parsed.
    #[error("machine model is not valid JSON of the expected form: {reason}")]
    MachineModelFormat {
        /// The parser's message.
        reason: String,
    },
}

/// A [`crate::Signal`] that cannot be built, with this crate's messages: an invalid rate is
/// [`CloseLoopError::InvalidSamplingRate`], no samples [`CloseLoopError::EmptyRecording`], a
/// non-finite sample [`CloseLoopError::NonFinite`].
impl From<sampled_signal::SignalError> for CloseLoopError {
    fn from(e: sampled_signal::SignalError) -> Self {
        match e {
            sampled_signal::SignalError::InvalidRate { fs_hz } => {
                Self::InvalidSamplingRate { fs: fs_hz }
            }
            sampled_signal::SignalError::Empty => Self::EmptyRecording,
            sampled_signal::SignalError::NonFinite { index, .. } => Self::NonFinite { index },
        }
    }
}
