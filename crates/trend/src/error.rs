//! The crate's one error type: one line each, naming the file or recording at fault.

/// Everything that can go wrong in ordering, checking and analysing a sequence of recordings.
#[derive(Debug, thiserror::Error)]
pub enum TrendError {
    /// A file name holds no timestamp or number the ordering understands.
    #[error("{file}: no timestamp in the name ({reason})")]
    Timestamp {
        /// The file (or name) at fault.
        file: String,
        /// What was expected.
        reason: String,
    },
    /// Two recordings carry the same time.
    #[error("{file}: duplicate timestamp {time} (also {other})")]
    DuplicateTime {
        /// The second file with that time.
        file: String,
        /// The first file with that time.
        other: String,
        /// The time, as printed.
        time: String,
    },
    /// Some names are timestamps and others plain numbers.
    #[error(
        "{file}: named {found}, but {first} is named {expected}: one naming per directory (or give an index CSV `file,time`)"
    )]
    MixedNaming {
        /// The file at fault.
        file: String,
        /// The naming found in it.
        found: &'static str,
        /// The first file.
        first: String,
        /// The naming of the first file.
        expected: &'static str,
    },
    /// A malformed index CSV.
    #[error("{path}: line {line}: {reason}")]
    IndexCsv {
        /// The index file.
        path: String,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// Fewer baseline recordings than the thresholds need.
    #[error(
        "{found} baseline recording(s), the thresholds need at least {needed} (median and MAD of fewer are not a statistic)"
    )]
    TooFewBaselines {
        /// Minimum.
        needed: usize,
        /// Given or available.
        found: usize,
    },
    /// Fewer recordings than the baseline count.
    #[error("{found} recording(s), fewer than the {needed} baseline recordings asked for")]
    TooFewRecordings {
        /// The baseline count.
        needed: usize,
        /// Recordings given.
        found: usize,
    },
    /// A recording at another sampling rate than the first.
    #[error("{name}: sampled at {fs_hz} Hz, the first recording ({first}) at {expected_hz} Hz")]
    MixedRates {
        /// The recording at fault.
        name: String,
        /// Its rate, Hz.
        fs_hz: f64,
        /// The first recording.
        first: String,
        /// The first recording's rate, Hz.
        expected_hz: f64,
    },
    /// A recording that cannot be analysed (empty, non-finite, constant, bad rate or speed).
    #[error("{name}: {reason}")]
    BadRecording {
        /// The recording at fault.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// Recordings not in increasing time order.
    #[error("{name}: time {time} is not after the previous recording's ({previous})")]
    NotOrdered {
        /// The recording at fault.
        name: String,
        /// Its time.
        time: f64,
        /// The previous recording's time.
        previous: f64,
    },
    /// A configuration value out of range.
    #[error("trend configuration: {0}")]
    Config(String),
}

/// `Result` with [`TrendError`].
pub type Result<T> = std::result::Result<T, TrendError>;
