//! Relative RMS difference of the default (adaptive) output from the 5 µs RK4 reference, for
//! the scenarios of the reference test, with the CPU time of each.
//!
//! `cargo run --release -j 1 -p bearing-model --example sim_converge -- [rtol atol] [seconds]`

use bearing_model::{FaultClass, Integrator, Scenario, SimConfig};

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let integrator = match (args.get(1), args.get(2)) {
        (Some(r), Some(a)) => Integrator::Adaptive {
            rtol: r.parse().expect("rtol"),
            atol: a.parse().expect("atol"),
        },
        _ => Integrator::DEFAULT,
    };
    let dur: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.3);
    // REF_STEP=1.25e-6: both runs on a finer internal grid, to see the adaptive path's own
    // error rather than the 5 µs reference's.
    let ref_step: Option<f64> = std::env::var("REF_STEP").ok().and_then(|v| v.parse().ok());
    let mut worst = 0.0_f64;
    for rpm in [300.0, 1797.0] {
        for fs in [12_000.0, 48_000.0] {
            for class in [
                FaultClass::None,
                FaultClass::Outer,
                FaultClass::Inner,
                FaultClass::Ball,
                FaultClass::InnerOuterBall,
            ] {
                let mut sc = Scenario::cwru(class, 0.007, rpm)
                    .expect("valid scenario")
                    .with_fs(fs);
                sc.sim = SimConfig::reference(fs, dur);
                if let Some(step) = ref_step {
                    // a finer reference (the output grid changes too: compare like with like)
                    sc.sim.max_step_s = step;
                }
                let r = sc.simulate().expect("reference");
                sc.sim.integrator = integrator;
                let a = sc.simulate().expect("adaptive");
                let d: Vec<f64> = a.accel.iter().zip(&r.accel).map(|(x, y)| x - y).collect();
                let rel = rms(&d) / rms(&r.accel);
                worst = worst.max(rel);
                println!(
                    "{rpm:6} rpm {:>2} kHz {:16}: rel RMS {rel:.2e}, steps {} vs {} (rms {:.3e})",
                    fs / 1000.0,
                    class.name(),
                    a.steps,
                    r.steps,
                    rms(&r.accel)
                );
            }
        }
    }
    println!("worst {worst:.2e}");
}
