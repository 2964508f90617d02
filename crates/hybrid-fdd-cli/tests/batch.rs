//! A directory of recordings: two inputs of one stem (`x.csv`, `x.tsv`) get reports of their
//! own, named by stem and extension whatever the thread timing, `summary.csv` says which report
//! is whose, and the command fails (after writing everything) when any file failed.

mod common;

use clap::Parser as _;
use common::{Diagnose, Fault, dir, machine, s};
use hybrid_fdd_cli::diagnose::report_names;

fn run_batch(input: &std::path::Path, out: &std::path::Path) -> anyhow::Result<()> {
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(input),
        "--fs",
        "20000",
        "--rpm",
        "1500",
        "--bearing",
        common::BEARING,
        "--report",
        s(out),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a)
}

/// BUG-6: `x.csv` and `x.tsv` both reported, each under its own name.
#[test]
fn inputs_of_one_stem_get_their_own_reports() {
    let d = dir("batch-stems");
    let input = d.join("in");
    std::fs::create_dir_all(&input).unwrap();
    common::write_one_column(
        &input.join("x.csv"),
        &machine(Fault::None, 20_000.0, 1500.0, 1.0, 1),
    );
    let y = machine(Fault::Outer, 20_000.0, 1500.0, 1.0, 2);
    common::write_time_signal(&input.join("x.tsv"), "vib", &y, 20_000.0, "\t");
    let out = d.join("out");
    run_batch(&input, &out).expect("batch");
    let csv = common::json(&out.join("x_csv.json"));
    let tsv = common::json(&out.join("x_tsv.json"));
    assert_ne!(
        csv["statistics"], tsv["statistics"],
        "two different reports"
    );
    assert!(!out.join("x.json").exists());
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(summary.starts_with("file,report,"), "{summary}");
    assert!(summary.contains("\nx.csv,x_csv.json,"), "{summary}");
    assert!(summary.contains("\nx.tsv,x_tsv.json,"), "{summary}");
    // reports into the input directory would mix with the recordings (a `simulate` sidecar
    // `x.json` there would be replaced by x.csv's report): refused, nothing written
    let e = format!("{:#}", run_batch(&input, &input).unwrap_err());
    assert!(e.contains("input directory"), "{e}");
    assert!(!input.join("summary.csv").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn report_names_are_unique_and_depend_on_the_names_only() {
    let files: Vec<std::path::PathBuf> = ["a.csv", "x.csv", "X.tsv", "x_csv.mat", "y.mat"]
        .iter()
        .map(std::path::PathBuf::from)
        .collect();
    assert_eq!(
        report_names(&files),
        ["a", "x_csv_2", "X_tsv", "x_csv_4", "y"]
    );
}

/// A batch with a failing file writes every report and the summary, then exits non-zero.
#[test]
fn a_batch_with_a_failed_file_fails_after_writing_everything() {
    let d = dir("batch-fail");
    let input = d.join("in");
    std::fs::create_dir_all(&input).unwrap();
    common::write_one_column(
        &input.join("good.csv"),
        &machine(Fault::None, 20_000.0, 1500.0, 1.0, 3),
    );
    std::fs::write(input.join("bad.csv"), "0.1\nnan\n0.3\n").unwrap();
    let out = d.join("out");
    let e = run_batch(&input, &out).expect_err("one file failed");
    assert!(e.to_string().contains("1 of 2 recordings failed"), "{e}");
    assert!(out.join("good.json").exists());
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(summary.contains("\nbad.csv,,"), "{summary}");
    assert!(summary.contains("\ngood.csv,good.json,"), "{summary}");
    let _ = std::fs::remove_dir_all(&d);
}
