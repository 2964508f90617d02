//! A dissertation table as classification problems: which recordings a table pools
//! ([`DissTable::recording_keys`]), the dataset of one cell (one crack size, or every size for
//! leave one fault size out; [`table_cell_dataset`]), the protocols reported for it
//! ([`DissTable::protocols`]) and its evaluation ([`evaluate_table_cell`]).
//!
//! A cell pools the table's conditions (one load or speed, or all four for the load- and
//! speed-variant tables 2.7, 3.5, 4.6, 5.6, 4.11, 5.11). Decisions (the shared normal recording
//! cut into one segment per condition, every n-th window of pooled recordings):
//! `docs/equations/xtask-chapters.md`, "Protocols".

use serde::Serialize;

use crate::dissertation::{Condition, DissTable};
use crate::evaluate::{CellOutcome, CellRecording, Dataset, Protocol};
use crate::recordings::{RecKey, cwru_key, multi_key};
use crate::{ClassifierKind, PipelineError, Result};

/// The conditions a run covers: CWRU loads (hp) and substitute speeds (rpm).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Scope {
    /// CWRU loads run.
    pub loads: Vec<u8>,
    /// Substitute speeds run.
    pub rpms: Vec<u32>,
}

/// A cell of one of our tables: measured, or not applicable with the reason.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Cell {
    /// Measured.
    Measured(CellOutcome),
    /// The protocol cannot be applied here.
    NotApplicable(String),
}

impl DissTable {
    /// Whether the table is on the CWRU data (else the multi-fault substitute).
    pub fn is_cwru(&self) -> bool {
        self.dataset == "cwru"
    }

    /// Whether `scope` runs this table (a pooled table needs more than one condition).
    pub fn selected(&self, scope: &Scope) -> bool {
        match self.condition {
            Condition::FixedLoad { load_hp } => scope.loads.contains(&load_hp),
            Condition::FixedSpeed { rpm } => scope.rpms.contains(&rpm),
            Condition::LoadVariant => scope.loads.len() > 1,
            Condition::SpeedVariant => scope.rpms.len() > 1,
        }
    }

    /// Conditions (load hp or rpm) the table pools within `scope`.
    pub fn conditions(&self, scope: &Scope) -> Vec<u32> {
        match self.condition {
            Condition::FixedLoad { load_hp } => vec![u32::from(load_hp)],
            Condition::FixedSpeed { rpm } => vec![rpm],
            Condition::LoadVariant => scope.loads.iter().map(|&l| u32::from(l)).collect(),
            Condition::SpeedVariant => scope.rpms.clone(),
        }
    }

    /// The recording behind (class, condition, crack index).
    pub fn recording_key(&self, class: &str, cond: u32, crack: usize) -> RecKey {
        if self.is_cwru() {
            cwru_key(class, cond as u8, crack)
        } else {
            multi_key(class, cond, crack)
        }
    }

    /// Every recording the table needs within `scope`, each once.
    pub fn recording_keys(&self, scope: &Scope) -> Vec<RecKey> {
        let mut v = Vec::new();
        for cond in self.conditions(scope) {
            for ci in 0..self.cracks.len() {
                for c in &self.classes {
                    let k = self.recording_key(c, cond, ci);
                    if !v.contains(&k) {
                        v.push(k);
                    }
                }
            }
        }
        v
    }

    /// Crack size `ci` as printed ("0.007" in, "3" mm) in mils (thousandths of an inch).
    ///
    /// # Errors
    /// [`PipelineError::BadCrackSize`] when the printed size is not a number.
    pub fn crack_mils(&self, ci: usize) -> Result<u32> {
        let text = self.cracks.get(ci).map_or("", String::as_str);
        let v: f64 = text.parse().map_err(|_| PipelineError::BadCrackSize {
            table: self.id.clone(),
            size: text.to_string(),
        })?;
        let inches = if self.crack_unit == "mm" { v / 25.4 } else { v };
        Ok((inches * 1000.0).round() as u32)
    }

    /// Leave one condition out for this table: the load for CWRU, the speed for the substitute.
    pub fn condition_protocol(&self) -> Protocol {
        if self.is_cwru() {
            Protocol::LeaveOneLoadOut
        } else {
            Protocol::LeaveOneSpeedOut
        }
    }

    /// Whether the table pools several conditions (load- or speed-variant).
    pub fn pooled(&self) -> bool {
        matches!(
            self.condition,
            Condition::LoadVariant | Condition::SpeedVariant
        )
    }

    /// The protocols reported for the table, the dissertation's (random windows) first.
    pub fn protocols(&self) -> Vec<Protocol> {
        let cond = self.condition_protocol();
        if self.pooled() {
            vec![
                Protocol::RandomWindows,
                Protocol::TimeBlocked,
                cond,
                Protocol::LeaveOneFaultSizeOut,
            ]
        } else {
            vec![
                Protocol::RandomWindows,
                Protocol::TimeBlocked,
                Protocol::LeaveOneFaultSizeOut,
                cond,
            ]
        }
    }
}

/// What a cell's recordings are, for [`table_cell_dataset`]: a recording's identifier and the
/// window energies of one source (observer or raw signal) over it, in time order.
pub trait CellSource {
    /// Identifier of the recording `k` (unique within a cell).
    ///
    /// # Errors
    /// When `k` is not available.
    fn id(&self, k: &RecKey) -> Result<String>;
    /// Window energies of `k`, earliest first.
    ///
    /// # Errors
    /// When they were not computed.
    fn energies(&self, k: &RecKey) -> Result<&[f64]>;
}

/// The recordings of one cell (every condition of `scope` the table pools, the crack sizes
/// `cracks`), each with its window energies and what it is.
fn cell_recordings(
    d: &DissTable,
    scope: &Scope,
    src: &dyn CellSource,
    cracks: &[usize],
) -> Result<Vec<CellRecording>> {
    let conds = d.conditions(scope);
    let Some(&first) = conds.first() else {
        return Err(PipelineError::EmptyScope {
            table: d.id.clone(),
        });
    };
    let load = |c: u32| {
        if d.is_cwru() { (c, None) } else { (0, Some(c)) }
    };
    // Pooled tables keep every n-th window of each recording (n = number of pooled conditions),
    // so a class has as many windows as in a single cell (the SVM's cost grows with n²).
    let stride = conds.len();
    let mut recs = Vec::new();
    for (class_idx, class) in d.classes.iter().enumerate() {
        if class == "normal" {
            // One normal recording (or one per speed for the substitute) serves every crack
            // size; when several conditions are pooled and they share one recording (CWRU 97),
            // it is cut into one contiguous pseudo-segment per condition, never duplicated.
            let k0 = d.recording_key(class, first, 0);
            if conds.iter().all(|&c| d.recording_key(class, c, 0) == k0) {
                let id = src.id(&k0)?;
                let e = src.energies(&k0)?;
                let per = e.len() / conds.len();
                for (si, &c) in conds.iter().enumerate() {
                    let (load_hp, speed_rpm) = load(c);
                    recs.push(CellRecording {
                        recording: if conds.len() > 1 {
                            format!("{id} (segment {} of {})", si + 1, conds.len())
                        } else {
                            id.clone()
                        },
                        class: class_idx,
                        load_hp,
                        speed_rpm,
                        fault_size_mils: None,
                        energies: e[si * per..(si + 1) * per].to_vec(),
                    });
                }
                continue;
            }
        }
        // Every other recording: one per (crack, condition), every `stride`-th window.
        let crack_list: Vec<Option<usize>> = if class == "normal" {
            vec![None]
        } else {
            cracks.iter().map(|&ci| Some(ci)).collect()
        };
        for crack in crack_list {
            for &c in &conds {
                let k = d.recording_key(class, c, crack.unwrap_or(0));
                let (load_hp, speed_rpm) = load(c);
                recs.push(CellRecording {
                    recording: src.id(&k)?,
                    class: class_idx,
                    load_hp,
                    speed_rpm,
                    fault_size_mils: crack.map(|ci| d.crack_mils(ci)).transpose()?,
                    energies: src.energies(&k)?.iter().step_by(stride).copied().collect(),
                });
            }
        }
    }
    Ok(recs)
}

/// The dataset of one cell of table `d` (crack size `ci`, or every size with `ci = None`),
/// classes named by the table's labels ([`DissTable::class_labels`]).
///
/// # Errors
/// A recording or its energies missing from `src`, an unreadable crack size, or the dataset's
/// error ([`crate::cell_dataset`]).
pub fn table_cell_dataset(
    d: &DissTable,
    scope: &Scope,
    src: &dyn CellSource,
    ci: Option<usize>,
) -> Result<Dataset> {
    let cracks: Vec<usize> = match ci {
        Some(c) => vec![c],
        None => (0..d.cracks.len()).collect(),
    };
    let recs = cell_recordings(d, scope, src, &cracks)?;
    crate::cell_dataset(d.class_labels(), &recs)
}

/// Evaluate one cell (crack size `ci`) of table `d` under `protocol`, repeated over `seeds` for
/// the random split. Leave one fault size out holds size `ci` out of the pooled sizes; leave one
/// condition out within one load or speed is not applicable (one recording per class) and says
/// so.
///
/// # Errors
/// As [`table_cell_dataset`], [`crate::cell_plan`] and [`crate::evaluate_cell`].
pub fn evaluate_table_cell(
    d: &DissTable,
    scope: &Scope,
    src: &dyn CellSource,
    ci: usize,
    protocol: Protocol,
    seeds: u64,
    clf: ClassifierKind,
) -> Result<Cell> {
    let (data, held) = match protocol {
        Protocol::LeaveOneFaultSizeOut => (
            table_cell_dataset(d, scope, src, None)?,
            Some(d.crack_mils(ci)?),
        ),
        Protocol::LeaveOneLoadOut | Protocol::LeaveOneSpeedOut if !d.pooled() => {
            let cond = if d.is_cwru() { "load" } else { "speed" };
            return Ok(Cell::NotApplicable(format!(
                "one recording per class at a fixed {cond}: grouping by recording would leave its class out of training"
            )));
        }
        _ => (table_cell_dataset(d, scope, src, Some(ci))?, None),
    };
    let plan = crate::cell_plan(&data, protocol, seeds, held)?;
    Ok(Cell::Measured(crate::evaluate_cell(&data, &plan, clf)?))
}
