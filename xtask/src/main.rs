//! `cargo xtask`: the project's task runner (rust-analyzer's xtask pattern).
//!
//! One small binary with a subcommand enum. Algorithm code lives in the library crates; each
//! module here only wires crates together, writes reports and figures, and checks results.

mod calibration;
mod chapters;
mod close_loop;
mod common;
mod data;
mod diagnose;
mod false_alarm;
mod identify;
mod trend;

use clap::{Parser, Subcommand};

/// Tasks of the hybrid-fdd workspace.
#[derive(Parser, Debug)]
#[command(name = "cargo xtask", version, about)]
struct Cli {
    #[command(flatten)]
    global: common::GlobalArgs,
    #[command(subcommand)]
    task: Task,
}

#[derive(Subcommand, Debug)]
enum Task {
    /// Print the CWRU catalog against what is on disk: present, verified, missing.
    Data(data::Args),
    /// Simulate a recording (the calibrated CWRU rig at 6205 / 12 kHz, in g; else the bare 5-DOF
    /// model, in m/s²) and write it as CSV with a JSON sidecar.
    Simulate(hybrid_fdd_cli::simulate::Args),
    /// Compare ARX, ARX-Laguerre and fuzzy ARX-Laguerre one-step prediction on held-out CWRU data.
    Identify(identify::Args),
    /// Chapter 2: APIO, SMO, HOSTSMO on the 5-DOF model, energy features, one-vs-one SVM.
    Chapter2(chapters::Args),
    /// Chapter 3: APIO, FLO, PFLO on the 5-DOF model, energy features, one-vs-one SVM.
    Chapter3(chapters::Args),
    /// Chapter 4: APIO, SMALPIO on ARX-Laguerre, energy features, one-vs-one SVM.
    Chapter4(chapters::Args),
    /// Chapter 5: SMO, ASMO, AFSMO on fuzzy ARX-Laguerre, energy features, Gini decision tree.
    Chapter5(chapters::Args),
    /// Every chapter, in order.
    All(chapters::Args),
    /// Close the loop: residual -> missing effect -> augmented model, error before and after.
    CloseLoop(close_loop::Args),
    /// Calibrate a machine model on a healthy recording (the loop's result, saved as JSON).
    Calibrate(hybrid_fdd_cli::close_loop::CalibrateArgs),
    /// Calibrate the simulator to the measured CWRU rig; compare simulated and measured records.
    CalibrateRig(calibration::Args),
    /// Diagnose a recording (or a directory, or with --all-real every CWRU, MFPT and UESTC
    /// recording, or with --false-alarm a corpus of simulated and real healthy machines): normal,
    /// inner, outer, ball, a combination or uncertain, training-free.
    Diagnose(diagnose::Args),
    /// Issue 57's validation: simulated degradation runs with known truth (--validate) and the
    /// staged real sequences (--staged) through the trend, into `results/trend/`.
    Trend(trend::Args),
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // One line per cause, no backtrace: errors name the recording and stage that failed.
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    let ctx = common::Context::new(&cli.global)?;
    match cli.task {
        Task::Data(a) => data::run(&ctx, a),
        Task::Simulate(a) => hybrid_fdd_cli::simulate::run(a),
        Task::Identify(a) => identify::run(&ctx, a),
        Task::Chapter2(a) => chapters::run(&ctx, &[2], a),
        Task::Chapter3(a) => chapters::run(&ctx, &[3], a),
        Task::Chapter4(a) => chapters::run(&ctx, &[4], a),
        Task::Chapter5(a) => chapters::run(&ctx, &[5], a),
        Task::All(a) => chapters::run(&ctx, &[2, 3, 4, 5], a),
        Task::CloseLoop(a) => close_loop::run(&ctx, a),
        Task::Calibrate(a) => hybrid_fdd_cli::close_loop::calibrate(a),
        Task::CalibrateRig(a) => calibration::run(&ctx, a),
        Task::Diagnose(a) => diagnose::run(&ctx, a),
        Task::Trend(a) => trend::run(&ctx, a),
    }
}
