//! Calibration of a rig on measured records (module docs of [`super`]): the healthy machine,
//! the contact preload, the impact paths, the severities, the sensor's horizontal sensitivity and
//! the measurement chain.

use super::{
    BURST_PERIODS, DEPTH_M, EXCITATION_HOUSING_HZ, Excitation, FORMAT, IMPACT_PATH_ORDER,
    ImpactPath, Location, RigModel, RigProvenance, SLIP_FRACTION, SMOOTH_HZ, STRIKE_FRACTIONS,
    Severity, Synthesis, VERSION, WARMUP, apply_fir, background_of, excitation, fault_rate_of,
    gated, line_prominence_db, mean_square, mix, smooth,
};
use crate::CloseLoopError;
use crate::machine::{MachineLine, MachineModel};
use crate::path::StructuralPath;
use crate::spectrum::Welch;
use bearing_model::{Bearing, FaultClass};
use std::f64::consts::PI;

/// Preloads the calibration tries, m.
pub const PRELOADS_M: &[f64] = &[0.0, 0.5e-6, 1e-6, 2e-6, 4e-6, 8e-6];

/// Radial loads on the shaft the calibration tries, N (0 up to about the static rating of a
/// 6205's most loaded ball at the calibrated preloads).
pub const RADIAL_LOADS_N: &[f64] = &[0.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0, 3200.0];

fn variance(y: &[f64]) -> f64 {
    let m = y.iter().sum::<f64>() / y.len().max(1) as f64;
    y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / y.len().max(1) as f64
}

/// Kurtosis (`residual-features`'); NaN for a constant signal, which calibration never feeds it
/// (records with no excess power are refused before).
fn kurtosis(y: &[f64]) -> f64 {
    residual_features::kurtosis(y).unwrap_or(f64::NAN)
}

/// The tones of the healthy machine (lines fixed in Hz: the measurement chain's interference,
/// e.g. CWRU's ~4.2 kHz comb) belong to the recording chain, not to the machine, and differ
/// between the healthy recording and the fault records. Each tone's amplitude is rescaled by the
/// median, over the training records, of the square root of its peak excess (largest PSD within
/// ±2 bins over the median of ±50 Hz) relative to the healthy recording's.
fn chain_tones(
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
        let med = crate::spectrum::median(&p[k - w..=k + w]);
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
fn chain_response(
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
fn background_chain(
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
fn background_remainder(
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

/// Impact paths and gains fitted for one preload.
struct PathFit {
    paths: Vec<ImpactPath>,
    gains: Vec<f64>,
    sims: Vec<Excitation>,
}

impl PathFit {
    fn path_of(&self, loc: Location, size_mm: f64) -> &ImpactPath {
        super::nearest_path(&self.paths, loc, size_mm).unwrap_or(&self.paths[0])
    }
}

/// For each location and spall size with training records: the AR path of the mean log ratio of
/// smoothed excess PSD (measured minus healthy, at least a tenth of the measured) to smoothed
/// excitation PSD, each record's ratio normalised to zero mean log; then each record's gain from
/// its excess mean square.
#[allow(clippy::too_many_arguments)]
fn fit_paths(
    bearing: Bearing,
    preload_m: f64,
    radial_load_n: f64,
    fs: f64,
    machine: &MachineModel,
    training: &[TrainingRecord<'_>],
    measured: &[(Vec<f64>, f64)],
    background: &[(Vec<f64>, f64)],
    welch: &Welch,
    half: usize,
    len: usize,
) -> Result<PathFit, CloseLoopError> {
    let nb = welch.n_bins();
    let mut sims = Vec::with_capacity(training.len());
    let mut ratios = Vec::with_capacity(training.len());
    for (i, t) in training.iter().enumerate() {
        let x = excitation(
            bearing,
            preload_m,
            radial_load_n,
            t.location.class(),
            t.size_mm,
            t.rpm * machine.speed_ratio,
            t.outer_angle_rad,
            fs,
            t.y.len().min(len) + WARMUP,
            1000 + i as u64,
            EXCITATION_HOUSING_HZ,
        )?;
        let s_x = smooth(&welch.try_psd(&x.vertical)?, half);
        ratios.push(excess_log_ratio(&measured[i].0, &background[i].0, &s_x));
        sims.push(x);
    }
    let mut paths = Vec::new();
    for loc in Location::ALL {
        let mut sizes: Vec<f64> = training
            .iter()
            .filter(|t| t.location == loc)
            .map(|t| t.size_mm)
            .collect();
        sizes.sort_by(f64::total_cmp);
        sizes.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1.0));
        for size in sizes {
            let idx: Vec<usize> = (0..training.len())
                .filter(|&i| {
                    training[i].location == loc
                        && (training[i].size_mm - size).abs() <= 1e-9 * size.abs().max(1.0)
                        && ratios[i].iter().all(|v| v.is_finite())
                })
                .collect();
            if idx.is_empty() {
                continue;
            }
            let shape: Vec<f64> = (0..nb)
                .map(|k| (idx.iter().map(|&i| ratios[i][k]).sum::<f64>() / idx.len() as f64).exp())
                .collect();
            paths.push(ImpactPath {
                location: loc,
                size_mm: Some(size),
                path: impact_path_of(&shape, welch, fs)?,
                outer_angle_rad: None,
            });
        }
    }
    if paths.is_empty() {
        return Err(CloseLoopError::Model {
            reason: "no training fault record carries a usable spectrum".into(),
        });
    }
    let mut fit = PathFit {
        paths,
        gains: Vec::new(),
        sims,
    };
    for (i, t) in training.iter().enumerate() {
        let through = fit
            .path_of(t.location, t.size_mm)
            .path
            .filter(&fit.sims[i].vertical);
        let ms_x = mean_square(&through[WARMUP.min(through.len() / 2)..]);
        if !(ms_x > 0.0 && ms_x.is_finite()) {
            return Err(CloseLoopError::Model {
                reason: format!("the excitation of {} is zero", t.name),
            });
        }
        fit.gains
            .push(((measured[i].1 - background[i].1).max(0.0) / ms_x).sqrt());
    }
    Ok(fit)
}

/// ln of a record's smoothed excess PSD (measured minus background, at least a tenth of the
/// measured) over its smoothed excitation PSD, normalised to zero mean over the bins above DC:
/// the shape an impact path is fitted to.
fn excess_log_ratio(measured: &[f64], background: &[f64], excitation: &[f64]) -> Vec<f64> {
    let r: Vec<f64> = measured
        .iter()
        .zip(background)
        .zip(excitation)
        .map(|((a, b), x)| ((a - b).max(0.1 * a) / x.max(1e-300)).max(1e-300).ln())
        .collect();
    let mean = r[1..].iter().sum::<f64>() / (r.len() - 1).max(1) as f64;
    r.iter().map(|v| v - mean).collect()
}

/// The impact path (AR order [`IMPACT_PATH_ORDER`], unit excitation variance) of a PSD shape.
fn impact_path_of(shape: &[f64], welch: &Welch, fs: f64) -> Result<StructuralPath, CloseLoopError> {
    let mut path = StructuralPath::from_psd(shape, welch.df(), fs, IMPACT_PATH_ORDER)?;
    path.excitation_variance = 1.0;
    Ok(path)
}

/// A measured or simulated training record for [`calibrate_rig`].
#[derive(Debug, Clone, Copy)]
pub struct TrainingRecord<'a> {
    /// Name (for the provenance).
    pub name: &'a str,
    /// Fault location.
    pub location: Location,
    /// Spall width, mm.
    pub size_mm: f64,
    /// Outer-race spall position, rad (6 o'clock = −π/2).
    pub outer_angle_rad: f64,
    /// Nominal speed, rpm.
    pub rpm: f64,
    /// The samples (rig units), at the rig's sampling rate.
    pub y: &'a [f64],
}

/// Calibrate a rig: the healthy machine on `healthy` (at `fs`, `rpm`), the impact path and one
/// severity per training record (module docs). `rule` says how the training records were chosen.
///
/// # Errors
/// The errors of [`crate::machine::calibrate`], of the Welch PSD and of [`excitation`];
/// [`CloseLoopError::Model`] when no training record carries more power than the healthy
/// machine.
pub fn calibrate_rig(
    healthy: &[f64],
    fs: f64,
    rpm: f64,
    bearing: Bearing,
    training: &[TrainingRecord<'_>],
    cfg: &crate::CheckedConfig,
    rule: &str,
) -> Result<RigModel, CloseLoopError> {
    let machine = crate::machine::calibrate(healthy, fs, rpm, bearing, cfg)?;
    // outer-race records with the spall off the vertical (sensor) axis calibrate the sensor's
    // horizontal sensitivity; the rest calibrate paths and severities
    let off_axis = |t: &TrainingRecord<'_>| {
        t.location == Location::Outer && t.outer_angle_rad.sin().abs() < 0.5
    };
    // and those with the spall at the top, opposite the load zone, the radial load
    let opposite =
        |t: &TrainingRecord<'_>| t.location == Location::Outer && t.outer_angle_rad.sin() > 0.5;
    let cross: Vec<TrainingRecord<'_>> = training.iter().copied().filter(off_axis).collect();
    let top: Vec<TrainingRecord<'_>> = training.iter().copied().filter(opposite).collect();
    let training: Vec<TrainingRecord<'_>> = training
        .iter()
        .copied()
        .filter(|t| !off_axis(t) && !opposite(t))
        .collect();
    let training = training.as_slice();
    if training.is_empty() {
        return Err(CloseLoopError::Model {
            reason: "no training fault record to calibrate the impact paths on".into(),
        });
    }
    let nperseg = ((fs / 12.0).log2().round().exp2() as usize).max(crate::MIN_NPERSEG);
    let welch = Welch::new(fs, nperseg)?;
    let half = ((SMOOTH_HZ / welch.df()).round() as usize).max(1);
    let measured: Vec<(Vec<f64>, f64)> = training
        .iter()
        .map(|t| Ok((smooth(&welch.try_psd(t.y)?, half), variance(t.y))))
        .collect::<Result<_, CloseLoopError>>()?;
    let chain_lines = chain_tones(&machine, healthy, training, fs)?;
    let remainder = background_remainder(&machine, healthy, rpm, &welch, half)?;
    // what the fault must add to each training record is its excess over the rig's own healthy
    // machine at that record's speed (chain tones, remainder and all), not over the healthy
    // recording: the two differ where the recording chains do (the ~4.2 kHz interference comb
    // is far stronger on 97 than on the 12 kHz fault records)
    // the fault records' chain on the broadband background, from the records themselves
    let bg_chain = background_chain(training, &measured, &welch, half, |rpm, n, seed| {
        background_of(&machine, &chain_lines, &remainder, &[], fs, rpm, n, seed)
    })?;
    let bg_of = |rpm: f64, n: usize, seed: u64| {
        background_of(
            &machine,
            &chain_lines,
            &remainder,
            &bg_chain,
            fs,
            rpm,
            n,
            seed,
        )
    };
    let background: Vec<(Vec<f64>, f64)> = training
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let n = t.y.len().min((4.0 * fs) as usize);
            let bg = bg_of(t.rpm, n, 7 + i as u64);
            Ok((smooth(&welch.try_psd(&bg)?, half), variance(&bg)))
        })
        .collect::<Result<_, CloseLoopError>>()?;
    let kurt: Vec<f64> = training.iter().map(|t| kurtosis(t.y)).collect();
    // the contact load: the preload whose fitted rig gives the training records' kurtosis best
    // (mean |ln(simulated / measured kurtosis)|), on 2 s excitations
    let fit_at = |preload: f64, radial: f64, len: usize| {
        fit_paths(
            bearing,
            preload,
            radial,
            fs,
            &machine,
            training,
            &measured,
            &background,
            &welch,
            half,
            len,
        )
    };
    let short = (2.0 * fs) as usize;
    let mut best: Option<(f64, f64)> = None;
    for &preload in PRELOADS_M {
        let fit = fit_at(preload, 0.0, short)?;
        let mut err = 0.0;
        for (i, t) in training.iter().enumerate() {
            let (g, path) = (&fit.gains[i], fit.path_of(t.location, t.size_mm));
            let rate = fault_rate_of(&machine, t.location, t.rpm);
            let tau = BURST_PERIODS * fs / rate.max(1e-9);
            let impacts: Vec<f64> = fit.sims[i].vertical.iter().map(|v| g * v).collect();
            // the impacts as often as the record's fault line says they strike (the strike
            // fraction whose simulated line prominence is nearest the measured one), since
            // striking in bursts raises the kurtosis as a stiffer contact does
            // the background and the measured line do not depend on the strike fraction
            let bg = bg_of(t.rpm, impacts.len(), 7 + i as u64);
            let skip = WARMUP.min(impacts.len() / 2);
            let measured_line =
                line_prominence_db(&t.y[..(impacts.len() - skip).min(t.y.len())], fs, rate);
            let mut chosen: Option<(f64, Vec<f64>)> = None;
            for &strike in &STRIKE_FRACTIONS {
                let through = path
                    .path
                    .filter(&gated(&impacts, strike, tau, 17 + i as u64));
                let y: Vec<f64> = through
                    .iter()
                    .zip(&bg)
                    .skip(skip)
                    .map(|(a, b)| a + b)
                    .collect();
                let miss = match (line_prominence_db(&y, fs, rate), &measured_line) {
                    (Ok(Some(a)), Ok(Some(b))) => (a - b).abs(),
                    _ => f64::INFINITY,
                };
                if chosen.as_ref().is_none_or(|c| miss < c.0 - 1e-9) {
                    chosen = Some((miss, y));
                }
            }
            if let Some((_, y)) = chosen {
                err += (kurtosis(&y) / kurt[i]).ln().abs();
            }
        }
        let err = err / training.len() as f64;
        if best.is_none_or(|b| err < b.1) {
            best = Some((preload, err));
        }
    }
    let preload_m = best.map_or(0.0, |b| b.0);
    // the radial load, at that preload: the one whose 12-over-6 o'clock ratio of simulated
    // impact power matches the measured ratio of fault power (module docs)
    let radial_load_n = if top.is_empty() {
        0.0
    } else {
        let fit0 = fit_at(preload_m, 0.0, short)?;
        fit_radial_load(
            bearing,
            preload_m,
            &machine,
            training,
            &measured,
            &background,
            &top,
            &fit0,
            &bg_of,
            short,
        )?
    };
    let long = (4.0 * fs) as usize;
    let fit = fit_at(preload_m, radial_load_n, long)?;
    // severities (gain, random fraction, strike fraction) of every training record for a sensor
    // κ: for each strike fraction of the grid (or the one already chosen, `strikes`), the random
    // fraction that matches the record's kurtosis and the gain that matches its excess mean
    // square; the strike fraction whose simulated fault line stands as far over its envelope-spectrum neighbours
    // as the measured one (the record's first samples, as many as simulated) wins
    // `recs`: (seed index, record, its excitation, the path it is seen through)
    type Rec<'r, 'a> = (usize, TrainingRecord<'a>, &'r Excitation, &'r ImpactPath);
    let severities_for =
        |recs: &[Rec<'_, '_>], kappa: f64, chain: &[f64], strikes: Option<&[f64]>| {
            let mut out = Vec::with_capacity(recs.len());
            for (k, &(i, t, sim, path)) in recs.iter().enumerate() {
                let seen = sim.seen(kappa);
                let bg = apply_fir(chain, &bg_of(t.rpm, sim.vertical.len(), 7 + i as u64));
                let skip = WARMUP.min(bg.len() / 2);
                let (measured_var, measured_kurt) = (variance(t.y), kurtosis(t.y));
                let excess = (measured_var - variance(&bg[skip..])).max(0.0);
                let rate = fault_rate_of(&machine, t.location, t.rpm);
                let tau = BURST_PERIODS * fs / rate.max(1e-9);
                // (gain, random fraction, simulated record) for a strike fraction, the gain and the
                // kurtosis averaged over the gate realisations of `seeds` (a gated train's kurtosis
                // varies from burst pattern to burst pattern)
                let fit_strike = |strike: f64, seeds: &[u64]| {
                    let trains: Vec<Vec<f64>> = seeds
                        .iter()
                        .map(|s| gated(&seen, strike, tau, s + i as u64))
                        .collect();
                    // gain and simulated records for a random fraction q
                    let at = |q: f64| {
                        let through: Vec<Vec<f64>> = trains
                            .iter()
                            .map(|x| apply_fir(chain, &path.path.filter(&mix(x, q, 11 + i as u64))))
                            .collect();
                        let skip = WARMUP.min(through[0].len() / 2);
                        let ms = through.iter().map(|x| mean_square(&x[skip..])).sum::<f64>()
                            / through.len() as f64;
                        let g = (excess / ms.max(1e-300)).sqrt();
                        let ys: Vec<Vec<f64>> = through
                            .iter()
                            .map(|x| {
                                x[skip..]
                                    .iter()
                                    .zip(&bg[skip..])
                                    .map(|(a, b)| g * a + b)
                                    .collect()
                            })
                            .collect();
                        (g, ys)
                    };
                    let kurt_at = |q: f64| {
                        let ys = at(q).1;
                        ys.iter().map(|y| kurtosis(y)).sum::<f64>() / ys.len() as f64
                    };
                    let (mut lo, mut hi) = (0.0, 0.99);
                    let q = if kurt_at(lo) <= measured_kurt {
                        0.0
                    } else if kurt_at(hi) >= measured_kurt {
                        hi
                    } else {
                        for _ in 0..14 {
                            let mid = 0.5 * (lo + hi);
                            if kurt_at(mid) > measured_kurt {
                                lo = mid;
                            } else {
                                hi = mid;
                            }
                        }
                        0.5 * (lo + hi)
                    };
                    let (g, mut ys) = at(q);
                    (g, q, ys.swap_remove(0))
                };
                // one gate realisation while the strike fraction is searched, three for the fit
                let search = [17];
                let fit_seeds: &[u64] = &[17, 1017, 2017];
                let (strike, (g, q, _)) = match strikes {
                    Some(b) => (b[k], fit_strike(b[k], fit_seeds)),
                    None => {
                        // (strike, kurtosis out of reach, line miss)
                        let mut best: Option<(f64, f64, f64)> = None;
                        // the measured line, on as many samples as simulated (the same for every
                        // strike fraction): computed once
                        let mut measured_line = None;
                        for &strike in &STRIKE_FRACTIONS {
                            let r = fit_strike(strike, &search);
                            let m = r.2.len().min(t.y.len());
                            let meas = measured_line
                                .get_or_insert_with(|| line_prominence_db(&t.y[..m], fs, rate));
                            let (Ok(Some(sim)), Ok(Some(meas))) =
                                (line_prominence_db(&r.2, fs, rate), meas)
                            else {
                                continue;
                            };
                            let meas = *meas;
                            let miss = (sim - meas).abs();
                            // how far the random fraction's range leaves the kurtosis: a strike
                            // fraction that cannot reach it loses to one that can
                            let out = ((kurtosis(&r.2) / measured_kurt).ln().abs()
                                - KURTOSIS_REACHED.ln())
                            .max(0.0);
                            let better = best.is_none_or(|b| {
                                out < b.1 - 1e-9 || (out <= b.1 + 1e-9 && miss < b.2 - 1e-9)
                            });
                            if better {
                                best = Some((strike, out, miss));
                            }
                        }
                        let strike = best.map_or(1.0, |b| b.0);
                        (strike, fit_strike(strike, fit_seeds))
                    }
                };
                out.push(Severity {
                    location: t.location,
                    size_mm: t.size_mm,
                    gain: g,
                    random_fraction: q,
                    strike_fraction: strike,
                    record: t.name.to_string(),
                    outer_angle_rad: None,
                });
            }
            out
        };
    let recs: Vec<Rec<'_, '_>> = training
        .iter()
        .enumerate()
        .map(|(i, t)| (i, *t, &fit.sims[i], fit.path_of(t.location, t.size_mm)))
        .collect();
    let severities = severities_for(&recs, 0.0, &[], None);
    let strikes: Vec<f64> = severities.iter().map(|s| s.strike_fraction).collect();
    let impact_paths = fit.paths.clone();
    let mut rig = RigModel {
        format: FORMAT.to_string(),
        version: VERSION,
        fs_hz: fs,
        units: "unknown".to_string(),
        bearing: machine.bearing.clone(),
        healthy: machine.clone(),
        chain_lines: chain_lines.clone(),
        impact_paths,
        preload_m,
        radial_load_n,
        sensor_horizontal: 0.0,
        chain_fir: Vec::new(),
        background_fir: remainder.clone(),
        background_chain_fir: bg_chain.clone(),
        excitation_housing_hz: EXCITATION_HOUSING_HZ,
        depth_m: DEPTH_M,
        slip_fraction: SLIP_FRACTION,
        severities,
        provenance: RigProvenance {
            healthy_record: String::new(),
            training_records: training.iter().map(|t| t.name.to_string()).collect(),
            training_rule: rule.to_string(),
        },
    };
    rig.provenance
        .training_records
        .extend(cross.iter().chain(&top).map(|t| t.name.to_string()));
    // κ from the off-axis records with the κ = 0 severities, then the severities again with κ
    rig.sensor_horizontal = fit_horizontal(&rig, bearing, &cross)?;
    if rig.sensor_horizontal > 0.0 {
        rig.severities = severities_for(&recs, rig.sensor_horizontal, &[], Some(&strikes));
    }
    // the measurement chain's response (the fault records' anti-alias roll-off), then the
    // severities once more behind it
    rig.chain_fir = chain_response(&rig, training, &measured, &welch, half)?;
    if !rig.chain_fir.is_empty() {
        rig.severities =
            severities_for(&recs, rig.sensor_horizontal, &rig.chain_fir, Some(&strikes));
    }
    // the off-axis and top records' own severities (each CWRU position is a separate bearing):
    // their excitation at their position, seen through their size's path and behind the same
    // sensor and chain, fitted as the reference records are (strike fraction searched)
    let positioned: Vec<TrainingRecord<'_>> = cross.iter().chain(&top).copied().collect();
    let sims: Vec<Excitation> = positioned
        .iter()
        .enumerate()
        .map(|(j, t)| {
            excitation(
                bearing,
                preload_m,
                radial_load_n,
                FaultClass::Outer,
                t.size_mm,
                t.rpm * machine.speed_ratio,
                t.outer_angle_rad,
                fs,
                t.y.len().min(long) + WARMUP,
                1000 + (training.len() + j) as u64,
                EXCITATION_HOUSING_HZ,
            )
        })
        .collect::<Result<_, CloseLoopError>>()?;
    // and their own paths (the path from a defect at 3 or 12 o'clock to the sensor is not the
    // one from 6): fitted as the reference paths are, on the excess over the rig's background
    // against what the sensor sees of their excitation
    let mut own_paths: Vec<ImpactPath> = Vec::with_capacity(positioned.len());
    // every training record's smoothed measured PSD, the positioned ones after the references
    let mut measured_all: Vec<Vec<f64>> = measured.iter().map(|m| m.0.clone()).collect();
    for (j, (t, sim)) in positioned.iter().zip(&sims).enumerate() {
        let n = t.y.len().min(long);
        let s_y = smooth(&welch.try_psd(t.y)?, half);
        measured_all.push(s_y.clone());
        let s_b = smooth(
            &welch.try_psd(&bg_of(t.rpm, n, 7 + (training.len() + j) as u64))?,
            half,
        );
        let s_x = smooth(&welch.try_psd(&sim.seen(rig.sensor_horizontal))?, half);
        let r = excess_log_ratio(&s_y, &s_b, &s_x);
        let shape: Vec<f64> = r.iter().map(|v| v.exp()).collect();
        let own = match impact_path_of(&shape, &welch, fs) {
            Ok(path) if r.iter().all(|v| v.is_finite()) => ImpactPath {
                location: Location::Outer,
                size_mm: Some(t.size_mm),
                path,
                outer_angle_rad: Some(t.outer_angle_rad),
            },
            // no usable spectrum: the reference path of its size
            _ => ImpactPath {
                outer_angle_rad: Some(t.outer_angle_rad),
                ..fit.path_of(Location::Outer, t.size_mm).clone()
            },
        };
        own_paths.push(own);
    }
    let recs: Vec<Rec<'_, '_>> = positioned
        .iter()
        .zip(&sims)
        .zip(&own_paths)
        .enumerate()
        .map(|(j, ((t, sim), path))| (training.len() + j, *t, sim, path))
        .collect();
    let own = severities_for(&recs, rig.sensor_horizontal, &rig.chain_fir, None);
    rig.severities
        .extend(own.into_iter().zip(&positioned).map(|(mut s, t)| {
            s.outer_angle_rad = Some(t.outer_angle_rad);
            s
        }));
    rig.impact_paths.extend(own_paths);
    // close the loop on the paths: each is corrected by what its records' simulated fault
    // spectrum misses of the measured one, behind everything fitted since it was first drawn
    // (sensor, chain, gate, mix), and the severities are fitted again through it
    let everyone: Vec<TrainingRecord<'_>> = training.iter().chain(&positioned).copied().collect();
    // what each record's fault must add: its measured excess over the rig's background behind
    // the chain (neither changes between rounds)
    let excess = measured_excess(&rig, &everyone, &measured_all, &welch, half)?;
    let strikes_all: Vec<f64> = rig.severities.iter().map(|s| s.strike_fraction).collect();
    for _ in 0..PATH_REFINEMENTS {
        if !refine_paths(&mut rig, &everyone, &excess, &welch, half)? {
            break;
        }
        let paths = rig.impact_paths.clone();
        let recs: Vec<Rec<'_, '_>> = training
            .iter()
            .enumerate()
            .map(|(i, t)| (i, *t, &fit.sims[i]))
            .chain(
                positioned
                    .iter()
                    .zip(&sims)
                    .enumerate()
                    .map(|(j, (t, sim))| (training.len() + j, *t, sim)),
            )
            .map(|(i, t, sim)| {
                let path =
                    super::nearest_path_at(&paths, t.location, t.size_mm, Some(t.outer_angle_rad))
                        .unwrap_or(&paths[0]);
                (i, t, sim, path)
            })
            .collect();
        let angles: Vec<Option<f64>> = rig.severities.iter().map(|s| s.outer_angle_rad).collect();
        rig.severities = severities_for(
            &recs,
            rig.sensor_horizontal,
            &rig.chain_fir,
            Some(&strikes_all),
        )
        .into_iter()
        .zip(angles)
        .map(|(mut s, a)| {
            s.outer_angle_rad = a;
            s
        })
        .collect();
    }
    Ok(rig)
}

/// A simulated kurtosis within this factor of the measured one counts as reached when the
/// strike fraction is chosen: the random fraction's bisection lands within it unless its range
/// cannot reach the measured kurtosis.
const KURTOSIS_REACHED: f64 = 1.1;

/// Rounds of closing the loop on the impact paths after their first fit, each followed by the
/// severities' refit: every path is corrected by what its training records' simulated fault
/// spectrum (behind sensor, chain and strike gate) misses of the measured excess (module docs).
pub const PATH_REFINEMENTS: usize = 2;

/// Largest change of an impact path's power response in one round of [`refine_paths`], dB.
const MAX_PATH_STEP_DB: f64 = 10.0;

/// Samples of a training record simulated by [`refine_paths`]: its length, at most 4 s.
fn refine_len(rig: &RigModel, t: &TrainingRecord<'_>) -> usize {
    t.y.len().min((4.0 * rig.fs_hz) as usize)
}

/// Seed of the `i`-th training record's simulation in [`refine_paths`] (its background in
/// [`measured_excess`] is the same realisation).
fn refine_seed(i: usize) -> u64 {
    5000 + i as u64
}

/// Each record's smoothed measured PSD (`measured`) over the rig's background behind the chain
/// at its speed and length ([`refine_len`], seed [`refine_seed`]), at least a tenth of the
/// measured, as the paths were first fitted: what [`refine_paths`] holds each record's
/// simulated fault part against.
fn measured_excess(
    rig: &RigModel,
    records: &[TrainingRecord<'_>],
    measured: &[Vec<f64>],
    welch: &Welch,
    half: usize,
) -> Result<Vec<Vec<f64>>, CloseLoopError> {
    records
        .iter()
        .zip(measured)
        .enumerate()
        .map(|(i, (t, meas))| {
            let bg = apply_fir(
                &rig.chain_fir,
                &rig.background(t.rpm, refine_len(rig, t), refine_seed(i)),
            );
            let s_b = smooth(&welch.try_psd(&bg)?, half);
            Ok(meas
                .iter()
                .zip(&s_b)
                .map(|(a, b)| (a - b).max(0.1 * a))
                .collect())
        })
        .collect()
}

/// One round of closing the loop on the impact paths: for each training record the fault part of
/// its simulation (the rig's fault signal behind the chain, at the record's speed and length up
/// to 4 s) against the measured excess over the rig's background (smoothed PSDs, the excess at
/// least a tenth of the measured, as the paths were first fitted); each path's response is
/// multiplied by the mean over its records of the log ratio (each record's ratio at zero mean,
/// so the gain keeps the level; at most [`MAX_PATH_STEP_DB`] per bin) and refitted. The
/// first fit draws a path from the excess over the vertical excitation alone; the sensor's
/// horizontal share, the chain's roll-off, the strike gate and the random part, fitted after it,
/// bend what the sensor sees of the path, and one or two rounds take that out. Returns whether
/// any path changed.
fn refine_paths(
    rig: &mut RigModel,
    records: &[TrainingRecord<'_>],
    excess: &[Vec<f64>],
    welch: &Welch,
    half: usize,
) -> Result<bool, CloseLoopError> {
    let nb = welch.n_bins();
    let mut sum: Vec<(Vec<f64>, usize)> = vec![(vec![0.0; nb], 0); rig.impact_paths.len()];
    for (i, (t, target)) in records.iter().zip(excess).enumerate() {
        let Ok(p) = rig.impact_path_for_at(t.location, t.size_mm, t.outer_angle_rad) else {
            continue;
        };
        let Some(k) = rig.impact_paths.iter().position(|q| std::ptr::eq(q, p)) else {
            continue;
        };
        let mut syn = Synthesis::new(
            t.location.class(),
            t.size_mm,
            t.rpm,
            refine_len(rig, t),
            refine_seed(i),
        );
        syn.outer_angle_rad = t.outer_angle_rad;
        let fault = apply_fir(&rig.chain_fir, &rig.fault_signal(&syn)?);
        let s_f = smooth(&welch.try_psd(&fault)?, half);
        let r: Vec<f64> = target
            .iter()
            .zip(&s_f)
            .map(|(a, f)| (a.max(1e-300) / f.max(1e-300)).ln())
            .collect();
        if !r.iter().all(|v| v.is_finite()) {
            continue;
        }
        let mean = r[1..].iter().sum::<f64>() / (nb - 1).max(1) as f64;
        for (acc, v) in sum[k].0.iter_mut().zip(&r) {
            *acc += v - mean;
        }
        sum[k].1 += 1;
    }
    let cap = MAX_PATH_STEP_DB / 10.0 * std::f64::consts::LN_10;
    let mut changed = false;
    for (p, (acc, count)) in rig.impact_paths.iter_mut().zip(sum) {
        if count == 0 {
            continue;
        }
        let old = p.path.psd(nb, welch.df());
        let shape: Vec<f64> = old
            .iter()
            .zip(&acc)
            .map(|(o, c)| o * (c / count as f64).clamp(-cap, cap).exp())
            .collect();
        p.path = impact_path_of(&shape, welch, rig.fs_hz)?;
        changed = true;
    }
    Ok(changed)
}

/// The radial load on the shaft from the outer-race records with the spall at the top
/// (`top`), opposite the load zone: each is paired with the on-axis (6 o'clock) training record
/// of the same size nearest in speed; its measured ratio is the fault power (mean square over
/// the rig's healthy background at its speed) of the top record over that of the 6 o'clock
/// one; the simulated ratio, at each of [`RADIAL_LOADS_N`], is the mean square of the two
/// excitations (same seed, same slip draws) through the 6 o'clock path of that size. The load
/// with the smallest mean |ln(simulated / measured)| wins (0 when no record pairs). Gain,
/// random fraction and strike gate are the same for the two positions and cancel in the ratio.
#[allow(clippy::too_many_arguments)]
fn fit_radial_load(
    bearing: Bearing,
    preload_m: f64,
    machine: &MachineModel,
    training: &[TrainingRecord<'_>],
    measured: &[(Vec<f64>, f64)],
    background: &[(Vec<f64>, f64)],
    top: &[TrainingRecord<'_>],
    fit0: &PathFit,
    bg_of: &dyn Fn(f64, usize, u64) -> Vec<f64>,
    len: usize,
) -> Result<f64, CloseLoopError> {
    let fs = machine.fs_hz;
    let same_size = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1.0);
    let mut pairs = Vec::new();
    for (j, t) in top.iter().enumerate() {
        let Some(i) = (0..training.len())
            .filter(|&i| {
                training[i].location == Location::Outer && same_size(training[i].size_mm, t.size_mm)
            })
            .min_by(|&a, &b| {
                (training[a].rpm - t.rpm)
                    .abs()
                    .total_cmp(&(training[b].rpm - t.rpm).abs())
            })
        else {
            continue;
        };
        let n = t.y.len().min(len);
        let bg = bg_of(t.rpm, n, 300 + j as u64);
        let top_excess = variance(&t.y[..n]) - variance(&bg);
        let six_excess = measured[i].1 - background[i].1;
        if top_excess > 0.0 && six_excess > 0.0 {
            pairs.push((i, *t, top_excess / six_excess, n));
        }
    }
    if pairs.is_empty() {
        return Ok(0.0);
    }
    let mut best: Option<(f64, f64)> = None;
    for &radial in RADIAL_LOADS_N {
        let mut err = 0.0;
        for (k, (i, t, meas, n)) in pairs.iter().enumerate() {
            let six = &training[*i];
            let path = &fit0.path_of(Location::Outer, t.size_mm).path;
            let power = |angle: f64| -> Result<f64, CloseLoopError> {
                let e = excitation(
                    bearing,
                    preload_m,
                    radial,
                    FaultClass::Outer,
                    t.size_mm,
                    t.rpm * machine.speed_ratio,
                    angle,
                    fs,
                    n + WARMUP,
                    3000 + k as u64,
                    EXCITATION_HOUSING_HZ,
                )?;
                let y = path.filter(&e.vertical);
                Ok(mean_square(&y[WARMUP.min(y.len() / 2)..]))
            };
            let (p_top, p_six) = (power(t.outer_angle_rad)?, power(six.outer_angle_rad)?);
            let sim = if p_six > 0.0 { p_top / p_six } else { 0.0 };
            err += if sim > 0.0 {
                (sim / meas).ln().abs()
            } else {
                f64::INFINITY
            };
        }
        let err = err / pairs.len() as f64;
        if best.is_none_or(|b| err < b.1) {
            best = Some((radial, err));
        }
    }
    Ok(best.map_or(0.0, |b| b.0))
}

/// The sensor's horizontal sensitivity κ: for each off-axis outer-race record, the κ in [0, 20]
/// (bisection) at which the rig's simulated mean square — the 6 o'clock severity of its size —
/// matches the measured one; the geometric mean over the records (0 without any).
fn fit_horizontal(
    rig: &RigModel,
    bearing: Bearing,
    cross: &[TrainingRecord<'_>],
) -> Result<f64, CloseLoopError> {
    let mut logs = Vec::new();
    for (i, t) in cross.iter().enumerate() {
        let (g, q) = rig.severity(Location::Outer, t.size_mm)?;
        let e = excitation(
            bearing,
            rig.preload_m,
            rig.radial_load_n,
            FaultClass::Outer,
            t.size_mm,
            t.rpm * rig.healthy.speed_ratio,
            t.outer_angle_rad,
            rig.fs_hz,
            t.y.len().min((4.0 * rig.fs_hz) as usize) + WARMUP,
            2000 + i as u64,
            rig.excitation_housing_hz,
        )?;
        let path = rig.impact_path_for(Location::Outer, t.size_mm)?;
        let strike = rig.strike_fraction(Location::Outer, t.size_mm)?;
        let tau = BURST_PERIODS * rig.fs_hz / rig.fault_rate_hz(Location::Outer, t.rpm).max(1e-9);
        let ms = |k: f64| {
            let impacts = gated(&e.seen(k), strike, tau, 19 + i as u64);
            let f = path.path.filter(&mix(&impacts, q, 13 + i as u64));
            g * g * mean_square(&f[WARMUP..])
        };
        let bg = background_of(
            &rig.healthy,
            &rig.chain_lines,
            &rig.background_fir,
            &rig.background_chain_fir,
            rig.fs_hz,
            t.rpm,
            t.y.len().min((4.0 * rig.fs_hz) as usize),
            7 + i as u64,
        );
        let target = (variance(t.y) - variance(&bg)).max(0.0);
        let (mut lo, mut hi) = (0.0f64, 20.0f64);
        if ms(hi) < target || ms(lo) > target {
            continue;
        }
        for _ in 0..30 {
            let mid = 0.5 * (lo + hi);
            if ms(mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        logs.push((0.5 * (lo + hi)).max(1e-6).ln());
    }
    Ok(if logs.is_empty() {
        0.0
    } else {
        (logs.iter().sum::<f64>() / logs.len() as f64).exp()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Gaussian;
    use crate::spectrum::{bandpass_coefficients, biquad_filter};

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
        let rig = crate::rig::cwru_rig().unwrap();
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
