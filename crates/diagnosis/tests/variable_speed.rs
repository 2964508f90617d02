//! Simulated machines (`bearing_model::machine`) whose speed sweeps through the recording — a
//! slow wander tone of 15 % at 0.06 Hz over 6 s, a 20–30 % spread — diagnosed self-referenced at
//! their mean speed: healthy ones stay `normal`, faulty ones are named, both through the order
//! tracking along their own shaft comb (`diagnosis::driver::first_look`).

mod common;

use bearing_model::FaultLocation;
use bearing_model::machine::{LocalizedFault, MachineParams, MachineRecipe, Nuisances};
use common::{show, sig};
use diagnosis::{BearingSpec, diagnose};

/// A machine of `name` at a mean of `rpm`, recorded 6 s, its speed sweeping (a wander tone of
/// 15 % at 0.06 Hz, phase from the seed), with `nuisances` and an optional fault at 0 dB.
fn sweeping(
    name: &str,
    rpm: f64,
    fs: f64,
    nuisances: Nuisances,
    fault: Option<FaultLocation>,
    seed: u64,
) -> MachineParams {
    let g = BearingSpec::parse(name).unwrap().geometry.unwrap();
    let mut r = MachineRecipe::healthy(g, rpm, fs, 6.0, seed)
        .unwrap()
        .with_nuisances(nuisances);
    if let Some(location) = fault {
        r = r.with_fault(LocalizedFault {
            location,
            severity_db: 0.0,
        });
    }
    let mut p = r.draw().unwrap();
    p.speed.tones = vec![[0.06, 0.15, seed as f64]];
    p.speed.rms_fraction = 0.1;
    p
}

/// 24 healthy sweeping machines (four bearings × three seeds × a shaft comb alone or with every
/// nuisance): at most one alarm (α = 1 % per recording), and most of them tracked.
#[test]
fn healthy_sweeping_machines_stay_normal() {
    let (mut alarms, mut tracked, mut n) = (Vec::new(), 0, 0);
    for (name, fs, rpm) in [
        ("6205", 12_000.0, 1800.0),
        ("6203", 20_000.0, 1500.0),
        ("UC204", 20_000.0, 1200.0),
        ("ZA-2115", 25_600.0, 2000.0),
    ] {
        let spec = BearingSpec::parse(name).unwrap();
        for nuisances in [Nuisances::SHAFT_COMB, Nuisances::ALL] {
            for seed in 1..=3 {
                let x = sweeping(name, rpm, fs, nuisances, None, seed)
                    .synthesize()
                    .unwrap()
                    .accel;
                let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
                let what = format!("{name} {} seed {seed}", nuisances.label());
                show(&what, &d);
                n += 1;
                tracked += usize::from(d.order_tracking.is_some());
                // a tracked record is read at its measured speed, and says the user's
                if d.order_tracking.is_some() {
                    let sp = d.operating_point.speed.as_ref().expect("a speed finding");
                    assert_eq!(sp.declared_rpm, Some(rpm), "{what}");
                    assert_eq!(sp.source, diagnosis::SpeedSource::SpectrumComb, "{what}");
                    assert!(sp.note.contains("order-tracked"), "{what}: {}", sp.note);
                }
                if d.verdict != "normal" {
                    alarms.push(format!("{what}: {}", d.verdict));
                }
            }
        }
    }
    eprintln!("{} alarms, {tracked} tracked, of {n}", alarms.len());
    assert!(alarms.len() <= 1, "{alarms:?}");
    assert!(2 * tracked >= n, "{tracked} of {n} tracked");
}

/// Sweeping machines with a fault at 0 dB (a 6205 at 1800 rpm mean, 12 kHz, and a UC204 at
/// 1200 rpm, 20 kHz, each with a shaft comb; outer, inner and ball races, two seeds): the fault
/// found on (nearly) every one — named alone, or with a second hypothesis significant beside it,
/// or among an `uncertain` verdict's candidates — and named alone on most. Beside each, the same
/// record order-tracked from a simulated 60-pulse tachometer (the tracking an encoder gives): the
/// tachless tracking names nearly as many. Until 2026-12-08 (frames tracked one after another,
/// the tracked record read as if its mean speed had been declared) 10 of 12 were named alone;
/// the path through all frames at once and the tracked record read at its measured speed, which
/// read the corpus's sweeping machines better (faults typed 10 → 14 of 45), name 9 and find 11
/// here — the misses on the UC204, where the tachometer's tracking too names one with a second
/// hypothesis (`inner+outer`): at 0 dB the second hypothesis stands near its significance level
/// either way.
#[test]
fn faulty_sweeping_machines_are_named() {
    let (mut named, mut found, mut named_tach, mut n, mut missed) = (0, 0, 0, 0, Vec::new());
    for (name, fs, rpm) in [("6205", 12_000.0, 1800.0), ("UC204", 20_000.0, 1200.0)] {
        let spec = BearingSpec::parse(name).unwrap();
        for location in [
            FaultLocation::Outer,
            FaultLocation::Inner,
            FaultLocation::Ball,
        ] {
            for seed in 1..=2 {
                let p = sweeping(name, rpm, fs, Nuisances::SHAFT_COMB, Some(location), seed);
                let (x, tach) = (p.synthesize().unwrap().accel, p.tachometer(60.0).unwrap());
                let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
                let what = format!("{name} {location:?} seed {seed}");
                show(&what, &d);
                let mut e = residual_features::SpectralEngine::new();
                let t = residual_features::order::order_track(&mut e, &x, &tach, fs, 60.0).unwrap();
                let dt = diagnose(
                    &sig(&t.samples, t.equivalent_fs_hz),
                    t.mean_rpm,
                    &spec,
                    None,
                )
                .unwrap();
                show(&format!("{what}, with a tachometer"), &dt);
                n += 1;
                named_tach += usize::from(dt.verdict == location.name());
                if d.verdict.split('+').any(|v| v == location.name())
                    || d.candidates.contains(&location)
                {
                    found += 1;
                }
                if d.verdict == location.name() {
                    named += 1;
                } else {
                    missed.push(format!(
                        "{what}: {} (tracked {})",
                        d.verdict,
                        d.order_tracking.is_some()
                    ));
                }
            }
        }
    }
    eprintln!(
        "{named} of {n} named, {found} found; with a tachometer {named_tach}; missed {missed:?}"
    );
    assert!(found + 1 >= n, "found {found} of {n}: {missed:?}");
    assert!(named >= 9, "{named} of {n}: {missed:?}");
    assert!(
        named + 3 >= named_tach,
        "{named} of {n}, {named_tach} with a tachometer"
    );
}
