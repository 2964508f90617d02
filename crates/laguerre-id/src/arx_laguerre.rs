//! ARX-Laguerre identification (eqs. 2.27–2.32, 4.4–4.15, 5.6–5.18).
//!
//! The ARX coefficient sequences of eq. 5.5 are expanded on Laguerre bases (eq. 5.6), which
//! turns the model into a linear regression on the Laguerre-filtered output and input
//! (eqs. 4.6–4.7, 5.8):
//!
//! ```text
//! y(k) = Σ_{n<N_a} K_{n,a} x_{n,y}(k) + Σ_{n<N_b} K_{n,b} x_{n,u}(k)
//! X(k+1) = A X(k) + b_y y(k) + b_u u(k),        ŷ(k+1) = Kᵀ X(k+1)        (eq. 4.11)
//! ```
//!
//! The Fourier coefficients K are fitted by least squares (faer QR); the poles come from a
//! [`PoleChoice`].

use crate::arx::{ArxModel, ArxOrders, check_io};
use crate::basis::{LaguerreBank, MAX_ORDER, Pole, step_bank};
use crate::error::{IdentError, Result};
use crate::lstsq;
use crate::state_space::StateSpace;
use serde::{Deserialize, Serialize};

/// Largest state dimension N_a + N_b.
pub const MAX_STATES: usize = 2 * MAX_ORDER;

/// How the poles ζ_a, ζ_b are chosen (eq. 4.10).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum PoleChoice {
    /// Given poles (ζ_b is ignored for the AR form).
    Fixed {
        /// Output-bank pole ζ_a.
        zeta_a: f64,
        /// Input-bank pole ζ_b.
        zeta_b: f64,
    },
    /// Eq. 4.10 read literally: fit a long plain ARX model (eq. 5.5) with `arx_order` lags, then
    /// pick for each polynomial the pole whose first N Laguerre functions capture most of the
    /// coefficient sequence, i.e. minimise ‖ε − Σ_{n<N} K_n l_n‖² (orthonormal projection).
    ArxProjection {
        /// Lags of the preliminary ARX fit (≥ 2 N_a, ≥ 2 N_b).
        arx_order: usize,
    },
    /// Minimise the one-step prediction error on the fitting data directly: a grid of `grid`
    /// poles over [−0.98, 0.98] then `refine` golden-section steps, alternating ζ_a and ζ_b until
    /// they settle (≤ 4 rounds); the cost is evaluated on at most `max_samples` samples.
    PredictionError {
        /// Grid points per coordinate (≥ 3).
        grid: usize,
        /// Golden-section iterations after the grid (≥ 0).
        refine: usize,
        /// Samples used for the cost (≥ 100).
        max_samples: usize,
    },
}

impl PoleChoice {
    /// The default search: 25-point grid, 30 golden-section steps, 30 000 samples.
    pub const DEFAULT_SEARCH: PoleChoice = PoleChoice::PredictionError {
        grid: 25,
        refine: 30,
        max_samples: 30_000,
    };
}

/// Validated identification settings: orders (N_a, N_b) and the pole choice.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ArxLaguerreConfig {
    n_a: usize,
    n_b: usize,
    poles: PoleChoice,
}

impl ArxLaguerreConfig {
    /// 1 ≤ N_a ≤ [`MAX_ORDER`], 0 ≤ N_b ≤ [`MAX_ORDER`] (0 = AR form, no input), and a valid pole
    /// choice.
    pub fn new(n_a: usize, n_b: usize, poles: PoleChoice) -> Result<Self> {
        if n_a == 0 || n_a > MAX_ORDER {
            return Err(IdentError::OrderOutOfRange {
                which: "n_a",
                found: n_a,
                min: 1,
                max: MAX_ORDER,
            });
        }
        if n_b > MAX_ORDER {
            return Err(IdentError::OrderOutOfRange {
                which: "n_b",
                found: n_b,
                min: 0,
                max: MAX_ORDER,
            });
        }
        match poles {
            PoleChoice::Fixed { zeta_a, zeta_b } => {
                Pole::new(zeta_a)?;
                if n_b > 0 {
                    Pole::new(zeta_b)?;
                }
            }
            PoleChoice::ArxProjection { arx_order } => {
                let need = 2 * n_a.max(n_b);
                if arx_order < need || arx_order > crate::arx::MAX_ARX_ORDER {
                    return Err(IdentError::OrderOutOfRange {
                        which: "arx_order",
                        found: arx_order,
                        min: need,
                        max: crate::arx::MAX_ARX_ORDER,
                    });
                }
            }
            PoleChoice::PredictionError {
                grid, max_samples, ..
            } => {
                if grid < 3 {
                    return Err(IdentError::InvalidParameter {
                        which: "grid",
                        value: grid as f64,
                    });
                }
                if max_samples < 100 {
                    return Err(IdentError::InvalidParameter {
                        which: "max_samples",
                        value: max_samples as f64,
                    });
                }
            }
        }
        Ok(Self { n_a, n_b, poles })
    }
    /// Output order N_a.
    pub fn n_a(&self) -> usize {
        self.n_a
    }
    /// Input order N_b.
    pub fn n_b(&self) -> usize {
        self.n_b
    }
    /// Pole choice.
    pub fn poles(&self) -> PoleChoice {
        self.poles
    }
}

/// The filter state X(k) of eq. 4.11: first N_a entries filter y, next N_b filter u; entries
/// beyond N_a + N_b are zero. `Copy`, 128 bytes, allocation free.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct LaguerreState {
    /// State entries (only the first `n_states` are used).
    pub x: [f64; MAX_STATES],
}

/// One candidate's orders (N_a, N_b) and its held-out one-step NRMSE
/// ([`ArxLaguerreModel::identify_orders`]).
pub type OrderScore = ((usize, usize), f64);

/// An identified ARX-Laguerre model (eq. 4.11): two Laguerre banks and the Fourier coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ArxLaguerreModel {
    bank_a: LaguerreBank,
    bank_b: Option<LaguerreBank>,
    k: [f64; MAX_STATES],
}

impl ArxLaguerreModel {
    /// Build a model from known poles, orders and coefficients (`coeffs.len() == N_a + N_b`).
    pub fn from_parts(
        bank_a: LaguerreBank,
        bank_b: Option<LaguerreBank>,
        coeffs: &[f64],
    ) -> Result<Self> {
        let n = bank_a.order() + bank_b.map_or(0, |b| b.order());
        if coeffs.len() != n {
            return Err(IdentError::StateMismatch {
                expected: n,
                found: coeffs.len(),
            });
        }
        crate::error::check_finite("coeffs", coeffs)?;
        let mut k = [0.0; MAX_STATES];
        k[..n].copy_from_slice(coeffs);
        Ok(Self { bank_a, bank_b, k })
    }

    /// Identify the Fourier coefficients by least squares for the configured orders and poles
    /// (eqs. 4.7, 4.10). `u` must be `Some` exactly when N_b > 0.
    pub fn identify(y: &[f64], u: Option<&[f64]>, cfg: &ArxLaguerreConfig) -> Result<Self> {
        check_io(y, u, cfg.n_b)?;
        let p = cfg.n_a + cfg.n_b;
        if y.len() < 4 * p + 8 {
            return Err(IdentError::TooFewSamples {
                found: y.len(),
                needed: 4 * p + 8,
            });
        }
        let (za, zb) = choose_poles(y, u, cfg)?;
        let bank_a = LaguerreBank::new(za, cfg.n_a)?;
        let bank_b = if cfg.n_b > 0 {
            Some(LaguerreBank::new(zb, cfg.n_b)?)
        } else {
            None
        };
        let regs = regressors(y, u, &bank_a, bank_b.as_ref(), y.len());
        let theta = lstsq::solve(y.len(), p, |r, c| regs[c][r], y)?;
        Self::from_parts(bank_a, bank_b, &theta)
    }

    /// Choose the output order N_a (and the poles, by `cfg`'s pole choice) by held-out one-step
    /// prediction error (eq. 4.10's criterion applied to the order as well): for every
    /// candidate N_a, identify on the first `1 − holdout` of `y` and score the NRMSE of the
    /// one-step prediction on the rest; the candidate with the smallest held-out NRMSE wins (the
    /// smaller order on a tie within 1 %), and is re-identified on the whole of `y`. AR form
    /// (N_b = 0) only. Returns the model and the held-out NRMSE of every candidate tried.
    ///
    /// # Errors
    /// [`IdentError::OrderOutOfRange`] for an empty or out-of-range candidate list (or when no
    /// candidate can be identified), [`IdentError::InvalidParameter`] for a `holdout` outside
    /// [0.1, 0.5], or any identification error of the winner.
    pub fn identify_order(
        y: &[f64],
        candidates: &[usize],
        holdout: f64,
        poles: PoleChoice,
    ) -> Result<(Self, Vec<(usize, f64)>)> {
        let pairs: Vec<(usize, usize)> = candidates.iter().map(|&n_a| (n_a, 0)).collect();
        let (m, scores) = Self::identify_orders(y, None, &pairs, holdout, poles)?;
        Ok((
            m,
            scores.into_iter().map(|((n_a, _), e)| (n_a, e)).collect(),
        ))
    }

    /// [`Self::identify_order`] with an exogenous input: the orders (N_a, N_b) are chosen
    /// together among `candidates` by held-out one-step NRMSE (identify on the first
    /// `1 − holdout` of `y` and `u`, score the rest); the smallest N_a + N_b within 1 % of the
    /// best wins (the smaller N_a on equal sums), re-identified on the whole of `y`. `u` must be
    /// `Some` exactly when a candidate has N_b > 0. Returns the model and the held-out NRMSE of
    /// every candidate that could be identified.
    ///
    /// # Errors
    /// As [`Self::identify_order`], and [`Self::identify`]'s input errors (`u` missing, or of
    /// another length than `y`).
    pub fn identify_orders(
        y: &[f64],
        u: Option<&[f64]>,
        candidates: &[(usize, usize)],
        holdout: f64,
        poles: PoleChoice,
    ) -> Result<(Self, Vec<OrderScore>)> {
        if !(0.1..=0.5).contains(&holdout) {
            return Err(IdentError::InvalidParameter {
                which: "holdout",
                value: holdout,
            });
        }
        if candidates.is_empty() {
            return Err(IdentError::OrderOutOfRange {
                which: "candidates (none given)",
                found: 0,
                min: 1,
                max: MAX_ORDER,
            });
        }
        let n_fit = ((1.0 - holdout) * y.len() as f64).round() as usize;
        let head = |v: &[f64]| -> Vec<f64> { v[..n_fit.min(v.len())].to_vec() };
        let u_fit = u.map(head);
        let mut scores = Vec::with_capacity(candidates.len());
        for &(n_a, n_b) in candidates {
            let cfg = ArxLaguerreConfig::new(n_a, n_b, poles)?;
            let u_c = if n_b > 0 { u_fit.as_deref() } else { None };
            let Ok(m) = Self::identify(&y[..n_fit], u_c, &cfg) else {
                continue;
            };
            let yhat = m.predict(y, if n_b > 0 { u } else { None })?;
            let fit = crate::FitMetrics::compute(&y[n_fit..], &yhat[n_fit..])?;
            if fit.nrmse.is_finite() {
                scores.push(((n_a, n_b), fit.nrmse));
            }
        }
        let best = scores.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
        let chosen = scores
            .iter()
            .filter(|s| s.1 <= best * 1.01)
            .map(|s| s.0)
            .min_by_key(|&(n_a, n_b)| (n_a + n_b, n_a))
            .ok_or(IdentError::OrderOutOfRange {
                which: "candidates (none could be identified)",
                found: candidates.len(),
                min: 1,
                max: MAX_ORDER,
            })?;
        let (n_a, n_b) = chosen;
        let m = Self::identify(
            y,
            if n_b > 0 { u } else { None },
            &ArxLaguerreConfig::new(n_a, n_b, poles)?,
        )?;
        Ok((m, scores))
    }

    /// Output order N_a.
    pub fn n_a(&self) -> usize {
        self.bank_a.order()
    }
    /// Input order N_b (0 for the AR form).
    pub fn n_b(&self) -> usize {
        self.bank_b.map_or(0, |b| b.order())
    }
    /// State dimension N_a + N_b.
    pub fn n_states(&self) -> usize {
        self.n_a() + self.n_b()
    }
    /// Output pole ζ_a.
    pub fn pole_a(&self) -> Pole {
        self.bank_a.pole()
    }
    /// Input pole ζ_b, if the model has an input.
    pub fn pole_b(&self) -> Option<Pole> {
        self.bank_b.map(|b| b.pole())
    }
    /// Output bank.
    pub fn bank_a(&self) -> LaguerreBank {
        self.bank_a
    }
    /// Input bank, if any.
    pub fn bank_b(&self) -> Option<LaguerreBank> {
        self.bank_b
    }
    /// Fourier coefficients K (length N_a + N_b).
    pub fn coefficients(&self) -> &[f64] {
        &self.k[..self.n_states()]
    }

    /// The explicit matrices A (block diagonal of A_y, A_u), b_y, b_u, K of eqs. 4.12–4.15, as
    /// the workspace's state-space type (n = N_a + N_b states, A row-major).
    pub fn state_space(&self) -> StateSpace {
        let (na, nb) = (self.n_a(), self.n_b());
        let n = na + nb;
        let mut ss = StateSpace {
            a: vec![0.0; n * n],
            b_y: vec![0.0; n],
            b_u: vec![0.0; n],
            k: self.k[..n].to_vec(),
        };
        for i in 0..na {
            for j in 0..na {
                ss.a[i * n + j] = self.bank_a.a_entry(i, j);
            }
            ss.b_y[i] = self.bank_a.b_entry(i);
        }
        if let Some(bb) = self.bank_b {
            for i in 0..nb {
                for j in 0..nb {
                    ss.a[(na + i) * n + na + j] = bb.a_entry(i, j);
                }
                ss.b_u[na + i] = bb.b_entry(i);
            }
        }
        ss
    }

    /// ŷ = Kᵀ X for a state.
    #[inline]
    pub fn output(&self, state: &LaguerreState) -> f64 {
        let n = self.n_states();
        let mut s = 0.0;
        for i in 0..n {
            s += self.k[i] * state.x[i];
        }
        s
    }

    /// One step of eq. 4.11 without faults: X(k+1) = A X(k) + b_y y(k) + b_u u(k) and
    /// ŷ(k+1) = Kᵀ X(k+1). O(N_a + N_b), allocation free; `u` is ignored for the AR form.
    #[inline]
    pub fn predict_next(&self, state: &LaguerreState, y: f64, u: f64) -> (LaguerreState, f64) {
        let mut next = *state;
        self.advance(&mut next, y, u);
        let yhat = self.output(&next);
        (next, yhat)
    }

    /// In-place variant of [`Self::predict_next`]'s state update.
    #[inline]
    pub fn advance(&self, state: &mut LaguerreState, y: f64, u: f64) {
        let na = self.n_a();
        let a = self.bank_a.pole();
        step_bank(a.value(), a.gain(), &mut state.x[..na], y);
        if let Some(bb) = self.bank_b {
            let b = bb.pole();
            step_bank(b.value(), b.gain(), &mut state.x[na..na + bb.order()], u);
        }
    }

    /// One-step-ahead predictions ŷ(k) = Kᵀ X(k) for every k (zero initial state).
    pub fn predict(&self, y: &[f64], u: Option<&[f64]>) -> Result<Vec<f64>> {
        check_io(y, u, self.n_b())?;
        let mut st = LaguerreState::default();
        let mut out = Vec::with_capacity(y.len());
        for k in 0..y.len() {
            out.push(self.output(&st));
            self.advance(&mut st, y[k], u.map_or(0.0, |u| u[k]));
        }
        Ok(out)
    }

    /// Free-run simulation: the measured y drives the state for the first `init` samples, the
    /// model's own output afterwards.
    pub fn simulate(&self, y: &[f64], u: Option<&[f64]>, init: usize) -> Result<Vec<f64>> {
        check_io(y, u, self.n_b())?;
        let mut st = LaguerreState::default();
        let mut out = Vec::with_capacity(y.len());
        for k in 0..y.len() {
            let yhat = self.output(&st);
            out.push(yhat);
            let drive = if k < init { y[k] } else { yhat };
            self.advance(&mut st, drive, u.map_or(0.0, |u| u[k]));
        }
        Ok(out)
    }

    /// The ARX coefficient sequences the model implies (eq. 5.6): ε_x(i) = Σ_n K_{n,a} l_n^a(i)
    /// and ε_y(i) = Σ_n K_{n,b} l_n^b(i) for i = 1..=horizon.
    pub fn equivalent_arx(&self, horizon: usize) -> ArxModel {
        let combine = |bank: &LaguerreBank, k: &[f64]| -> Vec<f64> {
            let l = bank.impulse_responses(horizon);
            (0..horizon)
                .map(|i| l.iter().zip(k).map(|(row, kn)| row[i] * kn).sum())
                .collect()
        };
        let na = self.n_a();
        let a = combine(&self.bank_a, &self.k[..na]);
        let b = self
            .bank_b
            .map_or(Vec::new(), |bb| combine(&bb, &self.k[na..na + bb.order()]));
        ArxModel { a, b }
    }
}

/// Laguerre-filtered regressors, one row per column of Φ (column-major for cache-friendly
/// filling): N_a filtered outputs then N_b filtered inputs, over the first `len` samples.
fn regressors(
    y: &[f64],
    u: Option<&[f64]>,
    ba: &LaguerreBank,
    bb: Option<&LaguerreBank>,
    len: usize,
) -> Vec<Vec<f64>> {
    let na = ba.order();
    let nb = bb.map_or(0, |b| b.order());
    let mut cols = vec![vec![0.0; len]; na + nb];
    let mut xa = [0.0; MAX_ORDER];
    let mut xb = [0.0; MAX_ORDER];
    for k in 0..len {
        for n in 0..na {
            cols[n][k] = xa[n];
        }
        for n in 0..nb {
            cols[na + n][k] = xb[n];
        }
        ba.step(&mut xa, y[k]);
        if let (Some(b), Some(u)) = (bb, u) {
            b.step(&mut xb, u[k]);
        }
    }
    cols
}

/// Residual sum of squares of the LS fit for given poles on the first `len` samples (normal
/// equations); +∞ when the fit fails.
fn rss_for(
    y: &[f64],
    u: Option<&[f64]>,
    za: f64,
    zb: f64,
    na: usize,
    nb: usize,
    len: usize,
) -> f64 {
    let (Ok(pa), Ok(pb)) = (Pole::new(za), Pole::new(zb)) else {
        return f64::INFINITY;
    };
    let Ok(ba) = LaguerreBank::new(pa, na) else {
        return f64::INFINITY;
    };
    let bb = if nb > 0 {
        LaguerreBank::new(pb, nb).ok()
    } else {
        None
    };
    let p = na + nb;
    let mut gram = vec![0.0; p * p];
    let mut rhs = vec![0.0; p];
    let mut tt = 0.0;
    let mut xa = [0.0; MAX_ORDER];
    let mut xb = [0.0; MAX_ORDER];
    let mut row = [0.0; MAX_STATES];
    for k in 0..len {
        row[..na].copy_from_slice(&xa[..na]);
        row[na..p].copy_from_slice(&xb[..nb]);
        let t = y[k];
        for i in 0..p {
            rhs[i] += row[i] * t;
            for j in 0..=i {
                gram[i * p + j] += row[i] * row[j];
            }
        }
        tt += t * t;
        ba.step(&mut xa, y[k]);
        if let (Some(b), Some(u)) = (bb.as_ref(), u) {
            b.step(&mut xb, u[k]);
        }
    }
    for i in 0..p {
        for j in 0..i {
            gram[j * p + i] = gram[i * p + j];
        }
    }
    lstsq::normal_rss(p, &gram, &rhs, tt).unwrap_or(f64::INFINITY)
}

/// Minimise `f` over [lo, hi]: a uniform grid of `grid` points, then `refine` golden-section
/// steps around the best grid point.
pub(crate) fn minimize_1d(
    f: impl Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    grid: usize,
    refine: usize,
) -> (f64, f64) {
    let step = (hi - lo) / (grid - 1) as f64;
    let mut best = (lo, f(lo));
    for i in 1..grid {
        let x = lo + step * i as f64;
        let v = f(x);
        if v < best.1 {
            best = (x, v);
        }
    }
    let (a, b) = ((best.0 - step).max(lo), (best.0 + step).min(hi));
    let refined = crate::optimize::golden_min(&f, a, b, refine);
    if refined.1 < best.1 {
        best = refined;
    }
    best
}

/// Fraction of ‖h‖² the first `n` Laguerre functions of pole ζ capture (orthonormal projection,
/// eq. 4.10); `h[i-1]` is the coefficient of lag i.
pub fn captured_energy(h: &[f64], zeta: f64, n: usize) -> f64 {
    let (Ok(p), true) = (Pole::new(zeta), n > 0 && n <= MAX_ORDER) else {
        return 0.0;
    };
    let Ok(bank) = LaguerreBank::new(p, n) else {
        return 0.0;
    };
    let norm: f64 = h.iter().map(|v| v * v).sum();
    if norm == 0.0 {
        return 0.0;
    }
    // g_n = Σ_i h(i) l_n(i): run the bank on the time-reversed sequence? Simpler: direct sums.
    let l = bank.impulse_responses(h.len());
    l.iter()
        .map(|row| row.iter().zip(h).map(|(a, b)| a * b).sum::<f64>().powi(2))
        .sum::<f64>()
        / norm
}

const POLE_LIMIT: f64 = 0.98;

fn choose_poles(y: &[f64], u: Option<&[f64]>, cfg: &ArxLaguerreConfig) -> Result<(Pole, Pole)> {
    let (na, nb) = (cfg.n_a, cfg.n_b);
    match cfg.poles {
        PoleChoice::Fixed { zeta_a, zeta_b } => Ok((
            Pole::new(zeta_a)?,
            if nb > 0 {
                Pole::new(zeta_b)?
            } else {
                Pole::new(0.0)?
            },
        )),
        PoleChoice::ArxProjection { arx_order } => {
            let arx = ArxModel::identify(
                y,
                u,
                ArxOrders::new(arx_order, if nb > 0 { arx_order } else { 0 })?,
            )?;
            let pick = |h: &[f64], n: usize| {
                minimize_1d(
                    |z| -captured_energy(h, z, n),
                    -POLE_LIMIT,
                    POLE_LIMIT,
                    41,
                    40,
                )
                .0
            };
            let za = pick(&arx.a, na);
            let zb = if nb > 0 { pick(&arx.b, nb) } else { 0.0 };
            Ok((Pole::new(za)?, Pole::new(zb)?))
        }
        PoleChoice::PredictionError {
            grid,
            refine,
            max_samples,
        } => {
            let len = y.len().min(max_samples);
            let (mut za, mut zb) = (0.0, 0.0);
            // Coordinate descent: full grid + golden section on each pole in turn, until the
            // poles move by less than 1e-4 (at most four rounds).
            let rounds = if nb > 0 { 4 } else { 1 };
            for _ in 0..rounds {
                let (old_a, old_b) = (za, zb);
                za = minimize_1d(
                    |z| rss_for(y, u, z, zb, na, nb, len),
                    -POLE_LIMIT,
                    POLE_LIMIT,
                    grid,
                    refine,
                )
                .0;
                if nb > 0 {
                    zb = minimize_1d(
                        |z| rss_for(y, u, za, z, na, nb, len),
                        -POLE_LIMIT,
                        POLE_LIMIT,
                        grid,
                        refine,
                    )
                    .0;
                }
                if (za - old_a).abs() < 1e-4 && (zb - old_b).abs() < 1e-4 {
                    break;
                }
            }
            Ok((Pole::new(za)?, Pole::new(zb)?))
        }
    }
}
