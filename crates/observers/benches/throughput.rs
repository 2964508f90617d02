//! Throughput of each observer in samples per second on one core (criterion): the ten kinds on
//! the physics mode (12 kHz) and on the 8-state reference ARX-Laguerre model.
#![allow(missing_docs)]

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use observers::named::{arx_observer, physics_observer};
use observers::scenarios::{ArxPlant, OscillatorPlant, reference_arx_model};
use observers::*;
use std::hint::black_box;

const N: usize = 120_000; // one CWRU 12 kHz record

fn bench(c: &mut Criterion) {
    let mode = ModalParams {
        natural_frequency_hz: 3300.0,
        damping_ratio: 0.05,
        input_gain: 0.0,
        sample_rate_hz: 12_000.0,
    };
    let w2 = mode.omega().powi(2);
    let mut plant = OscillatorPlant::new(&mode).unwrap();
    let y = plant.simulate(N, |k| w2 * ((k as f64) * 0.01).sin());
    let mut out = ObserverOutput::default();
    let mut g = c.benchmark_group("physics_mode");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(20);
    for kind in ObserverKind::ALL {
        let mut o = physics_observer(kind, mode, &ObserverSettings::new(1e-3)).unwrap();
        g.bench_with_input(BenchmarkId::from_parameter(kind), &y, |b, y| {
            b.iter(|| {
                o.reset();
                o.run_into(black_box(y), None, &mut out).unwrap();
            })
        });
    }
    g.finish();

    let model = reference_arx_model();
    let f = FaultDirection::Input.vector(&model);
    let mut plant = ArxPlant::new(&model, &f).unwrap();
    let (y, u) = plant.simulate(N, |k| ((k as f64) * 0.05).sin(), |_| 0.0);
    let mut g = c.benchmark_group("arx_laguerre_8_states");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(20);
    for kind in ObserverKind::ALL {
        let mut o = arx_observer(
            kind,
            &model,
            &FaultDirection::Input,
            &ObserverSettings::new(1e-3),
        )
        .unwrap();
        g.bench_with_input(BenchmarkId::from_parameter(kind), &y, |b, y| {
            b.iter(|| {
                o.reset();
                o.run_into(black_box(y), Some(&u), &mut out).unwrap();
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
