//! The detector's null on white noise: `cargo run --release -p diagnosis --example
//! null_calibration -- N SECONDS` diagnoses N white-noise recordings and prints each
//! hypothesis's p under healthy; their distribution should be uniform or, conservative, above it.
#![allow(missing_docs)]
use diagnosis::{BearingSpec, DiagnoseOptions, diagnose_with_options};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let secs: f64 = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(2.0);
    let fs = 12_000.0;
    let rpm = 1797.0;
    let spec = BearingSpec::parse(&std::env::var("HFDD_BEARING").unwrap_or("6205".into())).unwrap();
    let mut ps = Vec::new();
    let mut hits = [0usize; 4];
    for seed in 0..n as u64 {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let norm = Normal::new(0.0, 1.0).unwrap();
        let x: Vec<f64> = (0..(fs * secs) as usize)
            .map(|_| norm.sample(&mut rng))
            .collect();
        // the speed is known: a range that only the declared speed fits (no blind search)
        let opts = DiagnoseOptions::declared(rpm).with_rpm_range(rpm * 0.999, rpm * 1.001);
        let d = diagnose_with_options(&sig(&x, fs), &spec, None, &opts).unwrap();
        for (i, e) in d.evidence.iter().enumerate() {
            let p = e.significance.as_ref().unwrap().p_healthy;
            ps.push(p);
            for (j, lvl) in [0.1, 0.01, 0.0033, 0.001].iter().enumerate() {
                if p <= *lvl && i < 3 {
                    hits[j] += 1;
                }
            }
        }
        if d.verdict != "normal" {
            println!("seed {seed}: {}", d.verdict);
        }
    }
    let m = ps.len() as f64;
    println!(
        "{} p-values: <=0.1 {:.3}, <=0.01 {:.4}, <=0.0033 {:.4}, <=0.001 {:.4}",
        ps.len(),
        hits[0] as f64 / m,
        hits[1] as f64 / m,
        hits[2] as f64 / m,
        hits[3] as f64 / m
    );
}

/// `x` at `fs` Hz as a checked signal (the tests' recordings are finite and non-empty).
fn sig(x: &[f64], fs: f64) -> diagnosis::Signal<'_> {
    diagnosis::Signal::new(x, fs).unwrap()
}
