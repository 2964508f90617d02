//! The structural path and the predictors built from the model: the path alone as an observer
//! model, the whole machine as a one-step predictor, their residual statistics, and a path for
//! a model the loop left without one.

use super::MachineModel;
use crate::CloseLoopError;
use crate::effect::Mode;
use crate::path::StructuralPath;

/// Bins of the frequency grid (0 ..= fs/2) the path's and floor's autocorrelation is summed on
/// in [`MachineModel::predictor_model`]: 0.37 Hz at 12 kHz, finer than any calibrated mode's
/// half-power width.
const PREDICTOR_GRID_BINS: usize = 16_385;

impl MachineModel {
    /// Measure [`MachineModel::predictor_residual_rms`] and its kurtosis on `held_out` (left
    /// `None` without a path or when nothing finite is left).
    pub(super) fn set_predictor_stats(&mut self, held_out: &[f64]) {
        let stats = self
            .predictor_path()
            .ok()
            .and_then(|p| path_residual_stats(&p, held_out));
        (
            self.predictor_residual_rms,
            self.predictor_residual_kurtosis,
        ) = stats.unzip();
    }

    /// The calibrated structural path as an observer model: the AR path `y = e / A(z)` in shift
    /// form ([`observers::StateSpace::from_ar`]), the model the physics observers (SMO,
    /// HOSTSMO, FLO, VSO, PFLO) run on once a machine has been calibrated
    /// ([`observers::ModelConfig::CalibratedPath`]).
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the machine model holds no structural path (the loop found
    /// no broadband structure to add), [`CloseLoopError::Observer`] for an invalid path.
    pub fn observer_model(&self) -> Result<observers::StateSpace, CloseLoopError> {
        let path = self.path.as_ref().ok_or_else(|| CloseLoopError::Model {
            reason: "the machine model holds no structural path to run an observer on".into(),
        })?;
        observers::StateSpace::from_ar(&path.ar).map_err(|e| CloseLoopError::Observer {
            reason: e.to_string(),
        })
    }

    /// The whole calibrated machine as a one-step predictor: the AR model (the structural
    /// path's order plus two per line, Levinson; its excitation variance the innovation
    /// variance) of the stationary process the machine model describes at its calibration
    /// speed — the structural path at its calibrated level, the white floor and every line
    /// (shaft harmonics and tones, each a sinusoid of its calibrated amplitude, whose
    /// autocorrelation `A²/2 · cos(2π f m / fs)` is added exactly). A linear predictor needs no
    /// line's phase: a sinusoid is predicted from its own past. The path alone is
    /// [`MachineModel::path`].
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the model holds no structural path or the recursion fails.
    pub fn predictor_path(&self) -> Result<StructuralPath, CloseLoopError> {
        let path = self.path.as_ref().ok_or_else(|| CloseLoopError::Model {
            reason: "the machine model holds no structural path to run an observer on".into(),
        })?;
        let fs = self.fs_hz;
        let n_bins = PREDICTOR_GRID_BINS;
        let df = fs / 2.0 / (n_bins - 1) as f64;
        // the channel modes shape the background as they shape the physics
        let mut bg = path.psd(n_bins, df);
        Mode::shape_psd(&self.channel_modes, &mut bg, df, fs);
        let psd: Vec<f64> = bg
            .iter()
            .map(|s| s * self.path_level + self.noise_floor_psd)
            .collect();
        // each line is one more pole pair: the path's order plus two per line
        let order = path.order() + 2 * self.lines.len();
        let mut r = crate::path::autocorrelation(&psd, df, fs, order);
        let fr = self.calibration_shaft_hz();
        for l in &self.lines {
            let (f, a) = (l.frequency_at(fr, fr), l.amplitude());
            for (m, v) in r.iter_mut().enumerate() {
                *v += 0.5 * a * a * (2.0 * std::f64::consts::PI * f * m as f64 / fs).cos();
            }
        }
        let (ar, e) = crate::path::levinson(&r)?;
        Ok(StructuralPath {
            fs_hz: fs,
            ar,
            excitation_variance: e,
        })
    }

    /// The whole calibrated machine as an observer model: [`MachineModel::predictor_path`] in
    /// shift form, what the physics observers (SMO, HOSTSMO, FLO, VSO, PFLO) run on
    /// ([`observers::ModelConfig::CalibratedPath`]). [`MachineModel::observer_model`] is the
    /// path alone.
    ///
    /// # Errors
    /// As [`MachineModel::predictor_path`]; [`CloseLoopError::Observer`] for an invalid model.
    pub fn predictor_model(&self) -> Result<observers::StateSpace, CloseLoopError> {
        observers::StateSpace::from_ar(&self.predictor_path()?.ar).map_err(|e| {
            CloseLoopError::Observer {
                reason: e.to_string(),
            }
        })
    }
}

/// RMS and kurtosis of `y` through the path's prediction-error filter `A(z)` (after its start-up
/// of `order` samples); `None` when nothing finite is left.
pub(super) fn path_residual_stats(p: &StructuralPath, y: &[f64]) -> Option<(f64, f64)> {
    let e = p.prediction_error(y);
    let e = e.get(p.order()..)?;
    let n = e.len() as f64;
    let m2 = e.iter().map(|v| v * v).sum::<f64>() / n;
    let m4 = e.iter().map(|v| v.powi(4)).sum::<f64>() / n;
    (n > 0.0 && m2 > 0.0 && m2.is_finite() && m4.is_finite()).then(|| (m2.sqrt(), m4 / (m2 * m2)))
}

impl MachineModel {
    /// When the loop added no structural path — the declared model already explained the
    /// calibration recording — identify one from the recording directly
    /// ([`crate::path::identify_from_signal`] on `fit`, AR order up to `max_order`, residual
    /// statistics on `held_out`), so the model can still serve as a healthy baseline (a diagnosis
    /// whitens with its path). Returns whether a path was added; a model that holds one is left
    /// as it is.
    ///
    /// # Errors
    /// The identification's errors, and [`CloseLoopError::Model`] when the held-out segment
    /// leaves no finite residual statistics.
    pub fn ensure_path(
        &mut self,
        fit: &[f64],
        held_out: &[f64],
        max_order: usize,
    ) -> Result<bool, CloseLoopError> {
        if self.path.is_some() {
            return Ok(false);
        }
        let p = crate::path::identify_from_signal(fit, self.fs_hz, max_order)?;
        let (rms, kurtosis) =
            path_residual_stats(&p, held_out).ok_or_else(|| CloseLoopError::Model {
                reason: "the held-out segment leaves no finite path residual".into(),
            })?;
        self.structural_modes = p.modes();
        self.path_level = 1.0;
        self.path_residual_rms = Some(rms);
        self.path_residual_kurtosis = Some(kurtosis);
        self.path = Some(p);
        self.set_predictor_stats(held_out);
        Ok(true)
    }
}
