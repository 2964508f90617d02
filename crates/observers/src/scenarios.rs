//! Reference plants with known truth, shared by tests, benches and examples: a damped linear
//! oscillator (the physics mode) and an ARX-Laguerre system, each with an additive
//! lumped uncertainty / fault entering where the observers expect it.

use crate::error::ObserverError;
use crate::predictor::{ModalParams, StateSpace, discretize_mode};

/// The true mode Ẋ₁ = X₂, Ẋ₂ = −ω²X₁ − 2ζωX₂ + b u + d, sampled exactly (d, u held over a sample).
#[derive(Debug, Clone, PartialEq)]
pub struct OscillatorPlant {
    phi: [f64; 4],
    gam: [f64; 2],
    b: f64,
    x: [f64; 2],
}

impl OscillatorPlant {
    /// Plant at rest with the mode `p`.
    pub fn new(p: &ModalParams) -> Result<Self, ObserverError> {
        p.validate()?;
        let (phi, gam) = discretize_mode(p);
        Ok(Self {
            phi,
            gam,
            b: p.input_gain,
            x: [0.0; 2],
        })
    }
    /// Set the true state (X₁, X₂).
    pub fn set_state(&mut self, x1: f64, x2: f64) {
        self.x = [x1, x2];
    }
    /// Current X₁ (the measured output).
    pub fn output(&self) -> f64 {
        self.x[0]
    }
    /// Advance one sample with uncertainty d and input u; returns X₁ at the new sample.
    pub fn step(&mut self, d: f64, u: f64) -> f64 {
        let [x1, x2] = self.x;
        let w = d + self.b * u;
        self.x = [
            self.phi[0] * x1 + self.phi[1] * x2 + self.gam[0] * w,
            self.phi[2] * x1 + self.phi[3] * x2 + self.gam[1] * w,
        ];
        self.x[0]
    }
    /// Simulate `n` samples: returns y(k) = X₁(k) for k = 0..n with d(k) applied between k and k + 1.
    pub fn simulate(&mut self, n: usize, mut d: impl FnMut(usize) -> f64) -> Vec<f64> {
        let mut y = Vec::with_capacity(n);
        for k in 0..n {
            y.push(self.output());
            self.step(d(k), 0.0);
        }
        y
    }
}

/// The true ARX-Laguerre system X(k+1) = A X + b_y y + b_u u + f δ(k), y = Kᵀ X, with f scaled
/// so that Kᵀ f = 1 (the observers' convention).
#[derive(Debug, Clone, PartialEq)]
pub struct ArxPlant {
    model: StateSpace,
    f: Vec<f64>,
    x: Vec<f64>,
    tmp: Vec<f64>,
}

impl ArxPlant {
    /// Plant at rest; `f` is normalised to Kᵀ f = 1.
    pub fn new(model: &StateSpace, f: &[f64]) -> Result<Self, ObserverError> {
        model.validate()?;
        let kf: f64 = model.k.iter().zip(f).map(|(a, b)| a * b).sum();
        if f.len() != model.order() {
            return Err(ObserverError::DimensionMismatch {
                expected: model.order(),
                found: f.len(),
            });
        }
        if kf.abs() < 1e-12 {
            return Err(ObserverError::FaultDirectionInvisible { value: kf.abs() });
        }
        Ok(Self {
            model: model.clone(),
            f: f.iter().map(|v| v / kf).collect(),
            x: vec![0.0; model.order()],
            tmp: vec![0.0; model.order()],
        })
    }
    /// Set the true state.
    pub fn set_state(&mut self, x: &[f64]) {
        self.x.copy_from_slice(x);
    }
    /// y(k) = Kᵀ X(k).
    pub fn output(&self) -> f64 {
        self.model.k.iter().zip(&self.x).map(|(a, b)| a * b).sum()
    }
    /// Advance with fault δ and input u.
    pub fn step(&mut self, delta: f64, u: f64) -> f64 {
        let n = self.model.order();
        let y = self.output();
        for i in 0..n {
            let row = &self.model.a[i * n..(i + 1) * n];
            self.tmp[i] = row.iter().zip(&self.x).map(|(a, b)| a * b).sum::<f64>()
                + self.model.b_y[i] * y
                + self.model.b_u[i] * u
                + self.f[i] * delta;
        }
        std::mem::swap(&mut self.x, &mut self.tmp);
        self.output()
    }
    /// Simulate `n` samples with inputs u(k) and faults δ(k); returns y(0..n).
    pub fn simulate(
        &mut self,
        n: usize,
        mut u: impl FnMut(usize) -> f64,
        mut delta: impl FnMut(usize) -> f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let mut y = Vec::with_capacity(n);
        let mut us = Vec::with_capacity(n);
        for k in 0..n {
            y.push(self.output());
            let uk = u(k);
            us.push(uk);
            self.step(delta(k), uk);
        }
        (y, us)
    }
}

/// A reference ARX-Laguerre model with `n_a = n_b = 4` (8 states): Laguerre poles 0.6 / 0.5 and
/// coefficients chosen so that A + b_y Kᵀ is stable (spectral radius 0.9585, complex pole pairs).
pub fn reference_arx_model() -> StateSpace {
    let k = vec![0.3, -0.6, 0.3, -0.1, 1.0, 0.4, -0.2, 0.1];
    StateSpace::from_poles(0.6, 4, 0.5, 4, k).expect("constant, valid reference model")
}

/// An ARX-Laguerre model of the chapters' shape on CWRU 97: `n_a` output and `n_b` input
/// Laguerre functions with the poles the chapters identify there (0.8941 and −0.0391, at
/// N_a = 12, N_b = 1), and small alternating coefficients (0.05, −0.03, …) so that a simulated
/// plant stays bounded. For throughput measurements at a realistic state count.
///
/// # Errors
/// [`ObserverError`] when the orders are outside what [`StateSpace::from_poles`] accepts.
pub fn chapters_shaped_arx_model(n_a: usize, n_b: usize) -> Result<StateSpace, ObserverError> {
    let k = (0..n_a + n_b)
        .map(|j| if j % 2 == 0 { 0.05 } else { -0.03 })
        .collect();
    Ok(StateSpace::from_poles(0.8941, n_a, -0.0391, n_b, k)?)
}

/// Total variation per sample of a series (the chattering measure): mean |x(k+1) − x(k)|.
pub fn total_variation_per_sample(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return 0.0;
    }
    x.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>() / (x.len() - 1) as f64
}
