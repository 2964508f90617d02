//! `diagnose`: one recording or a directory of them → JSON + Markdown + PNG per recording.

mod args;
mod baseline;
mod batch;
mod classifier;
mod loader;
mod report;
mod text;
mod tracking;

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use bearing_data::SampleUnit;
use diagnosis::{BearingSpec, DiagnoseOptions, Diagnosis, DiagnosisError};

pub use args::{Args, RecordingFlags};
#[allow(deprecated)]
pub use baseline::Prepared;
pub use baseline::{
    BaselineAtRate, BaselineSource, MACHINE_SYNTHESIS_S, MACHINE_SYNTHESIS_SEED,
    MACHINE_SYNTHESIS_TURNS, decimated_to,
};
pub use batch::{expand, report_names};
pub use classifier::{TrainedClass, apply_classifier, load_classifier};
pub use loader::{
    FsFlag, Loaded, MAT_RATE_TOLERANCE, TIME_RATE_TOLERANCE, TIME_STEP_TOLERANCE,
    bearing_or_sidecar, load, load_with, rpm_or_sidecar, sidecar_bearing, sidecar_rpm,
};
pub use report::{markdown, write_reports};
pub use tracking::order_tracked;

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

/// `--bearing unknown`.
pub const UNKNOWN_BEARING: &str = "unknown";

/// The stand-in bearing of `--bearing unknown` (no geometry, no orders: the diagnosis finds the
/// fault's order itself, `diagnosis::diagnose_unknown_bearing`).
pub fn unknown_bearing() -> BearingSpec {
    BearingSpec {
        name: UNKNOWN_BEARING.into(),
        given: UNKNOWN_BEARING.into(),
        geometry: None,
        orders: bearing_model::FaultOrders {
            ftf: 0.0,
            bpfo: 0.0,
            bpfi: 0.0,
            ball_spin: 0.0,
            ball_defect: 0.0,
        },
    }
}

/// The speed range searched and the false-alarm probability (`--rpm-range`, `--false-alarm`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Search {
    /// Range the running speed is searched in, rpm.
    pub rpm_range: Option<[f64; 2]>,
    /// False-alarm probability per recording.
    pub false_alarm: f64,
    /// Never order-track the recording along its own shaft comb (`--steady-speed`).
    pub steady_speed: bool,
}

impl Default for Search {
    fn default() -> Self {
        Self {
            rpm_range: None,
            false_alarm: diagnosis::DEFAULT_FALSE_ALARM,
            steady_speed: false,
        }
    }
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

/// Diagnose samples already loaded (the speed searched within ± 10 % of the declared one, α at
/// its default).
///
/// # Errors
/// Missing speed, or the library's typed errors.
pub fn diagnose_loaded(
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
) -> anyhow::Result<Outcome> {
    diagnose_loaded_with(l, plan, baseline, &Search::default())
}

/// [`diagnose_loaded`] with a speed range and a false-alarm probability.
///
/// # Errors
/// Missing speed and range, a machine-model baseline without a speed, or the library's typed
/// errors.
pub fn diagnose_loaded_with(
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
    search: &Search,
) -> anyhow::Result<Outcome> {
    let declared = plan.rpm.or(l.rpm);
    let options = match (declared, search.rpm_range) {
        (Some(r), None) => DiagnoseOptions::declared(r),
        (Some(r), Some([lo, hi])) => DiagnoseOptions::declared(r).with_rpm_range(lo, hi),
        (None, Some([lo, hi])) => DiagnoseOptions::search(lo, hi),
        (None, None) => {
            anyhow::bail!("--rpm or --rpm-range is required (the file stores no speed)")
        }
    }
    .with_false_alarm(search.false_alarm);
    let options = if search.steady_speed {
        options.with_steady_speed()
    } else {
        options
    };
    // a machine model is synthesised at a speed: the declared one, else the range's middle
    let rpm = declared.unwrap_or_else(|| {
        let [lo, hi] = search.rpm_range.unwrap_or([0.0, 0.0]);
        0.5 * (lo + hi)
    });
    let unknown = plan.bearing.name == UNKNOWN_BEARING;
    // no samples, a non-finite one or a bad rate: the diagnosis' own one-line error
    let signal = diagnosis::Signal::new(&l.samples, l.fs_hz).map_err(DiagnosisError::from)?;
    let run = |b: Option<&diagnosis::Baseline>| {
        if unknown {
            diagnosis::diagnose_unknown_bearing(&signal, b, &options)
        } else {
            diagnosis::diagnose_with_options(&signal, &plan.bearing, b, &options)
        }
    };
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
            (run(Some(&b.0))?, Some(b.1.clone()))
        }
        None => (run(None)?, None),
    };
    Ok(Outcome {
        diagnosis: d,
        baseline_note: note,
        unit: l.unit.clone(),
        trained: None,
    })
}

/// Read one recording as `diagnose` does before diagnosing it: [`load_with`] (`channel`, `fs`
/// under `flag`), a note when a `fs` given is not the file's own rate, and the speed to declare
/// (`rpm` when given; else, for a file that stores none, its `simulate` sidecar's,
/// [`rpm_or_sidecar`], with a note). Returns the samples, that declared speed (`None`: the
/// file's own [`Loaded::rpm`], if any, is used) and the notes; the command and the Python
/// binding (`python/`) both call it.
///
/// # Errors
/// As [`load_with`].
pub fn read_recording(
    path: &Path,
    channel: &str,
    fs: Option<f64>,
    rpm: Option<f64>,
    flag: FsFlag,
) -> anyhow::Result<(Loaded, Option<f64>, Vec<String>)> {
    let mut notes = Vec::new();
    let l = load_with(path, channel, fs, flag)?;
    if let Some(f) = fs
        && (l.fs_hz - f).abs() > MAT_RATE_TOLERANCE * f
    {
        notes.push(format!(
            "{}: its own rate {} Hz used (--fs {f} is for files that store no rate)",
            path.display(),
            l.fs_hz
        ));
    }
    let (rpm, note) = if l.rpm.is_none() {
        rpm_or_sidecar(path, rpm)
    } else {
        (rpm, None)
    };
    notes.extend(note);
    Ok((l, rpm, notes))
}

/// What [`read_recording_tracked`] returns: the samples (order tracked when a tachometer was
/// given), the speed to declare, the loader's notes and the tracking.
pub type TrackedRead = (
    Loaded,
    Option<f64>,
    Vec<String>,
    Option<residual_features::OrderTracked>,
);

/// [`read_recording`], then — with a tachometer channel of the same file and its pulses a turn
/// (`--tach`, `--pulses-per-rev`) — the recording resampled at equal shaft angles
/// ([`order_tracked`]) and declared at the tachometer's mean speed; the tracking is returned to
/// be set on the diagnosis (`Diagnosis::order_tracking`). The command and the Python binding
/// both call it.
///
/// # Errors
/// As [`read_recording`] and [`order_tracked`].
pub fn read_recording_tracked(
    path: &Path,
    channel: &str,
    tach: Option<(&str, f64)>,
    fs: Option<f64>,
    rpm: Option<f64>,
    flag: FsFlag,
) -> anyhow::Result<TrackedRead> {
    let (l, rpm, notes) = read_recording(path, channel, fs, rpm, flag)?;
    let Some((tach, pulses_per_rev)) = tach else {
        return Ok((l, rpm, notes, None));
    };
    let t = load_with(path, tach, fs, flag)
        .with_context(|| format!("{}: tachometer", path.display()))?;
    let (tracked, summary) =
        order_tracked(&l, &t, pulses_per_rev).with_context(|| path.display().to_string())?;
    Ok((tracked, Some(summary.mean_rpm), notes, Some(summary)))
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
    let search = args.recording.search()?;
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
    if args.tach.is_some() && (args.recording.rpm.is_some() || search.rpm_range.is_some()) {
        anyhow::bail!(
            "--tach measures the speed: leave out --rpm and --rpm-range (the recording is diagnosed at the tachometer's mean speed)"
        );
    }
    if args.tach.is_some() && search.steady_speed {
        anyhow::bail!(
            "--tach with --steady-speed: the tachometer's order tracking is asked for; leave one of them out"
        );
    }
    if args.tach.is_some() && baseline.is_some() {
        anyhow::bail!(
            "--tach with --baseline is not supported: the baseline would need the same order tracking (diagnose the tracked recording self-referenced)"
        );
    }
    let one = |path: &Path, out: &Path| -> anyhow::Result<(Outcome, Vec<String>)> {
        let tach = args.tach.as_deref().map(|c| (c, args.pulses_per_rev));
        let (l, rpm, notes, tracking) =
            read_recording_tracked(path, &plan.channel, tach, plan.fs, plan.rpm, flag)?;
        let plan = Plan {
            rpm,
            ..plan.clone()
        };
        let mut o = diagnose_loaded_with(&l, &plan, baseline.as_ref(), &search)
            .with_context(|| path.display().to_string())?;
        if tracking.is_some() {
            o.diagnosis.order_tracking = tracking;
        }
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
