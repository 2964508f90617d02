//! `hybrid-fdd`: the installable command (`cargo install --path crates/hybrid-fdd-cli`).
//!
//! ```text
//! hybrid-fdd diagnose --input 130.mat --bearing 6205 --baseline 97.mat --report out/130.json
//! hybrid-fdd diagnose --input recordings/ --bearing 6205 --rpm 1750 --fs 12000 --report out/
//! hybrid-fdd calibrate --input 97.mat --decimate 4 --out rig.json
//! hybrid-fdd close-loop --input 130.mat --fault outer --machine rig.json --report out/130.json
//! hybrid-fdd simulate --fault outer --rpm 1797 --fs 12000 --duration 2 --seed 1 --out sim.csv
//! hybrid-fdd train-classifier --labels labelled.csv --bearing 6205 --out clf.json
//! hybrid-fdd diagnose --input 130.mat --bearing 6205 --classifier clf.json --report out/130.json
//! hybrid-fdd bearings            # the built-in bearing catalogue; `hybrid-fdd bearings uc204`
//! hybrid-fdd trend --input ims/1st_test --bearing ZA-2115 --rpm 2000 --report out/trend
//! ```

use clap::{Parser, Subcommand};

/// Model-based bearing fault diagnosis from vibration.
#[derive(Parser, Debug)]
#[command(name = "hybrid-fdd", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Diagnose a recording (or every .mat/.csv in a directory): normal, inner, outer, ball or a
    /// combination, with the envelope-spectrum evidence, as JSON + Markdown + PNG.
    Diagnose(hybrid_fdd_cli::diagnose::Args),
    /// Calibrate a machine model on a healthy recording (the closed loop's result, saved as
    /// versioned JSON: structural path and modes, lines, floor, speed ratio, units).
    Calibrate(hybrid_fdd_cli::close_loop::CalibrateArgs),
    /// Close the loop on a recording: residual -> missing effect -> augmented model, held-out
    /// error before and after, as JSON + Markdown + PNG.
    CloseLoop(hybrid_fdd_cli::close_loop::Args),
    /// Simulate a recording: the calibrated CWRU rig at 6205 / 12 kHz (accel in g), else the
    /// bare 5-DOF model (m/s²); CSV `time_s,accel` + JSON sidecar stating `accel_unit`.
    Simulate(hybrid_fdd_cli::simulate::Args),
    /// Simulate a degradation run with known truth: recordings named by time, a spall that
    /// appears and grows, speed drift, load and gain steps; plus DIR/truth.json.
    SimulateLife(hybrid_fdd_cli::simulate_life::Args),
    /// Train the optional classifier on labelled recordings (CSV `file,label[,load_hp][,rpm]`):
    /// the diagnosis evidence of their segments, a Gini tree or linear SVM, grouped
    /// cross-validation printed; `diagnose --classifier` then adds its class to the report.
    TrainClassifier(hybrid_fdd_cli::train::Args),
    /// List the built-in bearing catalogue that `--bearing` takes designations from: geometry,
    /// fault orders (× shaft frequency) and the source of each row; or the one row a
    /// designation names.
    Bearings(hybrid_fdd_cli::bearings::Args),
    /// Watch a machine over time: a directory of its recordings (or an index CSV `file,time`)
    /// in time order → health indicators per recording, thresholds from the first N, the onset
    /// alarm, the fault named and the severity after it (trend.csv/json, summary.md, trend.png).
    Trend(hybrid_fdd_cli::trend::Args),
}

fn main() -> std::process::ExitCode {
    let r = match Cli::parse().command {
        Command::Diagnose(a) => hybrid_fdd_cli::diagnose::run(&a),
        Command::Calibrate(a) => hybrid_fdd_cli::close_loop::calibrate(a),
        Command::CloseLoop(a) => hybrid_fdd_cli::close_loop::run(a),
        Command::Simulate(a) => hybrid_fdd_cli::simulate::run(a),
        Command::SimulateLife(a) => hybrid_fdd_cli::simulate_life::run(a),
        Command::TrainClassifier(a) => hybrid_fdd_cli::train::run(&a),
        Command::Bearings(a) => hybrid_fdd_cli::bearings::run(&a),
        Command::Trend(a) => hybrid_fdd_cli::trend::run(&a),
    };
    match r {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
