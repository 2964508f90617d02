//! The two error metrics, both scored on the held-out segment.
//!
//! * Log-spectral distance (primary): LSD = √( mean_k (10·log10(S_y(f_k) / S_m(f_k)))² ) dB over
//!   the scored band, S_y the Welch PSD of the measurement, S_m the model's PSD. It compares a
//!   stochastic vibration signal with a model in distribution, where sample-by-sample errors are
//!   meaningless (the phase of a free-running model is not the recording's).
//! * Residual RMS ratio (secondary): ‖y − ŷ‖ / ‖y‖ on the held-out samples, ŷ the model's
//!   phase-coherent part (lines fitted on the fitting segment and extrapolated).

use std::ops::Range;

/// Log-spectral distance in dB between a measured and a model PSD over the bins `bins`.
/// Zero or negative values are floored at 1e-300 before the logarithm.
pub fn log_spectral_distance(measured: &[f64], model: &[f64], bins: Range<usize>) -> f64 {
    let bins = bins.start.min(measured.len())..bins.end.min(measured.len()).min(model.len());
    let n = bins.len();
    if n == 0 {
        return 0.0;
    }
    let s: f64 = bins
        .map(|k| {
            let r = 10.0 * (measured[k].max(1e-300) / model[k].max(1e-300)).log10();
            r * r
        })
        .sum();
    (s / n as f64).sqrt()
}

/// Root mean square.
pub fn rms(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}
