//! Throughput of each observer in samples per second on one core (criterion): the ten kinds on
//! the physics mode (12 kHz), on the 8-state reference ARX-Laguerre model, on the chapters'
//! 13-state one (N_a = 12, N_b = 1), on a 16-state AR-form ARX-Laguerre model, and on a
//! calibrated-path (shift-form AR) model of 64, 128 and 156 states — the size of the structural
//! path the loop calibrates on CWRU 97, and of the whole machine model's predictor the chapters'
//! physics observers run on (the path plus two states per line,
//! `close_loop::machine::MachineModel::predictor_model`).
#![allow(missing_docs)]

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use observers::named::{arx_observer, path_observer, physics_observer};
use observers::scenarios::{
    ArxPlant, OscillatorPlant, chapters_shaped_arx_model, reference_arx_model,
};
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

    // The 8-state reference model, and N_a = 12, N_b = 1 (13 states, the chapters' held-out
    // order and pole choice on 97: 0.8941 for the output bank, -0.0391 for the input bank).
    let model13 = chapters_shaped_arx_model(12, 1).unwrap();
    for (name, model) in [
        ("arx_laguerre_8_states", reference_arx_model()),
        ("arx_laguerre_13_states", model13),
    ] {
        let f = FaultDirection::Input.vector(&model);
        let mut plant = ArxPlant::new(&model, &f).unwrap();
        let (y, u) = plant.simulate(N, |k| ((k as f64) * 0.05).sin(), |_| 0.0);
        let mut g = c.benchmark_group(name);
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

    // ARX-Laguerre with N_a = 16 (the largest output bank the order search may pick) in AR form.
    let k16: Vec<f64> = (0..16).map(|i| 0.5 * 0.8f64.powi(i)).collect();
    let model16 = StateSpace::from_poles(-0.2, 16, 0.0, 0, k16).unwrap();
    let y16: Vec<f64> = (0..N)
        .map(|k| ((k as f64) * 0.37).sin() + 0.3 * ((k as f64) * 1.91).sin())
        .collect();
    let mut g = c.benchmark_group("arx_laguerre_16_states");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(20);
    for kind in ObserverKind::ALL {
        let mut s = ObserverSettings::new(1e-3);
        s.linear = LinearDesign::innovations();
        let mut o = arx_observer(kind, &model16, &FaultDirection::OutputFilter, &s).unwrap();
        g.bench_with_input(BenchmarkId::from_parameter(kind), &y16, |b, y| {
            b.iter(|| {
                o.reset();
                o.run_into(black_box(y), None, &mut out).unwrap();
            })
        });
    }
    g.finish();

    // Calibrated structural path: a shift-form AR(p) (the predictor is deadbeat, so its cost and
    // output do not depend on the coefficients' stability; these are bounded and decaying).
    for p in [64usize, 128, 156] {
        let ar: Vec<f64> = (0..p)
            .map(|i| -0.5 * 0.95f64.powi(i as i32) * (0.3 * i as f64).cos())
            .collect();
        let path = StateSpace::from_ar(&ar).unwrap();
        let mut g = c.benchmark_group(format!("calibrated_path_{p}_states"));
        g.throughput(Throughput::Elements(N as u64));
        g.sample_size(20);
        for kind in [
            ObserverKind::Smo,
            ObserverKind::Hostsmo,
            ObserverKind::Flo,
            ObserverKind::Vso,
            ObserverKind::Pflo,
        ] {
            let mut o = path_observer(kind, &path, &ObserverSettings::new(1e-3)).unwrap();
            g.bench_with_input(BenchmarkId::from_parameter(kind), &y16, |b, y| {
                b.iter(|| {
                    o.reset();
                    o.run_into(black_box(y), None, &mut out).unwrap();
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
