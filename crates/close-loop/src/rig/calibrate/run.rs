//! [`calibrate_rig`]: the calibration's stages in order, with the search of the contact preload
//! and the fit of the severities (gain, random fraction, strike fraction) of every record.

use super::*;

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
