//! A checked sampled signal — samples with their sampling rate — and the one finite-sample check.
//!
//! [`Signal`] is the workspace's one type for "a recording's samples at a rate" (issue 58, one
//! type per concept): `bearing_data::Signal` (what the readers return), the recording
//! `diagnosis::diagnose` and `close_loop::close_loop` take, and the baseline a diagnosis is
//! compared with. It holds its samples as a [`Cow`], so it borrows a caller's slice or owns a
//! vector, and it is built only through [`Signal::new`], which checks the rate (finite, > 0),
//! that there is at least one sample and that every sample is finite: a function taking a
//! `&Signal` needs none of those checks, and a sampling rate can no longer be passed where a
//! shaft speed is expected (two adjacent `f64` arguments).
//!
//! [`first_non_finite`] is the one finite check of the workspace's slices: each crate keeps its
//! own typed error (and its message) in a thin wrapper around it.
//!
//! # Dependencies and why
//! - `thiserror`: [`SignalError`]. Nothing else, so every crate that takes a recording can depend
//!   on this one.
//!
//! # Example
//! ```
//! use sampled_signal::{Signal, SignalError};
//! let x: Vec<f64> = (0..1000).map(|k| (0.1 * k as f64).sin()).collect();
//! let s = Signal::new(&x, 1000.0)?; // borrows x
//! assert_eq!(s.duration_s(), 1.0);
//! let pieces: Vec<Signal<'_>> = s.chunks_exact(300).collect();
//! assert_eq!(pieces.len(), 3);
//! let mut bad = x.clone();
//! bad[7] = f64::NAN;
//! let e = Signal::new(bad, 1000.0).unwrap_err();
//! assert_eq!(e.to_string(), "non-finite sample NaN at index 7");
//! # Ok::<(), SignalError>(())
//! ```

use std::borrow::Cow;

/// Why samples and a rate do not make a [`Signal`]. Every message is one line. The three checks
/// of [`Signal::new`], all of them (exhaustive: a crate maps each to its own error).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum SignalError {
    /// The sampling rate is not finite and > 0.
    #[error("invalid sampling rate {fs_hz} Hz: must be finite and > 0")]
    InvalidRate {
        /// The rate given.
        fs_hz: f64,
    },
    /// No samples.
    #[error("signal has no samples")]
    Empty,
    /// A NaN or infinite sample.
    #[error("non-finite sample {value} at index {index}")]
    NonFinite {
        /// Index of the first offending sample.
        index: usize,
        /// The offending value.
        value: f64,
    },
}

/// The index and value of the first NaN or infinite sample of `x`; `None` when all are finite.
///
/// The workspace's one finite check of a slice: each crate wraps it in its own typed error.
#[must_use]
pub fn first_non_finite(x: &[f64]) -> Option<(usize, f64)> {
    x.iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
        .map(|(i, &v)| (i, v))
}

/// Samples with their sampling rate: the rate finite and > 0, at least one sample, every sample
/// finite — checked once, by [`Signal::new`], the only way to build one.
///
/// `'a` is the lifetime of borrowed samples; a `Signal<'static>` owns them ([`Signal::into_owned`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Signal<'a> {
    samples: Cow<'a, [f64]>,
    fs_hz: f64,
}

impl<'a> Signal<'a> {
    /// `samples` at `fs_hz` Hz: borrowed from a slice (`&x`) or owned (a `Vec<f64>`).
    ///
    /// # Errors
    /// [`SignalError::InvalidRate`] for a rate that is not finite and > 0 (checked first),
    /// [`SignalError::Empty`] for no samples, [`SignalError::NonFinite`] naming the first NaN or
    /// infinite sample.
    pub fn new(samples: impl Into<Cow<'a, [f64]>>, fs_hz: f64) -> Result<Self, SignalError> {
        if !(fs_hz.is_finite() && fs_hz > 0.0) {
            return Err(SignalError::InvalidRate { fs_hz });
        }
        let samples = samples.into();
        if samples.is_empty() {
            return Err(SignalError::Empty);
        }
        if let Some((index, value)) = first_non_finite(&samples) {
            return Err(SignalError::NonFinite { index, value });
        }
        Ok(Self { samples, fs_hz })
    }

    /// The samples.
    #[must_use]
    pub fn samples(&self) -> &[f64] {
        &self.samples
    }

    /// Sampling rate, Hz (finite, > 0).
    #[must_use]
    pub fn fs_hz(&self) -> f64 {
        self.fs_hz
    }

    /// Number of samples (at least one).
    #[must_use]
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Always `false`: a signal has at least one sample.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// Duration, s: samples / rate.
    #[must_use]
    pub fn duration_s(&self) -> f64 {
        self.samples.len() as f64 / self.fs_hz
    }

    /// The same signal borrowing this one's samples.
    #[must_use]
    pub fn borrowed(&self) -> Signal<'_> {
        Signal {
            samples: Cow::Borrowed(&self.samples),
            fs_hz: self.fs_hz,
        }
    }

    /// The same signal owning its samples (copied if borrowed).
    #[must_use]
    pub fn into_owned(self) -> Signal<'static> {
        Signal {
            samples: Cow::Owned(self.samples.into_owned()),
            fs_hz: self.fs_hz,
        }
    }

    /// The samples as a vector (copied if borrowed).
    #[must_use]
    pub fn into_samples(self) -> Vec<f64> {
        self.samples.into_owned()
    }

    /// Consecutive pieces of `len` samples each, borrowing this signal's samples, at its rate;
    /// the last partial piece is dropped (none for `len == 0` or `len` beyond the signal).
    /// Each is a checked signal: a non-empty piece of finite samples.
    pub fn chunks_exact(&self, len: usize) -> impl Iterator<Item = Signal<'_>> {
        let fs_hz = self.fs_hz;
        let pieces: &[f64] = if len == 0 { &[] } else { &self.samples };
        pieces.chunks_exact(len.max(1)).map(move |piece| Signal {
            samples: Cow::Borrowed(piece),
            fs_hz,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_rate_then_emptiness_then_samples() {
        for fs in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                Signal::new(&[1.0][..], fs),
                Err(SignalError::InvalidRate { .. })
            ));
        }
        // the rate is checked first
        assert!(matches!(
            Signal::new(Vec::new(), f64::NAN),
            Err(SignalError::InvalidRate { .. })
        ));
        assert_eq!(Signal::new(Vec::new(), 1.0), Err(SignalError::Empty));
        assert_eq!(
            Signal::new(vec![0.0, 1.0, f64::NEG_INFINITY, f64::NAN], 1.0),
            Err(SignalError::NonFinite {
                index: 2,
                value: f64::NEG_INFINITY
            })
        );
    }

    #[test]
    fn messages_are_one_line() {
        assert_eq!(
            SignalError::InvalidRate { fs_hz: 0.0 }.to_string(),
            "invalid sampling rate 0 Hz: must be finite and > 0"
        );
        assert_eq!(SignalError::Empty.to_string(), "signal has no samples");
        assert_eq!(
            SignalError::NonFinite {
                index: 3,
                value: f64::INFINITY
            }
            .to_string(),
            "non-finite sample inf at index 3"
        );
    }

    #[test]
    fn borrows_owns_and_cuts() {
        let x = vec![1.0, 2.0, 3.0, 4.0, 5.0];
        let s = Signal::new(&x, 2.0).unwrap();
        assert!(matches!(s.samples, Cow::Borrowed(_)));
        assert_eq!((s.len(), s.duration_s(), s.is_empty()), (5, 2.5, false));
        let o = s.clone().into_owned();
        assert!(matches!(o.samples, Cow::Owned(_)));
        assert_eq!(o, s);
        assert_eq!(o.borrowed(), s);
        let pieces: Vec<_> = s.chunks_exact(2).collect();
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[1].samples(), &[3.0, 4.0]);
        assert_eq!(pieces[1].fs_hz(), 2.0);
        assert_eq!(s.chunks_exact(0).count(), 0);
        assert_eq!(s.chunks_exact(6).count(), 0);
        assert_eq!(s.into_samples(), x);
        assert_eq!(first_non_finite(&x), None);
        assert_eq!(first_non_finite(&[]), None);
    }
}

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
