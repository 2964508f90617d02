//! The impact paths: the smoothing of the PSDs they are fitted on, their first fit on the
//! training records' excess spectra with each record's gain, and the rounds that close the loop
//! on them.

use super::{
    Bearing, CloseLoopError, EXCITATION_HOUSING_HZ, Excitation, ImpactPath, Location, MachineModel,
    RigModel, StructuralPath, Synthesis, TrainingRecord, WARMUP, Welch, apply_fir, excitation,
    mean_square,
};

/// Half width of the smoothing applied to the PSDs the impact path is fitted on, Hz.
pub(super) const SMOOTH_HZ: f64 = 150.0;
/// AR order of the impact path.
pub const IMPACT_PATH_ORDER: usize = 48;

/// Moving average of a PSD over ±`half` bins (edges use what exists).
pub(super) fn smooth(p: &[f64], half: usize) -> Vec<f64> {
    let mut cum = vec![0.0; p.len() + 1];
    for (k, v) in p.iter().enumerate() {
        cum[k + 1] = cum[k] + v;
    }
    (0..p.len())
        .map(|k| {
            let lo = k.saturating_sub(half);
            let hi = (k + half + 1).min(p.len());
            (cum[hi] - cum[lo]) / (hi - lo) as f64
        })
        .collect()
}

/// Impact paths and gains fitted for one preload.
pub(super) struct PathFit {
    pub(super) paths: Vec<ImpactPath>,
    pub(super) gains: Vec<f64>,
    pub(super) sims: Vec<Excitation>,
}

impl PathFit {
    pub(super) fn path_of(&self, loc: Location, size_mm: f64) -> &ImpactPath {
        super::nearest_path(&self.paths, loc, size_mm).unwrap_or(&self.paths[0])
    }
}

/// For each location and spall size with training records: the AR path of the mean log ratio of
/// smoothed excess PSD (measured minus healthy, at least a tenth of the measured) to smoothed
/// excitation PSD, each record's ratio normalised to zero mean log; then each record's gain from
/// its excess mean square.
#[allow(clippy::too_many_arguments)]
pub(super) fn fit_paths(
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
pub(super) fn excess_log_ratio(
    measured: &[f64],
    background: &[f64],
    excitation: &[f64],
) -> Vec<f64> {
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
pub(super) fn impact_path_of(
    shape: &[f64],
    welch: &Welch,
    fs: f64,
) -> Result<StructuralPath, CloseLoopError> {
    let mut path = StructuralPath::from_psd(shape, welch.df(), fs, IMPACT_PATH_ORDER)?;
    path.excitation_variance = 1.0;
    Ok(path)
}

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
pub(super) fn measured_excess(
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
pub(super) fn refine_paths(
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
