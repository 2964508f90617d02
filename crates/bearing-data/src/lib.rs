//! CWRU bearing recordings: an embedded catalog, MAT/CSV readers, SHA-256 checks and
//! anti-aliased integer decimation. The data edge of hybrid-fdd: everything else takes slices.
//!
//! * [`catalog()`], [`entry`], [`Query`]: what each CWRU file number is (sampling rate, fault
//!   location/diameter/position, load, rpm, channels, SHA-256, sample count), including the
//!   records the shared copy lacks, with no file access.
//! * [`load_record`] / [`parse_record`]: a typed [`Recording`] from a `.mat` file, handling the
//!   files' quirks (174 → X173, 3001–3008 → X056–X059/X048–X051, 99 → X099, miUINT16 rpm,
//!   missing BA/FE, no rpm); [`read_variable_sets`] for other CWRU-style MAT files;
//!   [`read_mat_tree`], [`select_signal`], [`sampling_rate_near`], [`shaft_speed_near`] for any
//!   other MAT v5–v7 file (compressed, signals inside structs, struct arrays and cells: other
//!   rigs' recordings);
//!   [`write_mat`] writes such files (round-trip tests, export to MATLAB).
//! * [`Decimator`]: Kaiser-window FIR decimation ([`Recording::de_at`] pairs 48 kHz with 12 kHz).
//! * [`read_csv`]: one column of a user's CSV/plain-text recording as a [`Signal`].
//! * [`DataLocation`]: the one data-directory setting (`--data-dir` / `HYBRID_FDD_DATA`).
//! * [`SampleUnit`]: the unit of a recording's samples as far as it is known (the one unit type
//!   of the reports and machine models).
//!
//! Every reader checks the samples it returns the same way: NaN or ±∞ is
//! [`DataError::NonFinite`], a finite sample of magnitude ≥ [`MAX_SAMPLE_MAGNITUDE`] (1e150, whose
//! square overflows every energy downstream) is [`DataError::SampleTooLarge`]; both name the
//! channel or column and the sample.
//!
//! Dependencies and why: `matfile` (pure-Rust MAT v5 reader; no HDF5/C toolchain, reads the
//! CWRU v5 files including small-element rpm scalars; it skips structs, cells and text, so
//! [`read_mat_tree`] walks those itself), `flate2` (zlib for MATLAB's compressed elements; already
//! in the build through the PNG encoder), `sha2` (RustCrypto SHA-256, the digest the
//! public mirrors pin), `csv` (robust quoting/trimming/comments for users' text files),
//! `thiserror` (the one typed error enum), `sampled-signal` (the workspace's one checked
//! sampled-signal type, [`Signal`], which [`read_csv`] returns), `serde` (labels, rpm and the label enums derive
//! `Serialize`/`Deserialize` so reports can write them); optionally (feature `bearing-model`,
//! off by default) `bearing-model`, for the `From` conversions of a [`FaultLabel`] to the
//! workspace's fault vocabulary (`bearing_model::FaultClass`, `Option<bearing_model::FaultLocation>`).
//!
//! ```no_run
//! use bearing_data::{DataLocation, LoadOptions, Query, load_record};
//! let loc = DataLocation::resolve(None, "/work/main".as_ref())?;
//! let dir = loc.required()?;
//! for e in Query::new().fs_hz(12_000).diameter_in(0.014).load_hp(2).run() {
//!     let rec = load_record(dir, e.number, &LoadOptions::default())?;
//!     println!("{} {} {} samples at {} rpm", e.number, e.class_name(), rec.len(), rec.rpm().value);
//! }
//! # Ok::<(), bearing_data::DataError>(())
//! ```

mod catalog;
mod catalog_absent;
mod catalog_table;
mod checksum;
mod decimate;
mod error;
mod grades;
mod location;
mod mat;
mod mat_tree;
#[cfg(feature = "bearing-model")]
mod model;
mod recording;
mod text;
mod unit;

pub use catalog::{
    BearingMake, CatalogEntry, Channels, FaultLabel, OuterPosition, Query, SensorEnd, catalog,
    entry,
};

/// The former name of [`FaultLabel`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed `FaultLabel` (a record's class label, `Normal` included); the fault location \
            is `bearing_model::FaultLocation`, and with the feature `bearing-model` a label \
            converts to it (and to `bearing_model::FaultClass`) with `From`"
)]
pub type FaultLocation = FaultLabel;
/// The former name of [`BearingMake`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed to `BearingMake`: a record's faulted bearing make (SKF or NTN-equivalent \
            6205); the bearing types are `bearing_model::Bearing` and `bearing_model::BearingSpec`"
)]
pub type Bearing = BearingMake;
pub use checksum::{FileStatus, Verify, check_file, sha256_hex, verify_bytes};
pub use decimate::{Decimator, DecimatorParams, decimate, integer_factor};
pub use error::{DataError, MAX_SAMPLE_MAGNITUDE, Result, check_samples};
pub use grades::smith_randall_grade;
pub use location::{DATA_DIR_ENV, DataLocation, ci_from_env};
pub use mat::{VariableSet, read_variable_sets, select_set, validate_structure};
pub use mat_tree::{
    MAX_DEPTH, MAX_INFLATED_BYTES, MIN_SIGNAL_SAMPLES, MatArray, MatLeaf, MatSignal, MatValue,
    SAMPLING_RATE_NAMES, StoredSpeed, is_sampling_rate_name, read_mat_tree, sampling_rate_near,
    select_signal, shaft_speed_near, write_mat,
};
pub use recording::{
    Labels, LoadOptions, Recording, Rpm, RpmSource, cwru_dir, load_record, parse_record,
    record_path,
};
pub use text::{Column, CsvOptions, HeaderRow, Signal, SignalError, read_csv, read_csv_file};
pub use unit::{CWRU_STATEMENT, SampleUnit};
