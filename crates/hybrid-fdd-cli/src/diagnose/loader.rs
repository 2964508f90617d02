//! Loading one recording: a CWRU record, any other MAT-file or a delimited text file (see
//! the `text` module), its sampling rate against `--fs`, and the speed from a `simulate` sidecar.

use std::path::Path;

use anyhow::{Context as _, bail};
use bearing_data::SampleUnit;

use super::text::load_csv;

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
pub(super) fn resolve_rate(
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
pub(super) fn sniff(path: &Path) -> anyhow::Result<&'static str> {
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
/// the signal (`fs`, `sr`, `sample_rate`, `SampleFrequency`, …: `bearing_data::is_sampling_rate_name`)
/// wins over `--fs` as a CWRU record's does; the shaft
/// speed stored beside it (`bearing_data::shaft_speed_near`: `rpm`, or a rotation frequency in Hz
/// such as MFPT's `rate`) is the speed.
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
            "{name}: the file stores no sampling rate (a scalar such as fs, sr, sample_rate, SampleFrequency or SamplingRate; case and _ ignored); give --fs"
        )
    })?;
    let speed = bearing_data::shaft_speed_near(&leaves, &signal.path, fs_hz);
    if let Some(sp) = speed.as_ref().filter(|sp| sp.unit != "rpm") {
        eprintln!(
            "{name}: speed {:.0} rpm from `{}` = {} {} (read as the shaft's rotation frequency)",
            sp.rpm, sp.path, sp.stored, sp.unit
        );
    }
    let rpm = speed.map(|sp| sp.rpm);
    bearing_data::check_samples(|| format!("`{}`", signal.path), &signal.samples, 0)
        .with_context(|| name.to_string())?;
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

/// The JSON sidecar of a text recording (`x.csv` → `x.json`), when it exists and parses.
pub(super) fn sidecar(path: &Path) -> Option<serde_json::Value> {
    let text = std::fs::read_to_string(path.with_extension("json")).ok()?;
    serde_json::from_str(&text).ok()
}

/// The shaft speed a `simulate` sidecar records (its `rpm`), for a text recording; `None` for
/// other files and sidecars without one.
pub fn sidecar_rpm(path: &Path) -> Option<f64> {
    simulate_sidecar(path)?["rpm"]
        .as_f64()
        .filter(|r| r.is_finite() && *r > 0.0)
}

/// The sidecar of a text recording written by `simulate` (its `generator` says so); `None` for
/// other files and other sidecars.
fn simulate_sidecar(path: &Path) -> Option<serde_json::Value> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    if !matches!(ext.as_str(), "csv" | "tsv" | "txt") {
        return None;
    }
    let v = sidecar(path)?;
    v["generator"]
        .as_str()
        .is_some_and(|g| g.contains("simulate"))
        .then_some(v)
}

/// The bearing a `simulate` sidecar records (its `bearing`: `6205` or `6203`), for a text
/// recording; `None` for other files and sidecars without one (written before 2026-11-27).
pub fn sidecar_bearing(path: &Path) -> Option<String> {
    simulate_sidecar(path)?["bearing"]
        .as_str()
        .map(str::trim)
        .filter(|b| !b.is_empty())
        .map(str::to_string)
}

/// The bearing to declare for `path`: `given` when given, else its `simulate` sidecar's
/// ([`sidecar_bearing`], with a note saying so), else the 6205 (CWRU's drive end).
///
/// # Errors
/// `given` names a built-in bearing other than the one the recording's `simulate` sidecar
/// records (a 6203 simulation declared as a 6205 would be modelled with the wrong geometry).
pub fn bearing_or_sidecar(
    path: &Path,
    given: Option<&str>,
) -> anyhow::Result<(String, Option<String>)> {
    let recorded = sidecar_bearing(path);
    match (given, recorded) {
        (Some(g), Some(r)) => {
            // two specs that parse disagree when any fault multiple differs by more than 0.1 %
            // (a geometry and its rounded catalogue multiples agree)
            let orders = |s: &str| bearing_model::BearingSpec::parse(s).ok().map(|b| b.orders);
            let differ = |a: f64, b: f64| (a - b).abs() > 1e-3 * b.abs().max(1e-9);
            if let (Some(a), Some(b)) = (orders(g), orders(&r))
                && (differ(a.bpfo, b.bpfo)
                    || differ(a.bpfi, b.bpfi)
                    || differ(a.ftf, b.ftf)
                    || differ(a.ball_defect, b.ball_defect))
            {
                anyhow::bail!(
                    "--bearing {g}, but {} was simulated with the {r} (its sidecar {})",
                    path.display(),
                    path.with_extension("json").display()
                );
            }
            Ok((g.to_string(), None))
        }
        (Some(g), None) => Ok((g.to_string(), None)),
        (None, Some(r)) => {
            let note = format!(
                "{}: --bearing {r} from its simulate sidecar {}",
                path.display(),
                path.with_extension("json").display()
            );
            Ok((r, Some(note)))
        }
        (None, None) => Ok(("6205".to_string(), None)),
    }
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
