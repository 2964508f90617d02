//! The radial load on the shaft and the sensor's horizontal sensitivity, from the outer-race
//! records with the spall off 6 o'clock.

use super::{
    BURST_PERIODS, Bearing, CloseLoopError, EXCITATION_HOUSING_HZ, FaultClass, Location,
    MachineModel, PathFit, RADIAL_LOADS_N, RigModel, TrainingRecord, WARMUP, background_of,
    excitation, gated, mean_square, mix, variance,
};

/// The radial load on the shaft from the outer-race records with the spall at the top
/// (`top`), opposite the load zone: each is paired with the on-axis (6 o'clock) training record
/// of the same size nearest in speed; its measured ratio is the fault power (mean square over
/// the rig's healthy background at its speed) of the top record over that of the 6 o'clock
/// one; the simulated ratio, at each of [`RADIAL_LOADS_N`], is the mean square of the two
/// excitations (same seed, same slip draws) through the 6 o'clock path of that size. The load
/// with the smallest mean |ln(simulated / measured)| wins (0 when no record pairs). Gain,
/// random fraction and strike gate are the same for the two positions and cancel in the ratio.
#[allow(clippy::too_many_arguments)]
pub(super) fn fit_radial_load(
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
pub(super) fn fit_horizontal(
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
