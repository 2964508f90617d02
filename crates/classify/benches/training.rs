//! SVM and tree training time on 3,200 windows (4 classes × 800), 1 feature (energy) and 6
//! features — the dissertation's scale (400 windows per class per dataset, several datasets).
#![allow(missing_docs)] // criterion_group! generates an undocumented pub fn

use classify::{ClassifierSpec, Dataset, RecordingInfo};
use criterion::{Criterion, criterion_group, criterion_main};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn data(n_features: usize) -> Dataset {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let names = ["normal", "ball", "inner", "outer"]
        .map(String::from)
        .to_vec();
    let features = (0..n_features).map(|k| format!("f{k}")).collect();
    let mut b = Dataset::builder(names, features);
    for c in 0..4 {
        for r in 0..4 {
            let info = RecordingInfo {
                class: c,
                recording: format!("{c}-{r}"),
                load_hp: r as u32,
                fault_size_mils: (c > 0).then_some(7),
                speed_rpm: None,
            };
            // overlapping classes so the SVM has real work (about 10 % overlap)
            let rows = (0..200)
                .map(|_| {
                    (0..n_features)
                        .map(|k| c as f64 * (1.0 + 0.1 * k as f64) + 0.8 * rng.random::<f64>())
                        .collect()
                })
                .collect();
            b.add_recording(&info, rows);
        }
    }
    b.build().unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("train_3200_windows");
    g.sample_size(10);
    for d in [1, 6] {
        let ds = data(d);
        let all: Vec<usize> = (0..ds.n_samples()).collect();
        g.bench_function(format!("ovo_linear_svm_{d}_features"), |b| {
            b.iter(|| ClassifierSpec::svm().fit(&ds, &all).unwrap())
        });
        g.bench_function(format!("gini_tree_{d}_features"), |b| {
            b.iter(|| ClassifierSpec::tree().fit(&ds, &all).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
