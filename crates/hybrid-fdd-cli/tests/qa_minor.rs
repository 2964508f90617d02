//! QA's minor findings, as a user meets them through the flags: a fault location named twice, a
//! fault onset outside the recording, reports that state no unit for their amplitudes, a
//! textbook ball spin given as `bsf`, a bearing spec echoed in lower case, and a negative speed
//! or rate read as an unknown flag.

mod common;

use clap::Parser as _;
use common::{Calibrate, CloseLoop, Diagnose, Simulate, dir, json, s};

/// `simulate`'s error for `extra` flags (written into `d`), as the command prints it.
fn simulate_error(d: &std::path::Path, extra: &[&str]) -> String {
    let out = d.join("sim.csv");
    let mut v = vec!["simulate", "--out", s(&out)];
    v.extend_from_slice(extra);
    let a = Simulate::try_parse_from(v).unwrap().a;
    format!("{:#}", hybrid_fdd_cli::simulate::run(a).unwrap_err())
}

/// 2 s of the bare 5-DOF model with an outer-race fault at 1797 rpm (accel in m/s², stated by
/// its sidecar).
fn simulate_outer(out: &std::path::Path) {
    let a = Simulate::try_parse_from([
        "simulate",
        "--fault",
        "outer",
        "--params",
        "cwru",
        "--duration",
        "2",
        "--seed",
        "4",
        "--out",
        s(out),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::simulate::run(a).unwrap();
}

/// `close-loop` on `input` with `fault`, reporting to `report`, plus `extra` flags.
fn close_loop(
    input: &std::path::Path,
    fault: &str,
    report: &std::path::Path,
    extra: &[&str],
) -> anyhow::Result<()> {
    let mut v = vec![
        "close-loop",
        "--input",
        s(input),
        "--fault",
        fault,
        "--report",
        s(report),
    ];
    v.extend_from_slice(extra);
    hybrid_fdd_cli::close_loop::run(CloseLoop::try_parse_from(v).unwrap().a)
}

#[test]
fn a_fault_location_named_twice_is_a_one_line_error() {
    let d = dir("qa-repeated");
    let out = d.join("sim.csv");
    for fault in ["inner+inner", "outer+outer", "ball+inner+ball", "IR+inner"] {
        // refused as the flag is read (bearing-model's parser, clap's wording), before any
        // simulation: the calibrated rig (the default here) and the bare 5-DOF model alike
        for params in ["auto", "cwru"] {
            let v = [
                "simulate",
                "--out",
                s(&out),
                "--fault",
                fault,
                "--params",
                params,
            ];
            let e = Simulate::try_parse_from(v).unwrap_err().to_string();
            let first = e.lines().next().unwrap_or_default();
            assert!(
                first.contains("twice") && first.contains(&format!("invalid value '{fault}'")),
                "{fault}: {e}"
            );
        }
    }
    assert!(!out.exists(), "nothing written");
    // close-loop parses its --fault with the same parser
    let e = CloseLoop::try_parse_from(["close-loop", "--fault", "outer+outer"])
        .unwrap_err()
        .to_string();
    assert!(
        e.lines().next().unwrap_or_default().contains("outer twice"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// An unknown `--fault` is refused as the flag is read, with clap's error naming the value and
/// listing the classes; `--help` lists them too; every spelling bearing-model's parser takes is
/// still taken (`normal`, `healthy`, `ir`, any order and case).
#[test]
fn an_unknown_fault_is_refused_with_the_possible_values() {
    const CLASSES: &str = "[possible values: none, inner, outer, ball, inner+outer, inner+ball, \
                           outer+ball, inner+outer+ball]";
    for e in [
        Simulate::try_parse_from(["simulate", "--out", "x.csv", "--fault", "cage"]).unwrap_err(),
        CloseLoop::try_parse_from(["close-loop", "--fault", "cage"]).unwrap_err(),
    ] {
        assert_eq!(e.kind(), clap::error::ErrorKind::InvalidValue);
        let text = e.to_string();
        assert!(
            text.starts_with("error: invalid value 'cage' for '--fault <FAULT>'"),
            "{text}"
        );
        assert!(text.contains(CLASSES), "{text}");
    }
    let help = <CloseLoop as clap::CommandFactory>::command()
        .term_width(0)
        .render_long_help()
        .to_string();
    assert!(help.contains(CLASSES), "{help}");
    for (v, want) in [
        ("normal", bearing_model::FaultClass::None),
        ("Healthy", bearing_model::FaultClass::None),
        ("IR", bearing_model::FaultClass::Inner),
        ("or+inner", bearing_model::FaultClass::InnerOuter),
        ("ball,OUTER,ir", bearing_model::FaultClass::InnerOuterBall),
    ] {
        let a = Simulate::try_parse_from(["simulate", "--out", "x.csv", "--fault", v])
            .unwrap()
            .a;
        assert_eq!(a.fault, want, "{v}");
    }
}

#[test]
fn a_fault_onset_outside_the_recording_is_an_error() {
    let d = dir("qa-onset");
    let base = ["--params", "cwru", "--duration", "0.1"];
    for (fault, onset, says) in [
        ("outer", "0.1", "never appear"),
        ("outer", "5", "never appear"),
        ("none", "5", "never appear"),
        ("inner", "-1", ">= 0"),
        ("inner", "nan", ">= 0"),
        ("inner", "inf", ">= 0"),
    ] {
        let mut v = base.to_vec();
        v.extend(["--fault", fault, "--onset", onset]);
        let e = simulate_error(&d, &v);
        assert!(e.contains("onset") && e.contains(says), "{onset}: {e}");
        assert!(!e.contains('\n'), "{e}");
        if says == "never appear" {
            assert!(e.contains("0.1 s recording"), "{e}");
        }
    }
    assert!(!d.join("sim.csv").exists(), "nothing written");
    // inside the recording it simulates
    let out = d.join("ok.csv");
    let mut v = vec![
        "simulate",
        "--out",
        s(&out),
        "--fault",
        "outer",
        "--onset",
        "0.05",
    ];
    v.extend(base);
    hybrid_fdd_cli::simulate::run(Simulate::try_parse_from(v).unwrap().a).unwrap();
    assert!(out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn reports_state_the_unit_and_echo_the_bearing_as_typed() {
    let d = dir("qa-unit");
    let csv = d.join("rec.csv");
    simulate_outer(&csv);
    let typed = "BPFO=3.5848,BPFI=5.4152,FTF=0.39828,BSF=4.7135";
    let report = d.join("loop.json");
    close_loop(
        &csv,
        "outer",
        &report,
        &["--model", "phenomenological", "--bearing", typed],
    )
    .unwrap();
    let v = json(&report);
    assert_eq!(v["unit"]["code"], "m/s^2", "{}", v["unit"]);
    assert!(v["unit"]["statement"].as_str().unwrap().starts_with("m/s²"));
    // the keys users script against are untouched
    assert!(v["error_before"].is_f64() && v["error_after"].is_f64());
    assert_eq!(
        v["declared"]["bearing"],
        "multiples bpfo=3.5848 bpfi=5.4152 ftf=0.39828 bsf=4.7135"
    );
    assert_eq!(v["declared"]["bearing_spec"], typed);
    let md = std::fs::read_to_string(report.with_extension("md")).unwrap();
    assert!(md.contains(&format!("bearing `{typed}`")), "{md}");
    assert!(md.contains("Recording unit: m/s²"), "{md}");
    assert!(md.contains("held-out signal RMS"), "{md}");
    let rms_line = md
        .lines()
        .find(|l| l.contains("held-out signal RMS"))
        .unwrap();
    assert!(rms_line.contains(" m/s²)"), "{rms_line}");

    // calibrate's report (beside the machine model) states it too
    let m = d.join("m.json");
    let a = Calibrate::try_parse_from([
        "calibrate",
        "--input",
        s(&csv),
        "--model",
        "phenomenological",
        "--bearing",
        "SKF6205",
        "--out",
        s(&m),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::close_loop::calibrate(a).unwrap();
    let r = d.join("m.report.json");
    assert_eq!(json(&r)["unit"]["code"], "m/s^2");
    let md = std::fs::read_to_string(r.with_extension("md")).unwrap();
    assert!(md.contains("bearing `SKF6205 (SKF 6205-2RS JEM)`"), "{md}");
    assert!(md.contains("Recording unit: m/s²"), "{md}");

    // diagnose echoes the spec as typed as well
    let dr = d.join("diag.json");
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&csv),
        "--bearing",
        typed,
        "--report",
        s(&dr),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a).unwrap();
    assert_eq!(json(&dr)["operating_point"]["bearing_spec"], typed);
    let md = std::fs::read_to_string(dr.with_extension("md")).unwrap();
    assert!(md.contains(&format!("bearing {typed}")), "{md}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_textbook_ball_spin_as_bsf_is_refused() {
    let plan = |bearing: &str| {
        Diagnose::try_parse_from(["diagnose", "--bearing", bearing])
            .unwrap()
            .a
            .recording
            .plan()
    };
    let e = format!(
        "{:#}",
        plan("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=2.3567").unwrap_err()
    );
    assert!(
        e.contains("textbook ball-spin") && e.contains("bsf=4.7134"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
    // CWRU's own table is accepted without a word; a value off the kinematics is accepted with
    // a warning (a catalogue may round or state another convention)
    let ok = plan("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135").unwrap();
    assert!(ok.bearing.warnings().is_empty());
    let odd = plan("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=5.3").unwrap();
    assert_eq!(odd.bearing.warnings().len(), 1);
    // close-loop reads --bearing with the same parser
    let d = dir("qa-bsf");
    let csv = d.join("rec.csv");
    simulate_outer(&csv);
    let flags = [
        "--model",
        "phenomenological",
        "--bearing",
        "bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=2.3567",
    ];
    let e = format!(
        "{:#}",
        close_loop(&csv, "outer", &d.join("r.json"), &flags).unwrap_err()
    );
    assert!(e.contains("textbook ball-spin"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_negative_speed_or_rate_gets_the_range_error_not_a_parse_error() {
    let d = dir("qa_negative");
    let csv = d.join("x.csv");
    std::fs::write(&csv, "1\n-1\n".repeat(4096)).unwrap();
    // diagnose: --rpm -5 is parsed as a number and refused by the speed's range check
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&csv),
        "--fs",
        "12000",
        "--rpm",
        "-5",
        "--bearing",
        "6205",
        "--report",
        s(&d.join("r.json")),
    ])
    .expect("a negative number is a value, not a flag")
    .a;
    let e = format!("{:#}", hybrid_fdd_cli::diagnose::run(&a).unwrap_err());
    assert!(e.contains("-5 rpm out of range"), "{e}");
    // close-loop and calibrate: --fs -12000
    let c = CloseLoop::try_parse_from([
        "close-loop",
        "--input",
        s(&csv),
        "--fs",
        "-12000",
        "--report",
        s(&d.join("c.json")),
    ])
    .expect("a negative number is a value, not a flag")
    .a;
    let e = format!("{:#}", hybrid_fdd_cli::close_loop::run(c).unwrap_err());
    assert!(e.contains("-12000"), "{e}");
    let c = Calibrate::try_parse_from([
        "calibrate",
        "--input",
        s(&csv),
        "--fs",
        "12000",
        "--rpm",
        "-1797",
        "--out",
        s(&d.join("m.json")),
    ])
    .expect("a negative number is a value, not a flag")
    .a;
    let e = format!(
        "{:#}",
        hybrid_fdd_cli::close_loop::calibrate(c).unwrap_err()
    );
    assert!(e.contains("-1797"), "{e}");
    // simulate: --rpm -100
    let e = simulate_error(&d, &["--rpm", "-100"]);
    assert!(e.contains("--rpm must be > 0 (got -100)"), "{e}");
}
