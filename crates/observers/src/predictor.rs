//! Models that predict the measured output one step ahead, with the observer's chain.
//!
//! A [`Predictor`] owns the model state x̂, the extended state(s) and the placement of the
//! correction increments of a [`crate::law::Correction`] on its three chain levels:
//!
//! | predictor | level 1 | level 2 | level 3 |
//! |---|---|---|---|
//! | [`SecondOrderPredictor`] (physics mode, eqs 2.26, 3.8) | X̂₁ (measured) | T·X̂₂ | T²·d̂ (lumped uncertainty/fault in the X₂ equation) |
//! | [`ArxLaguerrePredictor`] (eqs 2.28, 4.11) | state along the fault direction f | d̂ (fault, enters along f) | χ̂ (rate of d̂) |
//!
//! Levels are scaled so that one sample is one unit of time: all laws act on a chain that is
//! close to a discrete integrator chain, and a single set of per-sample gains and bounds applies
//! to every model (see `docs/equations/observers.md`).

use crate::error::ObserverError;
use crate::law::Correction;

/// A one-step-ahead output predictor with output injection and an extended state.
pub trait Predictor {
    /// ŷ(k), the prediction of the measured output from data up to k − 1.
    fn output(&self) -> f64;
    /// Advance to k + 1 given the measurement y(k), input u(k), error e(k) = y(k) − ŷ(k) and
    /// the law's increments.
    fn advance(&mut self, y: f64, u: f64, e: f64, c: Correction);
    /// The fault / lumped-uncertainty estimate d̂(k) in the model's physical units.
    fn fault_estimate(&self) -> f64;
    /// The fault-equivalent of one sample's increments (Utkin's equivalent output injection), in
    /// the units of [`Predictor::fault_estimate`]: the part of the lumped uncertainty the law
    /// is cancelling directly rather than through the extended state.
    fn equivalent_fault(&self, c: &Correction) -> f64;
    /// Largest magnitude among ŷ and the extended states, in output units (for divergence
    /// detection).
    fn magnitude(&self) -> f64;
    /// Return to the initial state.
    fn reset(&mut self);
    /// Number of model states (not counting extended states).
    fn order(&self) -> usize;
}

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

/// An ARX-Laguerre state-space model (eqs 2.28–2.32, 4.11–4.15):
/// X(k+1) = A X(k) + b_y y(k) + b_u u(k), y(k) = Kᵀ X(k).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ArxLaguerreModel {
    /// A, n×n, row-major.
    pub a: Vec<f64>,
    /// b_y, length n.
    pub b_y: Vec<f64>,
    /// b_u, length n (zeros when there is no input).
    pub b_u: Vec<f64>,
    /// K (Fourier coefficients), length n.
    pub k: Vec<f64>,
}

/// The Laguerre structure of an ARX-Laguerre model (eqs 2.29–2.32, 4.12–4.15): an output bank
/// of `n_a` functions with pole ζ_a followed by an input bank of `n_b` functions with pole ζ_b.
///
/// When a model has this structure, [`ArxLaguerrePredictor`] replaces the dense O(n²) product
/// A X̂ + b_y Ŷ + b_u u by the O(n) cascade of each bank,
/// x₀(k+1) = ζ x₀(k) + √(1−ζ²) s(k), xᵢ(k+1) = ζ xᵢ(k) + xᵢ₋₁(k) − ζ xᵢ₋₁(k+1),
/// which is the same linear map (see `laguerre_id::LaguerreBank::step`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LaguerreStructure {
    /// Output-bank pole ζ_a (0 when `n_a` = 0).
    pub zeta_a: f64,
    /// Output-bank order N_a.
    pub n_a: usize,
    /// Input-bank pole ζ_b (0 when `n_b` = 0).
    pub zeta_b: f64,
    /// Input-bank order N_b.
    pub n_b: usize,
}

/// Largest absolute deviation from the Laguerre block structure that
/// [`ArxLaguerreModel::laguerre_structure`] accepts (the entries are at most 1 in magnitude).
pub const LAGUERRE_STRUCTURE_TOLERANCE: f64 = 1e-12;

/// The Laguerre blocks of eqs (2.29)–(2.32): (A row-major, b_y, b_u) for n = n_a + n_b.
fn laguerre_blocks(
    zeta_a: f64,
    n_a: usize,
    zeta_b: f64,
    n_b: usize,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = n_a + n_b;
    let mut a = vec![0.0; n * n];
    let mut b_y = vec![0.0; n];
    let mut b_u = vec![0.0; n];
    let mut block = |off: usize, m: usize, z: f64, b: &mut [f64]| {
        let s = 1.0 - z * z;
        for i in 0..m {
            a[(off + i) * n + off + i] = z;
            for j in 0..i {
                // (2.30): entry (i, j) = (−ζ)^{i−j−1}(1 − ζ²) below the diagonal.
                a[(off + i) * n + off + j] = (-z).powi((i - j - 1) as i32) * s;
            }
            b[off + i] = s.sqrt() * (-z).powi(i as i32);
        }
    };
    block(0, n_a, zeta_a, &mut b_y);
    block(n_a, n_b, zeta_b, &mut b_u);
    (a, b_y, b_u)
}

impl ArxLaguerreModel {
    /// Number of states n.
    pub fn order(&self) -> usize {
        self.k.len()
    }

    /// Check shapes and finiteness.
    pub fn validate(&self) -> Result<(), ObserverError> {
        let n = self.k.len();
        if n == 0 {
            return Err(ObserverError::DimensionMismatch {
                expected: 1,
                found: 0,
            });
        }
        for (len, exp) in [
            (self.a.len(), n * n),
            (self.b_y.len(), n),
            (self.b_u.len(), n),
        ] {
            if len != exp {
                return Err(ObserverError::DimensionMismatch {
                    expected: exp,
                    found: len,
                });
            }
        }
        for v in self
            .a
            .iter()
            .chain(&self.b_y)
            .chain(&self.b_u)
            .chain(&self.k)
        {
            if !v.is_finite() {
                return Err(ObserverError::InvalidParameter {
                    name: "ARX-Laguerre coefficient",
                    value: *v,
                    reason: "must be finite",
                });
            }
        }
        Ok(())
    }

    /// Build the Laguerre block-diagonal A, b_y, b_u of eqs (2.29)–(2.32) for poles
    /// (ζ_a, ζ_b), orders (N_a, N_b) and Fourier coefficients K (length N_a + N_b).
    pub fn from_poles(
        zeta_a: f64,
        n_a: usize,
        zeta_b: f64,
        n_b: usize,
        k: Vec<f64>,
    ) -> Result<Self, ObserverError> {
        for (name, z) in [("zeta_a", zeta_a), ("zeta_b", zeta_b)] {
            if !(z.is_finite() && z.abs() < 1.0) {
                return Err(ObserverError::InvalidParameter {
                    name,
                    value: z,
                    reason: "Laguerre pole must satisfy |zeta| < 1",
                });
            }
        }
        let n = n_a + n_b;
        if k.len() != n {
            return Err(ObserverError::DimensionMismatch {
                expected: n,
                found: k.len(),
            });
        }
        let (a, b_y, b_u) = laguerre_blocks(zeta_a, n_a, zeta_b, n_b);
        let m = Self { a, b_y, b_u, k };
        m.validate()?;
        Ok(m)
    }

    /// The Laguerre structure of A, b_y, b_u (eqs 2.29–2.32), if the model has it to within
    /// [`LAGUERRE_STRUCTURE_TOLERANCE`] and n ≤ `laguerre_id::MAX_STATES`; `None` for a general
    /// (dense) model.
    ///
    /// N_a is the index of the first non-zero entry of b_u (its first entry √(1−ζ_b²) is never
    /// zero), or n when b_u = 0 (AR form); ζ_a = A₀₀ and ζ_b = A_{N_a N_a}. Every entry of A, b_y
    /// and b_u is then compared with the blocks [`ArxLaguerreModel::from_poles`] builds, so
    /// `from_poles` models and `laguerre-id` state spaces are recognised exactly.
    pub fn laguerre_structure(&self) -> Option<LaguerreStructure> {
        let n = self.order();
        if n == 0 || n > laguerre_id::MAX_STATES || self.validate().is_err() {
            return None;
        }
        let n_a = self.b_u.iter().position(|v| *v != 0.0).unwrap_or(n);
        let n_b = n - n_a;
        let zeta_a = if n_a > 0 { self.a[0] } else { 0.0 };
        let zeta_b = if n_b > 0 { self.a[n_a * n + n_a] } else { 0.0 };
        if !(zeta_a.abs() < 1.0 && zeta_b.abs() < 1.0) {
            return None;
        }
        let (a, b_y, b_u) = laguerre_blocks(zeta_a, n_a, zeta_b, n_b);
        let close = |x: &[f64], y: &[f64]| {
            x.iter()
                .zip(y)
                .all(|(p, q)| (p - q).abs() <= LAGUERRE_STRUCTURE_TOLERANCE)
        };
        (close(&a, &self.a) && close(&b_y, &self.b_y) && close(&b_u, &self.b_u)).then_some(
            LaguerreStructure {
                zeta_a,
                n_a,
                zeta_b,
                n_b,
            },
        )
    }

    /// The one-step predictor of an all-pole (autoregressive) model
    /// `y(k) = −a₁ y(k−1) − … − a_p y(k−p) + w(k)` in shift form: X(k) = [y(k−1), …, y(k−p)],
    /// A = the down-shift S, b_y = e₁, b_u = 0, K = −a. With the innovations gain K_p = b_y
    /// ([`crate::named::design_path_linear`]) the observer's prediction is exactly the AR
    /// predictor; this is how the calibrated structural path of a machine model (the modes of
    /// the path from bearing to sensor, identified by the closed loop) becomes an observer model.
    ///
    /// # Errors
    /// [`ObserverError::DimensionMismatch`] for an empty `ar`,
    /// [`ObserverError::InvalidParameter`] for a non-finite coefficient.
    pub fn from_ar(ar: &[f64]) -> Result<Self, ObserverError> {
        let n = ar.len();
        let mut a = vec![0.0; n * n];
        for i in 1..n {
            a[i * n + i - 1] = 1.0;
        }
        let mut b_y = vec![0.0; n];
        if let Some(b) = b_y.first_mut() {
            *b = 1.0;
        }
        let m = Self {
            a,
            b_y,
            b_u: vec![0.0; n],
            k: ar.iter().map(|v| -v).collect(),
        };
        m.validate()?;
        Ok(m)
    }

    /// Whether the model is in the shift (AR) form of [`ArxLaguerreModel::from_ar`]: A the
    /// down-shift, b_y = e₁, b_u = 0 (exactly).
    pub fn is_shift_form(&self) -> bool {
        let n = self.order();
        if n == 0 || self.validate().is_err() {
            return false;
        }
        let a_ok = (0..n).all(|i| {
            (0..n).all(|j| self.a[i * n + j] == if i >= 1 && j + 1 == i { 1.0 } else { 0.0 })
        });
        a_ok && self.b_y[0] == 1.0
            && self.b_y[1..].iter().all(|v| *v == 0.0)
            && self.b_u.iter().all(|v| *v == 0.0)
    }

    /// A + b_y Kᵀ, the model run as a parallel (simulation) model.
    pub fn closed_loop_matrix(&self) -> Vec<f64> {
        let n = self.order();
        let mut m = self.a.clone();
        for i in 0..n {
            for j in 0..n {
                m[i * n + j] += self.b_y[i] * self.k[j];
            }
        }
        m
    }
}

/// Fixed-size vectors of the O(n) Laguerre path (n ≤ `laguerre_id::MAX_STATES`, no heap).
type Fixed = [f64; laguerre_id::MAX_STATES];

/// The O(n) update of a model with [`LaguerreStructure`]: the two bank cascades fused with the
/// injection K_p e + f s and the output Kᵀ X̂(k+1).
#[derive(Debug, Clone, PartialEq)]
struct CascadeKernel {
    s: LaguerreStructure,
    gain_a: f64,
    gain_b: f64,
    /// AᵀK, so that Kᵀ X̂(k+1) = wᵀX̂(k) + β Ŷ(k) + γ u + κ e + (Kᵀf) s.
    w: Fixed,
    /// (Kᵀb_y, Kᵀb_u, KᵀK_p, Kᵀf).
    kb: [f64; 4],
    k: Fixed,
    kp: Fixed,
    f: Fixed,
    x: Fixed,
    x0: Fixed,
}

/// One bank: x ← A_bank x + b_bank drive (cascade) + kp e + f s.
///
/// The cascade runs on the model part alone (`pure`): xᵢ(k+1) − injectionᵢ =
/// ζ xᵢ(k) + xᵢ₋₁(k) − ζ (xᵢ₋₁(k+1) − injectionᵢ₋₁), an identity of the block matrix that holds
/// for any X̂(k).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn cascade_bank(z: f64, g: f64, drive: f64, e: f64, s: f64, x: &mut [f64], kp: &[f64], f: &[f64]) {
    let (Some((x0, xr)), Some((kp0, kpr)), Some((f0, fr))) =
        (x.split_first_mut(), kp.split_first(), f.split_first())
    else {
        return;
    };
    let mut prev_old = *x0;
    let mut prev_pure = z * prev_old + g * drive;
    *x0 = prev_pure + kp0 * e + f0 * s;
    for ((xi, kpi), fi) in xr.iter_mut().zip(kpr).zip(fr) {
        let old = *xi;
        let pure = z * old + prev_old - z * prev_pure;
        prev_old = old;
        prev_pure = pure;
        *xi = pure + kpi * e + fi * s;
    }
}

/// wᵀx over the fixed-size arrays with four partial sums (the padding is zero).
#[inline(always)]
fn dot_fixed(w: &Fixed, x: &Fixed) -> f64 {
    let mut acc = [0.0; 4];
    for (wc, xc) in w.chunks_exact(4).zip(x.chunks_exact(4)) {
        for i in 0..4 {
            acc[i] += wc[i] * xc[i];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

impl CascadeKernel {
    /// Advance X̂ and return Ŷ(k+1) = Kᵀ X̂(k+1), computed from X̂(k) through w = AᵀK so that the
    /// output does not wait for the cascade (the two dependency chains run in parallel).
    #[inline(always)]
    fn advance(&mut self, y_hat: f64, u: f64, e: f64, s: f64) -> f64 {
        let [kby, kbu, kkp, kf] = self.kb;
        let y_next = dot_fixed(&self.w, &self.x) + (kby * y_hat + kbu * u) + (kkp * e + kf * s);
        let na = self.s.n_a;
        let n = na + self.s.n_b;
        let (xa, xb) = self.x[..n].split_at_mut(na);
        let (kpa, kpb) = self.kp[..n].split_at(na);
        let (fa, fb) = self.f[..n].split_at(na);
        cascade_bank(self.s.zeta_a, self.gain_a, y_hat, e, s, xa, kpa, fa);
        cascade_bank(self.s.zeta_b, self.gain_b, u, e, s, xb, kpb, fb);
        y_next
    }
}

/// The general O(n²) update X̂(k+1) = A X̂ + b_y Ŷ + b_u u + K_p e + f s.
#[derive(Debug, Clone, PartialEq)]
struct DenseKernel {
    a: Vec<f64>,
    b_y: Vec<f64>,
    b_u: Vec<f64>,
    k: Vec<f64>,
    kp: Vec<f64>,
    f: Vec<f64>,
    x: Vec<f64>,
    x0: Vec<f64>,
    tmp: Vec<f64>,
}

impl DenseKernel {
    #[inline(always)]
    fn advance(&mut self, y_hat: f64, u: f64, e: f64, s: f64) -> f64 {
        let n = self.k.len();
        let mut y_next = 0.0;
        for i in 0..n {
            let row = &self.a[i * n..(i + 1) * n];
            let v = dot(row, &self.x)
                + self.b_y[i] * y_hat
                + self.b_u[i] * u
                + self.kp[i] * e
                + self.f[i] * s;
            self.tmp[i] = v;
            y_next += self.k[i] * v;
        }
        std::mem::swap(&mut self.x, &mut self.tmp);
        y_next
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Kernel {
    // Boxed: the fixed-size arrays are ~850 bytes and would bloat every observer enum.
    Cascade(Box<CascadeKernel>),
    Dense(Box<DenseKernel>),
    Shift(Box<ShiftKernel>),
}

/// The O(n) update of a model in shift (AR) form ([`ArxLaguerreModel::is_shift_form`]):
/// X̂(k+1) = S X̂(k) + e₁ Ŷ(k) + K_p e with S the down-shift (A X̂ is a copy), and the fault
/// entering the output directly: Ŷ(k+1) = Kᵀ X̂(k+1) + s. The state holds the (corrected)
/// output history, so an injection is not fed back as if it had been measured; a unit d̂ moves
/// the next prediction by one unit, as on the other models.
#[derive(Debug, Clone, PartialEq)]
struct ShiftKernel {
    k: Vec<f64>,
    kp: Vec<f64>,
    /// Zeros: the fault does not enter the state (see above).
    f: Vec<f64>,
    x: Vec<f64>,
    x0: Vec<f64>,
    /// K_p is zero past its first entry (the innovations design).
    first_only: bool,
}

impl ShiftKernel {
    #[inline(always)]
    fn advance(&mut self, y_hat: f64, e: f64, s: f64) -> f64 {
        let n = self.x.len();
        self.x.copy_within(0..n - 1, 1);
        self.x[0] = y_hat;
        if self.first_only {
            self.x[0] += self.kp[0] * e;
        } else {
            for (xi, kpi) in self.x.iter_mut().zip(&self.kp) {
                *xi += kpi * e;
            }
        }
        dot(&self.k, &self.x) + s
    }
}

/// The ARX-Laguerre observer's predictor (eqs 2.33, 3.9, 4.16, 4.18, 5.21):
///
/// X̂(k+1) = A X̂(k) + b_y Ŷ(k) + b_u u(k) + K_p e(k) + f (d̂(k) + c₁),
/// d̂(k+1) = d̂(k) + c₂ + χ̂(k), χ̂(k+1) = χ̂(k) + c₃, Ŷ(k) = Kᵀ X̂(k),
///
/// with the fault direction f normalised to Kᵀ f = 1 (so d̂ is in output units: a unit d̂ moves
/// the next prediction by one unit).
///
/// Models with the Laguerre structure ([`ArxLaguerreModel::laguerre_structure`]: every
/// `from_poles` model and every `laguerre-id` model up to `laguerre_id::MAX_STATES` states)
/// run the O(n) bank cascade on fixed-size arrays; any other A runs the dense O(n²) product.
/// The two paths agree to rounding ([`ArxLaguerrePredictor::new_dense`] forces the dense one).
#[derive(Debug, Clone, PartialEq)]
pub struct ArxLaguerrePredictor {
    n: usize,
    kernel: Kernel,
    d: f64,
    chi: f64,
    y_hat: f64,
}

impl ArxLaguerrePredictor {
    /// Build from a model, the fault direction (normalised here so that Kᵀf = 1) and the
    /// proportional output-injection vector K_p. Uses the O(n) Laguerre cascade when the model
    /// has the Laguerre structure, the dense product otherwise.
    pub fn new(
        model: &ArxLaguerreModel,
        fault_direction: &[f64],
        kp: &[f64],
    ) -> Result<Self, ObserverError> {
        Self::build(model, fault_direction, kp, true)
    }

    /// The predictor of a shift-form (AR) model ([`ArxLaguerreModel::from_ar`]) with the
    /// proportional injection K_p, run by an O(n) shift update; the fault d̂ (and the law's
    /// level-1 injection) adds to the next prediction directly instead of entering the state,
    /// so [`ArxLaguerrePredictor::fault_direction`] is zero.
    ///
    /// # Errors
    /// [`ObserverError::InvalidParameter`] when the model is not in shift form or K_p is not
    /// finite; [`ObserverError::DimensionMismatch`] when K_p has another length.
    pub fn new_path(model: &ArxLaguerreModel, kp: &[f64]) -> Result<Self, ObserverError> {
        model.validate()?;
        if !model.is_shift_form() {
            return Err(ObserverError::InvalidParameter {
                name: "model",
                value: model.order() as f64,
                reason: "not in shift (AR) form: build it with ArxLaguerreModel::from_ar",
            });
        }
        let n = model.order();
        if kp.len() != n {
            return Err(ObserverError::DimensionMismatch {
                expected: n,
                found: kp.len(),
            });
        }
        if let Some(v) = kp.iter().find(|v| !v.is_finite()) {
            return Err(ObserverError::InvalidParameter {
                name: "K_p",
                value: *v,
                reason: "must be finite",
            });
        }
        Ok(Self {
            n,
            kernel: Kernel::Shift(Box::new(ShiftKernel {
                k: model.k.clone(),
                kp: kp.to_vec(),
                f: vec![0.0; n],
                x: vec![0.0; n],
                x0: vec![0.0; n],
                first_only: kp[1..].iter().all(|v| *v == 0.0),
            })),
            d: 0.0,
            chi: 0.0,
            y_hat: 0.0,
        })
    }

    /// As [`ArxLaguerrePredictor::new`] but always with the dense O(n²) update (the reference
    /// path; results agree with the cascade to rounding).
    pub fn new_dense(
        model: &ArxLaguerreModel,
        fault_direction: &[f64],
        kp: &[f64],
    ) -> Result<Self, ObserverError> {
        Self::build(model, fault_direction, kp, false)
    }

    fn build(
        model: &ArxLaguerreModel,
        fault_direction: &[f64],
        kp: &[f64],
        allow_cascade: bool,
    ) -> Result<Self, ObserverError> {
        model.validate()?;
        let n = model.order();
        for len in [fault_direction.len(), kp.len()] {
            if len != n {
                return Err(ObserverError::DimensionMismatch {
                    expected: n,
                    found: len,
                });
            }
        }
        let kf: f64 = model
            .k
            .iter()
            .zip(fault_direction)
            .map(|(a, b)| a * b)
            .sum();
        let fnorm: f64 = fault_direction.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !kf.is_finite() || kf.abs() <= 1e-9 * fnorm.max(1e-300) {
            return Err(ObserverError::FaultDirectionInvisible { value: kf.abs() });
        }
        if let Some(v) = kp.iter().find(|v| !v.is_finite()) {
            return Err(ObserverError::InvalidParameter {
                name: "K_p",
                value: *v,
                reason: "must be finite",
            });
        }
        let f: Vec<f64> = fault_direction.iter().map(|v| v / kf).collect();
        let structure = if allow_cascade {
            model.laguerre_structure()
        } else {
            None
        };
        let kernel = match structure {
            Some(s) => {
                let fixed = |v: &[f64]| {
                    let mut a: Fixed = [0.0; laguerre_id::MAX_STATES];
                    a[..n].copy_from_slice(v);
                    a
                };
                let mut w: Fixed = [0.0; laguerre_id::MAX_STATES];
                for (i, ki) in model.k.iter().enumerate() {
                    for (j, wj) in w[..n].iter_mut().enumerate() {
                        *wj += model.a[i * n + j] * ki;
                    }
                }
                Kernel::Cascade(Box::new(CascadeKernel {
                    s,
                    gain_a: (1.0 - s.zeta_a * s.zeta_a).sqrt(),
                    gain_b: (1.0 - s.zeta_b * s.zeta_b).sqrt(),
                    w,
                    kb: [
                        dot(&model.k, &model.b_y),
                        dot(&model.k, &model.b_u),
                        dot(&model.k, kp),
                        dot(&model.k, &f),
                    ],
                    k: fixed(&model.k),
                    kp: fixed(kp),
                    f: fixed(&f),
                    x: [0.0; laguerre_id::MAX_STATES],
                    x0: [0.0; laguerre_id::MAX_STATES],
                }))
            }
            None => Kernel::Dense(Box::new(DenseKernel {
                a: model.a.clone(),
                b_y: model.b_y.clone(),
                b_u: model.b_u.clone(),
                k: model.k.clone(),
                kp: kp.to_vec(),
                f,
                x: vec![0.0; n],
                x0: vec![0.0; n],
                tmp: vec![0.0; n],
            })),
        };
        Ok(Self {
            n,
            kernel,
            d: 0.0,
            chi: 0.0,
            y_hat: 0.0,
        })
    }

    /// Whether the O(n) Laguerre cascade is in use (else the dense O(n²) product).
    pub fn uses_laguerre_cascade(&self) -> bool {
        matches!(self.kernel, Kernel::Cascade(_))
    }

    /// Whether the O(n) shift (AR-form) update is in use.
    pub fn uses_shift_form(&self) -> bool {
        matches!(self.kernel, Kernel::Shift(_))
    }

    fn parts(&self) -> (&[f64], &[f64], &[f64], &[f64]) {
        let n = self.n;
        match &self.kernel {
            Kernel::Cascade(c) => (&c.k[..n], &c.f[..n], &c.x[..n], &c.x0[..n]),
            Kernel::Dense(d) => (&d.k, &d.f, &d.x, &d.x0),
            Kernel::Shift(d) => (&d.k, &d.f, &d.x, &d.x0),
        }
    }

    fn state_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        let n = self.n;
        match &mut self.kernel {
            Kernel::Cascade(c) => (&mut c.x[..n], &mut c.x0[..n]),
            Kernel::Dense(d) => (&mut d.x[..], &mut d.x0[..]),
            Kernel::Shift(d) => (&mut d.x[..], &mut d.x0[..]),
        }
    }

    /// Set the initial state estimate (length n; also what [`Predictor::reset`] returns to);
    /// keeps d̂ and χ̂.
    pub fn set_state(&mut self, x: &[f64]) -> Result<(), ObserverError> {
        if x.len() != self.n {
            return Err(ObserverError::DimensionMismatch {
                expected: self.n,
                found: x.len(),
            });
        }
        let (cur, init) = self.state_mut();
        cur.copy_from_slice(x);
        init.copy_from_slice(x);
        let (k, _, xs, _) = self.parts();
        self.y_hat = dot(k, xs);
        Ok(())
    }

    /// The normalised fault direction f (Kᵀ f = 1).
    pub fn fault_direction(&self) -> &[f64] {
        self.parts().1
    }

    /// Current state estimate.
    pub fn state(&self) -> &[f64] {
        self.parts().2
    }
}

#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Predictor for ArxLaguerrePredictor {
    #[inline(always)]
    fn output(&self) -> f64 {
        self.y_hat
    }
    #[inline(always)]
    fn advance(&mut self, _y: f64, u: f64, e: f64, c: Correction) {
        let s = self.d + c.c1;
        let yh = self.y_hat;
        self.y_hat = match &mut self.kernel {
            Kernel::Cascade(k) => k.advance(yh, u, e, s),
            Kernel::Dense(k) => k.advance(yh, u, e, s),
            Kernel::Shift(k) => k.advance(yh, e, s),
        };
        self.d += c.c2 + self.chi;
        self.chi += c.c3;
    }
    #[inline(always)]
    fn fault_estimate(&self) -> f64 {
        self.d
    }
    #[inline(always)]
    fn equivalent_fault(&self, c: &Correction) -> f64 {
        c.c1
    }
    #[inline(always)]
    fn magnitude(&self) -> f64 {
        self.y_hat.abs().max(self.d.abs()).max(self.chi.abs())
    }
    fn reset(&mut self) {
        let (cur, init) = self.state_mut();
        cur.copy_from_slice(init);
        self.d = 0.0;
        self.chi = 0.0;
        let (k, _, xs, _) = self.parts();
        self.y_hat = dot(k, xs);
    }
    fn order(&self) -> usize {
        self.n
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

impl ArxLaguerreModel {
    /// Convert an identified model's explicit matrices (eqs 4.11–4.15, `laguerre-id`), which use
    /// the same convention X(k+1) = A X + b_y y + b_u u, ŷ = Kᵀ X.
    pub fn from_state_space(ss: &laguerre_id::StateSpace) -> Result<Self, ObserverError> {
        let n = ss.n_states;
        if n == 0 || n > laguerre_id::MAX_STATES {
            return Err(ObserverError::DimensionMismatch {
                expected: laguerre_id::MAX_STATES,
                found: n,
            });
        }
        let mut a = Vec::with_capacity(n * n);
        for row in ss.a.iter().take(n) {
            a.extend_from_slice(&row[..n]);
        }
        let m = Self {
            a,
            b_y: ss.b_y[..n].to_vec(),
            b_u: ss.b_u[..n].to_vec(),
            k: ss.k[..n].to_vec(),
        };
        m.validate()?;
        Ok(m)
    }
}

/// The fuzzy ARX-Laguerre predictor of eq. (5.19) with the observer's chain: the ARX-Laguerre
/// part is an [`ArxLaguerrePredictor`] (injection, d̂, χ̂ as there) and the fuzzy term
/// σ_f J_f(k), J_f = Table 5.1 inference on (e_b(k), e_b(k) − e_b(k−1)), is filtered by the
/// model's J_f Laguerre bank and added to the output with its coefficients λ_f (`fuzzy-ts`),
/// where e_b = y − Kᵀ X̂ is the error of the observer's ARX-Laguerre part (eqs 5.21, 5.25, 5.30
/// carry σ_f J_f inside the observer).
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

    /// The ARX-Laguerre part of the model as this crate's [`ArxLaguerreModel`].
    pub fn base_model(fal: &fuzzy_ts::FuzzyArxLaguerre) -> Result<ArxLaguerreModel, ObserverError> {
        ArxLaguerreModel::from_state_space(&fal.base().state_space())
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
        // fitted to predict (fuzzy-ts, stage 2).
        let e_base = y - self.base.output();
        let jf = self.fal.inference().infer(e_base, e_base - self.e_prev);
        self.e_prev = e_base;
        self.base.advance(y, u, e, c);
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
