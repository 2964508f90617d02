//! Development timing: one 10 s, 12 kHz simulated recording diagnosed repeatedly.
#![allow(missing_docs)]
use bearing_model::{FaultClass, Noise, Scenario};
use diagnosis::{BearingSpec, diagnose};
fn main() {
    let rpm = 1797.0;
    let rec = Scenario::cwru(FaultClass::Outer, 0.014, rpm)
        .unwrap()
        .with_duration(10.0)
        .with_noise(Noise::SnrDb(10.0))
        .with_seed(2)
        .simulate()
        .unwrap();
    let spec = BearingSpec::parse("6205").unwrap();
    let healthy = Scenario::cwru(FaultClass::None, 0.014, rpm)
        .unwrap()
        .with_duration(10.0)
        .with_noise(Noise::SnrDb(10.0))
        .with_seed(1)
        .simulate()
        .unwrap();
    let base = diagnosis::Baseline::prepare(&healthy.accel, healthy.fs_hz).unwrap();
    let with_base = std::env::var("SELF").is_err();
    let t = std::time::Instant::now();
    let n = 10;
    for _ in 0..n {
        let d = diagnose(
            &rec.accel,
            rec.fs_hz,
            rpm,
            &spec,
            with_base.then_some(&base),
        )
        .unwrap();
        std::hint::black_box(d);
    }
    println!(
        "{:.1} ms per diagnosis",
        t.elapsed().as_secs_f64() * 1e3 / n as f64
    );
}
