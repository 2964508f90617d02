//! Recordings behind the tables: CWRU drive-end records (or simulated CWRU-like ones when the
//! data is absent) and the simulated substitute for the private SHSE multi-fault data.
//!
//! Records are loaded (or simulated) once per run and shared by every chapter ([`Cache`]); which
//! record backs which cell is `pipeline::recordings`'.

use super::run::Config;
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

/// Window energies, the residual trace and RMS(residual)/RMS(signal) of one source on one
/// recording.
pub type SourceFeatures = (Vec<f64>, Vec<f64>, f64);

/// Recordings loaded or simulated so far (shared by all chapters of one run).
#[derive(Default)]
pub struct Cache {
    recs: BTreeMap<RecKey, Rec>,
    cwru_sim: bool,
    /// Models prepared on each healthy fit segment so far, every one with the fuzzy model and the
    /// calibrated machine, so any later chapter reuses it (the preparation is deterministic, so a
    /// model is the same whichever chapter made it).
    pub models: BTreeMap<RecKey, std::sync::Arc<::pipeline::Prepared>>,
    /// Gains tuned so far, per observer and healthy recording (a deterministic function of the
    /// model the observer runs on, which every reused [`Cache::models`] entry shares).
    pub tunings: BTreeMap<(::pipeline::Method, RecKey), ::pipeline::Tuning>,
    /// Window energies, residual trace and RMS ratio of each (observer or raw signal,
    /// recording) so far.
    pub features: BTreeMap<(Option<::pipeline::Method>, RecKey), SourceFeatures>,
    /// The machine model's input over each recording (`pipeline::Prepared::machine_input`),
    /// computed by the first observer that needs it and shared by every other (a deterministic
    /// function of the recording and its healthy model).
    pub machine_inputs: BTreeMap<RecKey, std::sync::Arc<MachineInputCell>>,
}

/// One recording's machine-model input, computed once ([`Cache::machine_inputs`]).
pub type MachineInputCell = std::sync::OnceLock<Result<Option<std::sync::Arc<Vec<f64>>>, String>>;

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
        // the substitute's spalls simulated once per speed and size, for every class (dropped
        // once loaded)
        let excitations = calibrated_rig::ExcitationCache::default();
        let loaded: Vec<anyhow::Result<(RecKey, Rec)>> = todo
            .par_iter()
            .map(|k| {
                let r = ::pipeline::recordings::load_shared(dir.as_deref(), &plan, k, &excitations)
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
