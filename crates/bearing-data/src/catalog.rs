//! The embedded CWRU catalog: what each record number is (public facts from the CWRU Bearing Data
//! Center), queryable without touching the disk.
//!
//! The rows of the shared copy are generated from its `MANIFEST.csv` into
//! [`catalog_table`](crate::catalog_table) (regenerate with
//! `UPDATE_CATALOG=1 cargo test -p bearing-data --test catalog_table`); the records the shared
//! copy lacks (normal 98–100, 48 kHz drive-end faults at 1–3 hp) are listed by hand in
//! `catalog_absent.rs`, with the SHA-256 other projects pinned from the official server.

use serde::{Deserialize, Serialize};

use crate::{catalog_absent, catalog_table};

/// A record's fault label (its class label): healthy (`Normal`) or where its seeded fault is.
///
/// Not a fault location: a location has no "normal". The workspace's fault location is
/// `bearing_model::FaultLocation`, its fault class `bearing_model::FaultClass`; with this crate's
/// feature `bearing-model` a label converts to either with `From` (`Option<FaultLocation>`,
/// `None` for a normal record).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum FaultLabel {
    /// Healthy baseline.
    Normal,
    /// Inner-race defect.
    InnerRace,
    /// Rolling-element (ball) defect.
    Ball,
    /// Outer-race defect.
    OuterRace,
}

impl FaultLabel {
    /// Short label: `normal`, `inner`, `ball`, `outer` (the manifest's spelling).
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Normal => "normal",
            Self::InnerRace => "inner",
            Self::Ball => "ball",
            Self::OuterRace => "outer",
        }
    }

    /// Parse the manifest's spelling.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "normal" => Some(Self::Normal),
            "inner" => Some(Self::InnerRace),
            "ball" => Some(Self::Ball),
            "outer" => Some(Self::OuterRace),
            _ => None,
        }
    }
}

/// Clock position of an outer-race defect relative to the load zone (6 o'clock).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum OuterPosition {
    /// @6: centred in the load zone.
    Centered6,
    /// @3: orthogonal to the load zone.
    Orthogonal3,
    /// @12: opposite the load zone.
    Opposite12,
}

impl OuterPosition {
    /// The manifest's spelling: `centered6`, `orthogonal3`, `opposite12`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Centered6 => "centered6",
            Self::Orthogonal3 => "orthogonal3",
            Self::Opposite12 => "opposite12",
        }
    }

    /// Clock position in hours (6, 3, 12).
    pub fn clock(self) -> u8 {
        match self {
            Self::Centered6 => 6,
            Self::Orthogonal3 => 3,
            Self::Opposite12 => 12,
        }
    }

    /// Parse the manifest's spelling.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "centered6" => Some(Self::Centered6),
            "orthogonal3" => Some(Self::Orthogonal3),
            "opposite12" => Some(Self::Opposite12),
            _ => None,
        }
    }
}

/// Accelerometer position (and the bearing end a fault was seeded at).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum SensorEnd {
    /// Drive end (`*_DE_time`), SKF 6205.
    DriveEnd,
    /// Fan end (`*_FE_time`), SKF 6203.
    FanEnd,
    /// Base plate (`*_BA_time`).
    Base,
}

impl SensorEnd {
    /// Variable-name suffix: `DE`, `FE`, `BA`.
    pub fn suffix(self) -> &'static str {
        match self {
            Self::DriveEnd => "DE",
            Self::FanEnd => "FE",
            Self::Base => "BA",
        }
    }
}

/// The faulted bearing's make (the CWRU record's drive-end bearing). Not a bearing geometry:
/// the workspace's bearing types are `bearing_model::Bearing` (built-in geometries) and
/// `bearing_model::BearingSpec`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum BearingMake {
    /// SKF 6205-2RS JEM (drive end): all records except the 0.028 in faults.
    Skf6205,
    /// NTN-equivalent 6205 used by CWRU for the 0.028 in faults (records 3001–3008).
    Ntn6205Equivalent,
}

/// Which accelerometer channels a file holds (bit set of DE/FE/BA).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Channels {
    /// `*_DE_time` present.
    pub de: bool,
    /// `*_FE_time` present.
    pub fe: bool,
    /// `*_BA_time` present.
    pub ba: bool,
}

impl Channels {
    /// DE, FE and BA (12 kHz fault files).
    pub const DE_FE_BA: Self = Self {
        de: true,
        fe: true,
        ba: true,
    };
    /// DE and FE (48 kHz files, normal baselines).
    pub const DE_FE: Self = Self {
        de: true,
        fe: true,
        ba: false,
    };
    /// DE only (0.028 in files 3001–3008).
    pub const DE: Self = Self {
        de: true,
        fe: false,
        ba: false,
    };

    /// Whether the channel of `end` is present.
    pub fn has(self, end: SensorEnd) -> bool {
        match end {
            SensorEnd::DriveEnd => self.de,
            SensorEnd::FanEnd => self.fe,
            SensorEnd::Base => self.ba,
        }
    }
}

/// One catalogued CWRU record (a `.mat` file). All fields are public facts.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct CatalogEntry {
    /// File number on the CWRU server (`<number>.mat`).
    pub number: u32,
    /// The `X###` number of the variables inside the file (differs for 174 and 3001–3008).
    pub variable: u32,
    /// Path relative to the `cwru/` folder of the data directory.
    pub rel_path: &'static str,
    /// Sampling rate in Hz (12 000 or 48 000).
    pub fs_hz: u32,
    /// Fault label: normal, or where the seeded fault is.
    pub fault: FaultLabel,
    /// Fault diameter in thousandths of an inch (7, 14, 21, 28); `None` for normal.
    pub diameter_mils: Option<u16>,
    /// Outer-race defect position; `None` unless the fault is outer race.
    pub outer_position: Option<OuterPosition>,
    /// Motor load in hp (0–3).
    pub load_hp: u8,
    /// Nominal shaft speed for the load (1797/1772/1750/1730 rpm).
    pub nominal_rpm: u16,
    /// The `X###RPM` value stored in the file, when it has one and it is known.
    pub stored_rpm: Option<u16>,
    /// Channels the file holds.
    pub channels: Channels,
    /// Samples per channel, when known.
    pub n_samples: Option<usize>,
    /// Pinned SHA-256 of the file (lower-case hex), when known.
    pub sha256: Option<&'static str>,
    /// Whether the shared data copy holds this file.
    pub in_shared_copy: bool,
}

impl CatalogEntry {
    /// Fault diameter in inches (0.007 … 0.028); `None` for normal.
    pub fn fault_diameter_in(&self) -> Option<f64> {
        self.diameter_mils.map(|m| f64::from(m) / 1000.0)
    }

    /// The bearing end the fault was seeded at (`DriveEnd` for every catalogued fault record).
    pub fn fault_end(&self) -> Option<SensorEnd> {
        match self.fault {
            FaultLabel::Normal => None,
            _ => Some(SensorEnd::DriveEnd),
        }
    }

    /// The faulted bearing's make (NTN-equivalent for the 0.028 in faults).
    pub fn bearing(&self) -> BearingMake {
        if self.diameter_mils == Some(28) {
            BearingMake::Ntn6205Equivalent
        } else {
            BearingMake::Skf6205
        }
    }

    /// Sampling rate as `f64` Hz.
    pub fn fs(&self) -> f64 {
        f64::from(self.fs_hz)
    }

    /// Best known shaft speed: stored when known, else nominal.
    pub fn rpm(&self) -> f64 {
        f64::from(self.stored_rpm.unwrap_or(self.nominal_rpm))
    }

    /// A short class name such as `IR014`, `OR021@6`, `normal`.
    pub fn class_name(&self) -> String {
        let d = self.diameter_mils.unwrap_or(0);
        match (self.fault, self.outer_position) {
            (FaultLabel::Normal, _) => "normal".to_owned(),
            (FaultLabel::InnerRace, _) => format!("IR{d:03}"),
            (FaultLabel::Ball, _) => format!("B{d:03}"),
            (FaultLabel::OuterRace, Some(p)) => format!("OR{d:03}@{}", p.clock()),
            (FaultLabel::OuterRace, None) => format!("OR{d:03}"),
        }
    }
}

/// Every catalogued record: the shared copy's 74 files followed by the 42 it lacks, each group
/// sorted by sampling rate then number.
pub fn catalog() -> impl Iterator<Item = &'static CatalogEntry> {
    catalog_table::PRESENT
        .iter()
        .chain(catalog_absent::ABSENT.iter())
}

/// Look a record up by file number.
pub fn entry(number: u32) -> Option<&'static CatalogEntry> {
    catalog().find(|e| e.number == number)
}

/// A catalog filter; unset criteria match everything.
///
/// ```
/// use bearing_data::{Query, FaultLabel};
/// // "all 12 kHz drive-end 0.014 in records at 2 hp"
/// let hits: Vec<u32> = Query::new().fs_hz(12_000).diameter_in(0.014).load_hp(2)
///     .run().iter().map(|e| e.number).collect();
/// assert_eq!(hits, vec![171, 187, 199]);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Query {
    fs_hz: Option<u32>,
    fault: Option<FaultLabel>,
    diameter_mils: Option<u16>,
    outer_position: Option<OuterPosition>,
    load_hp: Option<u8>,
    fault_end: Option<SensorEnd>,
    in_shared_copy: Option<bool>,
}

impl Query {
    /// A query that matches every record.
    pub fn new() -> Self {
        Self::default()
    }
    /// Only records sampled at `hz`.
    pub fn fs_hz(mut self, hz: u32) -> Self {
        self.fs_hz = Some(hz);
        self
    }
    /// Only records with this fault label.
    pub fn fault(mut self, fault: FaultLabel) -> Self {
        self.fault = Some(fault);
        self
    }
    /// Only records with this fault diameter in inches (rounded to the nearest 0.001 in).
    pub fn diameter_in(mut self, inches: f64) -> Self {
        let mils = (inches * 1000.0).round();
        // Out-of-range input matches nothing rather than panicking.
        self.diameter_mils = Some(if (0.0..=1000.0).contains(&mils) {
            mils as u16
        } else {
            u16::MAX
        });
        self
    }
    /// Only records with this fault diameter in thousandths of an inch.
    pub fn diameter_mils(mut self, mils: u16) -> Self {
        self.diameter_mils = Some(mils);
        self
    }
    /// Only outer-race records at this position.
    pub fn outer_position(mut self, p: OuterPosition) -> Self {
        self.outer_position = Some(p);
        self
    }
    /// Only records at this motor load (hp).
    pub fn load_hp(mut self, hp: u8) -> Self {
        self.load_hp = Some(hp);
        self
    }
    /// Only fault records seeded at this end (every catalogued fault is drive-end; normal
    /// records have no fault end and do not match).
    pub fn fault_end(mut self, end: SensorEnd) -> Self {
        self.fault_end = Some(end);
        self
    }
    /// Only records the shared copy holds (`true`) or lacks (`false`).
    pub fn in_shared_copy(mut self, yes: bool) -> Self {
        self.in_shared_copy = Some(yes);
        self
    }

    /// Whether `e` satisfies every set criterion.
    pub fn matches(&self, e: &CatalogEntry) -> bool {
        self.fs_hz.is_none_or(|v| v == e.fs_hz)
            && self.fault.is_none_or(|v| v == e.fault)
            && self
                .diameter_mils
                .is_none_or(|v| Some(v) == e.diameter_mils)
            && self
                .outer_position
                .is_none_or(|v| Some(v) == e.outer_position)
            && self.load_hp.is_none_or(|v| v == e.load_hp)
            && self.fault_end.is_none_or(|v| Some(v) == e.fault_end())
            && self.in_shared_copy.is_none_or(|v| v == e.in_shared_copy)
    }

    /// The matching records, sorted by number.
    pub fn run(&self) -> Vec<&'static CatalogEntry> {
        let mut v: Vec<&'static CatalogEntry> = catalog().filter(|e| self.matches(e)).collect();
        v.sort_by_key(|e| e.number);
        v
    }
}
