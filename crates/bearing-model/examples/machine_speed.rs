//! Time to synthesise one 10 s machine recording (`bearing_model::machine`) per nuisance mix at
//! 12 and 51.2 kHz, beside the 5-DOF model's healthy bearing over the same 10 s (the optional
//! varying-compliance component the corpus could have used), one core.
//!
//! `cargo run --release -j 1 -p bearing-model --example machine_speed`
//!
//! CPU time is this thread's on-CPU time from `/proc/thread-self/schedstat`; each figure is the
//! best of three runs.

use bearing_model::machine::{LocalizedFault, MachineRecipe, Nuisances};
use bearing_model::{BearingGeometry, FaultClass, FaultLocation, Scenario};
use std::time::Instant;

fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// Best of three (wall s, CPU s) of `f`.
fn best(mut f: impl FnMut()) -> (f64, f64) {
    let mut b = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        let (t, c) = (Instant::now(), cpu_ns());
        f();
        let wall = t.elapsed().as_secs_f64();
        let cpu = match (c, cpu_ns()) {
            (Some(a), Some(z)) => (z - a) as f64 * 1e-9,
            _ => f64::NAN,
        };
        b = (b.0.min(wall), b.1.min(cpu));
    }
    b
}

fn main() -> Result<(), bearing_model::ModelError> {
    let g = BearingGeometry::skf_6205();
    for fs in [12_000.0, 51_200.0] {
        for (name, mix) in [
            ("none", Nuisances::NONE),
            ("shaft-comb", Nuisances::SHAFT_COMB),
            ("once-per-rev", Nuisances::ONCE_PER_REV),
            ("gear-mesh", Nuisances::GEAR_MESH),
            ("electrical", Nuisances::ELECTRICAL),
            ("all", Nuisances::ALL),
        ] {
            let r = MachineRecipe::healthy(g, 1800.0, fs, 10.0, 1)?.with_nuisances(mix);
            let (w, c) = best(|| {
                r.synthesize().expect("valid recipe");
            });
            println!("machine {fs:>6} Hz {name:<13} wall {w:.3} s  CPU {c:.3} s");
        }
        let r = MachineRecipe::healthy(g, 1800.0, fs, 10.0, 1)?
            .with_nuisances(Nuisances::ALL)
            .with_fault(LocalizedFault {
                location: FaultLocation::Inner,
                severity_db: -10.0,
            });
        let (w, c) = best(|| {
            r.synthesize().expect("valid recipe");
        });
        println!("machine {fs:>6} Hz all + inner   wall {w:.3} s  CPU {c:.3} s");
        let sc = Scenario::cwru(FaultClass::None, 0.007, 1800.0)?
            .with_fs(fs)
            .with_duration(10.0);
        let (w, c) = best(|| {
            sc.simulate().expect("valid scenario");
        });
        println!("5-DOF   {fs:>6} Hz healthy       wall {w:.3} s  CPU {c:.3} s");
    }
    Ok(())
}
