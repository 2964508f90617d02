//! Real-data checks on the CWRU drive-end records (skipped when the data is absent, unless
//! `CI=true`).
//!
//! Measured (2026-11): kurtosis within 0.13 % of the table; wanted/other line ratio ≥ 6.6.
//!
//! Provenance: kurtosis of the whole DE channel from Smith & Randall (2015), Table B2, as quoted in
//! `shared/docs/references.md` (reproduced within 0.3 % elsewhere). Envelope lines: the data
//! README's sanity check — every IR007/014/021 record shows a strong BPFI line, every OR@6 007/021
//! record a strong BPFO line, in the envelope of the 2–5 kHz band, at the stored rpm.

use std::path::{Path, PathBuf};

use bearing_data::{DataLocation, LoadOptions, Recording, load_record};
use residual_features::*;

fn data_dir() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let loc = DataLocation::resolve(None, &root).ok()?;
    match loc.required() {
        Ok(dir) => Some(dir.to_path_buf()),
        Err(e) => {
            if std::env::var("CI").as_deref() == Ok("true") {
                panic!("CWRU data required under CI=true: {e}");
            }
            eprintln!("skipping CWRU test: {e}");
            None
        }
    }
}

fn load(dir: &Path, n: u32) -> Recording {
    load_record(dir, n, &LoadOptions::default()).unwrap()
}

#[test]
fn kurtosis_matches_smith_randall_table_b2() {
    let Some(dir) = data_dir() else { return };
    let table = [
        (106, 5.54),
        (170, 22.1),
        (210, 7.67),
        (119, 2.96),
        (186, 8.84),
        (223, 9.41),
        (131, 7.60),
        (198, 2.94),
        (235, 22.0),
    ];
    for (n, expected) in table {
        let k = kurtosis(load(&dir, n).de()).unwrap();
        let rel = (k / expected - 1.0).abs();
        println!("{n}: kurtosis {k:.3} vs {expected} ({:.2} %)", 100.0 * rel);
        assert!(rel < 0.005, "record {n}: {k} vs {expected}");
    }
}

#[test]
fn envelope_lines_identify_inner_and_outer_race_records() {
    let Some(dir) = data_dir() else { return };
    let band = Band::new(2000.0, 5000.0).unwrap();
    let cases: [(&[u32], FaultLine, FaultLine); 2] = [
        (
            &[105, 106, 107, 108, 169, 170, 171, 172, 209, 210, 211, 212],
            FaultLine::Bpfi,
            FaultLine::Bpfo,
        ),
        (
            &[130, 131, 132, 133, 234, 235, 236, 237],
            FaultLine::Bpfo,
            FaultLine::Bpfi,
        ),
    ];
    for (records, want, other) in cases {
        for &n in records {
            let rec = load(&dir, n);
            let env = EnvelopeSettings {
                shaft_hz: rec.rpm().shaft_hz(),
                multiples: bearing_model::BearingGeometry::skf_6205().orders(),
                demodulation_band: Some(band),
                tolerance: 0.02,
            };
            let features = vec![
                Feature::EnvelopeLine {
                    line: want,
                    harmonic: 1,
                },
                Feature::EnvelopeLine {
                    line: other,
                    harmonic: 1,
                },
            ];
            let mut fx = FeatureExtractor::new(FeatureConfig {
                features,
                sample_rate_hz: Some(rec.fs_hz()),
                envelope: Some(env),
            })
            .unwrap();
            // one 2^15-sample window (2.7 s at 12 kHz)
            let row = fx.extract(&rec.de()[..32_768]).unwrap();
            println!("{n}: {want:?} {:.4} vs {other:?} {:.4}", row[0], row[1]);
            assert!(row[0] > 4.0 * row[1], "record {n}: {row:?}");
        }
    }
}
