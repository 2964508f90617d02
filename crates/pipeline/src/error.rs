//! The one error type of the pipeline: each algorithm crate's typed error, named by its stage.

/// What can go wrong preparing a method or running it over a recording.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PipelineError {
    /// ARX-Laguerre identification on the healthy fit segment failed.
    #[error("ARX-Laguerre identification on the healthy fit segment: {0}")]
    Ident(#[from] laguerre_id::IdentError),
    /// Fuzzy ARX-Laguerre identification failed.
    #[error("fuzzy ARX-Laguerre identification on the healthy fit segment: {0}")]
    Fuzzy(#[from] fuzzy_ts::FuzzyError),
    /// The machine model could not be calibrated (or its path identified).
    #[error("calibrating the machine model on the healthy fit segment: {0}")]
    Calibration(#[from] close_loop::CloseLoopError),
    /// An observer could not be built or diverged.
    #[error("observer: {0}")]
    Observer(#[from] observers::ObserverError),
    /// The 5-DOF simulation failed.
    #[error("simulation: {0}")]
    Model(#[from] bearing_model::ModelError),
    /// Window features failed.
    #[error("window features: {0}")]
    Features(#[from] residual_features::FeatureError),
    /// A classifier failed.
    #[error("classifier: {0}")]
    Classify(#[from] classify::ClassifyError),
    /// A method needs a model [`crate::Prepared::new`] was asked not to prepare.
    #[error("{what} was not prepared (Prepared::new was called without it)")]
    NotPrepared {
        /// The missing model.
        what: &'static str,
    },
    /// No gain candidate ran stably on the healthy fit segment.
    #[error("no candidate gain of {method} ran stably on the fit segment")]
    NoStableGain {
        /// The method's column name.
        method: &'static str,
    },
    /// A signal is too short for the requested windows or samples.
    #[error("{what}: {found} samples, at least {needed} needed")]
    TooShort {
        /// What was short.
        what: &'static str,
        /// Samples needed.
        needed: usize,
        /// Samples found.
        found: usize,
    },
    /// A precomputed machine-model input ([`crate::Prepared::machine_input`]) of another length
    /// than the recording it is used with.
    #[error("the machine model's input has {found} samples, the recording {expected}")]
    InputLength {
        /// The recording's length.
        expected: usize,
        /// The input's length.
        found: usize,
    },
    /// A silent healthy fit segment (zero RMS).
    #[error("the healthy fit segment is silent (zero RMS)")]
    SilentFitSegment,
    /// Leave one fault size out was asked for without the size to hold out.
    #[error("leave one fault size out needs the fault size to hold out")]
    HeldSizeMissing,
    /// The fault size to hold out is not a fault size of the cell.
    #[error("fault size {mils} mils is not a fault size of this cell")]
    HeldSizeAbsent {
        /// The size asked for, in mils.
        mils: u32,
    },
    /// A CWRU recording could not be read or decimated.
    #[error("CWRU recording {number}.mat: {source}")]
    Recording {
        /// The record number.
        number: u32,
        /// What went wrong.
        source: bearing_data::DataError,
    },
    /// The catalog does not name exactly one record for a table cell.
    #[error("the catalog names {found} records for {query} (one expected)")]
    Catalog {
        /// The cell asked for.
        query: String,
        /// Records found.
        found: usize,
    },
    /// A table prints a crack size that is not a number.
    #[error("table {table}: crack size {size:?} is not a number")]
    BadCrackSize {
        /// The table.
        table: String,
        /// The size as printed.
        size: String,
    },
    /// A table's conditions are outside the run's scope (no load or speed to pool).
    #[error("table {table}: no condition of the table is in the run's scope")]
    EmptyScope {
        /// The table.
        table: String,
    },
    /// A recording (or its features) a cell needs is not available.
    #[error("{what} is not available")]
    Missing {
        /// What is missing.
        what: String,
    },
    /// The calibrated rig failed on a record (synthesis or statistics).
    #[error("rig model on record {record}: {source}")]
    Rig {
        /// The record number.
        record: u32,
        /// What went wrong.
        source: close_loop::CloseLoopError,
    },
}
