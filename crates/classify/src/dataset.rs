//! Feature rows with per-window metadata (class, recording, load, fault size).
//!
//! The metadata is what makes honest evaluation possible: the protocols in [`crate::protocol`]
//! group windows by recording, load or fault size so that a test window never shares its
//! recording (or its seeded bearing) with a training window.

use serde::{Deserialize, Serialize};

use crate::error::{ClassifyError, Result};

/// Metadata of one window.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct WindowMeta {
    /// Class index into [`Dataset::class_names`].
    pub class: usize,
    /// Recording identifier (e.g. the CWRU file number `"105"`).
    pub recording: String,
    /// Motor load in hp (CWRU: 0–3).
    pub load_hp: u32,
    /// Fault diameter in thousandths of an inch (7, 14, 21, 28); `None` for normal windows.
    pub fault_size_mils: Option<u32>,
    /// Shaft speed in rpm, when the protocols should group by it ([`crate::leave_one_condition_out`]
    /// with [`crate::OperatingCondition::Speed`]); `None` when unknown or irrelevant.
    #[serde(default)]
    pub speed_rpm: Option<u32>,
    /// Position of the window within its recording (0 = first in time).
    pub index_in_recording: usize,
}

/// A validated feature matrix (row-major, finite) with one [`WindowMeta`] per row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Dataset {
    class_names: Vec<String>,
    feature_names: Vec<String>,
    n_features: usize,
    x: Vec<f64>,
    meta: Vec<WindowMeta>,
}

impl Dataset {
    /// Build and validate a dataset.
    ///
    /// # Errors
    /// [`ClassifyError::Empty`] (no rows, no classes or no features),
    /// [`ClassifyError::LengthMismatch`] (rows vs metadata, row widths vs feature names),
    /// [`ClassifyError::NonFinite`], [`ClassifyError::UnknownClass`].
    pub fn new(
        class_names: Vec<String>,
        feature_names: Vec<String>,
        rows: &[Vec<f64>],
        meta: Vec<WindowMeta>,
    ) -> Result<Self> {
        if rows.is_empty() {
            return Err(ClassifyError::Empty { what: "rows" });
        }
        if class_names.is_empty() {
            return Err(ClassifyError::Empty {
                what: "class_names",
            });
        }
        if feature_names.is_empty() {
            return Err(ClassifyError::Empty {
                what: "feature_names",
            });
        }
        if rows.len() != meta.len() {
            return Err(ClassifyError::LengthMismatch {
                what: "rows vs metadata",
                expected: rows.len(),
                found: meta.len(),
            });
        }
        let d = feature_names.len();
        let mut x = Vec::with_capacity(rows.len() * d);
        for (i, (row, m)) in rows.iter().zip(&meta).enumerate() {
            if row.len() != d {
                return Err(ClassifyError::LengthMismatch {
                    what: "row width vs feature names",
                    expected: d,
                    found: row.len(),
                });
            }
            if let Some((j, &v)) = row.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(ClassifyError::NonFinite {
                    row: i,
                    column: j,
                    value: v,
                });
            }
            if m.class >= class_names.len() {
                return Err(ClassifyError::UnknownClass {
                    label: m.class,
                    n_classes: class_names.len(),
                });
            }
            x.extend_from_slice(row);
        }
        Ok(Self {
            class_names,
            feature_names,
            n_features: d,
            x,
            meta,
        })
    }

    /// Start an incremental build, one recording at a time.
    pub fn builder(class_names: Vec<String>, feature_names: Vec<String>) -> DatasetBuilder {
        DatasetBuilder {
            class_names,
            feature_names,
            rows: Vec::new(),
            meta: Vec::new(),
        }
    }

    /// Number of windows.
    pub fn n_samples(&self) -> usize {
        self.meta.len()
    }

    /// Number of features per window.
    pub fn n_features(&self) -> usize {
        self.n_features
    }

    /// Number of declared classes.
    pub fn n_classes(&self) -> usize {
        self.class_names.len()
    }

    /// Class names, indexed by class label.
    pub fn class_names(&self) -> &[String] {
        &self.class_names
    }

    /// Feature (column) names.
    pub fn feature_names(&self) -> &[String] {
        &self.feature_names
    }

    /// Features of window `i` (panics if `i` is out of range, like slice indexing).
    #[track_caller]
    pub fn row(&self, i: usize) -> &[f64] {
        &self.x[i * self.n_features..(i + 1) * self.n_features]
    }

    /// Class label of window `i`.
    #[track_caller]
    pub fn label(&self, i: usize) -> usize {
        self.meta[i].class
    }

    /// Metadata of every window.
    pub fn meta(&self) -> &[WindowMeta] {
        &self.meta
    }

    /// Check a list of indices against the dataset.
    pub(crate) fn check_indices(&self, idx: &[usize], what: &'static str) -> Result<()> {
        if idx.is_empty() {
            return Err(ClassifyError::Empty { what });
        }
        if let Some(&bad) = idx.iter().find(|&&i| i >= self.n_samples()) {
            return Err(ClassifyError::IndexOutOfRange {
                index: bad,
                len: self.n_samples(),
            });
        }
        Ok(())
    }
}

/// Incremental [`Dataset`] construction.
#[derive(Debug, Clone)]
pub struct DatasetBuilder {
    class_names: Vec<String>,
    feature_names: Vec<String>,
    rows: Vec<Vec<f64>>,
    meta: Vec<WindowMeta>,
}

/// Identity of one recording, for [`DatasetBuilder::add_recording`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RecordingInfo {
    /// Class index.
    pub class: usize,
    /// Recording identifier.
    pub recording: String,
    /// Motor load in hp.
    pub load_hp: u32,
    /// Fault size in mils, `None` for normal.
    pub fault_size_mils: Option<u32>,
    /// Shaft speed in rpm, `None` when unknown (see [`WindowMeta::speed_rpm`]).
    #[serde(default)]
    pub speed_rpm: Option<u32>,
}

impl DatasetBuilder {
    /// Append the feature rows of one recording, in time order.
    pub fn add_recording(&mut self, info: &RecordingInfo, rows: Vec<Vec<f64>>) -> &mut Self {
        for (k, row) in rows.into_iter().enumerate() {
            self.meta.push(WindowMeta {
                class: info.class,
                recording: info.recording.clone(),
                load_hp: info.load_hp,
                fault_size_mils: info.fault_size_mils,
                speed_rpm: info.speed_rpm,
                index_in_recording: k,
            });
            self.rows.push(row);
        }
        self
    }

    /// Validate and build (see [`Dataset::new`]).
    ///
    /// # Errors
    /// As [`Dataset::new`].
    pub fn build(self) -> Result<Dataset> {
        Dataset::new(self.class_names, self.feature_names, &self.rows, self.meta)
    }
}
