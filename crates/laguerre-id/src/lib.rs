//! ARX and ARX-Laguerre system identification (Piltan 2020, ch. 2, 4 and 5).
//!
//! - [`basis`]: discrete Laguerre functions and filter banks for a pole ζ (eqs. 4.5–4.6, 5.9–5.10)
//!   and the exact state-space blocks A_y, A_u, b_y, b_u (eqs. 2.29–2.32, 4.12–4.15).
//! - [`arx`]: plain ARX least squares (eq. 5.5).
//! - [`arx_laguerre`]: ARX-Laguerre identification of the Fourier coefficients (eqs. 4.7, 5.8),
//!   pole choice (eq. 4.10), one-step prediction and free-run simulation, and an allocation-free
//!   per-sample predictor ([`ArxLaguerreModel::predict_next`]) for observers.
//! - [`metrics`]: NRMSE and residual variance.
//! - [`state_space`]: the workspace's one linear state-space model [`StateSpace`] (A, b_y, b_u,
//!   K of any order: an identified model's explicit matrices, a Laguerre model from its poles,
//!   an AR model in shift form), which the observers run.
//!
//! The crate knows nothing about bearings: it takes slices of samples.
//!
//! # Dependencies and why
//! - `faer`: column-pivoted QR for the tall least-squares problems (120 000 × 16) and Cholesky
//!   inside the pole search; fast and numerically sound.
//! - `serde`: models and configs are serialisable for reports.
//! - `thiserror`: the single typed error enum [`IdentError`].
//! - `sampled-signal`: the workspace's one finite check of a slice (`first_non_finite`).
//!
//! The per-sample path uses fixed-size arrays (`[f64; MAX_STATES]`), no faer, no allocation.
//!
//! # Example
//! ```
//! use laguerre_id::{ArxLaguerreConfig, ArxLaguerreModel, FitMetrics, PoleChoice};
//! // A damped resonance driven by a deterministic pseudo-random input.
//! let n = 4000;
//! let mut u = vec![0.0; n];
//! let mut s: u64 = 1;
//! for v in u.iter_mut() {
//!     s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
//!     *v = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
//! }
//! let mut y = vec![0.0; n];
//! for k in 2..n {
//!     y[k] = 1.5 * y[k - 1] - 0.7 * y[k - 2] + 0.5 * u[k - 1];
//! }
//! let cfg = ArxLaguerreConfig::new(4, 2, PoleChoice::DEFAULT_SEARCH)?;
//! let model = ArxLaguerreModel::identify(&y, Some(&u), &cfg)?;
//! let yhat = model.predict(&y, Some(&u))?;
//! let fit = FitMetrics::compute(&y[100..], &yhat[100..])?;
//! assert!(fit.nrmse < 0.05);
//! // Allocation-free per-sample use, e.g. inside an observer:
//! let (next, yhat1) = model.predict_next(&Default::default(), y[0], u[0]);
//! # let _ = (next, yhat1);
//! # Ok::<(), laguerre_id::IdentError>(())
//! ```

// Index loops mirror the equations' subscripts in the numeric kernels.
#![allow(clippy::needless_range_loop)]

pub mod arx;
pub mod arx_laguerre;
pub mod basis;
pub mod error;
mod lstsq;
pub mod metrics;
pub mod optimize;
pub mod state_space;

pub use arx::{ArxModel, ArxOrders};
pub use arx_laguerre::{
    ArxLaguerreConfig, ArxLaguerreModel, LaguerreState, MAX_STATES, OrderScore, PoleChoice,
};
pub use basis::{LaguerreBank, MAX_ORDER, Pole};
pub use error::{IdentError, Result};
pub use metrics::FitMetrics;
pub use state_space::{LAGUERRE_STRUCTURE_TOLERANCE, LaguerreStructure, StateSpace};

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
