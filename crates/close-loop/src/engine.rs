//! The augmented model and its scoring: the declared model's simulated spectrum shaped by the
//! effects found so far, a calibrated measurement channel (gain and white floor), phase-coherent
//! lines, and the two error metrics on a segment.

use crate::effect::{Line, Mode, Modulation};
use crate::metric::{log_spectral_distance, rms};
use crate::spectrum::Welch;
use crate::{CheckedConfig, CloseLoopError, DeclaredModel, OperatingPoint};
use std::ops::Range;
use std::sync::Arc;

/// The declared model simulated at one speed ratio, with its spectra.
#[derive(Debug)]
pub(crate) struct Base {
    pub ratio: f64,
    pub signal: Vec<f64>,
    pub psd: Vec<f64>,
    pub psd_hi: Vec<f64>,
}

/// A shared declared model (the one given, or one with physics effects put in).
#[derive(Clone)]
pub(crate) struct ModelRef(pub Arc<dyn DeclaredModel>);

impl std::fmt::Debug for ModelRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0.name())
    }
}

/// The model as augmented so far.
#[derive(Debug, Clone)]
pub(crate) struct State {
    /// The physics model with the physics effects put in (`None`: the declared model as given).
    pub model: Option<ModelRef>,
    pub base: Arc<Base>,
    /// Steady-state responses to shaft forces that are in the simulation (`base`) already: they
    /// enter the time-domain residual, not the PSD.
    pub physics_lines: Vec<Line>,
    pub modes: Vec<Mode>,
    pub mods: Vec<Modulation>,
    pub lines: Vec<Line>,
    /// ln of the channel gain.
    pub log_gain: f64,
    /// ln of the white floor (units²/Hz).
    pub log_floor: f64,
}

/// Everything fixed during one run of the loop.
pub(crate) struct Ctx<'a> {
    pub y: &'a [f64],
    pub fs: f64,
    pub n_fit: usize,
    pub welch: Welch,
    pub welch_hi: Welch,
    pub bins: Range<usize>,
    pub bins_hi: Range<usize>,
    pub s_fit: Vec<f64>,
    pub s_held: Vec<f64>,
    pub s_fit_hi: Vec<f64>,
    pub op: OperatingPoint,
    pub model: &'a dyn DeclaredModel,
    pub cfg: &'a CheckedConfig,
}

/// Scores of a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scores {
    pub lsd: f64,
    pub rms: f64,
}

impl State {
    /// Sensor lines and physics lines together: the model's phase-coherent prediction.
    pub fn all_lines(&self) -> Vec<Line> {
        self.lines
            .iter()
            .chain(&self.physics_lines)
            .copied()
            .collect()
    }
}

impl Ctx<'_> {
    pub fn held(&self) -> Range<usize> {
        self.n_fit..self.y.len()
    }

    /// The state's model (the declared one unless physics effects were put in).
    pub fn model_of<'s>(&'s self, st: &'s State) -> &'s dyn DeclaredModel {
        match &st.model {
            Some(m) => m.0.as_ref(),
            None => self.model,
        }
    }

    /// Simulate the declared model at `ratio` × declared speed.
    pub fn make_base(&self, ratio: f64) -> Result<Arc<Base>, CloseLoopError> {
        self.make_base_with(self.model, ratio)
    }

    /// Simulate `model` at `ratio` × declared speed over the fitting segment.
    pub fn make_base_with(
        &self,
        model: &dyn DeclaredModel,
        ratio: f64,
    ) -> Result<Arc<Base>, CloseLoopError> {
        let n = self.n_fit;
        let op = self.op.with_speed_ratio(ratio);
        let signal = model.simulate(&op, n, self.fs)?;
        if signal.len() != n {
            return Err(CloseLoopError::ModelLength {
                expected: n,
                found: signal.len(),
            });
        }
        if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
            return Err(CloseLoopError::NonFinite { index });
        }
        let psd = match model.expected_psd(&op, self.welch.nperseg(), self.fs) {
            Some(p) if p.len() == self.welch.n_bins() => p,
            _ => self.welch.try_psd(&signal)?,
        };
        let psd_hi = match model.expected_psd(&op, self.welch_hi.nperseg(), self.fs) {
            Some(p) if p.len() == self.welch_hi.n_bins() => p,
            _ => self.welch_hi.try_psd(&signal)?,
        };
        Ok(Arc::new(Base {
            ratio,
            signal,
            psd,
            psd_hi,
        }))
    }

    /// Modulations then modes applied to the base PSD (before gain and floor).
    pub fn shaped(&self, st: &State) -> Vec<f64> {
        let df = self.welch.df();
        let mut s = st.base.psd.clone();
        for m in &st.mods {
            s = m.apply_psd(&s, df);
        }
        if !st.modes.is_empty() {
            for (k, v) in s.iter_mut().enumerate() {
                let f = k as f64 * df;
                for m in &st.modes {
                    *v *= m.power_gain(f, self.fs);
                }
            }
        }
        s
    }

    /// The lines as a time signal over `range`.
    pub fn lines_signal(&self, lines: &[Line], range: Range<usize>) -> Vec<f64> {
        let mut out = vec![0.0; range.len()];
        for l in lines {
            l.add_to(&mut out, range.start, self.fs);
        }
        out
    }

    /// Welch PSD of the lines over `range` (zeros when there are none).
    pub fn lines_psd(&self, lines: &[Line], range: Range<usize>) -> Vec<f64> {
        if lines.is_empty() {
            return vec![0.0; self.welch.n_bins()];
        }
        self.welch.psd(&self.lines_signal(lines, range))
    }

    /// Model PSD = gain·shaped + floor + lines.
    pub fn model_psd(&self, st: &State, shaped: &[f64], lines_psd: &[f64]) -> Vec<f64> {
        let g = st.log_gain.exp();
        let fl = st.log_floor.exp();
        shaped
            .iter()
            .zip(lines_psd)
            .map(|(s, l)| g * s + fl + l)
            .collect()
    }

    /// Fit gain and floor on the fitting segment (warm-started from `st`, or from scratch when
    /// `cold`) and return the state with its fitting-segment LSD.
    pub fn calibrate(&self, mut st: State, cold: bool) -> (State, f64) {
        let shaped = self.shaped(&st);
        let lp = self.lines_psd(&st.lines, 0..self.n_fit);
        let warm = if cold {
            None
        } else {
            Some((st.log_gain, st.log_floor))
        };
        let (u, v, lsd) = calibrate_gain_floor(&self.s_fit, &shaped, &lp, self.bins.clone(), warm);
        st.log_gain = u;
        st.log_floor = v;
        (st, lsd)
    }

    /// Held-out scores of a calibrated state.
    pub fn held_scores(&self, st: &State) -> Scores {
        let shaped = self.shaped(st);
        let held = self.held();
        let lp = self.lines_psd(&st.lines, held.clone());
        let model = self.model_psd(st, &shaped, &lp);
        let lsd = log_spectral_distance(&self.s_held, &model, self.bins.clone());
        let yh = &self.y[held.clone()];
        let d = self.lines_signal(&st.all_lines(), held);
        let r: Vec<f64> = yh.iter().zip(&d).map(|(a, b)| a - b).collect();
        let ry = rms(yh);
        Scores {
            lsd,
            rms: if ry > 0.0 { rms(&r) / ry } else { 0.0 },
        }
    }

    /// Fitting-segment residual y − (all lines of `st`).
    pub fn fit_residual(&self, st: &State) -> Vec<f64> {
        let d = self.lines_signal(&st.all_lines(), 0..self.n_fit);
        self.y[..self.n_fit]
            .iter()
            .zip(&d)
            .map(|(a, b)| a - b)
            .collect()
    }
}

const TINY: f64 = 1e-300;

/// Least squares in the log domain: min over (u, v) of Σ_k (ln S_y − ln(e^u·A + e^v + D))²,
/// Levenberg–Marquardt; returns (u, v, LSD in dB).
pub(crate) fn calibrate_gain_floor(
    sy: &[f64],
    a: &[f64],
    d: &[f64],
    bins: Range<usize>,
    warm: Option<(f64, f64)>,
) -> (f64, f64, f64) {
    let ly: Vec<f64> = bins.clone().map(|i| sy[i].max(TINY).ln()).collect();
    let aa = &a[bins.clone()];
    let dd = &d[bins.clone()];
    let n = ly.len().max(1) as f64;
    let cost = |u: f64, v: f64| -> f64 {
        let (g, fl) = (u.exp(), v.exp());
        ly.iter()
            .zip(aa)
            .zip(dd)
            .map(|((l, a), d)| {
                let r = l - (g * a + fl + d).max(TINY).ln();
                r * r
            })
            .sum::<f64>()
    };
    let starts: Vec<(f64, f64)> = match warm {
        Some(w) => vec![w],
        None => {
            let my = ly.iter().map(|l| l.exp()).sum::<f64>() / n;
            let ma = aa.iter().sum::<f64>() / n;
            let mut sorted = ly.clone();
            sorted.sort_by(|x, y| x.total_cmp(y));
            let q10 = sorted.get(sorted.len() / 10).copied().unwrap_or(0.0);
            let u0 = if ma > 0.0 && my > 0.0 {
                (my / ma).ln()
            } else {
                0.0
            };
            vec![
                (u0, q10),
                (u0, q10 - 4.6),
                (u0 - 2.3, q10),
                (u0, my.max(TINY).ln()),
                (u0 - 4.6, q10 - 2.3),
            ]
        }
    };
    let mut best = (0.0, 0.0, f64::INFINITY);
    for (mut u, mut v) in starts {
        let mut c = cost(u, v);
        let mut lambda = 1e-3;
        for _ in 0..60 {
            let (g, fl) = (u.exp(), v.exp());
            let (mut j11, mut j12, mut j22, mut g1, mut g2) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for ((l, a), d) in ly.iter().zip(aa).zip(dd) {
                let m = (g * a + fl + d).max(TINY);
                let r = l - m.ln();
                let du = -g * a / m;
                let dv = -fl / m;
                j11 += du * du;
                j12 += du * dv;
                j22 += dv * dv;
                g1 += du * r;
                g2 += dv * r;
            }
            let mut improved = false;
            for _ in 0..8 {
                let (a11, a22) = (j11 * (1.0 + lambda) + 1e-12, j22 * (1.0 + lambda) + 1e-12);
                let det = a11 * a22 - j12 * j12;
                if det.abs() < 1e-300 {
                    break;
                }
                let su = (-(a22 * g1 - j12 * g2) / det).clamp(-5.0, 5.0);
                let sv = (-(a11 * g2 - j12 * g1) / det).clamp(-5.0, 5.0);
                let c2 = cost(u + su, v + sv);
                if c2 < c {
                    u += su;
                    v += sv;
                    let rel = (c - c2) / c.max(1e-300);
                    c = c2;
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = rel > 1e-10;
                    break;
                }
                lambda *= 4.0;
            }
            if !improved {
                break;
            }
        }
        if c < best.2 {
            best = (u, v, c);
        }
    }
    let lsd = 10.0 / std::f64::consts::LN_10 * (best.2 / n).sqrt();
    (best.0, best.1, lsd)
}
