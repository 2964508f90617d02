//! Simulated seconds per wall-clock second at 12 and 48 kHz output, healthy, outer-race and
//! inner+outer+ball faults (CWRU 6205, 0.007 in, 1797 rpm, 1 % slip), for the default
//! integrator (adaptive Dormand–Prince 5(4)) and the reference (fixed-step RK4 at ≤ 5 µs).
//! Criterion's throughput is in simulated milliseconds per second (0.5 s recorded + 50 ms
//! settling = 550 "elements"): divide by 1000 for simulated seconds per second.
//!
//! Short, targeted run (the machine is shared):
//! `cargo bench -j 1 -p bearing-model --bench throughput -- --warm-up-time 1 --measurement-time 5 default/`

#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use bearing_model::{FaultClass, Scenario, SimConfig, Slip};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("simulate_0.5s");
    g.sample_size(10);
    for (name, reference) in [("default", false), ("reference", true)] {
        for fs in [12_000.0, 48_000.0] {
            for class in [
                FaultClass::None,
                FaultClass::Outer,
                FaultClass::InnerOuterBall,
            ] {
                let mut sc = Scenario::cwru(class, 0.007, 1797.0)
                    .expect("valid scenario")
                    .with_slip(Slip::Random { fraction: 0.01 })
                    .with_fs(fs)
                    .with_duration(0.5);
                if reference {
                    sc.sim = SimConfig::reference(fs, 0.5);
                }
                // Throughput in "elements" = simulated milliseconds (incl. 50 ms settling).
                g.throughput(Throughput::Elements(550));
                g.bench_function(format!("{name}/{}_{}kHz", class.name(), fs / 1000.0), |b| {
                    b.iter(|| sc.simulate().expect("simulates"))
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
