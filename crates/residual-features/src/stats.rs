//! Time-domain window statistics: energy (eq. 2.46 / 3.26 / 4.31 / 5.33) and the usual
//! condition-monitoring set (RMS, peak, crest factor, kurtosis, skewness).
//!
//! All functions reject empty or non-finite input with a typed error. Moments are population
//! moments (divide by N), the convention of Smith & Randall (2015), whose kurtosis values for the
//! CWRU records are quoted in the project references.

use crate::error::{FeatureError, Result, check_finite};

/// Energy of a window, eq. (2.46): `E = Σ r_i²`.
///
/// # Errors
/// [`FeatureError::Empty`] or [`FeatureError::NonFinite`].
pub fn energy(x: &[f64]) -> Result<f64> {
    check_finite(x)?;
    Ok(x.iter().map(|v| v * v).sum())
}

/// Root mean square `sqrt(Σ r_i² / N)`.
///
/// # Errors
/// [`FeatureError::Empty`] or [`FeatureError::NonFinite`].
pub fn rms(x: &[f64]) -> Result<f64> {
    Ok((energy(x)? / x.len() as f64).sqrt())
}

/// Peak absolute value `max |r_i|`.
///
/// # Errors
/// [`FeatureError::Empty`] or [`FeatureError::NonFinite`].
pub fn peak(x: &[f64]) -> Result<f64> {
    check_finite(x)?;
    Ok(x.iter().fold(0.0_f64, |m, v| m.max(v.abs())))
}

/// Crest factor `peak / RMS`.
///
/// # Errors
/// [`FeatureError::ZeroSpread`] for an all-zero window, plus the input errors.
pub fn crest_factor(x: &[f64]) -> Result<f64> {
    let r = rms(x)?;
    if r == 0.0 {
        return Err(FeatureError::ZeroSpread {
            statistic: "crest_factor",
            len: x.len(),
        });
    }
    Ok(peak(x)? / r)
}

/// Central moments (mean, m2, m3, m4), population normalisation.
fn central_moments(x: &[f64]) -> Result<(f64, f64, f64, f64)> {
    check_finite(x)?;
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let (mut m2, mut m3, mut m4) = (0.0, 0.0, 0.0);
    for v in x {
        let d = v - mean;
        let d2 = d * d;
        m2 += d2;
        m3 += d2 * d;
        m4 += d2 * d2;
    }
    Ok((mean, m2 / n, m3 / n, m4 / n))
}

/// Kurtosis `m4 / m2²` (not excess: a Gaussian gives 3, a sine 1.5).
///
/// # Errors
/// [`FeatureError::ZeroSpread`] for a constant window, plus the input errors.
pub fn kurtosis(x: &[f64]) -> Result<f64> {
    let (_, m2, _, m4) = central_moments(x)?;
    if m2 <= f64::MIN_POSITIVE {
        return Err(FeatureError::ZeroSpread {
            statistic: "kurtosis",
            len: x.len(),
        });
    }
    Ok(m4 / (m2 * m2))
}

/// Skewness `m3 / m2^{3/2}`.
///
/// # Errors
/// [`FeatureError::ZeroSpread`] for a constant window, plus the input errors.
pub fn skewness(x: &[f64]) -> Result<f64> {
    let (_, m2, m3, _) = central_moments(x)?;
    if m2 <= f64::MIN_POSITIVE {
        return Err(FeatureError::ZeroSpread {
            statistic: "skewness",
            len: x.len(),
        });
    }
    Ok(m3 / m2.powf(1.5))
}
