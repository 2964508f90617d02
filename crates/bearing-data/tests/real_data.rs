//! Tests on the real CWRU files (skip when the data directory is absent; fail under `CI=true`).

mod common;

use std::collections::HashMap;

use bearing_data::{
    DataError, FaultLabel, LoadOptions, RpmSource, Verify, entry, load_record, parse_record,
    sha256_hex, verify_bytes,
};

struct Row {
    number: u32,
    fs: f64,
    fault: String,
    stored_rpm: Option<f64>,
    nominal_rpm: f64,
    n: usize,
    has_fe: bool,
    has_ba: bool,
    de_var: String,
    sha: String,
}

fn manifest(dir: &std::path::Path) -> Vec<Row> {
    let mut rdr = csv::Reader::from_path(dir.join("cwru/MANIFEST.csv")).unwrap();
    let h: HashMap<String, usize> = rdr
        .headers()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, s)| (s.to_owned(), i))
        .collect();
    rdr.records()
        .map(|r| {
            let r = r.unwrap();
            let g = |k: &str| r[h[k]].to_owned();
            Row {
                number: g("file").trim_end_matches(".mat").parse().unwrap(),
                fs: g("sample_rate_hz").parse().unwrap(),
                fault: g("fault"),
                stored_rpm: g("stored_rpm").parse().ok(),
                nominal_rpm: g("nominal_rpm").parse().unwrap(),
                n: g("n_samples").parse().unwrap(),
                has_fe: !g("fe_var").is_empty(),
                has_ba: !g("ba_var").is_empty(),
                de_var: g("de_var"),
                sha: g("sha256"),
            }
        })
        .collect()
}

#[test]
fn every_file_loads_and_matches_the_manifest() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let rows = manifest(&dir);
    assert_eq!(rows.len(), 74);
    for row in &rows {
        // Verification on: every SHA-256 in the embedded catalog must match the file.
        let rec = load_record(&dir, row.number, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("record {}: {e}", row.number));
        assert_eq!(rec.len(), row.n, "record {} length", row.number);
        assert_eq!(rec.fs_hz(), row.fs, "record {} fs", row.number);
        assert_eq!(
            rec.fe().map(<[f64]>::len),
            row.has_fe.then_some(row.n),
            "record {} FE",
            row.number
        );
        assert_eq!(
            rec.ba().map(<[f64]>::len),
            row.has_ba.then_some(row.n),
            "record {} BA",
            row.number
        );
        assert_eq!(format!("X{:03}_DE_time", rec.variable()), row.de_var);
        match row.stored_rpm {
            Some(r) => {
                assert_eq!(rec.rpm().value, r, "record {} rpm", row.number);
                assert_eq!(rec.rpm().source, RpmSource::Stored);
            }
            None => {
                assert_eq!(rec.rpm().value, row.nominal_rpm);
                assert_eq!(rec.rpm().source, RpmSource::Nominal);
            }
        }
        assert_eq!(rec.labels().fault.as_str(), row.fault);
        assert_eq!(rec.entry().sha256, Some(row.sha.as_str()));
        let e = entry(row.number).unwrap();
        assert_eq!(e.n_samples, Some(row.n));
        assert!(e.in_shared_copy);
    }
}

/// Non-excess kurtosis m4 / m2² of the mean-removed signal.
fn kurtosis(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let (m2, m4) = x.iter().fold((0.0, 0.0), |(a, b), v| {
        let d = (v - mean) * (v - mean);
        (a + d, b + d * d)
    });
    (m4 / n) / (m2 / n).powi(2)
}

#[test]
fn de_kurtosis_matches_smith_randall_table_b2() {
    // Smith & Randall (MSSP 2015), Table B2, as transcribed in shared/docs/references.md.
    // Non-excess kurtosis (a Gaussian gives 3: record 119 → 2.96, 198 → 2.94).
    let Some(dir) = common::data_dir() else {
        return;
    };
    let published = [
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
    for (number, k_pub) in published {
        let rec = load_record(&dir, number, &LoadOptions::unverified()).unwrap();
        let k = kurtosis(rec.de());
        let rel = (k - k_pub).abs() / k_pub;
        assert!(
            rel < 0.01,
            "record {number}: kurtosis {k:.3}, published {k_pub} ({:.2} %)",
            rel * 100.0
        );
    }
}

#[test]
fn normal_97_decimates_to_12k_for_pairing() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let rec = load_record(&dir, 97, &LoadOptions::default()).unwrap();
    assert_eq!(rec.fs_hz(), 48_000.0);
    assert_eq!(rec.labels().fault, FaultLabel::Normal);
    let d = rec.de_at(12_000.0).unwrap();
    assert_eq!(d.len(), 243_938usize.div_ceil(4));
    // The anti-aliasing filter keeps the in-band content: the decimated RMS is within a few
    // percent of the original (97's energy sits far below 4.8 kHz).
    let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
    let (r0, r1) = (rms(rec.de()), rms(&d));
    assert!((r1 / r0 - 1.0).abs() < 0.05, "rms {r0} -> {r1}");
    // 12 kHz records are borrowed unchanged.
    let rec = load_record(&dir, 105, &LoadOptions::unverified()).unwrap();
    assert!(matches!(
        rec.de_at(12_000.0).unwrap(),
        std::borrow::Cow::Borrowed(_)
    ));
    assert!(matches!(
        rec.de_at(5_000.0),
        Err(DataError::NotIntegerFactor { .. })
    ));
}

#[test]
fn corrupted_real_bytes_give_typed_errors() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let path = dir.join("cwru/48k_drive_end/174.mat");
    let bytes = std::fs::read(path).unwrap();
    let e = entry(174).unwrap();
    verify_bytes(e, &bytes, Verify::Required).unwrap();
    assert_eq!(sha256_hex(&bytes), e.sha256.unwrap());
    // One flipped byte: checksum mismatch.
    let mut flipped = bytes.clone();
    flipped[5000] ^= 1;
    assert!(matches!(
        verify_bytes(e, &flipped, Verify::IfPinned),
        Err(DataError::ChecksumMismatch { number: 174, .. })
    ));
    // Truncated: malformed.
    assert!(matches!(
        parse_record(&bytes[..bytes.len() / 2], 174),
        Err(DataError::MalformedMat { .. })
    ));
    // Rename the DE variable in memory (X173_DE_time -> X173_DX_time): no DE channel.
    let mut renamed = bytes.clone();
    let pos = renamed
        .windows(12)
        .position(|w| w == b"X173_DE_time")
        .unwrap();
    renamed[pos + 6] = b'X';
    assert!(matches!(
        parse_record(&renamed, 174),
        Err(DataError::NoDriveEnd {
            variable: 173,
            found: 1
        })
    ));
    // Unpinned absent record: Verify::Required refuses.
    let absent = entry(113).or(entry(163)).unwrap();
    assert!(matches!(
        verify_bytes(absent, &bytes, Verify::Required),
        Err(DataError::NoPinnedChecksum { .. })
    ));
    // Catalogued but not on disk.
    assert!(matches!(
        load_record(&dir, 98, &LoadOptions::default()),
        Err(DataError::RecordMissing {
            number: 98,
            in_shared_copy: false,
            ..
        })
    ));
    assert!(matches!(
        load_record(&dir, 1, &LoadOptions::default()),
        Err(DataError::UnknownRecord { number: 1 })
    ));
}
