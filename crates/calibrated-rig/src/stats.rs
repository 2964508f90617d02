//! What simulated and measured recordings are compared on, and the calibration targets.

use close_loop::CloseLoopError;
use close_loop::spectrum::Welch;
use serde::{Deserialize, Serialize};

/// Band edges of [`SignalStats::band_energy`], Hz (the last band ends at fs/2).
pub const BANDS_HZ: [f64; 4] = [0.0, 1000.0, 2000.0, 4000.0];

/// What a simulated and a measured recording are compared on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SignalStats {
    /// RMS (mean removed), recording units.
    pub rms: f64,
    /// Kurtosis (not excess; 3 for a Gaussian).
    pub kurtosis: f64,
    /// Crest factor max|y|/RMS.
    pub crest: f64,
    /// Mean square in 0–1, 1–2, 2–4 and 4 kHz–fs/2 (Welch PSD integrated), units².
    pub band_energy: [f64; 4],
    /// Prominence of the fault line in the envelope spectrum, dB: the largest envelope power
    /// within ±1.5 % of the fault frequency over the median power of ±20 % around it (`None`
    /// without a fault frequency).
    pub line_prominence_db: Option<f64>,
}

/// [`SignalStats`] of `y` at `fs`, with the envelope line at `fault_hz` when given.
///
/// # Errors
/// [`CloseLoopError::TooShort`] below 4096 samples, and the errors of the Welch PSD and the
/// envelope spectrum.
pub fn signal_stats(
    y: &[f64],
    fs: f64,
    fault_hz: Option<f64>,
) -> Result<SignalStats, CloseLoopError> {
    if y.len() < 4096 {
        return Err(CloseLoopError::TooShort {
            needed: 4096,
            found: y.len(),
        });
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let c: Vec<f64> = y.iter().map(|v| v - mean).collect();
    let stat = |r: Result<f64, residual_features::FeatureError>| match r {
        Ok(v) => Ok(v),
        Err(residual_features::FeatureError::ZeroSpread { .. }) => Err(CloseLoopError::ZeroSignal),
        Err(e) => Err(CloseLoopError::Spectral {
            reason: e.to_string(),
        }),
    };
    let (rms, kurtosis, crest) = (
        stat(residual_features::rms(&c))?,
        stat(residual_features::kurtosis(&c))?,
        stat(residual_features::crest_factor(&c))?,
    );
    let welch = Welch::new(fs, 1024)?;
    let p = welch.try_psd(y)?;
    let mut band = [0.0; 4];
    for (k, v) in p.iter().enumerate() {
        let f = welch.frequency(k);
        let b = BANDS_HZ.iter().rposition(|&e| f >= e).unwrap_or(0);
        band[b] += v * welch.df();
    }
    let line_prominence_db = match fault_hz {
        Some(f0) => line_prominence_db(y, fs, f0)?,
        None => None,
    };
    Ok(SignalStats {
        rms,
        kurtosis,
        crest,
        band_energy: band,
        line_prominence_db,
    })
}

/// Prominence of the line at `f0` in the full-band envelope spectrum of `y`, dB: the largest
/// value within ±1.5 % of `f0` over the median of ±20 % around it ([`SignalStats`]); `None` when
/// `1.2·f0` is not below Nyquist.
///
/// # Errors
/// The envelope spectrum's errors (a record too short or not finite).
pub fn line_prominence_db(y: &[f64], fs: f64, f0: f64) -> Result<Option<f64>, CloseLoopError> {
    if !(f0 > 0.0 && 1.2 * f0 < 0.5 * fs) {
        return Ok(None);
    }
    let (e, de) = close_loop::spectrum::envelope_periodogram(y, fs)?;
    let idx = |f: f64| ((f / de).round() as usize).min(e.len() - 1);
    let peak = e[idx(0.985 * f0)..=idx(1.015 * f0)]
        .iter()
        .copied()
        .fold(0.0, f64::max);
    let around: Vec<f64> = e[idx(0.8 * f0)..=idx(1.2 * f0)].to_vec();
    let med = close_loop::spectrum::median(&around);
    Ok(Some(10.0 * (peak / med.max(1e-300)).log10()))
}

/// Simulated against measured statistics of one condition, and the calibration targets of
/// issue "A simulator calibrated to the measured rig": RMS and every band energy within a factor
/// [`Comparison::FACTOR`], kurtosis within [`Comparison::KURTOSIS_TOLERANCE`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// Of the measured recording.
    pub measured: SignalStats,
    /// Of the simulated one.
    pub simulated: SignalStats,
}

impl Comparison {
    /// Largest ratio (either way) of RMS and band energies that meets the target.
    pub const FACTOR: f64 = 1.5;
    /// Largest relative kurtosis error that meets the target.
    pub const KURTOSIS_TOLERANCE: f64 = 0.3;

    /// RMS simulated / measured.
    pub fn rms_ratio(&self) -> f64 {
        self.simulated.rms / self.measured.rms
    }
    /// Kurtosis simulated / measured − 1.
    pub fn kurtosis_error(&self) -> f64 {
        self.simulated.kurtosis / self.measured.kurtosis - 1.0
    }
    /// Band energies simulated / measured.
    pub fn band_ratios(&self) -> [f64; 4] {
        std::array::from_fn(|b| self.simulated.band_energy[b] / self.measured.band_energy[b])
    }
    /// Whether a ratio is within [`Comparison::FACTOR`] either way.
    pub fn within(ratio: f64) -> bool {
        (1.0 / Self::FACTOR..=Self::FACTOR).contains(&ratio)
    }
    /// (RMS, all four bands, kurtosis) targets met.
    pub fn meets(&self) -> (bool, bool, bool) {
        (
            Self::within(self.rms_ratio()),
            self.band_ratios().iter().all(|r| Self::within(*r)),
            self.kurtosis_error().abs() <= Self::KURTOSIS_TOLERANCE,
        )
    }
}
