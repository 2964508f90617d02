//! Delimited text recordings (`,`, `;` or tab): the column, the rate from a time column, and
//! `bearing-data`'s CSV errors restated for the user.

use std::path::Path;

use anyhow::{Context as _, bail};
use bearing_data::SampleUnit;

use super::loader::{
    FsFlag, Loaded, TIME_RATE_TOLERANCE, TIME_STEP_TOLERANCE, resolve_rate, sidecar,
};

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
    // where a sample of the signal column sits: its line, else its data row
    let at = |index: usize| match lines.get(index) {
        Some((line, _)) => format!("line {line}"),
        None => format!("data row {}", index + 1),
    };
    match e {
        bearing_data::DataError::NonFinite { index, .. } => anyhow::anyhow!(
            "{name}: {}, {}: non-finite sample (NaN or infinity)",
            at(index),
            col(signal)
        ),
        bearing_data::DataError::SampleTooLarge { index, value, .. } => anyhow::anyhow!(
            "{name}: {}, {}: sample {value:e} is too large: its square overflows (|x| must be below {:e})",
            at(index),
            col(signal),
            bearing_data::MAX_SAMPLE_MAGNITUDE
        ),
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
pub(super) fn load_csv(
    path: &Path,
    channel: &str,
    fs: Option<f64>,
    flag: FsFlag,
) -> anyhow::Result<Loaded> {
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
