//! The observer residual: the declared model run *through its observer* on the measurement, the
//! residual r(k) = s(k) − ŝ(k) of the one-step prediction, and its RMS on the held-out segment
//! (the second error metric of the ledger; definition in `docs/equations/close-loop.md`).
//!
//! * ARX-Laguerre (ch. 4): an ARX-Laguerre model (eq. 4.11, N_a = [`ARX_ORDER`], pole ζ_a by
//!   prediction-error search, `laguerre-id`) identified on the fitting segment of the scored signal,
//!   observed by ALPIO (eqs 4.16–4.17, `observers`), fault entering along b_y.
//! * Physics (ch. 2–3, 5): the measured-channel (housing) mode of the 5-DOF model, observed by
//!   ASMO (eqs 5.23–5.28), linear part designed with `LinearDesign::for_recordings`.
//! * Physics behind a structural path (the loop identified one, or a calibrated machine model
//!   gave it): the path `y = e/A(z)` as the observer's model
//!   ([`observers::ModelConfig::CalibratedPath`], what the chapter pipelines' physics observers
//!   run on once a machine is calibrated), observed by ASMO, default linear design: the
//!   observer then runs on the calibrated model, not on one fixed mode.
//!
//! The per-sample uncertainty bound is Γ = [`BOUND_FRACTION`]·RMS(s) on the fitting segment, as in
//! the `observers` crate's own 5-DOF test. Measured on a 2 s simulated CWRU-like outer-race record
//! (12 kHz, 10 % noise), held-out residual RMS / signal RMS: physics-mode ASMO 0.674 (HOSTSMO 1.30,
//! APIO 0.68, SMO 0.73); ARX-Laguerre ALPIO 0.886. With the chapter pipelines' data bound (0.99
//! quantile of |Δᵐ s|) the sliding-mode kinds chatter far above the signal (HOSTSMO 910×), so it
//! is not used here.
//! The scored signal is the measurement minus the phase-coherent lines the loop has fitted
//! (tones and shaft-harmonic responses), so an added line lowers the residual only if it
//! explains part of the held-out record.

use crate::CloseLoopError;
use laguerre_id::{ArxLaguerreConfig, PoleChoice};
use observers::{
    FaultDirection, LinearDesign, ModalParams, ModelConfig, ObserverKind, ObserverSettings,
};

/// N_a of the identified ARX-Laguerre model (the chapter pipelines' order).
pub const ARX_ORDER: usize = 6;
/// Γ = this × RMS of the fitting segment: the observer's per-sample uncertainty bound.
pub const BOUND_FRACTION: f64 = 1e-3;

/// The observer that scores a residual.
#[derive(Debug, Clone, PartialEq)]
pub enum ResidualObserver {
    /// ALPIO on an ARX-Laguerre model identified on the fitting segment of the scored signal.
    ArxLaguerre,
    /// ASMO on the measured-channel mode of the physics model.
    Physics {
        /// Natural frequency of the mode, Hz (clipped to 0.45·fs).
        natural_frequency_hz: f64,
        /// Damping ratio of the mode.
        damping_ratio: f64,
    },
    /// ASMO on the structural path the model is seen through (calibrated machine model or
    /// identified by the loop): `a₁ … a_p` of `A(z)`.
    CalibratedPath {
        /// AR coefficients `a₁ … a_p` of the path `1/A(z)`.
        ar: Vec<f64>,
    },
}

fn obs_err(e: impl std::fmt::Display) -> CloseLoopError {
    CloseLoopError::Observer {
        reason: e.to_string(),
    }
}

/// Identify the ARX-Laguerre model (N_a = [`ARX_ORDER`], no input, ζ_a by
/// `PoleChoice::DEFAULT_SEARCH`) on `fit`.
///
/// # Errors
/// [`CloseLoopError::Observer`] with `laguerre-id`'s message.
pub fn identify_arx(fit: &[f64]) -> Result<laguerre_id::ArxLaguerreModel, CloseLoopError> {
    let cfg = ArxLaguerreConfig::new(ARX_ORDER, 0, PoleChoice::DEFAULT_SEARCH).map_err(obs_err)?;
    laguerre_id::ArxLaguerreModel::identify(fit, None, &cfg).map_err(obs_err)
}

impl ResidualObserver {
    /// Name for the ledger, e.g. "ALPIO on ARX-Laguerre (N_a = 6)".
    pub fn describe(&self) -> String {
        match self {
            Self::ArxLaguerre => format!(
                "ALPIO on ARX-Laguerre (N_a = {ARX_ORDER}, identified on the fitting segment)"
            ),
            Self::Physics {
                natural_frequency_hz,
                damping_ratio,
            } => format!(
                "ASMO on the housing mode ({natural_frequency_hz:.1} Hz, zeta {damping_ratio:.4})"
            ),
            Self::CalibratedPath { ar } => format!(
                "ASMO on the structural path (AR order {}) of the calibrated model",
                ar.len()
            ),
        }
    }

    /// The observer residual of `signal` (fitted and bounded on `signal[..n_fit]`, run over the
    /// whole signal from a zero state) and its RMS over `signal[n_fit..]`.
    ///
    /// # Errors
    /// [`CloseLoopError::Observer`] if the identification, the design or the run fails, or the
    /// residual is not finite; [`CloseLoopError::TooShort`] if either part is empty.
    pub fn held_out_rms(
        &self,
        signal: &[f64],
        n_fit: usize,
        fs: f64,
    ) -> Result<f64, CloseLoopError> {
        if n_fit == 0 || n_fit >= signal.len() {
            return Err(CloseLoopError::TooShort {
                needed: n_fit + 1,
                found: signal.len(),
            });
        }
        let fit = &signal[..n_fit];
        let (kind, model, linear) = match self {
            Self::ArxLaguerre => {
                let id = identify_arx(fit)?;
                let model = id.state_space().validated().map_err(obs_err)?;
                (
                    ObserverKind::Alpio,
                    ModelConfig::ArxLaguerre {
                        model,
                        fault: FaultDirection::OutputFilter,
                    },
                    LinearDesign::default(),
                )
            }
            Self::CalibratedPath { ar } => (
                ObserverKind::Asmo,
                ModelConfig::CalibratedPath(observers::StateSpace::from_ar(ar).map_err(obs_err)?),
                LinearDesign::default(),
            ),
            &Self::Physics {
                natural_frequency_hz,
                damping_ratio,
            } => (
                ObserverKind::Asmo,
                ModelConfig::Physics(ModalParams {
                    natural_frequency_hz: natural_frequency_hz.min(0.45 * fs),
                    damping_ratio,
                    input_gain: 0.0,
                    sample_rate_hz: fs,
                }),
                LinearDesign::for_recordings(),
            ),
        };
        let bound = BOUND_FRACTION * crate::metric::rms(fit);
        if !(bound.is_finite() && bound > 0.0) {
            return Err(CloseLoopError::ZeroSignal);
        }
        let mut settings = ObserverSettings::new(bound);
        settings.linear = linear;
        let mut obs = observers::build_observer(kind, &model, &settings).map_err(obs_err)?;
        let out = obs.run(signal).map_err(obs_err)?;
        let r = &out.residual[n_fit..];
        let v = crate::metric::rms(r);
        if !v.is_finite() {
            return Err(obs_err("the observer residual is not finite"));
        }
        Ok(v)
    }
}

/// The ARX-Laguerre model as a declared model: identified on the fitting segment of the
/// recording and run open loop, driven by its own innovation (white, Gaussian, σ = RMS of its
/// one-step prediction error on the fitting segment). It has no kinematics, so a speed offset
/// changes nothing: the loop can add lines, modes and modulations to it, not speed.
#[derive(Debug, Clone, PartialEq)]
pub struct ArxLaguerreDeclared {
    /// The identified model.
    pub model: laguerre_id::ArxLaguerreModel,
    /// Innovation standard deviation.
    pub sigma: f64,
    /// Seed of the innovation draws.
    pub seed: u64,
}

/// Samples run before the simulated output is kept (the model's transient).
const ARX_WARMUP: usize = 2048;

impl ArxLaguerreDeclared {
    /// Identify on the fitting segment `fit` (eq. 4.10 pole search, N_a = [`ARX_ORDER`]).
    ///
    /// # Errors
    /// [`CloseLoopError::Observer`] when the identification fails.
    pub fn identify(fit: &[f64]) -> Result<Self, CloseLoopError> {
        let model = identify_arx(fit)?;
        let pred = model.predict(fit, None).map_err(obs_err)?;
        let skip = (fit.len() / 20).min(ARX_WARMUP);
        let e: Vec<f64> = fit[skip..]
            .iter()
            .zip(&pred[skip..])
            .map(|(a, b)| a - b)
            .collect();
        Ok(Self {
            model,
            sigma: crate::metric::rms(&e),
            seed: 11,
        })
    }
}

impl crate::DeclaredModel for ArxLaguerreDeclared {
    fn name(&self) -> &str {
        "arx-laguerre"
    }

    fn simulate(
        &self,
        _op: &crate::OperatingPoint,
        n: usize,
        _fs: f64,
    ) -> Result<Vec<f64>, CloseLoopError> {
        let mut g = crate::scenario::Gaussian::new(self.seed);
        let mut st = laguerre_id::LaguerreState::default();
        let mut out = Vec::with_capacity(n);
        let limit = 1e6 * self.sigma.max(1e-300);
        for k in 0..n + ARX_WARMUP {
            let y = self.model.output(&st) + self.sigma * g.sample();
            if !y.is_finite() || y.abs() > limit {
                return Err(CloseLoopError::Model {
                    reason: format!("the identified ARX-Laguerre model diverges at sample {k}"),
                });
            }
            self.model.advance(&mut st, y, 0.0);
            if k >= ARX_WARMUP {
                out.push(y);
            }
        }
        Ok(out)
    }

    fn residual_observer(&self, _fs: f64) -> ResidualObserver {
        ResidualObserver::ArxLaguerre
    }

    /// S(f) = c·σ²/fs / |1 − G(e^{j2πf/fs})|², c = 2 off DC and Nyquist (the one-sided density
    /// `residual-features`' Welch estimates), G the strictly causal one-step predictor
    /// ŷ = G(z)·y of eq. 4.11, from its impulse response (`predict` on a unit impulse, zero-padded
    /// to a multiple of `nperseg` ≥ `ARX_IMPULSE_LEN`, transformed by FFT).
    fn expected_psd(
        &self,
        _op: &crate::OperatingPoint,
        nperseg: usize,
        fs: f64,
    ) -> Option<Vec<f64>> {
        use rustfft::num_complex::Complex;
        if nperseg < 2 || !(fs.is_finite() && fs > 0.0) {
            return None;
        }
        let n = ARX_IMPULSE_LEN.div_ceil(nperseg) * nperseg;
        let mut d = vec![0.0; n];
        d[0] = 1.0;
        let h = self.model.predict(&d, None).ok()?;
        let mut buf: Vec<Complex<f64>> = h.iter().map(|&v| Complex::new(v, 0.0)).collect();
        rustfft::FftPlanner::<f64>::new()
            .plan_fft_forward(n)
            .process(&mut buf);
        let step = n / nperseg;
        let s2 = self.sigma * self.sigma / fs;
        let out: Vec<f64> = (0..=nperseg / 2)
            .map(|k| {
                let g = buf[k * step];
                let c = if k == 0 || k == nperseg / 2 { 1.0 } else { 2.0 };
                c * s2 / (Complex::new(1.0, 0.0) - g).norm_sqr().max(1e-300)
            })
            .collect();
        out.iter().all(|v| v.is_finite()).then_some(out)
    }
}

/// Length of the predictor impulse response behind [`ArxLaguerreDeclared`]'s expected PSD.
const ARX_IMPULSE_LEN: usize = 16_384;
