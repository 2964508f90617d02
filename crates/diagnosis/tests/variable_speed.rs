//! Simulated machines (`bearing_model::machine`) whose speed sweeps through the recording — a
//! slow wander tone of 15 % at 0.06 Hz over 6 s, a 20–30 % spread — diagnosed self-referenced at
//! their mean speed: healthy ones stay `normal`, faulty ones are named, both through the order
//! tracking along their own shaft comb (`diagnosis::driver::first_look`).

mod common;

use bearing_model::FaultLocation;
use bearing_model::machine::{LocalizedFault, MachineRecipe, Nuisances};
use common::{show, sig};
use diagnosis::{BearingSpec, diagnose};

/// A 6 s recording of `name` at a mean of `rpm`, its speed sweeping (a wander tone of 15 % at
/// 0.06 Hz, phase from the seed), with `nuisances` and an optional fault at 0 dB.
fn sweeping(
    name: &str,
    rpm: f64,
    fs: f64,
    nuisances: Nuisances,
    fault: Option<FaultLocation>,
    seed: u64,
) -> Vec<f64> {
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
    p.synthesize().unwrap().accel
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
                let x = sweeping(name, rpm, fs, nuisances, None, seed);
                let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
                let what = format!("{name} {} seed {seed}", nuisances.label());
                show(&what, &d);
                n += 1;
                tracked += usize::from(d.order_tracking.is_some());
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
/// 1200 rpm, 20 kHz, each with a shaft comb; outer, inner and ball races, two seeds): named.
#[test]
fn faulty_sweeping_machines_are_named() {
    let (mut named, mut n, mut missed) = (0, 0, Vec::new());
    for (name, fs, rpm) in [("6205", 12_000.0, 1800.0), ("UC204", 20_000.0, 1200.0)] {
        let spec = BearingSpec::parse(name).unwrap();
        for location in [
            FaultLocation::Outer,
            FaultLocation::Inner,
            FaultLocation::Ball,
        ] {
            for seed in 1..=2 {
                let x = sweeping(name, rpm, fs, Nuisances::SHAFT_COMB, Some(location), seed);
                let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
                let what = format!("{name} {location:?} seed {seed}");
                show(&what, &d);
                n += 1;
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
    eprintln!("{named} of {n} named; missed {missed:?}");
    assert!(named >= 9, "{named} of {n}: {missed:?}");
}
