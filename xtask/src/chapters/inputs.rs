//! Recordings behind the tables: CWRU drive-end records (or simulated CWRU-like ones when the
//! data is absent) and the simulated substitute for the private SHSE multi-fault data.
//!
//! Records are loaded (or simulated) once per run and shared by every chapter ([`Cache`]).

use super::pipeline::Config;
use crate::common::Context;
use ::pipeline as pl;
use anyhow::Context as _;
use bearing_data::{FaultLocation, LoadOptions, OuterPosition, Query};
use bearing_model::FaultClass;
use indicatif::ProgressBar;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

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

/// A recording ready for the observers.
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

/// Is the CWRU data directory there?
pub fn cwru_available(ctx: &Context) -> bool {
    data_dir(ctx).is_some()
}

fn data_dir(ctx: &Context) -> Option<PathBuf> {
    let loc = bearing_data::DataLocation::resolve(ctx.data_dir_flag.as_deref(), &ctx.root).ok()?;
    let p = loc.path()?.to_path_buf();
    bearing_data::cwru_dir(&p)
        .join("normal")
        .is_dir()
        .then_some(p)
}

/// Recordings loaded or simulated so far (shared by all chapters of one run).
#[derive(Default)]
pub struct Cache {
    recs: BTreeMap<RecKey, Rec>,
    cwru_sim: bool,
}

impl Cache {
    /// Load or simulate every key not yet present (in parallel; order-independent results).
    pub fn load_all(
        &mut self,
        ctx: &Context,
        cfg: &Config,
        keys: &[RecKey],
        pb: &ProgressBar,
    ) -> anyhow::Result<()> {
        let dir = data_dir(ctx);
        if dir.is_none() {
            self.cwru_sim = true;
        }
        // Healthy references first: every fault key needs its normal.
        let mut todo: Vec<RecKey> = Vec::new();
        for k in keys {
            for kk in [healthy_key(k), *k] {
                if !self.recs.contains_key(&kk) && !todo.contains(&kk) {
                    todo.push(kk);
                }
            }
        }
        let loaded: Vec<anyhow::Result<(RecKey, Rec)>> = todo
            .par_iter()
            .map(|k| {
                let r = make_rec(dir.as_ref(), cfg, k).map(|r| (*k, r));
                pb.inc(1);
                r
            })
            .collect();
        for r in loaded {
            let (k, rec) = r?;
            self.recs.insert(k, rec);
        }
        Ok(())
    }

    /// A loaded recording.
    pub fn get(&self, k: &RecKey) -> anyhow::Result<&Rec> {
        self.recs
            .get(k)
            .ok_or_else(|| anyhow::anyhow!("recording {k:?} was not loaded"))
    }

    /// The fit segment of the healthy recording that serves `k`.
    pub fn healthy_for(&self, k: &RecKey) -> anyhow::Result<&[f64]> {
        let h = self.get(&healthy_key(k))?;
        let n = (FIT_SECONDS * h.fs) as usize;
        h.signal.get(..n).ok_or_else(|| {
            anyhow::anyhow!("healthy recording {} shorter than its fit segment", h.id)
        })
    }

    /// Whether the CWRU recordings were simulated (data absent).
    pub fn cwru_simulated(&self) -> bool {
        self.cwru_sim
    }
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
pub fn cwru_number(class: u8, load: u8, crack: u8) -> anyhow::Result<u32> {
    if class == 0 {
        return Ok(97);
    }
    let fault = match class {
        1 => FaultLocation::Ball,
        2 => FaultLocation::OuterRace,
        _ => FaultLocation::InnerRace,
    };
    let mut q = Query::new()
        .fs_hz(12_000)
        .fault(fault)
        .diameter_in(CWRU_CRACKS_IN[crack as usize])
        .load_hp(load);
    if fault == FaultLocation::OuterRace {
        q = q.outer_position(OuterPosition::Centered6);
    }
    let hits = q.run();
    match hits.as_slice() {
        [e] => Ok(e.number),
        other => anyhow::bail!(
            "catalog query for class {class} load {load} hp crack {} in gave {} records",
            CWRU_CRACKS_IN[crack as usize],
            other.len()
        ),
    }
}

fn make_rec(dir: Option<&PathBuf>, cfg: &Config, k: &RecKey) -> anyhow::Result<Rec> {
    match *k {
        RecKey::Cwru { class, load, crack } => {
            let (wlen, nwin) = (cfg.window_len, cfg.windows_per_rec);
            let fit = (FIT_SECONDS * CWRU_FS) as usize;
            let start = if class == 0 { fit } else { WARMUP };
            let need = start + wlen * nwin;
            match dir {
                Some(dir) => {
                    let number = cwru_number(class, load, crack)?;
                    let rec = bearing_data::load_record(dir, number, &LoadOptions::unverified())
                        .with_context(|| format!("loading CWRU recording {number}.mat"))?;
                    let rpm = rec.rpm().value;
                    let mut sig = rec
                        .de_at(CWRU_FS)
                        .with_context(|| format!("decimating recording {number}"))?
                        .into_owned();
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
                    let seed =
                        1000 + u64::from(class) * 100 + u64::from(load) * 10 + u64::from(crack);
                    let sig =
                        pl::simulate(pl::SimKind::Cwru, fc, size_in, rpm, CWRU_FS, need, seed)
                            .with_context(|| {
                                format!("simulating CWRU-like {fault} at {rpm} rpm")
                            })?;
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
        RecKey::Multi { class, rpm, crack } => {
            let wlen = MULTI_WINDOW;
            let nwin = if cfg.quick {
                cfg.windows_per_rec.min(MULTI_WINDOWS)
            } else {
                MULTI_WINDOWS
            };
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
            let sig = pl::simulate(
                pl::SimKind::Shse,
                fc,
                size_mm,
                f64::from(rpm),
                MULTI_FS,
                need,
                seed,
            )
            .with_context(|| format!("simulating substitute {fault} {size_mm} mm at {rpm} rpm"))?;
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
    }
}
