//! `hybrid-fdd simulate-life`: a simulated degradation run with known truth — `--recordings`
//! recordings of one machine, `--interval` seconds apart, a healthy stretch, then a spall at
//! `--fault` that appears at a drawn recording and grows, with speed drift, load steps and
//! sensor-gain steps before the onset too (`bearing_model::life`, `docs/equations/life.md`).
//!
//! * `--bearing 6205` (default `--model auto`): the **calibrated CWRU rig**
//!   (`calibrated_rig::life`), 12 kHz, in **g**, the spall's width growing;
//!   `--model machine` gives the phenomenological machine with the 6205 instead (m/s²).
//! * `--bearing UC204` (25.6 kHz) or `--bearing 6308` (20 kHz): the phenomenological machine
//!   (`bearing_model::machine`), in **m/s²**, the spall's severity (dB) growing.
//!
//! Output in `--out DIR` (which must be empty or absent), one file per recording named by its
//! start time (UTC), so the names sort in time order:
//!
//! * `--layout ims` (default): IMS-style ASCII files without extension named
//!   `YYYY.MM.DD.hh.mm.ss`, one sample per line (a single tab-separated column), in the run's
//!   unit;
//! * `--layout csv`: `YYYY-MM-DD_hh-mm-ss.csv` with `time_s,accel` as `hybrid-fdd simulate`
//!   writes it, and its JSON sidecar (`rpm` = the declared, nominal speed; `bearing`;
//!   `accel_unit`; plus `rpm_true` and the recording's truth).
//!
//! and `DIR/truth.json`: the run's [`bearing_model::life::LifeTruth`], each recording with its
//! file name and its realised healthy and fault RMS.

use anyhow::Context as _;
use bearing_model::FaultLocation;
use bearing_model::life::{self, LifeConfig, LifeMachine, LifeRecording, LifeTruth, Schedule};
use calibrated_rig::life::{self as rig_life, RigLifeConfig};
use rayon::prelude::*;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::flags::FaultLocationParser;

/// Flags of this task.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Bearing: 6205 (the calibrated CWRU rig, g; or `--model machine`), UC204 (25.6 kHz) or
    /// 6308 (20 kHz) (the phenomenological machine, m/s²).
    #[arg(long, default_value = "6205")]
    pub bearing: String,
    /// What renders the run.
    #[arg(long, value_enum, ignore_case = true, default_value_t = LifeModel::Auto)]
    pub model: LifeModel,
    /// Spall location (one per run).
    #[arg(long, default_value = "outer", value_parser = FaultLocationParser)]
    pub fault: FaultLocation,
    /// Seed of the whole run (onset, nuisances, machine, noise).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Recordings in the run (≥ 2).
    #[arg(long, default_value_t = life::DEFAULT_RECORDINGS)]
    pub recordings: usize,
    /// Duration of each recording, s.
    #[arg(long, default_value_t = life::DEFAULT_DURATION_S)]
    pub duration: f64,
    /// Interval between recordings' starts, whole seconds (≥ duration).
    #[arg(long, default_value_t = life::DEFAULT_INTERVAL_S)]
    pub interval: u64,
    /// Start of the first recording, s since 1970-01-01 UTC (default 2026-01-01T00:00:00Z).
    #[arg(long, default_value_t = life::DEFAULT_START_UNIX_S)]
    pub start_unix: i64,
    /// Earliest onset, fraction of the run.
    #[arg(long, default_value_t = life::DEFAULT_ONSET_FRACTION.0)]
    pub onset_min: f64,
    /// Latest onset, fraction of the run.
    #[arg(long, default_value_t = life::DEFAULT_ONSET_FRACTION.1)]
    pub onset_max: f64,
    /// Speed drift across the run, ± fraction of the nominal speed.
    #[arg(long, default_value_t = life::DEFAULT_SPEED_DRIFT)]
    pub speed_drift: f64,
    /// Load steps (the first always before the onset).
    #[arg(long, default_value_t = life::DEFAULT_LOAD_STEPS)]
    pub load_steps: usize,
    /// Sensor-gain steps (anywhere in the run).
    #[arg(long, default_value_t = life::DEFAULT_GAIN_STEPS)]
    pub gain_steps: usize,
    /// Nominal (declared) speed, rpm (default: the rig's 1797, the machine preset's).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Machine only: severity at the onset, dB (impacts' RMS over healthy RMS; default −25).
    #[arg(long)]
    pub severity_start_db: Option<f64>,
    /// Machine only: severity at the last recording, dB (default 0).
    #[arg(long)]
    pub severity_end_db: Option<f64>,
    /// Rig only: spall width at the onset, mm (default 0.02).
    #[arg(long)]
    pub width_start_mm: Option<f64>,
    /// Rig only: spall width at the last recording, mm (default 0.1778 = 0.007 in).
    #[arg(long)]
    pub width_end_mm: Option<f64>,
    /// File layout.
    #[arg(long, value_enum, ignore_case = true, default_value_t = Layout::Ims)]
    pub layout: Layout,
    /// Output directory (created; must be empty if it exists).
    #[arg(long)]
    pub out: PathBuf,
}

/// Which renderer a run uses.
#[derive(Debug, Clone)]
pub enum Run {
    /// The calibrated CWRU rig.
    Rig(Box<calibrated_rig::RigModel>, RigLifeConfig),
    /// The phenomenological machine.
    Machine(LifeConfig),
}

/// What renders a run (`--model`).
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum LifeModel {
    /// The calibrated rig for the 6205, else the phenomenological machine.
    Auto,
    /// The calibrated CWRU rig (the 6205 at 12 kHz, in g).
    Rig,
    /// The phenomenological machine (m/s²).
    Machine,
}

/// File layout (`--layout`).
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// IMS-style ASCII files named `YYYY.MM.DD.hh.mm.ss`, one sample a line.
    Ims,
    /// `time_s,accel` CSV files and their JSON sidecars.
    Csv,
}

/// The run the flags describe (validated).
///
/// # Errors
/// Unknown bearing; `--model rig` for another bearing; flags of the other model; the
/// configuration's typed errors.
pub fn run_of(args: &Args) -> anyhow::Result<Run> {
    let loc = args.fault;
    let schedule = Schedule {
        recordings: args.recordings,
        duration_s: args.duration,
        interval_s: args.interval,
        start_unix_s: args.start_unix,
        onset_fraction: (args.onset_min, args.onset_max),
        speed_drift: args.speed_drift,
        load_steps: args.load_steps,
        gain_steps: args.gain_steps,
        ..Schedule::default()
    };
    let entry = bearing_model::catalog::lookup(&args.bearing)?;
    let is_6205 = entry.designation == "6205";
    let rig = match args.model {
        LifeModel::Auto => is_6205,
        LifeModel::Rig if is_6205 => true,
        LifeModel::Rig => anyhow::bail!(
            "--model rig: the calibrated rig is the 6205 at 12 kHz (got --bearing {})",
            args.bearing.trim()
        ),
        LifeModel::Machine => false,
    };
    if rig {
        if let Some(f) = [
            ("--severity-start-db", args.severity_start_db),
            ("--severity-end-db", args.severity_end_db),
        ]
        .iter()
        .find(|f| f.1.is_some())
        {
            anyhow::bail!(
                "{} applies to the phenomenological machine (--model machine), not to the calibrated rig (use --width-start-mm/--width-end-mm)",
                f.0
            );
        }
        let model = calibrated_rig::cwru_rig().context("loading the calibrated CWRU rig")?;
        let mut cfg = RigLifeConfig::new(loc);
        cfg.schedule = schedule;
        if let Some(r) = args.rpm {
            cfg.rpm = r;
        }
        cfg.width_mm = (
            args.width_start_mm.unwrap_or(cfg.width_mm.0),
            args.width_end_mm.unwrap_or(cfg.width_mm.1),
        );
        cfg.validate(&model)?;
        Ok(Run::Rig(Box::new(model), cfg))
    } else {
        if let Some(f) = [
            ("--width-start-mm", args.width_start_mm),
            ("--width-end-mm", args.width_end_mm),
        ]
        .iter()
        .find(|f| f.1.is_some())
        {
            anyhow::bail!(
                "{} applies to the calibrated rig (--bearing 6205), not to the phenomenological machine (use --severity-start-db/--severity-end-db)",
                f.0
            );
        }
        let mut cfg = LifeConfig::new(LifeMachine::preset(&args.bearing)?, loc);
        cfg.schedule = schedule;
        if let Some(r) = args.rpm {
            cfg.machine.rpm = r;
        }
        cfg.severity_db = (
            args.severity_start_db.unwrap_or(cfg.severity_db.0),
            args.severity_end_db.unwrap_or(cfg.severity_db.1),
        );
        cfg.validate()?;
        Ok(Run::Machine(cfg))
    }
}

impl Run {
    /// The run's truth (no samples).
    ///
    /// # Errors
    /// The configuration's typed errors.
    pub fn truth(&self, seed: u64) -> anyhow::Result<LifeTruth> {
        Ok(match self {
            Run::Rig(m, c) => rig_life::plan_rig_run(m, c, seed)?.1,
            Run::Machine(c) => life::plan_run(c, seed)?.1,
        })
    }

    /// Recording `index` of the run of `seed`.
    ///
    /// # Errors
    /// The renderer's typed errors.
    pub fn recording(&self, seed: u64, index: usize) -> anyhow::Result<LifeRecording> {
        Ok(match self {
            Run::Rig(m, c) => rig_life::simulate_rig_recording(m, c, seed, index)?,
            Run::Machine(c) => life::simulate_recording(c, seed, index)?,
        })
    }
}

/// The file name of recording `t` in `layout`.
pub fn file_name(layout: Layout, unix_s: i64) -> String {
    match layout {
        Layout::Ims => life::ims_name(unix_s),
        Layout::Csv => {
            // 2026-01-01T00:10:00Z -> 2026-01-01_00-10-00.csv
            let iso = life::iso_timestamp(unix_s);
            format!("{}_{}.csv", &iso[..10], iso[11..19].replace(':', "-"))
        }
    }
}

fn write_ims(path: &Path, x: &[f64]) -> anyhow::Result<()> {
    let f = std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = std::io::BufWriter::new(f);
    for v in x {
        // shortest decimal that reads back to the same f64
        writeln!(w, "{v}")?;
    }
    w.flush()?;
    Ok(())
}

/// Run the task.
pub fn run(args: Args) -> anyhow::Result<()> {
    let lay = args.layout;
    let spec = run_of(&args)?;
    if args.out.exists() {
        anyhow::ensure!(
            args.out.is_dir(),
            "--out {} is not a directory",
            args.out.display()
        );
        let busy = std::fs::read_dir(&args.out)
            .with_context(|| format!("reading {}", args.out.display()))?
            .next()
            .is_some();
        anyhow::ensure!(
            !busy,
            "--out {} is not empty: a run is written into an empty (or new) directory, so no recording of another run can be mistaken for one of this",
            args.out.display()
        );
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let truth = spec.truth(args.seed)?;
    let t0 = std::time::Instant::now();
    let written: Vec<(String, f64, f64)> = (0..truth.recordings.len())
        .into_par_iter()
        .map(|i| -> anyhow::Result<(String, f64, f64)> {
            let rec = spec.recording(args.seed, i)?;
            let rt = &truth.recordings[i];
            let name = file_name(lay, rt.unix_s);
            let path = args.out.join(&name);
            match lay {
                Layout::Ims => write_ims(&path, &rec.samples)?,
                Layout::Csv => {
                    let r = bearing_model::SimulatedRecording {
                        fs_hz: rec.fs_hz,
                        accel: rec.samples.clone(),
                        states: None,
                        step_s: f64::NAN,
                        steps: 0,
                        noise_std: 0.0,
                    };
                    crate::simulate::write_csv(&path, &r)?;
                    let meta = serde_json::json!({
                        "generator": format!("hybrid-fdd simulate-life ({})", truth.generator),
                        "rpm": rec.rpm_declared,
                        "rpm_true": rec.rpm_true,
                        "bearing": truth.bearing,
                        "columns": { "time_s": "s from the recording's start", "accel": format!("acceleration, {}", rec.unit) },
                        "accel_unit": rec.unit,
                        "fs_hz": rec.fs_hz,
                        "samples": rec.samples.len(),
                        "fault": truth.fault_location.name(),
                        "seed": args.seed,
                        "duration_s": truth.schedule.duration_s,
                        "fault_orders": truth.fault_orders,
                        "life": rt,
                        "healthy_rms": rec.healthy_rms,
                        "fault_rms": rec.fault_rms,
                    });
                    let side = path.with_extension("json");
                    std::fs::write(&side, serde_json::to_string_pretty(&meta)?)
                        .with_context(|| format!("writing {}", side.display()))?;
                }
            }
            Ok((name, rec.healthy_rms, rec.fault_rms))
        })
        .collect::<anyhow::Result<_>>()?;
    let wall = t0.elapsed().as_secs_f64();
    let mut value = serde_json::to_value(&truth)?;
    if let Some(list) = value["recordings"].as_array_mut() {
        for (v, (name, h, f)) in list.iter_mut().zip(&written) {
            v["file"] = serde_json::json!(name);
            v["healthy_rms"] = serde_json::json!(h);
            v["fault_rms"] = serde_json::json!(f);
            v["fault_over_healthy_db"] = if *f > 0.0 {
                serde_json::json!(20.0 * (f / h).log10())
            } else {
                serde_json::Value::Null
            };
        }
    }
    value["layout"] = serde_json::json!(match lay {
        Layout::Ims => "ims",
        Layout::Csv => "csv",
    });
    let truth_path = args.out.join("truth.json");
    std::fs::write(&truth_path, serde_json::to_string_pretty(&value)?)
        .with_context(|| format!("writing {}", truth_path.display()))?;
    let on = &truth.recordings[truth.onset_index];
    crate::say!(
        "wrote {} recordings of {} s to {} ({} layout, in {}; {}): {} fault from recording {} ({}), {:.1} s",
        written.len(),
        truth.schedule.duration_s,
        args.out.display(),
        match lay {
            Layout::Ims => "ims",
            Layout::Csv => "csv",
        },
        truth.unit,
        truth.generator,
        truth.fault_location,
        truth.onset_index,
        on.timestamp,
        wall
    );
    crate::say!("truth: {}", truth_path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_names_sort_in_time_order() {
        let a = file_name(Layout::Csv, life::DEFAULT_START_UNIX_S);
        let b = file_name(Layout::Csv, life::DEFAULT_START_UNIX_S + 600);
        assert_eq!(a, "2026-01-01_00-00-00.csv");
        assert!(a < b);
        assert_eq!(file_name(Layout::Ims, 1_076_581_959), "2004.02.12.10.32.39");
    }
}
