//! `diagnose`: one recording or a directory of them → JSON + Markdown + PNG per recording.

mod args;
mod baseline;
mod batch;
mod classifier;
mod loader;
mod report;
mod text;

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use bearing_data::SampleUnit;
use diagnosis::{BearingSpec, Diagnosis, diagnose};

pub use args::{Args, RecordingFlags};
pub use baseline::{
    BaselineSource, MACHINE_SYNTHESIS_S, MACHINE_SYNTHESIS_SEED, MACHINE_SYNTHESIS_TURNS, Prepared,
    decimated_to,
};
pub use batch::report_names;
pub use classifier::{TrainedClass, apply_classifier, load_classifier};
pub use loader::{
    FsFlag, Loaded, MAT_RATE_TOLERANCE, TIME_RATE_TOLERANCE, TIME_STEP_TOLERANCE,
    bearing_or_sidecar, load, load_with, rpm_or_sidecar, sidecar_bearing, sidecar_rpm,
};
pub use report::{markdown, write_reports};

/// Options shared by every recording of a run.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Channel.
    pub channel: String,
    /// Sampling rate override.
    pub fs: Option<f64>,
    /// Speed override.
    pub rpm: Option<f64>,
    /// Bearing.
    pub bearing: BearingSpec,
}

/// One recording diagnosed: the diagnosis, the baseline note, the unit statement.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The result.
    pub diagnosis: Diagnosis,
    /// How the baseline was used (`None` = self-referenced).
    pub baseline_note: Option<String>,
    /// Unit of the samples.
    pub unit: SampleUnit,
    /// The trained classifier's class, when one was given.
    pub trained: Option<TrainedClass>,
}

/// Diagnose samples already loaded.
///
/// # Errors
/// Missing speed, or the library's typed errors.
pub fn diagnose_loaded(
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
) -> anyhow::Result<Outcome> {
    let rpm = plan
        .rpm
        .or(l.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    let (d, note) = match baseline {
        Some(src) => {
            if let Some(u) = src.machine_units()
                && u != "unknown"
                && !l.unit.is_unknown()
                && u != l.unit.code
            {
                anyhow::bail!(
                    "baseline machine model {} is in {u} but the recording is in {}",
                    src.path.display(),
                    l.unit.code
                );
            }
            let b = src.at(l.fs_hz, rpm)?;
            (
                diagnose(&l.samples, l.fs_hz, rpm, &plan.bearing, Some(&b.0))?,
                Some(b.1.clone()),
            )
        }
        None => (
            diagnose(&l.samples, l.fs_hz, rpm, &plan.bearing, None)?,
            None,
        ),
    };
    Ok(Outcome {
        diagnosis: d,
        baseline_note: note,
        unit: l.unit.clone(),
        trained: None,
    })
}

/// Run `diagnose` with these flags (one file, or a directory in parallel with a progress bar).
///
/// # Errors
/// Missing flags, unreadable files, the library's typed errors (one line each); in a directory
/// batch, any file that failed (after every report and `summary.csv` are written).
pub fn run(args: &Args) -> anyhow::Result<()> {
    let input = args.input.as_deref().context("--input is required")?;
    let report = args.report.as_deref().context("--report is required")?;
    let plan = args.recording.plan()?;
    let baseline = args.recording.baseline_source()?;
    let trained = args
        .classifier
        .as_deref()
        .map(|p| load_classifier(p).map(|t| (t, p)))
        .transpose()?;
    let files = batch::expand(input)?;
    // one recording: its own rate must agree with a --fs; a batch: --fs is for files without one
    let flag = if input.is_dir() {
        FsFlag::ForUnstated
    } else {
        FsFlag::MustAgree
    };
    let one = |path: &Path, out: &Path| -> anyhow::Result<(Outcome, Vec<String>)> {
        let mut notes = Vec::new();
        let l = load_with(path, &plan.channel, plan.fs, flag)?;
        if let Some(f) = plan.fs
            && (l.fs_hz - f).abs() > MAT_RATE_TOLERANCE * f
        {
            notes.push(format!(
                "{}: its own rate {} Hz used (--fs {f} is for files that store no rate)",
                path.display(),
                l.fs_hz
            ));
        }
        let (rpm, note) = if l.rpm.is_none() {
            rpm_or_sidecar(path, plan.rpm)
        } else {
            (plan.rpm, None)
        };
        notes.extend(note);
        let plan = Plan {
            rpm,
            ..plan.clone()
        };
        let mut o = diagnose_loaded(&l, &plan, baseline.as_ref())
            .with_context(|| path.display().to_string())?;
        if let Some((t, p)) = &trained {
            apply_classifier(&mut o, t, p, &l, &plan, baseline.as_ref())
                .with_context(|| path.display().to_string())?;
        }
        let title = path
            .file_name()
            .and_then(|s| s.to_str())
            .unwrap_or("recording");
        write_reports(&o, out, title)?;
        Ok((o, notes))
    };
    let mut read: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    read.extend(args.recording.baseline.as_deref());
    read.extend(args.classifier.as_deref());
    if !input.is_dir() {
        crate::refuse_overwrite("--report", &crate::report_files(report), &read)?;
        let (o, notes) = one(input, report)?;
        for n in notes {
            eprintln!("note: {n}");
        }
        crate::say!(
            "{}: {} ({} reference){} -> {}",
            input.display(),
            o.diagnosis.verdict,
            if o.baseline_note.is_some() {
                "baseline"
            } else {
                "self"
            },
            o.trained.as_ref().map_or(String::new(), |t| format!(
                "; trained classifier: {}",
                t.class
            )),
            report.with_extension("json").display()
        );
        return Ok(());
    }
    batch::run_batch(input, report, &files, &read, &one)
}
