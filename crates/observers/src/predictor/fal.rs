//! The fuzzy ARX-Laguerre predictor of eq. (5.19) with the observer chain.

use super::Predictor;
use super::arx::dot;
use super::{ArxLaguerrePredictor, StateSpace};
use crate::error::ObserverError;
use crate::law::Correction;

/// The fuzzy ARX-Laguerre predictor of eq. (5.19) with the observer's chain: the ARX-Laguerre
/// part is an [`ArxLaguerrePredictor`] (injection, d̂, χ̂ as there) and the fuzzy term
/// σ_f J_f(k), J_f = Table 5.1 inference on (e_b(k), e_b(k) − e_b(k−1)), is filtered by the
/// model's J_f Laguerre bank and added to the output with its coefficients λ_f (`fuzzy-ts`),
/// where e_b = y − Kᵀ X̂ is the error of the observer's ARX-Laguerre part (eqs 5.21 and 5.25
/// carry σ_f J_f inside the observer; AFSMO keeps it although 5.30 prints α_f in its place, see
/// `docs/equations/observers.md`, item 18).
///
/// Under the innovations design ([`ArxLaguerrePredictor::new_innovations`]) the model part is
/// eq. 5.19's own one-step predictor (`fuzzy_ts::FuzzyArxLaguerre::predict`): its bank holds
/// the measured output and J_f is the inference on the model's error, neither of them touched by
/// the observer's injection d̂ + c₁, which adds to the prediction only
/// (`docs/equations/observers.md`, "The fuzzy term under the innovations design").
#[derive(Debug, Clone)]
pub struct FalPredictor {
    base: ArxLaguerrePredictor,
    fal: fuzzy_ts::FuzzyArxLaguerre,
    xf: Vec<f64>,
    kf: Vec<f64>,
    e_prev: f64,
    y_hat: f64,
}

impl FalPredictor {
    /// Wrap an already-built ARX-Laguerre predictor of `fal.base()` with the fuzzy term.
    pub fn new(base: ArxLaguerrePredictor, fal: fuzzy_ts::FuzzyArxLaguerre) -> Self {
        let kf = fal.fuzzy_coefficients().to_vec();
        let y_hat = base.output();
        Self {
            base,
            xf: vec![0.0; kf.len()],
            kf,
            fal,
            e_prev: 0.0,
            y_hat,
        }
    }

    /// The ARX-Laguerre part of the model as this crate's [`StateSpace`].
    pub fn base_model(fal: &fuzzy_ts::FuzzyArxLaguerre) -> Result<StateSpace, ObserverError> {
        Ok(fal.base().state_space().validated()?)
    }
}

impl Predictor for FalPredictor {
    #[inline(always)]
    fn output(&self) -> f64 {
        self.y_hat
    }
    #[inline(always)]
    fn advance(&mut self, y: f64, u: f64, e: f64, c: Correction) {
        // J_f is driven by the ARX-Laguerre part's own error, the quantity the fuzzy stage was
        // fitted to predict (fuzzy-ts, stage 2): y − KᵀX̂, without the injection d̂ + c₁ that an
        // output-fault (innovations) predictor adds to its prediction.
        let e_base = y - self.base.model_output();
        let jf = self.fal.inference().infer(e_base, e_base - self.e_prev);
        self.e_prev = e_base;
        if self.base.fault_enters_output() {
            // Innovations design (K_p = b_y): b_y Ŷ_b + K_p e_b = b_y y, i.e. the Laguerre bank
            // holds the *measured* output, only with the part's own error e_b = y − Ŷ_b. The
            // observer's error e = e_b − λ_fᵀx_f also holds the fuzzy term, which would enter
            // the bank as if it had been measured.
            self.base.advance(y, u, y - self.base.output(), c);
        } else {
            self.base.advance(y, u, e, c);
        }
        self.fal.fuzzy_bank().step(&mut self.xf, jf);
        self.y_hat = self.base.output() + dot(&self.kf, &self.xf);
    }
    #[inline(always)]
    fn fault_estimate(&self) -> f64 {
        self.base.fault_estimate()
    }
    #[inline(always)]
    fn equivalent_fault(&self, c: &Correction) -> f64 {
        self.base.equivalent_fault(c)
    }
    #[inline(always)]
    fn magnitude(&self) -> f64 {
        self.base.magnitude().max(self.y_hat.abs())
    }
    fn reset(&mut self) {
        self.base.reset();
        self.xf.iter_mut().for_each(|v| *v = 0.0);
        self.e_prev = 0.0;
        self.y_hat = self.base.output();
    }
    fn order(&self) -> usize {
        self.base.order() + self.xf.len()
    }
}
