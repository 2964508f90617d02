//! The calibrated rig simulator: the committed CWRU rig loads and validates, synthesis is seeded
//! and typed, severities interpolate, and calibration recovers the rig it is run on (a rig's own
//! simulated records as the "measured" data: the gains, preload and predicted levels come back).

use bearing_model::{Bearing, FaultClass};
use calibrated_rig::{self as rig, Location, RigModel, Synthesis, TrainingRecord};
use close_loop::{CloseLoopError, LoopConfig};

fn rms(y: &[f64]) -> f64 {
    let m = y.iter().sum::<f64>() / y.len() as f64;
    (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / y.len() as f64).sqrt()
}

#[test]
fn committed_rig_loads_round_trips_and_rejects_bad_files() {
    let r = rig::cwru_rig().expect("committed rig");
    assert_eq!(r.units, "g");
    assert_eq!(r.fs_hz, 12_000.0);
    assert!(!r.severities.is_empty() && !r.impact_paths.is_empty());
    let back = RigModel::from_json(&r.to_json().unwrap()).unwrap();
    assert_eq!(back, r);
    let text = r.to_json().unwrap();
    assert!(matches!(
        RigModel::from_json(&text.replacen("hybrid-fdd/rig-model", "other", 1)),
        Err(CloseLoopError::MachineModelMismatch { what: "format", .. })
    ));
    assert!(matches!(
        RigModel::from_json("{"),
        Err(CloseLoopError::MachineModelFormat { .. })
    ));
    let mut bad = r.clone();
    bad.severities[0].gain = -1.0;
    assert!(RigModel::from_json(&bad.to_json().unwrap()).is_err());
    let mut bad = r.clone();
    bad.preload_m = 1.0;
    assert!(RigModel::from_json(&bad.to_json().unwrap()).is_err());
    assert!(r.check_compatible(48_000.0, "6205").is_err());
    assert!(r.check_compatible(12_000.0, "6203").is_err());
    // a rig file written before the strike gate: every impact strikes
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    for s in v["severities"].as_array_mut().unwrap() {
        s.as_object_mut().unwrap().remove("strike_fraction");
    }
    let old = RigModel::from_json(&v.to_string()).unwrap();
    assert!(old.severities.iter().all(|s| s.strike_fraction == 1.0));
    // one written before the excitation's mount resonance was stored was fitted at 20 kHz
    assert_eq!(r.excitation_housing_hz, rig::EXCITATION_HOUSING_HZ);
    v.as_object_mut().unwrap().remove("excitation_housing_hz");
    let old = RigModel::from_json(&v.to_string()).unwrap();
    assert_eq!(old.excitation_housing_hz, rig::LEGACY_EXCITATION_HOUSING_HZ);
    // a mount inside the output band (or not a number) is refused
    for hz in [1000.0, f64::NAN] {
        let mut bad = r.clone();
        bad.excitation_housing_hz = hz;
        assert!(matches!(
            RigModel::from_json(&bad.to_json().unwrap_or_else(|_| text.clone())),
            Err(CloseLoopError::MachineModelFormat { .. })
        ));
    }
}

/// The strike gate is on the asked fraction of the time, in bursts of the asked mean length, with
/// mean square 1; it is seeded; a fraction of 1 is no gate.
#[test]
fn strike_gate_has_the_asked_fraction_bursts_and_power() {
    let (n, p, burst) = (400_000, 0.2, 50.0);
    let g = rig::strike_gate(n, p, burst, 7);
    let on = g.iter().filter(|v| **v > 0.0).count() as f64 / n as f64;
    assert!((on / p - 1.0).abs() < 0.1, "on {on}");
    let ms = g.iter().map(|v| v * v).sum::<f64>() / n as f64;
    assert!((ms - 1.0).abs() < 0.1, "mean square {ms}");
    let starts = g.windows(2).filter(|w| w[0] == 0.0 && w[1] > 0.0).count() as f64;
    let mean_burst = on * n as f64 / starts;
    assert!(
        (mean_burst / burst - 1.0).abs() < 0.15,
        "burst {mean_burst}"
    );
    assert_eq!(g, rig::strike_gate(n, p, burst, 7));
    assert_ne!(g, rig::strike_gate(n, p, burst, 8));
    assert!(
        rig::strike_gate(100, 1.0, burst, 7)
            .iter()
            .all(|v| *v == 1.0)
    );
}

/// Gating an impact train lowers its fault line's prominence in the envelope spectrum by far
/// more than the periodic power it removes would alone, and keeps its mean square.
#[test]
fn gated_impacts_stand_lower_in_the_envelope_spectrum() {
    let (fs, f0, n) = (12_000.0, 97.0, 600_000);
    // decaying 3 kHz ring-downs every 1/f0 s
    let mut x = vec![0.0; n];
    let period = fs / f0;
    let mut t0 = 0.0;
    while (t0 as usize) < n {
        for k in 0..200.min(n - t0 as usize) {
            let t = k as f64 / fs;
            x[t0 as usize + k] +=
                (-t * 800.0).exp() * (2.0 * std::f64::consts::PI * 3000.0 * t).sin();
        }
        t0 += period;
    }
    let gate = rig::strike_gate(n, 0.12, rig::BURST_PERIODS * period, 3);
    let y: Vec<f64> = x.iter().zip(&gate).map(|(a, g)| a * g).collect();
    let line = |v: &[f64]| rig::line_prominence_db(v, fs, f0).unwrap().unwrap();
    let (plain, gated) = (line(&x), line(&y));
    assert!(plain - gated > 15.0, "{plain:.1} dB -> {gated:.1} dB");
    assert!(gated > 3.0, "the line is still there: {gated:.1} dB");
    let ms = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>() / v.len() as f64;
    assert!((ms(&y) / ms(&x) - 1.0).abs() < 0.3);
}

#[test]
fn severity_interpolates_in_log_size_and_holds_outside() {
    let mut r = rig::cwru_rig().unwrap();
    r.severities.retain(|s| s.location == Location::Inner);
    r.severities.truncate(2);
    let (a, b) = (r.severities[0].clone(), r.severities[1].clone());
    let (lo, hi) = if a.size_mm < b.size_mm {
        (a, b)
    } else {
        (b, a)
    };
    let mid = (lo.size_mm * hi.size_mm).sqrt();
    let (g, q) = r.severity(Location::Inner, mid).unwrap();
    assert!((g - (lo.gain * hi.gain).sqrt()).abs() < 1e-9 * g);
    assert!((q - 0.5 * (lo.random_fraction + hi.random_fraction)).abs() < 1e-12);
    let p = r.strike_fraction(Location::Inner, mid).unwrap();
    assert!((p - 0.5 * (lo.strike_fraction + hi.strike_fraction)).abs() < 1e-12);
    assert_eq!(
        r.strike_fraction(Location::Inner, 10.0).unwrap(),
        hi.strike_fraction
    );
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(
        r.severity(Location::Inner, 0.01 * lo.size_mm).unwrap().0,
        lo.gain
    ));
    assert!(close(r.severity(Location::Inner, 10.0).unwrap().0, hi.gain));
    assert!(matches!(
        r.severity(Location::Ball, 0.3),
        Err(CloseLoopError::Model { .. })
    ));
}

/// An outer-race spall at a position the rig holds severities for uses them (interpolated
/// over that position's sizes); any other position, and every inner-race or ball spall, uses the
/// reference severities; a position on another location or a non-finite one is refused on
/// load.
#[test]
fn outer_race_positions_use_their_own_severities() {
    use std::f64::consts::FRAC_PI_2;
    let mut r = rig::cwru_rig().unwrap();
    r.severities
        .retain(|s| s.location != Location::Outer || s.outer_angle_rad.is_none());
    let reference = r
        .severities
        .iter()
        .find(|s| s.location == Location::Outer)
        .unwrap()
        .clone();
    let size = reference.size_mm;
    let six = r.severity_at(Location::Outer, size, -FRAC_PI_2).unwrap();
    assert_eq!(six, r.severity(Location::Outer, size).unwrap());
    let mut top = reference.clone();
    top.outer_angle_rad = Some(FRAC_PI_2);
    top.gain = 0.25 * reference.gain;
    top.random_fraction = 0.9;
    top.strike_fraction = 0.12;
    r.severities.push(top);
    let r = rig::RigModel::from_json(&r.to_json().unwrap()).unwrap();
    // 12 o'clock (and a hair off it) reads the top severity at every size, held beyond it
    for angle in [
        FRAC_PI_2,
        FRAC_PI_2 + 0.05,
        FRAC_PI_2 - 2.0 * std::f64::consts::TAU,
    ] {
        for s in [size, 0.5 * size, 3.0 * size] {
            let (g, q) = r.severity_at(Location::Outer, s, angle).unwrap();
            assert!(
                (g - 0.25 * reference.gain).abs() <= 1e-12 * g,
                "{angle} {s}"
            );
            assert_eq!(q, 0.9);
            assert_eq!(
                r.strike_fraction_at(Location::Outer, s, angle).unwrap(),
                0.12
            );
        }
    }
    // 6 and 3 o'clock keep the reference
    for angle in [-FRAC_PI_2, 0.0, FRAC_PI_2 + 0.3] {
        assert_eq!(
            r.severity_at(Location::Outer, size, angle).unwrap(),
            r.severity(Location::Outer, size).unwrap()
        );
    }
    assert_eq!(r.severity(Location::Outer, size).unwrap(), six);
    // inner race: a position never selects anything
    assert_eq!(
        r.severity_at(Location::Inner, 0.3, FRAC_PI_2).unwrap(),
        r.severity(Location::Inner, 0.3).unwrap()
    );
    // a louder top severity makes a louder 12 o'clock record than a 6 o'clock one would be
    let synth = |angle: f64| {
        let mut s = Synthesis::new(FaultClass::Outer, size, 1797.0, 12_000, 5);
        s.outer_angle_rad = angle;
        let y = r.fault_signal(&s).unwrap();
        rms(&y)
    };
    let mut louder = r.clone();
    for s in louder
        .severities
        .iter_mut()
        .filter(|s| s.outer_angle_rad.is_some())
    {
        s.gain *= 8.0;
    }
    let louder_top = {
        let mut s = Synthesis::new(FaultClass::Outer, size, 1797.0, 12_000, 5);
        s.outer_angle_rad = FRAC_PI_2;
        rms(&louder.fault_signal(&s).unwrap())
    };
    assert!((louder_top / synth(FRAC_PI_2) - 8.0).abs() < 1e-6 * 8.0);
    // a path fitted at 12 o'clock serves 12 o'clock only; the reference path every other position
    let mut r = r.clone();
    r.impact_paths.retain(|p| p.outer_angle_rad.is_none());
    let reference_path = r.impact_path_for(Location::Outer, size).unwrap().clone();
    let mut top_path = reference_path.clone();
    top_path.outer_angle_rad = Some(FRAC_PI_2);
    top_path.path.ar = vec![-0.5];
    r.impact_paths.push(top_path.clone());
    let r = rig::RigModel::from_json(&r.to_json().unwrap()).unwrap();
    assert_eq!(
        r.impact_path_for_at(Location::Outer, 3.0 * size, FRAC_PI_2 + 0.05)
            .unwrap(),
        &top_path
    );
    assert_eq!(
        r.impact_path_for(Location::Outer, size).unwrap(),
        &reference_path
    );
    assert_eq!(
        r.impact_path_for_at(Location::Outer, size, -FRAC_PI_2)
            .unwrap(),
        &reference_path
    );
    let mut bad = r.clone();
    bad.impact_paths.last_mut().unwrap().location = Location::Inner;
    assert!(rig::RigModel::from_json(&bad.to_json().unwrap()).is_err());
    // a position on another location is refused on load
    let mut bad = r.clone();
    let inner = bad
        .severities
        .iter_mut()
        .find(|s| s.location == Location::Inner)
        .unwrap();
    inner.outer_angle_rad = Some(0.0);
    assert!(rig::RigModel::from_json(&bad.to_json().unwrap()).is_err());
}

#[test]
fn synthesis_is_seeded_superposes_and_errors_are_typed() {
    let r = rig::cwru_rig().unwrap();
    let n = 6_000;
    let s = Synthesis::new(FaultClass::Inner, 0.3, 1797.0, n, 5);
    let a = r.synthesize(&s).unwrap();
    assert_eq!(a, r.synthesize(&s).unwrap());
    assert_ne!(
        a,
        r.synthesize(&Synthesis { seed: 6, ..s }).unwrap(),
        "another seed, another realisation"
    );
    // a fault adds power to the healthy machine
    let h = r
        .synthesize(&Synthesis::new(FaultClass::None, 0.3, 1797.0, n, 5))
        .unwrap();
    assert!(rms(&a) > 1.2 * rms(&h), "{} vs {}", rms(&a), rms(&h));
    // combined faults superpose: (IO − N) = (I − N) + (O − N), the chain being linear
    let syn = |c| r.synthesize(&Synthesis::new(c, 0.3, 1797.0, n, 5)).unwrap();
    let (io, i, o) = (
        syn(FaultClass::InnerOuter),
        syn(FaultClass::Inner),
        syn(FaultClass::Outer),
    );
    let scale = rms(&io);
    for k in 0..n {
        assert!((io[k] - h[k] - (i[k] - h[k]) - (o[k] - h[k])).abs() < 1e-9 * scale);
    }
    assert!(matches!(
        r.synthesize(&Synthesis::new(FaultClass::Inner, 0.3, 0.0, n, 1)),
        Err(CloseLoopError::InvalidRpm { .. })
    ));
    assert!(
        r.synthesize(&Synthesis::new(FaultClass::Inner, 0.3, 1797.0, 100, 1))
            .is_err()
    );
    assert!(
        r.synthesize(&Synthesis::new(FaultClass::Inner, 20.0, 1797.0, n, 1))
            .is_err()
    );
}

/// Calibrate on records simulated by a known rig: the recovered rig predicts the levels of
/// held-out conditions (another speed, other seeds) within 15 %, and its strike fractions come
/// back within one grid step. (The contact preload is weakly identified from one speed: the
/// committed rig's 2 µm comes back as a stiffer preload, which moves the 1730 rpm levels by up to
/// ~13 %.)
/// Mean RMS of `r`'s synthesis over three realisations (`synth(0..3)`): a gated train's level
/// varies from burst pattern to burst pattern.
fn mean_rms(r: &RigModel, synth: impl Fn(u64) -> Synthesis) -> f64 {
    (0..3)
        .map(|k| rms(&r.synthesize(&synth(k)).unwrap()))
        .sum::<f64>()
        / 3.0
}

#[test]
fn calibration_recovers_the_rig_it_is_run_on() {
    let truth = rig::cwru_rig().unwrap();
    let fs = truth.fs_hz;
    let healthy = truth.background_as_calibrated(1797.0, (6.0 * fs) as usize, 1);
    // the background chain is read where some record's fault adds least (module docs of
    // `rig`): on CWRU that is the 0.007 in ball record (118), whose counterpart is here
    let specs = [
        (Location::Inner, 0.178),
        (Location::Outer, 0.533),
        (Location::Ball, 0.356),
        (Location::Ball, 0.178),
    ];
    let ys: Vec<Vec<f64>> = specs
        .iter()
        .enumerate()
        .map(|(i, (loc, size))| {
            truth
                .synthesize(&Synthesis::new(
                    loc.class(),
                    *size,
                    1797.0,
                    // as long as a CWRU record: a ball spall strikes in bursts, and a 4 s record
                    // holds too few of them to fix its level within 15 %
                    (10.0 * fs) as usize,
                    10 + i as u64,
                ))
                .unwrap()
        })
        .collect();
    let names = ["a", "b", "c", "e"];
    let mut training: Vec<TrainingRecord<'_>> = specs
        .iter()
        .zip(&ys)
        .zip(names)
        .map(|(((loc, size), y), name)| TrainingRecord {
            name,
            location: *loc,
            size_mm: *size,
            outer_angle_rad: -std::f64::consts::FRAC_PI_2,
            rpm: 1797.0,
            y,
        })
        .collect();
    // the outer-race spall at 12 o'clock, opposite the load zone: it fixes the radial load
    let top = truth
        .synthesize(&Synthesis {
            outer_angle_rad: std::f64::consts::FRAC_PI_2,
            ..Synthesis::new(
                Location::Outer.class(),
                0.533,
                1797.0,
                (10.0 * fs) as usize,
                13,
            )
        })
        .unwrap();
    training.push(TrainingRecord {
        name: "d",
        location: Location::Outer,
        size_mm: 0.533,
        outer_angle_rad: std::f64::consts::FRAC_PI_2,
        rpm: 1797.0,
        y: &top,
    });
    let cfg = LoopConfig::default().check().unwrap();
    let got = rig::calibrate_rig(
        &healthy,
        fs,
        1797.0,
        Bearing::Skf6205,
        &training,
        &cfg,
        "test",
    )
    .unwrap();
    // the fault records' chain on the healthy background (the truth rig's, which the records
    // carry and the healthy recording does not) comes back: mean power response over 4.2–5.4 kHz
    let band_power = |h: &[f64]| {
        let m = h.len() / 2;
        let fs_bins: Vec<f64> = (0..=24).map(|i| 4200.0 + 50.0 * i as f64).collect();
        fs_bins
            .iter()
            .map(|f| {
                let w = 2.0 * std::f64::consts::PI * f / fs;
                let re: f64 = h
                    .iter()
                    .enumerate()
                    .map(|(k, c)| c * (w * (k as f64 - m as f64)).cos())
                    .sum();
                re * re
            })
            .sum::<f64>()
            / fs_bins.len() as f64
    };
    assert!(!truth.background_chain_fir.is_empty());
    let (want, have) = (
        band_power(&truth.background_chain_fir),
        band_power(&got.background_chain_fir),
    );
    assert!(
        want < 0.6,
        "the committed rig attenuates its background there: {want}"
    );
    assert!(
        (have / want).ln().abs() < 1.5f64.ln(),
        "recovered background chain {have:.3} against {want:.3}"
    );
    // four reference severities and the 12 o'clock record's own
    assert_eq!(got.severities.len(), 5);
    assert_eq!(
        got.severities
            .iter()
            .filter_map(|s| s.outer_angle_rad)
            .collect::<Vec<_>>(),
        vec![std::f64::consts::FRAC_PI_2]
    );
    // the strike fraction comes back within one step of the grid it is chosen from — where the
    // truth pins it: a truth severity whose random fraction sits at its search bound (0.99: even
    // a wholly random train does not bring the kurtosis down to the record's) strikes a train
    // that is random all but 1 %, and its strike fraction is not identified by the data (the
    // 0.178 mm ball, 118's counterpart, where the background chain is read: the committed rig's
    // own choice moved 0.18 → 0.08 with a small change of the healthy machine's background, and
    // this calibration reads 0.35). Its level is checked (bands, below); at least three strike
    // fractions are.
    let mut checked = 0;
    for s in &got.severities {
        let truth_sev = truth.severities.iter().find(|t| {
            t.location == s.location
                && (t.size_mm - s.size_mm).abs() < 1e-3
                && t.outer_angle_rad.is_some() == s.outer_angle_rad.is_some()
        });
        if truth_sev.is_some_and(|t| t.random_fraction >= 0.99 - 1e-9) {
            continue;
        }
        checked += 1;
        let want = match s.outer_angle_rad {
            None => truth.strike_fraction(s.location, s.size_mm).unwrap(),
            Some(a) => truth.strike_fraction_at(s.location, s.size_mm, a).unwrap(),
        };
        let step = |p: f64| {
            (0..rig::STRIKE_FRACTIONS.len())
                .min_by(|&a, &b| {
                    let d = |i: usize| (rig::STRIKE_FRACTIONS[i] - p).abs();
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(0) as i64
        };
        assert!(
            (step(s.strike_fraction) - step(want)).abs() <= 1,
            "{:?} {} mm: strike fraction {} vs truth {want}",
            s.location,
            s.size_mm,
            s.strike_fraction
        );
    }
    assert!(
        checked >= 3,
        "strike fraction checked on {checked} records only"
    );
    // the 12 o'clock spall's level: the radial load (with the preload it is fitted at; the two
    // trade off, so the level, not the load, is what must come back)
    let top = |k: u64| Synthesis {
        outer_angle_rad: std::f64::consts::FRAC_PI_2,
        ..Synthesis::new(
            Location::Outer.class(),
            0.533,
            1730.0,
            (10.0 * fs) as usize,
            70 + k,
        )
    };
    let (a, b) = (mean_rms(&truth, top), mean_rms(&got, top));
    assert!(
        (b / a - 1.0).abs() < 0.15,
        "outer at 12 o'clock: recovered rig RMS {b} vs truth {a} (radial load {} N vs {} N)",
        got.radial_load_n,
        truth.radial_load_n
    );
    // the training records' band energies come back (the impact paths are closed on their
    // records): each of the four bands of the recovered rig within ×1.5 of the training
    // record's, the rig's as a mean over three 10 s realisations on other seeds. A sparsely
    // gated train's band levels vary by up to ×2 from one 10 s realisation to the next (the
    // 0.356 mm ball, striking on 8 % of its bursts, 1.1e-2 to 2.2e-2 in 2–4 kHz over ten
    // seeds), so a single realisation of the truth is no reference: the calibration can only
    // reproduce the realisation it was given
    for ((loc, size), y) in specs.iter().zip(&ys) {
        let a = rig::signal_stats(y, fs, None).unwrap().band_energy;
        let mut b = [0.0; 4];
        for seed in 60..63 {
            let syn = Synthesis::new(loc.class(), *size, 1797.0, (10.0 * fs) as usize, seed);
            let e = rig::signal_stats(&got.synthesize(&syn).unwrap(), fs, None)
                .unwrap()
                .band_energy;
            for k in 0..4 {
                b[k] += e[k] / 3.0;
            }
        }
        for k in 0..4 {
            assert!(
                (b[k] / a[k]).ln().abs() < 1.5f64.ln(),
                "{loc:?} {size} mm band {k}: recovered {:.3e} vs training record {:.3e}",
                b[k],
                a[k]
            );
        }
    }
    for (loc, size) in specs {
        // held out: the training speed and 1730 rpm, other seeds; a gated train's level varies
        // from burst pattern to burst pattern, so the levels are means over three 10 s
        // realisations
        for rpm in [1797.0, 1730.0] {
            let held =
                |k: u64| Synthesis::new(loc.class(), size, rpm, (10.0 * fs) as usize, 90 + k);
            let (a, b) = (mean_rms(&truth, held), mean_rms(&got, held));
            assert!(
                (b / a - 1.0).abs() < 0.15,
                "{loc:?} at {rpm} rpm: recovered rig RMS {b} vs truth {a}"
            );
        }
    }
}

/// Bad calibration input is a typed error, never a panic: no training record, a training record
/// shorter than one spectral segment, a non-finite healthy record.
#[test]
fn calibration_rejects_bad_input_with_typed_errors() {
    let truth = rig::cwru_rig().unwrap();
    let fs = truth.fs_hz;
    let healthy = truth.background_as_calibrated(1797.0, (4.0 * fs) as usize, 2);
    let cfg = LoopConfig::default().check().unwrap();
    let cal = |h: &[f64], t: &[TrainingRecord<'_>]| {
        rig::calibrate_rig(h, fs, 1797.0, Bearing::Skf6205, t, &cfg, "test")
    };
    assert!(cal(&healthy, &[]).is_err());
    let short = vec![0.1; 100];
    let rec = TrainingRecord {
        name: "short",
        location: Location::Inner,
        size_mm: 0.178,
        outer_angle_rad: 0.0,
        rpm: 1797.0,
        y: &short,
    };
    assert!(cal(&healthy, &[rec]).is_err());
    let mut bad = healthy.clone();
    bad[10] = f64::NAN;
    let y = truth
        .synthesize(&Synthesis::new(FaultClass::Inner, 0.178, 1797.0, 24_000, 3))
        .unwrap();
    let rec = TrainingRecord { y: &y, ..rec };
    assert!(cal(&bad, &[rec]).is_err());
}

#[test]
fn signal_stats_measure_and_reject() {
    // a Gaussian-like signal: kurtosis near 3, crest a few; a constant or short one is an error
    let r = rig::cwru_rig().unwrap();
    let y = r.background(1797.0, 24_000, 4);
    let s = rig::signal_stats(&y, r.fs_hz, Some(100.0)).unwrap();
    assert!((2.5..4.0).contains(&s.kurtosis), "{}", s.kurtosis);
    assert!(s.crest > 2.0 && s.rms > 0.0);
    let total: f64 = s.band_energy.iter().sum();
    assert!(
        (total / (s.rms * s.rms) - 1.0).abs() < 0.1,
        "bands {total} vs {}",
        s.rms * s.rms
    );
    assert!(s.line_prominence_db.is_some());
    assert!(matches!(
        rig::signal_stats(&[1.0; 8000], r.fs_hz, None),
        Err(CloseLoopError::ZeroSignal)
    ));
    assert!(matches!(
        rig::signal_stats(&y[..100], r.fs_hz, None),
        Err(CloseLoopError::TooShort { .. })
    ));
}

/// The committed rig holds one impact path per calibrated location and size; a spall is seen
/// through its own size's path, another size through the nearest one (log size); a path
/// without a size (files written before paths were fitted per size) serves every size; a
/// non-positive size is rejected on load.
#[test]
fn impact_paths_are_per_size_and_the_nearest_calibrated_size_is_used() {
    let r = rig::cwru_rig().unwrap();
    for s in &r.severities {
        let p = r.impact_path_for(s.location, s.size_mm).unwrap();
        assert_eq!(p.location, s.location);
        assert_eq!(p.size_mm, Some(s.size_mm), "{:?} {}", s.location, s.size_mm);
    }
    let sizes = |loc: Location| -> Vec<f64> {
        let mut v: Vec<f64> = r
            .impact_paths
            .iter()
            .filter(|p| p.location == loc)
            .filter_map(|p| p.size_mm)
            .collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let inner = sizes(Location::Inner);
    assert!(inner.len() >= 2, "{inner:?}");
    let (small, large) = (inner[0], inner[inner.len() - 1]);
    assert_eq!(
        r.impact_path_for(Location::Inner, 0.9 * small)
            .unwrap()
            .size_mm,
        Some(small)
    );
    assert_eq!(
        r.impact_path_for(Location::Inner, 6.0).unwrap().size_mm,
        Some(large)
    );
    // the paths of different sizes are different paths
    assert_ne!(
        r.impact_path_for(Location::Inner, small).unwrap().path,
        r.impact_path_for(Location::Inner, large).unwrap().path
    );
    // an unsized (pooled) path serves every size of its location
    let mut pooled = r.clone();
    pooled
        .impact_paths
        .retain(|p| p.location != Location::Outer);
    let mut p = r.impact_path_for(Location::Outer, 0.533).unwrap().clone();
    p.size_mm = None;
    pooled.impact_paths.push(p.clone());
    let back = RigModel::from_json(&pooled.to_json().unwrap()).unwrap();
    assert_eq!(back.impact_path_for(Location::Outer, 0.178).unwrap(), &p);
    assert!(!pooled.to_json().unwrap().contains("\"size_mm\": null"));
    let mut bad = r.clone();
    bad.impact_paths[0].size_mm = Some(0.0);
    assert!(RigModel::from_json(&bad.to_json().unwrap()).is_err());
}

/// The excitation's looser integration tolerance ([`rig::EXCITATION_RTOL`]) stays within
/// 1e-3 relative RMS of the same model integrated at 1e-8 (the bearing model's accuracy
/// target against its reference), for a race spall and a ball at the dissertation's lowest
/// speed and at CWRU's.
#[test]
fn excitation_tolerance_keeps_the_output_within_1e_3_of_a_tight_integration() {
    let r = rig::cwru_rig().expect("committed rig");
    let fs = r.fs_hz;
    let n = (0.25 * fs) as usize;
    for (class, rpm) in [(FaultClass::Outer, 1797.0), (FaultClass::Ball, 300.0)] {
        let at = |rtol: f64| {
            rig::excitation_with(
                Bearing::Skf6205,
                r.preload_m,
                r.radial_load_n,
                class,
                0.5,
                rpm,
                0.0,
                fs,
                n,
                11,
                r.excitation_housing_hz,
                rtol,
            )
            .expect("simulates")
            .vertical
        };
        let (x, reference) = (at(rig::EXCITATION_RTOL), at(1e-8));
        let d = x
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        let norm = reference.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(norm > 0.0);
        assert!(d / norm < 1e-3, "{class:?} at {rpm} rpm: {:.2e}", d / norm);
    }
}

#[test]
fn a_shared_excitation_is_simulated_once_and_changes_nothing_but_the_work() {
    let r = rig::cwru_rig().unwrap();
    let n = 6_000;
    let s = |c, seed| Synthesis::new(c, 0.3, 450.0, n, seed).with_excitation_seed(77);
    let cache = rig::ExcitationCache::default();
    for (c, seed) in [
        (FaultClass::Inner, 1),
        (FaultClass::InnerOuter, 2),
        (FaultClass::InnerOuterBall, 3),
    ] {
        assert_eq!(
            r.synthesize_cached(&s(c, seed), &cache).unwrap(),
            r.synthesize(&s(c, seed)).unwrap(),
            "{c:?}: bit-identical with and without the cache"
        );
    }
    assert_eq!(
        cache.len(),
        3,
        "one excitation per location, shared by the classes"
    );
    // the combined fault is the superposition of the single-fault recordings' very spalls:
    // with every seed but the excitation's equal, (IO − N) = (I − N) + (O − N)
    let h = r.synthesize(&s(FaultClass::None, 9)).unwrap();
    let (io, i, o) = (
        r.synthesize_cached(&s(FaultClass::InnerOuter, 9), &cache)
            .unwrap(),
        r.synthesize_cached(&s(FaultClass::Inner, 9), &cache)
            .unwrap(),
        r.synthesize_cached(&s(FaultClass::Outer, 9), &cache)
            .unwrap(),
    );
    let scale = rms(&io);
    for k in 0..n {
        assert!((io[k] - h[k] - (i[k] - h[k]) - (o[k] - h[k])).abs() < 1e-9 * scale);
    }
    // without a shared excitation seed each class draws its own spall (the seed's)
    let own = r
        .synthesize(&Synthesis::new(FaultClass::Inner, 0.3, 450.0, n, 1))
        .unwrap();
    assert_ne!(own, r.synthesize(&s(FaultClass::Inner, 1)).unwrap());
    assert_eq!(cache.len(), 3);
}
