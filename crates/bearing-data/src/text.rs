//! Plain-text / CSV recordings supplied by users (and the CSV `cargo xtask simulate` writes):
//! one numeric column, chosen by position or header name, with the sampling rate given.

use std::io::Read;
use std::path::Path;

use crate::error::{DataError, Result};

/// Which column holds the signal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Column {
    /// The file has exactly one column.
    Single,
    /// The column at this 0-based index.
    Index(usize),
    /// The column with this header name (implies a header row), e.g. `accel`.
    Name(String),
}

/// Whether the first row is a header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HeaderRow {
    /// A header if the selected field of the first row is not a number (default).
    #[default]
    Auto,
    /// The first row is a header.
    Present,
    /// Every row is data.
    Absent,
}

/// How to read a CSV recording.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvOptions {
    /// Sampling rate of the recording in Hz (finite, > 0).
    pub fs_hz: f64,
    /// Which column to read.
    pub column: Column,
    /// Header handling (ignored for [`Column::Name`], which always reads a header).
    pub header: HeaderRow,
    /// Field delimiter (default `b','`).
    pub delimiter: u8,
}

impl CsvOptions {
    /// Read `column` at `fs_hz`, header detected automatically, comma-delimited.
    pub fn new(fs_hz: f64, column: Column) -> Self {
        Self {
            fs_hz,
            column,
            header: HeaderRow::Auto,
            delimiter: b',',
        }
    }
}

/// A single-channel signal with its sampling rate: non-empty, all samples finite, the rate finite
/// and > 0 — the workspace's one sampled-signal type, [`sampled_signal::Signal`] (re-exported
/// here and as `bearing_data::Signal`); its [`SignalError`] becomes a [`DataError`] with the
/// messages this crate has always given (`From<SignalError> for DataError`).
pub use sampled_signal::{Signal, SignalError};

fn truncate(s: &str) -> String {
    s.chars().take(40).collect()
}

/// Read one column of a CSV / plain-text file. Lines starting with `#` are comments; fields are
/// trimmed. Errors: no data rows, a non-numeric or non-finite field, a missing column.
pub fn read_csv<R: Read>(reader: R, opts: &CsvOptions) -> Result<Signal<'static>> {
    if !(opts.fs_hz.is_finite() && opts.fs_hz > 0.0) {
        return Err(DataError::InvalidParameter {
            name: "fs_hz",
            value: opts.fs_hz,
            reason: "sampling rate must be finite and > 0",
        });
    }
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .delimiter(opts.delimiter)
        .from_reader(reader);
    let mut samples = Vec::new();
    let mut column: Option<usize> = match &opts.column {
        Column::Single => Some(0),
        Column::Index(i) => Some(*i),
        Column::Name(_) => None,
    };
    let mut first = true;
    let mut record = csv::StringRecord::new();
    loop {
        match rdr.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                return Err(DataError::Csv {
                    message: e.to_string(),
                });
            }
        }
        let line = record.position().map_or(0, |p| p.line());
        if record.len() == 1 && record.get(0) == Some("") {
            continue; // blank line
        }
        if first {
            first = false;
            let header = match (&opts.column, opts.header) {
                (Column::Name(name), _) => {
                    let idx = record.iter().position(|f| f == name.as_str());
                    column =
                        Some(idx.ok_or_else(|| DataError::CsvNoSuchColumn { name: name.clone() })?);
                    true
                }
                (_, HeaderRow::Present) => true,
                (_, HeaderRow::Absent) => false,
                (_, HeaderRow::Auto) => {
                    let c = column.unwrap_or(0);
                    record.get(c).is_some_and(|f| f.parse::<f64>().is_err())
                }
            };
            if header {
                continue;
            }
        }
        let c = column.unwrap_or(0);
        if opts.column == Column::Single && record.len() > 1 {
            return Err(DataError::CsvSeveralColumns {
                line,
                fields: record.len(),
            });
        }
        let field = record.get(c).ok_or(DataError::CsvMissingField {
            line,
            fields: record.len(),
            column: c,
        })?;
        let v: f64 = field.parse().map_err(|_| DataError::CsvNotANumber {
            line,
            column: c,
            text: truncate(field),
        })?;
        crate::error::check_samples(|| format!("CSV column {c}"), &[v], samples.len())?;
        samples.push(v);
    }
    if samples.is_empty() {
        return Err(DataError::Empty {
            what: "CSV has no data rows",
        });
    }
    Ok(Signal::new(samples, opts.fs_hz)?)
}

/// [`read_csv`] on a file.
pub fn read_csv_file(path: &Path, opts: &CsvOptions) -> Result<Signal<'static>> {
    let f = std::fs::File::open(path).map_err(|source| DataError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_csv(std::io::BufReader::new(f), opts)
}
