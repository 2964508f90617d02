//! Throughput of the Table 5.1 inference, the eq. 5.29 law and the FAL one-step predictor.

// criterion_group! generates an undocumented function.
#![allow(missing_docs, clippy::needless_range_loop)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fuzzy_ts::{FalConfig, FalState, FuzzyArxLaguerre, FuzzyInference, Switching, TsSwitchingLaw};
use laguerre_id::{ArxLaguerreConfig, PoleChoice};
use std::hint::black_box;

fn signal(n: usize) -> Vec<f64> {
    let mut s: u64 = 3;
    let mut y = vec![0.0; n];
    for k in 2..n {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let w = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        y[k] = 1.6 * y[k - 1] - 0.8 * y[k - 2] + w;
    }
    y
}

fn bench(c: &mut Criterion) {
    let n = 100_000;
    let y = signal(n);
    let fis = FuzzyInference::dissertation();
    let mut g = c.benchmark_group("fuzzy");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("infer_table_5_1", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for k in 1..n {
                acc += fis.infer(y[k] * 0.1, (y[k] - y[k - 1]) * 0.05);
            }
            black_box(acc)
        })
    });
    let law = TsSwitchingLaw::new(0.5, 0.1, 0.8, Switching::Smooth { width: 0.05 }).unwrap();
    g.bench_function("ts_switching_eq_5_29", |b| {
        b.iter(|| {
            let mut a = 0.0;
            for k in 0..n {
                a = law.step(a, y[k], 1e-6 * y[k]);
            }
            black_box(a)
        })
    });
    let cfg = FalConfig::with_base(
        ArxLaguerreConfig::new(
            4,
            0,
            PoleChoice::Fixed {
                zeta_a: 0.5,
                zeta_b: 0.0,
            },
        )
        .unwrap(),
    );
    let fal = FuzzyArxLaguerre::identify(&y, None, &cfg).unwrap();
    g.bench_function("fal_predict_next_4_states", |b| {
        b.iter(|| {
            let mut st = FalState::default();
            let mut acc = 0.0;
            for &yk in &y {
                let (next, yhat) = fal.predict_next(&st, yk, 0.0);
                acc += yhat;
                st = next;
            }
            black_box(acc)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
