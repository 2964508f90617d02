//! `--tach`: a recording resampled at equal shaft angles from its tachometer channel before it
//! is diagnosed (`residual_features::order` holds the algorithm).

use residual_features::{OrderTracked, SpectralEngine, order_track};

use super::Loaded;

/// `l` resampled at equal shaft angles from the tachometer `tach` read from the same file
/// (`pulses_per_rev` pulses a turn): the tracked recording, at its equivalent rate and with the
/// tachometer's mean speed as its speed, and what the tracking did (samples left out).
///
/// # Errors
/// The two channels at different rates, or the order tracking's typed errors (too few pulses,
/// a missed pulse, channels of different lengths).
pub fn order_tracked(
    l: &Loaded,
    tach: &Loaded,
    pulses_per_rev: f64,
) -> anyhow::Result<(Loaded, OrderTracked)> {
    if (tach.fs_hz - l.fs_hz).abs() > 1e-9 * l.fs_hz {
        anyhow::bail!(
            "the tachometer is sampled at {} Hz and the vibration at {} Hz: they must be recorded together",
            tach.fs_hz,
            l.fs_hz
        );
    }
    let mut engine = SpectralEngine::new();
    let mut t = order_track(
        &mut engine,
        &l.samples,
        &tach.samples,
        l.fs_hz,
        pulses_per_rev,
    )?;
    let tracked = Loaded {
        samples: std::mem::take(&mut t.samples),
        fs_hz: t.equivalent_fs_hz,
        rpm: Some(t.mean_rpm),
        unit: l.unit.clone(),
        fault_size_in: l.fault_size_in,
    };
    Ok((tracked, t))
}
