//! Recordings behind the tables: CWRU drive-end records (or simulated CWRU-like ones when the
//! data is absent) and the simulated substitute for the private SHSE multi-fault data.
//!
//! Records are loaded (or simulated) once per run and shared by every chapter ([`Cache`]); which
//! record backs which cell is `pipeline::recordings`'.

use super::pipeline::Config;
use crate::common::Context;
pub use ::pipeline::recordings::{
    CWRU_FS, FIT_SECONDS, MULTI_FS, MULTI_WINDOW, MULTI_WINDOWS, Rec, RecKey, RecordingPlan,
    cwru_key, healthy_key, multi_key,
};
use indicatif::ProgressBar;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

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
        let plan = RecordingPlan {
            window_len: cfg.window_len,
            windows_per_rec: cfg.windows_per_rec,
            multi_windows: if cfg.quick {
                cfg.windows_per_rec.min(MULTI_WINDOWS)
            } else {
                MULTI_WINDOWS
            },
        };
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
                let r = ::pipeline::recordings::load(dir.as_deref(), &plan, k)
                    .map(|r| (*k, r))
                    .map_err(anyhow::Error::from);
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
