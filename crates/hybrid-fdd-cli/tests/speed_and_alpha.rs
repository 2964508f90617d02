//! `hybrid-fdd diagnose` without a declared speed (`--rpm-range`), with a false-alarm level
//! (`--alpha`), with a bearing nobody gave (`--bearing unknown`), and the typed errors of bad
//! ranges, on synthetic recordings of the 12-ball rig of `common`.

mod common;

use clap::Parser;
use common::{BEARING, Diagnose, Fault, dir, machine, s, write_one_column};

fn run(args: &[&str]) -> anyhow::Result<()> {
    let mut argv = vec!["diagnose"];
    argv.extend_from_slice(args);
    hybrid_fdd_cli::diagnose::run(&Diagnose::try_parse_from(argv)?.a)
}

/// The rig's recording with a shaft comb added: orders 1–12, amplitude 0.3/k (a shaft with
/// runout and a coupling's harmonics).
fn with_comb(mut x: Vec<f64>, fs: f64, rpm: f64) -> Vec<f64> {
    let fr = rpm / 60.0;
    for (n, v) in x.iter_mut().enumerate() {
        let t = n as f64 / fs;
        *v += (1..=12)
            .map(|k| {
                let k = f64::from(k);
                0.3 / k * (2.0 * std::f64::consts::PI * k * fr * t + 0.7 * k).sin()
            })
            .sum::<f64>();
    }
    x
}

fn report(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("report")).expect("JSON")
}

/// An outer-race recording at 1530 rpm, no speed declared: the range 1200–1800 rpm is searched,
/// the shaft's 1× line gives the speed (within 0.5 %), the fault is found, and the report says
/// no speed was declared.
#[test]
fn the_speed_is_found_in_a_range_without_a_declared_one() {
    let d = dir("rpm-range");
    let csv = d.join("outer.csv");
    let x = with_comb(
        machine(Fault::Outer, 12_000.0, 1530.0, 6.0, 3),
        12_000.0,
        1530.0,
    );
    write_one_column(&csv, &x);
    let out = d.join("outer.json");
    run(&[
        "--input",
        s(&csv),
        "--fs",
        "12000",
        "--rpm-range",
        "1200-1800",
        "--bearing",
        BEARING,
        "--report",
        s(&out),
    ])
    .unwrap();
    let r = report(&out);
    let speed = &r["operating_point"]["speed"];
    assert!(speed["declared_rpm"].is_null(), "{speed}");
    assert_eq!(speed["search_rpm"], serde_json::json!([1200.0, 1800.0]));
    let used = r["operating_point"]["rpm_used"].as_f64().unwrap();
    assert!((used / 1530.0 - 1.0).abs() < 5e-3, "{used}");
    assert_eq!(r["verdict"], "outer", "{}", r["evidence"]);
    assert_eq!(r["false_alarm"], 0.01);
}

/// `--alpha` sets the level written into the report; a bad level and bad ranges are one-line
/// errors naming what is wrong.
#[test]
fn alpha_and_bad_ranges() {
    let d = dir("alpha");
    let csv = d.join("healthy.csv");
    write_one_column(&csv, &machine(Fault::None, 12_000.0, 1500.0, 4.0, 5));
    let out = d.join("report.json"); // healthy.json is the recording's sidecar
    let args = |alpha: &str, range: &str| {
        vec![
            "--input".to_string(),
            s(&csv).to_string(),
            "--fs".into(),
            "12000".into(),
            "--rpm".into(),
            "1500".into(),
            "--rpm-range".into(),
            range.into(),
            "--alpha".into(),
            alpha.into(),
            "--bearing".into(),
            BEARING.into(),
            "--report".into(),
            s(&out).to_string(),
        ]
    };
    let call = |a: Vec<String>| run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    call(args("0.05", "1400-1600")).unwrap();
    let r = report(&out);
    assert_eq!(r["false_alarm"], 0.05);
    assert_eq!(r["thresholds"]["false_alarm"], 0.05);
    for (alpha, range, want) in [
        ("0", "1400-1600", "(0, 0.2]"),
        ("0.01", "1600-1400", "inverted"),
        ("0.01", "1500-1500", "empty"),
        ("0.01", "fast", "LOW-HIGH"),
        ("0.01", "1600-1700", "outside"),
    ] {
        let e = call(args(alpha, range)).unwrap_err();
        let msg = format!("{e:#}");
        assert!(msg.contains(want), "{alpha} {range}: {msg}");
        assert!(!msg.contains('\n'), "{msg}");
    }
}

/// `--bearing unknown`: the outer-race comb is found at the 12-ball rig's BPFO order
/// (`6(1 − d/D)` = 4.76 × fr, within 1 %), named outer (no sidebands), and the report says it
/// guessed; a healthy recording reads `normal`. The machine shows its shaft comb: an order is
/// only as sure as the speed (without a comb the declared speed is ± 10 % and no order can be
/// told).
#[test]
fn an_unknown_bearing_is_guessed_from_its_comb() {
    let d = dir("unknown");
    for (fault, want) in [(Fault::Outer, "outer"), (Fault::None, "normal")] {
        let csv = d.join(format!("{want}.csv"));
        let x = with_comb(machine(fault, 12_000.0, 1500.0, 6.0, 7), 12_000.0, 1500.0);
        write_one_column(&csv, &x);
        let out = d.join(format!("{want}.json"));
        run(&[
            "--input",
            s(&csv),
            "--fs",
            "12000",
            "--rpm",
            "1500",
            "--bearing",
            "unknown",
            "--report",
            s(&out),
        ])
        .unwrap();
        let r = report(&out);
        assert_eq!(r["verdict"], want, "{}", r["bearing_guess"]);
        let g = &r["bearing_guess"];
        assert!(g["note"].as_str().unwrap().starts_with("guessed"), "{g}");
        if fault == Fault::Outer {
            let bpfo = 6.0 * (1.0 - 7.94 / 38.5);
            let o = g["fault_order"].as_f64().unwrap();
            assert!((o / bpfo - 1.0).abs() < 0.01, "{o} against {bpfo}");
        }
        let md = std::fs::read_to_string(out.with_extension("md")).unwrap();
        assert!(md.contains("Bearing not given"), "{md}");
    }
}
