//! Watch a machine over time: per-recording health indicators, thresholds from the baseline
//! recordings' own statistics, an m-of-n onset alarm, the fault the diagnosis names at the
//! alarm, and the severity trend after it (issue 57).
//!
//! ```no_run
//! # fn recordings() -> Vec<trend::TrendRecording> { vec![] }
//! let recs: Vec<trend::TrendRecording> = recordings(); // in time order, one channel each
//! let cfg = trend::TrendConfig { baseline_count: 10, ..Default::default() }.check()?;
//! let bearing = diagnosis::BearingSpec::parse("6205").expect("catalogue bearing");
//! let report = trend::analyse(&recs, trend::TimeAxis::Seconds, &bearing, &cfg)?;
//! if let Some(a) = &report.alarm {
//!     println!("alarm at {} on {:?}: {}", a.name, a.indicators, a.fault);
//! }
//! # Ok::<(), trend::TrendError>(())
//! ```
//!
//! The indicators: RMS, peak, crest factor, kurtosis (`residual_features::stats`), the band
//! velocity RMS 10–1000 Hz ([`indicators::band_velocity_rms`], mm/s and the ISO 20816-3 zone
//! when the unit is known), the signal's mean square, the diagnosis' evidence −log10 p_healthy
//! per hypothesis (`diagnosis`, against the baseline's healthy reference), and the residual mean
//! square of the dissertation's observers HOSTSMO, PFLO, SMALPIO, AFSMO (`pipeline`: the healthy
//! model prepared and tuned once on the first baseline recording), absolute and relative to the
//! signal's own mean square. Every choice (k·MAD, the m-of-n rule, the speed exponent, the
//! level) is in `docs/equations/trend.md`.
//!
//! Every function returns [`TrendError`] (one line naming the file or recording), never panics
//! on data, and no NaN leaves it: a value that cannot be computed is `None` with a note.

pub mod alarm;
mod analyse;
mod config;
mod error;
pub mod indicators;
pub mod order;

pub use alarm::{Domain, Severity, Threshold};
pub use analyse::{
    ALARM_ON_ALL, Alarm, DIAGNOSIS_BASELINE_SECONDS, IndicatorInfo, OBSERVERS, ObserverSetup,
    Onset, Row, RuleMet, Scale, Timing, TrendRecording, TrendReport, analyse,
    analyse_with_progress,
};
pub use config::{
    CheckedTrendConfig, DEFAULT_K, DEFAULT_LEVEL_FACTOR, DEFAULT_M, DEFAULT_N,
    DEFAULT_SPEED_EXPONENT, MIN_BASELINES, MIN_EVIDENCE_SPREAD, MIN_LOG_SPREAD, SPEED_FIT_MIN_SPAN,
    TrendConfig,
};
pub use error::{Result, TrendError};

/// The former name of [`TrendRecording`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed to `TrendRecording`: one recording of a trend sequence, with its time and \
            speed (a recording as read from a file is `bearing_data::Recording`)"
)]
pub type Recording = TrendRecording;
pub use indicators::{MachineGroup, SignalIndicators, Unit, Zone};
pub use order::{IndexEntry, NameTime, TimeAxis, order_names, parse_index, parse_name};

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
