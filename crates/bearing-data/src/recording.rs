//! A typed CWRU recording (channels, sampling rate, rpm, labels) and the loader that builds it.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::catalog::{self, BearingMake, CatalogEntry, FaultLabel, OuterPosition, SensorEnd};
use crate::checksum::{Verify, verify_bytes};
use crate::decimate::{Decimator, DecimatorParams, integer_factor};
use crate::error::{DataError, Result};
use crate::mat::{read_variable_sets, select_set};

/// Where a recording's shaft speed came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RpmSource {
    /// The file's own `X###RPM` value.
    Stored,
    /// The catalog's nominal speed for the load (the file stores none: 98, 99, 3001–3008).
    Nominal,
}

/// Shaft speed of a recording.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rpm {
    /// Revolutions per minute.
    pub value: f64,
    /// Stored in the file or nominal.
    pub source: RpmSource,
}

impl Rpm {
    /// Shaft frequency `fr = rpm/60` in Hz.
    pub fn shaft_hz(self) -> f64 {
        self.value / 60.0
    }
}

/// The class labels of a record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Labels {
    /// Fault label: normal, or where the seeded fault is.
    pub fault: FaultLabel,
    /// Fault diameter in inches; `None` for normal.
    pub fault_diameter_in: Option<f64>,
    /// Outer-race defect position (outer-race faults only).
    pub outer_position: Option<OuterPosition>,
    /// Motor load in hp.
    pub load_hp: u8,
    /// The bearing end the fault was seeded at; `None` for normal.
    pub fault_end: Option<SensorEnd>,
    /// The faulted bearing's make.
    pub bearing: BearingMake,
}

/// Options for [`load_record`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LoadOptions {
    /// SHA-256 verification before parsing (default [`Verify::IfPinned`]).
    pub verify: Verify,
}

impl LoadOptions {
    /// No checksum (fastest).
    pub fn unverified() -> Self {
        Self {
            verify: Verify::Skip,
        }
    }
}

/// One CWRU recording: DE channel (always), FE and BA (when the file has them), all the same
/// length, all finite, with the sampling rate, shaft speed and labels.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    entry: &'static CatalogEntry,
    variable: u32,
    rpm: Rpm,
    de: Vec<f64>,
    fe: Option<Vec<f64>>,
    ba: Option<Vec<f64>>,
}

impl Recording {
    /// Catalog facts of this record.
    pub fn entry(&self) -> &'static CatalogEntry {
        self.entry
    }
    /// Record (file) number.
    pub fn number(&self) -> u32 {
        self.entry.number
    }
    /// The `X###` number of the variables that were read.
    pub fn variable(&self) -> u32 {
        self.variable
    }
    /// Sampling rate in Hz.
    pub fn fs_hz(&self) -> f64 {
        self.entry.fs()
    }
    /// Shaft speed: stored in the file when it has one, else nominal.
    pub fn rpm(&self) -> Rpm {
        self.rpm
    }
    /// Class labels.
    pub fn labels(&self) -> Labels {
        let e = self.entry;
        Labels {
            fault: e.fault,
            fault_diameter_in: e.fault_diameter_in(),
            outer_position: e.outer_position,
            load_hp: e.load_hp,
            fault_end: e.fault_end(),
            bearing: e.bearing(),
        }
    }
    /// Drive-end accelerometer samples.
    pub fn de(&self) -> &[f64] {
        &self.de
    }
    /// Fan-end accelerometer samples, if the file has them.
    pub fn fe(&self) -> Option<&[f64]> {
        self.fe.as_deref()
    }
    /// Base-plate accelerometer samples, if the file has them.
    pub fn ba(&self) -> Option<&[f64]> {
        self.ba.as_deref()
    }
    /// The channel of `end`, if present.
    pub fn channel(&self, end: SensorEnd) -> Option<&[f64]> {
        match end {
            SensorEnd::DriveEnd => Some(&self.de),
            SensorEnd::FanEnd => self.fe(),
            SensorEnd::Base => self.ba(),
        }
    }
    /// Samples per channel.
    pub fn len(&self) -> usize {
        self.de.len()
    }
    /// Always `false`: a recording has at least one sample.
    pub fn is_empty(&self) -> bool {
        self.de.is_empty()
    }
    /// Duration in seconds.
    pub fn duration_s(&self) -> f64 {
        self.de.len() as f64 / self.fs_hz()
    }
    /// The DE channel at `target_fs_hz`: borrowed when the rates are equal, else decimated by
    /// the integer factor `fs/target` with the default anti-aliasing design
    /// ([`DecimatorParams::new`]). E.g. `de_at(12_000.0)` pairs 97.mat (48 kHz) with the 12 kHz
    /// fault records. Errors: [`DataError::NotIntegerFactor`].
    pub fn de_at(&self, target_fs_hz: f64) -> Result<Cow<'_, [f64]>> {
        self.channel_at(SensorEnd::DriveEnd, target_fs_hz)?
            .ok_or(DataError::NoDriveEnd {
                variable: self.variable,
                found: 0,
            })
    }
    /// Like [`de_at`](Self::de_at) for any channel; `Ok(None)` if the file lacks it.
    pub fn channel_at(&self, end: SensorEnd, target_fs_hz: f64) -> Result<Option<Cow<'_, [f64]>>> {
        let factor = integer_factor(self.fs_hz(), target_fs_hz)?;
        let Some(x) = self.channel(end) else {
            return Ok(None);
        };
        if factor == 1 {
            return Ok(Some(Cow::Borrowed(x)));
        }
        let dec = Decimator::new(DecimatorParams::new(factor))?;
        Ok(Some(Cow::Owned(dec.decimate(x)?)))
    }
    /// Take the DE channel.
    pub fn into_de(self) -> Vec<f64> {
        self.de
    }
}

fn check_channel(name: String, v: &[f64], expected: usize) -> Result<()> {
    if v.len() != expected {
        return Err(DataError::ChannelLengthMismatch {
            name,
            expected,
            found: v.len(),
        });
    }
    crate::error::check_samples(|| name, v, 0)
}

/// Parse the bytes of CWRU record `number` (no checksum): pick the variable set the catalog
/// names (174 → X173, 3001–3004 → X056–X059, 3005–3008 → X048–X051, 99 → X099 not X098),
/// read DE/FE/BA and the stored rpm (falling back to the nominal speed).
pub fn parse_record(bytes: &[u8], number: u32) -> Result<Recording> {
    let entry = catalog::entry(number).ok_or(DataError::UnknownRecord { number })?;
    let sets = read_variable_sets(bytes)?;
    let set = select_set(sets, Some(entry.variable))?;
    let de = set.de.ok_or(DataError::NoDriveEnd {
        variable: entry.variable,
        found: 0,
    })?;
    if de.is_empty() {
        return Err(DataError::Empty {
            what: "drive-end channel has no samples",
        });
    }
    let n = de.len();
    check_channel(format!("X{:03}_DE_time", set.number), &de, n)?;
    if let Some(fe) = &set.fe {
        check_channel(format!("X{:03}_FE_time", set.number), fe, n)?;
    }
    if let Some(ba) = &set.ba {
        check_channel(format!("X{:03}_BA_time", set.number), ba, n)?;
    }
    let rpm = match set.rpm {
        Some(value) => Rpm {
            value,
            source: RpmSource::Stored,
        },
        None => Rpm {
            value: f64::from(entry.nominal_rpm),
            source: RpmSource::Nominal,
        },
    };
    Ok(Recording {
        entry,
        variable: set.number,
        rpm,
        de,
        fe: set.fe,
        ba: set.ba,
    })
}

/// The `cwru/` folder for `dir`: `dir/cwru` when that exists (a data directory as resolved by
/// [`DataLocation`](crate::DataLocation)), else `dir` itself (the `cwru/` folder given directly).
pub fn cwru_dir(dir: &Path) -> PathBuf {
    let sub = dir.join("cwru");
    if sub.is_dir() { sub } else { dir.to_path_buf() }
}

/// Path of record `number`'s file under `dir` (see [`cwru_dir`]); errors on an unknown number.
pub fn record_path(dir: &Path, number: u32) -> Result<PathBuf> {
    let entry = catalog::entry(number).ok_or(DataError::UnknownRecord { number })?;
    Ok(cwru_dir(dir).join(entry.rel_path))
}

/// Load CWRU record `number` from the data directory `dir` (or its `cwru/` folder): read the
/// file once, verify its SHA-256 per `opts`, and parse it ([`parse_record`]).
///
/// ```no_run
/// use bearing_data::{load_record, LoadOptions};
/// let rec = load_record("/work/shared/data".as_ref(), 97, &LoadOptions::default())?;
/// let de12k = rec.de_at(12_000.0)?; // 48 kHz baseline decimated by 4
/// assert_eq!(de12k.len(), rec.len().div_ceil(4));
/// # Ok::<(), bearing_data::DataError>(())
/// ```
pub fn load_record(dir: &Path, number: u32, opts: &LoadOptions) -> Result<Recording> {
    let entry = catalog::entry(number).ok_or(DataError::UnknownRecord { number })?;
    let path = cwru_dir(dir).join(entry.rel_path);
    if !path.is_file() {
        return Err(DataError::RecordMissing {
            number,
            path,
            in_shared_copy: entry.in_shared_copy,
        });
    }
    let bytes = std::fs::read(&path).map_err(|source| DataError::Io { path, source })?;
    verify_bytes(entry, &bytes, opts.verify)?;
    parse_record(&bytes, number)
}
