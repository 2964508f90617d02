//! The run's parameters ([`TrendConfig`]) and their check ([`CheckedTrendConfig`]).

use crate::error::{Result, TrendError};
use crate::indicators::{MachineGroup, Unit};

/// Fewest baseline recordings the thresholds accept: a median and a MAD of fewer than five
/// values move by a large part of their spread when one value changes.
pub const MIN_BASELINES: usize = 5;
/// Default k of the thresholds median + k·σ̂ (σ̂ = 1.4826·MAD).
pub const DEFAULT_K: f64 = 5.0;
/// Default m of the m-of-n alarm rule.
pub const DEFAULT_M: usize = 3;
/// Default n of the m-of-n alarm rule.
pub const DEFAULT_N: usize = 4;
/// Default exponent p of the speed normalisation (amplitude / (rpm/rpm_ref)^p).
pub const DEFAULT_SPEED_EXPONENT: f64 = 1.5;
/// Smallest spread of the baseline's speeds, max/min − 1, at which the speed exponent of each
/// amplitude indicator is fitted on the baseline instead of taking `speed_exponent`.
pub const SPEED_FIT_MIN_SPAN: f64 = 0.10;
/// Default severity level: this multiple of an indicator's threshold.
pub const DEFAULT_LEVEL_FACTOR: f64 = 10.0;
/// Smallest spread σ̂ of a log10-domain threshold, decades (2 % in ratio terms per σ̂): a
/// floor for baselines that agree to a few parts per thousand (simulated, quantised).
pub const MIN_LOG_SPREAD: f64 = 0.02;
/// Smallest spread σ̂ of an evidence threshold (−log10 p), decades.
pub const MIN_EVIDENCE_SPREAD: f64 = 0.5;

/// The parameters of a trend run. [`TrendConfig::check`] validates them.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrendConfig {
    /// The first this many recordings (in time order) are the healthy baseline: thresholds
    /// from their statistics, the diagnosis' reference, the observers' healthy model.
    pub baseline_count: usize,
    /// k of the thresholds median + k·σ̂ ([`DEFAULT_K`]).
    pub k: f64,
    /// An indicator alarms when above its threshold in `m` of `n` consecutive recordings.
    pub m: usize,
    /// See `m`.
    pub n: usize,
    /// Exponent p of the speed normalisation of amplitude indicators (energies take 2p).
    pub speed_exponent: f64,
    /// Fit p per amplitude indicator on the baseline (log-log least squares, clamped to
    /// [0, 4]) when the baseline's speeds span at least [`SPEED_FIT_MIN_SPAN`].
    pub fit_speed_exponent: bool,
    /// The severity level an indicator is projected to: this multiple of its threshold (the
    /// velocity's zone C boundary instead, when a machine group is given and the unit known).
    pub level_factor: f64,
    /// Unit of the samples.
    pub unit: Unit,
    /// ISO 20816-3 machine group and foundation, for the velocity's zone.
    pub machine_group: Option<MachineGroup>,
    /// Run the diagnosis on every recording (its evidence indicators and verdict).
    pub diagnosis: bool,
    /// Prepare the dissertation's observers on the baseline and trend their residual energy.
    pub observers: bool,
    /// Seconds of baseline the observers' healthy model is fitted on: the first baseline
    /// recording's, joined to the next ones when it is shorter (`pipeline`'s `FIT_SECONDS`,
    /// 1 s, by default).
    pub fit_seconds: f64,
    /// The diagnosis' false-alarm probability per recording.
    pub false_alarm: f64,
    /// The indicators whose alarms make the run's alarm (`None`: the gain-immune ones — crest,
    /// kurtosis, the evidence, the observers' residual share — which a load step or a sensor's
    /// gain does not move; `["all"]`: every indicator with a threshold).
    pub alarm_on: Option<Vec<String>>,
}

impl Default for TrendConfig {
    fn default() -> Self {
        Self {
            baseline_count: 10,
            k: DEFAULT_K,
            m: DEFAULT_M,
            n: DEFAULT_N,
            speed_exponent: DEFAULT_SPEED_EXPONENT,
            fit_speed_exponent: true,
            level_factor: DEFAULT_LEVEL_FACTOR,
            unit: Unit::Unknown,
            machine_group: None,
            diagnosis: true,
            observers: true,
            fit_seconds: pipeline::recordings::FIT_SECONDS,
            false_alarm: diagnosis::DEFAULT_FALSE_ALARM,
            alarm_on: None,
        }
    }
}

/// A [`TrendConfig`] whose values were checked.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CheckedTrendConfig(TrendConfig);

impl CheckedTrendConfig {
    /// The checked values.
    pub fn get(&self) -> &TrendConfig {
        &self.0
    }
}

impl TrendConfig {
    /// Validate: `baseline_count` ≥ [`MIN_BASELINES`] ([`TrendError::TooFewBaselines`]),
    /// 1 ≤ m ≤ n, finite positive k, level factor > 1, fit seconds > 0, speed exponent in
    /// [0, 4], false alarm in (0, 1).
    ///
    /// # Errors
    /// One line per value out of range.
    pub fn check(self) -> Result<CheckedTrendConfig> {
        let bad = |s: String| Err(TrendError::Config(s));
        if self.baseline_count < MIN_BASELINES {
            return Err(TrendError::TooFewBaselines {
                needed: MIN_BASELINES,
                found: self.baseline_count,
            });
        }
        if !(self.k.is_finite() && self.k > 0.0) {
            return bad(format!("k = {} must be finite and positive", self.k));
        }
        if self.m == 0 || self.m > self.n {
            return bad(format!(
                "m-of-n rule {} of {}: need 1 <= m <= n",
                self.m, self.n
            ));
        }
        if !(self.speed_exponent.is_finite() && (0.0..=4.0).contains(&self.speed_exponent)) {
            return bad(format!(
                "speed exponent {} must lie in [0, 4]",
                self.speed_exponent
            ));
        }
        if !(self.level_factor.is_finite() && self.level_factor > 1.0) {
            return bad(format!(
                "level factor {} must be finite and above 1",
                self.level_factor
            ));
        }
        if !(self.fit_seconds.is_finite() && self.fit_seconds > 0.0) {
            return bad(format!(
                "fit seconds {} must be finite and positive",
                self.fit_seconds
            ));
        }
        if !(self.false_alarm > 0.0 && self.false_alarm < 1.0) {
            return bad(format!(
                "false alarm {} must lie in (0, 1)",
                self.false_alarm
            ));
        }
        if self.alarm_on.as_ref().is_some_and(|a| a.is_empty()) {
            return bad("alarm_on lists no indicator".into());
        }
        Ok(CheckedTrendConfig(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks() {
        assert!(TrendConfig::default().check().is_ok());
        let e = TrendConfig {
            baseline_count: 3,
            ..TrendConfig::default()
        }
        .check()
        .unwrap_err();
        assert!(matches!(
            e,
            TrendError::TooFewBaselines {
                needed: 5,
                found: 3
            }
        ));
        for c in [
            TrendConfig {
                m: 5,
                ..TrendConfig::default()
            },
            TrendConfig {
                k: f64::NAN,
                ..TrendConfig::default()
            },
            TrendConfig {
                level_factor: 1.0,
                ..TrendConfig::default()
            },
            TrendConfig {
                alarm_on: Some(vec![]),
                ..TrendConfig::default()
            },
        ] {
            assert!(c.check().is_err());
        }
    }
}
