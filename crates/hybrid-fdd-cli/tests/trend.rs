//! `hybrid-fdd trend` on the IMS- and XJTU-SY-layout fixtures (`fixtures/trend/`), an index
//! CSV, and the bad inputs that must be one-line errors naming the file.

mod common;

use std::path::{Path, PathBuf};

use clap::Parser;

#[derive(Parser)]
struct Trend {
    #[command(flatten)]
    a: hybrid_fdd_cli::trend::Args,
}

fn fixtures(layout: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/trend")
        .join(layout)
}

fn run(args: &[&str]) -> anyhow::Result<()> {
    let mut v = vec!["trend"];
    v.extend_from_slice(args);
    hybrid_fdd_cli::trend::run(&Trend::parse_from(v).a)
}

fn err(args: &[&str]) -> String {
    format!("{:#}", run(args).expect_err("an error"))
}

fn json(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("trend.json")).unwrap()).unwrap()
}

#[test]
fn ims_layout_in_timestamp_order_with_an_alarm_after_the_baseline() {
    let out = common::dir("trend-ims");
    let input = fixtures("ims");
    run(&[
        "--input",
        common::s(&input),
        "--bearing",
        "ZA-2115",
        "--rpm",
        "2000",
        "--baseline-count",
        "5",
        "--unit",
        "g",
        "--machine-group",
        "group2-rigid",
        "--no-observers",
        "--report",
        common::s(&out),
    ])
    .unwrap();
    for f in ["trend.csv", "trend.json", "summary.md", "trend.png"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let j = json(&out);
    assert_eq!(j["axis"], "seconds");
    assert_eq!(j["layout"], "IMS (tab-separated, no header)");
    assert_eq!(j["fs_hz"], 20_000.0);
    let rows = j["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 10);
    assert_eq!(rows[0]["name"], "2004.02.12.10.32.39");
    assert_eq!(rows[9]["name"], "2004.02.12.12.02.39");
    // 10 minutes apart
    let t = |k: usize| rows[k]["time"].as_f64().unwrap();
    assert_eq!(t(1) - t(0), 600.0);
    // the impacts begin in the 7th file (index 6): with 3 of 4 the alarm is at index 8 at the
    // earliest, and nothing fires before the fault
    let alarm = &j["alarm"];
    assert_eq!(alarm["index"], 8, "{alarm}");
    assert!(
        alarm["indicators"]
            .as_array()
            .unwrap()
            .iter()
            .any(|i| i == "kurtosis"),
        "{alarm}"
    );
    for o in j["onsets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|o| !o.is_null())
    {
        assert!(o["first_exceedance_index"].as_u64().unwrap() >= 6, "{o}");
    }
    // too short for the diagnosis (20 shaft turns): said, not hidden
    assert_eq!(alarm["fault"], "not diagnosed");
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("**Alarm at 2004.02.12.11.52.39 (2004-02-12T11:52:39)**"),
        "{md}"
    );
    assert!(md.contains("needs at least 20 turns"), "{md}");
    let csv = std::fs::read_to_string(out.join("trend.csv")).unwrap();
    assert_eq!(csv.lines().count(), 11);
    assert!(csv.lines().next().unwrap().contains(",kurtosis,"));
    // zone A/B on a velocity in mm/s (g known, group given)
    assert!(rows.iter().all(|r| r["zone"].is_string()));
}

#[test]
fn xjtu_layout_in_numeric_order() {
    let out = common::dir("trend-xjtu");
    let input = fixtures("xjtu");
    run(&[
        "--input",
        common::s(&input),
        "--bearing",
        "UER204",
        "--rpm",
        "2100",
        "--baseline-count",
        "5",
        "--no-observers",
        "--report",
        common::s(&out),
    ])
    .unwrap();
    let j = json(&out);
    assert_eq!(j["axis"], "index");
    assert_eq!(j["fs_hz"], 25_600.0);
    assert_eq!(j["channel"], "Horizontal_vibration_signals");
    let names: Vec<&str> = j["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "1.csv", "2.csv", "3.csv", "4.csv", "5.csv", "6.csv", "7.csv", "8.csv", "9.csv",
            "10.csv"
        ]
    );
    assert!(j["alarm"]["index"].as_u64().unwrap() >= 8, "{}", j["alarm"]);
    // the unit is not stated: the velocity stays in unit·s and there is no zone
    assert!(j["rows"][0]["zone"].is_null());
    let vel = j["indicators"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["name"] == "velocity_rms")
        .unwrap()
        .clone();
    assert_eq!(vel["unit"], "unit·s");
    // the vertical channel carries no fault: no alarm
    let out2 = common::dir("trend-xjtu-v");
    run(&[
        "--input",
        common::s(&input),
        "--bearing",
        "UER204",
        "--rpm",
        "2100",
        "--baseline-count",
        "5",
        "--channel",
        "Vertical_vibration_signals",
        "--no-observers",
        "--report",
        common::s(&out2),
    ])
    .unwrap();
    assert!(json(&out2)["alarm"].is_null(), "{}", json(&out2)["alarm"]);
}

#[test]
fn observers_trend_on_the_ims_fixture() {
    let out = common::dir("trend-ims-obs");
    run(&[
        "--input",
        common::s(&fixtures("ims")),
        "--bearing",
        "ZA-2115",
        "--rpm",
        "2000",
        "--baseline-count",
        "5",
        "--report",
        common::s(&out),
    ])
    .unwrap();
    let j = json(&out);
    let names: Vec<&str> = j["indicators"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    for m in ["hostsmo", "pflo", "smalpio", "afsmo"] {
        assert!(names.contains(&format!("{m}_ms").as_str()), "{names:?}");
        assert!(names.contains(&format!("{m}_ratio").as_str()), "{names:?}");
    }
    // the baseline recordings (0.1 s each) are joined to the fit segment
    assert!(
        j["observers"]["fit_recording"]
            .as_str()
            .unwrap()
            .ends_with("(joined)")
    );
}

#[test]
fn an_index_csv_orders_files_elsewhere_and_cuts_segments() {
    let d = common::dir("trend-index");
    let xjtu = fixtures("xjtu");
    // listed in reverse, times say the order; relative to the index and absolute mixed
    let copy = d.join("data");
    std::fs::create_dir_all(&copy).unwrap();
    std::fs::copy(xjtu.join("1.csv"), copy.join("a.csv")).unwrap();
    let mut idx = String::from("file,time,start_s,duration_s\n");
    for k in (2..=10).rev() {
        idx.push_str(&format!(
            "{},2024-03-{k:02}T08:00:00,0.01,0.06\n",
            common::s(&xjtu.join(format!("{k}.csv")))
        ));
    }
    idx.push_str("data/a.csv,2024-03-01T08:00:00,0.01,0.06\n");
    std::fs::write(d.join("index.csv"), idx).unwrap();
    let out = d.join("out");
    run(&[
        "--index",
        common::s(&d.join("index.csv")),
        "--bearing",
        "UER204",
        "--rpm",
        "2100",
        "--baseline-count",
        "5",
        "--no-observers",
        "--report",
        common::s(&out),
    ])
    .unwrap();
    let j = json(&out);
    assert_eq!(j["axis"], "seconds");
    let rows = j["rows"].as_array().unwrap();
    assert_eq!(rows[0]["name"], "data/a.csv[0.01+0.06s]");
    assert!(rows[9]["name"].as_str().unwrap().contains("10.csv"));
    assert_eq!(
        rows[1]["time"].as_f64().unwrap() - rows[0]["time"].as_f64().unwrap(),
        86_400.0
    );
    // a segment past the file's end is an error naming the row's file
    let mut bad = String::from("file,time,start_s,duration_s\n");
    for k in 0..5 {
        let dur = if k == 3 { "5" } else { "0.05" };
        bad.push_str(&format!("data/a.csv,{k},0,{dur}\n"));
    }
    std::fs::write(d.join("bad.csv"), bad).unwrap();
    let e = err(&[
        "--index",
        common::s(&d.join("bad.csv")),
        "--bearing",
        "UER204",
        "--rpm",
        "2100",
        "--baseline-count",
        "5",
        "--report",
        common::s(&d.join("out2")),
    ]);
    assert!(
        e.starts_with(
            "data/a.csv[0+5s]: the segment asks for samples 0..128000, the file has 2048"
        ),
        "{e}"
    );
}

/// A directory with copies of the IMS fixture's files under the given names.
fn ims_copies(test: &str, names: &[&str]) -> PathBuf {
    let d = common::dir(test);
    let src = fixtures("ims");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&src)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for (n, f) in names.iter().zip(files.iter().cycle()) {
        std::fs::copy(f, d.join(n)).unwrap();
    }
    d
}

const IMS_NAMES: [&str; 6] = [
    "2004.02.12.10.32.39",
    "2004.02.12.10.42.39",
    "2004.02.12.10.52.39",
    "2004.02.12.11.02.39",
    "2004.02.12.11.12.39",
    "2004.02.12.11.22.39",
];

fn ims_args<'a>(input: &'a Path, out: &'a Path, baselines: &'a str) -> Vec<&'a str> {
    vec![
        "--input",
        common::s(input),
        "--bearing",
        "ZA-2115",
        "--rpm",
        "2000",
        "--baseline-count",
        baselines,
        "--no-observers",
        "--report",
        common::s(out),
    ]
}

#[test]
fn duplicate_and_unparseable_timestamps_are_one_line_errors_naming_the_file() {
    let mut names = IMS_NAMES.to_vec();
    names.push("2004-02-12T10:42:39.csv");
    let d = ims_copies("trend-dup", &names);
    let out = d.join("out");
    let e = err(&ims_args(&d, &out, "5"));
    assert!(
        e.contains("duplicate timestamp 2004-02-12T10:42:39")
            && e.contains("2004-02-12T10:42:39.csv"),
        "{e}"
    );
    assert_eq!(e.lines().count(), 1, "{e}");
    let mut names = IMS_NAMES.to_vec();
    names.push("readings_final.csv");
    let d = ims_copies("trend-unparsed", &names);
    let e = err(&ims_args(&d, &d.join("out"), "5"));
    assert!(e.starts_with("readings_final.csv: no timestamp"), "{e}");
}

#[test]
fn too_few_baselines_are_typed_errors() {
    let d = ims_copies("trend-few", &IMS_NAMES);
    let e = err(&ims_args(&d, &d.join("out"), "3"));
    assert!(
        e.contains("3 baseline recording(s), the thresholds need at least 5"),
        "{e}"
    );
    let e = err(&ims_args(&d, &d.join("out"), "8"));
    assert!(
        e.contains("6 recording(s), fewer than the 8 baseline"),
        "{e}"
    );
}

#[test]
fn mixed_channel_counts_and_rates_are_errors_naming_the_file() {
    let d = ims_copies("trend-cols", &IMS_NAMES);
    // an 8-column file among 4-column ones
    let eight: String = (0..2000)
        .map(|i| {
            let v = 0.01 * ((i * 7919) % 200) as f64 - 1.0;
            format!("{v:.3}\t{v:.3}\t{v:.3}\t{v:.3}\t{v:.3}\t{v:.3}\t{v:.3}\t{v:.3}\n")
        })
        .collect();
    std::fs::write(d.join("2004.02.12.11.32.39"), eight).unwrap();
    let e = err(&ims_args(&d, &d.join("out"), "5"));
    assert!(
        e.starts_with("2004.02.12.11.32.39: 8 columns, but 2004.02.12.10.32.39 has 4"),
        "{e}"
    );
    // CSV files with a time column: the 6th sampled at another rate
    let d = common::dir("trend-rates");
    for k in 1..=6 {
        let fs = if k == 6 { 10_000.0 } else { 12_000.0 };
        let x = common::noise(3000, k);
        let mut s = String::from("time_s,accel\n");
        for (i, v) in x.iter().enumerate() {
            s.push_str(&format!("{:.9},{v:.5}\n", i as f64 / fs));
        }
        std::fs::write(d.join(format!("{k}.csv")), s).unwrap();
    }
    let out = d.join("out");
    let e = err(&[
        "--input",
        common::s(&d),
        "--bearing",
        "6205",
        "--rpm",
        "1797",
        "--baseline-count",
        "5",
        "--no-observers",
        "--report",
        common::s(&out),
    ]);
    assert!(
        e.starts_with("6.csv: sampled at 10000 Hz, the first recording (1.csv) at 12000 Hz"),
        "{e}"
    );
}

#[test]
fn the_report_may_not_be_the_input_directory() {
    let d = ims_copies("trend-self", &IMS_NAMES);
    let e = err(&ims_args(&d, &d, "5"));
    assert!(e.contains("is the input directory"), "{e}");
}

#[test]
fn alarm_on_restricts_the_alarm_and_rejects_unknown_indicators() {
    let d = common::dir("trend-alarm-on");
    let input = fixtures("ims");
    let mut args = ims_args(&input, &d, "5");
    args.extend(["--alarm-on", "crest,kurtosis"]);
    run(&args).unwrap();
    let j = json(&d);
    assert_eq!(j["alarm"]["indicators"], serde_json::json!(["kurtosis"]));
    assert_eq!(j["alarm_on"], serde_json::json!(["crest", "kurtosis"]));
    let mut args = ims_args(&input, &d, "5");
    args.extend(["--alarm-on", "kurtosis,hostsmo_ms"]);
    let e = err(&args);
    assert!(
        e.contains("alarm indicator `hostsmo_ms` is not among this run's indicators"),
        "{e}"
    );
}
