//! Simulated seconds per wall-clock second and per CPU second of `simulate`, one core.
//!
//! `cargo run --release -j 1 -p bearing-model --example sim_speed -- [default|reference] [seconds] [class]`
//!
//! CWRU 6205, 0.007 in spalls, 1797 rpm, 1 % slip; healthy, outer, inner+outer+ball at 12 and
//! 48 kHz. Simulated time counts the recorded duration plus the 50 ms settling. CPU time is
//! this thread's on-CPU time from `/proc/thread-self/schedstat` (ns), so it is not inflated by
//! other processes on a loaded machine the way wall time is. Each figure is the best of three
//! runs.

use bearing_model::{FaultClass, Scenario, SimConfig, Slip};
use std::time::Instant;

fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let which = args.get(1).map(String::as_str).unwrap_or("default");
    let dur: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let only = args.get(3).map(String::as_str);
    for fs in [12_000.0, 48_000.0] {
        for class in [
            FaultClass::None,
            FaultClass::Outer,
            FaultClass::InnerOuterBall,
        ] {
            if only.is_some_and(|o| o != class.name()) {
                continue;
            }
            let mut sc = Scenario::cwru(class, 0.007, 1797.0)
                .expect("valid scenario")
                .with_slip(Slip::Random { fraction: 0.01 })
                .with_fs(fs)
                .with_duration(dur);
            if which == "reference" {
                sc.sim = SimConfig::reference(fs, dur);
            }
            let sim_s = dur + sc.sim.settle_s;
            // best of three: the machine is shared, the fastest run is the least disturbed
            let (mut wall, mut cpu) = (f64::INFINITY, f64::INFINITY);
            let mut rec = None;
            for _ in 0..3 {
                let c0 = cpu_ns();
                let w0 = Instant::now();
                rec = Some(sc.simulate().expect("simulates"));
                wall = wall.min(w0.elapsed().as_secs_f64());
                if let (Some(a), Some(b)) = (c0, cpu_ns()) {
                    cpu = cpu.min((b - a) as f64 * 1e-9);
                }
            }
            let rec = rec.expect("ran");
            println!(
                "{which:9} {:>2} kHz {:16}: {:6.1} sim s/wall s, {:6.1} sim s/CPU s ({} steps, mean {:.2} µs)",
                fs / 1000.0,
                class.name(),
                sim_s / wall,
                sim_s / cpu,
                rec.steps,
                sim_s / rec.steps as f64 * 1e6
            );
        }
    }
}
