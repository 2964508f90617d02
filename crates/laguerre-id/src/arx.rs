//! Plain ARX identification (eq. 5.5):
//! y(k) = Σ_{i=1}^{n_a} a_i y(k−i) + Σ_{i=1}^{n_b} b_i u(k−i), fitted by least squares.

use crate::error::{IdentError, Result, check_finite};
use crate::lstsq;
use serde::{Deserialize, Serialize};

/// Largest ARX order accepted (lags per polynomial).
pub const MAX_ARX_ORDER: usize = 512;

/// Orders (δ_x, δ_y) of eq. 5.5: `n_a` output lags (≥ 1), `n_b` input lags (0 = no input, AR form).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArxOrders {
    n_a: usize,
    n_b: usize,
}

impl ArxOrders {
    /// Validate 1 ≤ n_a ≤ [`MAX_ARX_ORDER`], 0 ≤ n_b ≤ [`MAX_ARX_ORDER`].
    pub fn new(n_a: usize, n_b: usize) -> Result<Self> {
        if n_a == 0 || n_a > MAX_ARX_ORDER {
            return Err(IdentError::OrderOutOfRange {
                which: "n_a",
                found: n_a,
                min: 1,
                max: MAX_ARX_ORDER,
            });
        }
        if n_b > MAX_ARX_ORDER {
            return Err(IdentError::OrderOutOfRange {
                which: "n_b",
                found: n_b,
                min: 0,
                max: MAX_ARX_ORDER,
            });
        }
        Ok(Self { n_a, n_b })
    }
    /// Output lags n_a.
    pub fn n_a(&self) -> usize {
        self.n_a
    }
    /// Input lags n_b.
    pub fn n_b(&self) -> usize {
        self.n_b
    }
}

/// Check y/u lengths, finiteness, and that `n_b > 0` exactly when an input is present.
pub(crate) fn check_io(y: &[f64], u: Option<&[f64]>, n_b: usize) -> Result<()> {
    check_finite("y", y)?;
    match u {
        Some(u) => {
            if u.len() != y.len() {
                return Err(IdentError::LengthMismatch {
                    expected: y.len(),
                    found: u.len(),
                });
            }
            check_finite("u", u)?;
            if n_b == 0 {
                return Err(IdentError::InputMismatch {
                    n_b,
                    has_input: true,
                });
            }
        }
        None => {
            if n_b != 0 {
                return Err(IdentError::InputMismatch {
                    n_b,
                    has_input: false,
                });
            }
        }
    }
    Ok(())
}

/// An identified ARX model (eq. 5.5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArxModel {
    /// Output coefficients a_1..a_{n_a} (ε_x of eq. 5.5).
    pub a: Vec<f64>,
    /// Input coefficients b_1..b_{n_b} (ε_y of eq. 5.5); empty for the AR form.
    pub b: Vec<f64>,
}

impl ArxModel {
    /// Identify by least squares over k = max(n_a, n_b) .. len (eq. 5.5; no zero padding).
    pub fn identify(y: &[f64], u: Option<&[f64]>, orders: ArxOrders) -> Result<Self> {
        check_io(y, u, orders.n_b)?;
        let (na, nb) = (orders.n_a, orders.n_b);
        let start = na.max(nb);
        let p = na + nb;
        let rows = y.len().saturating_sub(start);
        if rows < 2 * p {
            return Err(IdentError::TooFewSamples {
                found: y.len(),
                needed: start + 2 * p,
            });
        }
        let uu = u.unwrap_or(&[]);
        let theta = lstsq::solve(
            rows,
            p,
            |r, c| {
                let k = start + r;
                if c < na {
                    y[k - 1 - c]
                } else {
                    uu[k - 1 - (c - na)]
                }
            },
            &y[start..],
        )?;
        Ok(Self {
            a: theta[..na].to_vec(),
            b: theta[na..].to_vec(),
        })
    }

    /// One-step-ahead predictions ŷ(k) from measured past y and u (values before index 0 taken as
    /// zero). Same length as `y`.
    pub fn predict(&self, y: &[f64], u: Option<&[f64]>) -> Result<Vec<f64>> {
        check_io(y, u, self.b.len())?;
        let uu = u.unwrap_or(&[]);
        Ok((0..y.len())
            .map(|k| {
                let mut s = 0.0;
                for (i, a) in self.a.iter().enumerate().take(k) {
                    s += a * y[k - 1 - i];
                }
                for (i, b) in self.b.iter().enumerate().take(k) {
                    s += b * uu[k - 1 - i];
                }
                s
            })
            .collect())
    }

    /// Free-run simulation: the model's own output replaces y in the regressor after the first
    /// `n_a` samples, which are taken from `y` (initial conditions).
    pub fn simulate(&self, y: &[f64], u: Option<&[f64]>) -> Result<Vec<f64>> {
        check_io(y, u, self.b.len())?;
        let uu = u.unwrap_or(&[]);
        let na = self.a.len();
        let mut out = vec![0.0; y.len()];
        for k in 0..y.len() {
            if k < na {
                out[k] = y[k];
                continue;
            }
            let mut s = 0.0;
            for (i, a) in self.a.iter().enumerate() {
                s += a * out[k - 1 - i];
            }
            for (i, b) in self.b.iter().enumerate().take(k) {
                s += b * uu[k - 1 - i];
            }
            out[k] = s;
        }
        Ok(out)
    }
}
