//! `diagnose`: one recording or a directory of them → JSON + Markdown + PNG per recording.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{Context as _, bail};
use bearing_data::SampleUnit;
use diagnosis::{Baseline, BearingSpec, Diagnosis, diagnose};
use rayon::prelude::*;

/// Flags of `diagnose`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Args {
    /// Recording: a CWRU `.mat` file (named by its number, e.g. `130.mat`), any other MAT-file
    /// (v5–v7, the signal at the top level or inside structs and cells: MFPT's `bearing.gs`,
    /// Paderborn's `X.Y(k).Data`), a delimited text file (`.csv`, `.tsv`, `.txt`, or any name
    /// whose content is text, such as IMS's date-named files), or a directory: every
    /// `.mat`/`.csv`/`.tsv` in it (and every MAT or text file named without an extension or with
    /// an all-digit one, as IMS's) is diagnosed, in parallel, one report per file (named by its
    /// stem; by stem and extension, `x_csv.json`, when two files share a stem)
    /// and `summary.csv` listing each file's report; the exit status is non-zero when any file
    /// failed (after all reports and the summary are written).
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// How the recordings are read and what machine they come from.
    #[command(flatten)]
    pub recording: RecordingFlags,
    /// JSON report path (Markdown and PNG beside it); with a directory input, an output directory.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Optional trained classifier (`hybrid-fdd train-classifier`'s JSON): its class is added
    /// to the report under `"classifier"` beside the training-free verdict.
    #[arg(long)]
    pub classifier: Option<PathBuf>,
}

/// The flags `diagnose` and `train-classifier` share: channel, rate, speed, bearing, baseline.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RecordingFlags {
    /// Channel: of a CWRU `.mat` file DE, FE or BA; of another MAT-file a variable path
    /// (`bearing.gs`), a struct element's `Name` (`vibration_1`) or a last path component, by
    /// default its only vector of at least 1024 samples; of a text file a column name or number
    /// (1 = first; by default `accel`, the only column, or the second of `time,signal`).
    #[arg(long, default_value = "DE")]
    pub channel: String,
    /// Sampling rate, Hz, of recordings that store none (a text file without a time column, a
    /// MAT-file without a scalar `fs`, `sr`, `sample_rate` or `sampling_rate` beside its signal).
    /// A CWRU `.mat` file's rate, a stored rate and a time column's always win: for a single file, a `--fs` more than 0.1 % (`.mat`) or 1 % (time column)
    /// away from it is an error; in a directory batch (and `train-classifier`'s labelled list)
    /// `--fs` applies only to the files that store no rate.
    #[arg(long)]
    pub fs: Option<f64>,
    /// Shaft speed, rpm (when omitted: a CWRU file's stored speed, else its nominal one; the
    /// `rpm` of a `simulate` CSV's JSON sidecar, said on stderr).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Bearing: `6205`, `6203`, a geometry `n=9,d=0.3126in,D=1.537in,angle=0deg` or the four
    /// shaft-rate multiples `bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135` (the 6205's). There
    /// `bsf` is CWRU's ball-defect rate = 2 × the ball spin frequency: a textbook BSF must be
    /// doubled (the 6205's textbook BSF is 2.3567; CWRU's `bsf` is 4.7135).
    #[arg(long)]
    pub bearing: Option<String>,
    /// Healthy recording of the same machine (same formats; resampled by an integer factor
    /// with an anti-aliasing FIR when its rate is a multiple of the recording's), or a machine
    /// model JSON from `hybrid-fdd calibrate` (or `cargo xtask calibrate`; its structural path is
    /// the healthy model; same sampling rate and units as the recording). A text baseline
    /// without a time column is taken at `--fs`; a `.mat` baseline or one with a time column at
    /// its own rate. Without a baseline the evidence is self-referenced.
    #[arg(long)]
    pub baseline: Option<PathBuf>,
}

impl RecordingFlags {
    /// The plan these flags give (the bearing is required).
    ///
    /// # Errors
    /// A missing or unparsable `--bearing`.
    pub fn plan(&self) -> anyhow::Result<Plan> {
        let spec = self
            .bearing
            .as_deref()
            .context("--bearing is required (6205, 6203, a geometry or the four multiples)")?;
        Ok(Plan {
            channel: self.channel.clone(),
            fs: self.fs,
            rpm: self.rpm,
            bearing: crate::parse_bearing(spec)?,
        })
    }

    /// The baseline, when `--baseline` is given.
    ///
    /// # Errors
    /// An unreadable baseline.
    pub fn baseline_source(&self) -> anyhow::Result<Option<BaselineSource>> {
        self.baseline
            .as_deref()
            .map(|p| BaselineSource::load(p, &self.channel, self.fs))
            .transpose()
    }
}

/// A loaded recording.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// Samples of the chosen channel.
    pub samples: Vec<f64>,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Speed stored in (or catalogued for) the file, rpm.
    pub rpm: Option<f64>,
    /// Unit of the samples, as far as known (its code, "g", "m/s^2" or "unknown", and the
    /// statement reports print).
    pub unit: SampleUnit,
    /// Catalogued fault diameter, inches, for a CWRU record.
    pub fault_size_in: Option<f64>,
}

/// How a `--fs` meets a rate the file itself stores (a CWRU record's, a time column's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FsFlag {
    /// One recording: the file's own rate is used, and a `--fs` that disagrees with it (by more
    /// than [`MAT_RATE_TOLERANCE`] or [`TIME_RATE_TOLERANCE`]) is an error.
    MustAgree,
    /// A directory batch, a labelled list or a baseline: `--fs` is the rate of the files that
    /// store none; a file's own rate is used without comparison.
    ForUnstated,
}

/// Largest relative difference between `--fs` and a CWRU record's rate.
pub const MAT_RATE_TOLERANCE: f64 = 1e-3;
/// Largest relative difference between `--fs` and the rate of a time column.
pub const TIME_RATE_TOLERANCE: f64 = 1e-2;
/// Largest relative deviation of one time step from the median step.
pub const TIME_STEP_TOLERANCE: f64 = 1e-2;

/// The rate of a file: its stored rate `stored` (described by `what`) when it has one, else
/// `fs`; under [`FsFlag::MustAgree`] a `fs` more than `tolerance` (relative) from the stored
/// rate is an error.
fn resolve_rate(
    path: &Path,
    fs: Option<f64>,
    stored: Option<f64>,
    tolerance: f64,
    what: &str,
    flag: FsFlag,
) -> anyhow::Result<Option<f64>> {
    match (stored, fs) {
        // a NaN --fs disagrees too
        (Some(s), Some(f))
            if flag == FsFlag::MustAgree && ((f - s).abs() > tolerance * s || f.is_nan()) =>
        {
            bail!(
                "{}: --fs {f} Hz disagrees with {what} ({s} Hz, tolerance {} %): omit --fs",
                path.display(),
                100.0 * tolerance
            )
        }
        (Some(s), _) => Ok(Some(s)),
        (None, f) => Ok(f),
    }
}

/// Load one channel of a `.mat` (CWRU record or CWRU-style variables) or one column of a
/// delimited text file (`,`, `;` or tab; `hybrid-fdd simulate`'s CSV: its `accel` column, fs
/// from `time_s`), as one recording: a `--fs` that disagrees with the file's own rate is an
/// error ([`load_with`] and [`FsFlag::MustAgree`]).
/// The one recording loader of the command-line tools (`hybrid-fdd`, `cargo xtask`).
///
/// # Errors
/// Unreadable files, unknown channel or extension, missing `--fs` where the file has no rate,
/// a `--fs` that disagrees with the file's rate, a time column that is not increasing and
/// evenly spaced.
pub fn load(path: &Path, channel: &str, fs: Option<f64>) -> anyhow::Result<Loaded> {
    load_with(path, channel, fs, FsFlag::MustAgree)
}

/// [`load`] with the rule `flag` for a `fs` where the file stores its own rate.
///
/// # Errors
/// As [`load`].
pub fn load_with(
    path: &Path,
    channel: &str,
    fs: Option<f64>,
    flag: FsFlag,
) -> anyhow::Result<Loaded> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let kind = match ext.as_str() {
        "mat" => "mat",
        "csv" | "txt" | "tsv" => "text",
        // no or another extension (IMS names its files by date, `2004.02.12.10.32.39`): what
        // the first bytes are
        _ => sniff(path)?,
    };
    match kind {
        "mat" => {
            let bytes =
                std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
            let end = match channel.to_ascii_uppercase().as_str() {
                "DE" => Some(bearing_data::SensorEnd::DriveEnd),
                "FE" => Some(bearing_data::SensorEnd::FanEnd),
                "BA" => Some(bearing_data::SensorEnd::Base),
                _ => None,
            };
            let number = path
                .file_stem()
                .and_then(|s| s.to_str())
                .and_then(|s| s.parse::<u32>().ok());
            if let (Some(number), Some(end)) = (number, end)
                && let Ok(rec) = bearing_data::parse_record(&bytes, number)
            {
                let fs_hz = resolve_rate(
                    path,
                    fs,
                    Some(rec.fs_hz()),
                    MAT_RATE_TOLERANCE,
                    "the CWRU record's rate",
                    flag,
                )?
                .unwrap_or(rec.fs_hz());
                let x = rec
                    .channel(end)
                    .with_context(|| format!("{} has no {channel} channel", path.display()))?
                    .to_vec();
                return Ok(Loaded {
                    samples: x,
                    fs_hz,
                    rpm: Some(rec.rpm().value),
                    unit: SampleUnit::cwru(),
                    fault_size_in: bearing_data::entry(number).and_then(|e| e.fault_diameter_in()),
                });
            }
            // CWRU-style variables (`X###_DE_time`) in a file of another name
            if let Some(end) = end
                && let Ok(set) = bearing_data::read_variable_sets(&bytes)
                    .and_then(|sets| bearing_data::select_set(sets, None))
            {
                let x = set
                    .channel(end)
                    .with_context(|| format!("{} has no {channel} channel", path.display()))?
                    .to_vec();
                let fs = fs.with_context(|| {
                    format!(
                        "{}: --fs is required for a .mat file that is not a CWRU record",
                        path.display()
                    )
                })?;
                return Ok(Loaded {
                    samples: x,
                    fs_hz: fs,
                    rpm: set.rpm,
                    // CWRU-style variables of another file: the CWRU statement, no unit claimed
                    unit: SampleUnit {
                        code: "unknown".into(),
                        ..SampleUnit::cwru()
                    },
                    fault_size_in: None,
                });
            }
            load_generic_mat(path, &bytes, channel, end.is_some(), fs, flag)
        }
        _ => load_csv(path, channel, fs, flag),
    }
}

/// What a file without a known extension holds: `"mat"` for a MATLAB MAT-file header, `"text"`
/// for UTF-8 text; anything else is an error.
fn sniff(path: &Path) -> anyhow::Result<&'static str> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .with_context(|| format!("reading {}", path.display()))?;
    if head.starts_with(b"MATLAB") {
        return Ok("mat");
    }
    // a cut in the middle of a multi-byte character at the 4096th byte is still text
    let valid = match std::str::from_utf8(&head) {
        Ok(_) => true,
        Err(e) => e.error_len().is_none(),
    };
    if valid && !head.is_empty() && !head.contains(&0) {
        return Ok("text");
    }
    bail!(
        "{}: neither a MAT-file nor text (extensions read: .mat, .csv, .tsv, .txt; other names are read by content)",
        path.display()
    )
}

/// Any other MAT-file (v5–v7, structs, struct arrays, cells; `bearing_data::read_mat_tree`): the
/// signal named by `channel` (a path such as `bearing.gs`, a struct element's `Name` such as
/// `vibration_1`, or a last path component); with the default channel (`DE`, `FE`, `BA`, which
/// only a CWRU file has), the only real vector of at least 1024 samples. The rate stored beside
/// the signal (`fs`, `sr`, `sample_rate`, …) wins over `--fs` as a CWRU record's does; a scalar
/// `rpm` beside it is the speed.
///
/// # Errors
/// The file's structure, no or several fitting signals (listed), no rate stored and no `--fs`,
/// a `--fs` that disagrees with the stored rate.
fn load_generic_mat(
    path: &Path,
    bytes: &[u8],
    channel: &str,
    cwru_channel: bool,
    fs: Option<f64>,
    flag: FsFlag,
) -> anyhow::Result<Loaded> {
    let name = path.display();
    let leaves = bearing_data::read_mat_tree(bytes).with_context(|| name.to_string())?;
    let signal = match bearing_data::select_signal(&leaves, Some(channel)) {
        Ok(s) => s,
        // `DE` (the default), `FE` or `BA` of a file that is not CWRU's: the only signal
        Err(_) if cwru_channel => {
            let s = bearing_data::select_signal(&leaves, None).with_context(|| {
                format!("{name}: not a CWRU file, so --channel {channel} names nothing")
            })?;
            eprintln!(
                "{name}: not a CWRU file; took its only signal `{}`{}",
                s.path,
                s.alias
                    .as_ref()
                    .map_or(String::new(), |a| format!(" ({a})"))
            );
            s
        }
        Err(e) => return Err(anyhow::Error::new(e).context(name.to_string())),
    };
    let stored = bearing_data::sampling_rate_near(&leaves, &signal.path);
    let fs_hz = resolve_rate(
        path,
        fs,
        stored,
        MAT_RATE_TOLERANCE,
        "the sampling rate stored in the file",
        flag,
    )?
    .with_context(|| {
        format!(
            "{name}: the file stores no sampling rate (a scalar fs, sr, sample_rate or sampling_rate); give --fs"
        )
    })?;
    let parent = signal.path.rsplit_once('.').map_or("", |(p, _)| p);
    let rpm = leaves
        .iter()
        .filter(|l| l.last_name().eq_ignore_ascii_case("rpm") && l.parent() == parent)
        .find_map(|l| l.scalar().filter(|v| v.is_finite() && *v > 0.0));
    if let Some((i, _)) = signal
        .samples
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
    {
        bail!("{name}: sample {i} of `{}` is not finite", signal.path);
    }
    Ok(Loaded {
        samples: signal.samples,
        fs_hz,
        rpm,
        unit: SampleUnit {
            code: "unknown".into(),
            statement: format!("MAT-file `{}` (unit not stated in the file)", signal.path),
        },
        fault_size_in: None,
    })
}

/// Time-column names read as seconds.
const TIME_NAMES: [&str; 5] = ["time_s", "time", "t", "seconds", "s"];

/// A text field without its surrounding blanks and double quotes.
fn unquote(f: &str) -> &str {
    let f = f.trim();
    f.strip_prefix('"')
        .and_then(|g| g.strip_suffix('"'))
        .map_or(f, str::trim)
}

/// The sampling rate of a time column in seconds, `stamps` as (line number, value): strictly
/// increasing, every step within [`TIME_STEP_TOLERANCE`] of the median step; the rate over the
/// whole span, snapped to a whole Hz when within 1 ppm of one (`simulate` prints its stamps
/// to 1 ns).
///
/// # Errors
/// Fewer than two stamps, a non-finite, decreasing, repeated or unevenly spaced stamp (the
/// first offending line named).
fn time_column_rate(path: &Path, column: &str, stamps: &[(usize, f64)]) -> anyhow::Result<f64> {
    let name = path.display();
    if let Some((line, t)) = stamps.iter().find(|(_, t)| !t.is_finite()) {
        bail!("{name}: line {line}: time `{column}` = {t} is not finite");
    }
    if stamps.len() < 2 {
        bail!("{name}: the time column `{column}` has fewer than two stamps; give --fs");
    }
    let steps: Vec<(usize, f64)> = stamps
        .windows(2)
        .map(|w| (w[1].0, w[1].1 - w[0].1))
        .collect();
    if let Some((line, dt)) = steps.iter().find(|(_, dt)| *dt <= 0.0) {
        bail!(
            "{name}: the time column `{column}` is not strictly increasing at line {line} (step {dt:.4e} s)"
        );
    }
    let mut sorted: Vec<f64> = steps.iter().map(|s| s.1).collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    if let Some((line, dt)) = steps
        .iter()
        .find(|(_, dt)| (dt - median).abs() > TIME_STEP_TOLERANCE * median)
    {
        bail!(
            "{name}: the time column `{column}` is not evenly spaced: the step to line {line} is {dt:.4e} s, the median step {median:.4e} s (more than {} % apart)",
            100.0 * TIME_STEP_TOLERANCE
        );
    }
    let (a, b) = (stamps[0].1, stamps[stamps.len() - 1].1);
    let f = (stamps.len() - 1) as f64 / (b - a);
    let whole = f.round();
    Ok(if (f - whole).abs() <= 1e-6 * f {
        whole
    } else {
        f
    })
}

/// A CSV reading error of `bearing-data` restated for the user: the file named, columns
/// numbered from 1 (as `--channel`), lines as in the file; `lines` are the file's data lines
/// (line number, text) in order.
fn csv_error(
    path: &Path,
    e: bearing_data::DataError,
    names: &[String],
    signal: usize,
    lines: &[(usize, &str)],
) -> anyhow::Error {
    let name = path.display();
    let col = |c: usize| match names.get(c) {
        Some(n) if !n.starts_with("column ") => format!("column {} (`{n}`)", c + 1),
        _ => format!("column {}", c + 1),
    };
    match e {
        bearing_data::DataError::NonFinite { index, .. } => match lines.get(index) {
            Some((line, _)) => anyhow::anyhow!(
                "{name}: line {line}, {}: non-finite sample (NaN or infinity)",
                col(signal)
            ),
            None => anyhow::anyhow!(
                "{name}: data row {}, {}: non-finite sample (NaN or infinity)",
                index + 1,
                col(signal)
            ),
        },
        bearing_data::DataError::CsvNotANumber { line, column, text } => {
            anyhow::anyhow!(
                "{name}: line {line}, {}: {text:?} is not a number",
                col(column)
            )
        }
        bearing_data::DataError::CsvMissingField {
            line,
            fields,
            column,
        } => anyhow::anyhow!(
            "{name}: line {line} has {fields} field(s), no {}",
            col(column)
        ),
        other => anyhow::Error::new(other).context(name.to_string()),
    }
}

/// A delimited text recording: a UTF-8 byte-order mark dropped, the delimiter sniffed from the
/// first data line (tab, `;` or `,`), header names and fields without surrounding double
/// quotes; the column by `channel` (a header name, case-insensitive, or a 1-based number), else
/// `accel` (`simulate`'s CSV), else the only column, else the second of two when the first is
/// time; the rate from a time column in seconds (checked, [`time_column_rate`]), else `fs`.
fn load_csv(path: &Path, channel: &str, fs: Option<f64>, flag: FsFlag) -> anyhow::Result<Loaded> {
    let raw =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let text = raw.strip_prefix('\u{feff}').unwrap_or(&raw);
    let content: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .collect();
    let first = content.first().map_or("", |c| c.1);
    let delimiter = if first.contains('\t') {
        b'\t'
    } else if first.contains(';') {
        b';'
    } else {
        b','
    };
    let split = |l: &str| -> Vec<String> {
        l.split(char::from(delimiter))
            .map(|f| unquote(f).to_string())
            .collect()
    };
    let fields = split(first);
    let has_header = fields.iter().any(|f| f.parse::<f64>().is_err());
    let names: Vec<String> = if has_header {
        fields.iter().map(|f| f.to_ascii_lowercase()).collect()
    } else {
        (1..=fields.len()).map(|i| format!("column {i}")).collect()
    };
    let data = &content[usize::from(has_header).min(content.len())..];
    let listed = || names.join(", ");
    let time_col = (names.len() >= 2 && TIME_NAMES.contains(&names[0].as_str())).then_some(0);
    let want = channel.trim();
    let col = if !want.is_empty() && !want.eq_ignore_ascii_case("DE") {
        if let Some(i) = names.iter().position(|n| n.eq_ignore_ascii_case(want)) {
            i
        } else if let Ok(k) = want.parse::<usize>()
            && (1..=names.len()).contains(&k)
        {
            k - 1
        } else {
            bail!(
                "{}: no column `{want}` (columns: {}; give a name or a number, 1 = first)",
                path.display(),
                listed()
            )
        }
    } else if let Some(i) = names.iter().position(|n| n == "accel") {
        i
    } else if names.len() == 1 {
        0
    } else if names.len() == 2 && time_col.is_some() {
        1
    } else {
        bail!(
            "{}: {} columns ({}); choose the signal with --channel NAME or NUMBER",
            path.display(),
            names.len(),
            listed()
        )
    };
    let stored = match time_col.filter(|&t| t != col) {
        Some(t) => {
            let stamps = data
                .iter()
                .map(|&(line, l)| {
                    let f = split(l);
                    let v = f.get(t).with_context(|| {
                        format!(
                            "{}: line {line} has no `{}` field",
                            path.display(),
                            names[t]
                        )
                    })?;
                    let v: f64 = v.parse().map_err(|_| {
                        anyhow::anyhow!(
                            "{}: line {line}: time `{}` = {v:?} is not a number",
                            path.display(),
                            names[t]
                        )
                    })?;
                    Ok((line, v))
                })
                .collect::<anyhow::Result<Vec<_>>>()?;
            Some(time_column_rate(path, &names[t], &stamps)?)
        }
        None => None,
    };
    let what = format!("the rate of its time column `{}`", names[0]);
    let fs =
        resolve_rate(path, fs, stored, TIME_RATE_TOLERANCE, &what, flag)?.with_context(|| {
            format!(
                "{}: --fs is required for a text recording without a time column ({})",
                path.display(),
                TIME_NAMES.join(", ")
            )
        })?;
    let mut opts = bearing_data::CsvOptions::new(fs, bearing_data::Column::Index(col));
    opts.delimiter = delimiter;
    opts.header = if has_header {
        bearing_data::HeaderRow::Present
    } else {
        bearing_data::HeaderRow::Absent
    };
    let sig = bearing_data::read_csv(text.as_bytes(), &opts)
        .map_err(|e| csv_error(path, e, &names, col, data))?;
    // `simulate` states the unit of `accel` in its JSON sidecar (g for the calibrated rig, m/s²
    // for the 5-DOF parameter sets); a column named `accel` without that sidecar is any
    // logger's, whose unit the file does not state
    let side_unit = (names[col] == "accel")
        .then(|| sidecar(path))
        .flatten()
        .and_then(|v| v["accel_unit"].as_str().map(str::to_string));
    let unit = match side_unit.as_deref() {
        Some("g") => SampleUnit::stated("g", "g (`simulate` output, calibrated CWRU rig)")?,
        Some("m/s^2") => SampleUnit::stated("m/s^2", "m/s² (`simulate` output)")?,
        _ => SampleUnit::stated("unknown", "CSV units (not stated in the file)")?,
    };
    Ok(Loaded {
        samples: sig.into_samples(),
        fs_hz: fs,
        rpm: None,
        unit,
        fault_size_in: None,
    })
}

/// The JSON sidecar of a text recording (`x.csv` → `x.json`), when it exists and parses.
fn sidecar(path: &Path) -> Option<serde_json::Value> {
    let text = std::fs::read_to_string(path.with_extension("json")).ok()?;
    serde_json::from_str(&text).ok()
}

/// The shaft speed a `simulate` sidecar records (its `rpm`), for a text recording; `None` for
/// other files and sidecars without one.
pub fn sidecar_rpm(path: &Path) -> Option<f64> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    if !matches!(ext.as_str(), "csv" | "tsv" | "txt") {
        return None;
    }
    let v = sidecar(path)?;
    let from_simulate = v["generator"]
        .as_str()
        .is_some_and(|g| g.contains("simulate"));
    v["rpm"]
        .as_f64()
        .filter(|r| from_simulate && r.is_finite() && *r > 0.0)
}

/// The speed to use for `path`: `rpm` when given, else its `simulate` sidecar's
/// ([`sidecar_rpm`]), with a note saying so.
pub fn rpm_or_sidecar(path: &Path, rpm: Option<f64>) -> (Option<f64>, Option<String>) {
    match rpm {
        Some(r) => (Some(r), None),
        None => match sidecar_rpm(path) {
            Some(r) => (
                Some(r),
                Some(format!(
                    "{}: --rpm {r} from its simulate sidecar {}",
                    path.display(),
                    path.with_extension("json").display()
                )),
            ),
            None => (None, None),
        },
    }
}

/// A prepared baseline and a note saying how it was made (rate, decimation).
pub type Prepared = Arc<(Baseline, String)>;

/// A healthy baseline: a recording's samples, prepared on demand for each recording rate it is
/// asked for, or a calibrated machine model (`hybrid-fdd calibrate`), whose structural path is
/// the healthy model.
#[derive(Debug)]
pub struct BaselineSource {
    /// Where it came from.
    pub path: PathBuf,
    samples: Vec<f64>,
    fs_hz: f64,
    machine: Option<Box<close_loop::machine::MachineModel>>,
    prepared: Mutex<Vec<(u64, Prepared)>>,
}

impl BaselineSource {
    /// Load a baseline file: a recording (as [`load_with`] under [`FsFlag::ForUnstated`]: a
    /// text file without a time column at `fs`, the recording's `--fs`; a `.mat` file or a
    /// time column at its own rate), or a machine model JSON (`.json`, validated by
    /// `close_loop::machine::MachineModel::from_json`).
    ///
    /// # Errors
    /// As [`load`], or the machine model's typed format errors.
    pub fn load(path: &Path, channel: &str, fs: Option<f64>) -> anyhow::Result<Self> {
        if path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading baseline {}", path.display()))?;
            let m = close_loop::machine::MachineModel::from_json(&text)
                .with_context(|| format!("baseline machine model {}", path.display()))?;
            return Ok(Self::from_machine(path, m));
        }
        // the loader's errors name the file
        let l = load_with(path, channel, fs, FsFlag::ForUnstated).context("baseline")?;
        Ok(Self::from_samples(path, l.samples, l.fs_hz))
    }

    /// A baseline from a machine model already in memory (`path` names it in reports).
    pub fn from_machine(path: &Path, m: close_loop::machine::MachineModel) -> Self {
        Self {
            path: path.to_path_buf(),
            samples: Vec::new(),
            fs_hz: m.fs_hz,
            machine: Some(Box::new(m)),
            prepared: Mutex::new(Vec::new()),
        }
    }

    /// A baseline from samples already in memory.
    pub fn from_samples(path: &Path, samples: Vec<f64>, fs_hz: f64) -> Self {
        Self {
            path: path.to_path_buf(),
            samples,
            fs_hz,
            machine: None,
            prepared: Mutex::new(Vec::new()),
        }
    }

    /// The units a machine-model baseline was calibrated in ("g", "m/s^2", "unknown"); `None`
    /// for a recording baseline.
    pub fn machine_units(&self) -> Option<&str> {
        self.machine.as_deref().map(|m| m.units.as_str())
    }

    /// The baseline from a machine model: the prediction-error filter of the whole model's
    /// one-step predictor (structural path, floor and lines,
    /// `close_loop::machine::MachineModel::predictor_path`) and the residual statistics measured
    /// through it when it was calibrated; for a model written before those statistics existed,
    /// the path's own filter and statistics. The rate is the model's (the library reports a
    /// recording at another rate as its typed mismatch error).
    fn prepare_machine(&self, m: &close_loop::machine::MachineModel) -> anyhow::Result<Prepared> {
        let name = self.path.display();
        let path = m.path.as_ref().with_context(|| {
            format!("baseline machine model {name} holds no structural path to whiten with")
        })?;
        let (ar, rms, kurt, what) = match (m.predictor_residual_rms, m.predictor_residual_kurtosis)
        {
            (Some(rms), Some(kurt)) => {
                let p = m
                    .predictor_path()
                    .with_context(|| format!("baseline machine model {name}"))?;
                let what = format!(
                    "the whole model (structural path of AR order {} and {} lines) as the healthy model, its one-step predictor of AR order {}",
                    path.ar.len(),
                    m.lines.len(),
                    p.ar.len()
                );
                (p.ar, rms, kurt, what)
            }
            _ => {
                let (Some(rms), Some(kurt)) = (m.path_residual_rms, m.path_residual_kurtosis)
                else {
                    anyhow::bail!(
                        "baseline machine model {name} has no path residual statistics (written by an older version): recalibrate it with `hybrid-fdd calibrate` (or `cargo xtask calibrate`)"
                    );
                };
                let what = format!(
                    "structural path of AR order {} as the healthy model (a model written before the whole model's residual statistics)",
                    path.ar.len()
                );
                (path.ar.clone(), rms, kurt, what)
            }
        };
        let w = diagnosis::ArWhitener::from_coefficients(
            ar.iter().map(|a| -a).collect(),
            m.fs_hz,
            "baseline machine model",
        )?;
        let samples = m.provenance.fit_samples[1];
        let b = Baseline::from_whitener(w, rms, kurt, samples)?;
        let note = format!(
            "machine model {name} (calibrated on {}, {} Hz, units {}): {what}",
            if m.provenance.recording.is_empty() {
                "an unnamed recording"
            } else {
                m.provenance.recording.as_str()
            },
            m.fs_hz,
            m.units,
        );
        Ok(Arc::new((b, note)))
    }

    /// The baseline prepared at `fs_hz` (decimated by an integer factor when needed) and a note
    /// saying how; prepared once per rate.
    ///
    /// # Errors
    /// A rate that is neither equal nor an integer fraction of the baseline's (the library's
    /// typed mismatch error), or a baseline the AR fit rejects.
    pub fn at(&self, fs_hz: f64) -> anyhow::Result<Prepared> {
        let key = fs_hz.to_bits();
        let mut cache = self
            .prepared
            .lock()
            .map_err(|_| anyhow::anyhow!("baseline cache poisoned"))?;
        if let Some((_, b)) = cache.iter().find(|(k, _)| *k == key) {
            return Ok(b.clone());
        }
        if let Some(m) = self.machine.as_deref() {
            let b = self.prepare_machine(m)?;
            cache.push((key, b.clone()));
            return Ok(b);
        }
        let name = self.path.display();
        let (x, fs_b, note) = if let Some((x, q)) = decimated_to(&self.samples, self.fs_hz, fs_hz)?
        {
            (
                x,
                fs_hz,
                format!(
                    "{name}, {} Hz decimated by {q} (bearing-data anti-aliasing FIR) to {fs_hz} Hz",
                    self.fs_hz
                ),
            )
        } else {
            // equal rates, or a mismatch the library reports as its typed error
            (
                self.samples.clone(),
                self.fs_hz,
                format!("{name} at {} Hz", self.fs_hz),
            )
        };
        let b = Baseline::prepare(&x, fs_b).with_context(|| format!("baseline {name}"))?;
        let b = Arc::new((b, note));
        cache.push((key, b.clone()));
        Ok(b)
    }
}

/// `x` sampled at `from_hz`, decimated to `to_hz` with `bearing-data`'s anti-aliasing FIR, and
/// the factor, when `from_hz` is an integer multiple (> 1) of `to_hz`; `None` otherwise (equal
/// rates, or rates that an integer factor cannot join).
///
/// # Errors
/// The decimator's errors.
pub fn decimated_to(
    x: &[f64],
    from_hz: f64,
    to_hz: f64,
) -> anyhow::Result<Option<(Vec<f64>, usize)>> {
    let ratio = from_hz / to_hz;
    if ratio > 1.0 + 1e-9 && (ratio - ratio.round()).abs() < 1e-9 {
        let q = ratio.round() as usize;
        let d = bearing_data::Decimator::new(bearing_data::DecimatorParams::new(q))?;
        Ok(Some((d.decimate(x)?, q)))
    } else {
        Ok(None)
    }
}

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

/// What an optional trained classifier says about a recording.
#[derive(Debug, Clone)]
pub struct TrainedClass {
    /// Its class (the majority over the segments).
    pub class: String,
    /// The class of each segment.
    pub segments: Vec<String>,
    /// The classifier's name.
    pub classifier: String,
    /// Examples and recordings it was trained on.
    pub examples: usize,
    /// Distinct recordings among them.
    pub recordings: usize,
    /// Where it was read from.
    pub file: String,
}

/// Read a trained classifier saved by `train-classifier`.
///
/// # Errors
/// Unreadable file, or the library's format error.
pub fn load_classifier(path: &Path) -> anyhow::Result<diagnosis::TrainedDiagnoser> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("classifier {}", path.display()))?;
    diagnosis::TrainedDiagnoser::from_json(&text)
        .with_context(|| format!("classifier {}", path.display()))
}

/// Apply a trained classifier to a recording the way it was trained: its segments diagnosed
/// against the same reference, classified, and the majority class kept.
///
/// # Errors
/// Missing speed, the library's errors (another reference than the training diagnoses).
pub fn apply_classifier(
    o: &mut Outcome,
    t: &diagnosis::TrainedDiagnoser,
    file: &Path,
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
) -> anyhow::Result<()> {
    let rpm = plan
        .rpm
        .or(l.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    // at the classifier's rate (decimated when the recording's is an integer multiple of it)
    let (x, fs) = match decimated_to(&l.samples, l.fs_hz, t.fs_hz)? {
        Some((x, _)) => (x, t.fs_hz),
        None => (l.samples.clone(), l.fs_hz),
    };
    let b = baseline.map(|src| src.at(fs)).transpose()?;
    let (class, segments) =
        t.classify_recording(&x, fs, rpm, &plan.bearing, b.as_ref().map(|b| &b.0))?;
    o.trained = Some(TrainedClass {
        class,
        segments,
        classifier: t.classifier.clone(),
        examples: t.examples,
        recordings: t.recordings,
        file: file.display().to_string(),
    });
    Ok(())
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
            let b = src.at(l.fs_hz)?;
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

/// Write `<report>.json`, `.md` and `.png`.
///
/// # Errors
/// File system or drawing errors.
pub fn write_reports(o: &Outcome, report: &Path, title: &str) -> anyhow::Result<()> {
    if let Some(parent) = report.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    let mut json = serde_json::to_value(&o.diagnosis)?;
    if let (Some(t), Some(obj)) = (&o.trained, json.as_object_mut()) {
        obj.insert(
            "classifier".into(),
            serde_json::json!({
                "class": t.class,
                "segments": t.segments,
                "classifier": t.classifier,
                "examples": t.examples,
                "recordings": t.recordings,
                "file": t.file,
            }),
        );
    }
    std::fs::write(
        report.with_extension("json"),
        serde_json::to_string_pretty(&json)? + "\n",
    )?;
    std::fs::write(report.with_extension("md"), markdown(o, title))?;
    crate::figure::envelope_figure(&o.diagnosis, &report.with_extension("png"), title)?;
    Ok(())
}

/// The Markdown report.
pub fn markdown(o: &Outcome, title: &str) -> String {
    let d = &o.diagnosis;
    let op = &d.operating_point;
    let s = &d.statistics;
    let mut m = format!("# Diagnosis of {title}\n\n**Verdict: {}**\n\n", d.verdict);
    if let Some(t) = &o.trained {
        m += &format!(
            "Trained classifier ({}, {} examples from {} labelled recordings, {}): **{}** (segments: {}) — learned from the user's labels, beside the training-free verdict above.\n\n",
            t.classifier,
            t.examples,
            t.recordings,
            t.file,
            t.class,
            t.segments.join(", ")
        );
    }
    m += &match op.measured_speed {
        Some(ms) => format!(
            "- speed: declared {:.1} rpm; the recording's shaft-harmonic comb (orders 1–{}) says {:.1} rpm (score {:.1}, contrast {:.1}: {}); analysed at {:.1} rpm\n",
            op.rpm,
            ms.orders,
            ms.rpm,
            ms.comb_score,
            ms.contrast,
            if ms.accepted {
                "clear"
            } else {
                "not clear enough to use"
            },
            op.rpm_used
        ),
        None => format!(
            "- speed: declared {:.1} rpm (the recording is too short to measure it from its shaft-harmonic comb)\n",
            op.rpm
        ),
    };
    m += &format!(
        "- reference: {} ({})\n- operating point: {:.1} rpm (fr = {:.3} Hz), fs = {} Hz, bearing {}\n\
         - fault frequencies (Hz): BPFO {:.2}, BPFI {:.2}, BSF (ball-defect rate, 2× spin) {:.2}, FTF {:.2}\n\
         - samples: {}; spectra are of the squared envelope, so line prominences are power ratios (dB) and do not depend on the unit\n\
         - residual: AR({}) prediction error; RMS {:.4e} {}; kurtosis {:.2} (signal {:.2})\n",
        match d.reference {
            diagnosis::Reference::Baseline => "baseline",
            diagnosis::Reference::SelfReference => "self",
        },
        o.baseline_note
            .as_deref()
            .unwrap_or("AR model fitted on the recording itself"),
        op.rpm_used,
        op.shaft_hz,
        op.fs_hz,
        if op.bearing_spec.is_empty() {
            &op.bearing
        } else {
            &op.bearing_spec
        },
        op.frequencies_hz.bpfo,
        op.frequencies_hz.bpfi,
        op.frequencies_hz.ball_defect,
        op.frequencies_hz.ftf,
        o.unit,
        d.whitening.order,
        s.residual_rms,
        o.unit.label(),
        s.residual_kurtosis,
        s.signal_kurtosis,
    );
    m += &match (s.energy_ratio_db, &d.reference) {
        (Some(db), _) => format!(
            "- against the baseline residual: energy {db:+.1} dB, kurtosis ×{:.2}\n",
            s.kurtosis_ratio
        ),
        _ => format!("- kurtosis / 3 (Gaussian): ×{:.2}\n", s.kurtosis_ratio),
    };
    m += &format!(
        "- band (Hz): {:.0}–{:.0}, {} (SK {:.2}, line threshold {:.1} dB); kurtogram band {:.0}–{:.0} (SK {:.2})\n\n",
        d.band.low_hz,
        d.band.high_hz,
        d.band.chosen_by,
        d.band.spectral_kurtosis,
        d.band.line_threshold_db,
        d.kurtogram_band.low_hz,
        d.kurtogram_band.high_hz,
        d.kurtogram_band.spectral_kurtosis
    );
    for r in &d.secondary {
        m += &format!(
            "- {} found in a band of its own (Hz): {:.0}–{:.0} (SK {:.2}, line threshold {:.1} dB, score {:.1} dB): {}\n",
            r.hypothesis.name(),
            r.band.low_hz,
            r.band.high_hz,
            r.band.spectral_kurtosis,
            r.band.line_threshold_db,
            r.evidence.score_db,
            r.band.chosen_by
        );
    }
    if !d.secondary.is_empty() {
        m += "\n";
    }
    m += &format!("Rule: {}.\n\n", d.thresholds.rule);
    m += "| hypothesis | score (dB) | detected | band (Hz) | line | expected (Hz) | found (Hz) | prominence (dB) | in baseline (dB) | evidence (dB) | counts |\n|---|---:|---|---|---|---:|---:|---:|---:|---:|---|\n";
    let own_band = d.secondary.iter().map(|r| (&r.evidence, " (own band)"));
    for (e, tag) in d.evidence.iter().map(|e| (e, "")).chain(own_band) {
        for (i, l) in e.harmonics.iter().chain(&e.sidebands).enumerate() {
            let head = if i == 0 {
                format!(
                    "{}{tag} | {:.1} | {} | {:.0}–{:.0}",
                    e.hypothesis.name(),
                    e.score_db,
                    if e.detected { "**yes**" } else { "no" },
                    e.band_hz[0],
                    e.band_hz[1]
                )
            } else {
                " | | | ".to_string()
            };
            let counts = match (l.present, l.explained_by, l.consistent) {
                (true, None, true) => "yes".to_string(),
                (true, Some(h), _) => format!("no, explained by {}", h.name()),
                (true, None, false) => "no, off the common fundamental".to_string(),
                _ => "no".to_string(),
            };
            let base = l
                .baseline_prominence_db
                .map_or("—".to_string(), |b| format!("{b:.1}"));
            m += &format!(
                "| {head} | {} | {:.2} | {:.2} | {:.1} | {base} | {:.1} | {counts} |\n",
                l.label, l.expected_hz, l.found_hz, l.prominence_db, l.evidence_db
            );
        }
    }
    m += "\nShaft harmonics in the band's envelope spectrum: ";
    m += &d
        .shaft_harmonics
        .iter()
        .map(|l| format!("{} {:.1} dB", l.label, l.prominence_db))
        .collect::<Vec<_>>()
        .join(", ");
    m += "\n";
    m
}

/// Files a directory input expands to, sorted: `.mat`, `.csv`, `.tsv`, and files named without an
/// extension or with an all-digit one (IMS names its records by date, `2004.02.12.10.32.39`)
/// whose content is a MAT-file or text ([`sniff`]).
fn expand(input: &Path) -> anyhow::Result<Vec<PathBuf>> {
    if !input.is_dir() {
        return Ok(vec![input.to_path_buf()]);
    }
    let mut v: Vec<PathBuf> = std::fs::read_dir(input)
        .with_context(|| format!("reading {}", input.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .filter(|p| match p.extension().and_then(|e| e.to_str()) {
            Some(e)
                if ["mat", "csv", "tsv"]
                    .iter()
                    .any(|x| e.eq_ignore_ascii_case(x)) =>
            {
                true
            }
            Some(e) if !e.bytes().all(|b| b.is_ascii_digit()) => false,
            _ => sniff(p).is_ok(),
        })
        .collect();
    v.sort();
    if v.is_empty() {
        bail!(
            "{} holds no .mat, .csv or .tsv file (nor a MAT or text file named without an extension)",
            input.display()
        );
    }
    Ok(v)
}

/// The report name (without extension) of each batch input, in order: its stem, or
/// `<stem>_<ext>` (`x_csv`, `x_tsv`) when several inputs share the stem (compared ignoring
/// case), and `<name>_<k>` (k = 1-based position among `files`) for any name still taken twice.
/// Deterministic: depends on the file names only.
pub fn report_names(files: &[PathBuf]) -> Vec<String> {
    let stem = |p: &PathBuf| {
        p.file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("recording")
            .to_string()
    };
    let count =
        |names: &[String], n: &str| names.iter().filter(|m| m.eq_ignore_ascii_case(n)).count();
    let stems: Vec<String> = files.iter().map(stem).collect();
    let names: Vec<String> = files
        .iter()
        .zip(&stems)
        .map(|(p, s)| {
            if count(&stems, s) > 1 {
                let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
                format!("{s}_{ext}")
            } else {
                s.clone()
            }
        })
        .collect();
    names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            if count(&names, n) > 1 {
                format!("{n}_{}", k + 1)
            } else {
                n.clone()
            }
        })
        .collect()
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
    let files = expand(input)?;
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
    let names = report_names(&files);
    if crate::resolved(input).is_some() && crate::resolved(input) == crate::resolved(report) {
        bail!(
            "--report {} is the input directory: the reports would be mixed with the recordings (and read as recordings by the next run); choose another directory",
            report.display()
        );
    }
    let mut outputs: Vec<PathBuf> = names
        .iter()
        .flat_map(|n| crate::report_files(&report.join(format!("{n}.json"))))
        .collect();
    outputs.push(report.join("summary.csv"));
    crate::refuse_overwrite("--report", &outputs, &read)?;
    std::fs::create_dir_all(report)?;
    let bar = indicatif::ProgressBar::new(files.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    type Done = (PathBuf, String, anyhow::Result<(Outcome, Vec<String>)>);
    let results: Vec<Done> = files
        .par_iter()
        .zip(&names)
        .map(|(p, n)| {
            let json = format!("{n}.json");
            let r = one(p, &report.join(&json));
            bar.inc(1);
            (p.clone(), json, r)
        })
        .collect();
    bar.finish_and_clear();
    let mut csv = String::from(
        "file,report,verdict,reference,score_inner_db,score_outer_db,score_ball_db,band_low_hz,band_high_hz,error\n",
    );
    let mut failed = 0;
    for (p, json, r) in &results {
        let name = p.file_name().and_then(|s| s.to_str()).unwrap_or("");
        match r {
            Ok((o, notes)) => {
                for n in notes {
                    eprintln!("note: {n}");
                }
                let d = &o.diagnosis;
                crate::say!("{name}: {} -> {json}", d.verdict);
                csv += &format!(
                    "{name},{json},{},{},{:.2},{:.2},{:.2},{:.0},{:.0},\n",
                    d.verdict,
                    if o.baseline_note.is_some() {
                        "baseline"
                    } else {
                        "self"
                    },
                    d.scores.inner,
                    d.scores.outer,
                    d.scores.ball,
                    d.band.low_hz,
                    d.band.high_hz
                );
            }
            Err(e) => {
                failed += 1;
                let msg = format!("{e:#}").replace([',', '\n'], ";");
                eprintln!("{name}: error: {msg}");
                csv += &format!("{name},,,,,,,,,{msg}\n");
            }
        }
    }
    std::fs::write(report.join("summary.csv"), csv)?;
    crate::say!(
        "{} recordings, {failed} failed; reports in {}",
        results.len(),
        report.display()
    );
    if failed > 0 {
        bail!(
            "{failed} of {} recordings failed (their errors are in {})",
            results.len(),
            report.join("summary.csv").display()
        );
    }
    Ok(())
}
