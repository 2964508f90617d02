//! The observer loop: predict, take the error, correct (eq. 2.35, 3.19, 4.30, 5.32).

use crate::error::ObserverError;
use crate::law::CorrectionLaw;
use crate::predictor::Predictor;

/// Series produced by running an observer over a record (one value per input sample).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ObserverOutput {
    /// Residual r(k) = y(k) − ŷ(k) (eqs 2.35, 2.45, 3.19, 4.30, 5.32).
    pub residual: Vec<f64>,
    /// One-step prediction ŷ(k).
    pub y_hat: Vec<f64>,
    /// Fault / lumped-uncertainty estimate (extended state plus smoothed equivalent injection;
    /// eqs 2.37, 2.42, 3.14, 3.18, 4.17, 4.19, 5.22, 5.26, 5.31).
    pub fault: Vec<f64>,
    /// Level-1 output injection c₁(k), the signal whose chattering the laws differ in.
    pub injection: Vec<f64>,
}

impl ObserverOutput {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.residual.len()
    }
    /// True when no samples are held.
    pub fn is_empty(&self) -> bool {
        self.residual.is_empty()
    }
    fn resize(&mut self, n: usize) {
        for v in [
            &mut self.residual,
            &mut self.y_hat,
            &mut self.fault,
            &mut self.injection,
        ] {
            v.clear();
            v.resize(n, 0.0);
        }
    }
}

/// One sample of an observer run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutput {
    /// r(k).
    pub residual: f64,
    /// ŷ(k).
    pub y_hat: f64,
    /// Fault estimate after the update: extended state d̂(k+1) plus the smoothed equivalent
    /// output injection.
    pub fault: f64,
    /// c₁(k).
    pub injection: f64,
}

/// Default divergence factor: the run fails when a chain magnitude exceeds
/// `factor · (1 + max |y|)`.
pub const DEFAULT_DIVERGENCE_FACTOR: f64 = 1e6;

/// An observer: a [`Predictor`] composed with a [`CorrectionLaw`].
#[derive(Debug, Clone)]
pub struct Observer<P, L> {
    predictor: P,
    law: L,
    divergence_factor: f64,
    eq_alpha: f64,
    eq_state: f64,
}

/// Default smoothing of the equivalent output injection added to the fault estimate
/// (first-order low-pass, coefficient per sample: time constant 50 samples).
pub const DEFAULT_EQUIVALENT_INJECTION_ALPHA: f64 = 0.02;

impl<P: Predictor, L: CorrectionLaw> Observer<P, L> {
    /// Compose a predictor and a law.
    pub fn new(predictor: P, law: L) -> Self {
        Self {
            predictor,
            law,
            divergence_factor: DEFAULT_DIVERGENCE_FACTOR,
            eq_alpha: DEFAULT_EQUIVALENT_INJECTION_ALPHA,
            eq_state: 0.0,
        }
    }

    /// Smoothing coefficient α ∈ (0, 1] of the equivalent output injection: the reported fault
    /// estimate is d̂ + LP_α(equivalent injection), LP_α(x)(k+1) = LP(k) + α (x − LP(k)).
    pub fn with_equivalent_injection_alpha(mut self, alpha: f64) -> Result<Self, ObserverError> {
        if !(alpha.is_finite() && alpha > 0.0 && alpha <= 1.0) {
            return Err(ObserverError::InvalidParameter {
                name: "equivalent_injection_alpha",
                value: alpha,
                reason: "must be in (0, 1]",
            });
        }
        self.eq_alpha = alpha;
        Ok(self)
    }

    /// Change the divergence factor (must be finite and > 1).
    pub fn with_divergence_factor(mut self, factor: f64) -> Result<Self, ObserverError> {
        if !(factor.is_finite() && factor > 1.0) {
            return Err(ObserverError::InvalidParameter {
                name: "divergence_factor",
                value: factor,
                reason: "must be finite and > 1",
            });
        }
        self.divergence_factor = factor;
        Ok(self)
    }

    /// The predictor.
    pub fn predictor(&self) -> &P {
        &self.predictor
    }

    /// The law.
    pub fn law(&self) -> &L {
        &self.law
    }

    /// Reset predictor and law to their initial state.
    pub fn reset(&mut self) {
        self.predictor.reset();
        self.law.reset();
        self.eq_state = 0.0;
    }

    /// One sample (no validation; use [`Observer::run`] for checked runs).
    #[inline(always)]
    pub fn step(&mut self, y: f64, u: f64) -> StepOutput {
        let y_hat = self.predictor.output();
        let e = y - y_hat;
        let c = self.law.correct(e);
        let eq = self.predictor.equivalent_fault(&c);
        self.eq_state += self.eq_alpha * (eq - self.eq_state);
        self.predictor.advance(y, u, e, c);
        StepOutput {
            residual: e,
            y_hat,
            fault: self.predictor.fault_estimate() + self.eq_state,
            injection: c.c1,
        }
    }

    /// Run over a whole record from the current state; see [`Observer::run_into`].
    pub fn run(&mut self, y: &[f64], u: Option<&[f64]>) -> Result<ObserverOutput, ObserverError> {
        let mut out = ObserverOutput::default();
        self.run_into(y, u, &mut out)?;
        Ok(out)
    }

    /// Run over a whole record, writing into `out` (its buffers are reused; no per-sample
    /// allocation). Continues from the current state (call [`Observer::reset`] to restart).
    ///
    /// Errors: empty `y`, `u` of another length, any non-finite sample, or divergence (a chain
    /// magnitude non-finite or above `factor · (1 + max|y|)`).
    pub fn run_into(
        &mut self,
        y: &[f64],
        u: Option<&[f64]>,
        out: &mut ObserverOutput,
    ) -> Result<(), ObserverError> {
        if y.is_empty() {
            return Err(ObserverError::EmptyInput);
        }
        if let Some(u) = u {
            if u.len() != y.len() {
                return Err(ObserverError::LengthMismatch {
                    expected: y.len(),
                    found: u.len(),
                });
            }
            if let Some(i) = u.iter().position(|v| !v.is_finite()) {
                return Err(ObserverError::NonFiniteInput { index: i });
            }
        }
        let mut ymax = 0.0f64;
        for (i, v) in y.iter().enumerate() {
            if !v.is_finite() {
                return Err(ObserverError::NonFiniteInput { index: i });
            }
            ymax = ymax.max(v.abs());
        }
        let limit = (self.divergence_factor * (1.0 + ymax)).min(f64::MAX);
        out.resize(y.len());
        let ObserverOutput {
            residual,
            y_hat,
            fault,
            injection,
        } = out;
        for k in 0..y.len() {
            let uk = u.map_or(0.0, |u| u[k]);
            let s = self.step(y[k], uk);
            residual[k] = s.residual;
            y_hat[k] = s.y_hat;
            fault[k] = s.fault;
            injection[k] = s.injection;
            let m = self
                .predictor
                .magnitude()
                .max(s.residual.abs())
                .max(s.injection.abs());
            // `limit` is finite, so an infinite magnitude fails too. The fault
            // estimate is in physical units (it may legitimately exceed the output scale), so
            // only its finiteness is checked.
            if m.is_nan() || m > limit || !s.fault.is_finite() {
                return Err(ObserverError::Diverged {
                    index: k,
                    value: m,
                    limit,
                });
            }
        }
        Ok(())
    }
}

/// Object-safe view of any observer, for pipelines that choose the observer at run time.
pub trait RunObserver: Send {
    /// See [`Observer::run`].
    fn run(&mut self, y: &[f64], u: Option<&[f64]>) -> Result<ObserverOutput, ObserverError>;
    /// See [`Observer::run_into`].
    fn run_into(
        &mut self,
        y: &[f64],
        u: Option<&[f64]>,
        out: &mut ObserverOutput,
    ) -> Result<(), ObserverError>;
    /// See [`Observer::reset`].
    fn reset(&mut self);
}

impl<P, L> RunObserver for Observer<P, L>
where
    P: Predictor + Send,
    L: CorrectionLaw + Send,
{
    fn run(&mut self, y: &[f64], u: Option<&[f64]>) -> Result<ObserverOutput, ObserverError> {
        Observer::run(self, y, u)
    }
    fn run_into(
        &mut self,
        y: &[f64],
        u: Option<&[f64]>,
        out: &mut ObserverOutput,
    ) -> Result<(), ObserverError> {
        Observer::run_into(self, y, u, out)
    }
    fn reset(&mut self) {
        Observer::reset(self)
    }
}
