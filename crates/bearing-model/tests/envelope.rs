//! Envelope spectra of simulated faults look the way a vibration analyst expects: outer race
//! at BPFO, inner race at BPFI with shaft-rate sidebands, ball at the ball-defect rate
//! (2 × ball spin) with cage-rate sidebands, combined faults show each line, and a healthy
//! bearing only the varying-compliance vibration at the ball-pass rate.
//!
//! Settings: SKF 6205, CWRU set, 1797 rpm, 0.014 in spalls, 1 % slip, 12 kHz, 1 s, noise at
//! 10 dB SNR, envelope of the 2–5 kHz band (around the 3.3 kHz housing resonance).

mod common;

use bearing_model::*;
use common::*;

const RPM: f64 = 1797.0;

fn env(class: FaultClass) -> (f64, Vec<f64>, Vec<f64>) {
    let r = Scenario::cwru(class, 0.014, RPM)
        .unwrap()
        .with_noise(Noise::SnrDb(10.0))
        .with_seed(3)
        .simulate()
        .unwrap();
    let (df, e) = envelope_spectrum(&r.accel, r.fs_hz, 2000.0, 5000.0);
    (df, e, r.accel)
}

fn lines() -> (f64, FaultOrders) {
    let fr = RPM / 60.0;
    (fr, BearingGeometry::skf_6205().orders().at(fr))
}

/// Peak within 1 % of `f` relative to the median background of 5–600 Hz.
fn prominence(df: f64, e: &[f64], f: f64) -> f64 {
    peak_near(df, e, f, (0.01 * f).max(df)) / median_in(df, e, 5.0, 600.0)
}

#[test]
fn outer_race_strongest_line_within_1_percent_of_bpfo() {
    let (_, o) = lines();
    let (df, e, _) = env(FaultClass::Outer);
    let f = argmax_in(df, &e, 5.0, 600.0);
    assert!(
        (f - o.bpfo).abs() <= 0.01 * o.bpfo,
        "strongest {f} Hz, BPFO {} Hz",
        o.bpfo
    );
    assert!(prominence(df, &e, 2.0 * o.bpfo) > 5.0, "2×BPFO harmonic");
}

#[test]
fn inner_race_bpfi_with_shaft_rate_sidebands() {
    let (fr, o) = lines();
    let (df, e, _) = env(FaultClass::Inner);
    let p = prominence(df, &e, o.bpfi);
    assert!(p > 10.0, "BPFI prominence {p}");
    for sb in [o.bpfi - fr, o.bpfi + fr] {
        let q = prominence(df, &e, sb);
        assert!(q > 5.0, "sideband at {sb} Hz: prominence {q}");
    }
    assert!(prominence(df, &e, fr) > 5.0, "shaft-rate modulation line");
    assert!(prominence(df, &e, o.bpfo) < 3.0, "no BPFO line");
}

#[test]
fn ball_defect_rate_with_cage_sidebands() {
    let (_, o) = lines();
    let (df, e, _) = env(FaultClass::Ball);
    let p = prominence(df, &e, o.ball_defect);
    assert!(p > 10.0, "ball-defect-rate prominence {p}");
    for sb in [o.ball_defect - o.ftf, o.ball_defect + o.ftf] {
        let q = prominence(df, &e, sb);
        assert!(q > 5.0, "cage sideband at {sb} Hz: prominence {q}");
    }
    assert!(prominence(df, &e, o.ftf) > 5.0, "cage-rate line");
    assert!(prominence(df, &e, o.bpfi) < 3.0, "no BPFI line");
}

#[test]
fn combined_faults_show_each_line() {
    let (_, o) = lines();
    for class in [
        FaultClass::InnerOuter,
        FaultClass::InnerBall,
        FaultClass::OuterBall,
        FaultClass::InnerOuterBall,
    ] {
        let (df, e, _) = env(class);
        let mut want = Vec::new();
        if class.has_inner() {
            want.push(("BPFI", o.bpfi));
        }
        if class.has_outer() {
            want.push(("BPFO", o.bpfo));
        }
        if class.has_ball() {
            want.push(("ball defect", o.ball_defect));
        }
        for (name, f) in want {
            let p = prominence(df, &e, f);
            assert!(p > 5.0, "{class}: {name} prominence {p}");
        }
    }
}

#[test]
fn healthy_shows_only_the_ball_pass_vibration() {
    let (_, o) = lines();
    let r = Scenario::cwru(FaultClass::None, 0.014, RPM)
        .unwrap()
        .simulate()
        .unwrap();
    let (df, e) = envelope_spectrum(&r.accel, r.fs_hz, 2000.0, 5000.0);
    // the plain spectrum's strongest line is a ball-pass harmonic
    let n = r.accel.len();
    let raw = {
        let mut planner = rustfft::FftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(n);
        let mean = r.accel.iter().sum::<f64>() / n as f64;
        let mut b: Vec<rustfft::num_complex::Complex<f64>> = r
            .accel
            .iter()
            .map(|&v| rustfft::num_complex::Complex::new(v - mean, 0.0))
            .collect();
        fft.process(&mut b);
        b[..n / 2].iter().map(|c| c.norm()).collect::<Vec<f64>>()
    };
    let dfr = r.fs_hz / n as f64;
    let f = argmax_in(dfr, &raw, 5.0, 1000.0);
    let k = (f / o.bpfo).round();
    assert!(
        k >= 1.0 && (f - k * o.bpfo).abs() <= 0.01 * f,
        "strongest raw line {f} Hz is not a BPFO harmonic"
    );
    assert!(prominence(df, &e, o.bpfi) < 3.0, "no BPFI line");
    assert!(
        prominence(df, &e, o.ball_defect) < 3.0,
        "no ball-defect line"
    );
    let (_, _, outer) = env(FaultClass::Outer);
    assert!(
        rms(&r.accel) < 0.05 * rms(&outer),
        "healthy {} vs outer {}",
        rms(&r.accel),
        rms(&outer)
    );
}
