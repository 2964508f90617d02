//! The workspace's one linear state-space model (eqs. 2.28–2.32, 4.11–4.15): the explicit
//! matrices of an identified ARX-Laguerre model ([`ArxLaguerreModel::state_space`]), a model
//! built from Laguerre poles ([`StateSpace::from_poles`]), or an all-pole (AR) model in shift
//! form ([`StateSpace::from_ar`]) — what the observers run.
//!
//! [`ArxLaguerreModel::state_space`]: crate::ArxLaguerreModel::state_space

use serde::{Deserialize, Serialize};

use crate::MAX_STATES;
use crate::error::{IdentError, Result};

/// The linear one-step model X(k+1) = A X(k) + b_y y(k) + b_u u(k), ŷ(k+1) = Kᵀ X(k+1)
/// (eqs. 2.28–2.32, 4.11–4.15), of any order n: an identified ARX-Laguerre model
/// ([`crate::ArxLaguerreModel::state_space`]), a Laguerre model from its poles
/// ([`StateSpace::from_poles`]) or the calibrated structural path of a machine model in shift
/// form ([`StateSpace::from_ar`]).
///
/// The one state-space type of the workspace: the observers run it (`observers` re-exports it;
/// its former name there, `observers::LinearModel`, is a deprecated alias). Its serialised form
/// is `{"a": [...], "b_y": [...], "b_u": [...], "k": [...]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StateSpace {
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
/// When a model has this structure, the observers' ARX-Laguerre predictor replaces the dense
/// O(n²) product A X̂ + b_y Ŷ + b_u u by the O(n) cascade of each bank,
/// x₀(k+1) = ζ x₀(k) + √(1−ζ²) s(k), xᵢ(k+1) = ζ xᵢ(k) + xᵢ₋₁(k) − ζ xᵢ₋₁(k+1),
/// which is the same linear map (see [`crate::LaguerreBank::step`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
/// [`StateSpace::laguerre_structure`] accepts (the entries are at most 1 in magnitude).
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

impl StateSpace {
    /// Number of states n.
    pub fn order(&self) -> usize {
        self.k.len()
    }

    /// Check shapes (n ≥ 1, A n×n, b_y, b_u and K of length n) and finiteness.
    ///
    /// # Errors
    /// [`IdentError::StateMismatch`] for a wrong size, [`IdentError::InvalidParameter`] for a
    /// non-finite entry.
    pub fn validate(&self) -> Result<()> {
        let n = self.k.len();
        if n == 0 {
            return Err(IdentError::StateMismatch {
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
                return Err(IdentError::StateMismatch {
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
                return Err(IdentError::InvalidParameter {
                    which: "state-space coefficient (must be finite)",
                    value: *v,
                });
            }
        }
        Ok(())
    }

    /// The model itself once [`StateSpace::validate`] accepts it.
    ///
    /// # Errors
    /// As [`StateSpace::validate`].
    pub fn validated(self) -> Result<Self> {
        self.validate()?;
        Ok(self)
    }

    /// Build the Laguerre block-diagonal A, b_y, b_u of eqs (2.29)–(2.32) for poles
    /// (ζ_a, ζ_b), orders (N_a, N_b) and Fourier coefficients K (length N_a + N_b).
    ///
    /// # Errors
    /// [`IdentError::PoleOutOfRange`] for a pole outside (−1, 1), [`IdentError::StateMismatch`]
    /// when K is not of length N_a + N_b, and the errors of [`StateSpace::validate`].
    pub fn from_poles(
        zeta_a: f64,
        n_a: usize,
        zeta_b: f64,
        n_b: usize,
        k: Vec<f64>,
    ) -> Result<Self> {
        for z in [zeta_a, zeta_b] {
            if !(z.is_finite() && z.abs() < 1.0) {
                return Err(IdentError::PoleOutOfRange { value: z });
            }
        }
        let n = n_a + n_b;
        if k.len() != n {
            return Err(IdentError::StateMismatch {
                expected: n,
                found: k.len(),
            });
        }
        let (a, b_y, b_u) = laguerre_blocks(zeta_a, n_a, zeta_b, n_b);
        Self { a, b_y, b_u, k }.validated()
    }

    /// The Laguerre structure of A, b_y, b_u (eqs 2.29–2.32), if the model has it to within
    /// [`LAGUERRE_STRUCTURE_TOLERANCE`] and n ≤ [`MAX_STATES`]; `None` for a general (dense)
    /// model.
    ///
    /// N_a is the index of the first non-zero entry of b_u (its first entry √(1−ζ_b²) is never
    /// zero), or n when b_u = 0 (AR form); ζ_a = A₀₀ and ζ_b = A_{N_a N_a}. Every entry of A, b_y
    /// and b_u is then compared with the blocks [`StateSpace::from_poles`] builds, so
    /// `from_poles` models and identified models' state spaces are recognised exactly.
    pub fn laguerre_structure(&self) -> Option<LaguerreStructure> {
        let n = self.order();
        if n == 0 || n > MAX_STATES || self.validate().is_err() {
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
    /// (the observers' `design_path_linear`) the observer's prediction is exactly the AR
    /// predictor; this is how the calibrated structural path of a machine model (the modes of
    /// the path from bearing to sensor, identified by the closed loop) becomes an observer model.
    ///
    /// # Errors
    /// [`IdentError::StateMismatch`] for an empty `ar`, [`IdentError::InvalidParameter`] for a
    /// non-finite coefficient.
    pub fn from_ar(ar: &[f64]) -> Result<Self> {
        let n = ar.len();
        let mut a = vec![0.0; n * n];
        for i in 1..n {
            a[i * n + i - 1] = 1.0;
        }
        let mut b_y = vec![0.0; n];
        if let Some(b) = b_y.first_mut() {
            *b = 1.0;
        }
        Self {
            a,
            b_y,
            b_u: vec![0.0; n],
            k: ar.iter().map(|v| -v).collect(),
        }
        .validated()
    }

    /// Whether the model is in the shift (AR) form of [`StateSpace::from_ar`]: A the
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

    /// Matrix form of eq. 4.11: X(k+1) = A X(k) + b_y y(k) + b_u u(k), ŷ(k+1) = Kᵀ X(k+1), for
    /// a state `x` of the model's order. O(n²) and allocating; an identified model's
    /// [`crate::ArxLaguerreModel::predict_next`] is the O(n), allocation-free equivalent.
    ///
    /// # Panics
    /// When `x` has fewer than [`StateSpace::order`] entries or the model's shapes are wrong
    /// ([`StateSpace::validate`]).
    pub fn step(&self, x: &[f64], y: f64, u: f64) -> (Vec<f64>, f64) {
        let n = self.order();
        let mut next = vec![0.0; n];
        let mut yhat = 0.0;
        for i in 0..n {
            let mut s = self.b_y[i] * y + self.b_u[i] * u;
            for j in 0..n {
                s += self.a[i * n + j] * x[j];
            }
            next[i] = s;
            yhat += self.k[i] * s;
        }
        (next, yhat)
    }
}
