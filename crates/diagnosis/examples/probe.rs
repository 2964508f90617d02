//! Development probe: simulated CWRU-like recordings diagnosed self-referenced, the detector's
//! reading of each hypothesis printed (statistic, probability under healthy, modulation depth).
#![allow(missing_docs)]
use bearing_model::{FaultClass, Noise, Scenario};
use diagnosis::{BearingSpec, diagnose};

fn main() {
    let rpm = 1797.0;
    for (class, seed) in [
        (FaultClass::None, 1),
        (FaultClass::Inner, 2),
        (FaultClass::Outer, 3),
        (FaultClass::Ball, 4),
    ] {
        for snr in [20.0, 10.0, 0.0] {
            let rec = Scenario::cwru(class, 0.014, rpm)
                .unwrap()
                .with_noise(Noise::SnrDb(snr))
                .with_duration(2.0)
                .with_seed(seed)
                .simulate()
                .unwrap();
            let d = diagnose(
                &rec.accel,
                rec.fs_hz,
                rpm,
                &BearingSpec::parse("6205").unwrap(),
                None,
            )
            .unwrap();
            let sp = d.operating_point.speed.as_ref().unwrap();
            println!(
                "{class:?} snr {snr}: {} (p {:.1e}) speed {:.1} {:?} slack {:.4} read at {:?}",
                d.verdict, d.p_healthy, sp.rpm_used, sp.source, sp.relative_uncertainty, sp.read_at
            );
            for e in &d.evidence {
                let s = e.significance.as_ref().unwrap();
                println!(
                    "   {:<5} f1/F {:.4} T {:5.1} p {:.1e} pb {:.1e} depth {:.3} band {:?} sk {:.2} n {} lines {:?}",
                    e.hypothesis.name(),
                    s.fundamental_hz / e.fault_hz,
                    s.statistic_db,
                    s.p_healthy,
                    s.p_band,
                    s.modulation_depth,
                    s.band_hz.map(|x| x.round()),
                    e.band_spectral_kurtosis,
                    s.null_size,
                    e.harmonics
                        .iter()
                        .chain(&e.sidebands)
                        .map(|l| (l.evidence_db * 10.0).round() / 10.0)
                        .collect::<Vec<_>>()
                );
            }
        }
    }
}
