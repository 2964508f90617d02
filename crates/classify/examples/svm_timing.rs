//! Time one-vs-one SVM training on 3,200 synthetic windows and show linfa's solver statistics.
//!
//! `cargo run --release -p classify --example svm_timing`

use std::time::Instant;

use classify::{ClassifierSpec, Dataset, LinearSvmParams, RecordingInfo};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() -> Result<(), classify::ClassifyError> {
    direct();
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let names = ["normal", "ball", "inner", "outer"]
        .map(String::from)
        .to_vec();
    let mut b = Dataset::builder(names, vec!["energy".into()]);
    for c in 0..4 {
        for r in 0..4u32 {
            let info = RecordingInfo {
                class: c,
                recording: format!("{c}-{r}"),
                load_hp: r,
                fault_size_mils: (c > 0).then_some(7),
                speed_rpm: None,
            };
            let rows = (0..200)
                .map(|_| vec![c as f64 + 0.8 * rng.random::<f64>()])
                .collect();
            b.add_recording(&info, rows);
        }
    }
    let data = b.build()?;
    let all: Vec<usize> = (0..data.n_samples()).collect();
    let settings = [
        (
            "default (C=10, per-pair, balanced)",
            LinearSvmParams::default(),
        ),
        (
            "default, tolerance 1e-2",
            LinearSvmParams {
                tolerance: 1e-2,
                ..Default::default()
            },
        ),
        ("sklearn (C=1, global, uniform)", LinearSvmParams::sklearn()),
    ];
    for (name, p) in settings {
        let spec = ClassifierSpec::LinearSvm(p);
        let t = Instant::now();
        let _m = spec.fit(&data, &all)?;
        println!("{name}: {:.3} s", t.elapsed().as_secs_f64());
    }
    Ok(())
}

/// Direct linfa call on one pair, printing the solver summary (iterations, objective).
pub fn direct() {
    use linfa::prelude::*;
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let n = 1600;
    let x = ndarray::Array2::from_shape_fn((n, 1), |(i, _)| {
        (if i < n / 2 { 0.0 } else { 1.0 }) + 0.8 * rng.random::<f64>()
    });
    let y = ndarray::Array1::from_shape_fn(n, |i| i < n / 2);
    let ds = linfa::Dataset::new(x, y);
    for shrink in [false, true] {
        let t = Instant::now();
        let m = linfa_svm::Svm::<f64, bool>::params()
            .pos_neg_weights(1.0, 1.0)
            .eps(1e-3)
            .shrinking(shrink)
            .linear_kernel()
            .fit(&ds)
            .unwrap();
        println!(
            "shrinking {shrink}: {:.3} s, {m}",
            t.elapsed().as_secs_f64()
        );
    }
}
