//! The healthy baseline of a run: a recording prepared at each recording rate (decimated by an
//! integer factor when needed), or a calibrated machine model.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::Context as _;
use diagnosis::Baseline;

use super::loader::{FsFlag, load_with};

/// A prepared baseline and a note saying how it was made (rate, decimation).
pub type Prepared = Arc<(Baseline, String)>;

/// A healthy baseline: a recording's samples, prepared on demand for each recording rate it is
/// asked for, or a calibrated machine model (`hybrid-fdd calibrate`), whose structural path is
/// the healthy model.
#[derive(Debug)]
pub struct BaselineSource {
    /// Where it came from.
    pub path: PathBuf,
    samples: Vec<f64>,
    fs_hz: f64,
    machine: Option<Box<close_loop::machine::MachineModel>>,
    prepared: Mutex<Vec<(u64, Prepared)>>,
}

impl BaselineSource {
    /// Load a baseline file: a recording (as [`load_with`] under [`FsFlag::ForUnstated`]: a
    /// text file without a time column at `fs`, the recording's `--fs`; a `.mat` file or a
    /// time column at its own rate), or a machine model JSON (`.json`, validated by
    /// `close_loop::machine::MachineModel::from_json`).
    ///
    /// # Errors
    /// As [`load`], or the machine model's typed format errors.
    ///
    /// [`load`]: super::load
    pub fn load(path: &Path, channel: &str, fs: Option<f64>) -> anyhow::Result<Self> {
        if path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading baseline {}", path.display()))?;
            let m = close_loop::machine::MachineModel::from_json(&text)
                .with_context(|| format!("baseline machine model {}", path.display()))?;
            return Ok(Self::from_machine(path, m));
        }
        // the loader's errors name the file
        let l = load_with(path, channel, fs, FsFlag::ForUnstated).context("baseline")?;
        Ok(Self::from_samples(path, l.samples, l.fs_hz))
    }

    /// A baseline from a machine model already in memory (`path` names it in reports).
    pub fn from_machine(path: &Path, m: close_loop::machine::MachineModel) -> Self {
        Self {
            path: path.to_path_buf(),
            samples: Vec::new(),
            fs_hz: m.fs_hz,
            machine: Some(Box::new(m)),
            prepared: Mutex::new(Vec::new()),
        }
    }

    /// A baseline from samples already in memory.
    pub fn from_samples(path: &Path, samples: Vec<f64>, fs_hz: f64) -> Self {
        Self {
            path: path.to_path_buf(),
            samples,
            fs_hz,
            machine: None,
            prepared: Mutex::new(Vec::new()),
        }
    }

    /// The units a machine-model baseline was calibrated in ("g", "m/s^2", "unknown"); `None`
    /// for a recording baseline.
    pub fn machine_units(&self) -> Option<&str> {
        self.machine.as_deref().map(|m| m.units.as_str())
    }

    /// The baseline from a machine model: the prediction-error filter of the whole model's
    /// one-step predictor (structural path, floor and lines,
    /// `close_loop::machine::MachineModel::predictor_path`) and the residual statistics measured
    /// through it when it was calibrated; for a model written before those statistics existed,
    /// the path's own filter and statistics. The rate is the model's (the library reports a
    /// recording at another rate as its typed mismatch error).
    fn prepare_machine(&self, m: &close_loop::machine::MachineModel) -> anyhow::Result<Prepared> {
        let name = self.path.display();
        let path = m.path.as_ref().with_context(|| {
            format!("baseline machine model {name} holds no structural path to whiten with")
        })?;
        let (ar, rms, kurt, what) = match (m.predictor_residual_rms, m.predictor_residual_kurtosis)
        {
            (Some(rms), Some(kurt)) => {
                let p = m
                    .predictor_path()
                    .with_context(|| format!("baseline machine model {name}"))?;
                let what = format!(
                    "the whole model (structural path of AR order {} and {} lines) as the healthy model, its one-step predictor of AR order {}",
                    path.ar.len(),
                    m.lines.len(),
                    p.ar.len()
                );
                (p.ar, rms, kurt, what)
            }
            _ => {
                let (Some(rms), Some(kurt)) = (m.path_residual_rms, m.path_residual_kurtosis)
                else {
                    anyhow::bail!(
                        "baseline machine model {name} has no path residual statistics (written by an older version): recalibrate it with `hybrid-fdd calibrate` (or `cargo xtask calibrate`)"
                    );
                };
                let what = format!(
                    "structural path of AR order {} as the healthy model (a model written before the whole model's residual statistics)",
                    path.ar.len()
                );
                (path.ar.clone(), rms, kurt, what)
            }
        };
        let w = diagnosis::ArWhitener::from_coefficients(
            ar.iter().map(|a| -a).collect(),
            m.fs_hz,
            "baseline machine model",
        )?;
        let samples = m.provenance.fit_samples[1];
        let b = Baseline::from_whitener(w, rms, kurt, samples)?;
        let note = format!(
            "machine model {name} (calibrated on {}, {} Hz, units {}): {what}",
            if m.provenance.recording.is_empty() {
                "an unnamed recording"
            } else {
                m.provenance.recording.as_str()
            },
            m.fs_hz,
            m.units,
        );
        Ok(Arc::new((b, note)))
    }

    /// The baseline prepared at `fs_hz` (decimated by an integer factor when needed) and a note
    /// saying how; prepared once per rate.
    ///
    /// # Errors
    /// A rate that is neither equal nor an integer fraction of the baseline's (the library's
    /// typed mismatch error), or a baseline the AR fit rejects.
    pub fn at(&self, fs_hz: f64) -> anyhow::Result<Prepared> {
        let key = fs_hz.to_bits();
        let mut cache = self
            .prepared
            .lock()
            .map_err(|_| anyhow::anyhow!("baseline cache poisoned"))?;
        if let Some((_, b)) = cache.iter().find(|(k, _)| *k == key) {
            return Ok(b.clone());
        }
        if let Some(m) = self.machine.as_deref() {
            let b = self.prepare_machine(m)?;
            cache.push((key, b.clone()));
            return Ok(b);
        }
        let name = self.path.display();
        let (x, fs_b, note) = if let Some((x, q)) = decimated_to(&self.samples, self.fs_hz, fs_hz)?
        {
            (
                x,
                fs_hz,
                format!(
                    "{name}, {} Hz decimated by {q} (bearing-data anti-aliasing FIR) to {fs_hz} Hz",
                    self.fs_hz
                ),
            )
        } else {
            // equal rates, or a mismatch the library reports as its typed error
            (
                self.samples.clone(),
                self.fs_hz,
                format!("{name} at {} Hz", self.fs_hz),
            )
        };
        let b = Baseline::prepare(&x, fs_b).with_context(|| format!("baseline {name}"))?;
        let b = Arc::new((b, note));
        cache.push((key, b.clone()));
        Ok(b)
    }
}

/// `x` sampled at `from_hz`, decimated to `to_hz` with `bearing-data`'s anti-aliasing FIR, and
/// the factor, when `from_hz` is an integer multiple (> 1) of `to_hz`; `None` otherwise (equal
/// rates, or rates that an integer factor cannot join).
///
/// # Errors
/// The decimator's errors.
pub fn decimated_to(
    x: &[f64],
    from_hz: f64,
    to_hz: f64,
) -> anyhow::Result<Option<(Vec<f64>, usize)>> {
    let ratio = from_hz / to_hz;
    if ratio > 1.0 + 1e-9 && (ratio - ratio.round()).abs() < 1e-9 {
        let q = ratio.round() as usize;
        let d = bearing_data::Decimator::new(bearing_data::DecimatorParams::new(q))?;
        Ok(Some((d.decimate(x)?, q)))
    } else {
        Ok(None)
    }
}
