//! Accuracy and wall time of the rig's excitation model at integration tolerances from the
//! bearing model's default (2e-6) to 1e-3, against the same model integrated at 1e-8:
//! relative RMS difference of the vertical output, 1 s at 12 kHz, inner / outer / ball spall
//! of 0.5 mm at 300 and 1797 rpm. Backs [`calibrated_rig::EXCITATION_RTOL`].
//!
//! `cargo run --release -p close-loop --example excitation_tolerance`

use bearing_model::{Bearing, FaultClass};
use calibrated_rig::{RigModel, cwru_rig, excitation_with};

fn run(rig: &RigModel, class: FaultClass, rpm: f64, rtol: f64) -> (Vec<f64>, f64) {
    let t = std::time::Instant::now();
    let e = excitation_with(
        Bearing::Skf6205,
        rig.preload_m,
        rig.radial_load_n,
        class,
        0.5,
        rpm,
        0.0,
        12_000.0,
        12_000,
        3,
        rig.excitation_housing_hz,
        rtol,
    )
    .expect("the calibrated rig's excitation simulates");
    (e.vertical, t.elapsed().as_secs_f64())
}

fn main() {
    let rig = cwru_rig().expect("the embedded rig model parses");
    let tolerances = [2e-6, 2e-5, 2e-4, 1e-3];
    println!(
        "| spall | rpm | {} |",
        tolerances
            .iter()
            .map(|r| format!("rtol {r:e}: rel. RMS diff (wall s)"))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|---|{}", "---|".repeat(tolerances.len()));
    for class in [FaultClass::Inner, FaultClass::Outer, FaultClass::Ball] {
        for rpm in [300.0, 1797.0] {
            let (r, _) = run(&rig, class, rpm, 1e-8);
            let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
            let cells: Vec<String> = tolerances
                .iter()
                .map(|&rtol| {
                    let (x, t) = run(&rig, class, rpm, rtol);
                    let d = x
                        .iter()
                        .zip(&r)
                        .map(|(a, b)| (a - b) * (a - b))
                        .sum::<f64>()
                        .sqrt();
                    format!("{:.1e} ({t:.3})", d / norm)
                })
                .collect();
            println!("| {} | {rpm} | {} |", class.name(), cells.join(" | "));
        }
    }
}
