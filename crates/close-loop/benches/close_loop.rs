//! Criterion bench: the whole loop on a 10 s, 12 kHz recording (phenomenological model with an
//! undeclared tone and speed offset), and on 2 s. Target: 10 s in under 30 s on one core.
#![allow(missing_docs)] // criterion_group! generates an undocumented function

use close_loop::scenario::{PhenomenologicalModel, add_noise, add_tone};
use close_loop::{
    BearingRates, DeclaredFault, DeclaredModel, LoopConfig, OperatingPoint, close_loop,
};
use criterion::{Criterion, criterion_group, criterion_main};

fn recording(seconds: f64) -> Vec<f64> {
    let fs = 12_000.0;
    let op = OperatingPoint::new(
        1797.0 * 1.004,
        BearingRates::skf6205(),
        DeclaredFault::Outer,
    )
    .unwrap();
    let mut y = PhenomenologicalModel::default()
        .with_seed(9)
        .simulate(&op, (seconds * fs) as usize, fs)
        .unwrap();
    add_tone(&mut y, fs, 1234.5, 0.05, 0.0);
    add_noise(&mut y, 0.01, 3);
    y
}

fn bench(c: &mut Criterion) {
    let op = OperatingPoint::new(1797.0, BearingRates::skf6205(), DeclaredFault::Outer).unwrap();
    let cfg = LoopConfig::default().check().unwrap();
    let model = PhenomenologicalModel::default();
    let mut g = c.benchmark_group("close_loop");
    g.sample_size(10);
    for seconds in [2.0, 10.0] {
        let y = recording(seconds);
        g.bench_function(format!("{seconds} s at 12 kHz"), |b| {
            b.iter(|| close_loop(&model, &y, 12_000.0, &op, &cfg).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
