//! Throughput of each observer kind on the 8-state reference ARX-Laguerre model (120 000
//! samples per run), reported against wall time and against this thread's on-CPU time
//! (`/proc/thread-self/schedstat`, Linux), so that a loaded, shared machine still gives the
//! single-core figure: `cargo run --release -p observers --example arx_throughput`.
//! With `-- --dense` the predictor is forced onto the dense O(n²) update (the pre-cascade path).
//! With `-- --orders NA,NB` the model has N_a output and N_b input Laguerre functions instead
//! (`observers::scenarios::chapters_shaped_arx_model`: the chapters' poles on CWRU 97).

use observers::named::arx_observer;
use observers::scenarios::{ArxPlant, chapters_shaped_arx_model, reference_arx_model};
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
    let args: Vec<String> = std::env::args().collect();
    let model = match args.iter().position(|a| a == "--orders") {
        Some(i) => {
            let spec = args.get(i + 1).map(String::as_str).unwrap_or("");
            let (na, nb) = spec
                .split_once(',')
                .and_then(|(a, b)| Some((a.parse::<usize>().ok()?, b.parse::<usize>().ok()?)))
                .ok_or(ObserverError::InvalidParameter {
                    name: "--orders",
                    value: f64::NAN,
                    reason: "expected two counts NA,NB, e.g. --orders 12,1",
                })?;
            chapters_shaped_arx_model(na, nb)?
        }
        None => reference_arx_model(),
    };
    println!("model: {} states", model.order());
    let f = FaultDirection::Input.vector(&model);
    let mut plant = ArxPlant::new(&model, &f)?;
    let (y, u) = plant.simulate(N, |k| ((k as f64) * 0.05).sin(), |_| 0.0);
    let mut out = ObserverOutput::default();
    let dense = args.iter().any(|a| a == "--dense");
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
