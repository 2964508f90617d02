//! `hybrid-fdd bearings` and catalogue designations on the command line: the table lists every
//! row with its orders and source, one designation shows its row, an unknown one names the
//! nearest, and every `--bearing` help says designations are taken.

mod common;

use clap::{Args, Command, Parser as _};
use common::{Diagnose, Fault, dir, json, machine, s};

#[test]
fn the_table_lists_every_catalogue_row_with_orders_and_source() {
    let rows = bearing_model::catalog::entries();
    let t = hybrid_fdd_cli::bearings::table(rows);
    let lines: Vec<&str> = t.lines().collect();
    assert_eq!(lines.len(), rows.len() + 1, "{t}");
    for h in [
        "designation",
        "n",
        "d (mm)",
        "D (mm)",
        "angle",
        "BPFO",
        "BPFI",
        "FTF",
        "BSF",
        "source",
    ] {
        assert!(lines[0].contains(h), "{h}: {}", lines[0]);
    }
    for (e, line) in rows.iter().zip(&lines[1..]) {
        assert!(line.starts_with(e.designation), "{line}");
        assert!(line.ends_with(e.source), "{line}");
        let o = e.orders();
        for v in [o.bpfo, o.bpfi, o.ftf, o.ball_defect] {
            assert!(line.contains(&format!("{v:.4}")), "{v}: {line}");
        }
    }
    // the CWRU drive end as CWRU's table gives it (BSF = ball-defect rate)
    let cwru = lines.iter().find(|l| l.starts_with("6205 ")).unwrap();
    for v in [
        "9", "7.940", "39.040", "3.5848", "5.4152", "0.3983", "4.7134",
    ] {
        assert!(cwru.split_whitespace().any(|w| w == v), "{v}: {cwru}");
    }
    assert!(hybrid_fdd_cli::bearings::LEGEND.contains("ball-defect rate"));
}

#[test]
fn one_designation_shows_its_row_and_an_unknown_one_names_the_nearest() {
    let one = hybrid_fdd_cli::bearings::Args {
        designation: Some("skf 6205-2rs".into()),
    };
    hybrid_fdd_cli::bearings::run(&one).expect("a known designation");
    let bad = hybrid_fdd_cli::bearings::Args {
        designation: Some("UC2O4".into()),
    };
    let e = hybrid_fdd_cli::bearings::run(&bad).unwrap_err().to_string();
    assert!(
        e.starts_with("unknown bearing \"UC2O4\": near UC204, UC205, UC206"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}

#[test]
fn diagnose_takes_a_designation_and_refuses_a_near_miss_with_the_nearest() {
    let d = dir("bearings-designation");
    let f = d.join("rec.csv");
    common::write_one_column(&f, &machine(Fault::None, 12_000.0, 1500.0, 1.0, 4));
    let run = |bearing: &str, report: &str| {
        let report = d.join(report);
        let args = [
            "diagnose",
            "--input",
            s(&f),
            "--fs",
            "12000",
            "--rpm",
            "1500",
            "--bearing",
            bearing,
            "--report",
            s(&report),
        ];
        hybrid_fdd_cli::diagnose::run(&Diagnose::try_parse_from(args).unwrap().a)
            .map(|()| json(&report))
    };
    let r = run("Rexnord ZA-2115", "za.json").expect("a catalogue designation");
    assert_eq!(r["operating_point"]["bearing"], "Rexnord ZA-2115", "{r}");
    let bpfo = r["operating_point"]["orders"]["bpfo"].as_f64().unwrap();
    assert!((bpfo - 7.0921).abs() < 1e-4, "{bpfo}");
    // `6205` keeps naming the CWRU bearing as before
    let r = run("6205", "cwru.json").expect("6205");
    assert_eq!(r["operating_point"]["bearing"], "SKF 6205-2RS JEM", "{r}");
    assert_eq!(
        r["operating_point"]["bearing_spec"],
        "6205 (SKF 6205-2RS JEM)"
    );
    let e = format!("{:#}", run("6O08", "bad.json").unwrap_err());
    // a letter O for a zero: both sizes one edit away come first
    assert!(
        e.contains("unknown bearing \"6O08\": near 6208, 6308,"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

fn help<A: Args>(name: &'static str) -> String {
    A::augment_args(Command::new(name))
        .term_width(0)
        .render_long_help()
        .to_string()
}

#[test]
fn every_bearing_help_says_catalogue_designations_are_taken() {
    for (name, h) in [
        (
            "diagnose",
            help::<hybrid_fdd_cli::diagnose::Args>("diagnose"),
        ),
        (
            "close-loop",
            help::<hybrid_fdd_cli::close_loop::Args>("close-loop"),
        ),
        (
            "calibrate",
            help::<hybrid_fdd_cli::close_loop::CalibrateArgs>("calibrate"),
        ),
        (
            "simulate",
            help::<hybrid_fdd_cli::simulate::Args>("simulate"),
        ),
        (
            "train-classifier",
            help::<hybrid_fdd_cli::train::Args>("train-classifier"),
        ),
    ] {
        let i = h.find("--bearing ").unwrap_or_else(|| panic!("{name}"));
        let rest = &h[i..];
        let b = &rest[..rest.find("\n  -").unwrap_or(rest.len())];
        assert!(b.contains("hybrid-fdd bearings"), "{name}: {b}");
        assert!(b.contains("case-insensitive"), "{name}: {b}");
    }
    // a MAT-file's stored rate: the help names the spellings it reads
    let d = help::<hybrid_fdd_cli::diagnose::Args>("diagnose");
    let i = d.find("--fs ").unwrap();
    assert!(d[i..].contains("SampleFrequency"));
}
