//! The recordings behind each dissertation table: a [`RecKey`] names one (class, load or speed,
//! crack size), [`load`] reads it from the CWRU data (drive end, decimated to 12 kHz) or
//! simulates it (the calibrated rig when the data is absent; the SHSE multi-fault substitute
//! always), cut into the scored segment the chapters window. Which record backs which cell,
//! the fit segment and the seeds are fixed here, so every user of the tables gets the same
//! datasets. Decisions: `docs/equations/xtask-chapters.md`, "Data".

use crate::{PipelineError, Result, SimKind};
use bearing_data::{FaultLabel, LoadOptions, OuterPosition, Query};
use bearing_model::FaultClass;
use calibrated_rig::ExcitationCache;
use std::path::Path;

/// Sampling rate of the CWRU tables (12 kHz drive end).
pub const CWRU_FS: f64 = 12_000.0;
/// Sampling rate of the simulated multi-fault substitute.
pub const MULTI_FS: f64 = 12_000.0;
/// Seconds at the start of every healthy recording used to fit models (never scored).
pub const FIT_SECONDS: f64 = 1.0;
/// Samples skipped at the start of every fault recording (observer start-up transient).
pub const WARMUP: usize = 600;
/// Samples per window on the multi-fault substitute: 50 ms, i.e. at least one outer-race impact
/// period at 300 rpm, so that window energies are not dominated by whether a window holds an
/// impact at all.
pub const MULTI_WINDOW: usize = 600;
/// Windows per recording on the multi-fault substitute (full configuration): Table 4.1's 400
/// per class (20 s of simulated signal per recording).
pub const MULTI_WINDOWS: usize = 400;

/// What a recording is, independent of where it comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RecKey {
    /// CWRU: class index (0 normal, 1 ball, 2 outer, 3 inner), load, crack index (0.007/0.014/
    /// 0.021 in). Normal is always `(0, 0, 0)`: one recording serves every load and size.
    Cwru {
        /// Class index.
        class: u8,
        /// Load hp.
        load: u8,
        /// Crack index.
        crack: u8,
    },
    /// Substitute: class index (0 normal, 1 IR, 2 OR, 3 ball, 4 IR-ball, 5 OR-ball, 6 IR-OR,
    /// 7 IR-OR-ball), speed, crack index (3 / 6 mm). Normal has crack 0 at every speed.
    Multi {
        /// Class index.
        class: u8,
        /// Shaft speed.
        rpm: u32,
        /// Crack index.
        crack: u8,
    },
}

const CWRU_CLASSES: [&str; 4] = ["normal", "ball", "outer", "inner"];
const MULTI_CLASSES: [&str; 8] = [
    "normal",
    "inner",
    "outer",
    "ball",
    "inner_ball",
    "outer_ball",
    "inner_outer",
    "inner_outer_ball",
];
const CWRU_CRACKS_IN: [f64; 3] = [0.007, 0.014, 0.021];
const MULTI_CRACKS_MM: [f64; 2] = [3.0, 6.0];

impl RecKey {
    /// The dataset the recording belongs to, for reports.
    pub fn dataset(&self) -> &'static str {
        match self {
            RecKey::Cwru { .. } => "CWRU",
            RecKey::Multi { .. } => "multi-fault substitute (simulated)",
        }
    }

    /// Class index (the row order of the dataset's tables).
    pub fn class_index(&self) -> usize {
        match *self {
            RecKey::Cwru { class, .. } | RecKey::Multi { class, .. } => usize::from(class),
        }
    }

    /// The tables' label of the recording's class ("Normal", "OR", "IR-Ball", …).
    pub fn class_label(&self) -> String {
        let names: &[&str] = match self {
            RecKey::Cwru { .. } => &CWRU_CLASSES,
            RecKey::Multi { .. } => &MULTI_CLASSES,
        };
        crate::dissertation::class_label(names.get(self.class_index()).copied().unwrap_or("?"))
    }
}

/// Key of a CWRU table cell's recording.
pub fn cwru_key(class: &str, load: u8, crack: usize) -> RecKey {
    let c = CWRU_CLASSES.iter().position(|x| *x == class).unwrap_or(0) as u8;
    if c == 0 {
        RecKey::Cwru {
            class: 0,
            load: 0,
            crack: 0,
        }
    } else {
        RecKey::Cwru {
            class: c,
            load,
            crack: crack as u8,
        }
    }
}

/// Key of a substitute table cell's recording.
pub fn multi_key(class: &str, rpm: u32, crack: usize) -> RecKey {
    let c = MULTI_CLASSES.iter().position(|x| *x == class).unwrap_or(0) as u8;
    RecKey::Multi {
        class: c,
        rpm,
        crack: if c == 0 { 0 } else { crack as u8 },
    }
}

/// A recording of the tables, ready for the observers.
#[derive(Debug, Clone)]
pub struct Rec {
    /// Human id: CWRU file number ("105", "97 (48 kHz → 12 kHz)") or "sim:...".
    pub id: String,
    /// Sampling rate in Hz.
    pub fs: f64,
    /// Shaft speed in rpm.
    pub rpm: f64,
    /// The measured (or simulated) acceleration.
    pub signal: Vec<f64>,
    /// First sample of the scored segment (after the fit segment or the warm-up).
    pub window_start: usize,
    /// Samples per window.
    pub window_len: usize,
    /// Windows to cut.
    pub n_windows: usize,
}

/// The healthy recording that serves `k` (its fit segment identifies the models).
pub fn healthy_key(k: &RecKey) -> RecKey {
    match *k {
        RecKey::Cwru { .. } => RecKey::Cwru {
            class: 0,
            load: 0,
            crack: 0,
        },
        RecKey::Multi { rpm, .. } => RecKey::Multi {
            class: 0,
            rpm,
            crack: 0,
        },
    }
}

/// CWRU record number for a key (12 kHz drive end, OR at 6 o'clock; normal 97).
///
/// # Errors
/// [`PipelineError::Catalog`] when the catalog does not name exactly one record.
pub fn cwru_number(class: u8, load: u8, crack: u8) -> Result<u32> {
    if class == 0 {
        return Ok(97);
    }
    let fault = match class {
        1 => FaultLabel::Ball,
        2 => FaultLabel::OuterRace,
        _ => FaultLabel::InnerRace,
    };
    let mut q = Query::new()
        .fs_hz(12_000)
        .fault(fault)
        .diameter_in(CWRU_CRACKS_IN[crack as usize])
        .load_hp(load);
    if fault == FaultLabel::OuterRace {
        q = q.outer_position(OuterPosition::Centered6);
    }
    let hits = q.run();
    match hits.as_slice() {
        [e] => Ok(e.number),
        other => Err(PipelineError::Catalog {
            query: format!(
                "class {class} load {load} hp crack {} in",
                CWRU_CRACKS_IN[crack as usize]
            ),
            found: other.len(),
        }),
    }
}

/// How many windows of what length a recording of the tables is cut into.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordingPlan {
    /// Samples per window on the CWRU tables.
    pub window_len: usize,
    /// Windows per CWRU recording at most.
    pub windows_per_rec: usize,
    /// Windows per substitute recording (its window is [`MULTI_WINDOW`]).
    pub multi_windows: usize,
}

/// Load (CWRU, from `dir`, drive end at 12 kHz) or simulate (no `dir`: the calibrated rig at
/// the record's conditions; and always for the substitute) the recording `k`, cut to what
/// `plan` scores.
///
/// # Errors
/// [`PipelineError::Recording`] when a CWRU file cannot be read or decimated,
/// [`PipelineError::Catalog`] when the catalog does not name exactly one record for `k`, or the
/// simulation's error.
pub fn load(dir: Option<&Path>, plan: &RecordingPlan, k: &RecKey) -> Result<Rec> {
    load_shared(dir, plan, k, &ExcitationCache::default())
}

/// [`load`], the substitute's spall excitations looked up in, or added to, `excitations`: the
/// recordings of one speed and fault size share each spall's 5-DOF excitation (their
/// backgrounds, strike gates and random parts are their own), so loading the eight classes
/// of one condition with one cache simulates three spalls instead of twelve. The result is
/// the same with or without a shared cache.
///
/// # Errors
/// As [`load`].
pub fn load_shared(
    dir: Option<&Path>,
    plan: &RecordingPlan,
    k: &RecKey,
    excitations: &ExcitationCache,
) -> Result<Rec> {
    match *k {
        RecKey::Cwru { class, load, crack } => cwru_rec(dir, plan, class, load, crack),
        RecKey::Multi { class, rpm, crack } => multi_rec(plan, class, rpm, crack, excitations),
    }
}

/// The CWRU recording of `class`, `load` and `crack` ([`RecKey::Cwru`]): read from `dir`, or
/// simulated CWRU-like without it.
fn cwru_rec(
    dir: Option<&Path>,
    plan: &RecordingPlan,
    class: u8,
    load: u8,
    crack: u8,
) -> Result<Rec> {
    let (wlen, nwin) = (plan.window_len, plan.windows_per_rec);
    let fit = (FIT_SECONDS * CWRU_FS) as usize;
    let start = if class == 0 { fit } else { WARMUP };
    let need = start + wlen * nwin;
    match dir {
        Some(dir) => {
            let number = cwru_number(class, load, crack)?;
            let bad = |source| PipelineError::Recording { number, source };
            let rec =
                bearing_data::load_record(dir, number, &LoadOptions::unverified()).map_err(bad)?;
            let rpm = rec.rpm().value;
            let mut sig = rec.de_at(CWRU_FS).map_err(bad)?.into_owned();
            let id = if rec.fs_hz() != CWRU_FS {
                format!("{number} ({} kHz → 12 kHz)", rec.fs_hz() / 1000.0)
            } else {
                number.to_string()
            };
            sig.truncate(need);
            let n_windows = ((sig.len().saturating_sub(start)) / wlen).min(nwin);
            Ok(Rec {
                id,
                fs: CWRU_FS,
                rpm,
                signal: sig,
                window_start: start,
                window_len: wlen,
                n_windows,
            })
        }
        None => {
            let rpm = [1797.0, 1772.0, 1750.0, 1730.0][load as usize % 4];
            let fault = ["none", "ball", "outer", "inner"][class as usize];
            let fc = [
                FaultClass::None,
                FaultClass::Ball,
                FaultClass::Outer,
                FaultClass::Inner,
            ][class as usize];
            let size_in = CWRU_CRACKS_IN[crack as usize];
            let seed = 1000 + u64::from(class) * 100 + u64::from(load) * 10 + u64::from(crack);
            let sig = crate::simulate(SimKind::Cwru, fc, size_in, rpm, CWRU_FS, need, seed)?;
            Ok(Rec {
                id: format!(
                    "sim:{fault}:{load}hp:{:.3}in",
                    CWRU_CRACKS_IN[crack as usize]
                ),
                fs: CWRU_FS,
                rpm,
                signal: sig,
                window_start: start,
                window_len: wlen,
                n_windows: nwin,
            })
        }
    }
}

/// The simulated multi-fault substitute's recording of `class`, `rpm` and `crack`
/// ([`RecKey::Multi`]), its spall excitations shared through `excitations`.
fn multi_rec(
    plan: &RecordingPlan,
    class: u8,
    rpm: u32,
    crack: u8,
    excitations: &ExcitationCache,
) -> Result<Rec> {
    let wlen = MULTI_WINDOW;
    let nwin = plan.multi_windows;
    let fit = (FIT_SECONDS * MULTI_FS) as usize;
    let start = if class == 0 { fit } else { WARMUP };
    let need = start + wlen * nwin;
    let fault = [
        "none",
        "inner",
        "outer",
        "ball",
        "inner+ball",
        "outer+ball",
        "inner+outer",
        "inner+outer+ball",
    ][class as usize];
    let fc = [
        FaultClass::None,
        FaultClass::Inner,
        FaultClass::Outer,
        FaultClass::Ball,
        FaultClass::InnerBall,
        FaultClass::OuterBall,
        FaultClass::InnerOuter,
        FaultClass::InnerOuterBall,
    ][class as usize];
    let size_mm = MULTI_CRACKS_MM[crack as usize];
    let seed = 2000 + u64::from(class) * 1000 + u64::from(rpm) + u64::from(crack) * 7;
    // one excitation seed per speed and size, whatever the class: the spalls of a
    // combined fault are those of the single-fault recordings
    let excitation_seed = 9000 + u64::from(rpm) + u64::from(crack) * 7;
    let sig = crate::simulate_substitute(
        fc,
        size_mm,
        f64::from(rpm),
        MULTI_FS,
        need,
        seed,
        excitation_seed,
        excitations,
    )?;
    Ok(Rec {
        id: if class == 0 {
            format!("sim:normal:{rpm}rpm")
        } else {
            format!("sim:{fault}:{size_mm}mm:{rpm}rpm")
        },
        fs: MULTI_FS,
        rpm: f64::from(rpm),
        signal: sig,
        window_start: start,
        window_len: wlen,
        n_windows: nwin,
    })
}

/// What one source (an observer, or the raw signal with `None`) yields over one recording of
/// the tables: its window energies (eq. 2.46 / 5.33) over the scored segment, a short residual
/// trace (0.1 s) for figures, and RMS(residual) / RMS(signal) over the scored windows.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceFeatures {
    /// Window energies, earliest first.
    pub energies: Vec<f64>,
    /// The first 0.1 s of the scored residual.
    pub trace: Vec<f64>,
    /// RMS(residual) / RMS(signal) over the scored windows (1 for the raw signal).
    pub rms_ratio: f64,
}

/// Run `method` (with the gains `tuning`, on the models `prepared` from the recording's healthy
/// fit segment) over `rec`, or take the raw signal when `method` is `None`, and window the
/// scored segment. `input`: the machine model's input over `rec` when computed beforehand
/// ([`crate::Prepared::machine_input`], once per recording for every method that takes it;
/// `None` computes it when needed).
///
/// # Errors
/// The observer's error, or [`PipelineError::TooShort`] when the scored segment holds no
/// complete window.
pub fn source_features(
    method: Option<(crate::Method, &crate::Prepared, &crate::Tuning)>,
    rec: &Rec,
    input: Option<&[f64]>,
) -> Result<SourceFeatures> {
    let full = match method {
        Some((m, prep, t)) => crate::residual_with_input(m, prep, t, &rec.signal, input)?,
        None => rec.signal.clone(),
    };
    let residual = full.get(rec.window_start..).unwrap_or(&[]);
    let signal = rec.signal.get(rec.window_start..).unwrap_or(&[]);
    let scored = (rec.window_len * rec.n_windows)
        .min(residual.len())
        .min(signal.len());
    let rms_ratio = crate::rms_ratio(&residual[..scored], &signal[..scored]);
    let energies = crate::window_energies(residual, rec.window_len, rec.n_windows)?;
    let trace_len = residual.len().min(rec.fs as usize / 10);
    Ok(SourceFeatures {
        energies,
        trace: residual[..trace_len].to_vec(),
        rms_ratio,
    })
}
