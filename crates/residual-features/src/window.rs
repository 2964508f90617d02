//! Windowing of a 1-D series: fixed length, fixed count, or sliding with a hop.
//!
//! The dissertation cuts each residual recording into windows (400 per class) before computing the
//! energy of eq. (2.46)/(5.33). Here the tail handling is always explicit ([`TailPolicy`]): samples
//! that do not fill a window are either rejected with an error, discarded *and reported* in
//! [`WindowSet::discarded_tail`], or kept as a shorter last window. Nothing is padded.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::error::{FeatureError, Result};

/// How to cut a series into windows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Windowing {
    /// Non-overlapping windows of `length` samples, starting at sample 0.
    FixedLength {
        /// Samples per window (> 0).
        length: usize,
    },
    /// Exactly `count` non-overlapping windows of `floor(n / count)` samples each, starting at 0
    /// (the dissertation's "N windows per recording").
    FixedCount {
        /// Number of windows (> 0).
        count: usize,
    },
    /// Overlapping windows of `length` samples whose starts are `hop` samples apart.
    Sliding {
        /// Samples per window (> 0).
        length: usize,
        /// Distance between window starts (> 0; `hop < length` overlaps, `hop > length` skips).
        hop: usize,
    },
}

/// What to do with trailing samples that do not fill a whole window.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TailPolicy {
    /// Return [`FeatureError::TailRejected`] unless the series divides exactly.
    Reject,
    /// Drop the tail and report its range in [`WindowSet::discarded_tail`].
    Discard,
    /// Keep the tail as a last, shorter window (not allowed with [`Windowing::FixedCount`],
    /// which promises equal windows).
    KeepShort,
}

/// A validated windowing plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowPlan {
    windowing: Windowing,
    tail: TailPolicy,
}

impl WindowPlan {
    /// Validate a windowing and a tail policy.
    ///
    /// # Errors
    /// [`FeatureError::InvalidParameter`] for zero lengths, counts or hops, and for
    /// `FixedCount` combined with `KeepShort`.
    pub fn new(windowing: Windowing, tail: TailPolicy) -> Result<Self> {
        let bad = |name, value: usize, reason| {
            Err(FeatureError::InvalidParameter {
                name,
                value: value as f64,
                reason,
            })
        };
        match windowing {
            Windowing::FixedLength { length: 0 } => bad("length", 0, "must be > 0")?,
            Windowing::FixedCount { count: 0 } => bad("count", 0, "must be > 0")?,
            Windowing::FixedCount { count } if tail == TailPolicy::KeepShort => bad(
                "count",
                count,
                "FixedCount makes equal windows; use Discard or Reject for the tail",
            )?,
            Windowing::Sliding { length: 0, .. } => bad("length", 0, "must be > 0")?,
            Windowing::Sliding { hop: 0, .. } => bad("hop", 0, "must be > 0")?,
            _ => {}
        }
        Ok(Self { windowing, tail })
    }

    /// The windowing this plan uses.
    pub fn windowing(&self) -> Windowing {
        self.windowing
    }

    /// The tail policy this plan uses.
    pub fn tail_policy(&self) -> TailPolicy {
        self.tail
    }

    /// Cut a series of `len` samples into windows.
    ///
    /// # Errors
    /// [`FeatureError::TooShort`] if not even one full window fits, and
    /// [`FeatureError::TailRejected`] when the tail policy is `Reject` and samples are left over.
    pub fn split(&self, len: usize) -> Result<WindowSet> {
        let (length, hop, full) = match self.windowing {
            Windowing::FixedLength { length } => (length, length, len / length),
            Windowing::FixedCount { count } => {
                let length = len / count;
                if length == 0 {
                    return Err(FeatureError::TooShort {
                        needed: count,
                        found: len,
                    });
                }
                (length, length, count)
            }
            Windowing::Sliding { length, hop } => {
                let full = if len >= length {
                    (len - length) / hop + 1
                } else {
                    0
                };
                (length, hop, full)
            }
        };
        if full == 0 {
            return Err(FeatureError::TooShort {
                needed: length,
                found: len,
            });
        }
        let mut ranges: Vec<Range<usize>> = (0..full).map(|i| i * hop..i * hop + length).collect();
        // First sample not covered by any full window (and not inside the last one).
        let covered_end = ranges.last().map_or(0, |r| r.end);
        let next_start = full * hop;
        let tail_start = covered_end.max(next_start.min(len));
        let tail = tail_start..len;
        let mut discarded_tail = None;
        if !tail.is_empty() {
            match self.tail {
                TailPolicy::Reject => {
                    return Err(FeatureError::TailRejected {
                        len,
                        tail: tail.len(),
                    });
                }
                TailPolicy::Discard => discarded_tail = Some(tail),
                TailPolicy::KeepShort => ranges.push(next_start.min(tail.start)..len),
            }
        }
        Ok(WindowSet {
            ranges,
            discarded_tail,
            len,
        })
    }

    /// Cut `signal` into borrowed windows (see [`WindowPlan::split`]).
    ///
    /// # Errors
    /// As [`WindowPlan::split`].
    pub fn windows<'a>(&self, signal: &'a [f64]) -> Result<Vec<&'a [f64]>> {
        let set = self.split(signal.len())?;
        Ok(set.ranges.iter().map(|r| &signal[r.clone()]).collect())
    }
}

/// The result of cutting a series: window ranges plus what was left out.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct WindowSet {
    ranges: Vec<Range<usize>>,
    discarded_tail: Option<Range<usize>>,
    len: usize,
}

impl WindowSet {
    /// Sample ranges of the windows, in time order.
    pub fn ranges(&self) -> &[Range<usize>] {
        &self.ranges
    }

    /// Number of windows.
    pub fn len(&self) -> usize {
        self.ranges.len()
    }

    /// True if there are no windows (never the case for a successful split).
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// Samples dropped under [`TailPolicy::Discard`], if any.
    pub fn discarded_tail(&self) -> Option<Range<usize>> {
        self.discarded_tail.clone()
    }

    /// Length of the series that was split.
    pub fn series_len(&self) -> usize {
        self.len
    }
}
