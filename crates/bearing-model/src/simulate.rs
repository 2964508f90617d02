//! Simulation: integrate the model (adaptive Dormand–Prince 5(4) by default, fixed-step RK4 as
//! the reference), evaluate the housing acceleration on an internal grid that is an integer
//! multiple of the output rate, a linear-phase anti-alias FIR (the acquisition chain),
//! decimation, and seeded measurement noise.
//!
//! # Integrator
//!
//! The ball contacts switch on and off, but the Hertz force `k_b δ^1.5` is C¹ in the state
//! (its slope vanishes at δ = 0) and the spall profiles are continuous in time, so explicit
//! Runge–Kutta schemes converge without event handling. The internal grid is
//! `h = 1/(m·fs)` with the smallest integer `m` giving `h ≤` [`SimConfig::max_step_s`]
//! (default [`SimConfig::DEFAULT_MAX_STEP`] = 5 µs).
//!
//! * [`Integrator::Adaptive`] (the default, [`Integrator::DEFAULT`]: `rtol` 2e-6, `atol`
//!   1e-9 m/s²): Dormand–Prince 5(4) with FSAL, an embedded error estimate and step-size
//!   control, and its 4th-order continuous extension evaluated at every grid time. Between
//!   spall impacts the response is smooth and the step grows to 25–60 µs; around a ball
//!   re-entering contact it shrinks to a few µs. The error estimate is weighted per DOF by
//!   the tangent stiffness at the start (a position error of DOF i counts `max_j |∂q̈_j/∂q_i|`
//!   times, a velocity error the square root of that), so it is in acceleration units, and
//!   must stay below `atol + rtol · (largest |output| so far)`. It stays within 1e-3 relative
//!   RMS of the reference (measured ≤ 2.6e-4 over healthy/outer/inner/ball/inner+outer+ball,
//!   12 and 48 kHz, 300 and 1797 rpm: test `reference`), with 5–23× fewer steps.
//! * [`Integrator::Rk4Fixed`] ([`SimConfig::reference`]): classical RK4 stepping on the grid
//!   itself, the former default. Halving its step changes the output by far less than 0.1 %
//!   relative RMS (test `halving_the_reference_step_changes_the_output_by_less_than_0_1_percent`).
//!
//! Both are deterministic: the same inputs give bit-identical output.

use crate::error::{ModelError, Result, check_range};
use crate::state_space::{BearingModel, Input, N_DOF, State};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::PI;

/// Measurement noise added to the output after the anti-alias filter.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Noise {
    /// No noise.
    Off,
    /// White Gaussian noise of this standard deviation, m/s².
    Std(f64),
    /// White Gaussian noise at this signal-to-noise ratio (dB) relative to the clean RMS.
    SnrDb(f64),
}

/// How the equations of motion are integrated (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Integrator {
    /// Classical RK4 stepping exactly on the internal grid `h = 1/(m·fs) ≤`
    /// [`SimConfig::max_step_s`]: the reference (5 µs by default).
    Rk4Fixed,
    /// Dormand–Prince 5(4) with error control and its 4th-order dense output evaluated on the
    /// internal grid. The local error estimate, in acceleration units (positions × ω², velocities
    /// × ω, ω the model's highest natural frequency), must stay below
    /// `atol + rtol · (largest |output − y₀| so far)`.
    Adaptive {
        /// Relative tolerance (to the largest output magnitude seen so far).
        rtol: f64,
        /// Absolute tolerance, m/s².
        atol: f64,
    },
}

impl Integrator {
    /// The default: [`Integrator::Adaptive`] with tolerances that keep the output within
    /// 1e-3 relative RMS of the 5 µs RK4 reference (test `reference`).
    pub const DEFAULT: Integrator = Integrator::Adaptive {
        rtol: 2e-6,
        atol: Self::DEFAULT_ATOL,
    };
    /// The default's absolute tolerance, m/s².
    pub const DEFAULT_ATOL: f64 = 1e-9;

    /// [`Integrator::Adaptive`] with relative tolerance `rtol` and the default's `atol`.
    pub const fn adaptive(rtol: f64) -> Integrator {
        Integrator::Adaptive {
            rtol,
            atol: Self::DEFAULT_ATOL,
        }
    }
}

impl Default for Integrator {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// How a simulation is run and sampled.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimConfig {
    /// Output sampling rate, Hz.
    pub fs_hz: f64,
    /// Recorded duration, s.
    pub duration_s: f64,
    /// Largest step of the internal grid, s: the sprung-mass acceleration is evaluated at
    /// `h = 1/(m·fs)`, `m` the smallest integer with `h ≤ max_step_s`, anti-alias filtered and
    /// decimated by `m`. [`Integrator::Rk4Fixed`] steps on this grid; the adaptive integrator
    /// evaluates its dense output on it.
    pub max_step_s: f64,
    /// How the equations are integrated.
    #[serde(default)]
    pub integrator: Integrator,
    /// Time simulated before `t = 0` and discarded (start-up transient), s.
    pub settle_s: f64,
    /// Measurement noise.
    pub noise: Noise,
    /// Also record all ten states at each output sample.
    pub record_states: bool,
    /// Seed of the noise draws (slip and uncertainty draws use the model's seed).
    pub seed: u64,
}

impl SimConfig {
    /// Default bound on the internal grid step (the reference RK4 step): 5 µs.
    pub const DEFAULT_MAX_STEP: f64 = 5e-6;

    /// `duration_s` at `fs_hz`, default step, 50 ms settling, no noise, no states.
    pub fn new(fs_hz: f64, duration_s: f64) -> Self {
        Self {
            fs_hz,
            duration_s,
            max_step_s: Self::DEFAULT_MAX_STEP,
            integrator: Integrator::DEFAULT,
            settle_s: 0.05,
            noise: Noise::Off,
            record_states: false,
            seed: 0,
        }
    }

    /// [`SimConfig::new`] with the reference integrator: fixed-step RK4 at ≤ 5 µs.
    pub fn reference(fs_hz: f64, duration_s: f64) -> Self {
        Self {
            integrator: Integrator::Rk4Fixed,
            ..Self::new(fs_hz, duration_s)
        }
    }

    /// Oversampling factor `m` (internal steps per output sample).
    pub fn oversampling(&self) -> usize {
        (1.0 / (self.fs_hz * self.max_step_s)).ceil().max(1.0) as usize
    }

    fn validate(&self, model: &BearingModel) -> Result<()> {
        check_range("fs_hz", self.fs_hz, 1.0, 1e7, "1 ..= 1e7 Hz")?;
        check_range("duration_s", self.duration_s, 0.0, 3600.0, "0 ..= 3600 s")?;
        check_range("max_step_s", self.max_step_s, 1e-9, 1e-3, "1e-9 ..= 1e-3 s")?;
        check_range("settle_s", self.settle_s, 0.0, 60.0, "0 ..= 60 s")?;
        if let Integrator::Adaptive { rtol, atol } = self.integrator {
            check_range("rtol", rtol, 1e-14, 1.0, "1e-14 ..= 1")?;
            check_range("atol", atol, 0.0, 1e9, "0 ..= 1e9 m/s²")?;
        }
        match self.noise {
            Noise::Off => {}
            Noise::Std(s) => check_range("noise std", s, 0.0, 1e9, "0 ..= 1e9 m/s²")?,
            Noise::SnrDb(s) => check_range("noise snr_db", s, -60.0, 200.0, "-60 ..= 200 dB")?,
        }
        model.spec().faults.check_onsets(self.duration_s)?;
        let n = (self.duration_s * self.fs_hz).round();
        let max = 5e8 / self.oversampling() as f64;
        if n < 1.0 || n > max {
            return Err(ModelError::BadLength { samples: n, max });
        }
        // A resonant housing must lie in the output band. A heavily damped one (ζ ≥ 0.5) above
        // the band is a stiff mount that only low-passes the pedestal motion (the excitation
        // model of `calibrated_rig`), so it may sit anywhere.
        let housing = model.spec().housing;
        let f_res = housing.resonance_hz;
        let required = 2.2 * f_res;
        if self.fs_hz < required && housing.damping_ratio < 0.5 {
            return Err(ModelError::SamplingTooLow {
                fs_hz: self.fs_hz,
                resonance_hz: f_res,
                required_hz: required,
            });
        }
        Ok(())
    }
}

/// A simulated recording: the 5-DOF model's housing acceleration (and, when asked for, its
/// states). A measured recording is `bearing_data::Recording`.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedRecording {
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Housing acceleration the accelerometer sees (sprung-mass acceleration, anti-alias
    /// filtered, noise added), m/s². Sample `k` is at `t = k / fs`.
    pub accel: Vec<f64>,
    /// All ten states at each output sample (point samples, unfiltered), when requested.
    pub states: Option<Vec<State>>,
    /// Step of the internal grid the output is evaluated on before the anti-alias filter, s
    /// (the RK4 step for [`Integrator::Rk4Fixed`]).
    pub step_s: f64,
    /// Number of accepted integrator steps.
    pub steps: usize,
    /// Standard deviation of the noise that was added, m/s².
    pub noise_std: f64,
}

/// The former name of [`SimulatedRecording`], kept so that code written against it still
/// compiles.
#[deprecated(
    note = "renamed to `SimulatedRecording`: the 5-DOF model's output (a measured recording is \
            `bearing_data::Recording`)"
)]
pub type Recording = SimulatedRecording;

impl SimulatedRecording {
    /// Time of sample `k`, s.
    pub fn time(&self, k: usize) -> f64 {
        k as f64 / self.fs_hz
    }
}

/// Half-length of the anti-alias FIR in output samples.
const FIR_HALF_OUT: usize = 16;
/// Anti-alias cutoff as a fraction of the output rate.
const FIR_CUTOFF: f64 = 0.44;

fn design_fir(m: usize) -> Vec<f64> {
    let half = FIR_HALF_OUT * m;
    let fc = FIR_CUTOFF / m as f64; // cycles per internal sample
    let mut h: Vec<f64> = (0..=2 * half)
        .map(|i| {
            let k = i as f64 - half as f64;
            let sinc = if k == 0.0 {
                2.0 * fc
            } else {
                (2.0 * PI * fc * k).sin() / (PI * k)
            };
            let w = 0.5 * (1.0 + (PI * k / (half as f64 + 1.0)).cos());
            sinc * w
        })
        .collect();
    let s: f64 = h.iter().sum();
    h.iter_mut().for_each(|v| *v /= s);
    h
}

/// `Σ a_i b_i` with four independent accumulators (lets the compiler keep four products in
/// flight; the sum order is fixed, so the result is deterministic).
#[inline]
fn fir_dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Simulate `model` per `cfg`: start from the static equilibrium at `−settle`, integrate
/// (adaptive Dormand–Prince 5(4) by default, fixed-step RK4 as the reference), evaluate the
/// sprung-mass acceleration on the internal grid, filter, decimate, add noise.
pub fn simulate(model: &BearingModel, cfg: &SimConfig) -> Result<SimulatedRecording> {
    cfg.validate(model)?;
    let m = cfg.oversampling();
    let h = 1.0 / (cfg.fs_hz * m as f64);
    let n_out = (cfg.duration_s * cfg.fs_hz).round() as usize;
    let n_settle = ((cfg.settle_s * cfg.fs_hz).ceil() as usize).max(FIR_HALF_OUT + 1);
    let fir = design_fir(m);
    let half = FIR_HALF_OUT * m;
    // internal samples: from output index −n_settle to n_out − 1 + FIR_HALF_OUT
    let n_int = (n_settle + n_out + FIR_HALF_OUT) * m + 1;
    let t0 = -(n_settle as f64) / cfg.fs_hz;
    let x0 = model.static_equilibrium(t0)?;
    let mut raw = Vec::with_capacity(n_int);
    let mut states = if cfg.record_states {
        Some(Vec::with_capacity(n_out))
    } else {
        None
    };
    let grid = Grid {
        t0,
        h,
        n: n_int,
        m,
        first_state: n_settle,
        end_state: n_settle + n_out,
    };
    let steps = match cfg.integrator {
        Integrator::Rk4Fixed => integrate_rk4(model, x0, &grid, &mut raw, &mut states)?,
        Integrator::Adaptive { rtol, atol } => {
            integrate_dp54(model, x0, &grid, rtol, atol, &mut raw, &mut states)?
        }
    };
    debug_assert_eq!(raw.len(), n_int);
    let mut accel: Vec<f64> = (0..n_out)
        .map(|k| {
            let c = (n_settle + k) * m;
            fir_dot(&raw[c - half..=c + half], &fir)
        })
        .collect();
    let noise_std = match cfg.noise {
        Noise::Off => 0.0,
        Noise::Std(s) => s,
        Noise::SnrDb(db) => {
            let mean = accel.iter().sum::<f64>() / n_out as f64;
            let rms = (accel.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / n_out as f64).sqrt();
            rms / 10f64.powf(db / 20.0)
        }
    };
    if noise_std > 0.0 {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(cfg.seed);
        rng.set_stream(3);
        for a in accel.iter_mut() {
            let z: f64 = StandardNormal.sample(&mut rng);
            *a += noise_std * z;
        }
    }
    debug_assert!(states.as_ref().is_none_or(|s| s.len() == n_out));
    Ok(SimulatedRecording {
        fs_hz: cfg.fs_hz,
        accel,
        states,
        step_s: h,
        steps,
        noise_std,
    })
}

/// The internal output grid `t_i = t0 + i h`, `i < n`; states are recorded at `i = k m` for
/// `first_state ≤ k < end_state`.
struct Grid {
    t0: f64,
    h: f64,
    n: usize,
    m: usize,
    first_state: usize,
    end_state: usize,
}

impl Grid {
    #[inline]
    fn time(&self, i: usize) -> f64 {
        self.t0 + i as f64 * self.h
    }
    #[inline]
    fn records_state(&self, i: usize) -> bool {
        i % self.m == 0 && i / self.m >= self.first_state && i / self.m < self.end_state
    }
}

fn check_finite(x: &State, t: f64) -> Result<()> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ModelError::Diverged { time_s: t })
    }
}

/// The reference: classical RK4 on the grid itself. Returns the number of steps.
fn integrate_rk4(
    model: &BearingModel,
    mut x: State,
    g: &Grid,
    raw: &mut Vec<f64>,
    states: &mut Option<Vec<State>>,
) -> Result<usize> {
    let u = Input::zeros();
    let mut frame = model.frame(g.t0);
    for i in 0..g.n {
        let t = g.time(i);
        raw.push(model.output(t, &x));
        if let Some(st) = states.as_mut() {
            if g.records_state(i) {
                st.push(x);
            }
        }
        frame = model.step_with_frame(&frame, t, &mut x, g.h, &u);
        if i % 1024 == 0 {
            check_finite(&x, t)?;
        }
    }
    check_finite(&x, g.time(g.n))?;
    Ok(g.n)
}

// Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, DOPRI5).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// β of the PI step-size controller (DOPRI5's default 0.04). Where the step is limited by
/// stability rather than accuracy (a stiff out-of-band mode, e.g. close-loop's excitation
/// model with its heavily damped sprung mass above the output band) the plain controller oscillates around the
/// stability limit and rejects about one step in nine; with β = 0.04 one in thirty (measured
/// in close-loop's `examples/excitation_tolerance.rs`).
const PI_BETA: f64 = 0.04;

/// Adaptive Dormand–Prince 5(4) with a PI step controller and the 4th-order continuous
/// extension evaluated at every grid time. Returns the number of accepted steps.
#[allow(clippy::too_many_arguments)]
fn integrate_dp54(
    model: &BearingModel,
    mut x: State,
    g: &Grid,
    rtol: f64,
    atol: f64,
    raw: &mut Vec<f64>,
    states: &mut Option<Vec<State>>,
) -> Result<usize> {
    let u = Input::zeros();
    let hrow = model.output_row();
    let y0 = model.output_offset();
    // H has four non-zero entries (pedestal and sprung-mass y, positions and velocities).
    let hk: [(usize, f64); 4] = {
        use crate::state_space::idx::{VEL, YP, YR};
        [YP, YR, YP + VEL, YR + VEL].map(|i| (i, hrow[i]))
    };
    debug_assert!((hrow.abs().sum() - hk.iter().map(|v| v.1.abs()).sum::<f64>()).abs() == 0.0);
    let dot = |v: &State| hk.iter().map(|&(i, c)| c * v[i]).sum::<f64>();
    // Error weights, per DOF from the tangent stiffness at the start (contacts included): a
    // position error e of DOF i moves the accelerations by up to w_i e, w_i = max_j |∂q̈_j/∂q_i|;
    // a velocity error by √w_i e (the DOF's own frequency).
    let jac = model.jacobian(g.t0, &x, &u);
    let mut w = State::zeros();
    for i in 0..N_DOF {
        let wq = (0..N_DOF)
            .map(|j| jac[(N_DOF + j, i)].abs())
            .fold(1.0, f64::max);
        w[i] = wq;
        w[i + N_DOF] = wq.sqrt();
    }
    let t_end = g.time(g.n - 1);
    let mut t = g.t0;
    let mut k1 = model.derivatives(t, &x, &u);
    let (mut fa, mut fb, mut fc, mut fd, mut f1) = Default::default();
    let mut h = g.h;
    let mut level = 0.0_f64;
    let mut rejected = false;
    let mut steps = 0usize;
    // the error of the last accepted step (the PI controller's memory), floored as DOPRI5 does
    let mut facold = 1e-4_f64;
    // sample 0 is the initial state
    raw.push(dot(&x) + y0);
    if let Some(st) = states.as_mut() {
        if g.records_state(0) {
            st.push(x);
        }
    }
    let mut next = 1usize;
    let h_min = 1e-6 * g.h;
    while next < g.n {
        let last = t + h >= t_end;
        if last {
            h = t_end - t;
        }
        model.frame_into(t + C2 * h, &mut fa);
        let k2 = model.derivatives_frame(&fa, &(x + k1 * (h * A21)), &u);
        model.frame_into(t + C3 * h, &mut fb);
        let k3 = model.derivatives_frame(&fb, &(x + (k1 * A31 + k2 * A32) * h), &u);
        model.frame_into(t + C4 * h, &mut fc);
        let k4 = model.derivatives_frame(&fc, &(x + (k1 * A41 + k2 * A42 + k3 * A43) * h), &u);
        model.frame_into(t + C5 * h, &mut fd);
        let k5 = model.derivatives_frame(
            &fd,
            &(x + (k1 * A51 + k2 * A52 + k3 * A53 + k4 * A54) * h),
            &u,
        );
        let t_new = if last { t_end } else { t + h };
        model.frame_into(t_new, &mut f1);
        let k6 = model.derivatives_frame(
            &f1,
            &(x + (k1 * A61 + k2 * A62 + k3 * A63 + k4 * A64 + k5 * A65) * h),
            &u,
        );
        let x_new = x + (k1 * B1 + k3 * B3 + k4 * B4 + k5 * B5 + k6 * B6) * h;
        let k7 = model.derivatives_frame(&f1, &x_new, &u);
        let e = (k1 * E1 + k3 * E3 + k4 * E4 + k5 * E5 + k6 * E6 + k7 * E7) * h;
        let y_new = dot(&x_new) + y0;
        let scale = atol + rtol * level.max((y_new - y0).abs());
        let err = e.component_mul(&w).amax() / scale;
        if !err.is_finite() {
            return Err(ModelError::Diverged { time_s: t });
        }
        // Step-size controller: DOPRI5's (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4)
        // with its PI ("Lund") stabilisation, β = PI_BETA: h_new = h · 0.9 / (err^(1/5 − 0.75β)
        // · err_prev^(−β)), ratio in [0.2, 10]; a rejected step shrinks by err^(1/5 − 0.75β)/0.9
        // (at most 5×).
        let fac11 = err.powf(0.2 - 0.75 * PI_BETA);
        if err <= 1.0 || h <= h_min {
            // continuous extension: x(t + θh) = r1 + θ(r2 + (1−θ)(r3 + θ(r4 + (1−θ) r5))),
            // r1 = x, r2 = x_new − x, r3 = h k1 − r2, r4 = r2 − h k7 − r3, r5 = h Σ d_i k_i; the
            // output is linear in the state, so its coefficients are the same combinations of
            // H·x, H·x_new and H·k_i (the state vectors only when states are recorded).
            let yx = dot(&x);
            let yk = [dot(&k1), dot(&k3), dot(&k4), dot(&k5), dot(&k6), dot(&k7)];
            let y2 = dot(&x_new) - yx;
            let y3 = h * yk[0] - y2;
            let y4 = y2 - h * yk[5] - y3;
            let y5 =
                h * (D1 * yk[0] + D3 * yk[1] + D4 * yk[2] + D5 * yk[3] + D6 * yk[4] + D7 * yk[5]);
            let y1 = yx + y0;
            let mut rs: Option<[State; 4]> = None;
            while next < g.n && (last || g.time(next) <= t_new) {
                let th = (g.time(next) - t) / h;
                let th1 = 1.0 - th;
                let y = y1 + th * (y2 + th1 * (y3 + th * (y4 + th1 * y5)));
                level = level.max((y - y0).abs());
                raw.push(y);
                if let Some(st) = states.as_mut() {
                    if g.records_state(next) {
                        let [r2, r3, r4, r5] = *rs.get_or_insert_with(|| {
                            let r2 = x_new - x;
                            let r3 = k1 * h - r2;
                            let r4 = r2 - k7 * h - r3;
                            let r5 =
                                (k1 * D1 + k3 * D3 + k4 * D4 + k5 * D5 + k6 * D6 + k7 * D7) * h;
                            [r2, r3, r4, r5]
                        });
                        st.push(x + (r2 + (r3 + (r4 + r5 * th1) * th) * th1) * th);
                    }
                }
                next += 1;
            }
            check_finite(&x_new, t_new)?;
            x = x_new;
            t = t_new;
            k1 = k7;
            steps += 1;
            let fac = (fac11 / facold.powf(PI_BETA) / 0.9).clamp(0.1, 5.0);
            facold = err.max(1e-4);
            let mut h_new = h / fac;
            if rejected {
                h_new = h_new.min(h);
            }
            rejected = false;
            h = h_new;
        } else {
            rejected = true;
            h /= (fac11 / 0.9).min(5.0);
        }
    }
    Ok(steps)
}
