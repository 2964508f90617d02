//! Accuracy and cost of the loop's 5-DOF simulations at integration tolerances from the bearing
//! model's default (2e-6) to 1e-3: relative RMS difference of the output from the default's,
//! and the loop's own metric between the two Welch PSDs (floor-regularised LSD, floor 30 dB
//! below the mean PSD, 1024-sample segments for 12 kHz, 4096 for 48 kHz), over healthy and
//! faulted models at 300 and 1797 rpm, 12 and 48 kHz, with and without slip and preload, 5 s
//! each. Backs [`close_loop::physics::LOOP_RTOL`].
//!
//! `cargo run --release -p close-loop --example loop_tolerance`

use bearing_model::{FaultClass, Integrator};
use close_loop::metric::{floor_of, regularised_lsd, rms};
use close_loop::physics::PhysicsModel;
use close_loop::spectrum::Welch;
use close_loop::{BearingSpec, OperatingPoint};

fn main() {
    let tolerances = [1e-5, 2e-5, 5e-5, 2e-4];
    println!(
        "| model | rpm | kHz | steps at 2e-6 | {} |",
        tolerances
            .iter()
            .map(|r| format!("rtol {r:e}: rel. RMS / LSD dB / steps ratio"))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|---|---|---|{}", "---|".repeat(tolerances.len()));
    let bearing = BearingSpec::designated(bearing_model::Bearing::Skf6205);
    let mut worst = (0.0_f64, 0.0_f64);
    for (class, slip, preload) in [
        (FaultClass::None, 0.01, None),
        (FaultClass::Outer, 0.01, None),
        (FaultClass::Inner, 0.0, Some(2e-6)),
        (FaultClass::Ball, 0.01, None),
        (FaultClass::InnerOuterBall, 0.05, Some(0.5e-6)),
    ] {
        for rpm in [300.0, 1797.0] {
            for fs in [12_000.0, 48_000.0] {
                let model = PhysicsModel {
                    fault_size_in: 0.014,
                    slip_fraction: slip,
                    clearance_m: preload.map(|p: f64| -p),
                    ..PhysicsModel::default()
                };
                let op = OperatingPoint::new(rpm, bearing.clone(), class).expect("valid");
                let n = (5.0 * fs) as usize;
                let run = |rtol: f64| {
                    let mut sc = model.scenario(&op, n, fs).expect("valid scenario");
                    sc.sim.integrator = Integrator::adaptive(rtol);
                    let rec = sc.simulate().expect("simulates");
                    (rec.accel, rec.steps)
                };
                let (r, steps0) = run(2e-6);
                let welch = Welch::new(fs, if fs > 20_000.0 { 4096 } else { 1024 }).expect("welch");
                let pr = welch.try_psd(&r).expect("psd");
                let bins = 1..welch.n_bins() - 1;
                let eps = floor_of(&pr, bins.clone(), -30.0);
                let norm = rms(&r);
                let cells: Vec<String> = tolerances
                    .iter()
                    .map(|&rtol| {
                        let (x, steps) = run(rtol);
                        let d: Vec<f64> = x.iter().zip(&r).map(|(a, b)| a - b).collect();
                        let rel = rms(&d) / norm;
                        let px = welch.try_psd(&x).expect("psd");
                        let lsd = regularised_lsd(&pr, &px, bins.clone(), eps);
                        if rtol == close_loop::physics::LOOP_RTOL {
                            worst = (worst.0.max(rel), worst.1.max(lsd));
                        }
                        format!("{rel:.1e} / {lsd:.4} / {:.2}", steps0 as f64 / steps as f64)
                    })
                    .collect();
                println!(
                    "| {} slip {slip} preload {:?} | {rpm} | {} | {steps0} | {} |",
                    class.name(),
                    preload,
                    fs / 1000.0,
                    cells.join(" | ")
                );
            }
        }
    }
    println!(
        "\nat LOOP_RTOL: largest relative RMS difference {:.2e}, largest LSD {:.4} dB",
        worst.0, worst.1
    );
}
