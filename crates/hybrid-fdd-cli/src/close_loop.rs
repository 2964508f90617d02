//! `hybrid-fdd close-loop` / `hybrid-fdd calibrate` (and the same `cargo xtask` tasks): run the
//! declared model against a recording, trace the residual to effects the model lacks, add them,
//! and write the ledger (JSON + Markdown + PNG figure); or calibrate a machine model on a healthy
//! recording. The CWRU batch (`cargo xtask close-loop --all-real`) lives in xtask.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context as _, bail};
use bearing_model::FaultClass;
use close_loop::machine::MachineModel;
use close_loop::observe::ArxLaguerreDeclared;
use close_loop::physics::PhysicsModel;
use close_loop::scenario::PhenomenologicalModel;
use close_loop::{
    BearingSpec, DeclaredModel, LoopConfig, OperatingPoint, Outcome, close_loop_from,
};

use crate::flags::{FaultClassParser, SignalFlags};

/// Flags of this task.
#[derive(clap::Args, Debug, Clone)]
// a negative --rpm or --fs gets the range error, not "unexpected argument"
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Recording: a CWRU `.mat` file (named by its number, e.g. `105.mat`), any other MAT-file
    /// (the signal at the top level or inside structs and cells), a one-column `.csv`, or
    /// `hybrid-fdd simulate`'s CSV (its `accel` column is read, fs from `time_s`).
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// How the recording is read and what the loop is told about the machine.
    #[command(flatten)]
    pub common: LoopFlags,
    /// Declared fault: none (also normal, healthy), inner, outer, ball or a combination joined
    /// by `+` (also `-` or `,`; `ir`, `or`, `b` for short; any order and case).
    #[arg(long, default_value = "none", value_parser = FaultClassParser)]
    pub fault: FaultClass,
    /// Use at most this many seconds of the recording (from its start).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Maximum number of effects besides amplitude modulations (at most 2 more, found in the
    /// spectral loop or the envelope phase after it).
    #[arg(long, default_value_t = 8)]
    pub max_effects: usize,
    /// JSON report path (Markdown and PNG are written beside it).
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Start from a calibrated machine model (`hybrid-fdd calibrate` or `cargo xtask
    /// calibrate`) instead of the bare declared model.
    #[arg(long)]
    pub machine: Option<PathBuf>,
    /// Spall width of the declared fault, inches (CWRU sizes 0.007 / 0.014 / 0.021 / 0.028;
    /// a CWRU record's own when omitted).
    #[arg(long)]
    pub fault_size_in: Option<f64>,
}

/// The flags `close-loop` and `calibrate` share, with the same meaning: how the recording is
/// read (channel, rate, units, decimation) and what the loop is told about the machine (speed,
/// bearing, declared model, mains frequency).
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct LoopFlags {
    /// Channel and sampling rate, as `diagnose` reads them.
    #[command(flatten)]
    pub signal: SignalFlags,
    /// Declared shaft speed, rpm (when omitted: a CWRU file's stored speed; the `rpm` of a
    /// `simulate` CSV's JSON sidecar, said on stderr).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Bearing: a designation from the built-in catalogue (`hybrid-fdd bearings` lists them;
    /// case-insensitive, a maker's name and seal or clearance suffixes ignored: `6205`, `uc204`,
    /// `ZA-2115`, `6206-2RS`), a geometry (`n=8,d=0.235in,D=1.245in,angle=0deg`) or the four
    /// shaft-rate multiples (`bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135`, the 6205's), where
    /// `bsf` is CWRU's ball-defect rate = 2 × the ball spin frequency: a textbook BSF must be
    /// doubled (the 6205's textbook BSF is 2.3567). The physics model simulates 6205, 6203 or a
    /// geometry (a catalogue bearing's included), not the multiples alone (`--model
    /// arx-laguerre` or `phenomenological` then). When omitted: a `simulate` CSV's sidecar's
    /// bearing (said on stderr), else 6205.
    #[arg(long)]
    pub bearing: Option<String>,
    /// Declared model.
    #[arg(long, value_enum, default_value_t = DeclaredModelKind::Physics)]
    pub model: DeclaredModelKind,
    /// Units of the recording: g, m/s^2 or unknown (default: g for CWRU .mat files, m/s^2 for
    /// `simulate`'s CSV, unknown otherwise).
    #[arg(long)]
    pub units: Option<String>,
    /// Decimate the recording by this integer factor first (anti-aliased), e.g. 4 for 48 → 12 kHz.
    #[arg(long, default_value_t = 1)]
    pub decimate: usize,
    /// Mains frequency of the rig (a line nearer its multiples than fr's is a tone); 0 = unknown.
    #[arg(long, default_value_t = 60.0)]
    pub line_frequency: f64,
}

impl Default for LoopFlags {
    /// The flags' defaults.
    fn default() -> Self {
        Self {
            signal: SignalFlags::default(),
            rpm: None,
            bearing: None,
            model: DeclaredModelKind::Physics,
            units: None,
            decimate: 1,
            line_frequency: 60.0,
        }
    }
}

/// The declared model `--model` names: what the loop starts from.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeclaredModelKind {
    /// The 5-DOF physics model (a bearing's geometry: 6205, 6203 or `n=…,d=…,D=…`).
    Physics,
    /// ARX-Laguerre, identified on the fitting segment (any bearing).
    ArxLaguerre,
    /// An impact train (any bearing).
    Phenomenological,
}

/// Flags of `hybrid-fdd calibrate` (and `cargo xtask calibrate`).
#[derive(clap::Args, Debug, Clone)]
// a negative --rpm or --fs gets the range error, not "unexpected argument"
#[command(allow_negative_numbers = true)]
pub struct CalibrateArgs {
    /// Healthy recording (`.mat` or text, read as `close-loop --input`).
    #[arg(long)]
    pub input: PathBuf,
    /// As for `close-loop`.
    #[command(flatten)]
    pub common: LoopFlags,
    /// Maximum number of effects.
    #[arg(long, default_value_t = close_loop::machine::CALIBRATE_MAX_EFFECTS)]
    pub max_effects: usize,
    /// Machine model JSON to write (the loop's ledger, Markdown and figure go beside it as
    /// `<out>.report.json|md|png`).
    #[arg(long)]
    pub out: PathBuf,
}

/// `hybrid-fdd calibrate` (and `cargo xtask calibrate`): the loop on a healthy recording from
/// the declared model `--model`, its result saved as a machine model.
pub fn calibrate(a: CalibrateArgs) -> anyhow::Result<()> {
    let t = Instant::now();
    let args = Args {
        input: Some(a.input.clone()),
        common: a.common,
        fault: FaultClass::None,
        seconds: None,
        max_effects: a.max_effects,
        report: Some(report_beside(&a.out)),
        machine: None,
        fault_size_in: None,
    };
    let mut outputs = crate::report_files(&report_beside(&a.out));
    outputs.push(a.out.clone());
    crate::refuse_overwrite("--out", &outputs, &[a.input.as_path()])?;
    let (o, _, _) = calibrate_one(&args)?;
    write_machine(&o, &a.out)?;
    for w in undeclared_fault_warnings(&a.input, &o.ledger) {
        eprintln!("warning: {w}");
    }
    crate::say!(
        "{}: machine model with {} structural mode(s), {} line(s), speed ratio {:.5}; held-out {} {:.3} -> {:.3} dB; {:.2} s -> {}",
        a.input.display(),
        o.machine
            .structural_modes
            .iter()
            .filter(|m| m.frequency_hz > 0.0)
            .count(),
        o.machine.lines.len(),
        o.machine.speed_ratio,
        o.ledger.error_metric,
        o.ledger.error_before,
        o.ledger.error_after,
        t.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}

/// What `calibrate` says on stderr when the loop found a fault on the recording declared
/// healthy: one line per fault location (however many verification passes took it again). The
/// machine model keeps the healthy machine without it.
pub fn undeclared_fault_warnings(input: &Path, ledger: &close_loop::Ledger) -> Vec<String> {
    let mut told: Vec<&str> = Vec::new();
    let mut out = Vec::new();
    for e in &ledger.effects {
        let Some(rate) = e.kinematic_rate.as_deref() else {
            continue;
        };
        if e.kind != close_loop::EffectKind::BearingFault || told.contains(&rate) {
            continue;
        }
        told.push(rate);
        out.push(format!(
            "{}, declared healthy, holds a fault at {rate}: {}; the machine model leaves it out \
             (check the recording with `hybrid-fdd diagnose` before using it as a baseline)",
            input.display(),
            e.description
        ));
    }
    out
}

/// `rig.json` → `rig.report.json`.
pub fn report_beside(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("machine");
    out.with_file_name(format!("{stem}.report.json"))
}

/// Write the outcome's machine model as JSON at `out` (parent directories created).
pub fn write_machine(o: &Outcome, out: &Path) -> anyhow::Result<()> {
    if let Some(parent) = out.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(out, o.machine.to_json()? + "\n")?;
    Ok(())
}

/// Load and validate a machine model file.
pub fn load_machine(path: &Path) -> anyhow::Result<MachineModel> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    Ok(MachineModel::from_json(&text)?)
}

/// Run the task on one recording.
pub fn run(args: Args) -> anyhow::Result<()> {
    let prior = args.machine.as_deref().map(load_machine).transpose()?;
    let t = Instant::now();
    let (o, _, _) = run_one(&args, prior.as_ref())?;
    crate::say!(
        "{}: {} {:.3} dB -> {:.3} dB, {} effect(s): {}; {:.2} s",
        args.input
            .as_deref()
            .map(Path::display)
            .map(|d| d.to_string())
            .unwrap_or_default(),
        o.ledger.error_metric,
        o.ledger.error_before,
        o.ledger.error_after,
        o.ledger.effects.len(),
        effect_list(&o),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The accepted effects in one line for the terminal (kind, order, frequency or ratio, placement).
pub fn effect_list(o: &Outcome) -> String {
    let eff: Vec<String> = o
        .ledger
        .effects
        .iter()
        .map(|e| {
            let p = match e.placement {
                close_loop::Placement::Physics => "P",
                close_loop::Placement::Measurement => "M",
            };
            if let Some(rate) = &e.kinematic_rate {
                return format!(
                    "{} {:.1} Hz at {rate} ({p})",
                    e.kind.as_str(),
                    e.frequency_hz.unwrap_or(f64::NAN)
                );
            }
            if e.kind == close_loop::EffectKind::DefectRate {
                let angle = e
                    .parameters
                    .get("contact_angle_deg")
                    .map_or(String::new(), |a| format!(", contact angle {a:.1} deg"));
                return format!(
                    "{} x{:.4} ({:.4} x fr{angle}) ({p})",
                    e.kind.as_str(),
                    e.parameters.get("ratio").copied().unwrap_or(f64::NAN),
                    e.parameters
                        .get("measured_order")
                        .copied()
                        .unwrap_or(f64::NAN),
                );
            }
            if e.kind == close_loop::EffectKind::ContactPreload {
                let rate = e
                    .parameters
                    .get("defect_rate_ratio")
                    .map_or(String::new(), |q| format!(", defect rate x{q:.4}"));
                return format!(
                    "{} {:.1} um{rate} ({p})",
                    e.kind.as_str(),
                    e.parameters.get("preload_um").copied().unwrap_or(f64::NAN),
                );
            }
            let order = e
                .parameters
                .get("order")
                .map_or(String::new(), |k| format!(" {k}x"));
            match e.frequency_hz {
                Some(f) => format!("{}{order} {:.1} Hz ({p})", e.kind.as_str(), f),
                None => match (e.parameters.get("ratio"), e.parameters.get("fraction")) {
                    (Some(r), _) => format!("{} x{r:.4} ({p})", e.kind.as_str()),
                    (None, Some(f)) => format!("{} {:.2} % ({p})", e.kind.as_str(), 100.0 * f),
                    _ => format!("{} ({p})", e.kind.as_str()),
                },
            }
        })
        .collect();
    if eff.is_empty() {
        "–".to_string()
    } else {
        eff.join("; ")
    }
}

/// The loop on the recording of `args` (from `prior` when given): load, optionally decimate and
/// truncate, build the declared model, run, write the JSON/Markdown/PNG report. Returns the
/// outcome, the sampling rate and the declared speed.
///
/// # Errors
/// Missing `--input`/`--report`/speed, bad units or decimation, a machine model that does not
/// match, or the loop's typed errors.
pub fn run_one(args: &Args, prior: Option<&MachineModel>) -> anyhow::Result<(Outcome, f64, f64)> {
    run_one_as(args, prior, false)
}

/// [`run_one`] as a calibration (no prior machine model): the loop followed by its verification
/// passes from the machine model as saved (`close_loop::machine::calibrate_with`), so that the
/// loop run again from the written model on the same recording adds nothing.
///
/// # Errors
/// As [`run_one`].
pub fn calibrate_one(args: &Args) -> anyhow::Result<(Outcome, f64, f64)> {
    run_one_as(args, None, true)
}

fn run_one_as(
    args: &Args,
    prior: Option<&MachineModel>,
    calibrating: bool,
) -> anyhow::Result<(Outcome, f64, f64)> {
    let input = args.input.as_deref().context("--input is required")?;
    let report = args.report.as_deref().context("--report is required")?;
    let common = &args.common;
    anyhow::ensure!(
        common.line_frequency.is_finite() && common.line_frequency >= 0.0,
        "--line-frequency must be a mains frequency in Hz, or 0 for unknown (got {})",
        common.line_frequency
    );
    let mut read = vec![input];
    read.extend(args.machine.as_deref());
    crate::refuse_overwrite("--report", &crate::report_files(report), &read)?;
    let loaded = crate::diagnose::load(input, &common.signal.channel, common.signal.fs)?;
    let unit = match common.units.as_deref() {
        Some(code) => close_loop::SampleUnit::from_code(code)?,
        None => loaded.unit.clone(),
    };
    let (mut y, mut fs) = (loaded.samples, loaded.fs_hz);
    if common.decimate > 1 {
        y = bearing_data::decimate(&y, common.decimate)?;
        fs /= common.decimate as f64;
    } else if common.decimate == 0 {
        bail!("--decimate must be >= 1");
    }
    if let Some(s) = args.seconds {
        y.truncate((s * fs).round() as usize);
    }
    let (rpm, note) = match loaded.rpm {
        Some(r) => (Some(common.rpm.unwrap_or(r)), None),
        None => crate::diagnose::rpm_or_sidecar(input, common.rpm),
    };
    if let Some(n) = note {
        eprintln!("note: {n}");
    }
    let rpm = rpm.context("--rpm is required (the file stores no speed)")?;
    let (bearing_text, note) =
        crate::diagnose::bearing_or_sidecar(input, common.bearing.as_deref())?;
    if let Some(n) = note {
        eprintln!("note: {n}");
    }
    let builtin = bearing_text.parse::<bearing_model::Bearing>().ok();
    let bearing = match builtin {
        // named by its designation (what machine models compare), echoed as typed
        Some(b) => BearingSpec {
            given: bearing_text.trim().to_string(),
            ..BearingSpec::designated(b)
        },
        None => crate::parse_bearing(&bearing_text)?,
    };
    let fault = args.fault;
    let op = OperatingPoint::new(rpm, bearing, fault)?;
    if let Some(m) = prior {
        m.check_compatible(fs, &op.bearing.name)?;
        m.check_units(&unit.code)?;
    }
    let cfg = LoopConfig {
        max_effects: args.max_effects,
        line_frequency_hz: (common.line_frequency > 0.0).then_some(common.line_frequency),
        ..LoopConfig::default()
    }
    .check()?;
    let model: Box<dyn DeclaredModel> = match common.model {
        DeclaredModelKind::Physics => {
            let m = PhysicsModel::for_bearing(&op.bearing).with_context(|| {
                format!(
                    "the physics model simulates a bearing's geometry (6205, 6203 or n=…,d=…,D=…[,angle=…]), not the four multiples `{}`; use --model arx-laguerre or phenomenological",
                    bearing_text
                )
            })?;
            let size = args
                .fault_size_in
                .or(loaded.fault_size_in)
                .unwrap_or(m.fault_size_in);
            Box::new(PhysicsModel {
                fault_size_in: size,
                ..m
            })
        }
        DeclaredModelKind::Phenomenological => Box::new(PhenomenologicalModel {
            resonance_hz: 3300.0f64.min(0.4 * fs),
            ..PhenomenologicalModel::default()
        }),
        DeclaredModelKind::ArxLaguerre => {
            // identified on the fitting segment only (the held-out part stays unseen)
            let n_fit = close_loop::fit_len(y.len(), &cfg);
            Box::new(ArxLaguerreDeclared::identify(&y[..n_fit])?)
        }
    };
    let recording = close_loop::Signal::new(&y, fs).map_err(close_loop::CloseLoopError::from)?;
    let mut out = if calibrating {
        close_loop::machine::calibrate_with(model.as_ref(), &recording, &op, &cfg)?
    } else {
        close_loop_from(model.as_ref(), prior, &recording, &op, &cfg)?
    };
    if fault == FaultClass::None {
        // a healthy machine model is a diagnosis baseline: it needs a structural path even when
        // the declared model already explained the recording and the loop added none
        let n_fit = close_loop::fit_len(y.len(), &cfg);
        out.machine
            .ensure_path(&y[..n_fit], &y[n_fit..], cfg.get().max_path_order)?;
    }
    out.machine.units = unit.code.clone();
    out.ledger.unit = unit;
    out.machine.provenance.recording = input
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("recording")
        .to_string();
    if let Some(parent) = report.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(report, serde_json::to_string_pretty(&out.ledger)? + "\n")?;
    let title = input
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("recording")
        .to_string();
    std::fs::write(report.with_extension("md"), out.ledger.to_markdown(&title))?;
    crate::figure::close_loop::figure(&out, &report.with_extension("png"), &title)?;
    Ok((out, rpm, fs))
}
