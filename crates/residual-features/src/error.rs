//! The crate's single error type.

use thiserror::Error;

/// Everything that can go wrong while windowing a signal or computing window features.
///
/// Every variant carries the numbers needed to see what was wrong; nothing in this crate panics
/// on data.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum FeatureError {
    /// The input signal or window is empty.
    #[error("empty input")]
    Empty,
    /// The input has fewer samples than the operation needs.
    #[error("input too short: needs at least {needed} samples, found {found}")]
    TooShort {
        /// Minimum number of samples required.
        needed: usize,
        /// Number of samples given.
        found: usize,
    },
    /// A sample is NaN or infinite.
    #[error("non-finite sample {value} at index {index}")]
    NonFinite {
        /// Index of the first offending sample.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A parameter is outside its documented range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name as spelled in the config struct.
        name: &'static str,
        /// The offending value (converted to f64).
        value: f64,
        /// What the valid range is.
        reason: &'static str,
    },
    /// The window has zero variance (or zero RMS), so a normalised statistic is undefined.
    #[error("statistic `{statistic}` is undefined for a window of {len} samples with zero spread")]
    ZeroSpread {
        /// Which statistic was asked for.
        statistic: &'static str,
        /// Window length.
        len: usize,
    },
    /// The signal length does not divide into windows under [`crate::TailPolicy::Reject`].
    #[error(
        "{tail} trailing samples of {len} do not fill a window and the tail policy rejects them"
    )]
    TailRejected {
        /// Signal length.
        len: usize,
        /// Number of samples left over.
        tail: usize,
    },
    /// A tachometer channel whose pulses span too few shaft turns (a constant channel has none).
    #[error(
        "tachometer: {pulses} pulses span {turns:.1} shaft turns; order tracking needs at least {needed_turns} (is it a pulse channel, and are the pulses per turn right?)"
    )]
    TachPulses {
        /// Pulses found.
        pulses: usize,
        /// Turns they span at the pulses per turn given.
        turns: f64,
        /// Turns needed.
        needed_turns: f64,
    },
    /// A tachometer pulse interval far from its neighbours': a missed or spurious pulse.
    #[error(
        "tachometer: pulse interval {pulse} is {ratio:.2} times the median of its neighbours (a missed or spurious pulse)"
    )]
    TachIrregular {
        /// Index of the interval (1 = between the first two pulses).
        pulse: usize,
        /// Its length over its neighbours' median.
        ratio: f64,
    },
    /// The tachometer and the signal differ in length.
    #[error(
        "tachometer has {tach} samples but the signal {signal}: they must be recorded together"
    )]
    TachLength {
        /// Signal samples.
        signal: usize,
        /// Tachometer samples.
        tach: usize,
    },
    /// The FFT backend reported a length or buffer mismatch (should not happen; reported, not panicked).
    #[error("FFT buffer mismatch for length {len}")]
    Fft {
        /// Transform length.
        len: usize,
    },
}

/// Shorthand result type.
pub type Result<T> = std::result::Result<T, FeatureError>;

/// Check that a slice is non-empty and finite ([`sampled_signal::first_non_finite`]).
pub(crate) fn check_finite(x: &[f64]) -> Result<()> {
    if x.is_empty() {
        return Err(FeatureError::Empty);
    }
    if let Some((index, value)) = sampled_signal::first_non_finite(x) {
        return Err(FeatureError::NonFinite { index, value });
    }
    Ok(())
}

/// Check that a parameter is finite and strictly positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FeatureError::InvalidParameter {
            name,
            value,
            reason: "must be finite and > 0",
        })
    }
}
