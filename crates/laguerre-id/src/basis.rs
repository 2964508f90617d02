//! Discrete Laguerre orthonormal functions and filter banks (eqs. 4.5–4.6, 5.9–5.10) and their
//! state-space form (eqs. 2.29–2.32, 4.12–4.15).
//!
//! For a pole ζ with |ζ| < 1 the n-th Laguerre function is, in the z-domain (eq. 4.5),
//!
//! ```text
//! L_n(z) = √(1−ζ²)/(z−ζ) · ((1−ζz)/(z−ζ))^n ,      n = 0, 1, …
//! ```
//!
//! and its impulse response l_n(i), i ≥ 1 (the 1/(z−ζ) factor delays by one sample), is
//! orthonormal: Σ_{i≥1} l_n(i) l_m(i) = δ_nm. Filtering a signal s through the first N functions
//! gives the state x_n(k) = Σ_{i≥1} l_n(i) s(k−i) (eq. 4.6), which obeys
//!
//! ```text
//! x(k+1) = A x(k) + b s(k)
//! A[i][i] = ζ,   A[i][j] = (−ζ)^{i−j−1} (1−ζ²)  (i > j),   A[i][j] = 0 (i < j)
//! b[i]    = √(1−ζ²) (−ζ)^i
//! ```
//!
//! (eq. 2.30 / 4.13 and eq. 2.31 / 4.15; see `docs/equations/laguerre-id.md` for the printed
//! exponent of the last row). The cheap O(N) recursion used in the hot path is
//! x_0(k+1) = ζ x_0(k) + √(1−ζ²) s(k), x_n(k+1) = ζ x_n(k) + x_{n−1}(k) − ζ x_{n−1}(k+1).

use crate::error::{IdentError, Result};
use serde::{Deserialize, Serialize};

/// Largest order of one Laguerre bank (N_a or N_b).
pub const MAX_ORDER: usize = 16;

/// A validated Laguerre pole ζ ∈ (−1, 1) (eq. 4.5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pole(f64);

impl Pole {
    /// Validate a pole: finite and strictly inside (−1, 1).
    pub fn new(zeta: f64) -> Result<Self> {
        if zeta.is_finite() && zeta.abs() < 1.0 {
            Ok(Self(zeta))
        } else {
            Err(IdentError::PoleOutOfRange { value: zeta })
        }
    }

    /// The pole value ζ.
    pub fn value(self) -> f64 {
        self.0
    }

    /// √(1−ζ²), the gain of the first function.
    pub fn gain(self) -> f64 {
        (1.0 - self.0 * self.0).sqrt()
    }
}

/// A bank of the first `order` Laguerre filters for one pole: the block A_y (or A_u) and b_y (or
/// b_u) of eqs. 2.30–2.32 / 4.13–4.15.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LaguerreBank {
    pole: Pole,
    order: usize,
}

impl LaguerreBank {
    /// A bank of `order` functions, 1 ≤ order ≤ [`MAX_ORDER`].
    pub fn new(pole: Pole, order: usize) -> Result<Self> {
        if order == 0 || order > MAX_ORDER {
            return Err(IdentError::OrderOutOfRange {
                which: "order",
                found: order,
                min: 1,
                max: MAX_ORDER,
            });
        }
        Ok(Self { pole, order })
    }

    /// The pole ζ.
    pub fn pole(&self) -> Pole {
        self.pole
    }

    /// Number of functions N.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Entry (i, j) of the block matrix of eq. 2.30 / 4.13.
    pub fn a_entry(&self, i: usize, j: usize) -> f64 {
        let z = self.pole.value();
        if i == j {
            z
        } else if i > j {
            (-z).powi((i - j - 1) as i32) * (1.0 - z * z)
        } else {
            0.0
        }
    }

    /// Entry i of the input vector of eq. 2.31 / 4.15: √(1−ζ²)(−ζ)^i.
    pub fn b_entry(&self, i: usize) -> f64 {
        self.pole.gain() * (-self.pole.value()).powi(i as i32)
    }

    /// The block matrix as rows (row-major `order × order`).
    pub fn a_matrix(&self) -> Vec<Vec<f64>> {
        (0..self.order)
            .map(|i| (0..self.order).map(|j| self.a_entry(i, j)).collect())
            .collect()
    }

    /// The input vector b.
    pub fn b_vector(&self) -> Vec<f64> {
        (0..self.order).map(|i| self.b_entry(i)).collect()
    }

    /// One step of the filter bank, in place: x ← A x + b s (O(N) recursion, allocation free).
    /// `x` must hold at least `order` entries; entries beyond `order` are left untouched.
    #[inline]
    pub fn step(&self, x: &mut [f64], s: f64) {
        step_bank(self.pole.value(), self.pole.gain(), &mut x[..self.order], s);
    }

    /// Impulse responses l_n(i) for n < order and i = 1..=horizon (eq. 4.5), as `order` rows of
    /// length `horizon` (row n, column i−1).
    pub fn impulse_responses(&self, horizon: usize) -> Vec<Vec<f64>> {
        let mut out = vec![vec![0.0; horizon]; self.order];
        let mut x = [0.0; MAX_ORDER];
        for i in 0..horizon {
            self.step(&mut x, if i == 0 { 1.0 } else { 0.0 });
            for (n, row) in out.iter_mut().enumerate() {
                row[i] = x[n];
            }
        }
        out
    }

    /// Filter a whole signal (eq. 4.6): returns `order` rows of length `s.len()` where row n,
    /// column k holds x_n(k) = Σ_{i≥1} l_n(i) s(k−i) with s = 0 before index 0.
    pub fn filter(&self, s: &[f64]) -> Result<Vec<Vec<f64>>> {
        crate::error::check_finite("signal", s)?;
        let mut out = vec![vec![0.0; s.len()]; self.order];
        let mut x = [0.0; MAX_ORDER];
        for (k, &sk) in s.iter().enumerate() {
            for (n, row) in out.iter_mut().enumerate() {
                row[k] = x[n];
            }
            self.step(&mut x, sk);
        }
        Ok(out)
    }
}

/// The O(N) Laguerre recursion x ← A x + b s for pole `z` and gain `g` = √(1−z²).
#[inline(always)]
pub(crate) fn step_bank(z: f64, g: f64, x: &mut [f64], s: f64) {
    let mut prev_old = 0.0;
    let mut prev_new = 0.0;
    for (n, xn) in x.iter_mut().enumerate() {
        let old = *xn;
        let new = if n == 0 {
            z * old + g * s
        } else {
            z * old + prev_old - z * prev_new
        };
        *xn = new;
        prev_old = old;
        prev_new = new;
    }
}

/// Closed-form impulse response of the first Laguerre function, l_0(i) = √(1−ζ²) ζ^{i−1}, i ≥ 1.
pub fn laguerre_first(pole: Pole, i: usize) -> f64 {
    if i == 0 {
        0.0
    } else {
        pole.gain() * pole.value().powi(i as i32 - 1)
    }
}
