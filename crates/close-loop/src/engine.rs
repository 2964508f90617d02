//! The augmented model and its scoring: the declared model's simulated spectrum shaped by the
//! effects found so far, a calibrated measurement channel (gain and white floor), phase-coherent
//! lines, and the two error metrics on a segment.

use crate::effect::{CoherentLine, Mode, Modulation};
use crate::metric::{regularised_lsd, rms};
use crate::path::{PathMode, StructuralPath};
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
    /// The declared model simulated at the speed ratio its fault impacts run at.
    pub base: Arc<Base>,
    /// The fault's impact rate over the rate the declared geometry gives at the shaft's speed
    /// (1 until a defect-rate effect is taken): the physics runs at `base.ratio`, the shaft at
    /// `base.ratio / defect_rate` ([`State::shaft_ratio`]).
    pub defect_rate: f64,
    /// Steady-state responses to shaft forces that are in the simulation (`base`) already: they
    /// enter the time-domain residual, not the PSD.
    pub physics_lines: Vec<CoherentLine>,
    /// Shaft harmonics found on this recording and taken into the model (physics or sensor):
    /// (order, refined frequency in Hz, amplitude). The shaft's speed as the recording shows it
    /// when its comb cannot be read ([`crate::runner`]'s speed candidates).
    pub shaft_lines: Vec<(f64, f64, f64)>,
    pub modes: Vec<Mode>,
    pub mods: Vec<Modulation>,
    pub lines: Vec<CoherentLine>,
    /// The structural path the broadband excitation rings (identified by the loop or given by
    /// a machine model); `None` until one is found.
    pub path: Option<Arc<PathPsd>>,
    /// The physics output is seen through the structural path instead of the model's own
    /// housing mode: its PSD is multiplied by this (metric grid), see [`Ctx::shaped`].
    pub phys_shape: Option<Arc<Vec<f64>>>,
    /// The path the declared physics is seen through, when identified on this recording or
    /// given by a machine model's `physics_path`.
    pub phys_path: Option<Arc<PathPsd>>,
    /// `phys_path` was identified on this recording (not inherited from a machine model).
    pub phys_path_fitted: bool,
    /// A high-pass (corner in Hz, Butterworth order) on the physics part: the fault's impacts
    /// reach the sensor weaker below the corner than the physics' path gives
    /// ([`crate::effect::Effect::ImpactsHighPass`]); applied in [`Ctx::shaped`].
    pub phys_highpass: Option<(f64, u32)>,
    /// ln of the channel gain.
    pub log_gain: f64,
    /// ln of the white floor (units²/Hz).
    pub log_floor: f64,
    /// ln of the path's excitation level (relative to the identified σ²).
    pub log_bg: f64,
    /// The part of the shaft's speed ratio that speed steps assumed without reading it on the
    /// recording's shaft lines (a step read from the fault's lines alone, `shaft_measured` = 0;
    /// 1 when every step was read there): the shaft may still run at
    /// `shaft_ratio() / assumed_shaft_step`, so a line at an order of that speed is a shaft line
    /// too ([`crate::runner`]'s line candidates).
    pub assumed_shaft_step: f64,
}

/// A structural path with its PSD on the metric grid.
#[derive(Debug)]
pub(crate) struct PathPsd {
    pub path: StructuralPath,
    pub psd: Vec<f64>,
    /// The path's power gain |1/A|² on the same grid ([`StructuralPath::power_gain`]), which
    /// every re-simulation behind the path is shaped with ([`Ctx::physics_shape`]).
    pub gain: Vec<f64>,
    pub modes: Vec<PathMode>,
}

impl PathPsd {
    pub fn new(path: StructuralPath, n_bins: usize, df: f64) -> Self {
        let psd = path.psd(n_bins, df);
        let gain = (0..n_bins)
            .map(|k| path.power_gain(k as f64 * df))
            .collect();
        let modes = path.modes();
        Self {
            path,
            psd,
            gain,
            modes,
        }
    }
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
    /// Floor of the regularised log-spectral distance (units²/Hz).
    pub eps: f64,
    /// Speed ratios judged and rejected (not simulated again).
    pub rejected_ratios: std::sync::Mutex<Vec<f64>>,
    /// Simulations of the run, by model key ([`DeclaredModel::cache_key`]) and speed ratio:
    /// the candidates of every round re-try the same models (a slip fraction, the declared
    /// physics at the current speed), and the 5-DOF simulation is most of a round's time.
    pub bases: std::sync::Mutex<std::collections::HashMap<(String, u64), Arc<Base>>>,
    /// The last few residuals y − lines ([`Ctx::held_residual`], [`Ctx::fit_residual`]) by the
    /// exact bits of their lines and segment: every candidate that adds no line is scored with
    /// its state's lines, and a rig's machine model carries some forty (their sum over a
    /// segment was 9 % of a measured record's loop).
    pub residuals: ResidualMemo,
    /// The shaft speed over the declared one that the fitting segment's own shaft-harmonic comb
    /// shows (`residual_features::speed`; `None`: no comb clear enough to read).
    pub shaft: Option<f64>,
    /// The fault locations the training-free diagnosis (`diagnosis::diagnose`, self-referenced)
    /// detects on the fitting segment and, read on its own, on the held-out segment too, with
    /// their fitting-segment scores (dB); empty for a model without spalls or when the diagnosis
    /// cannot run. A location the model leaves healthy is offered as a fault nobody declared
    /// (`runner::fault`).
    pub detected: Vec<(bearing_model::FaultLocation, f64)>,
    pub op: OperatingPoint,
    pub model: &'a dyn DeclaredModel,
    pub cfg: &'a CheckedConfig,
}

/// A bounded memo of line residuals: the [`RESIDUAL_MEMO_LEN`] most recently computed, keyed
/// by the segment and the bits of every line (frequency, a, b) in order; a hit returns the very
/// vector that was computed, so results are bit-identical with and without it.
#[derive(Default)]
pub(crate) struct ResidualMemo {
    slots: std::sync::Mutex<std::collections::VecDeque<(ResidualKey, Arc<Vec<f64>>)>>,
}

/// Segment start and end, then each line's frequency, cosine and sine coefficient bits.
type ResidualKey = Vec<u64>;

/// Residuals kept by [`ResidualMemo`] (each a segment long: ~0.5 MB at 12 kHz).
const RESIDUAL_MEMO_LEN: usize = 8;

impl ResidualMemo {
    fn get_or_compute(
        &self,
        lines: &[CoherentLine],
        range: &Range<usize>,
        compute: impl FnOnce() -> Vec<f64>,
    ) -> Arc<Vec<f64>> {
        let mut key: ResidualKey = Vec::with_capacity(2 + 3 * lines.len());
        key.extend([range.start as u64, range.end as u64]);
        for l in lines {
            key.extend([l.frequency_hz.to_bits(), l.a.to_bits(), l.b.to_bits()]);
        }
        let lock = || {
            self.slots
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
        };
        if let Some((_, r)) = lock().iter().find(|(k, _)| *k == key) {
            return r.clone();
        }
        let r = Arc::new(compute());
        let mut slots = lock();
        if slots.len() == RESIDUAL_MEMO_LEN {
            slots.pop_front();
        }
        slots.push_back((key, r.clone()));
        r
    }
}

/// A state's scores on the held-out samples: the regularised LSD of its model PSD against the
/// measured one, and the RMS of its residual relative to the measurement's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HeldOutScores {
    pub lsd: f64,
    pub rms: f64,
}

impl State {
    /// The shaft's speed over the declared one: where the shaft-synchronous lines and rates sit.
    pub fn shaft_ratio(&self) -> f64 {
        self.base.ratio / self.defect_rate
    }

    /// Sensor lines and physics lines together: the model's phase-coherent prediction.
    pub fn all_lines(&self) -> Vec<CoherentLine> {
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
        let key = model.cache_key().map(|k| (k, ratio.to_bits()));
        if let Some(k) = &key {
            if let Some(b) = self.bases.lock().ok().and_then(|m| m.get(k).cloned()) {
                return Ok(b);
            }
        }
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
        let base = Arc::new(Base {
            ratio,
            signal,
            psd,
            psd_hi,
        });
        if let (Some(k), Ok(mut m)) = (key, self.bases.lock()) {
            m.insert(k, base.clone());
        }
        Ok(base)
    }

    /// The multiplier that puts the declared physics behind a structural path: its PSD is divided
    /// by its own smooth level (lines replaced by the local median, ±60 Hz) and multiplied by the
    /// path's power gain |1/A|², so the physics contributes its line structure (kinematic lines,
    /// sidebands) and the path its resonances. The level is free (the physics gain is
    /// calibrated).
    pub fn physics_shape(&self, base_psd: &[f64], path: &PathPsd) -> Vec<f64> {
        let df = self.welch.df();
        let half = ((60.0 / df).round() as usize).max(3);
        let smooth = crate::path::line_free(base_psd, half, 3.0);
        smooth
            .iter()
            .zip(&path.gain)
            .map(|(sm, g)| g / sm.max(1e-300))
            .collect()
    }

    /// Replace the state's simulation (another speed, slip, force or housing), re-deriving the
    /// physics shaping from it when the physics is behind a path.
    pub fn rebase(&self, st: &mut State, base: Arc<Base>) {
        if let Some(p) = &st.phys_path {
            st.phys_shape = Some(Arc::new(self.physics_shape(&base.psd, p)));
        }
        st.base = base;
    }

    /// The structural path's background PSD (before its level) with the state's modulations and
    /// channel modes: an amplitude modulation acts on the structural vibration, the physics and
    /// the background alike, not on the white floor nor on the sensor lines
    /// (`docs/equations/close-loop.md`, "Modulation"); a mode of the measurement channel shapes
    /// all vibration the sensor sees, the background as the physics ("Resonance").
    pub fn background_psd(&self, st: &State) -> Option<Vec<f64>> {
        let p = st.path.as_ref()?;
        let df = self.welch.df();
        let mut s = p.psd.clone();
        for m in &st.mods {
            s = m.apply_psd(&s, df);
        }
        Mode::shape_psd(&st.modes, &mut s, df, self.fs);
        Some(s)
    }

    /// Path shaping, modulations, then modes applied to the base PSD (before gain and floor).
    pub fn shaped(&self, st: &State) -> Vec<f64> {
        let df = self.welch.df();
        let mut s = st.base.psd.clone();
        if let Some(t) = &st.phys_shape {
            for (v, g) in s.iter_mut().zip(t.iter()) {
                *v *= g;
            }
        }
        if let Some((corner, order)) = st.phys_highpass {
            for (k, v) in s.iter_mut().enumerate() {
                *v *= highpass_power(k as f64 * df, corner, order);
            }
        }
        for m in &st.mods {
            s = m.apply_psd(&s, df);
        }
        Mode::shape_psd(&st.modes, &mut s, df, self.fs);
        s
    }

    /// The lines as a time signal over `range`.
    pub fn lines_signal(&self, lines: &[CoherentLine], range: Range<usize>) -> Vec<f64> {
        let mut out = vec![0.0; range.len()];
        for l in lines {
            l.add_to(&mut out, range.start, self.fs);
        }
        out
    }

    /// Welch PSD of the lines (zeros when there are none), in closed form: a line A·cos(2πf₀t+φ)
    /// seen through the Welch estimator's periodic Hann window w has the one-sided density
    /// A²/2 · (|W(f − f₀)|² + |W(f + f₀)|²) / (fs·Σw²), W the window's DTFT (lines at different
    /// frequencies add in power: their relative phase turns from segment to segment). Evaluated
    /// within ±[`LINE_KERNEL_BINS`] bins of each line, where the Hann kernel holds all but
    /// −60 dB of the line's power. The same for every segment of the recording, so `_range` is
    /// only kept for the call sites' clarity.
    pub fn lines_psd(&self, lines: &[CoherentLine], _range: Range<usize>) -> Vec<f64> {
        let nb = self.welch.n_bins();
        let mut out = vec![0.0; nb];
        if lines.is_empty() {
            return out;
        }
        let n = self.welch.nperseg();
        let df = self.welch.df();
        let u = 3.0 * n as f64 / 8.0; // Σ w² of a periodic Hann window of n samples
        for l in lines {
            let a2 = l.amplitude().powi(2);
            let k0 = (l.frequency_hz / df).round() as i64;
            for k in (k0 - LINE_KERNEL_BINS)..=(k0 + LINE_KERNEL_BINS) {
                if k < 0 || k as usize >= nb {
                    continue;
                }
                let f = k as f64 * df;
                let w = hann_kernel_power((f - l.frequency_hz) / df, n)
                    + hann_kernel_power((f + l.frequency_hz) / df, n);
                out[k as usize] += a2 / 2.0 * w / (self.fs * u);
            }
        }
        out
    }

    /// Model PSD = gain·shaped + level·path + floor + lines.
    pub fn model_psd(&self, st: &State, shaped: &[f64], lines_psd: &[f64]) -> Vec<f64> {
        let g = st.log_gain.exp();
        let fl = st.log_floor.exp();
        let b = st.log_bg.exp();
        let bg = self.background_psd(st);
        let path = bg.as_deref();
        shaped
            .iter()
            .zip(lines_psd)
            .enumerate()
            .map(|(k, (s, l))| g * s + fl + l + path.map_or(0.0, |p| b * p[k]))
            .collect()
    }

    /// [`Ctx::calibrate`] warm and cold, the lower fitting error kept: where the declared
    /// physics is far from the data the calibration has driven its gain down, and a warm start
    /// stays there whatever the candidate changes (a grid over a housing frequency or a spall
    /// width was then flat).
    pub fn calibrate_warm_and_cold(&self, st: State) -> (State, f64) {
        let (warm, lw) = self.calibrate(st.clone(), false);
        let (cold, lc) = self.calibrate(st, true);
        if lc < lw { (cold, lc) } else { (warm, lw) }
    }

    /// Fit gain and floor on the fitting segment (warm-started from `st`, or from scratch when
    /// `cold`) and return the state with its fitting-segment LSD.
    pub fn calibrate(&self, mut st: State, cold: bool) -> (State, f64) {
        let shaped = self.shaped(&st);
        let lp = self.lines_psd(&st.lines, 0..self.n_fit);
        let ones = vec![1.0; shaped.len()];
        let mut comps: Vec<&[f64]> = vec![&shaped, &ones];
        let mut warm = vec![st.log_gain, st.log_floor];
        let bg = self.background_psd(&st);
        if let Some(p) = &bg {
            comps.push(p);
            warm.push(st.log_bg);
        }
        let (u, lsd) = fit_weights(
            &self.s_fit,
            &comps,
            &lp,
            self.bins.clone(),
            self.eps,
            (!cold).then_some(warm.as_slice()),
        );
        st.log_gain = u[0];
        st.log_floor = u[1];
        if u.len() > 2 {
            st.log_bg = u[2];
        }
        (st, lsd)
    }

    /// Held-out scores of a calibrated state.
    pub fn held_scores(&self, st: &State) -> HeldOutScores {
        let shaped = self.shaped(st);
        let held = self.held();
        let lp = self.lines_psd(&st.lines, held.clone());
        let model = self.model_psd(st, &shaped, &lp);
        let lsd = regularised_lsd(&self.s_held, &model, self.bins.clone(), self.eps);
        let r = self.held_residual(st);
        let ry = rms(&self.y[held]);
        HeldOutScores {
            lsd,
            rms: if ry > 0.0 { rms(&r) / ry } else { 0.0 },
        }
    }

    /// Held-out residual y − (all lines of `st`).
    pub fn held_residual(&self, st: &State) -> Arc<Vec<f64>> {
        self.residual(&st.all_lines(), self.held())
    }

    /// Fitting-segment residual y − (all lines of `st`).
    pub fn fit_residual(&self, st: &State) -> Arc<Vec<f64>> {
        self.residual(&st.all_lines(), 0..self.n_fit)
    }

    /// y − `lines` over `range`, through the memo.
    fn residual(&self, lines: &[CoherentLine], range: Range<usize>) -> Arc<Vec<f64>> {
        self.residuals.get_or_compute(lines, &range, || {
            let d = self.lines_signal(lines, range.clone());
            self.y[range.clone()]
                .iter()
                .zip(&d)
                .map(|(a, b)| a - b)
                .collect()
        })
    }
}

const TINY: f64 = 1e-300;

/// Half-width, in bins, of a line's footprint in the Welch PSD ([`Ctx::lines_psd`]).
pub(crate) const LINE_KERNEL_BINS: i64 = 12;

/// |W(ν)|² of a periodic Hann window of `n` samples at ν bins from the centre:
/// W(ν) = ½D(ν) − ¼D(ν − 1) − ¼D(ν + 1), D(x) = Σ_m e^{−j2πxm/n} = e^{−jπx(n−1)/n}·sin(πx)/sin(πx/n).
/// With θ = π(n−1)/n and s = sin(πν): |W|² = s²·|½/sin(πν/n) + ¼e^{jθ}/sin(π(ν−1)/n)
/// + ¼e^{−jθ}/sin(π(ν+1)/n)|² (integer ν is taken as the limit, by a 1e-7-bin offset).
pub(crate) fn hann_kernel_power(nu: f64, n: usize) -> f64 {
    use std::f64::consts::PI;
    let nf = n as f64;
    let nu = if (nu - nu.round()).abs() < 1e-7 {
        nu + 1e-7
    } else {
        nu
    };
    let th = PI * (nf - 1.0) / nf;
    let (a0, am, ap) = (
        (PI * nu / nf).sin(),
        (PI * (nu - 1.0) / nf).sin(),
        (PI * (nu + 1.0) / nf).sin(),
    );
    let re = 0.5 / a0 + 0.25 * th.cos() * (1.0 / am + 1.0 / ap);
    let im = 0.25 * th.sin() * (1.0 / am - 1.0 / ap);
    let s = (PI * nu).sin();
    s * s * (re * re + im * im)
}

/// Least squares in the floor-regularised log domain: min over log-weights u of
/// Σ_k (ln(S_y,k + ε) − ln(Σ_j e^{u_j}·C_j,k + D_k + ε))², Levenberg–Marquardt from a few
/// starts; returns (u, regularised LSD in dB). `comps` are the components (physics, path,
/// the white floor as a vector of ones), `d` the fixed part (lines).
pub(crate) fn fit_weights(
    sy: &[f64],
    comps: &[&[f64]],
    d: &[f64],
    bins: Range<usize>,
    eps: f64,
    warm: Option<&[f64]>,
) -> (Vec<f64>, f64) {
    let nc = comps.len();
    let ly: Vec<f64> = bins.clone().map(|i| (sy[i] + eps).max(TINY).ln()).collect();
    let cs: Vec<&[f64]> = comps.iter().map(|c| &c[bins.clone()]).collect();
    let dd = &d[bins.clone()];
    let n = ly.len().max(1) as f64;
    // the weights e^{u_j} are taken once per evaluation, not once per bin
    let weights = |u: &[f64]| -> Vec<f64> { u.iter().map(|v| v.exp()).collect() };
    let model = |w: &[f64], k: usize| -> f64 {
        let mut m = dd[k] + eps;
        for (j, c) in cs.iter().enumerate() {
            m += w[j] * c[k];
        }
        m.max(TINY)
    };
    let cost = |u: &[f64]| -> f64 {
        let w = weights(u);
        (0..ly.len())
            .map(|k| {
                let r = ly[k] - model(&w, k).ln();
                r * r
            })
            .sum::<f64>()
    };
    let starts: Vec<Vec<f64>> = match warm {
        Some(w) if w.len() == nc => vec![w.to_vec()],
        _ => {
            let my = ly.iter().map(|l| l.exp()).sum::<f64>() / n;
            let mut sorted = ly.clone();
            sorted.sort_by(|x, y| x.total_cmp(y));
            let q10 = sorted.get(sorted.len() / 10).copied().unwrap_or(0.0).exp();
            let level = |c: &[f64], target: f64| -> f64 {
                let mc = c.iter().sum::<f64>() / n;
                if mc > 0.0 && target > 0.0 {
                    (target / mc).ln()
                } else {
                    -50.0
                }
            };
            let base: Vec<f64> = cs.iter().map(|c| level(c, my)).collect();
            let mut v = vec![base.clone()];
            for j in 0..nc {
                let mut s = base.clone();
                s[j] = level(cs[j], q10);
                v.push(s);
                let mut s = base.clone();
                s[j] -= 4.6;
                v.push(s);
            }
            v
        }
    };
    let mut best = (vec![0.0; nc], f64::INFINITY);
    for mut u in starts {
        let mut c = cost(&u);
        let mut lambda = 1e-3;
        for _ in 0..80 {
            let mut jtj = nalgebra::DMatrix::<f64>::zeros(nc, nc);
            let mut g = nalgebra::DVector::<f64>::zeros(nc);
            let w = weights(&u);
            let mut jac = vec![0.0; nc];
            for k in 0..ly.len() {
                let m = model(&w, k);
                let r = ly[k] - m.ln();
                for (j, jj) in jac.iter_mut().enumerate() {
                    *jj = -w[j] * cs[j][k] / m;
                }
                for a in 0..nc {
                    g[a] += jac[a] * r;
                    for b in 0..nc {
                        jtj[(a, b)] += jac[a] * jac[b];
                    }
                }
            }
            let mut improved = false;
            for _ in 0..8 {
                let mut a = jtj.clone();
                for j in 0..nc {
                    a[(j, j)] = a[(j, j)] * (1.0 + lambda) + 1e-12;
                }
                let Some(step) = a.lu().solve(&(-&g)) else {
                    break;
                };
                let u2: Vec<f64> = (0..nc).map(|j| u[j] + step[j].clamp(-5.0, 5.0)).collect();
                let c2 = cost(&u2);
                if c2 < c {
                    let rel = (c - c2) / c.max(1e-300);
                    u = u2;
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
        if c < best.1 {
            best = (u, c);
        }
    }
    let lsd = 10.0 / std::f64::consts::LN_10 * (best.1 / n).sqrt();
    (best.0, lsd)
}

/// Power gain |H(f)|² = 1 / (1 + (f_c/f)^(2n)) of an n-th order Butterworth high-pass with corner
/// `corner_hz` (0 at DC).
pub fn highpass_power(f_hz: f64, corner_hz: f64, order: u32) -> f64 {
    if f_hz <= 0.0 {
        return 0.0;
    }
    1.0 / (1.0 + (corner_hz / f_hz).powi(2 * order as i32))
}

#[cfg(test)]
mod tests {
    use super::hann_kernel_power;

    /// The closed-form Hann kernel equals the window's DTFT computed by brute force.
    #[test]
    fn hann_kernel_matches_the_dtft() {
        let n = 64;
        let w: Vec<f64> = (0..n)
            .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
            .collect();
        for &nu in &[0.0, 0.3, 1.0, 1.7, 2.5, 6.2] {
            let (mut re, mut im) = (0.0, 0.0);
            for (m, v) in w.iter().enumerate() {
                let ph = -2.0 * std::f64::consts::PI * nu * m as f64 / n as f64;
                re += v * ph.cos();
                im += v * ph.sin();
            }
            let brute = re * re + im * im;
            let closed = hann_kernel_power(nu, n);
            assert!(
                (brute - closed).abs() <= 1e-6 * brute.max(1e-3),
                "nu {nu}: {brute} vs {closed}"
            );
        }
    }
}
