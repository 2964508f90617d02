//! The default integrator (adaptive Dormand–Prince 5(4), `Integrator::DEFAULT`) against the
//! reference (classical RK4 at ≤ 5 µs, `SimConfig::reference`): healthy, outer, inner, ball and
//! inner+outer+ball; 12 and 48 kHz; 300 and 1797 rpm; CWRU 6205, 0.007 in spalls, 1 % slip,
//! 0.25 s after 50 ms settling, no noise.
//!
//! Measured relative RMS differences of the output (default − reference, over the reference's
//! RMS), worst per rate/speed over the five classes (all 20 printed with `--nocapture`):
//!
//! | rpm  | 12 kHz  | 48 kHz  |
//! |------|---------|---------|
//! | 300  | 2.6e-4  | 2.6e-4  |
//! | 1797 | 2.5e-4  | 2.0e-4  |
//!
//! (healthy: 1.4e-4 / 2.0e-4 at 300 rpm, where the signal is only 2.4e-6 m/s² RMS, and 8.8e-6
//! at 1797 rpm; the 5 µs reference is itself ~1.4e-4 from a 1.25 µs RK4, see
//! `examples/sim_converge.rs`). The envelope spectrum (2–5 kHz band) at each fault line of the
//! class (BPFO; BPFI ± fr; ball-defect rate ± FTF) changes by less than 0.1 % of the line's
//! height (measured ≤ 1.9e-4). The default path takes 5–23× fewer steps.

mod common;

use bearing_model::*;
use common::*;

const DURATION_S: f64 = 0.25;

fn rel_rms(a: &[f64], reference: &[f64]) -> f64 {
    let d: Vec<f64> = a.iter().zip(reference).map(|(x, y)| x - y).collect();
    rms(&d) / rms(reference)
}

/// The fault lines of `class` at `rpm`, with their first modulation sidebands.
fn fault_lines(class: FaultClass, rpm: f64) -> Vec<(&'static str, f64)> {
    let fr = rpm / 60.0;
    let o = BearingGeometry::skf_6205().orders().at(fr);
    let mut v = Vec::new();
    if class.has_outer() {
        v.push(("BPFO", o.bpfo));
    }
    if class.has_inner() {
        v.extend([
            ("BPFI", o.bpfi),
            ("BPFI−fr", o.bpfi - fr),
            ("BPFI+fr", o.bpfi + fr),
        ]);
    }
    if class.has_ball() {
        v.extend([
            ("ball defect", o.ball_defect),
            ("ball defect−FTF", o.ball_defect - o.ftf),
            ("ball defect+FTF", o.ball_defect + o.ftf),
        ]);
    }
    v
}

#[test]
fn default_integrator_matches_the_5_us_rk4_reference() {
    let mut worst: f64 = 0.0;
    let mut worst_line: f64 = 0.0;
    for rpm in [300.0, 1797.0] {
        for fs in [12_000.0, 48_000.0] {
            for class in [
                FaultClass::None,
                FaultClass::Outer,
                FaultClass::Inner,
                FaultClass::Ball,
                FaultClass::InnerOuterBall,
            ] {
                let mut sc = Scenario::cwru(class, 0.007, rpm).unwrap().with_fs(fs);
                sc.sim = SimConfig::new(fs, DURATION_S);
                assert_eq!(sc.sim.integrator, Integrator::DEFAULT);
                let a = sc.simulate().unwrap();
                sc.sim = SimConfig::reference(fs, DURATION_S);
                assert_eq!(sc.sim.integrator, Integrator::Rk4Fixed);
                let r = sc.simulate().unwrap();
                assert_eq!(a.accel.len(), r.accel.len());
                assert_eq!(a.step_s, r.step_s, "same output grid");
                let rel = rel_rms(&a.accel, &r.accel);
                // envelope spectrum at the fault lines, relative to the line's height
                let (df, ea) = envelope_spectrum(&a.accel, fs, 2000.0, 5000.0);
                let (_, er) = envelope_spectrum(&r.accel, fs, 2000.0, 5000.0);
                let mut line_change: f64 = 0.0;
                for (name, f) in fault_lines(class, rpm) {
                    let tol = (0.01 * f).max(df);
                    let (pa, pr) = (peak_near(df, &ea, f, tol), peak_near(df, &er, f, tol));
                    let c = (pa - pr).abs() / pr;
                    line_change = line_change.max(c);
                    assert!(
                        c < 1e-3,
                        "{rpm} rpm {fs} Hz {class}: {name} line changed by {c:.2e}"
                    );
                }
                eprintln!(
                    "{rpm:6} rpm {:>2} kHz {:16}: rel RMS {rel:.2e}, fault lines {line_change:.1e}, \
                     steps {} vs {}",
                    fs / 1000.0,
                    class.name(),
                    a.steps,
                    r.steps
                );
                assert!(
                    rel < 1e-3,
                    "{rpm} rpm {fs} Hz {class}: relative RMS difference {rel:.2e}"
                );
                assert!(
                    a.steps * 3 < r.steps,
                    "the default path takes far fewer steps"
                );
                worst = worst.max(rel);
                worst_line = worst_line.max(line_change);
            }
        }
    }
    eprintln!("worst rel RMS {worst:.2e}, worst fault-line change {worst_line:.1e}");
}

#[test]
fn reference_integrator_is_the_former_default_path() {
    // `Rk4Fixed` steps exactly on the internal grid, one step per grid sample.
    let sc = Scenario::cwru(FaultClass::Outer, 0.007, 1797.0)
        .unwrap()
        .with_duration(0.01);
    let mut cfg = SimConfig::reference(12_000.0, 0.01);
    cfg.settle_s = 0.005;
    let r = simulate(&sc.model().unwrap(), &cfg).unwrap();
    assert_eq!(r.step_s, 1.0 / (12_000.0 * cfg.oversampling() as f64));
    assert!(r.step_s <= SimConfig::DEFAULT_MAX_STEP);
    let m = cfg.oversampling();
    let grid = ((cfg.settle_s + cfg.duration_s) * 12_000.0).round() as usize * m;
    assert!(
        r.steps >= grid && r.steps <= grid + 20 * m,
        "{} steps for {grid} grid samples",
        r.steps
    );
}

#[test]
fn adaptive_tolerances_are_validated_and_converge() {
    let sc = Scenario::cwru(FaultClass::Outer, 0.007, 1797.0).unwrap();
    let model = sc.model().unwrap();
    let mut cfg = SimConfig::new(12_000.0, 0.05);
    cfg.integrator = Integrator::Adaptive {
        rtol: -1.0,
        atol: 1e-9,
    };
    assert!(matches!(
        simulate(&model, &cfg),
        Err(ModelError::OutOfRange { .. })
    ));
    // tighter tolerance → closer to a tight reference, more steps
    let reference = simulate(&model, &SimConfig::reference(12_000.0, 0.05)).unwrap();
    let run = |rtol: f64| {
        let mut c = SimConfig::new(12_000.0, 0.05);
        c.integrator = Integrator::Adaptive { rtol, atol: 1e-9 };
        simulate(&model, &c).unwrap()
    };
    let (loose, tight) = (run(1e-4), run(1e-6));
    assert!(tight.steps > loose.steps);
    assert!(rel_rms(&tight.accel, &reference.accel) < 1e-3);
    assert!(rel_rms(&loose.accel, &reference.accel) > rel_rms(&tight.accel, &reference.accel));
}
