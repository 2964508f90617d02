//! `train-classifier`: labelled recordings → a classifier trained on the diagnosis evidence
//! (`diagnosis::TrainedDiagnoser`), with its grouped cross-validation.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use diagnosis::{DiagnosisError, Labelled, Reference, TrainedDiagnoser};
use rayon::prelude::*;

use crate::diagnose::{
    BaselineSource, FsFlag, Loaded, Plan, RecordingFlags, decimated_to, diagnose_loaded, load_with,
};

/// Flags of `train-classifier`.
#[derive(clap::Args, Debug, Clone)]
// a negative --rpm or --fs gets the range error, not "unexpected argument"
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// CSV of labelled recordings with a header: columns `file` (path, relative to the CSV) and
    /// `label` (e.g. normal, inner, outer, ball), optional `load_hp` and `rpm` (a row's `rpm`
    /// overrides `--rpm`).
    #[arg(long)]
    pub labels: Option<PathBuf>,
    /// As for `diagnose`; with `--baseline` the classifier takes only diagnoses against a
    /// baseline, without it only self-referenced ones.
    #[command(flatten)]
    pub recording: RecordingFlags,
    /// Seconds per example: each recording is cut into pieces this long (each ≥ 10 shaft turns).
    #[arg(long, default_value_t = 2.5)]
    pub segment_seconds: f64,
    /// The classifier.
    #[arg(long, value_enum, default_value_t = ClassifierKind::Tree)]
    pub model: ClassifierKind,
    /// Where to write the trained classifier (JSON).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// One protocol's result: (accuracy over the test examples in %, per-class text), or why it
/// could not be run.
pub type ProtocolResult = Result<(f64, String), String>;

/// What is known about a labelled recording.
#[derive(Debug, Clone)]
pub struct ExampleMeta {
    /// Known class.
    pub label: String,
    /// Recording id.
    pub recording: String,
    /// Load, hp (0 when unknown).
    pub load_hp: u32,
    /// Fault size, mils, when known.
    pub fault_size_mils: Option<u32>,
}

/// The labelled examples of one recording: its segments of `seconds`, each diagnosed (against
/// `baseline` when given, else self-referenced) and turned into evidence features.
///
/// # Errors
/// Missing speed, or the library's errors on a segment.
pub fn examples(
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
    seconds: f64,
    meta: &ExampleMeta,
) -> anyhow::Result<Vec<Labelled>> {
    let rpm = plan
        .rpm
        .or(l.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    let signal = diagnosis::Signal::new(&l.samples, l.fs_hz).map_err(DiagnosisError::from)?;
    diagnosis::trained::segments(&signal, rpm, seconds)
        .into_iter()
        .map(|seg| {
            let part = Loaded {
                samples: seg.into_samples(),
                ..l.clone()
            };
            let o = diagnose_loaded(&part, plan, baseline)?;
            Ok(Labelled {
                features: o.diagnosis.evidence_features(),
                label: meta.label.clone(),
                recording: meta.recording.clone(),
                load_hp: meta.load_hp,
                fault_size_mils: meta.fault_size_mils,
                speed_rpm: Some(rpm.round() as u32),
            })
        })
        .collect()
}

/// Grouped cross-validation of `spec` on `examples`: (protocol, accuracy over all test
/// examples in % — ACA, eq. 5.37, mean over folds — and per-class accuracies) for four folds of recordings and for leave one load out — no recording is on
/// both sides of a split (a class with a single recording is split in time, and the protocol
/// says so). A protocol the data cannot support gives its reason instead.
pub fn cross_validate(
    examples: &[Labelled],
    spec: &classify::ClassifierSpec,
) -> Vec<(String, ProtocolResult)> {
    let data = match diagnosis::trained::labelled_dataset(examples) {
        Ok(d) => d,
        Err(e) => return vec![("dataset".into(), Err(e.to_string()))],
    };
    let plans = [
        (
            "grouped by recording (4 folds)",
            classify::grouped_by_recording(&data, &classify::GroupedConfig::default()),
        ),
        (
            "leave one load out",
            classify::leave_one_load_out(&data, classify::DegenerateClassPolicy::default()),
        ),
    ];
    plans
        .into_iter()
        .map(|(name, plan)| {
            let r = plan
                .and_then(|p| classify::evaluate(&data, &p, spec))
                .map_err(|e| e.to_string())
                .and_then(|ev| {
                    let avg = ev.average_accuracy().ok_or("no class was tested")?.mean;
                    let per = data
                        .class_names()
                        .iter()
                        .zip(ev.per_class_accuracy())
                        .map(|(c, a)| match a {
                            Some(s) => format!("{c} {:.1}", s.mean),
                            None => format!("{c} –"),
                        })
                        .collect::<Vec<_>>()
                        .join(", ");
                    Ok((avg, per))
                });
            (name.to_string(), r)
        })
        .collect()
}

/// The classifier `--model` names.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClassifierKind {
    /// A Gini decision tree (its rules are readable).
    Tree,
    /// A one-vs-one linear SVM.
    Svm,
}

impl ClassifierKind {
    /// The classifier with its default parameters.
    pub fn spec(self) -> classify::ClassifierSpec {
        match self {
            Self::Tree => classify::ClassifierSpec::tree(),
            Self::Svm => classify::ClassifierSpec::svm(),
        }
    }
}

/// One row of the labels CSV.
struct LabelRow {
    file: PathBuf,
    label: String,
    load_hp: u32,
    rpm: Option<f64>,
}

fn read_labels(path: &Path) -> anyhow::Result<Vec<LabelRow>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("labels {}", path.display()))?;
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<String> = lines
        .next()
        .context("the labels file is empty")?
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    let col = |name: &str| header.iter().position(|h| h == name);
    let (Some(fi), Some(li)) = (col("file"), col("label")) else {
        bail!(
            "labels {}: the header needs columns `file` and `label` (found: {})",
            path.display(),
            header.join(", ")
        );
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    lines
        .enumerate()
        .map(|(i, line)| {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let get = |j: usize| cells.get(j).copied().unwrap_or("");
            let num = |name: &str| -> anyhow::Result<Option<f64>> {
                match col(name).map(get).filter(|s| !s.is_empty()) {
                    Some(s) => Ok(Some(s.parse::<f64>().with_context(|| {
                        format!("labels line {}: {name} {s:?} is not a number", i + 2)
                    })?)),
                    None => Ok(None),
                }
            };
            let (file, label) = (get(fi), get(li));
            if file.is_empty() || label.is_empty() {
                bail!("labels line {}: empty file or label", i + 2);
            }
            Ok(LabelRow {
                file: dir.join(file),
                label: label.to_ascii_lowercase(),
                load_hp: num("load_hp")?.map_or(0, |v| v.round().max(0.0) as u32),
                rpm: num("rpm")?,
            })
        })
        .collect()
}

/// Run `train-classifier`.
///
/// # Errors
/// Missing flags, unreadable files, fewer than two classes, the library's errors.
pub fn run(args: &Args) -> anyhow::Result<()> {
    let labels = args.labels.as_deref().context("--labels is required")?;
    let out = args.out.as_deref().context("--out is required")?;
    let base_plan = args.recording.plan()?;
    if !(args.segment_seconds.is_finite() && args.segment_seconds > 0.0) {
        bail!("--segment-seconds must be > 0");
    }
    let spec = args.model.spec();
    let rows = read_labels(labels)?;
    let baseline = args.recording.baseline_source()?;
    let mut loaded: Vec<Loaded> = rows
        .par_iter()
        .map(|r| {
            load_with(
                &r.file,
                &base_plan.channel,
                base_plan.fs,
                FsFlag::ForUnstated,
            )
        })
        .collect::<anyhow::Result<_>>()?;
    // one rate: the lowest; recordings at an integer multiple of it are decimated (as a
    // baseline is), any other rate is refused
    let fs = loaded.iter().map(|l| l.fs_hz).fold(f64::INFINITY, f64::min);
    let mut decimated = 0usize;
    for (l, r) in loaded.iter_mut().zip(&rows) {
        if (l.fs_hz - fs).abs() > 1e-9 * fs {
            let Some((x, _)) = decimated_to(&l.samples, l.fs_hz, fs)? else {
                bail!(
                    "{}: {} Hz is not an integer multiple of {fs} Hz, the lowest rate among the labelled recordings: resample it",
                    r.file.display(),
                    l.fs_hz
                );
            };
            l.samples = x;
            l.fs_hz = fs;
            decimated += 1;
        }
    }
    let bar = indicatif::ProgressBar::new(rows.len() as u64);
    let per: Vec<Vec<Labelled>> = rows
        .par_iter()
        .zip(&loaded)
        .map(|(r, l)| -> anyhow::Result<Vec<Labelled>> {
            let plan = Plan {
                rpm: r.rpm.or(base_plan.rpm),
                ..base_plan.clone()
            };
            let meta = ExampleMeta {
                label: r.label.clone(),
                recording: r.file.display().to_string(),
                load_hp: r.load_hp,
                fault_size_mils: l.fault_size_in.map(|d| (d * 1000.0).round() as u32),
            };
            let ex = examples(l, &plan, baseline.as_ref(), args.segment_seconds, &meta)
                .with_context(|| r.file.display().to_string());
            bar.inc(1);
            ex
        })
        .collect::<anyhow::Result<_>>()?;
    bar.finish_and_clear();
    let all: Vec<Labelled> = per.into_iter().flatten().collect();
    let reference = if baseline.is_some() {
        Reference::Baseline
    } else {
        Reference::SelfReference
    };
    let t = TrainedDiagnoser::train(&all, reference, fs, args.segment_seconds, &spec)?;
    if decimated > 0 {
        crate::say!("{decimated} recordings decimated to {fs} Hz (bearing-data anti-aliasing FIR)");
    }
    if let Some(parent) = out.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(out, t.to_json()? + "\n")?;
    crate::say!(
        "{}: {} on {} examples ({} s each) from {} recordings, classes {}",
        out.display(),
        t.classifier,
        t.examples,
        args.segment_seconds,
        t.recordings,
        t.classes.join(", ")
    );
    for (name, r) in cross_validate(&all, &spec) {
        match r {
            Ok((avg, per)) => crate::say!("  {name}: accuracy {avg:.1} % of test examples ({per})"),
            Err(e) => crate::say!("  {name}: not evaluated ({e})"),
        }
    }
    Ok(())
}
