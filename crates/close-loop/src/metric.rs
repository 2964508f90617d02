//! The error metrics, scored on the held-out segment (definitions and the reasons for them:
//! `docs/equations/close-loop.md`, "Error metric").
//!
//! * Floor-regularised log-spectral distance (primary):
//!   LSD_ε = √( mean_k (10·log10((S_y(f_k) + ε) / (S_m(f_k) + ε)))² ) dB over the scored band,
//!   S_y the Welch PSD of the measurement, S_m the model's PSD, ε = 10^(floor_db/10) × the mean of
//!   S_y over the band on the fitting segment. Without ε (ε = 0, [`log_spectral_distance`]) the
//!   deep floors between the lines of a noise-free or line-dominated signal — where the PSD is
//!   60–150 dB below its peaks and carries no energy anyone can measure — dominate the distance.
//! * Residual RMS ratio (secondary): ‖y − ŷ‖ / ‖y‖ on the held-out samples, ŷ the model's
//!   phase-coherent part (lines fitted on the fitting segment and extrapolated): the
//!   time-domain error of the deterministic (shaft-synchronous and tonal) part.

use std::ops::Range;

/// Log-spectral distance in dB between a measured and a model PSD over the bins `bins`, both
/// regularised by the floor `eps` (units²/Hz; 0 gives the plain LSD, values floored at 1e-300).
pub fn regularised_lsd(measured: &[f64], model: &[f64], bins: Range<usize>, eps: f64) -> f64 {
    let bins = bins.start.min(measured.len())..bins.end.min(measured.len()).min(model.len());
    let n = bins.len();
    if n == 0 {
        return 0.0;
    }
    let s: f64 = bins
        .map(|k| {
            let r = 10.0 * ((measured[k] + eps).max(1e-300) / (model[k] + eps).max(1e-300)).log10();
            r * r
        })
        .sum();
    (s / n as f64).sqrt()
}

/// Plain log-spectral distance in dB (no floor): [`regularised_lsd`] with ε = 0.
pub fn log_spectral_distance(measured: &[f64], model: &[f64], bins: Range<usize>) -> f64 {
    regularised_lsd(measured, model, bins, 0.0)
}

/// The floor ε of [`regularised_lsd`]: `10^(floor_db/10)` × the mean of `psd` over `bins`.
pub fn floor_of(psd: &[f64], bins: Range<usize>, floor_db: f64) -> f64 {
    let n = bins.len().max(1) as f64;
    let mean = psd[bins].iter().sum::<f64>() / n;
    10f64.powf(floor_db / 10.0) * mean
}

/// Expected regularised LSD of a correct model from estimation variance alone: a Welch PSD of
/// K half-overlapped Hann segments has ν ≈ 1.9·K degrees of freedom (Welch 1967; Percival &
/// Walden §7.3), so 10·log10 of it scatters by ≈ 4.34·√(2/ν) dB; measurement and model estimate
/// add. `segments_model` = `None` for a model PSD known in closed form.
pub fn estimation_lsd(segments_measured: usize, segments_model: Option<usize>) -> f64 {
    let nu = |k: usize| 1.9 * k.max(1) as f64;
    let var = 2.0 / nu(segments_measured) + segments_model.map_or(0.0, |k| 2.0 / nu(k));
    10.0 / std::f64::consts::LN_10 * var.sqrt()
}

/// Mean square (0 for an empty slice).
pub fn mean_square(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64
}

/// Root mean square (0 for an empty slice).
pub fn rms(x: &[f64]) -> f64 {
    mean_square(x).sqrt()
}
