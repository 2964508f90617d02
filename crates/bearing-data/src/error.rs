//! The crate's single error type: every way reading, checking or resampling a recording can fail.

use std::path::PathBuf;

/// Everything that can go wrong in `bearing-data`. Data problems are errors, never panics.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// A file could not be read from disk.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file or directory involved.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The record number is not in the embedded CWRU catalog.
    #[error("record {number} is not in the CWRU catalog")]
    UnknownRecord {
        /// The record (file) number asked for.
        number: u32,
    },
    /// The record is catalogued but the file is not on disk.
    #[error("record {number} is not on disk (expected at {path}){}", if *.in_shared_copy { "" } else { "; it is not part of the shared copy" })]
    RecordMissing {
        /// The record number.
        number: u32,
        /// Where the file was looked for.
        path: PathBuf,
        /// Whether the shared data copy is supposed to hold this file.
        in_shared_copy: bool,
    },
    /// The file's SHA-256 differs from the pinned value.
    #[error("SHA-256 mismatch for record {number}: expected {expected}, found {found}")]
    ChecksumMismatch {
        /// The record number.
        number: u32,
        /// The pinned digest (lower-case hex).
        expected: String,
        /// The digest of the bytes read (lower-case hex).
        found: String,
    },
    /// Verification was requested but no SHA-256 is pinned for the record.
    #[error("no SHA-256 is pinned for record {number}; load it with `Verify::Skip`")]
    NoPinnedChecksum {
        /// The record number.
        number: u32,
    },
    /// The bytes are not a MATLAB level-5 MAT-file, or its structure is damaged.
    #[error("malformed MAT-file at byte {offset}: {reason}")]
    MalformedMat {
        /// Byte offset where the problem was detected.
        offset: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// The MAT-file uses a feature this reader does not support (e.g. compression).
    #[error("unsupported MAT-file feature at byte {offset}: {feature}")]
    UnsupportedMat {
        /// Byte offset of the element.
        offset: usize,
        /// The feature.
        feature: &'static str,
    },
    /// The `matfile` parser rejected the file (after our structural checks passed).
    #[error("MAT-file parser failed: {message}")]
    MatParse {
        /// The parser's message.
        message: String,
    },
    /// No signal, or more than one, of a MAT-file fits what was asked (`mat_tree::select_signal`).
    #[error("{reason}")]
    MatSignal {
        /// What was asked, and what the file holds.
        reason: String,
    },
    /// The file holds no drive-end channel for the requested variable number.
    #[error(
        "no drive-end channel X{variable:03}_DE_time in the file ({found} signal variables found)"
    )]
    NoDriveEnd {
        /// The variable number looked for.
        variable: u32,
        /// How many `*_time` variables the file holds.
        found: usize,
    },
    /// Several variable sets have a drive-end channel and no number was given to pick one.
    #[error("{sets} variable sets with a drive-end channel; give the variable number to pick one")]
    AmbiguousVariables {
        /// How many `X###` sets with a DE channel were found.
        sets: usize,
    },
    /// A channel is not a real N×1 / 1×N double vector.
    #[error("variable {name} is not a real vector ({rows}×{cols})")]
    NotAVector {
        /// Variable name.
        name: String,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// Channels of one recording have different lengths.
    #[error("channel {name} has {found} samples, the drive-end channel {expected}")]
    ChannelLengthMismatch {
        /// Variable name.
        name: String,
        /// Samples of the DE channel.
        expected: usize,
        /// Samples of this channel.
        found: usize,
    },
    /// A sample is NaN or infinite.
    #[error("non-finite sample in {what} at index {index}")]
    NonFinite {
        /// Which channel or column.
        what: String,
        /// Sample index (0-based; for CSV the data row).
        index: usize,
    },
    /// A sample so large that its square (every energy and power downstream) overflows.
    #[error(
        "sample {value:e} in {what} at index {index} is too large: its square overflows (|x| must be below {MAX_SAMPLE_MAGNITUDE:e})"
    )]
    SampleTooLarge {
        /// Which channel or column.
        what: String,
        /// Sample index (0-based; for CSV the data row).
        index: usize,
        /// The sample.
        value: f64,
    },
    /// A signal with no samples where samples are needed.
    #[error("empty input: {what}")]
    Empty {
        /// What was empty.
        what: &'static str,
    },
    /// A CSV field is not a number.
    #[error("CSV line {line}, column {column}: {text:?} is not a number")]
    CsvNotANumber {
        /// 1-based line number in the file.
        line: u64,
        /// 0-based column index.
        column: usize,
        /// The offending text (truncated to 40 characters).
        text: String,
    },
    /// The CSV has no column of the requested name.
    #[error("CSV has no column named {name:?}")]
    CsvNoSuchColumn {
        /// The column asked for.
        name: String,
    },
    /// The CSV row is shorter than the requested column index.
    #[error("CSV line {line} has {fields} fields, column {column} was requested")]
    CsvMissingField {
        /// 1-based line number.
        line: u64,
        /// Fields on the line.
        fields: usize,
        /// 0-based column requested.
        column: usize,
    },
    /// `Column::Single` was requested but the CSV has several columns.
    #[error("CSV line {line} has {fields} columns; name the column to read")]
    CsvSeveralColumns {
        /// 1-based line number.
        line: u64,
        /// Fields on the line.
        fields: usize,
    },
    /// The CSV could not be tokenised (bad UTF-8, I/O).
    #[error("CSV error: {message}")]
    Csv {
        /// The csv crate's message.
        message: String,
    },
    /// A parameter is out of its valid range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// The target sampling rate is not the source rate divided by an integer.
    #[error("cannot resample {from_hz} Hz to {to_hz} Hz by an integer decimation factor")]
    NotIntegerFactor {
        /// Source rate.
        from_hz: f64,
        /// Requested rate.
        to_hz: f64,
    },
    /// A unit code that is not one of `g`, `m/s^2`, `unknown`.
    #[error("unknown units `{code}` (g, m/s^2 or unknown)")]
    UnknownUnit {
        /// The code given.
        code: String,
    },
    /// An explicitly given data directory does not exist.
    #[error("data directory {path} does not exist or is not a directory")]
    DataDirNotFound {
        /// The directory given.
        path: PathBuf,
    },
    /// No data directory was found and it is required (e.g. `CI=true`).
    #[error("no data directory: looked for {searched}; set --data-dir or HYBRID_FDD_DATA")]
    DataAbsent {
        /// The default location that was searched.
        searched: PathBuf,
    },
}

/// A [`sampled_signal::Signal`] that cannot be built, with this crate's messages: an invalid
/// rate is [`DataError::InvalidParameter`] `fs_hz`, no samples [`DataError::Empty`], a non-finite
/// sample [`DataError::NonFinite`] in `signal`.
impl From<sampled_signal::SignalError> for DataError {
    fn from(e: sampled_signal::SignalError) -> Self {
        match e {
            sampled_signal::SignalError::InvalidRate { fs_hz } => DataError::InvalidParameter {
                name: "fs_hz",
                value: fs_hz,
                reason: "sampling rate must be finite and > 0",
            },
            sampled_signal::SignalError::Empty => DataError::Empty {
                what: "signal has no samples",
            },
            sampled_signal::SignalError::NonFinite { index, .. } => DataError::NonFinite {
                what: "signal".into(),
                index,
            },
        }
    }
}

/// Shorthand for `Result<T, DataError>`.
pub type Result<T> = std::result::Result<T, DataError>;

/// Largest sample magnitude a recording may hold: energies and powers are sums of squares, and
/// the square of 1e154 already overflows f64, so 1e150 leaves room for sums of 10⁸ samples.
pub const MAX_SAMPLE_MAGNITUDE: f64 = 1e150;

/// The one check every reader applies to the samples it returns: finite
/// ([`DataError::NonFinite`]) and below [`MAX_SAMPLE_MAGNITUDE`] ([`DataError::SampleTooLarge`]);
/// `x[0]` is sample `first` of the recording (the index the error names). Public for readers
/// outside this crate (a caller's own format), so that they check the same way.
///
/// # Errors
/// The first sample that fails, as above, with `what()` naming the channel or column.
pub fn check_samples(what: impl FnOnce() -> String, x: &[f64], first: usize) -> Result<()> {
    match x
        .iter()
        .position(|v| !(v.is_finite() && v.abs() < MAX_SAMPLE_MAGNITUDE))
    {
        None => Ok(()),
        Some(i) if !x[i].is_finite() => Err(DataError::NonFinite {
            what: what(),
            index: first + i,
        }),
        Some(i) => Err(DataError::SampleTooLarge {
            what: what(),
            index: first + i,
            value: x[i],
        }),
    }
}
