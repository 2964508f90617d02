//! `hybrid-fdd simulate-life` as a user runs it: a tiny degradation run in each layout, its
//! files named so that they sort in time order, `truth.json` agreeing with them, the same seed
//! giving the same bytes, and one-line errors for bad flags.

mod common;

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hybrid-fdd"))
}

fn simulate(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut c = bin();
    c.arg("simulate-life").args(extra).arg("--out").arg(out);
    c.output().expect("running hybrid-fdd")
}

/// The recordings in `dir` (everything but JSON), by name.
fn recordings(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| !n.ends_with(".json"))
        .collect();
    v.sort();
    v
}

fn truth(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("truth.json")).unwrap()).unwrap()
}

#[test]
fn rig_run_in_ims_layout() {
    let d = common::dir("simulate-life-ims");
    let a = d.join("a");
    let o = simulate(
        &a,
        &[
            "--bearing",
            "6205",
            "--fault",
            "inner",
            "--seed",
            "3",
            "--recordings",
            "6",
            "--duration",
            "0.2",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let names = recordings(&a);
    assert_eq!(names.len(), 6);
    let t = truth(&a);
    assert_eq!(t["unit"], "g");
    assert_eq!(t["fault_location"], "inner");
    assert_eq!(t["layout"], "ims");
    let recs = t["recordings"].as_array().unwrap();
    assert_eq!(recs.len(), 6);
    // names sort in time order: the sorted names are the recordings in index order
    let by_index: Vec<String> = recs
        .iter()
        .map(|r| r["file"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(names, by_index);
    assert_eq!(names[0], "2026.01.01.00.00.00");
    assert_eq!(names[1], "2026.01.01.00.10.00");
    let times: Vec<i64> = recs.iter().map(|r| r["unix_s"].as_i64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[1] - w[0] == 600));
    // onset in the stated range (0.4·6 = 2.4 → 3 ..= floor(4.2) = 4), healthy before, growing after
    let on = t["onset_index"].as_u64().unwrap() as usize;
    assert!((3..=4).contains(&on), "{on}");
    for (i, r) in recs.iter().enumerate() {
        assert_eq!(r["faulty"], i >= on);
        if i < on {
            assert_eq!(r["fault_rms"].as_f64().unwrap(), 0.0);
        }
        assert_eq!(r["spall_width_mm"].is_null(), i < on);
    }
    let w: Vec<f64> = recs[on..]
        .iter()
        .map(|r| r["spall_width_mm"].as_f64().unwrap())
        .collect();
    assert!(w.windows(2).all(|p| p[1] > p[0]), "{w:?}");
    // a load step in the healthy stretch
    let first_load = t["load_step_indices"][0].as_u64().unwrap() as usize;
    assert!(first_load >= 1 && first_load < on);
    // each file: one sample a line, 0.2 s at 12 kHz
    let text = std::fs::read_to_string(a.join(&names[0])).unwrap();
    let x: Vec<f64> = text.lines().map(|l| l.trim().parse().unwrap()).collect();
    assert_eq!(x.len(), 2400);
    assert!(x.iter().all(|v| v.is_finite()) && x.iter().any(|v| *v != 0.0));
    // the same seed, the same bytes; another seed, other samples
    let b = d.join("b");
    assert!(
        simulate(
            &b,
            &[
                "--fault",
                "inner",
                "--seed",
                "3",
                "--recordings",
                "6",
                "--duration",
                "0.2"
            ]
        )
        .status
        .success()
    );
    for n in &names {
        assert_eq!(
            std::fs::read(a.join(n)).unwrap(),
            std::fs::read(b.join(n)).unwrap(),
            "{n}"
        );
    }
    assert_eq!(
        std::fs::read(a.join("truth.json")).unwrap(),
        std::fs::read(b.join("truth.json")).unwrap()
    );
    let c = d.join("c");
    assert!(
        simulate(
            &c,
            &[
                "--fault",
                "inner",
                "--seed",
                "4",
                "--recordings",
                "6",
                "--duration",
                "0.2"
            ]
        )
        .status
        .success()
    );
    assert_ne!(
        std::fs::read(a.join(&names[0])).unwrap(),
        std::fs::read(c.join(&names[0])).unwrap()
    );
    // a run is not written over another
    let o = simulate(&a, &["--recordings", "6", "--duration", "0.2"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("not empty"));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn machine_run_in_csv_layout() {
    let d = common::dir("simulate-life-csv");
    let o = simulate(
        &d.join("run"),
        &[
            "--bearing",
            "UC204",
            "--fault",
            "ball",
            "--seed",
            "1",
            "--recordings",
            "5",
            "--duration",
            "0.2",
            "--interval",
            "3600",
            "--layout",
            "csv",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let dir = d.join("run");
    let names = recordings(&dir);
    assert_eq!(
        names,
        [
            "2026-01-01_00-00-00.csv",
            "2026-01-01_01-00-00.csv",
            "2026-01-01_02-00-00.csv",
            "2026-01-01_03-00-00.csv",
            "2026-01-01_04-00-00.csv"
        ]
    );
    let t = truth(&dir);
    assert_eq!(t["unit"], "m/s^2");
    assert_eq!(t["bearing"], "UC204");
    let on = t["onset_index"].as_u64().unwrap() as usize;
    let sev: Vec<f64> = t["recordings"].as_array().unwrap()[on..]
        .iter()
        .map(|r| r["severity_db"].as_f64().unwrap())
        .collect();
    assert_eq!(sev.first(), Some(&-25.0));
    assert_eq!(sev.last(), Some(&0.0));
    // realised severity as planned (the fault's RMS over the healthy RMS)
    for r in &t["recordings"].as_array().unwrap()[on..] {
        let got = r["fault_over_healthy_db"].as_f64().unwrap();
        let want = r["severity_db"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-6, "{got} {want}");
    }
    // the sidecar `simulate` writes: rpm (declared), bearing, accel_unit
    let side: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("2026-01-01_00-00-00.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(side["rpm"], 2100.0);
    assert_eq!(side["bearing"], "UC204");
    assert_eq!(side["accel_unit"], "m/s^2");
    assert_eq!(side["fs_hz"], 25_600.0);
    let csv = std::fs::read_to_string(dir.join(&names[0])).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("time_s,accel"));
    assert_eq!(lines.count(), 5120);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_flags_are_one_line_errors() {
    let d = common::dir("simulate-life-bad");
    for (i, flags) in [
        &["--bearing", "UC204", "--width-start-mm", "0.1"][..],
        &["--severity-start-db", "-30"],
        &["--recordings", "1"],
        &["--bearing", "6203"],
        &["--duration", "0.01"],
        &["--onset-min", "0.8", "--onset-max", "0.2"],
        &["--bearing", "6308", "--model", "rig"],
    ]
    .iter()
    .enumerate()
    {
        let o = simulate(&d.join(format!("r{i}")), flags);
        assert!(!o.status.success(), "{flags:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.starts_with("error: ") && err.trim_end().lines().count() == 1,
            "{flags:?}: {err}"
        );
    }
    std::fs::remove_dir_all(&d).ok();
}

/// A value outside a flag's values is refused before anything runs, with clap's error naming the
/// value and listing the possible ones (and nothing written).
#[test]
fn an_unknown_fault_model_or_layout_lists_the_possible_values() {
    let d = common::dir("simulate-life-values");
    for (i, (flags, listed)) in [
        (
            &["--fault", "cage"][..],
            "[possible values: inner, outer, ball]",
        ),
        (
            &["--model", "5dof"],
            "[possible values: auto, rig, machine]",
        ),
        (&["--layout", "mat"], "[possible values: ims, csv]"),
    ]
    .iter()
    .enumerate()
    {
        let out = d.join(format!("r{i}"));
        let o = simulate(&out, flags);
        assert!(!o.status.success(), "{flags:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        let first = err.lines().next().unwrap_or_default();
        assert_eq!(
            first,
            format!(
                "error: invalid value '{}' for '{} <{}>'",
                flags[1],
                flags[0],
                flags[0][2..].to_uppercase()
            ),
            "{err}"
        );
        assert!(err.contains(listed), "{flags:?}: {err}");
        assert!(!out.exists(), "{flags:?}: nothing written");
    }
    // any case, as before
    let o = simulate(
        &d.join("upper"),
        &[
            "--fault",
            "BALL",
            "--model",
            "Machine",
            "--bearing",
            "6308",
            "--layout",
            "CSV",
            "--recordings",
            "4",
            "--duration",
            "0.2",
            "--interval",
            "3600",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::remove_dir_all(&d).ok();
}
