//! Another rig's engineer: a bearing that is not built in is calibrated with an identified
//! declared model (`calibrate --model arx-laguerre`) and the machine model is the diagnosis
//! baseline of that rig; a `simulate` CSV's sidecar supplies the speed when `--rpm` is omitted.

mod common;

use clap::Parser as _;
use common::{BEARING, Calibrate, Diagnose, Fault, Simulate, dir, json, machine, s};

/// BUG-8: `calibrate --model arx-laguerre` on a healthy recording of a 12-ball bearing, then
/// `diagnose --baseline m.json` on an outer-race fault of that bearing and on another healthy
/// recording. The physics model calibrates it too, from its geometry; given only its four
/// multiples it cannot, and says which model can.
#[test]
fn calibrate_a_rig_with_a_bearing_that_is_not_built_in() {
    let d = dir("other-rig");
    let healthy = d.join("healthy.csv");
    common::write_time_signal(
        &healthy,
        "signal",
        &machine(Fault::None, 20_000.0, 1500.0, 2.0, 1),
        20_000.0,
        ",",
    );
    let m = d.join("m.json");
    let cal = |bearing: &str, model: Option<&str>| {
        let mut v = vec![
            "calibrate",
            "--input",
            s(&healthy),
            "--rpm",
            "1500",
            "--bearing",
            bearing,
            "--out",
            s(&m),
        ];
        if let Some(model) = model {
            v.extend(["--model", model]);
        }
        hybrid_fdd_cli::close_loop::calibrate(Calibrate::try_parse_from(v).unwrap().a)
    };
    // the physics model simulates the geometry (the machine model names it, normalised) ...
    cal(BEARING, None).expect("calibrated from the 5-DOF model of this geometry");
    let physics =
        close_loop::machine::MachineModel::from_json(&std::fs::read_to_string(&m).unwrap())
            .unwrap();
    assert!(physics.bearing.starts_with("n=12,"), "{}", physics.bearing);
    // ... but not the four multiples alone: the error names the option that can
    let e = cal("bpfo=4.7626,bpfi=7.2374,ftf=0.39688,bsf=4.6428", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--model arx-laguerre"), "{e}");
    cal(BEARING, Some("arx-laguerre")).expect("calibrated with an identified model");
    let model = close_loop::machine::MachineModel::from_json(&std::fs::read_to_string(&m).unwrap())
        .unwrap();
    assert!(model.path.is_some());
    let diagnose = |fault: Fault, seed: u64| {
        let rec = d.join(format!("{fault:?}-{seed}.csv"));
        common::write_one_column(&rec, &machine(fault, 20_000.0, 1500.0, 2.0, seed));
        let report = d.join(format!("{fault:?}-{seed}.json"));
        let a = Diagnose::try_parse_from([
            "diagnose",
            "--input",
            s(&rec),
            "--fs",
            "20000",
            "--rpm",
            "1500",
            "--bearing",
            BEARING,
            "--baseline",
            s(&m),
            "--report",
            s(&report),
        ])
        .unwrap()
        .a;
        hybrid_fdd_cli::diagnose::run(&a).unwrap();
        let v = json(&report);
        assert_eq!(v["reference"], "baseline");
        v["verdict"].as_str().unwrap().to_string()
    };
    assert_eq!(diagnose(Fault::Outer, 2), "outer");
    assert_eq!(diagnose(Fault::None, 3), "normal");
    let _ = std::fs::remove_dir_all(&d);
}

/// Item 9: `simulate` records `rpm` in its sidecar and `diagnose` takes it when `--rpm` is
/// omitted.
#[test]
fn the_speed_of_a_simulated_csv_comes_from_its_sidecar() {
    let d = dir("sidecar-rpm");
    let csv = d.join("sim.csv");
    let sim = Simulate::try_parse_from([
        "simulate",
        "--fault",
        "outer",
        "--rpm",
        "1750",
        "--duration",
        "1",
        "--out",
        s(&csv),
    ])
    .unwrap();
    hybrid_fdd_cli::simulate::run(sim.a).unwrap();
    let side = json(&csv.with_extension("json"));
    assert_eq!(side["rpm"], 1750.0);
    assert!(
        side["generator"]
            .as_str()
            .unwrap()
            .contains("hybrid-fdd simulate")
    );
    assert_eq!(hybrid_fdd_cli::diagnose::sidecar_rpm(&csv), Some(1750.0));
    // `diagnose --input <the simulated CSV> --bearing 6205 --report <report>`, no --rpm
    let diagnose_to = |report: &std::path::Path| {
        Diagnose::try_parse_from([
            "diagnose",
            "--input",
            s(&csv),
            "--bearing",
            "6205",
            "--report",
            s(report),
        ])
        .unwrap()
        .a
    };
    let report = d.join("sim-report.json");
    let a = diagnose_to(&report);
    hybrid_fdd_cli::diagnose::run(&a).expect("speed from the sidecar");
    assert_eq!(json(&report)["operating_point"]["rpm"], 1750.0);
    // a report at the sidecar's own path would overwrite it: refused, sidecar intact
    let over = diagnose_to(&csv.with_extension("json"));
    let e = hybrid_fdd_cli::diagnose::run(&over)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("would overwrite") && e.contains("sidecar"),
        "{e}"
    );
    assert_eq!(json(&csv.with_extension("json"))["rpm"], 1750.0);
    // a sidecar not written by simulate is not read for a speed
    std::fs::write(csv.with_extension("json"), r#"{"rpm": 1750}"#).unwrap();
    assert_eq!(hybrid_fdd_cli::diagnose::sidecar_rpm(&csv), None);
    let _ = std::fs::remove_dir_all(&d);
}

/// `simulate --bearing <bearing> --params <params> --fault outer --rpm 1500 --fs 20000
/// <extra…> --out <out>`.
fn simulate_outer(
    bearing: &str,
    params: &str,
    extra: &[&str],
    out: &std::path::Path,
) -> anyhow::Result<()> {
    let mut v = vec![
        "simulate",
        "--bearing",
        bearing,
        "--params",
        params,
        "--fault",
        "outer",
        "--rpm",
        "1500",
        "--fs",
        "20000",
    ];
    v.extend_from_slice(extra);
    v.extend(["--out", s(out)]);
    hybrid_fdd_cli::simulate::run(Simulate::try_parse_from(v).unwrap().a)
}

/// `simulate --bearing <geometry>` on the bare 5-DOF model: another rig's bearing (MFPT's NICE
/// bearing) simulated with an outer-race spall reads `outer` at that geometry's BPFO; the four
/// multiples alone cannot place balls, and the calibrated rig is the 6205's only.
#[test]
fn a_bearing_given_by_its_geometry_is_simulated_and_diagnosed() {
    let d = dir("simulate-geometry");
    let geometry = "n=8,d=0.235in,D=1.245in,angle=0deg";
    let simulate = |bearing: &str, params: &str, out: &std::path::Path| {
        simulate_outer(
            bearing,
            params,
            &["--duration", "4", "--seed", "5", "--snr-db", "10"],
            out,
        )
    };
    let csv = d.join("nice.csv");
    simulate(geometry, "cwru", &csv).expect("simulated with the given geometry");
    let side = json(&csv.with_extension("json"));
    assert_eq!(side["bearing"], geometry);
    assert_eq!(side["spec"]["geometry"]["n_balls"], 8);
    // MFPT's documented outer-race rate at 25 Hz shaft speed: 81.1 Hz
    let bpfo = side["fault_orders"]["bpfo"].as_f64().unwrap();
    assert!((bpfo * 25.0 - 81.12).abs() < 0.01, "BPFO {bpfo} x fr");
    let report = d.join("nice-report.json");
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&csv),
        "--bearing",
        geometry,
        "--report",
        s(&report),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a).expect("diagnosed");
    assert_eq!(json(&report)["verdict"], "outer");
    // the four multiples alone: refused, naming what is missing
    let e = simulate(
        "bpfo=3.245,bpfi=4.755,ftf=0.4056,bsf=5.109",
        "cwru",
        &d.join("x.csv"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("geometry"), "{e}");
    // the calibrated rig is the 6205's
    let e = simulate(geometry, "calibrated", &d.join("y.csv"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("calibrated rig is the 6205"), "{e}");
    // a recording simulated with one geometry, closed-looped as another bearing: refused
    let e = hybrid_fdd_cli::diagnose::bearing_or_sidecar(&csv, Some("6205"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("was simulated with"), "{e}");
    assert!(hybrid_fdd_cli::diagnose::bearing_or_sidecar(&csv, Some(geometry)).is_ok());
    let _ = std::fs::remove_dir_all(&d);
}

/// `close-loop --model physics` on a bearing given by its geometry: its own 5-DOF simulation
/// declared right adds nothing; declared healthy, the outer race nobody declared is named at that
/// geometry's BPFO.
#[test]
fn the_loop_runs_the_physics_model_of_a_bearing_given_by_its_geometry() {
    let d = dir("loop-geometry");
    let geometry = "n=8,d=0.235in,D=1.245in,angle=0deg";
    let csv = d.join("outer.csv");
    simulate_outer(geometry, "cwru", &["--duration", "2", "--seed", "8"], &csv).unwrap();
    let run = |fault: &str| {
        let report = d.join(format!("loop-{fault}.json"));
        let a = common::CloseLoop::try_parse_from([
            "close-loop",
            "--input",
            s(&csv),
            "--fault",
            fault,
            "--report",
            s(&report),
        ])
        .unwrap()
        .a;
        hybrid_fdd_cli::close_loop::run(a).expect("the loop runs");
        json(&report)
    };
    let own = run("outer");
    assert_eq!(own["effects"].as_array().unwrap().len(), 0, "{own}");
    let healthy = run("none");
    let first = &healthy["effects"][0];
    assert_eq!(first["kind"], "bearing_fault", "{healthy}");
    let bpfo = 25.0 * 3.244_979_919_678_715;
    let f = first["frequency_hz"].as_f64().unwrap();
    assert!(
        (f - bpfo).abs() < 0.005 * bpfo,
        "{f} Hz against BPFO {bpfo}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
