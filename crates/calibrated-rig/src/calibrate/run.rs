//! [`calibrate_rig`]: the calibration's stages in order, with the search of the contact preload
//! and the fit of the severities (gain, random fraction, strike fraction) of every record.

use super::{
    BURST_PERIODS, Bearing, CloseLoopError, DEPTH_M, EXCITATION_HOUSING_HZ, Excitation, FORMAT,
    FaultClass, ImpactPath, Location, MachineLine, MachineModel, PRELOADS_M, PathFit, RigModel,
    RigProvenance, SLIP_FRACTION, SMOOTH_HZ, STRIKE_FRACTIONS, Severity, TrainingRecord, VERSION,
    WARMUP, Welch, apply_fir, background_chain, background_of, background_remainder,
    chain_response, chain_tones, excess_log_ratio, excitation, fault_rate_of, fit_horizontal,
    fit_paths, fit_radial_load, gated, impact_path_of, kurtosis, line_prominence_db, mean_square,
    measured_excess, mix, refine_paths, smooth, variance,
};

/// What the stages of a rig calibration share: the healthy machine and its background, the
/// reference training records (outer-race spalls at 6 o'clock, inner races, balls) with their
/// smoothed measured PSDs and variances and their background's, and the Welch estimator.
struct Stages<'c, 'a> {
    bearing: Bearing,
    fs: f64,
    machine: &'c MachineModel,
    chain_lines: &'c [MachineLine],
    remainder: &'c [f64],
    bg_chain: &'c [f64],
    training: &'c [TrainingRecord<'a>],
    measured: &'c [(Vec<f64>, f64)],
    background: &'c [(Vec<f64>, f64)],
    welch: &'c Welch,
    half: usize,
}

/// A record whose severity is fitted: (seed index, record, its excitation, the path it is seen
/// through).
type Rec<'r, 'a> = (usize, TrainingRecord<'a>, &'r Excitation, &'r ImpactPath);

/// Calibrate a rig: the healthy machine on `healthy` (at `fs`, `rpm`), the impact path and one
/// severity per training record (module docs). `rule` says how the training records were chosen.
///
/// The stages, in order: the healthy machine model; the records split into the reference ones,
/// the off-axis outer races (the sensor's horizontal sensitivity κ) and the top ones (the radial
/// load); the rig's background at each record's speed; the contact preload; the radial load; the
/// impact paths at both; the severities; κ and the measurement chain, each followed by the
/// severities again; the off-axis and top records' own paths and severities; the paths' closed
/// loop.
///
/// # Errors
/// The errors of [`close_loop::machine::calibrate`], of the Welch PSD and of [`excitation`];
/// [`CloseLoopError::Model`] when no training record carries more power than the healthy
/// machine.
pub fn calibrate_rig(
    healthy: &[f64],
    fs: f64,
    rpm: f64,
    bearing: Bearing,
    training: &[TrainingRecord<'_>],
    cfg: &close_loop::CheckedConfig,
    rule: &str,
) -> Result<RigModel, CloseLoopError> {
    let machine =
        close_loop::machine::calibrate(&close_loop::Signal::new(healthy, fs)?, rpm, bearing, cfg)?;
    let (training, cross, top) = split_records(training)?;
    let training = training.as_slice();
    let nperseg = ((fs / 12.0).log2().round().exp2() as usize).max(close_loop::MIN_NPERSEG);
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
    let mut stages = Stages {
        bearing,
        fs,
        machine: &machine,
        chain_lines: &chain_lines,
        remainder: &remainder,
        bg_chain: &bg_chain,
        training,
        measured: &measured,
        background: &[],
        welch: &welch,
        half,
    };
    let background: Vec<(Vec<f64>, f64)> = training
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let n = t.y.len().min((4.0 * fs) as usize);
            let bg = stages.bg_of(t.rpm, n, 7 + i as u64);
            Ok((smooth(&welch.try_psd(&bg)?, half), variance(&bg)))
        })
        .collect::<Result<_, CloseLoopError>>()?;
    stages.background = &background;
    let stages = stages;

    let short = (2.0 * fs) as usize;
    let preload_m = stages.preload(short)?;
    // the radial load, at that preload: the one whose 12-over-6 o'clock ratio of simulated
    // impact power matches the measured ratio of fault power (module docs)
    let radial_load_n = if top.is_empty() {
        0.0
    } else {
        let fit0 = stages.fit_at(preload_m, 0.0, short)?;
        let bg_of = |rpm: f64, n: usize, seed: u64| stages.bg_of(rpm, n, seed);
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
    let fit = stages.fit_at(preload_m, radial_load_n, long)?;
    let recs: Vec<Rec<'_, '_>> = training
        .iter()
        .enumerate()
        .map(|(i, t)| (i, *t, &fit.sims[i], fit.path_of(t.location, t.size_mm)))
        .collect();
    let severities = stages.severities_for(&recs, 0.0, &[], None);
    let strikes: Vec<f64> = severities.iter().map(|s| s.strike_fraction).collect();
    let mut rig = RigModel {
        format: FORMAT.to_string(),
        version: VERSION,
        fs_hz: fs,
        units: "unknown".to_string(),
        bearing: machine.bearing.clone(),
        healthy: machine.clone(),
        chain_lines: chain_lines.clone(),
        impact_paths: fit.paths.clone(),
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
        rig.severities = stages.severities_for(&recs, rig.sensor_horizontal, &[], Some(&strikes));
    }
    // the measurement chain's response (the fault records' anti-alias roll-off), then the
    // severities once more behind it
    rig.chain_fir = chain_response(&rig, training, &measured, &welch, half)?;
    if !rig.chain_fir.is_empty() {
        rig.severities =
            stages.severities_for(&recs, rig.sensor_horizontal, &rig.chain_fir, Some(&strikes));
    }
    // the off-axis and top records' own severities (each CWRU position is a separate bearing):
    // their excitation at their position, seen through their size's path and behind the same
    // sensor and chain, fitted as the reference records are (strike fraction searched)
    let positioned: Vec<TrainingRecord<'_>> = cross.iter().chain(&top).copied().collect();
    let sims = stages.positioned_excitations(&positioned, preload_m, radial_load_n, long)?;
    let (own_paths, measured_all) =
        stages.own_paths(&positioned, &sims, &fit, rig.sensor_horizontal, long)?;
    let recs: Vec<Rec<'_, '_>> = positioned
        .iter()
        .zip(&sims)
        .zip(&own_paths)
        .enumerate()
        .map(|(j, ((t, sim), path))| (training.len() + j, *t, sim, path))
        .collect();
    let own = stages.severities_for(&recs, rig.sensor_horizontal, &rig.chain_fir, None);
    rig.severities
        .extend(own.into_iter().zip(&positioned).map(|(mut s, t)| {
            s.outer_angle_rad = Some(t.outer_angle_rad);
            s
        }));
    rig.impact_paths.extend(own_paths);
    stages.close_paths(&mut rig, &fit, &positioned, &sims, &measured_all)?;
    Ok(rig)
}

/// The training records split by what they calibrate: outer-race records with the spall off the
/// vertical (sensor) axis calibrate the sensor's horizontal sensitivity (`cross`), those with the
/// spall at the top, opposite the load zone, the radial load (`top`); the rest (returned first)
/// calibrate paths and severities.
///
/// # Errors
/// [`CloseLoopError::Model`] when no record is left for the paths.
#[allow(clippy::type_complexity)]
fn split_records<'a>(
    training: &[TrainingRecord<'a>],
) -> Result<
    (
        Vec<TrainingRecord<'a>>,
        Vec<TrainingRecord<'a>>,
        Vec<TrainingRecord<'a>>,
    ),
    CloseLoopError,
> {
    let off_axis = |t: &TrainingRecord<'_>| {
        t.location == Location::Outer && t.outer_angle_rad.sin().abs() < 0.5
    };
    let opposite =
        |t: &TrainingRecord<'_>| t.location == Location::Outer && t.outer_angle_rad.sin() > 0.5;
    let cross: Vec<TrainingRecord<'_>> = training.iter().copied().filter(off_axis).collect();
    let top: Vec<TrainingRecord<'_>> = training.iter().copied().filter(opposite).collect();
    let reference: Vec<TrainingRecord<'_>> = training
        .iter()
        .copied()
        .filter(|t| !off_axis(t) && !opposite(t))
        .collect();
    if reference.is_empty() {
        return Err(CloseLoopError::Model {
            reason: "no training fault record to calibrate the impact paths on".into(),
        });
    }
    Ok((reference, cross, top))
}

impl Stages<'_, '_> {
    /// The rig's background (healthy machine, chain tones, remainder, the fault records' chain)
    /// at `rpm`, `n` samples, noise seed `seed`.
    fn bg_of(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        background_of(
            self.machine,
            self.chain_lines,
            self.remainder,
            self.bg_chain,
            self.fs,
            rpm,
            n,
            seed,
        )
    }

    /// The impact paths and gains fitted at a preload and radial load on excitations of `len`
    /// samples ([`fit_paths`]).
    fn fit_at(&self, preload: f64, radial: f64, len: usize) -> Result<PathFit, CloseLoopError> {
        fit_paths(
            self.bearing,
            preload,
            radial,
            self.fs,
            self.machine,
            self.training,
            self.measured,
            self.background,
            self.welch,
            self.half,
            len,
        )
    }

    /// The contact load: the preload of [`PRELOADS_M`] whose fitted rig gives the training
    /// records' kurtosis best (mean |ln(simulated / measured kurtosis)|), on excitations of
    /// `short` samples.
    fn preload(&self, short: usize) -> Result<f64, CloseLoopError> {
        let kurt: Vec<f64> = self.training.iter().map(|t| kurtosis(t.y)).collect();
        let mut best: Option<(f64, f64)> = None;
        for &preload in PRELOADS_M {
            let fit = self.fit_at(preload, 0.0, short)?;
            let mut err = 0.0;
            for (i, t) in self.training.iter().enumerate() {
                if let Some(y) = self.striking_record(&fit, i, t) {
                    err += (kurtosis(&y) / kurt[i]).ln().abs();
                }
            }
            let err = err / self.training.len() as f64;
            if best.is_none_or(|b| err < b.1) {
                best = Some((preload, err));
            }
        }
        Ok(best.map_or(0.0, |b| b.0))
    }

    /// Training record `i` (`t`) simulated through `fit` with its impacts as often as the record's
    /// fault line says they strike (the strike fraction whose simulated line prominence is
    /// nearest the measured one), since striking in bursts raises the kurtosis as a stiffer
    /// contact does; `None` when no strike fraction gives a line to compare.
    fn striking_record(&self, fit: &PathFit, i: usize, t: &TrainingRecord<'_>) -> Option<Vec<f64>> {
        let fs = self.fs;
        let (g, path) = (&fit.gains[i], fit.path_of(t.location, t.size_mm));
        let rate = fault_rate_of(self.machine, t.location, t.rpm);
        let tau = BURST_PERIODS * fs / rate.max(1e-9);
        let impacts: Vec<f64> = fit.sims[i].vertical.iter().map(|v| g * v).collect();
        // the background and the measured line do not depend on the strike fraction
        let bg = self.bg_of(t.rpm, impacts.len(), 7 + i as u64);
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
        chosen.map(|(_, y)| y)
    }

    /// Severities (gain, random fraction, strike fraction) of every record of `recs` for a
    /// sensor κ behind the chain `chain` ([`Stages::severity`]).
    fn severities_for(
        &self,
        recs: &[Rec<'_, '_>],
        kappa: f64,
        chain: &[f64],
        strikes: Option<&[f64]>,
    ) -> Vec<Severity> {
        recs.iter()
            .enumerate()
            .map(|(k, rec)| self.severity(rec, kappa, chain, strikes.map(|b| b[k])))
            .collect()
    }

    /// A record's severity for a sensor κ: for each strike fraction of the grid (or the one
    /// already chosen, `strike`), the random fraction that matches the record's kurtosis and
    /// the gain that matches its excess mean square; the strike fraction whose simulated fault
    /// line stands as far over its envelope-spectrum neighbours as the measured one (the
    /// record's first samples, as many as simulated) wins.
    fn severity(
        &self,
        &(i, t, sim, path): &Rec<'_, '_>,
        kappa: f64,
        chain: &[f64],
        strike: Option<f64>,
    ) -> Severity {
        let fs = self.fs;
        let seen = sim.seen(kappa);
        let bg = apply_fir(chain, &self.bg_of(t.rpm, sim.vertical.len(), 7 + i as u64));
        let skip = WARMUP.min(bg.len() / 2);
        let (measured_var, measured_kurt) = (variance(t.y), kurtosis(t.y));
        let excess = (measured_var - variance(&bg[skip..])).max(0.0);
        let rate = fault_rate_of(self.machine, t.location, t.rpm);
        let tau = BURST_PERIODS * fs / rate.max(1e-9);
        let strike_fit = StrikeFit {
            i,
            seen: &seen,
            bg: &bg,
            chain,
            path,
            excess,
            measured_kurt,
            tau,
        };
        // one gate realisation while the strike fraction is searched, three for the fit
        let search = [17];
        let fit_seeds: &[u64] = &[17, 1017, 2017];
        let (strike, (g, q, _)) = match strike {
            Some(b) => (b, strike_fit.fit(b, fit_seeds)),
            None => {
                let strike = strike_fit.search(&search, t, fs, rate);
                (strike, strike_fit.fit(strike, fit_seeds))
            }
        };
        Severity {
            location: t.location,
            size_mm: t.size_mm,
            gain: g,
            random_fraction: q,
            strike_fraction: strike,
            record: t.name.to_string(),
            outer_angle_rad: None,
        }
    }

    /// The off-axis and top records' excitations at their own spall positions.
    fn positioned_excitations(
        &self,
        positioned: &[TrainingRecord<'_>],
        preload_m: f64,
        radial_load_n: f64,
        long: usize,
    ) -> Result<Vec<Excitation>, CloseLoopError> {
        positioned
            .iter()
            .enumerate()
            .map(|(j, t)| {
                excitation(
                    self.bearing,
                    preload_m,
                    radial_load_n,
                    FaultClass::Outer,
                    t.size_mm,
                    t.rpm * self.machine.speed_ratio,
                    t.outer_angle_rad,
                    self.fs,
                    t.y.len().min(long) + WARMUP,
                    1000 + (self.training.len() + j) as u64,
                    EXCITATION_HOUSING_HZ,
                )
            })
            .collect()
    }

    /// The off-axis and top records' own paths (the path from a defect at 3 or 12 o'clock to the
    /// sensor is not the one from 6): fitted as the reference paths are, on the excess over the
    /// rig's background against what the sensor (κ = `kappa`) sees of their excitation; and every
    /// training record's smoothed measured PSD, the positioned ones after the references.
    fn own_paths(
        &self,
        positioned: &[TrainingRecord<'_>],
        sims: &[Excitation],
        fit: &PathFit,
        kappa: f64,
        long: usize,
    ) -> Result<(Vec<ImpactPath>, Vec<Vec<f64>>), CloseLoopError> {
        let (welch, half) = (self.welch, self.half);
        let mut own_paths: Vec<ImpactPath> = Vec::with_capacity(positioned.len());
        let mut measured_all: Vec<Vec<f64>> = self.measured.iter().map(|m| m.0.clone()).collect();
        for (j, (t, sim)) in positioned.iter().zip(sims).enumerate() {
            let n = t.y.len().min(long);
            let s_y = smooth(&welch.try_psd(t.y)?, half);
            measured_all.push(s_y.clone());
            let s_b = smooth(
                &welch.try_psd(&self.bg_of(t.rpm, n, 7 + (self.training.len() + j) as u64))?,
                half,
            );
            let s_x = smooth(&welch.try_psd(&sim.seen(kappa))?, half);
            let r = excess_log_ratio(&s_y, &s_b, &s_x);
            let shape: Vec<f64> = r.iter().map(|v| v.exp()).collect();
            let own = match impact_path_of(&shape, welch, self.fs) {
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
        Ok((own_paths, measured_all))
    }

    /// Close the loop on the paths: each is corrected by what its records' simulated fault
    /// spectrum misses of the measured one, behind everything fitted since it was first drawn
    /// (sensor, chain, gate, mix), and the severities are fitted again through it, at most
    /// [`PATH_REFINEMENTS`](super::PATH_REFINEMENTS) times.
    fn close_paths(
        &self,
        rig: &mut RigModel,
        fit: &PathFit,
        positioned: &[TrainingRecord<'_>],
        sims: &[Excitation],
        measured_all: &[Vec<f64>],
    ) -> Result<(), CloseLoopError> {
        let training = self.training;
        let everyone: Vec<TrainingRecord<'_>> =
            training.iter().chain(positioned).copied().collect();
        // what each record's fault must add: its measured excess over the rig's background behind
        // the chain (neither changes between rounds)
        let excess = measured_excess(rig, &everyone, measured_all, self.welch, self.half)?;
        let strikes_all: Vec<f64> = rig.severities.iter().map(|s| s.strike_fraction).collect();
        for _ in 0..super::PATH_REFINEMENTS {
            if !refine_paths(rig, &everyone, &excess, self.welch, self.half)? {
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
                        .zip(sims)
                        .enumerate()
                        .map(|(j, (t, sim))| (training.len() + j, *t, sim)),
                )
                .map(|(i, t, sim)| {
                    let path = super::nearest_path_at(
                        &paths,
                        t.location,
                        t.size_mm,
                        Some(t.outer_angle_rad),
                    )
                    .unwrap_or(&paths[0]);
                    (i, t, sim, path)
                })
                .collect();
            let angles: Vec<Option<f64>> =
                rig.severities.iter().map(|s| s.outer_angle_rad).collect();
            rig.severities = self
                .severities_for(
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
        Ok(())
    }
}

/// One record's severity fit at a sensor κ: its impacts as the sensor sees them (`seen`), the
/// background behind the chain (`bg`), its path, the excess mean square the fault must add and
/// the measured kurtosis.
struct StrikeFit<'r> {
    i: usize,
    seen: &'r [f64],
    bg: &'r [f64],
    chain: &'r [f64],
    path: &'r ImpactPath,
    excess: f64,
    measured_kurt: f64,
    tau: f64,
}

impl StrikeFit<'_> {
    /// (gain, random fraction, simulated record) for a strike fraction, the gain and the
    /// kurtosis averaged over the gate realisations of `seeds` (a gated train's kurtosis varies
    /// from burst pattern to burst pattern).
    fn fit(&self, strike: f64, seeds: &[u64]) -> (f64, f64, Vec<f64>) {
        let i = self.i;
        let trains: Vec<Vec<f64>> = seeds
            .iter()
            .map(|s| gated(self.seen, strike, self.tau, s + i as u64))
            .collect();
        // gain and simulated records for a random fraction q
        let at = |q: f64| {
            let through: Vec<Vec<f64>> = trains
                .iter()
                .map(|x| {
                    apply_fir(
                        self.chain,
                        &self.path.path.filter(&mix(x, q, 11 + i as u64)),
                    )
                })
                .collect();
            let skip = WARMUP.min(through[0].len() / 2);
            let ms =
                through.iter().map(|x| mean_square(&x[skip..])).sum::<f64>() / through.len() as f64;
            let g = (self.excess / ms.max(1e-300)).sqrt();
            let ys: Vec<Vec<f64>> = through
                .iter()
                .map(|x| {
                    x[skip..]
                        .iter()
                        .zip(&self.bg[skip..])
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
        let measured_kurt = self.measured_kurt;
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
    }

    /// The strike fraction of [`STRIKE_FRACTIONS`] (each fitted on the gate realisations of
    /// `seeds`) whose simulated record reaches the measured kurtosis and, among those, whose
    /// fault line (at `rate` Hz) stands nearest the measured line's prominence; 1 when none
    /// gives a line to compare.
    fn search(&self, seeds: &[u64], t: TrainingRecord<'_>, fs: f64, rate: f64) -> f64 {
        // (strike, kurtosis out of reach, line miss)
        let mut best: Option<(f64, f64, f64)> = None;
        // the measured line, on as many samples as simulated (the same for every strike
        // fraction): computed once
        let mut measured_line = None;
        for &strike in &STRIKE_FRACTIONS {
            let r = self.fit(strike, seeds);
            let m = r.2.len().min(t.y.len());
            let meas = measured_line.get_or_insert_with(|| line_prominence_db(&t.y[..m], fs, rate));
            let (Ok(Some(sim)), Ok(Some(meas))) = (line_prominence_db(&r.2, fs, rate), meas) else {
                continue;
            };
            let meas = *meas;
            let miss = (sim - meas).abs();
            // how far the random fraction's range leaves the kurtosis: a strike fraction that
            // cannot reach it loses to one that can
            let out =
                ((kurtosis(&r.2) / self.measured_kurt).ln().abs() - KURTOSIS_REACHED.ln()).max(0.0);
            let better =
                best.is_none_or(|b| out < b.1 - 1e-9 || (out <= b.1 + 1e-9 && miss < b.2 - 1e-9));
            if better {
                best = Some((strike, out, miss));
            }
        }
        best.map_or(1.0, |b| b.0)
    }
}

/// A simulated kurtosis within this factor of the measured one counts as reached when the
/// strike fraction is chosen: the random fraction's bisection lands within it unless its range
/// cannot reach the measured kurtosis.
const KURTOSIS_REACHED: f64 = 1.1;
