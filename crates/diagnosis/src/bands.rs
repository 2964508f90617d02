//! The filter bank of the fast kurtogram's shape and the squared envelope spectra of its bands
//! (the recording's, with their spectral kurtosis, and the healthy baseline's in the same bands): step 2 of [`diagnose`](crate::diagnose).

use residual_features::{Band, BandEnvelope, SpectralEngine, WelchConfig};

use crate::{
    BAND_DIVISORS, Baseline, EnvelopeSpectrum, HARMONICS, LINE_THRESHOLD_DB, Result,
    SEGMENT_TURNS_MAX, SEGMENT_TURNS_MIN,
};
use bearing_model::FaultOrders;

/// The candidate demodulation bands at `fs_hz`: no narrower than `min_width_hz` and with a
/// lower edge at or above it.
pub fn candidate_bands(fs_hz: f64, min_width_hz: f64) -> Vec<Band> {
    let nyq = 0.5 * fs_hz;
    let mut out = Vec::new();
    for d in BAND_DIVISORS {
        let w = nyq / d;
        if w < min_width_hz {
            continue;
        }
        let step = 0.5 * w;
        let mut lo = 0.0;
        while lo + w <= nyq * (1.0 + 1e-12) {
            // the band must lie above the fault lines and their first harmonics, or its
            // envelope shows beats between discrete low-frequency components (e.g. the
            // varying-compliance vibration at BPFO of a healthy bearing), not modulation
            if lo >= min_width_hz
                && let Ok(b) = Band::new(lo, (lo + w).min(nyq))
            {
                out.push(b);
            }
            lo += step;
        }
    }
    out
}

/// Narrowest band that holds three harmonics of `NULL_REACH` × the highest fault line plus a
/// shaft-order sideband, with 20 % margin: `1.2 (3 · 1.5 · max(BPFO, BPFI, BSF) + 1) fr`. The
/// detector's null reads the fault templates at fundamentals up to where their top harmonic
/// leaves the band: a band that held only the hypotheses' own harmonics would leave the null a
/// few dozen fundamentals, too few to state a probability of 0.3 %.
pub fn min_band_width_hz(orders: &FaultOrders, fr: f64) -> f64 {
    let top = orders.bpfo.max(orders.bpfi).max(orders.ball_defect);
    1.2 * (HARMONICS as f64 * NULL_REACH * top + 1.0) * fr
}

/// How far beyond the highest fault rate the null's fundamentals reach (see
/// [`min_band_width_hz`]).
pub const NULL_REACH: f64 = 1.5;

/// The squared envelope spectra of a residual of `duration_s` seconds from its band squared
/// envelopes `envs` (`SpectralEngine::band_squared_envelopes`; shaft at `fr` Hz), each with its
/// spectral kurtosis.
pub(crate) fn envelope_spectra(
    engine: &mut SpectralEngine,
    envs: &[BandEnvelope],
    duration_s: f64,
    fr: f64,
) -> Result<Vec<EnvelopeSpectrum>> {
    let duration_turns = duration_s * fr;
    let seg_turns = (duration_turns / 4.0)
        .clamp(SEGMENT_TURNS_MIN, SEGMENT_TURNS_MAX)
        .min(duration_turns);
    let mut spectra = Vec::with_capacity(envs.len());
    for be in envs {
        let s = &be.squared_envelope;
        let sk = be.spectral_kurtosis();
        // `seg_turns` shaft turns, shortened to the nearest even 7-smooth length (≤ 2 %
        // shorter): an odd or large-prime segment takes a real FFT several times slower
        let target = (seg_turns / fr * be.rate_hz).round() as usize;
        let seg = (2 * residual_features::smooth_floor(target / 2)).clamp(16, s.len());
        let cfg = WelchConfig::half_overlap(seg);
        let psd = engine.welch_psd(s, be.rate_hz, cfg)?;
        let segments = if s.len() >= seg {
            1 + (s.len() - seg) / (seg - cfg.overlap)
        } else {
            0
        };
        spectra.push(EnvelopeSpectrum {
            band_hz: [be.band.low_hz(), be.band.high_hz()],
            resolution_hz: psd.resolution_hz,
            power: psd.values,
            spectral_kurtosis: if sk.is_finite() { sk } else { 0.0 },
            segments,
            line_threshold_db: LINE_THRESHOLD_DB,
            mean_square: if s.is_empty() {
                0.0
            } else {
                s.iter().sum::<f64>() / s.len() as f64
            },
        });
    }
    Ok(spectra)
}

/// The healthy machine's squared envelope spectra in the same bands, at the recording's
/// resolution `resolutions_hz` (one per band; a baseline holding a residual only — a
/// recording's, or a synthesis of a machine model's; one too short for a band's Welch segment
/// gives none there), computed once per baseline, band set and resolution; `n` empty ones for a
/// baseline without a residual.
pub(crate) fn healthy_spectra(
    engine: &mut SpectralEngine,
    baseline: Option<&Baseline>,
    fs_hz: f64,
    bands: &[Band],
    resolutions_hz: &[f64],
    n: usize,
) -> Result<std::sync::Arc<Vec<Option<EnvelopeSpectrum>>>> {
    Ok(
        match baseline.and_then(|b| b.residual.as_deref().map(|r| (b, r))) {
            Some((b, br)) => {
                let mut key = vec![fs_hz.to_bits()];
                for (band, &res) in bands.iter().zip(resolutions_hz) {
                    key.extend([
                        band.low_hz().to_bits(),
                        band.high_hz().to_bits(),
                        res.to_bits(),
                    ]);
                }
                match b.spectra.get(&key) {
                    Some(s) => s,
                    None => {
                        let s = std::sync::Arc::new(baseline_spectra(
                            engine,
                            br,
                            fs_hz,
                            bands,
                            resolutions_hz,
                        )?);
                        b.spectra.put(key, s.clone());
                        s
                    }
                }
            }
            None => std::sync::Arc::new(vec![None; n]),
        },
    )
}

/// The healthy machine's squared envelope spectra in `bands`, each at the resolution given for
/// its band (`None` where the baseline is shorter than the segment that resolution needs).
///
/// The Welch segment is chosen at the baseline's own envelope rate: the band envelope's rate
/// depends on the signal's length (`SpectralEngine::band_squared_envelopes` keeps a smooth
/// number of bins), so the recording's segment length in samples would give a baseline
/// resolution up to a few per cent off the recording's, and no line of the baseline could be
/// compared (until 2026-11-27 none was, on any measured pair of unequal lengths).
fn baseline_spectra(
    engine: &mut SpectralEngine,
    residual: &[f64],
    fs_hz: f64,
    bands: &[Band],
    resolutions_hz: &[f64],
) -> Result<Vec<Option<EnvelopeSpectrum>>> {
    let benvs = engine.band_squared_envelopes(residual, fs_hz, bands)?;
    let mut out = Vec::with_capacity(benvs.len());
    for (be, &res) in benvs.iter().zip(resolutions_hz) {
        let s = &be.squared_envelope;
        let seg = 2 * ((be.rate_hz / res / 2.0).round() as usize).max(8);
        out.push(if s.len() >= seg {
            let psd = engine.welch_psd(s, be.rate_hz, WelchConfig::half_overlap(seg))?;
            Some(EnvelopeSpectrum {
                band_hz: [be.band.low_hz(), be.band.high_hz()],
                resolution_hz: psd.resolution_hz,
                power: psd.values,
                ..EnvelopeSpectrum::default()
            })
        } else {
            None
        });
    }
    Ok(out)
}
