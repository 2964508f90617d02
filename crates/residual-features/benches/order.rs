//! Computed order tracking of a 10 s sweep: from a tachometer, and from the recording's own
//! shaft comb (frames, then a shaft order's phase).
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use residual_features::SpectralEngine;
use residual_features::order::{order_track, order_track_profile, speed_profile};

/// A 15 → 25 Hz sweep over 10 s at `fs`: a shaft comb (orders 1–10) in pseudo-noise, and a
/// tachometer of `ppr` square pulses a turn.
fn sweep(fs: f64, ppr: f64) -> (Vec<f64>, Vec<f64>) {
    let n = (10.0 * fs) as usize;
    let mut s = 12345u64;
    let mut x = Vec::with_capacity(n);
    let mut tach = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 / fs;
        let a = 15.0 * t + 0.5 * t * t; // turns
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let comb: f64 = (1..=10)
            .map(|j| 0.8f64.powi(j - 1) * (2.0 * std::f64::consts::PI * f64::from(j) * a).sin())
            .sum();
        x.push(comb + noise);
        tach.push(if (a * ppr).fract() < 0.5 { 5.0 } else { 0.0 });
    }
    (x, tach)
}

fn bench(c: &mut Criterion) {
    for fs in [12_000.0, 51_200.0] {
        let (x, tach) = sweep(fs, 60.0);
        let mut g = c.benchmark_group(format!("order_track_10s_{}Hz", fs as u32));
        g.sample_size(10);
        g.throughput(Throughput::Elements(x.len() as u64));
        g.bench_function("tachometer_60_ppr", |b| {
            let mut e = SpectralEngine::new();
            b.iter(|| order_track(&mut e, &x, &tach, fs, 60.0).unwrap())
        });
        g.bench_function("own_shaft_comb", |b| {
            let mut e = SpectralEngine::new();
            b.iter(|| {
                let p = speed_profile(&mut e, &x, fs, 1080.0, 1320.0)
                    .unwrap()
                    .unwrap();
                order_track_profile(&mut e, &x, fs, &p).unwrap()
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
