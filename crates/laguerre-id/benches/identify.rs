//! Identification time on a 120 000-sample record and per-sample prediction throughput.

// criterion_group! generates an undocumented function.
#![allow(missing_docs, clippy::needless_range_loop)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laguerre_id::{
    ArxLaguerreConfig, ArxLaguerreModel, ArxModel, ArxOrders, LaguerreState, PoleChoice,
};
use std::hint::black_box;

/// A 120 000-sample record: two resonances driven by a deterministic pseudo-random input.
fn record(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut s: u64 = 7;
    let u: Vec<f64> = (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect();
    let mut y = vec![0.0; n];
    for k in 4..n {
        y[k] = 2.2 * y[k - 1] - 2.1 * y[k - 2] + 1.1 * y[k - 3] - 0.3 * y[k - 4]
            + u[k - 1]
            + 0.1 * u[k]
            // Equation noise keeps over-parameterised fits (ARX 8/8) full rank.
            + 0.01 * u[(k * 7919) % n];
    }
    (y, u)
}

fn bench(c: &mut Criterion) {
    let (y, u) = record(120_000);
    let mut g = c.benchmark_group("identify_120k");
    g.sample_size(10);
    g.bench_function("arx_8_8", |b| {
        b.iter(|| {
            ArxModel::identify(black_box(&y), Some(&u), ArxOrders::new(8, 8).unwrap()).unwrap()
        })
    });
    let fixed = ArxLaguerreConfig::new(
        4,
        4,
        PoleChoice::Fixed {
            zeta_a: 0.5,
            zeta_b: 0.2,
        },
    )
    .unwrap();
    g.bench_function("arx_laguerre_4_4_fixed_poles", |b| {
        b.iter(|| ArxLaguerreModel::identify(black_box(&y), Some(&u), &fixed).unwrap())
    });
    let search = ArxLaguerreConfig::new(4, 4, PoleChoice::DEFAULT_SEARCH).unwrap();
    g.bench_function("arx_laguerre_4_4_pole_search", |b| {
        b.iter(|| ArxLaguerreModel::identify(black_box(&y), Some(&u), &search).unwrap())
    });
    let ar = ArxLaguerreConfig::new(8, 0, PoleChoice::DEFAULT_SEARCH).unwrap();
    g.bench_function("arx_laguerre_8_0_pole_search", |b| {
        b.iter(|| ArxLaguerreModel::identify(black_box(&y), None, &ar).unwrap())
    });
    g.finish();

    let mut g = c.benchmark_group("predict_next");
    let n = y.len();
    g.throughput(Throughput::Elements(n as u64));
    for (na, nb) in [(4, 4), (8, 0), (8, 8)] {
        let cfg = ArxLaguerreConfig::new(
            na,
            nb,
            PoleChoice::Fixed {
                zeta_a: 0.5,
                zeta_b: 0.2,
            },
        )
        .unwrap();
        let m = if nb > 0 {
            ArxLaguerreModel::identify(&y, Some(&u), &cfg).unwrap()
        } else {
            ArxLaguerreModel::identify(&y, None, &cfg).unwrap()
        };
        g.bench_function(format!("n_a{na}_n_b{nb}"), |b| {
            b.iter(|| {
                let mut st = LaguerreState::default();
                let mut acc = 0.0;
                for k in 0..n {
                    let (next, yhat) = m.predict_next(&st, y[k], u[k]);
                    acc += yhat;
                    st = next;
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
