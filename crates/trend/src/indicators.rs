//! Per-recording indicators from the signal alone: RMS, peak, crest factor, kurtosis (the
//! workspace's `residual_features::stats`), mean square, and the band velocity RMS 10–1000 Hz
//! of ISO 20816 with its zone.

use crate::error::{Result, TrendError};

/// Standard gravity, m/s² per g (ISO 80000-3).
pub const STANDARD_GRAVITY: f64 = 9.806_65;
/// The velocity band of ISO 20816-3 (and ISO 10816-3 before it) for machines above 600 rpm, Hz.
pub const VELOCITY_BAND_HZ: [f64; 2] = [10.0, 1000.0];

/// The unit of the samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Unit {
    /// Standard gravity.
    #[serde(rename = "g")]
    G,
    /// m/s².
    #[serde(rename = "m/s^2")]
    MetersPerSecondSquared,
    /// Not stated: the velocity stays in the samples' unit × s, and no zone is given.
    #[serde(rename = "unknown")]
    Unknown,
}

impl Unit {
    /// Parse `g`, `m/s^2` (or `m/s2`, `m/s²`) or `unknown`.
    ///
    /// # Errors
    /// [`TrendError::Config`] for anything else.
    pub fn parse(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "g" => Ok(Unit::G),
            "m/s^2" | "m/s2" | "m/s²" => Ok(Unit::MetersPerSecondSquared),
            "unknown" | "" => Ok(Unit::Unknown),
            o => Err(TrendError::Config(format!(
                "unit `{o}`: expected g, m/s^2 or unknown"
            ))),
        }
    }

    /// m/s² per sample unit (`None` when unknown).
    pub fn to_si(self) -> Option<f64> {
        match self {
            Unit::G => Some(STANDARD_GRAVITY),
            Unit::MetersPerSecondSquared => Some(1.0),
            Unit::Unknown => None,
        }
    }

    /// The unit's code.
    pub fn code(self) -> &'static str {
        match self {
            Unit::G => "g",
            Unit::MetersPerSecondSquared => "m/s^2",
            Unit::Unknown => "unknown",
        }
    }
}

/// An ISO 20816-3 machine group and foundation (the standard's Annex A, Tables A.1 and A.2;
/// the same boundaries as ISO 10816-3:2009 Annex A): group 1 = large machines, 300 kW–50 MW
/// rated power; group 2 = medium machines, 15–300 kW.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MachineGroup {
    /// Group 1, rigid foundation.
    Group1Rigid,
    /// Group 1, flexible foundation.
    Group1Flexible,
    /// Group 2, rigid foundation.
    Group2Rigid,
    /// Group 2, flexible foundation.
    Group2Flexible,
}

impl MachineGroup {
    /// Parse `group1-rigid`, `group1-flexible`, `group2-rigid`, `group2-flexible` (`1r`, `2f`, …
    /// too).
    ///
    /// # Errors
    /// [`TrendError::Config`] for anything else.
    pub fn parse(s: &str) -> Result<Self> {
        match s
            .trim()
            .to_ascii_lowercase()
            .replace(['_', ' '], "-")
            .as_str()
        {
            "group1-rigid" | "1-rigid" | "1r" => Ok(Self::Group1Rigid),
            "group1-flexible" | "1-flexible" | "1f" => Ok(Self::Group1Flexible),
            "group2-rigid" | "2-rigid" | "2r" => Ok(Self::Group2Rigid),
            "group2-flexible" | "2-flexible" | "2f" => Ok(Self::Group2Flexible),
            o => Err(TrendError::Config(format!(
                "machine group `{o}`: expected group1-rigid, group1-flexible, group2-rigid or group2-flexible"
            ))),
        }
    }

    /// The zone boundaries A/B, B/C, C/D, r.m.s. velocity in mm/s (ISO 20816-3:2022 Annex A).
    pub fn boundaries_mm_s(self) -> [f64; 3] {
        match self {
            Self::Group1Rigid => [2.3, 4.5, 7.1],
            Self::Group1Flexible => [3.5, 7.1, 11.0],
            Self::Group2Rigid => [1.4, 2.8, 4.5],
            Self::Group2Flexible => [2.3, 4.5, 7.1],
        }
    }

    /// The zone of a velocity r.m.s. in mm/s: `A` below A/B, `B` below B/C, `C` below C/D,
    /// else `D`.
    pub fn zone(self, v_mm_s: f64) -> Zone {
        let [ab, bc, cd] = self.boundaries_mm_s();
        if v_mm_s < ab {
            Zone::A
        } else if v_mm_s < bc {
            Zone::B
        } else if v_mm_s < cd {
            Zone::C
        } else {
            Zone::D
        }
    }
}

/// An ISO 20816 evaluation zone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
pub enum Zone {
    /// Newly commissioned machines.
    A,
    /// Unrestricted long-term operation.
    B,
    /// Restricted operation: not for long-term operation.
    C,
    /// Vibration severe enough to cause damage.
    D,
}

/// The signal indicators of one recording.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SignalIndicators {
    /// RMS, sample unit.
    pub rms: f64,
    /// Peak |x|, sample unit.
    pub peak: f64,
    /// Peak / RMS.
    pub crest: f64,
    /// Kurtosis m4/m2² (3 for a Gaussian).
    pub kurtosis: f64,
    /// Mean square, sample unit².
    pub mean_square: f64,
    /// Band velocity r.m.s. 10–1000 Hz: mm/s when the unit is known, else sample unit × s.
    pub velocity_rms: f64,
}

/// RMS, peak, crest factor, kurtosis, mean square and band velocity of `x` at `fs_hz` in `unit`.
///
/// # Errors
/// [`TrendError::BadRecording`] (named `name`) for an empty, non-finite or constant recording.
pub fn signal_indicators(
    name: &str,
    x: &[f64],
    fs_hz: f64,
    unit: Unit,
) -> Result<SignalIndicators> {
    let bad = |e: residual_features::FeatureError| TrendError::BadRecording {
        name: name.to_string(),
        reason: e.to_string(),
    };
    use residual_features::stats;
    let rms = stats::rms(x).map_err(bad)?;
    let peak = stats::peak(x).map_err(bad)?;
    let crest = stats::crest_factor(x).map_err(bad)?;
    let kurtosis = stats::kurtosis(x).map_err(bad)?;
    let v =
        band_velocity_rms(x, fs_hz, VELOCITY_BAND_HZ).ok_or_else(|| TrendError::BadRecording {
            name: name.to_string(),
            reason: format!(
                "too short or too slowly sampled for a velocity band {}–{} Hz at {fs_hz} Hz",
                VELOCITY_BAND_HZ[0], VELOCITY_BAND_HZ[1]
            ),
        })?;
    let velocity_rms = match unit.to_si() {
        Some(k) => v * k * 1000.0,
        None => v,
    };
    Ok(SignalIndicators {
        rms,
        peak,
        crest,
        kurtosis,
        mean_square: rms * rms,
        velocity_rms,
    })
}

/// The r.m.s. of the velocity of acceleration `x` (sampled at `fs_hz`) in `band` Hz (upper edge
/// cut at Nyquist), integrated in the frequency domain: the mean removed, the one-sided
/// DFT `A_k` (rectangular window), and by Parseval v_rms² = Σ_{f_k in band} 2|A_k|² /
/// (N² (2π f_k)²) — division by jω is integration, bins outside the band are dropped (ISO 20816's
/// band-limited velocity). Unit: `x`'s unit × s. `None` when no DFT bin falls in the band or the
/// rate is not positive.
pub fn band_velocity_rms(x: &[f64], fs_hz: f64, band: [f64; 2]) -> Option<f64> {
    let n = x.len();
    if n < 4 || !fs_hz.is_finite() || fs_hz <= 0.0 {
        return None;
    }
    // the mean removed (a DC offset is not vibration; it sits in bin 0, outside the band)
    let nf = n as f64;
    let xm = x.iter().sum::<f64>() / nf;
    let mut buf: Vec<f64> = x.iter().map(|v| v - xm).collect();
    let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut spec = fft.make_output_vec();
    fft.process(&mut buf, &mut spec).ok()?;
    let df = fs_hz / nf;
    let hi = band[1].min(fs_hz / 2.0);
    let mut sum = 0.0;
    let mut bins = 0usize;
    for (k, c) in spec.iter().enumerate().skip(1) {
        let f = k as f64 * df;
        if f < band[0] || f > hi {
            continue;
        }
        // the Nyquist bin (even n) has no mirror
        let two = if n % 2 == 0 && k == n / 2 { 1.0 } else { 2.0 };
        let w = 2.0 * std::f64::consts::PI * f;
        sum += two * c.norm_sqr() / (w * w);
        bins += 1;
    }
    if bins == 0 {
        return None;
    }
    let v = (sum / (nf * nf)).sqrt();
    v.is_finite().then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn velocity_of_a_sine_is_amplitude_over_omega() {
        let fs = 10_000.0;
        let f = 100.0;
        let a = 9.806_65; // 1 g peak
        let x: Vec<f64> = (0..10_000)
            .map(|i| a * (2.0 * std::f64::consts::PI * f * i as f64 / fs).sin())
            .collect();
        let v = band_velocity_rms(&x, fs, VELOCITY_BAND_HZ).unwrap();
        let expected = a / (2.0 * std::f64::consts::PI * f) / 2f64.sqrt();
        assert!((v / expected - 1.0).abs() < 1e-9, "{v} vs {expected}");
        // outside the band: nothing
        let y: Vec<f64> = (0..10_000)
            .map(|i| (2.0 * std::f64::consts::PI * 2000.0 * i as f64 / fs).sin())
            .collect();
        let in_band = 1.0 / (2.0 * std::f64::consts::PI * 2000.0) / 2f64.sqrt();
        assert!(band_velocity_rms(&y, fs, VELOCITY_BAND_HZ).unwrap() < 1e-9 * in_band);
        let s = signal_indicators("s", &x, fs, Unit::MetersPerSecondSquared).unwrap();
        assert!((s.velocity_rms / (expected * 1000.0) - 1.0).abs() < 1e-9);
        let g = signal_indicators("s", &x, fs, Unit::G).unwrap();
        assert!((g.velocity_rms / s.velocity_rms - STANDARD_GRAVITY).abs() < 1e-9);
    }

    #[test]
    fn zones() {
        let g = MachineGroup::parse("group2-rigid").unwrap();
        assert_eq!(g.zone(1.0), Zone::A);
        assert_eq!(g.zone(2.0), Zone::B);
        assert_eq!(g.zone(3.0), Zone::C);
        assert_eq!(g.zone(4.5), Zone::D);
        assert!(MachineGroup::parse("group3").is_err());
    }

    #[test]
    fn bad_recordings_are_named() {
        let e = signal_indicators("r7", &[1.0; 100], 1000.0, Unit::G).unwrap_err();
        assert!(e.to_string().starts_with("r7:"), "{e}");
        let e = signal_indicators("r8", &[0.0, f64::NAN, 1.0], 1000.0, Unit::G).unwrap_err();
        assert!(e.to_string().starts_with("r8:"), "{e}");
    }

    proptest::proptest! {
        /// Crest factor and kurtosis do not change with the sensor's gain; RMS, peak and
        /// velocity scale with it.
        #[test]
        fn scale_invariance(seed in 0u64..1000, gain in 0.01f64..100.0) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let x: Vec<f64> = (0..2048).map(|_| rng.random_range(-1.0..1.0)).collect();
            let y: Vec<f64> = x.iter().map(|v| v * gain).collect();
            let a = signal_indicators("x", &x, 20_000.0, Unit::G).unwrap();
            let b = signal_indicators("y", &y, 20_000.0, Unit::G).unwrap();
            proptest::prop_assert!((a.crest - b.crest).abs() < 1e-9 * a.crest);
            proptest::prop_assert!((a.kurtosis - b.kurtosis).abs() < 1e-9 * a.kurtosis);
            proptest::prop_assert!((b.rms / a.rms / gain - 1.0).abs() < 1e-9);
            proptest::prop_assert!((b.velocity_rms / a.velocity_rms / gain - 1.0).abs() < 1e-9);
        }
    }
}
