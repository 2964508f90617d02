//! `hybrid-fdd`: the installable command (`cargo install --path crates/hybrid-fdd-cli`).
//!
//! ```text
//! hybrid-fdd diagnose --input 130.mat --bearing 6205 --baseline 97.mat --report out/130.json
//! hybrid-fdd diagnose --input recordings/ --bearing 6205 --rpm 1750 --fs 12000 --report out/
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
}

fn main() -> std::process::ExitCode {
    let r = match Cli::parse().command {
        Command::Diagnose(a) => hybrid_fdd_cli::diagnose::run(&a),
    };
    match r {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
