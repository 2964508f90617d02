//! Where a recording's sampling rate comes from: a CWRU `.mat` file's rate and a time column's
//! always win (a disagreeing `--fs` is a one-line error for one file, and applies only to the
//! files that store no rate in a directory batch); a time column must be strictly increasing
//! and evenly spaced; a one-column text baseline is taken at `--fs`; a baseline at a multiple of
//! the recording's rate is decimated and compared below its anti-aliasing passband edge.

mod common;

use clap::Parser as _;
use common::{BEARING, Diagnose, Fault, dir, json, machine, s};
use hybrid_fdd_cli::diagnose::{FsFlag, RecordingFlags, load, load_with};
use hybrid_fdd_cli::flags::SignalFlags;

/// BUG-3: `--baseline one.csv` (no time column) with `--fs` given is read at `--fs`.
#[test]
fn a_one_column_baseline_is_read_at_fs() {
    let d = dir("rates-baseline");
    let one = d.join("one.csv");
    common::write_one_column(&one, &machine(Fault::None, 20_000.0, 1500.0, 1.0, 1));
    let flags = RecordingFlags {
        signal: SignalFlags {
            channel: "DE".into(),
            fs: Some(20_000.0),
        },
        baseline: Some(one.clone()),
        ..RecordingFlags::default()
    };
    let b = flags
        .baseline_source()
        .expect("a one-column baseline at --fs")
        .expect("given");
    assert!(
        b.at(20_000.0, 1797.0)
            .expect("prepared")
            .1
            .contains("20000 Hz")
    );
    // the whole command, as QA ran it
    let report = d.join("one.json");
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&one),
        "--fs",
        "20000",
        "--rpm",
        "1500",
        "--bearing",
        BEARING,
        "--baseline",
        s(&one),
        "--report",
        s(&report),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a).expect("diagnose with a one-column baseline");
    assert_eq!(json(&report)["reference"], "baseline");
    // without --fs the baseline's rate is unknown: a one-line error naming --fs
    let flags = RecordingFlags {
        signal: SignalFlags {
            fs: None,
            ..flags.signal
        },
        ..flags
    };
    let e = flags.baseline_source().unwrap_err();
    assert!(format!("{e:#}").contains("--fs is required"), "{e:#}");
    let _ = std::fs::remove_dir_all(&d);
}

/// A baseline at four times the recording's rate is decimated, and its energy and kurtosis are
/// compared below the anti-aliasing filter's passband edge (0.8 of the new Nyquist), said in the
/// note and the report; a baseline at the recording's own rate compares the whole band.
#[test]
fn a_decimated_baseline_is_compared_below_its_passband_edge() {
    let d = dir("rates-decimated-baseline");
    let hi = d.join("hi.csv");
    common::write_time_signal(
        &hi,
        "accel",
        &machine(Fault::None, 48_000.0, 1500.0, 1.0, 1),
        48_000.0,
        ",",
    );
    let rec = d.join("rec.csv");
    common::write_time_signal(
        &rec,
        "accel",
        &machine(Fault::None, 12_000.0, 1500.0, 2.0, 2),
        12_000.0,
        ",",
    );
    let flags = RecordingFlags {
        signal: SignalFlags {
            channel: "accel".into(),
            fs: Some(12_000.0),
        },
        baseline: Some(hi.clone()),
        ..RecordingFlags::default()
    };
    let b = flags.baseline_source().unwrap().expect("given");
    let prepared = b.at(12_000.0, 1500.0).expect("decimated by 4");
    assert_eq!(prepared.0.band_limit_hz, Some(4_800.0));
    assert!(
        prepared.1.contains("passband edge, 4800 Hz"),
        "{}",
        prepared.1
    );
    let same = b.at(48_000.0, 1500.0).expect("at its own rate");
    assert_eq!(same.0.band_limit_hz, None);
    let report = d.join("rec.json");
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&rec),
        "--fs",
        "12000",
        "--rpm",
        "1500",
        "--bearing",
        BEARING,
        "--baseline",
        s(&hi),
        "--channel",
        "accel",
        "--report",
        s(&report),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a).expect("diagnose against a decimated baseline");
    assert_eq!(json(&report)["statistics"]["compared_below_hz"], 4800.0);
    let _ = std::fs::remove_dir_all(&d);
}

/// BUG-5: a CWRU record's own rate wins; a `--fs` more than 0.1 % away is an error for one file;
/// in a batch `--fs` applies only to the files that store no rate.
#[test]
fn a_cwru_record_keeps_its_rate() {
    let d = dir("rates-mat");
    // 105 is a 12 kHz drive-end record in the catalog
    let mat = d.join("105.mat");
    common::write_cwru_mat(
        &mat,
        105,
        &machine(Fault::None, 12_000.0, 1797.0, 1.0, 2),
        1797,
    );
    assert_eq!(load(&mat, "DE", None).unwrap().fs_hz, 12_000.0);
    assert_eq!(load(&mat, "DE", Some(12_005.0)).unwrap().fs_hz, 12_000.0);
    let e = load(&mat, "DE", Some(20_000.0)).unwrap_err().to_string();
    assert!(
        e.contains("105.mat") && e.contains("--fs 20000") && e.contains("12000 Hz"),
        "{e}"
    );
    assert!(!e.contains('\n'), "one line: {e}");
    let batch = load_with(&mat, "DE", Some(20_000.0), FsFlag::ForUnstated).unwrap();
    assert_eq!(batch.fs_hz, 12_000.0);

    // a batch of a .mat and a one-column CSV with --fs for the CSV: each at its own rate
    let csv = d.join("one.csv");
    common::write_one_column(&csv, &machine(Fault::None, 20_000.0, 1797.0, 1.0, 3));
    let out = d.join("out");
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&d),
        "--fs",
        "20000",
        "--rpm",
        "1797",
        "--bearing",
        "6205",
        "--report",
        s(&out),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a).expect("batch");
    assert_eq!(
        json(&out.join("105.json"))["operating_point"]["fs_hz"],
        12_000.0
    );
    assert_eq!(
        json(&out.join("one.json"))["operating_point"]["fs_hz"],
        20_000.0
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// QA m3 and m4: a time column gives the rate only when it is strictly increasing and evenly
/// spaced (the first bad line named), and a `--fs` more than 1 % from it is an error.
#[test]
fn a_time_column_is_checked() {
    let d = dir("rates-time");
    let x = machine(Fault::None, 20_000.0, 1500.0, 0.1, 4);
    let p = d.join("ts.csv");
    common::write_time_signal(&p, "vib", &x, 20_000.0, ",");
    assert_eq!(load(&p, "DE", None).unwrap().fs_hz, 20_000.0);
    assert_eq!(load(&p, "DE", Some(20_100.0)).unwrap().fs_hz, 20_000.0);
    let e = load(&p, "DE", Some(25_000.0)).unwrap_err().to_string();
    assert!(e.contains("time column") && e.contains("20000 Hz"), "{e}");
    assert_eq!(
        load_with(&p, "DE", Some(25_000.0), FsFlag::ForUnstated)
            .unwrap()
            .fs_hz,
        20_000.0
    );
    // rows (line numbers count the header as line 1)
    let text = std::fs::read_to_string(&p).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let bad = |lines: &[String], name: &str| {
        let q = d.join(name);
        std::fs::write(&q, lines.join("\n")).unwrap();
        load(&q, "DE", None).unwrap_err().to_string()
    };
    // a repeated stamp at line 11 (the 10th sample's repeated)
    let mut rep = lines.clone();
    rep[10] = format!("{},{}", rep[9].split(',').next().unwrap(), "0.5");
    let e = bad(&rep, "repeat.csv");
    assert!(
        e.contains("not strictly increasing at line 11"),
        "repeated stamp: {e}"
    );
    // a gap: the samples from line 201 on shifted by half a step
    for l in lines.iter_mut().skip(200) {
        let (t, v) = l.split_once(',').unwrap();
        let t: f64 = t.parse().unwrap();
        *l = format!("{:.9},{v}", t + 0.5 / 20_000.0);
    }
    let e = bad(&lines, "gap.csv");
    assert!(
        e.contains("not evenly spaced") && e.contains("line 201"),
        "gap: {e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
