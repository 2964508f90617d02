//! The measurement chains and the healthy background: the chain's tones, its roll-off on the
//! fault records and on the background, and the healthy recording's broadband remainder.

use super::{
    CloseLoopError, MachineLine, MachineModel, PI, RigModel, Synthesis, TrainingRecord, Welch,
    background_of, smooth,
};

/// The tones of the healthy machine (lines fixed in Hz: the measurement chain's interference,
/// e.g. CWRU's ~4.2 kHz comb) belong to the recording chain, not to the machine, and differ
/// between the healthy recording and the fault records. Each tone's amplitude is rescaled by the
/// median, over the training records, of the square root of its peak excess (largest PSD within
/// ±2 bins over the median of ±50 Hz) relative to the healthy recording's.
pub(super) fn chain_tones(
    machine: &MachineModel,
    healthy: &[f64],
    training: &[TrainingRecord<'_>],
    fs: f64,
) -> Result<Vec<MachineLine>, CloseLoopError> {
    let mut lines = machine.lines.clone();
    let welch = Welch::new(fs, ((fs / 3.0).log2().round().exp2() as usize).max(1024))?;
    let df = welch.df();
    let excess = |p: &[f64], f: f64| {
        let k = (f / df).round() as usize;
        let w = ((50.0 / df).round() as usize).max(4);
        if k + w >= p.len() || k < w {
            return None;
        }
        let peak = p[k - 2..=k + 2].iter().copied().fold(0.0, f64::max);
        let med = close_loop::spectrum::median(&p[k - w..=k + w]);
        Some((peak - med).max(0.0))
    };
    let p_h = welch.try_psd(healthy)?;
    let p_t: Vec<Vec<f64>> = training
        .iter()
        .map(|t| welch.try_psd(t.y))
        .collect::<Result<_, _>>()?;
    for l in lines.iter_mut() {
        if let MachineLine::Tone {
            frequency_hz,
            amplitude,
        } = l
        {
            let Some(h) = excess(&p_h, *frequency_hz).filter(|h| *h > 0.0) else {
                continue;
            };
            let mut r: Vec<f64> = p_t
                .iter()
                .filter_map(|p| excess(p, *frequency_hz))
                .map(|e| (e / h).sqrt())
                .collect();
            if !r.is_empty() {
                r.sort_by(f64::total_cmp);
                *amplitude *= r[r.len() / 2];
            }
        }
    }
    Ok(lines)
}

/// Half length of the chain FIR (taps = 2·CHAIN_HALF + 1).
const CHAIN_HALF: usize = 64;

/// The measurement chain: the median over the training records of the smoothed ratio of the
/// measured PSD to the rig's (no chain yet) simulated PSD, normalised to unit geometric mean over
/// 300 Hz–fs/3 and clamped at 1 — so it holds only what attenuates (the roll-off of the records'
/// anti-alias filter, which the all-pole paths cannot follow) — as a Hann-windowed zero-phase FIR
/// of `2·CHAIN_HALF + 1` taps by frequency sampling of its square root. Empty when nothing is
/// attenuated by more than 1 dB.
pub(super) fn chain_response(
    rig: &RigModel,
    training: &[TrainingRecord<'_>],
    measured: &[(Vec<f64>, f64)],
    welch: &Welch,
    half: usize,
) -> Result<Vec<f64>, CloseLoopError> {
    let fs = rig.fs_hz;
    let nb = welch.n_bins();
    let mut logs: Vec<Vec<f64>> = Vec::new();
    for (i, t) in training.iter().enumerate() {
        let n = t.y.len().min((4.0 * fs) as usize);
        let mut syn = Synthesis::new(t.location.class(), t.size_mm, t.rpm, n, 3000 + i as u64);
        syn.outer_angle_rad = t.outer_angle_rad;
        let sim = rig.synthesize(&syn)?;
        let s_sim = smooth(&welch.try_psd(&sim)?, half);
        logs.push(
            measured[i]
                .0
                .iter()
                .zip(&s_sim)
                .map(|(a, b)| (a.max(1e-300) / b.max(1e-300)).ln())
                .collect(),
        );
    }
    if logs.is_empty() {
        return Ok(Vec::new());
    }
    let med: Vec<f64> = (0..nb)
        .map(|k| {
            let mut v: Vec<f64> = logs.iter().map(|l| l[k]).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        })
        .collect();
    let band: Vec<usize> = (0..nb)
        .filter(|&k| (300.0..=fs / 3.0).contains(&welch.frequency(k)))
        .collect();
    let mean = band.iter().map(|&k| med[k]).sum::<f64>() / band.len().max(1) as f64;
    let r: Vec<f64> = med.iter().map(|v| (v - mean).min(0.0).exp()).collect();
    if r.iter().all(|v| *v > 10f64.powf(-0.1)) {
        return Ok(Vec::new());
    }
    Ok(zero_phase_fir(&r, welch, |v| v.sqrt()))
}

/// The fault records' measurement chain as the healthy machine's broadband background sees it:
/// per frequency the smallest, over the training records, of the smoothed ratio of the measured
/// PSD to the rig's background PSD at that record's speed (its lines at the fault records'
/// levels, no fault), clamped at 1, as a zero-phase FIR of its square root. A fault only adds
/// power, so the record whose fault adds least in a band tells how much of the healthy
/// recording's broadband power the fault records' chain lets through there (97, recorded at
/// 48 kHz, keeps 20–30 times the 4–6 kHz power of the 12 kHz ball-fault records). Empty when
/// nothing is attenuated by more than 1 dB.
pub(super) fn background_chain(
    training: &[TrainingRecord<'_>],
    measured: &[(Vec<f64>, f64)],
    welch: &Welch,
    half: usize,
    bg: impl Fn(f64, usize, u64) -> Vec<f64>,
) -> Result<Vec<f64>, CloseLoopError> {
    let fs = welch.fs();
    let mut low = vec![0.0f64; welch.n_bins()];
    for (i, t) in training.iter().enumerate() {
        let n = t.y.len().min((4.0 * fs) as usize);
        let s_bg = smooth(&welch.try_psd(&bg(t.rpm, n, 7 + i as u64))?, half);
        for ((l, a), b) in low.iter_mut().zip(&measured[i].0).zip(&s_bg) {
            *l = l.min((a.max(1e-300) / b.max(1e-300)).ln());
        }
    }
    let r: Vec<f64> = low.iter().map(|v| v.exp()).collect();
    if training.is_empty() || r.iter().all(|v| *v > 10f64.powf(-0.1)) {
        return Ok(Vec::new());
    }
    Ok(zero_phase_fir(&r, welch, |v| v.sqrt()))
}

/// A Hann-windowed zero-phase FIR of `2·CHAIN_HALF + 1` taps whose amplitude response samples
/// `amp(p(f))`, `p` a per-bin quantity of `welch`'s grid interpolated linearly in frequency
/// (frequency sampling on a 1024-point grid).
fn zero_phase_fir(p: &[f64], welch: &Welch, amp: impl Fn(f64) -> f64) -> Vec<f64> {
    let fs = welch.fs();
    let nb = p.len();
    let nfft = 1024usize;
    let at = |f: f64| {
        let x = f / welch.df();
        let k = (x.floor() as usize).min(nb - 2);
        let t = (x - k as f64).clamp(0.0, 1.0);
        amp((1.0 - t) * p[k] + t * p[k + 1])
    };
    let h_k: Vec<f64> = (0..=nfft / 2)
        .map(|k| at(k as f64 * fs / nfft as f64))
        .collect();
    let mut h = vec![0.0; 2 * CHAIN_HALF + 1];
    for (j, v) in h.iter_mut().enumerate() {
        let m = j as f64 - CHAIN_HALF as f64;
        let mut acc = h_k[0];
        for (k, a) in h_k.iter().enumerate().skip(1) {
            let w = if k == nfft / 2 { 1.0 } else { 2.0 };
            acc += w * a * (2.0 * PI * k as f64 * m / nfft as f64).cos();
        }
        let win = 0.5 * (1.0 + (PI * m / (CHAIN_HALF as f64 + 1.0)).cos());
        *v = acc / nfft as f64 * win;
    }
    h
}

/// The healthy recording's broadband remainder: what the loop's machine model leaves of the
/// healthy PSD (both smoothed over ±[`SMOOTH_HZ`]), `R = max(0, S_healthy − S_model)`, as the
/// zero-phase FIR that shapes unit-variance white noise to it (|H| = √(R·fs/2): white noise of
/// unit variance has the one-sided density 2/fs). It carries the healthy machine's power the
/// loop did not name — lines it left (CWRU's 360 Hz family), their spread — so the simulated
/// band energies of the healthy machine are the measured ones. Empty when the model holds
/// every band within 1 dB already.
pub(super) fn background_remainder(
    machine: &MachineModel,
    healthy: &[f64],
    rpm: f64,
    welch: &Welch,
    half: usize,
) -> Result<Vec<f64>, CloseLoopError> {
    let fs = welch.fs();
    let s_h = smooth(&welch.try_psd(healthy)?, half);
    let model = background_of(
        machine,
        &machine.lines,
        &[],
        &[],
        fs,
        rpm,
        healthy.len(),
        17,
    );
    let s_m = smooth(&welch.try_psd(&model)?, half);
    let r: Vec<f64> = s_h
        .iter()
        .zip(&s_m)
        .map(|(a, b)| (a - b).max(0.0))
        .collect();
    if s_h
        .iter()
        .zip(&s_m)
        .all(|(a, b)| *b >= *a * 10f64.powf(-0.1))
    {
        return Ok(Vec::new());
    }
    Ok(zero_phase_fir(&r, welch, |v| {
        (v.max(0.0) * fs / 2.0).sqrt()
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::SMOOTH_HZ;
    use close_loop::scenario::Gaussian;
    use close_loop::spectrum::{bandpass_coefficients, biquad_filter};

    fn band_power(psd: &[f64], welch: &Welch, lo: f64, hi: f64) -> f64 {
        (0..psd.len())
            .filter(|&k| (lo..hi).contains(&welch.frequency(k)))
            .map(|k| psd[k])
            .sum()
    }

    /// A healthy recording holding a band the machine model does not (narrow-band noise at
    /// 600 Hz, twice the model's power in 400–800 Hz): the remainder puts the band's power back
    /// and leaves the other bands alone; with nothing missing there is no remainder to speak of.
    #[test]
    fn the_remainder_restores_what_the_machine_model_leaves() {
        let rig = crate::cwru_rig().unwrap();
        let m = &rig.healthy;
        let (fs, rpm, n) = (rig.fs_hz, 1797.0, 96_000);
        let welch = Welch::new(fs, 1024).unwrap();
        let half = ((SMOOTH_HZ / welch.df()).round() as usize).max(1);
        let model = background_of(m, &m.lines, &[], &[], fs, rpm, n, 3);
        let p_model = welch.try_psd(&model).unwrap();
        let band = |p: &[f64]| band_power(p, &welch, 400.0, 800.0);
        let (b, a) = bandpass_coefficients(600.0, 0.1, fs);
        let mut g = Gaussian::new(5);
        let w: Vec<f64> = (0..n).map(|_| g.sample()).collect();
        let mut extra = biquad_filter(&b, &a, &w);
        let k = (2.0 * band(&p_model) / band(&welch.try_psd(&extra).unwrap())).sqrt();
        extra.iter_mut().for_each(|v| *v *= k);
        let healthy: Vec<f64> = model.iter().zip(&extra).map(|(a, b)| a + b).collect();
        let p_healthy = welch.try_psd(&healthy).unwrap();

        let fir = background_remainder(m, &healthy, rpm, &welch, half).unwrap();
        assert!(!fir.is_empty());
        let with = welch
            .try_psd(&background_of(m, &m.lines, &fir, &[], fs, rpm, n, 9))
            .unwrap();
        let ratio = band(&with) / band(&p_healthy);
        assert!((0.8..1.25).contains(&ratio), "400–800 Hz: {ratio}");
        let (lo, hi) = (
            band_power(&with, &welch, 2000.0, 4000.0),
            band_power(&p_model, &welch, 2000.0, 4000.0),
        );
        assert!((lo / hi - 1.0).abs() < 0.1, "2–4 kHz: {lo} vs {hi}");

        // the model's own realisation: at most a trace of remainder
        let own = background_remainder(m, &model, rpm, &welch, half).unwrap();
        let trace = welch
            .try_psd(&background_of(m, &m.lines, &own, &[], fs, rpm, n, 9))
            .unwrap();
        let total = |p: &[f64]| p.iter().sum::<f64>();
        assert!(
            total(&trace) / total(&p_model) < 1.15,
            "{} vs {}",
            total(&trace),
            total(&p_model)
        );
    }
}
