//! One 10 s, 12 kHz simulated outer-race recording diagnosed against a prepared baseline model
//! (the AR fit of the baseline and its envelope spectra are outside the timed loop), and against
//! the same baseline as a model would give it (no recording to compare envelope lines with).
//! Target: ≤ 50 ms. Then 10 s at 12, 20 and 51.2 kHz (machines of the corpus,
//! `bearing_model::machine`, with a shaft comb and an outer-race fault) against a prepared
//! baseline, for the cost per sample at the rates other rigs record at.
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use bearing_model::{FaultClass, Noise, Scenario};
use criterion::{Criterion, criterion_group, criterion_main};
use diagnosis::{Baseline, BearingSpec, Signal, diagnose};

fn bench(c: &mut Criterion) {
    let rpm = 1797.0;
    let rec = |class, seed| {
        Scenario::cwru(class, 0.014, rpm)
            .unwrap()
            .with_duration(10.0)
            .with_noise(Noise::SnrDb(10.0))
            .with_seed(seed)
            .simulate()
            .unwrap()
    };
    let healthy = rec(FaultClass::None, 1);
    let faulty = rec(FaultClass::Outer, 2);
    let baseline = Baseline::prepare(&Signal::new(&healthy.accel, healthy.fs_hz).unwrap()).unwrap();
    let recording = Signal::new(&faulty.accel, faulty.fs_hz).unwrap();
    let spec = BearingSpec::parse("6205").unwrap();
    // the same baseline without its residual: no envelope lines of the healthy machine to
    // compare with (a machine-model baseline with no synthesised recording attached)
    let model_like = Baseline::from_whitener(
        baseline.whitener.clone(),
        baseline.residual_rms,
        baseline.residual_kurtosis,
        baseline.samples,
    )
    .unwrap();
    // a machine model's whole-model predictor is longer (CWRU 97 at 12 kHz: path order 64 plus
    // two per line, 142): the same predictor padded with zero coefficients to that order costs
    // what such a whitener costs
    let mut long = baseline.whitener.coefficients.clone();
    long.resize(142, 0.0);
    let machine_like = Baseline::from_whitener(
        diagnosis::ArWhitener::from_coefficients(long, healthy.fs_hz, "bench").unwrap(),
        baseline.residual_rms,
        baseline.residual_kurtosis,
        baseline.samples,
    )
    .unwrap();
    for (name, b) in [
        ("diagnose 10 s 12 kHz, baseline model only", &model_like),
        (
            "diagnose 10 s 12 kHz, model only, whitener of order 142",
            &machine_like,
        ),
        ("diagnose 10 s 12 kHz with prepared baseline", &baseline),
    ] {
        c.bench_function(name, |bench| {
            bench.iter(|| diagnose(std::hint::black_box(&recording), rpm, &spec, Some(b)).unwrap())
        });
    }
}

fn bench_rates(c: &mut Criterion) {
    use bearing_model::machine::{LocalizedFault, MachineRecipe, Nuisances};
    use bearing_model::{BearingGeometry, FaultLocation};
    let rpm = 1500.0;
    let spec = BearingSpec::parse("6205").unwrap();
    for fs in [12_000.0, 20_000.0, 51_200.0] {
        let recipe = |seed| {
            MachineRecipe::healthy(BearingGeometry::skf_6205(), rpm, fs, 10.0, seed)
                .unwrap()
                .with_nuisances(Nuisances::SHAFT_COMB)
        };
        let healthy = recipe(1).synthesize().unwrap();
        let faulty = recipe(1)
            .with_fault(LocalizedFault {
                location: FaultLocation::Outer,
                severity_db: 0.0,
            })
            .synthesize()
            .unwrap();
        let baseline = Baseline::prepare(&Signal::new(&healthy.accel, fs).unwrap()).unwrap();
        let recording = Signal::new(&faulty.accel, fs).unwrap();
        c.bench_function(
            &format!(
                "machine with a shaft comb, 10 s {} kHz, prepared baseline",
                fs / 1000.0
            ),
            |bench| {
                bench.iter(|| {
                    diagnose(
                        std::hint::black_box(&recording),
                        rpm,
                        &spec,
                        Some(&baseline),
                    )
                    .unwrap()
                })
            },
        );
    }
}

/// A 10 s, 12 kHz 6205 machine at 1500 rpm (seed 1) with the nuisances `mix` and an outer-race
/// fault at 0 dB.
fn outer_race_machine(mix: bearing_model::machine::Nuisances) -> Vec<f64> {
    use bearing_model::machine::{LocalizedFault, MachineRecipe};
    use bearing_model::{BearingGeometry, FaultLocation};
    MachineRecipe::healthy(BearingGeometry::skf_6205(), 1500.0, 12_000.0, 10.0, 1)
        .unwrap()
        .with_nuisances(mix)
        .with_fault(LocalizedFault {
            location: FaultLocation::Outer,
            severity_db: 0.0,
        })
        .synthesize()
        .unwrap()
        .accel
}

/// That machine without a shaft comb: the declared speed is unconfirmed, so the detector reads
/// the templates at it and over its ± 10 % (both readings, the costlier path), self-referenced.
fn bench_unconfirmed(c: &mut Criterion) {
    let (rpm, fs) = (1500.0, 12_000.0);
    let spec = BearingSpec::parse("6205").unwrap();
    let accel = outer_race_machine(bearing_model::machine::Nuisances::NONE);
    let recording = Signal::new(&accel, fs).unwrap();
    c.bench_function(
        "machine without a shaft comb, 10 s 12 kHz, speed unconfirmed, self-referenced",
        |bench| {
            bench.iter(|| diagnose(std::hint::black_box(&recording), rpm, &spec, None).unwrap())
        },
    );
}

/// `--bearing unknown` on that machine with an outer-race fault: with a shaft comb (the speed
/// from it; shaft orders masked) and without one (the comb read in Hz over the declared speed's
/// ± 10 %, nothing masked).
fn bench_unknown(c: &mut Criterion) {
    use bearing_model::machine::Nuisances;
    let (rpm, fs) = (1500.0, 12_000.0);
    for (name, mix) in [
        ("with a shaft comb", Nuisances::SHAFT_COMB),
        ("no shaft comb", Nuisances::NONE),
    ] {
        let accel = outer_race_machine(mix);
        let recording = Signal::new(&accel, fs).unwrap();
        let options = diagnosis::DiagnoseOptions::declared(rpm);
        c.bench_function(
            &format!("unknown bearing, machine {name}, 10 s 12 kHz, self-referenced"),
            |bench| {
                bench.iter(|| {
                    diagnosis::diagnose_unknown_bearing(
                        std::hint::black_box(&recording),
                        None,
                        &options,
                    )
                    .unwrap()
                })
            },
        );
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench, bench_rates, bench_unconfirmed, bench_unknown
}
criterion_main!(benches);
