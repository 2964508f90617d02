//! The healthy baseline of a run: a recording prepared at each recording rate (decimated by an
//! integer factor when needed), or a calibrated machine model, prepared at each recording speed
//! with the envelope of a healthy recording synthesised from it.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::Context as _;
use diagnosis::Baseline;

use super::loader::{FsFlag, load_with};

/// A baseline prepared at one recording rate (and, for a machine model, one speed) and a note
/// saying how it was made (rate, decimation; for a machine model, the synthesis its healthy
/// envelope comes from). Not `pipeline::Prepared` (the observers' models of a healthy record).
pub type BaselineAtRate = Arc<(Baseline, String)>;

/// The former name of [`BaselineAtRate`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed to `BaselineAtRate`: a baseline prepared at one rate and speed, with its note \
            (`pipeline::Prepared` is the observers' prepared models)"
)]
pub type Prepared = BaselineAtRate;

/// Seed of a machine model's healthy synthesis (excitation, floor, line phases): fixed, so a
/// diagnosis against a machine model is reproducible; chosen before any run on real data.
pub const MACHINE_SYNTHESIS_SEED: u64 = 1;

/// Shortest machine-model synthesis, seconds. The healthy envelope is a Welch estimate like the
/// recording's, and its scatter falls with the segments it averages: 10 s averages 17
/// half-overlapping segments of the longest the diagnosis uses ([`diagnosis::SEGMENT_TURNS_MAX`]
/// turns) at 1800 rpm, and [`MACHINE_SYNTHESIS_TURNS`] keeps at least 7 at any speed. A fixed length (not the recording's) keeps one synthesis per rate
/// and speed for a batch of recordings of different lengths; a recording longer than the
/// synthesis only has more segments of the same resolution, which the synthesis still matches.
pub const MACHINE_SYNTHESIS_S: f64 = 10.0;

/// Fewest shaft turns of a machine-model synthesis: four of the longest Welch segment
/// ([`diagnosis::SEGMENT_TURNS_MAX`]), the length at which a recording's own segments reach it;
/// longer than [`MACHINE_SYNTHESIS_S`] below 768 rpm.
pub const MACHINE_SYNTHESIS_TURNS: f64 = 4.0 * diagnosis::SEGMENT_TURNS_MAX;

/// Longest machine-model synthesis, seconds: [`MACHINE_SYNTHESIS_TURNS`] at the library's
/// slowest speed (`diagnosis::MIN_RPM`, 30 rpm) would be 256 s — at 48 kHz 12 M samples and
/// some 10 s of physics per speed. Below 128 rpm the synthesis stops at 60 s (64 turns at
/// 64 rpm): a recording of such a machine needs minutes for its own longest segments, and
/// where the synthesis is too short for a band's segment that band discounts no line.
pub const MACHINE_SYNTHESIS_MAX_S: f64 = 60.0;

/// A cache slot: filled once by whichever caller gets to it first; other callers of the same
/// key wait on it, callers of other keys do not.
type Slot = Arc<Mutex<Option<BaselineAtRate>>>;

/// Cache key of a rate and speed (speed `NO_RPM` for what does not depend on it).
type Key = (u64, u64);

/// Speed key of a prepared baseline that holds for every speed.
const NO_RPM: u64 = u64::MAX;

/// A healthy baseline: a recording's samples, prepared on demand for each recording rate it is
/// asked for, or a calibrated machine model (`hybrid-fdd calibrate`), whose whole model is the
/// healthy model and whose synthesised healthy recording at each speed asked for gives the
/// healthy envelope lines. Safe to share across threads: each rate and speed is prepared once.
#[derive(Debug)]
pub struct BaselineSource {
    /// Where it came from.
    pub path: PathBuf,
    samples: Vec<f64>,
    fs_hz: f64,
    machine: Option<Box<close_loop::machine::MachineModel>>,
    prepared: Mutex<Vec<(Key, Slot)>>,
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
    /// recording at another rate as its typed mismatch error). No healthy envelope yet: that
    /// depends on the speed ([`Self::with_synthesis`]).
    fn prepare_machine(
        &self,
        m: &close_loop::machine::MachineModel,
    ) -> anyhow::Result<BaselineAtRate> {
        let name = self.path.display();
        let path = m.path.as_ref().with_context(|| {
            format!("baseline machine model {name} holds no structural path to whiten with")
        })?;
        let (whitening_path, rms, kurt, what) = match (
            m.predictor_residual_rms,
            m.predictor_residual_kurtosis,
        ) {
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
                (p, rms, kurt, what)
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
                (path.clone(), rms, kurt, what)
            }
        };
        let w = diagnosis::ArWhitener::from_coefficients(
            whitening_path.prediction_coefficients(),
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

    /// A machine baseline `base` (its whitener, [`Self::prepare_machine`]) with the residual of
    /// a healthy recording synthesised from the model at `rpm` through that whitener, whose
    /// envelope lines the diagnosis discounts as a baseline recording's
    /// (`close_loop::machine::MachineModel::simulate_healthy`: path, floor, lines, modulations
    /// and the declared healthy physics; [`MACHINE_SYNTHESIS_SEED`], the longer of
    /// [`MACHINE_SYNTHESIS_S`] and [`MACHINE_SYNTHESIS_TURNS`], at most
    /// [`MACHINE_SYNTHESIS_MAX_S`]). A model that cannot be
    /// synthesised (physics seen through its own path, a declared fault, a declared model other
    /// than the 5-DOF physics) keeps no healthy envelope, and the note says so and why.
    fn with_synthesis(
        m: &close_loop::machine::MachineModel,
        base: &BaselineAtRate,
        rpm: f64,
    ) -> BaselineAtRate {
        let fs = m.fs_hz;
        let turns_s = MACHINE_SYNTHESIS_TURNS * 60.0 / rpm;
        let duration_s = MACHINE_SYNTHESIS_S
            .max(turns_s)
            .min(MACHINE_SYNTHESIS_MAX_S);
        let n = (duration_s * fs).ceil() as usize;
        let attached = m
            .simulate_healthy(rpm, n, MACHINE_SYNTHESIS_SEED)
            .map_err(anyhow::Error::from)
            .and_then(|y| {
                let e = base.0.whitener.residual(&y);
                Ok(base.0.clone().with_residual(e)?)
            });
        match attached {
            Ok(b) => {
                let note = format!(
                    "{}; its healthy envelope lines from a recording synthesised from the machine model ({duration_s:.1} s at {rpm} rpm, seed {MACHINE_SYNTHESIS_SEED}) through the same predictor",
                    base.1
                );
                Arc::new((b, note))
            }
            Err(e) => {
                let note = format!(
                    "{}; no healthy envelope lines, so none is discounted: the machine model cannot be synthesised ({e:#})",
                    base.1
                );
                Arc::new((base.0.clone(), note))
            }
        }
    }

    /// The cached value under `key`, made by `make` when absent (an error is returned, not
    /// kept). The list is locked only to find or add the key's slot: a long preparation blocks
    /// callers of its own key, who would otherwise compute it again, and no other.
    fn cached(
        &self,
        key: Key,
        make: impl FnOnce() -> anyhow::Result<BaselineAtRate>,
    ) -> anyhow::Result<BaselineAtRate> {
        let poisoned = || anyhow::anyhow!("baseline cache poisoned");
        let slot = {
            let mut slots = self.prepared.lock().map_err(|_| poisoned())?;
            match slots.iter().find(|(k, _)| *k == key) {
                Some((_, s)) => s.clone(),
                None => {
                    let s = Slot::default();
                    slots.push((key, s.clone()));
                    s
                }
            }
        };
        let mut v = slot.lock().map_err(|_| poisoned())?;
        if let Some(p) = v.as_ref() {
            return Ok(p.clone());
        }
        let p = make()?;
        *v = Some(p.clone());
        Ok(p)
    }

    /// The baseline prepared for a recording at `fs_hz` whose shaft turns at `rpm` (declared),
    /// and a note saying how. A recording is prepared once per rate (decimated by an integer
    /// factor when needed; the speed does not enter). A machine model's whitener is prepared
    /// once, and a healthy recording synthesised from it once per speed (the shaft lines and
    /// the physics move with it; [`MACHINE_SYNTHESIS_SEED`], [`MACHINE_SYNTHESIS_S`]; the note
    /// says so, or why the model could not be synthesised and discounts no line) — not at all
    /// for a recording at another rate than the model's or at a speed the library refuses,
    /// which the diagnosis then reports as its typed error.
    ///
    /// # Errors
    /// A rate that is neither equal nor an integer fraction of the baseline's (the library's
    /// typed mismatch error), a baseline the AR fit rejects, a machine model that cannot whiten.
    pub fn at(&self, fs_hz: f64, rpm: f64) -> anyhow::Result<BaselineAtRate> {
        if let Some(m) = self.machine.as_deref() {
            let base = self.cached((m.fs_hz.to_bits(), NO_RPM), || self.prepare_machine(m))?;
            let synthesisable = fs_hz == m.fs_hz
                && rpm.is_finite()
                && (diagnosis::MIN_RPM..=diagnosis::MAX_RPM).contains(&rpm);
            if !synthesisable {
                return Ok(base);
            }
            return self.cached((fs_hz.to_bits(), rpm.to_bits()), || {
                Ok(Self::with_synthesis(m, &base, rpm))
            });
        }
        self.cached((fs_hz.to_bits(), NO_RPM), || self.prepare_recording(fs_hz))
    }

    /// The baseline recording prepared at `fs_hz` (decimated by an integer factor when needed).
    fn prepare_recording(&self, fs_hz: f64) -> anyhow::Result<BaselineAtRate> {
        let name = self.path.display();
        let (x, fs_b, note, limit) = if let Some((x, q)) =
            decimated_to(&self.samples, self.fs_hz, fs_hz)?
        {
            // above the anti-aliasing filter's passband edge the decimated baseline holds
            // the filter's transition band: energy and kurtosis are compared below it
            let edge = bearing_data::DecimatorParams::new(q).passband_edge_hz(self.fs_hz);
            (
                x,
                fs_hz,
                format!(
                    "{name}, {} Hz decimated by {q} (bearing-data anti-aliasing FIR) to {fs_hz} Hz; energy and kurtosis compared below its passband edge, {edge:.0} Hz",
                    self.fs_hz
                ),
                Some(edge),
            )
        } else {
            // equal rates, or a mismatch the library reports as its typed error
            (
                self.samples.clone(),
                self.fs_hz,
                format!("{name} at {} Hz", self.fs_hz),
                None,
            )
        };
        let mut b = diagnosis::Signal::new(x, fs_b)
            .map_err(|e| diagnosis::DiagnosisError::signal("baseline", e))
            .and_then(|signal| Baseline::prepare(&signal))
            .with_context(|| format!("baseline {name}"))?;
        if let Some(edge) = limit {
            b = b
                .band_limited(edge)
                .with_context(|| format!("baseline {name}"))?;
        }
        Ok(Arc::new((b, note)))
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
