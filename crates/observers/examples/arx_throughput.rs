//! Throughput of each observer kind on the 8-state reference ARX-Laguerre model (120 000
//! samples per run), reported against wall time and against this thread's on-CPU time
//! (`/proc/thread-self/schedstat`, Linux), so that a loaded, shared machine still gives the
//! single-core figure: `cargo run --release -p observers --example arx_throughput`.
//! With `-- --dense` the predictor is forced onto the dense O(n²) update (the pre-cascade path).

use observers::named::arx_observer;
use observers::scenarios::{ArxPlant, reference_arx_model};
use observers::*;
use std::hint::black_box;
use std::time::Instant;

const N: usize = 120_000;
const RUNS: usize = 100;

/// Nanoseconds this thread has spent on a CPU, if the kernel reports it.
fn on_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn main() -> Result<(), ObserverError> {
    let model = reference_arx_model();
    let f = FaultDirection::Input.vector(&model);
    let mut plant = ArxPlant::new(&model, &f)?;
    let (y, u) = plant.simulate(N, |k| ((k as f64) * 0.05).sin(), |_| 0.0);
    let mut out = ObserverOutput::default();
    let dense = std::env::args().any(|a| a == "--dense");
    let kp = named::design_arx_linear(&model, &f, &ObserverSettings::new(1e-3).linear)?.kp;
    println!("kind      wall M/s   on-CPU M/s   (cascade path)");
    for kind in ObserverKind::ALL {
        let s = ObserverSettings::new(1e-3);
        let mut o = arx_observer(kind, &model, &FaultDirection::Input, &s)?;
        if dense {
            o = Observer::new(ArxLaguerrePredictor::new_dense(&model, &f, &kp)?, *o.law());
        }
        o.run_into(&y, Some(&u), &mut out)?; // warm-up
        let (t0, c0) = (Instant::now(), on_cpu_ns());
        for _ in 0..RUNS {
            o.reset();
            o.run_into(black_box(&y), Some(&u), &mut out)?;
        }
        let wall = t0.elapsed().as_secs_f64();
        let samples = (N * RUNS) as f64;
        let cpu = match (c0, on_cpu_ns()) {
            (Some(a), Some(b)) if b > a => {
                format!("{:10.1}", samples / ((b - a) as f64 * 1e-9) / 1e6)
            }
            _ => "       n/a".to_string(),
        };
        println!(
            "{:8} {:9.1}   {cpu}   ({})",
            kind.name(),
            samples / wall / 1e6,
            o.predictor().uses_laguerre_cascade()
        );
    }
    Ok(())
}
