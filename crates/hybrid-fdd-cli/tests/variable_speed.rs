//! `hybrid-fdd diagnose` on recordings whose speed sweeps (a run-up, a coast-down): order
//! tracked from a tachometer column (`--tach`) or, without one, from the recording's own shaft
//! comb; and the typed errors of a tachometer that is not one.

mod common;

use std::f64::consts::PI;

use clap::Parser;
use common::{BEARING, Diagnose, dir, noise, s};

fn run(args: &[&str]) -> anyhow::Result<()> {
    let mut argv = vec!["diagnose"];
    argv.extend_from_slice(args);
    hybrid_fdd_cli::diagnose::run(&Diagnose::try_parse_from(argv)?.a)
}

fn report(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("report")).expect("JSON")
}

const FS: f64 = 20_000.0;
const SECS: f64 = 8.0;
/// Tachometer pulses per turn.
const PPR: f64 = 60.0;

/// A sweep from `f0` to `f1` Hz over [`SECS`] of the [`BEARING`] rig: the vibration (noise, a
/// 1× line, with `comb` the shaft's orders 1–12 at 0.3/k, with `outer` outer-race impacts at
/// BPFO of the shaft's angle, 1 % jitter accumulating, ringing 3 kHz) and a tachometer of
/// [`PPR`] square pulses a turn.
fn sweep(f0: f64, f1: f64, outer: bool, comb: bool, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let n = (FS * SECS) as usize;
    let w = noise(n + 4096, seed);
    let theta: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 / FS;
            f0 * t + 0.5 * (f1 - f0) / SECS * t * t
        })
        .collect();
    let mut x: Vec<f64> = (0..n)
        .map(|k| {
            let a = 2.0 * PI * theta[k];
            let c = if comb {
                (1..=12)
                    .map(|j| 0.3 / f64::from(j) * (f64::from(j) * a + 0.7 * f64::from(j)).sin())
                    .sum::<f64>()
            } else {
                0.0
            };
            0.2 * (a + 0.3).sin() + c + 1.73 * w[k]
        })
        .collect();
    if outer {
        let r = 7.94 / 38.5;
        let step = 1.0 / (6.0 * (1.0 - r)); // turns between impacts
        let kernel: Vec<f64> = (0..(0.0064 * FS) as usize)
            .map(|k| {
                let t = k as f64 / FS;
                (-t / 0.0008).exp() * (2.0 * PI * 3000.0 * t).sin()
            })
            .collect();
        let (mut a, mut j, mut k) = (0.0, 0, 0);
        while a < theta[n - 1] {
            while k + 1 < n && theta[k + 1] <= a {
                k += 1;
            }
            for (i, v) in kernel.iter().enumerate() {
                if let Some(y) = x.get_mut(k + i) {
                    *y += v;
                }
            }
            a += step * (1.0 + 0.02 * w[n + (j % 4096)]);
            j += 1;
        }
    }
    let tach = theta
        .iter()
        .map(|a| if (a * PPR).fract() < 0.5 { 5.0 } else { 0.0 })
        .collect();
    (x, tach)
}

fn write(path: &std::path::Path, x: &[f64], tach: &[f64]) {
    let mut body = String::from("accel,tach\n");
    for (a, t) in x.iter().zip(tach) {
        body += &format!("{a:.6},{t:.1}\n");
    }
    std::fs::write(path, body).expect("write");
}

/// `diagnose`'s flags for `csv` (its `accel` column at 20 kHz) reported to `out`, then `extra`.
fn args<'a>(csv: &'a std::path::Path, out: &'a std::path::Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![
        "--input",
        s(csv),
        "--channel",
        "accel",
        "--fs",
        "20000",
        "--bearing",
        BEARING,
        "--report",
        s(out),
    ];
    a.extend_from_slice(extra);
    a
}

fn diagnose(csv: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> serde_json::Value {
    run(&args(csv, out, extra)).expect("diagnose");
    report(out)
}

/// An outer race coasting down from 1500 to 900 rpm: read at one speed its lines smear over the
/// sweep and nothing is found; order tracked from the tachometer the fault is named, and the
/// report says how the speed went.
#[test]
fn a_coast_down_is_diagnosed_from_its_tachometer() {
    let d = dir("coast-down");
    let csv = d.join("outer.csv");
    let (x, tach) = sweep(25.0, 15.0, true, false, 3);
    write(&csv, &x, &tach);
    let j = diagnose(&csv, &d.join("untracked.json"), &["--rpm", "1200"]);
    assert_eq!(j["verdict"], "normal", "{}", j["verdict"]);
    assert!(j.get("order_tracking").is_none());
    let j = diagnose(
        &csv,
        &d.join("tracked.json"),
        &["--tach", "tach", "--pulses-per-rev", "60"],
    );
    assert_eq!(j["verdict"], "outer", "{}", j["verdict"]);
    let t = &j["order_tracking"];
    assert_eq!(t["source"]["kind"], "tachometer");
    let (lo, hi) = (
        t["min_rpm"].as_f64().unwrap(),
        t["max_rpm"].as_f64().unwrap(),
    );
    assert!(
        (lo - 900.0).abs() < 10.0 && (hi - 1500.0).abs() < 10.0,
        "{lo}–{hi}"
    );
    let md = std::fs::read_to_string(d.join("tracked.md")).unwrap();
    assert!(md.contains("order tracked from the tachometer"), "{md}");
    // a healthy machine on the same sweep stays normal
    let (x, tach) = sweep(25.0, 15.0, false, false, 4);
    let healthy = d.join("healthy.csv");
    write(&healthy, &x, &tach);
    let j = diagnose(
        &healthy,
        &d.join("healthy.json"),
        &["--tach", "tach", "--pulses-per-rev", "60"],
    );
    assert_eq!(j["verdict"], "normal", "{}", j["verdict"]);
}

/// A run-up with a shaft comb and no tachometer given: the comb read frame by frame gives the
/// speed, the recording is tracked along it, and the fault is named.
#[test]
fn a_run_up_is_tracked_from_its_own_shaft_comb() {
    let d = dir("run-up");
    let csv = d.join("outer.csv");
    let (x, tach) = sweep(15.0, 25.0, true, true, 5);
    write(&csv, &x, &tach);
    let j = diagnose(&csv, &d.join("outer.json"), &["--rpm", "1200"]);
    assert_eq!(j["verdict"], "outer", "{}", j["verdict"]);
    let t = &j["order_tracking"];
    assert_eq!(t["source"]["kind"], "shaft_comb", "{t}");
    let (lo, hi) = (
        t["min_rpm"].as_f64().unwrap(),
        t["max_rpm"].as_f64().unwrap(),
    );
    assert!(lo < 1000.0 && hi > 1400.0, "{lo}–{hi}");
    // `--steady-speed`: the same file read at one speed, its lines smeared over the run-up
    let one = diagnose(
        &csv,
        &d.join("one.json"),
        &["--rpm", "1200", "--steady-speed"],
    );
    assert!(one.get("order_tracking").is_none(), "{one}");
    assert_ne!(one["verdict"], "outer", "{}", one["verdict"]);
}

/// `--tach` with a declared speed, a tachometer without pulses and one without enough of them
/// are one-line errors that say what is wrong.
#[test]
fn a_tachometer_that_is_not_one_is_a_typed_error() {
    let d = dir("tach-errors");
    let csv = d.join("outer.csv");
    let (x, tach) = sweep(20.0, 20.0, true, false, 6);
    write(&csv, &x, &tach);
    let out = d.join("r.json");
    let with = |extra: &[&str]| format!("{:#}", run(&args(&csv, &out, extra)).unwrap_err());
    let e = with(&["--tach", "tach", "--rpm", "1200"]);
    assert!(e.contains("leave out --rpm"), "{e}");
    let e = with(&["--tach", "tach", "--baseline", s(&csv)]);
    assert!(e.contains("not supported"), "{e}");
    let e = with(&["--tach", "tach", "--steady-speed"]);
    assert!(e.contains("--steady-speed"), "{e}");
    // the vibration itself as the tachometer: its crossings are no pulse train
    let e = with(&["--tach", "accel"]);
    assert!(e.contains("tachometer"), "{e}");
    // 60 pulses a turn read as 6000: too few turns
    let e = with(&["--tach", "tach", "--pulses-per-rev", "6000"]);
    assert!(e.contains("needs at least 20"), "{e}");
}
