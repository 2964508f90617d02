//! Simulated seconds per wall-clock second at 12 and 48 kHz output, healthy and outer-race
//! fault, at the default converged step (5 µs). Run: `cargo bench -p bearing-model`.

#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use bearing_model::{FaultClass, Scenario, Slip};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("simulate_0.5s");
    g.sample_size(10);
    for fs in [12_000.0, 48_000.0] {
        for class in [
            FaultClass::None,
            FaultClass::Outer,
            FaultClass::InnerOuterBall,
        ] {
            let sc = Scenario::cwru(class, 0.007, 1797.0)
                .expect("valid scenario")
                .with_slip(Slip::Random { fraction: 0.01 })
                .with_fs(fs)
                .with_duration(0.5);
            // Throughput in "elements" = simulated milliseconds (incl. 50 ms settling).
            g.throughput(Throughput::Elements(550));
            g.bench_function(format!("{}_{}kHz", class.name(), fs / 1000.0), |b| {
                b.iter(|| sc.simulate().expect("simulates"))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
