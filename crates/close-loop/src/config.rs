//! Loop parameters ([`LoopConfig`]) and their one-time validation ([`CheckedConfig`]).

use crate::CloseLoopError;
use serde::{Deserialize, Serialize};

/// Parameters of the loop. Build with `LoopConfig::default()`, change fields, then
/// [`LoopConfig::check`] once. Every threshold is documented in `docs/equations/close-loop.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoopConfig {
    /// Fraction of the recording used for fitting (the rest is held out), in [0.2, 0.8].
    pub fit_fraction: f64,
    /// Target Welch bin width, Hz (the segment length is the power of two nearest fs / this).
    pub resolution_hz: f64,
    /// Minimum number of 50 %-overlapped Welch segments in each of the two parts (≥ 4); the
    /// segment length halves until both parts hold this many.
    pub min_segments: usize,
    /// Lower edge of the scored band, Hz.
    pub band_low_hz: f64,
    /// Upper edge of the scored band as a fraction of fs (≤ 0.5).
    pub band_high_fraction: f64,
    /// Stop rule: an effect is kept only if it lowers the held-out error by at least this
    /// fraction of the error before it (0.01 = 1 %).
    pub margin: f64,
    /// At most this many effects are added besides amplitude modulations, which have their own
    /// budget (`runner::MAX_MODULATIONS`, 2) in whichever phase they are found.
    pub max_effects: usize,
    /// A residual line must stand this far (dB) above the running median of the log spectral ratio.
    pub line_threshold_db: f64,
    /// A broadband bump or dip of the smoothed log ratio must exceed this (dB) to propose a mode.
    pub broadband_threshold_db: f64,
    /// An envelope line must stand this far (dB) above its local median to propose a modulation.
    pub envelope_threshold_db: f64,
    /// Largest speed offset searched, as a fraction (0.05 = ±5 %: an induction motor's nameplate
    /// speed is off by its slip, 3–5 %; ±2 % until 2026-11-25).
    pub max_speed_offset: f64,
    /// Smallest speed step proposed, as a fraction.
    pub min_speed_step: f64,
    /// A line within this relative distance of k·fr (k ≤ `max_harmonic_order`) is a shaft harmonic.
    pub harmonic_tolerance: f64,
    /// Highest shaft order named a shaft harmonic.
    pub max_harmonic_order: u32,
    /// Mains frequency of the test rig, if known: a line nearer a multiple of it than of fr is a tone.
    pub line_frequency_hz: Option<f64>,
    /// At most this many line candidates, the strongest by power, are evaluated per round, and
    /// up to half as many more that stand ≥ 30 dB over their neighbourhood (plain lines that
    /// stronger, broader ones crowd out; `runner::lines::PLAIN_LINE_DB`).
    pub max_line_candidates: usize,
    /// Floor of the regularised log-spectral distance, dB relative to the measurement's mean PSD
    /// over the scored band (see [`crate::metric::regularised_lsd`]).
    pub floor_db: f64,
    /// The loop stops once the held-out error is within this factor of the error a correct
    /// model would show from estimation variance alone ([`crate::metric::estimation_lsd`]).
    pub noise_stop_factor: f64,
    /// An effect must also lower the held-out error by at least this much, dB.
    pub min_improvement_db: f64,
    /// A phase-coherent line (tone, shaft harmonic or comb in the measurement channel) is also
    /// kept when it removes at least this fraction of the held-out signal's power from the
    /// time-domain residual without raising the held-out spectral error: a narrow line covers a
    /// few of the scored bins, so the bin-averaged distance alone under-rates a strong one.
    #[serde(default = "default_min_line_power")]
    pub min_line_power: f64,
    /// Highest AR order tried for the structural path.
    pub max_path_order: usize,
}

impl Default for LoopConfig {
    fn default() -> Self {
        Self {
            fit_fraction: 0.5,
            resolution_hz: 12.0,
            min_segments: 8,
            band_low_hz: 5.0,
            band_high_fraction: 0.45,
            margin: 0.02,
            max_effects: 8,
            line_threshold_db: 6.0,
            broadband_threshold_db: 3.0,
            envelope_threshold_db: 8.0,
            max_speed_offset: 0.05,
            min_speed_step: 1e-3,
            harmonic_tolerance: 0.004,
            max_harmonic_order: 20,
            line_frequency_hz: None,
            max_line_candidates: 8,
            floor_db: -30.0,
            noise_stop_factor: 1.25,
            min_improvement_db: 0.03,
            min_line_power: default_min_line_power(),
            max_path_order: 128,
        }
    }
}

fn default_min_line_power() -> f64 {
    0.005
}

/// A validated [`LoopConfig`].
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedConfig(pub(crate) LoopConfig);

impl CheckedConfig {
    /// The parameters.
    pub fn get(&self) -> &LoopConfig {
        &self.0
    }
}

fn range(name: &'static str, value: f64, min: f64, max: f64) -> Result<(), CloseLoopError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        Err(CloseLoopError::ParameterOutOfRange {
            name,
            value,
            min,
            max,
        })
    }
}

impl LoopConfig {
    /// Validate once.
    ///
    /// # Errors
    /// [`CloseLoopError::ParameterOutOfRange`] naming the first bad field.
    pub fn check(self) -> Result<CheckedConfig, CloseLoopError> {
        range("fit_fraction", self.fit_fraction, 0.2, 0.8)?;
        range("resolution_hz", self.resolution_hz, 1e-3, 1e4)?;
        range("min_segments", self.min_segments as f64, 4.0, 1e4)?;
        range("band_low_hz", self.band_low_hz, 0.0, 1e6)?;
        range("band_high_fraction", self.band_high_fraction, 0.05, 0.5)?;
        range("margin", self.margin, 0.0, 0.5)?;
        range("max_effects", self.max_effects as f64, 0.0, 100.0)?;
        range("line_threshold_db", self.line_threshold_db, 1.0, 60.0)?;
        range(
            "broadband_threshold_db",
            self.broadband_threshold_db,
            0.5,
            60.0,
        )?;
        range(
            "envelope_threshold_db",
            self.envelope_threshold_db,
            1.0,
            60.0,
        )?;
        range("max_speed_offset", self.max_speed_offset, 1e-4, 0.2)?;
        range(
            "min_speed_step",
            self.min_speed_step,
            1e-6,
            self.max_speed_offset,
        )?;
        range("harmonic_tolerance", self.harmonic_tolerance, 1e-5, 0.1)?;
        range(
            "max_harmonic_order",
            f64::from(self.max_harmonic_order),
            1.0,
            1000.0,
        )?;
        if let Some(f) = self.line_frequency_hz {
            range("line_frequency_hz", f, 1.0, 1e4)?;
        }
        range(
            "max_line_candidates",
            self.max_line_candidates as f64,
            0.0,
            100.0,
        )?;
        range("floor_db", self.floor_db, -200.0, 0.0)?;
        range("noise_stop_factor", self.noise_stop_factor, 0.0, 10.0)?;
        range("min_improvement_db", self.min_improvement_db, 0.0, 10.0)?;
        range("min_line_power", self.min_line_power, 0.0, 1.0)?;
        range("max_path_order", self.max_path_order as f64, 2.0, 256.0)?;
        Ok(CheckedConfig(self))
    }
}
