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
}
