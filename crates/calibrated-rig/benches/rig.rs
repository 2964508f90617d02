//! Criterion bench of the calibrated rig simulator: 10 s at 12 kHz of the CWRU rig, healthy and
//! with one and three faults (simulated seconds per wall second = 10 / time).
#![allow(missing_docs)] // criterion_group! generates an undocumented function

use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    // the calibrated rig: 10 s at 12 kHz (simulated seconds per wall second = 10 / time)
    let rig = calibrated_rig::cwru_rig().unwrap();
    let mut g = c.benchmark_group("rig");
    g.sample_size(10);
    for (name, class) in [
        ("healthy", bearing_model::FaultClass::None),
        ("inner", bearing_model::FaultClass::Inner),
        (
            "inner+outer+ball",
            bearing_model::FaultClass::InnerOuterBall,
        ),
    ] {
        let s = calibrated_rig::Synthesis::new(class, 0.356, 1797.0, 120_000, 1);
        g.bench_function(format!("synthesize 10 s at 12 kHz, {name}"), |b| {
            b.iter(|| rig.synthesize(&s).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
