//! The physics mode of the measured channel (eqs 2.26 / 3.8 restricted to one mode): its
//! parameters, exact discretisation and the observer chain on it.

use super::Predictor;
use crate::error::ObserverError;
use crate::law::Correction;

/// A damped second-order mode of the measured channel (eqs 2.26 / 3.8 restricted to one mode):
/// Ẋ₁ = X₂, Ẋ₂ = −ω²X₁ − 2ζωX₂ + b·u + d.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModalParams {
    /// Natural frequency f_n in Hz (ω = 2π f_n).
    pub natural_frequency_hz: f64,
    /// Damping ratio ζ (≥ 0).
    pub damping_ratio: f64,
    /// Input gain b (units of X₂ per unit u per second).
    pub input_gain: f64,
    /// Sampling rate of the measurement, Hz.
    pub sample_rate_hz: f64,
}

impl ModalParams {
    /// Check ranges: f_n > 0 and below Nyquist, ζ ∈ [0, 10], fs > 0, b finite.
    pub fn validate(&self) -> Result<(), ObserverError> {
        let bad = |name, value, reason| {
            Err(ObserverError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        if !(self.sample_rate_hz.is_finite() && self.sample_rate_hz > 0.0) {
            return bad("sample_rate_hz", self.sample_rate_hz, "must be > 0");
        }
        if !(self.natural_frequency_hz.is_finite()
            && self.natural_frequency_hz > 0.0
            && self.natural_frequency_hz < 0.5 * self.sample_rate_hz)
        {
            return bad(
                "natural_frequency_hz",
                self.natural_frequency_hz,
                "must be in (0, fs/2)",
            );
        }
        if !(self.damping_ratio.is_finite() && (0.0..=10.0).contains(&self.damping_ratio)) {
            return bad("damping_ratio", self.damping_ratio, "must be in [0, 10]");
        }
        if !self.input_gain.is_finite() {
            return bad("input_gain", self.input_gain, "must be finite");
        }
        Ok(())
    }

    /// Sampling period T.
    pub fn dt(&self) -> f64 {
        1.0 / self.sample_rate_hz
    }

    /// ω in rad/s.
    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.natural_frequency_hz
    }
}

/// Exact (zero-order-hold) discretisation of the mode with the lumped uncertainty d̂ and the
/// input u held over a sample, in per-sample scaled states z₁ = X̂₁, z₂ = T·X̂₂, z₃ = T²·d̂.
///
/// The measured X₁ enters only through the output injection (the laws); α uses X̂₁. Putting the
/// measured X₁ inside α, as eqs (2.36), (3.13) print it, makes the ZOH model inexact by O(ωT)
/// and biases the fault estimate (see `docs/equations/observers.md`).
#[derive(Debug, Clone, PartialEq)]
pub struct SecondOrderPredictor {
    p: ModalParams,
    /// Per-sample chain matrix, row-major: z(k+1) = M z(k) + g_u u(k).
    m: [f64; 9],
    g_u: [f64; 2],
    z: [f64; 3],
    z0: [f64; 3],
    inv_t2: f64,
}

/// Φ = e^{AT} and Γ = ∫₀ᵀ e^{As} ds·[0, 1]ᵀ for A = [[0, 1], [−ω², −2ζω]].
pub fn discretize_mode(p: &ModalParams) -> ([f64; 4], [f64; 2]) {
    let t = p.dt();
    let w = p.omega();
    let mut aug = nalgebra::Matrix3::<f64>::zeros();
    aug[(0, 1)] = t;
    aug[(1, 0)] = -w * w * t;
    aug[(1, 1)] = -2.0 * p.damping_ratio * w * t;
    aug[(1, 2)] = t;
    let e = aug.exp();
    (
        [e[(0, 0)], e[(0, 1)], e[(1, 0)], e[(1, 1)]],
        [e[(0, 2)], e[(1, 2)]],
    )
}

impl SecondOrderPredictor {
    /// Discretise the mode at its sampling rate.
    pub fn new(p: ModalParams) -> Result<Self, ObserverError> {
        p.validate()?;
        let t = p.dt();
        let (phi, gam) = discretize_mode(&p);
        let m = [
            phi[0],
            phi[1] / t,
            gam[0] / (t * t),
            t * phi[2],
            phi[3],
            gam[1] / t,
            0.0,
            0.0,
            1.0,
        ];
        Ok(Self {
            p,
            m,
            g_u: [gam[0] * p.input_gain, t * gam[1] * p.input_gain],
            z: [0.0; 3],
            z0: [0.0; 3],
            inv_t2: 1.0 / (t * t),
        })
    }

    /// Set the initial estimate (X̂₁, X̂₂, d̂) in physical units; also used by [`Predictor::reset`].
    pub fn with_initial_state(mut self, x1: f64, x2: f64, d: f64) -> Self {
        let t = self.p.dt();
        self.z0 = [x1, t * x2, t * t * d];
        self.z = self.z0;
        self
    }

    /// The mode parameters.
    pub fn params(&self) -> ModalParams {
        self.p
    }

    /// The per-sample error-chain matrix (row-major 3×3) of (z₁, z₂, z₃) used for gain design.
    pub fn chain_matrix(&self) -> [f64; 9] {
        self.m
    }

    /// Current estimate (X̂₁, X̂₂, d̂) in physical units.
    pub fn state(&self) -> [f64; 3] {
        let t = self.p.dt();
        [self.z[0], self.z[1] / t, self.z[2] * self.inv_t2]
    }
}

impl Predictor for SecondOrderPredictor {
    #[inline(always)]
    fn output(&self) -> f64 {
        self.z[0]
    }
    #[inline(always)]
    fn advance(&mut self, _y: f64, u: f64, _e: f64, c: Correction) {
        let [z1, z2, z3] = self.z;
        let m = &self.m;
        let n1 = m[0] * z1 + m[1] * z2 + m[2] * z3 + self.g_u[0] * u + c.c1;
        let n2 = m[3] * z1 + m[4] * z2 + m[5] * z3 + self.g_u[1] * u + c.c2;
        self.z = [n1, n2, z3 + c.c3];
    }
    #[inline(always)]
    fn fault_estimate(&self) -> f64 {
        self.z[2] * self.inv_t2
    }
    #[inline(always)]
    fn equivalent_fault(&self, c: &Correction) -> f64 {
        c.c2 * self.inv_t2
    }
    #[inline(always)]
    fn magnitude(&self) -> f64 {
        self.z[0].abs().max(self.z[1].abs()).max(self.z[2].abs())
    }
    fn reset(&mut self) {
        self.z = self.z0;
    }
    fn order(&self) -> usize {
        2
    }
}

impl ModalParams {
    /// The measured channel's mode from the 5-DOF model (eqs 2.12–2.26): the sprung-mass
    /// (housing) resonance f_r, ζ_r of `spec`, sampled at `sample_rate_hz`.
    ///
    /// The housing acceleration a = ÿ_r obeys ä + 2ζω ȧ + ω² a = ω² ÿ_p + 2ζω y⃛_p, so the
    /// measured acceleration itself is X₁ of this mode and the pedestal excitation (ball contacts,
    /// spalls, gravity and everything the 10-state model couples in) is the lumped input d that
    /// the extended state estimates. Units cancel (the mode is linear), so m/s² and g both work.
    pub fn from_bearing_model(
        spec: &bearing_model::ModelSpec,
        sample_rate_hz: f64,
    ) -> Result<Self, ObserverError> {
        let p = Self {
            natural_frequency_hz: spec.housing.resonance_hz,
            damping_ratio: spec.housing.damping_ratio,
            input_gain: 0.0,
            sample_rate_hz,
        };
        p.validate()?;
        Ok(p)
    }
}
