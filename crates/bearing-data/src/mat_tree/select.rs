//! Choosing the signal and its stated rate among a MAT-file's leaves ([`super::read_mat_tree`]).

use super::MatLeaf;
use crate::error::{DataError, Result};

/// A signal chosen from a MAT-file.
#[derive(Debug, Clone, PartialEq)]
pub struct MatSignal {
    /// Its path in the file.
    pub path: String,
    /// Its `Name`, when the file gives one.
    pub alias: Option<String>,
    /// The samples.
    pub samples: Vec<f64>,
}

/// The signal named `channel` (a full path, a struct element's `Name`, or a last path component,
/// case-insensitive), or with `None` the only real vector of at least [`super::MIN_SIGNAL_SAMPLES`]
/// samples.
///
/// # Errors
/// [`DataError::MatSignal`] saying what the file holds when no leaf, or more than one, fits.
pub fn select_signal(leaves: &[MatLeaf], channel: Option<&str>) -> Result<MatSignal> {
    let listing = || {
        let v: Vec<String> = leaves
            .iter()
            .filter_map(|l| {
                l.vector().map(|x| match &l.alias {
                    Some(a) => format!("{} ({a}, {} samples)", l.path, x.len()),
                    None => format!("{} ({} samples)", l.path, x.len()),
                })
            })
            .collect();
        if v.is_empty() {
            "no real vector".to_string()
        } else {
            v.join(", ")
        }
    };
    let found: Vec<&MatLeaf> = match channel {
        Some(c) => {
            let eq = |s: &str| s.eq_ignore_ascii_case(c);
            let exact: Vec<&MatLeaf> = leaves
                .iter()
                .filter(|l| eq(&l.path) || l.alias.as_deref().is_some_and(eq))
                .collect();
            if exact.is_empty() {
                leaves.iter().filter(|l| eq(l.last_name())).collect()
            } else {
                exact
            }
        }
        None => leaves
            .iter()
            .filter(|l| {
                l.vector()
                    .is_some_and(|x| x.len() >= super::MIN_SIGNAL_SAMPLES)
            })
            .collect(),
    };
    match found.as_slice() {
        [l] => {
            let x = l.vector().ok_or_else(|| DataError::MatSignal {
                reason: format!(
                    "`{}` is not a real vector; the file holds {}",
                    l.path,
                    listing()
                ),
            })?;
            Ok(MatSignal {
                path: l.path.clone(),
                alias: l.alias.clone(),
                samples: x.to_vec(),
            })
        }
        [] => Err(DataError::MatSignal {
            reason: match channel {
                Some(c) => format!("no signal `{c}`; the file holds {}", listing()),
                None => format!(
                    "no real vector of at least {} samples; the file holds {}",
                    super::MIN_SIGNAL_SAMPLES,
                    listing()
                ),
            },
        }),
        _ => Err(DataError::MatSignal {
            reason: format!(
                "{} signals fit{}; choose one with --channel PATH or NAME: {}",
                found.len(),
                channel.map_or(String::new(), |c| format!(" `{c}`")),
                listing()
            ),
        }),
    }
}

/// Names read as a sampling rate in Hz, as [`is_sampling_rate_name`] compares them: lower case,
/// without `_`.
pub const SAMPLING_RATE_NAMES: [&str; 11] = [
    "fs",
    "sr",
    "samplerate",
    "samplingrate",
    "samplefrequency",
    "samplingfrequency",
    "samplefreq",
    "samplingfreq",
    "freqsampling",
    "fsample",
    "fshz",
];

/// Whether a variable named `name` (its last path component) states a sampling rate: one of
/// [`SAMPLING_RATE_NAMES`] with case and `_` ignored, so `fs`, `Fs`, `sr`, `sample_rate`,
/// `sampling_rate`, `SampleRate`, `SamplingRate`, `SampleFrequency` (UESTC's),
/// `SamplingFrequency`, `freq_sampling` and `fs_hz` all do.
pub fn is_sampling_rate_name(name: &str) -> bool {
    let folded: String = name
        .chars()
        .filter(|&c| c != '_')
        .map(|c| c.to_ascii_lowercase())
        .collect();
    SAMPLING_RATE_NAMES.contains(&folded.as_str())
}

/// The sampling rate the file states for the signal at `signal_path`: a finite positive scalar
/// whose name states a rate ([`is_sampling_rate_name`]: `fs`, `sr`, `sample_rate`,
/// `SampleFrequency`, …, case and `_` ignored) in the same struct, else the only such scalar in
/// the file; `None` when there is none or several disagree.
pub fn sampling_rate_near(leaves: &[MatLeaf], signal_path: &str) -> Option<f64> {
    let rates: Vec<(&MatLeaf, f64)> = leaves
        .iter()
        .filter(|l| is_sampling_rate_name(l.last_name()))
        .filter_map(|l| {
            l.scalar()
                .filter(|v| v.is_finite() && *v > 0.0)
                .map(|v| (l, v))
        })
        .collect();
    let parent = signal_path.rsplit_once('.').map_or("", |(p, _)| p);
    if let Some((_, v)) = rates.iter().find(|(l, _)| l.parent() == parent) {
        return Some(*v);
    }
    match rates.as_slice() {
        [(_, v)] => Some(*v),
        _ => None,
    }
}

/// Names read as a shaft speed in rev/min.
const RPM_NAMES: [&str; 4] = ["rpm", "speed_rpm", "shaft_rpm", "rotational_speed_rpm"];
/// Names read as a shaft rotation frequency in Hz.
const SHAFT_HZ_NAMES: [&str; 5] = [
    "shaft_hz",
    "shaft_rate",
    "shaft_frequency",
    "shaft_freq",
    "fr",
];

/// A shaft speed a MAT-file states beside a signal ([`shaft_speed_near`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StoredSpeed {
    /// The speed, rev/min.
    pub rpm: f64,
    /// The path of the scalar it was read from (`bearing.rate`).
    pub path: String,
    /// The scalar as stored, in its own unit.
    pub stored: f64,
    /// That unit: `"rpm"` or `"Hz"`.
    pub unit: &'static str,
}

/// The shaft speed the file states for the signal at `signal_path`, read from a finite positive
/// scalar in the signal's own struct: named `rpm` (or `speed_rpm`, `shaft_rpm`,
/// `rotational_speed_rpm`), in rev/min; or `shaft_hz` (`shaft_rate`, `shaft_frequency`,
/// `shaft_freq`, `fr`), in Hz; or `rate`, in Hz — the MFPT Society's files store their shaft rate
/// so (`bearing.rate = 25` beside `bearing.sr = 48828`) — but only where the same struct also
/// states a sampling rate ([`is_sampling_rate_name`]) that `rate` is not, and the value lies
/// below a twentieth of that sampling rate, so that a `rate` meaning the sampling rate is never
/// read as a speed. A rotation frequency at or above half of `fs_hz` (the sampling rate in use)
/// is not a speed. `None` when no scalar fits, or when several fit and disagree (by more than
/// 0.1 %).
pub fn shaft_speed_near(leaves: &[MatLeaf], signal_path: &str, fs_hz: f64) -> Option<StoredSpeed> {
    let parent = signal_path.rsplit_once('.').map_or("", |(p, _)| p);
    let named =
        |l: &MatLeaf, names: &[&str]| names.iter().any(|n| n.eq_ignore_ascii_case(l.last_name()));
    let siblings = || leaves.iter().filter(|l| l.parent() == parent);
    let value = |l: &MatLeaf| l.scalar().filter(|v| v.is_finite() && *v > 0.0);
    let stated_rate: Vec<f64> = siblings()
        .filter(|l| is_sampling_rate_name(l.last_name()))
        .filter_map(value)
        .collect();
    let found: Vec<StoredSpeed> = siblings()
        .filter_map(|l| {
            let v = value(l)?;
            let (rpm, unit) = if named(l, &RPM_NAMES) {
                (v, "rpm")
            } else if named(l, &SHAFT_HZ_NAMES)
                || (l.last_name().eq_ignore_ascii_case("rate")
                    && !stated_rate.is_empty()
                    && stated_rate.iter().all(|&fs| v < fs / 20.0))
            {
                (v * 60.0, "Hz")
            } else {
                return None;
            };
            (rpm / 60.0 < fs_hz / 2.0).then(|| StoredSpeed {
                rpm,
                path: l.path.clone(),
                stored: v,
                unit,
            })
        })
        .collect();
    let first = found.first()?;
    found
        .iter()
        .all(|s| (s.rpm - first.rpm).abs() <= 1e-3 * first.rpm)
        .then(|| first.clone())
}
