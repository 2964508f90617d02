//! Feature extraction throughput (samples per second) on 12 kHz-like windows.
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use residual_features::{
    Band, EnvelopeSettings, FeatureConfig, FeatureExtractor, TailPolicy, WindowPlan, Windowing,
};

fn signal(n: usize) -> Vec<f64> {
    // deterministic pseudo-noise (LCG) plus a tone; no RNG dependency needed
    let mut s = 12345u64;
    (0..n)
        .map(|k| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) + (0.01 * k as f64).sin()
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    // one CWRU 12 kHz record (~120k samples) cut into 400 windows of 300 samples
    let x = signal(120_000);
    let plan = WindowPlan::new(Windowing::FixedCount { count: 400 }, TailPolicy::Discard).unwrap();
    let mut g = c.benchmark_group("extract_120k_samples_400_windows");
    g.throughput(Throughput::Elements(x.len() as u64));
    g.bench_function("energy_only", |b| {
        let mut fx = FeatureExtractor::new(FeatureConfig::energy_only()).unwrap();
        b.iter(|| fx.extract_windows(&x, &plan).unwrap())
    });
    g.bench_function("time_domain", |b| {
        let mut fx = FeatureExtractor::new(FeatureConfig::time_domain()).unwrap();
        b.iter(|| fx.extract_windows(&x, &plan).unwrap())
    });
    let env = EnvelopeSettings {
        shaft_hz: 1797.0 / 60.0,
        multiples: bearing_model::BearingGeometry::skf_6205().orders(),
        demodulation_band: Some(Band::new(2000.0, 4000.0).unwrap()),
        tolerance: 0.02,
    };
    let full = FeatureConfig::full(12_000.0, env, &[Band::new(2000.0, 4000.0).unwrap()]);
    g.bench_function("full_envelope", |b| {
        let mut fx = FeatureExtractor::new(full.clone()).unwrap();
        b.iter(|| fx.extract_windows(&x, &plan).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
