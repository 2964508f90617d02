//! The crate's single error type.

use thiserror::Error;

/// Everything that can go wrong when diagnosing a recording. Every message is one line and
/// names the offending value; nothing in this crate panics on data or returns NaN.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DiagnosisError {
    /// Shaft speed outside the accepted range.
    #[error("shaft speed {rpm} rpm out of range ({min}..={max} rpm)")]
    RpmOutOfRange {
        /// Given speed.
        rpm: f64,
        /// Smallest accepted speed.
        min: f64,
        /// Largest accepted speed.
        max: f64,
    },
    /// Sampling rate outside the accepted range.
    #[error("sampling rate {fs_hz} Hz out of range ({min}..={max} Hz)")]
    SampleRateOutOfRange {
        /// Given rate.
        fs_hz: f64,
        /// Smallest accepted rate.
        min: f64,
        /// Largest accepted rate.
        max: f64,
    },
    /// The sampling rate is too low for the fault lines at this speed.
    #[error(
        "sampling rate {fs_hz} Hz too low for {rpm} rpm: a demodulation band at least {needed_hz:.0} Hz wide (3 harmonics of the highest fault line) must fit between {needed_hz:.0} Hz and fs/2"
    )]
    SampleRateTooLow {
        /// Given rate.
        fs_hz: f64,
        /// Given speed.
        rpm: f64,
        /// Narrowest demodulation band needed, Hz.
        needed_hz: f64,
    },
    /// The recording is too short for the envelope spectrum to resolve the fault lines.
    #[error(
        "recording too short: {samples} samples = {turns:.1} shaft turns, needs at least {min_turns} turns ({needed} samples)"
    )]
    TooShort {
        /// Samples given.
        samples: usize,
        /// Samples needed.
        needed: usize,
        /// Shaft turns given.
        turns: f64,
        /// Shaft turns needed.
        min_turns: f64,
    },
    /// The baseline is too short to fit the AR model.
    #[error("baseline too short: {samples} samples, needs at least {needed}")]
    BaselineTooShort {
        /// Samples given.
        samples: usize,
        /// Samples needed.
        needed: usize,
    },
    /// No samples.
    #[error("{what} has no samples")]
    Empty {
        /// `"recording"` or `"baseline"`.
        what: &'static str,
    },
    /// A NaN or infinite sample.
    #[error("{what} has a non-finite sample {value} at index {index}")]
    NonFinite {
        /// `"recording"` or `"baseline"`.
        what: &'static str,
        /// Index of the first offending sample.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// Baseline and recording were sampled at different rates.
    #[error(
        "baseline sampled at {baseline_hz} Hz but the recording at {recording_hz} Hz (resample the baseline first)"
    )]
    SampleRateMismatch {
        /// Recording's rate.
        recording_hz: f64,
        /// Baseline's rate.
        baseline_hz: f64,
    },
    /// The signal is constant or otherwise cannot be modelled.
    #[error("{what} is degenerate: {reason}")]
    Degenerate {
        /// `"recording"` or `"baseline"`.
        what: &'static str,
        /// Why.
        reason: String,
    },
    /// Options that do not check (a speed range empty, inverted or out of range, a false-alarm
    /// probability out of range, no speed at all).
    #[error("invalid options: {reason}")]
    InvalidOptions {
        /// What is wrong.
        reason: String,
    },
    /// No speed declared, no shaft comb found, and a range too wide to search the fault lines
    /// over.
    #[error(
        "no shaft comb found between {low_rpm} and {high_rpm} rpm and no speed declared: give --rpm, or a range no wider than {max_ratio}:1"
    )]
    SpeedNotFound {
        /// Lower end of the range searched, rpm.
        low_rpm: f64,
        /// Upper end, rpm.
        high_rpm: f64,
        /// Widest range (high/low) searched without a comb.
        max_ratio: f64,
    },
    /// A spectral computation failed (should not happen after validation; reported, not panicked).
    #[error("spectral computation failed: {0}")]
    Spectral(#[from] residual_features::FeatureError),
    /// Training or applying the optional classifier failed (`classify`'s error, as text).
    #[error("classifier: {0}")]
    Classifier(String),
    /// A trained classifier was applied to a diagnosis with another reference.
    #[error(
        "the classifier was trained on {trained}-referenced diagnoses, this one is {got}-referenced"
    )]
    ReferenceMismatch {
        /// Reference of the training diagnoses.
        trained: String,
        /// Reference of the diagnosis to classify.
        got: String,
    },
    /// A trained classifier was applied to a recording at another sampling rate.
    #[error(
        "the classifier was trained at {trained_hz} Hz, the recording is at {recording_hz} Hz: resample it (or train at its rate)"
    )]
    ClassifierRate {
        /// Rate of the recording.
        recording_hz: f64,
        /// Rate of the training recordings.
        trained_hz: f64,
    },
    /// A saved classifier that this version cannot use.
    #[error("trained classifier file: {reason}")]
    ClassifierFormat {
        /// What is wrong.
        reason: String,
    },
}

#[cfg(feature = "trained")]
impl From<classify::ClassifyError> for DiagnosisError {
    fn from(e: classify::ClassifyError) -> Self {
        Self::Classifier(e.to_string())
    }
}

/// Result with [`DiagnosisError`].
pub type Result<T> = std::result::Result<T, DiagnosisError>;

impl DiagnosisError {
    /// Why samples and a rate do not make a [`crate::Signal`], for the recording or baseline
    /// `what`, with the messages this crate gives: a rate that is not finite and > 0 is
    /// [`DiagnosisError::SampleRateOutOfRange`], no samples [`DiagnosisError::Empty`], a NaN or
    /// infinite sample [`DiagnosisError::NonFinite`].
    pub fn signal(what: &'static str, e: sampled_signal::SignalError) -> Self {
        match e {
            sampled_signal::SignalError::InvalidRate { fs_hz } => Self::SampleRateOutOfRange {
                fs_hz,
                min: crate::MIN_FS_HZ,
                max: crate::MAX_FS_HZ,
            },
            sampled_signal::SignalError::Empty => Self::Empty { what },
            sampled_signal::SignalError::NonFinite { index, value } => {
                Self::NonFinite { what, index, value }
            }
        }
    }
}

/// [`DiagnosisError::signal`] of the recording.
impl From<sampled_signal::SignalError> for DiagnosisError {
    fn from(e: sampled_signal::SignalError) -> Self {
        Self::signal("recording", e)
    }
}
