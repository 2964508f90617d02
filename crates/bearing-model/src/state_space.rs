//! The 5-DOF model in state-space form, eqs. (2.4), (2.26), (3.8): the map from state and input
//! to acceleration, its uncertainty/fault term, the measured output, one RK4 step, the linear
//! parts `M, C, K` of eq. (2.3) and a numerical linearization.
//!
//! # State
//!
//! Generalized coordinates `q = [x_s, y_s, x_p, y_p, y_r]` (shaft/inner race x, y; pedestal/
//! outer race x, y; sprung mass y), metres; the state is `x = [q; q̇]` ([`STATE_DIM`] = 10).
//! `y` points up. The index constants in [`idx`] name the entries; the housing (pedestal and
//! sprung mass) positions are [`HOUSING_DOFS`].
//!
//! # Equations (signs corrected, see `docs/equations/bearing-model.md`)
//!
//! ```text
//! M_S ẍ_s = −K_S x_s − C_S ẋ_s − F_x + h_x + u_0
//! M_S ÿ_s = −K_S y_s − C_S ẏ_s − F_y + h_y − W − M_S g + u_1
//! M_P ẍ_p = −K_P x_p − C_P ẋ_p + F_x + u_2
//! M_P ÿ_p = −K_P y_p − C_P ẏ_p − K_R (y_p − y_r) − C_R (ẏ_p − ẏ_r) + F_y − M_P g⋆ + u_3
//! M_R ÿ_r = −K_R (y_r − y_p) − C_R (ẏ_r − ẏ_p) − M_R g⋆ + u_4
//! F_x, F_y = Σ_j k_b δ_j^1.5 (cos θ_j, sin θ_j),  δ_j = max(e_x cos θ_j + e_y sin θ_j − c − β_j(t), 0)
//! ```
//!
//! with `e = (x_s − x_p, y_s − y_p)`, `θ_j` from eq. (2.8), `β_j(t)` the spall drops
//! (eqs. 2.16–2.24), `h` the shaft-harmonic forces, `W` the radial load, `g⋆ = g` only for
//! [`crate::Gravity::AllMasses`]. The measured output is the sprung-mass acceleration `ÿ_r`
//! (m/s²), a *linear* function of the state: `y = H x + y₀` ([`BearingModel::output_row`]).

use crate::error::{ModelError, Result};
use crate::fault::SpallProfile;
use crate::params::{G, Gravity, ModelSpec, ShaftHarmonic, Slip};
use nalgebra::{SMatrix, SVector};
use rand::{Rng, SeedableRng};
use std::f64::consts::{PI, TAU};

/// Number of mechanical degrees of freedom.
pub const N_DOF: usize = 5;
/// State dimension `[q; q̇]`.
pub const STATE_DIM: usize = 10;
/// State vector `[x_s, y_s, x_p, y_p, y_r, ẋ_s, ẏ_s, ẋ_p, ẏ_p, ẏ_r]`.
pub type State = SVector<f64, STATE_DIM>;
/// Generalized forces added to the five equations (N), the input `u` of eq. (2.26).
pub type Input = SVector<f64, N_DOF>;
/// A vector over the five DOFs (accelerations, forces).
pub type DofVector = SVector<f64, N_DOF>;
/// A 5×5 matrix over the DOFs.
pub type DofMatrix = SMatrix<f64, N_DOF, N_DOF>;
/// The 10×10 state matrix of a linearization.
pub type StateMatrix = SMatrix<f64, STATE_DIM, STATE_DIM>;

/// Indices into [`State`] (positions; add [`N_DOF`] for the matching velocity).
pub mod idx {
    /// Shaft / inner race x.
    pub const XS: usize = 0;
    /// Shaft / inner race y.
    pub const YS: usize = 1;
    /// Pedestal / outer race x.
    pub const XP: usize = 2;
    /// Pedestal / outer race y.
    pub const YP: usize = 3;
    /// Sprung mass (housing resonance, the measured point) y.
    pub const YR: usize = 4;
    /// Offset from a position to its velocity.
    pub const VEL: usize = super::N_DOF;
}

/// The housing DOFs (pedestal x, y and sprung mass y), as indices into the positions.
pub const HOUSING_DOFS: [usize; 3] = [idx::XP, idx::YP, idx::YR];
/// The state index of the measured DOF (sprung-mass position); the output is its acceleration.
pub const MEASURED_DOF: usize = idx::YR;

/// Linear parts of eq. (2.3): `M q̈ + C q̇ + K q + (contact, gravity, faults) = u`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearParts {
    /// Mass matrix `M` (diagonal).
    pub mass: DofMatrix,
    /// Damping matrix `C`.
    pub damping: DofMatrix,
    /// Stiffness matrix `K` (without the ball contacts).
    pub stiffness: DofMatrix,
}

const SLIP_REVS: usize = 1024;

/// Source of [`BearingModel`] ids (0 is "no model").
static NEXT_MODEL_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// Largest number of balls the model supports (fixed-size per-ball buffers).
pub const MAX_BALLS: usize = 32;

/// Everything about the balls that depends on time only (not on the state): their directions
/// (the cage angle `θ_c` and each ball's offset `a_j` in the cage), their gaps (clearance +
/// spall drop), and the shaft-harmonic force. Computing it once per time instant lets RK4
/// share it between the two mid-step stages and between the end of one step and the start of
/// the next. Refilling a frame with [`BearingModel::frame_into`] reuses the ball offsets when
/// no ball's slip draw changed since the last fill by the same model.
#[derive(Debug, Clone, Copy)]
pub struct BallFrame {
    n: usize,
    /// Which model filled `ca`, `sa`, `off` ([`BearingModel`]'s id, 0 = none) and for which
    /// slip state (ball 0's revolution count, first ball one revolution ahead).
    cache: (u64, i64, usize),
    /// a_j = 2πj/n + slip.
    off: [f64; MAX_BALLS],
    /// cos θ_c, sin θ_c (cage angle of ball 0 without slip).
    c0: f64,
    s0: f64,
    /// Ball directions in the cage frame: cos a_j, sin a_j (a_j = 2πj/n + slip).
    ca: [f64; MAX_BALLS],
    sa: [f64; MAX_BALLS],
    gap: [f64; MAX_BALLS],
    hx: f64,
    hy: f64,
}

impl Default for BallFrame {
    /// No balls (fill with [`BearingModel::frame_into`]).
    fn default() -> Self {
        Self {
            n: 0,
            cache: (0, 0, 0),
            off: [0.0; MAX_BALLS],
            c0: 1.0,
            s0: 0.0,
            ca: [0.0; MAX_BALLS],
            sa: [0.0; MAX_BALLS],
            gap: [0.0; MAX_BALLS],
            hx: 0.0,
            hy: 0.0,
        }
    }
}

/// The 5-DOF bearing model with its (possibly perturbed) parameters, faults and slip.
///
/// Build once with [`BearingModel::new`]; every evaluation afterwards is allocation-free.
#[derive(Debug, Clone)]
pub struct BearingModel {
    spec: ModelSpec,
    ms: f64,
    mp: f64,
    mr: f64,
    ks: f64,
    kp: f64,
    kr: f64,
    cs: f64,
    cp: f64,
    cr: f64,
    kb: f64,
    clearance: f64,
    inv_ms: f64,
    inv_mp: f64,
    inv_mr: f64,
    g_shaft: f64,
    g_housing: f64,
    radial_load: f64,
    omega_s: f64,
    omega_c: f64,
    omega_spin: f64,
    theta0: f64,
    n_balls: usize,
    /// cos/sin of 2πj/n.
    ball_offsets: Vec<(f64, f64)>,
    /// 2πj/n.
    ball_nominal: Vec<f64>,
    /// 1 − j/n: ball j's slip revolution count is one more than ball 0's past this fraction.
    slip_threshold: Vec<f64>,
    /// Slip table: per ball, SLIP_REVS entries of (ε, cos(α_j+ε), sin(α_j+ε)).
    slip: Option<Vec<(f64, f64, f64)>>,
    slip_switch: f64,
    /// Slip amplitude as a fraction of the ball spacing (0 without slip).
    slip_fraction: f64,
    /// Unique per [`BearingModel::new`] (clones share it: same tables), for [`BallFrame`]'s cache.
    id: u64,
    inner: Option<SpallProfile>,
    outer: Option<SpallProfile>,
    ball: Option<(SpallProfile, SpallProfile)>,
    harmonics: Vec<ShaftHarmonic>,
}

impl BearingModel {
    /// Validate `spec` and precompute everything the inner loop needs (perturbed parameters
    /// from the seeded ΔM/ΔC/ΔK draws, ball offsets, slip table, spall profiles).
    pub fn new(spec: &ModelSpec) -> Result<Self> {
        spec.validate()?;
        let s = &spec.structure;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed);
        rng.set_stream(1);
        let u = spec.uncertainty;
        let mut draw = |b: f64| {
            if b > 0.0 {
                1.0 + rng.random_range(-b..=b)
            } else {
                1.0
            }
        };
        let ms = s.shaft_mass_kg * draw(u.mass);
        let mp = s.pedestal_mass_kg * draw(u.mass);
        let mr = spec.housing.mass_kg * draw(u.mass);
        let ks = s.shaft_stiffness_n_m * draw(u.stiffness);
        let kp = s.pedestal_stiffness_n_m * draw(u.stiffness);
        let kr = spec.housing.stiffness() * draw(u.stiffness);
        let kb = spec.contact.hertz_constant * draw(u.stiffness);
        let cs = s.shaft_damping_ns_m * draw(u.damping);
        let cp = s.pedestal_damping_ns_m * draw(u.damping);
        let cr = spec.housing.damping() * draw(u.damping);
        let (g_shaft, g_housing) = match spec.gravity {
            Gravity::Off => (0.0, 0.0),
            Gravity::ShaftOnly => (G, 0.0),
            Gravity::AllMasses => (G, G),
        };
        let geo = &spec.geometry;
        let orders = geo.orders();
        let omega_s = TAU * spec.speed.hz();
        let n = geo.n_balls;
        let ball_offsets: Vec<(f64, f64)> = (0..n)
            .map(|j| (TAU * j as f64 / n as f64).sin_cos())
            .map(|(s, c)| (c, s))
            .collect();
        // Load on the pedestal from a rigid-contact estimate: negative = pushed down = load
        // zone at 6 o'clock; slip offsets are redrawn on the opposite (unloaded) side.
        let total_down = ms * g_shaft + spec.radial_load_n + (mp + mr) * g_housing;
        let fy_ped = (mp + mr) * g_housing - kp / (ks + kp) * total_down;
        let slip_switch = if fy_ped <= 0.0 { PI / 2.0 } else { -PI / 2.0 };
        let slip = match spec.slip {
            Slip::Off => None,
            Slip::Random { fraction } => {
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed);
                rng.set_stream(2);
                let amp = fraction * TAU / n as f64;
                let mut t = Vec::with_capacity(n * SLIP_REVS);
                for j in 0..n {
                    let a = TAU * j as f64 / n as f64;
                    for _ in 0..SLIP_REVS {
                        let e: f64 = rng.random_range(-amp..=amp);
                        let (sn, cs) = (a + e).sin_cos();
                        t.push((e, cs, sn));
                    }
                }
                Some(t)
            }
        };
        let r_ball = 0.5 * geo.ball_diameter_m;
        let r_in = geo.inner_race_radius_m();
        let r_out = geo.outer_race_radius_m();
        let inner = spec
            .faults
            .inner
            .map(|sp| SpallProfile::new(&sp, r_in, r_ball, r_in, 1.0));
        let outer = spec
            .faults
            .outer
            .map(|sp| SpallProfile::new(&sp, r_out, r_ball, r_out, -1.0));
        let ball = spec.faults.ball.map(|sp| {
            (
                SpallProfile::new(&sp, r_ball, r_ball, r_out, -1.0),
                SpallProfile::new(&sp, r_ball, r_ball, r_in, 1.0),
            )
        });
        Ok(Self {
            spec: spec.clone(),
            ms,
            mp,
            mr,
            ks,
            kp,
            kr,
            cs,
            cp,
            cr,
            kb,
            clearance: spec.contact.clearance_m,
            inv_ms: 1.0 / ms,
            inv_mp: 1.0 / mp,
            inv_mr: 1.0 / mr,
            g_shaft,
            g_housing,
            radial_load: spec.radial_load_n,
            omega_s,
            omega_c: orders.ftf * omega_s,
            omega_spin: orders.ball_spin * omega_s,
            theta0: spec.cage_angle0_rad,
            n_balls: n,
            ball_offsets,
            ball_nominal: (0..n).map(|j| TAU * j as f64 / n as f64).collect(),
            slip_threshold: (0..n).map(|j| 1.0 - j as f64 / n as f64).collect(),
            slip,
            slip_switch,
            slip_fraction: match spec.slip {
                Slip::Off => 0.0,
                Slip::Random { fraction } => fraction,
            },
            id: NEXT_MODEL_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            inner,
            outer,
            ball,
            harmonics: spec.harmonics.clone(),
        })
    }

    /// The spec this model was built from.
    pub fn spec(&self) -> &ModelSpec {
        &self.spec
    }

    /// The same bearing without faults, slip or uncertainty: the nominal model an observer
    /// uses as its predictor.
    pub fn nominal(&self) -> Result<BearingModel> {
        let mut s = self.spec.clone();
        s.faults = crate::fault::FaultSet::healthy();
        s.slip = Slip::Off;
        s.uncertainty = crate::params::Uncertainty::default();
        BearingModel::new(&s)
    }

    /// Number of balls.
    pub fn n_balls(&self) -> usize {
        self.n_balls
    }

    /// Shaft angular speed, rad/s.
    pub fn shaft_omega(&self) -> f64 {
        self.omega_s
    }

    /// Cage angle θ_c(t) of ball 0 without slip (eq. 2.8), rad.
    pub fn cage_angle(&self, t: f64) -> f64 {
        self.theta0 + self.omega_c * t
    }

    /// Visit every ball: `(j, cos θ_j, sin θ_j, a_j)` with `θ_j = θ_c(t) + a_j`, `a_j` the
    /// ball's angular offset from ball 0's nominal position (2πj/n plus slip).
    #[inline(always)]
    fn for_each_ball(&self, t: f64, mut f: impl FnMut(usize, f64, f64, f64)) {
        let th = self.cage_angle(t);
        let (s0, c0) = sin_cos(th);
        self.for_each_ball_in_cage(th, |j, ca, sa, a| {
            f(j, c0 * ca - s0 * sa, s0 * ca + c0 * sa, a)
        });
    }

    /// What the slip offsets of all balls depend on at cage angle `th`: ball 0's revolution
    /// count `⌊b⌋` and the first ball `j*` whose count is one more (`frac(b) ≥ 1 − j/n` for
    /// `j ≥ j*`, see [`Self::for_each_ball_in_cage`]). `(0, 0)` without slip.
    #[inline(always)]
    fn slip_state(&self, th: f64) -> (i64, usize) {
        if self.slip.is_none() {
            return (0, 0);
        }
        let b = (th - self.slip_switch) * (1.0 / TAU);
        let r0 = floor_i64(b);
        let fr = b - r0 as f64;
        let first = self
            .slip_threshold
            .iter()
            .take_while(|&&thr| fr < thr)
            .count();
        (r0, first)
    }

    /// Visit every ball in the cage frame (rotated by `−θ_c`): `(j, cos a_j, sin a_j, a_j)`.
    ///
    /// Slip: ball `j`'s offset is redrawn when `θ_c + 2πj/n` crosses `slip_switch` (mod 2π),
    /// i.e. its revolution count is `⌊b + j/n⌋ = ⌊b⌋ + [frac(b) ≥ 1 − j/n]` with
    /// `b = (θ_c − slip_switch)/2π`: one floor per evaluation instead of one per ball.
    #[inline(always)]
    fn for_each_ball_in_cage(&self, th: f64, mut f: impl FnMut(usize, f64, f64, f64)) {
        match &self.slip {
            None => {
                for (j, (&(ca, sa), &a)) in
                    self.ball_offsets.iter().zip(&self.ball_nominal).enumerate()
                {
                    f(j, ca, sa, a);
                }
            }
            Some(tab) => {
                let b = (th - self.slip_switch) * (1.0 / TAU);
                let r0 = floor_i64(b);
                let fr = b - r0 as f64;
                for (j, (&a, &thr)) in self
                    .ball_nominal
                    .iter()
                    .zip(&self.slip_threshold)
                    .enumerate()
                {
                    let rev = r0 + i64::from(fr >= thr);
                    let k = (rev & (SLIP_REVS as i64 - 1)) as usize;
                    let (e, ca, sa) = tab[j * SLIP_REVS + k];
                    f(j, ca, sa, a + e);
                }
            }
        }
    }

    /// Per-evaluation fault phases: the cage angle relative to each race spall's entry edge
    /// (wrapped once), and the ball spall's spin angle. `NaN` = spall absent or not yet there.
    #[inline(always)]
    fn fault_phases(&self, t: f64) -> [f64; 3] {
        let th = self.cage_angle(t);
        let mut ph = [f64::NAN; 3];
        if let Some(p) = &self.outer {
            if t >= p.onset {
                ph[0] = wrap(th - p.angle0);
            }
        }
        if let Some(p) = &self.inner {
            if t >= p.onset {
                ph[1] = wrap(th - p.angle0 - self.omega_s * t);
            }
        }
        if let Some((po, _)) = &self.ball {
            if t >= po.onset {
                ph[2] = wrap(po.angle0 + self.omega_spin * t);
            }
        }
        ph
    }

    /// Total spall drop β_j(t) for ball `j` with offset `a_j` (eqs. 2.16–2.24), given the
    /// phases of [`Self::fault_phases`].
    #[inline(always)]
    fn spall_drop(&self, ph: &[f64; 3], j: usize, a: f64) -> f64 {
        let mut drop = 0.0;
        if let Some(p) = &self.outer {
            if !ph[0].is_nan() {
                drop += p.drop(wrap_fast(ph[0] + a));
            }
        }
        if let Some(p) = &self.inner {
            if !ph[1].is_nan() {
                drop += p.drop(wrap_fast(ph[1] + a));
            }
        }
        if j == 0 && !ph[2].is_nan() {
            if let Some((po, pi)) = &self.ball {
                drop += po.drop(ph[2]) + pi.drop(wrap_fast(ph[2] + PI));
            }
        }
        drop
    }

    #[inline(always)]
    fn has_faults(&self) -> bool {
        self.inner.is_some() || self.outer.is_some() || self.ball.is_some()
    }

    /// The time-only part of the model at `t` (ball directions, gaps, harmonic force).
    #[inline]
    pub fn frame(&self, t: f64) -> BallFrame {
        let mut f = BallFrame::default();
        self.frame_into(t, &mut f);
        f
    }

    /// [`Self::frame`] written into `f` (no 0.8 kB copy; only the first `n_balls` entries
    /// are touched). Bit-identical to [`Self::frame`].
    #[inline]
    pub fn frame_into(&self, t: f64, f: &mut BallFrame) {
        f.hx = 0.0;
        f.hy = 0.0;
        let clearance = self.clearance;
        let th = self.cage_angle(t);
        (f.s0, f.c0) = sin_cos(th);
        let key = (self.id, self.slip_state(th));
        if f.n != self.n_balls || (f.cache.0, (f.cache.1, f.cache.2)) != key {
            self.for_each_ball_in_cage(th, |j, ca, sa, a| {
                f.ca[j] = ca;
                f.sa[j] = sa;
                f.off[j] = a;
            });
            f.n = self.n_balls;
            f.cache = (key.0, key.1.0, key.1.1);
        }
        f.gap[..self.n_balls].fill(clearance);
        let offs = &f.off;
        if self.has_faults() {
            // Each spall's drop is added only to the balls that can be inside it; every other
            // ball's drop is exactly 0 (see `spall_candidates`), so the gaps are bit-identical
            // to summing every spall over every ball (unit test).
            let ph = self.fault_phases(t);
            let mut drop = [0.0; MAX_BALLS];
            let mut touched = 0u32;
            for (k, p) in [(0, &self.outer), (1, &self.inner)] {
                if let Some(p) = p {
                    if !ph[k].is_nan() {
                        let mut mask = self.spall_candidates(ph[k], p.width_rad);
                        touched |= mask;
                        while mask != 0 {
                            let j = mask.trailing_zeros() as usize;
                            mask &= mask - 1;
                            drop[j] += p.drop(wrap_fast(ph[k] + offs[j]));
                        }
                    }
                }
            }
            if let Some((po, pi)) = &self.ball {
                if !ph[2].is_nan() {
                    drop[0] += po.drop(ph[2]) + pi.drop(wrap_fast(ph[2] + PI));
                    touched |= 1;
                }
            }
            while touched != 0 {
                let j = touched.trailing_zeros() as usize;
                touched &= touched - 1;
                f.gap[j] = clearance + drop[j];
            }
        }
        for h in &self.harmonics {
            let (sn, cs) = (h.order as f64 * self.omega_s * t + h.phase_rad).sin_cos();
            f.hx += h.amplitude_n * cs;
            f.hy += h.amplitude_n * sn;
        }
    }

    /// Bit set of the balls that can be inside a race spall of angular width `width` at phase
    /// `ph ∈ [0, 2π)` (from [`Self::fault_phases`]). Ball `j` is inside iff
    /// `wrap(ph + a_j) < width` with `a_j = j·s + ε_j`, `s = 2π/n`, `|ε_j| ≤ f·s` (`f` the slip
    /// fraction, 0 without slip) and `width < s` (validated), i.e. (mod n)
    /// `j ∈ [q − f, q + width/s + f)` with `q = (2π − ph)/s`. The candidates
    /// `⌊q − f − 10⁻⁹⌋ ..= ⌊q + width/s + f + 10⁻⁹⌋` cover it (the 10⁻⁹ spacing absorbs
    /// rounding): usually one or two balls.
    #[inline(always)]
    fn spall_candidates(&self, ph: f64, width: f64) -> u32 {
        const MARGIN: f64 = 1e-9;
        let n = self.n_balls as i64;
        let per = self.n_balls as f64 * (1.0 / TAU);
        let q = (TAU - ph) * per;
        let lo = floor_i64(q - self.slip_fraction - MARGIN);
        let hi = floor_i64(q + width * per + self.slip_fraction + MARGIN).min(lo + n - 1);
        // q ∈ (0, n] and f ≤ 0.1, so lo ∈ [−1, n]
        let mut j = if lo < 0 {
            lo + n
        } else if lo >= n {
            lo - n
        } else {
            lo
        };
        let mut mask = 0u32;
        for _ in lo..=hi {
            mask |= 1 << j;
            j += 1;
            if j == n {
                j = 0;
            }
        }
        mask
    }

    #[inline(always)]
    fn contact_force_frame(&self, f: &BallFrame, x: &State) -> (f64, f64) {
        let ex = x[idx::XS] - x[idx::XP];
        let ey = x[idx::YS] - x[idx::YP];
        // In the cage frame: δ_j = e·n_j − gap_j = (R(−θ_c) e)·(cos a_j, sin a_j) − gap_j and
        // F = R(θ_c) Σ Q_j (cos a_j, sin a_j).
        let (c0, s0) = (f.c0, f.s0);
        let eu = ex * c0 + ey * s0;
        let ev = ey * c0 - ex * s0;
        let (mut fu, mut fv) = (0.0, 0.0);
        for j in 0..f.n {
            let (ca, sa) = (f.ca[j], f.sa[j]);
            let d = eu * ca + ev * sa - f.gap[j];
            if d > 0.0 {
                let q = self.kb * d * d.sqrt();
                fu += q * ca;
                fv += q * sa;
            }
        }
        (c0 * fu - s0 * fv, s0 * fu + c0 * fv)
    }

    /// Contact force on the pedestal `(F_x, F_y)` (eq. 2.9); the shaft gets the opposite.
    #[inline]
    pub fn contact_force(&self, t: f64, x: &State) -> (f64, f64) {
        self.contact_force_frame(&self.frame(t), x)
    }

    /// Per-ball contact loads `Q_j ≥ 0` (N) into `out` (length ≥ `n_balls`), eqs. (2.9)–(2.11).
    pub fn ball_loads(&self, t: f64, x: &State, out: &mut [f64]) {
        let ex = x[idx::XS] - x[idx::XP];
        let ey = x[idx::YS] - x[idx::YP];
        let ph = self.fault_phases(t);
        self.for_each_ball(t, |j, c, s, a| {
            let d = ex * c + ey * s - self.clearance - self.spall_drop(&ph, j, a);
            if let Some(o) = out.get_mut(j) {
                *o = if d > 0.0 { self.kb * d * d.sqrt() } else { 0.0 };
            }
        });
    }

    /// Angles θ_j(t) of the balls (slip included), rad, into `out`.
    pub fn ball_angles(&self, t: f64, out: &mut [f64]) {
        let th = self.cage_angle(t);
        self.for_each_ball(t, |j, _, _, a| {
            if let Some(o) = out.get_mut(j) {
                *o = th + a;
            }
        });
    }

    /// Generalized accelerations `q̈ = f(t, x, u)`, eq. (2.4)/(3.8), allocation-free.
    #[inline]
    pub fn accelerations(&self, t: f64, x: &State, u: &Input) -> DofVector {
        self.accelerations_frame(&self.frame(t), x, u)
    }

    /// [`Self::accelerations`] with the time-only part precomputed by [`Self::frame`].
    #[inline(always)]
    pub fn accelerations_frame(&self, f: &BallFrame, x: &State, u: &Input) -> DofVector {
        let (fx, fy) = self.contact_force_frame(f, x);
        let (hx, hy) = (f.hx, f.hy);
        let (xs, ys, xp, yp, yr) = (x[0], x[1], x[2], x[3], x[4]);
        let (vxs, vys, vxp, vyp, vyr) = (x[5], x[6], x[7], x[8], x[9]);
        let spring_r = self.kr * (yp - yr) + self.cr * (vyp - vyr);
        DofVector::new(
            (-self.ks * xs - self.cs * vxs - fx + hx + u[0]) * self.inv_ms,
            (-self.ks * ys - self.cs * vys - fy + hy - self.radial_load + u[1]) * self.inv_ms
                - self.g_shaft,
            (-self.kp * xp - self.cp * vxp + fx + u[2]) * self.inv_mp,
            (-self.kp * yp - self.cp * vyp - spring_r + fy + u[3]) * self.inv_mp - self.g_housing,
            (spring_r + u[4]) * self.inv_mr - self.g_housing,
        )
    }

    /// State derivative `ẋ = [q̇; q̈]`, the right-hand side of eq. (3.8).
    #[inline]
    pub fn derivatives(&self, t: f64, x: &State, u: &Input) -> State {
        self.derivatives_frame(&self.frame(t), x, u)
    }

    /// [`Self::derivatives`] with the time-only part precomputed by [`Self::frame`].
    #[inline(always)]
    pub fn derivatives_frame(&self, f: &BallFrame, x: &State, u: &Input) -> State {
        let a = self.accelerations_frame(f, x, u);
        let mut d = State::zeros();
        d.fixed_rows_mut::<N_DOF>(0)
            .copy_from(&x.fixed_rows::<N_DOF>(N_DOF));
        d.fixed_rows_mut::<N_DOF>(N_DOF).copy_from(&a);
        d
    }

    /// Measured output (eq. 2.26 `Y`): the housing (sprung-mass) acceleration ÿ_r, m/s², with
    /// no input on the sprung mass. Equals `output_row() · x + output_offset()`.
    #[inline]
    pub fn output(&self, _t: f64, x: &State) -> f64 {
        (self.kr * (x[idx::YP] - x[idx::YR])
            + self.cr * (x[idx::YP + idx::VEL] - x[idx::YR + idx::VEL]))
            * self.inv_mr
            - self.g_housing
    }

    /// The output is linear in the state: `Y = H x + y₀`; this is `H`.
    pub fn output_row(&self) -> SMatrix<f64, 1, STATE_DIM> {
        let mut h = SMatrix::<f64, 1, STATE_DIM>::zeros();
        h[idx::YP] = self.kr * self.inv_mr;
        h[idx::YR] = -self.kr * self.inv_mr;
        h[idx::YP + idx::VEL] = self.cr * self.inv_mr;
        h[idx::YR + idx::VEL] = -self.cr * self.inv_mr;
        h
    }

    /// The constant `y₀` of the output (−g when gravity acts on the sprung mass, else 0).
    pub fn output_offset(&self) -> f64 {
        -self.g_housing
    }

    /// One classical fourth-order Runge–Kutta step of length `h` with the input held constant.
    #[inline]
    pub fn step(&self, t: f64, x: &mut State, h: f64, u: &Input) {
        let f0 = self.frame(t);
        let _ = self.step_with_frame(&f0, t, x, h, u);
    }

    /// RK4 step given the frame at `t`; returns the frame at `t + h` for the next step
    /// (two frame evaluations per step instead of four).
    #[inline]
    pub fn step_with_frame(
        &self,
        f0: &BallFrame,
        t: f64,
        x: &mut State,
        h: f64,
        u: &Input,
    ) -> BallFrame {
        let fm = self.frame(t + 0.5 * h);
        let f1 = self.frame(t + h);
        let k1 = self.derivatives_frame(f0, x, u);
        let k2 = self.derivatives_frame(&fm, &(*x + k1 * (0.5 * h)), u);
        let k3 = self.derivatives_frame(&fm, &(*x + k2 * (0.5 * h)), u);
        let k4 = self.derivatives_frame(&f1, &(*x + k3 * h), u);
        *x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        f1
    }

    /// `n` RK4 steps of `h` from `t` (useful when an observer runs slower than the model's
    /// converged step). Returns the final time.
    pub fn step_n(&self, t: f64, x: &mut State, h: f64, n: usize, u: &Input) -> f64 {
        for i in 0..n {
            self.step(t + i as f64 * h, x, h, u);
        }
        t + n as f64 * h
    }

    /// The linear parts `M, C, K` of eq. (2.3) with this model's (perturbed) values; the ball
    /// contacts, gravity and faults are the nonlinear remainder.
    pub fn linear_parts(&self) -> LinearParts {
        let mut m = DofMatrix::zeros();
        m[(0, 0)] = self.ms;
        m[(1, 1)] = self.ms;
        m[(2, 2)] = self.mp;
        m[(3, 3)] = self.mp;
        m[(4, 4)] = self.mr;
        let band = |a: f64, b: f64, r: f64| {
            let mut k = DofMatrix::zeros();
            k[(0, 0)] = a;
            k[(1, 1)] = a;
            k[(2, 2)] = b;
            k[(3, 3)] = b + r;
            k[(3, 4)] = -r;
            k[(4, 3)] = -r;
            k[(4, 4)] = r;
            k
        };
        LinearParts {
            mass: m,
            damping: band(self.cs, self.cp, self.cr),
            stiffness: band(self.ks, self.kp, self.kr),
        }
    }

    /// Numerical Jacobian `∂ẋ/∂x` at `(t, x, u)` by central differences (a linearization for
    /// observer gain design). Position steps 1e-10 m, velocity steps 1e-7 m/s.
    pub fn jacobian(&self, t: f64, x: &State, u: &Input) -> StateMatrix {
        let mut a = StateMatrix::zeros();
        for i in 0..STATE_DIM {
            let h = if i < N_DOF { 1e-10 } else { 1e-7 };
            let mut xp = *x;
            xp[i] += h;
            let mut xm = *x;
            xm[i] -= h;
            let col = (self.derivatives(t, &xp, u) - self.derivatives(t, &xm, u)) / (2.0 * h);
            a.set_column(i, &col);
        }
        a
    }

    /// Upper bound on the highest natural angular frequency (rad/s) at state `x`: Gershgorin
    /// bound on `M⁻¹ K_t`, `K_t` the tangent stiffness including the ball contacts.
    pub fn max_omega(&self, t: f64, x: &State) -> f64 {
        let a = self.jacobian(t, x, &Input::zeros());
        let mut worst: f64 = 0.0;
        for i in N_DOF..STATE_DIM {
            let row: f64 = (0..N_DOF).map(|j| a[(i, j)].abs()).sum();
            worst = worst.max(row);
        }
        worst.sqrt()
    }

    /// The uncertainty/fault term λ of eq. (2.4) (Γ of eq. 3.5) at `(t, x, u)`: this model's
    /// acceleration minus `nominal`'s. With `nominal = self.nominal()` it is exactly what the
    /// faults, slip and ΔM/ΔC/ΔK add.
    pub fn lumped_term(&self, nominal: &BearingModel, t: f64, x: &State, u: &Input) -> DofVector {
        self.accelerations(t, x, u) - nominal.accelerations(t, x, u)
    }

    /// Static equilibrium at time `t` (ball positions frozen at `t`, harmonics off, input 0):
    /// damped Newton iteration on the five force balances.
    pub fn static_equilibrium(&self, t: f64) -> Result<State> {
        let frame = self.frame(t);
        let resid = |q: &DofVector| -> DofVector {
            let mut x = State::zeros();
            x.fixed_rows_mut::<N_DOF>(0).copy_from(q);
            let (fx, fy) = self.contact_force_frame(&frame, &x);
            let spring_r = self.kr * (q[3] - q[4]);
            DofVector::new(
                -self.ks * q[0] - fx,
                -self.ks * q[1] - fy - self.radial_load - self.ms * self.g_shaft,
                -self.kp * q[2] + fx,
                -self.kp * q[3] - spring_r + fy - self.mp * self.g_housing,
                spring_r - self.mr * self.g_housing,
            )
        };
        // Initial guess: shaft and pedestal moving together on ks + kp.
        let total =
            self.ms * self.g_shaft + self.radial_load + (self.mp + self.mr) * self.g_housing;
        let y0 = -total / (self.ks + self.kp);
        let mut q = DofVector::new(0.0, y0, 0.0, y0, y0 - self.mr * self.g_housing / self.kr);
        let scale = total.max(1.0);
        let mut r = resid(&q);
        let mut it = 0;
        while it < 200 {
            if r.norm() < 1e-10 * scale {
                let mut x = State::zeros();
                x.fixed_rows_mut::<N_DOF>(0).copy_from(&q);
                return Ok(x);
            }
            let mut j = DofMatrix::zeros();
            for i in 0..N_DOF {
                let h = 1e-11_f64.max(1e-7 * q[i].abs());
                let mut qp = q;
                qp[i] += h;
                let mut qm = q;
                qm[i] -= h;
                j.set_column(i, &((resid(&qp) - resid(&qm)) / (2.0 * h)));
            }
            let Some(dq) = j.lu().solve(&(-r)) else { break };
            let mut lambda = 1.0;
            loop {
                let qn = q + dq * lambda;
                let rn = resid(&qn);
                if rn.norm() < r.norm() || lambda < 1e-6 {
                    q = qn;
                    r = rn;
                    break;
                }
                lambda *= 0.5;
            }
            it += 1;
        }
        Err(ModelError::EquilibriumNotFound {
            iterations: it,
            residual_n: r.norm(),
        })
    }

    /// Mechanical energy (J) at state `x` and time `t`: kinetic + spring + Hertz contact
    /// (`k_b δ^2.5 / 2.5` per ball) + gravity and radial-load potential. Conserved up to the
    /// dampers' dissipation only when the shaft is at rest (rpm = 0) and no harmonic acts.
    pub fn mechanical_energy(&self, t: f64, x: &State) -> f64 {
        let v = |i: usize| x[i + N_DOF];
        let kin = 0.5 * self.ms * (v(0) * v(0) + v(1) * v(1))
            + 0.5 * self.mp * (v(2) * v(2) + v(3) * v(3))
            + 0.5 * self.mr * v(4) * v(4);
        let spr = 0.5 * self.ks * (x[0] * x[0] + x[1] * x[1])
            + 0.5 * self.kp * (x[2] * x[2] + x[3] * x[3])
            + 0.5 * self.kr * (x[3] - x[4]).powi(2);
        let ex = x[0] - x[2];
        let ey = x[1] - x[3];
        let mut hz = 0.0;
        let ph = self.fault_phases(t);
        self.for_each_ball(t, |j, c, s, a| {
            let d = ex * c + ey * s - self.clearance - self.spall_drop(&ph, j, a);
            if d > 0.0 {
                hz += self.kb * d * d * d.sqrt() / 2.5;
            }
        });
        let grav = (self.ms * self.g_shaft + self.radial_load) * x[1]
            + self.g_housing * (self.mp * x[3] + self.mr * x[4]);
        kin + spr + hz + grav
    }
}

/// `(sin x, cos x)` within about one ulp of the correctly rounded values, about four times
/// cheaper than libm's `sincos` (which the cage angle needs once per frame): Cody–Waite
/// reduction by π/2 in two 33-bit parts (exact products for |x| < 2²⁰·π/2) and fdlibm's
/// kernels on [−π/4, π/4], tail of the reduced argument included. libm for |x| ≥ 10⁵ rad.
#[inline]
#[allow(clippy::excessive_precision)] // fdlibm's constants, as published
fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() >= 1e5 {
        return x.sin_cos();
    }
    const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11;
    const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
    const S1: f64 = -1.666_666_666_666_663_243_48e-1;
    const S2: f64 = 8.333_333_333_322_489_461_24e-3;
    const S3: f64 = -1.984_126_982_985_794_931_34e-4;
    const S4: f64 = 2.755_731_370_707_006_767_89e-6;
    const S5: f64 = -2.505_076_025_340_686_341_95e-8;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    const C1: f64 = 4.166_666_666_666_660_190_37e-2;
    const C2: f64 = -1.388_888_888_887_410_957_49e-3;
    const C3: f64 = 2.480_158_728_947_672_941_78e-5;
    const C4: f64 = -2.755_731_435_139_066_330_35e-7;
    const C5: f64 = 2.087_572_321_298_174_827_90e-9;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    // round to nearest by the 1.5·2⁵² trick (no libm call on baseline x86-64)
    const SHIFTER: f64 = 6_755_399_441_055_744.0;
    let fn_ = (x * INV_PIO2 + SHIFTER) - SHIFTER;
    let n = fn_ as i64;
    let t = x - fn_ * PIO2_1; // exact
    let w = fn_ * PIO2_2; // exact
    let r = t - w;
    let w = fn_ * PIO2_2T - ((t - r) - w);
    let y0 = r - w;
    let y1 = (r - y0) - w;
    let z = y0 * y0;
    // fdlibm __kernel_sin(y0, y1, 1)
    let v = z * y0;
    let rs = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    let sn = y0 - ((z * (0.5 * y1 - v * rs) - y1) - v * S1);
    // fdlibm __kernel_cos(y0, y1)
    let rc = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let wc = 1.0 - hz;
    let cs = wc + (((1.0 - wc) - hz) + (z * rc - y0 * y1));
    match n & 3 {
        0 => (sn, cs),
        1 => (cs, -sn),
        2 => (-sn, -cs),
        _ => (-cs, sn),
    }
}

/// `⌊x⌋` for `|x| < 2⁶³`, bit-identical to `f64::floor` there, without the libm call that
/// baseline x86-64 (no SSE4.1 `roundsd`) makes for `floor`: one truncating conversion.
#[inline(always)]
fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x { i - 1 } else { i }
}

/// Wrap an angle known to lie in `(−2π, 4π)` into `[0, 2π)` without a division.
#[inline(always)]
fn wrap_fast(x: f64) -> f64 {
    if x >= TAU {
        let y = x - TAU;
        if y >= TAU { y - TAU } else { y }
    } else if x < 0.0 {
        x + TAU
    } else {
        x
    }
}

/// Wrap any finite angle into `[0, 2π)`.
#[inline(always)]
fn wrap(x: f64) -> f64 {
    let y = x - TAU * floor_i64(x * (1.0 / TAU)) as f64;
    if y >= TAU {
        y - TAU
    } else if y < 0.0 {
        0.0
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FaultClass, Scenario, Slip};

    /// The frame as first written: every spall summed over every ball, no candidate filter.
    fn gaps_all_balls(m: &BearingModel, t: f64) -> [f64; MAX_BALLS] {
        let mut gap = [m.clearance; MAX_BALLS];
        let ph = m.fault_phases(t);
        m.for_each_ball(t, |j, _, _, a| {
            gap[j] += m.spall_drop(&ph, j, a);
        });
        gap
    }

    #[test]
    fn candidate_filter_gives_bit_identical_gaps_and_cage_frame_the_same_directions() {
        for (class, size_in, slip) in [
            (FaultClass::InnerOuterBall, 0.021, 0.1),
            (FaultClass::InnerOuter, 0.007, 0.01),
            (FaultClass::Outer, 0.014, 0.0),
        ] {
            let mut sc = Scenario::cwru(class, size_in, 1797.0).unwrap();
            sc.spec.slip = if slip > 0.0 {
                Slip::Random { fraction: slip }
            } else {
                Slip::Off
            };
            let m = sc.model().unwrap();
            let mut f = BallFrame::default();
            let mut in_spall = 0;
            for i in 0..200_000 {
                let t = -0.05 + i as f64 * 1.37e-6;
                m.frame_into(t, &mut f);
                let g = gaps_all_balls(&m, t);
                let mut dirs = [(0.0, 0.0); MAX_BALLS];
                m.for_each_ball(t, |j, c, s, _| dirs[j] = (c, s));
                for j in 0..m.n_balls {
                    assert_eq!(f.gap[j].to_bits(), g[j].to_bits(), "{class} t {t} ball {j}");
                    let c = f.c0 * f.ca[j] - f.s0 * f.sa[j];
                    let s = f.s0 * f.ca[j] + f.c0 * f.sa[j];
                    assert_eq!(
                        (c.to_bits(), s.to_bits()),
                        (dirs[j].0.to_bits(), dirs[j].1.to_bits())
                    );
                    in_spall += usize::from(g[j] != m.clearance);
                }
            }
            assert!(
                in_spall > 1000,
                "{class}: the test crosses spalls ({in_spall})"
            );
        }
    }

    #[test]
    fn slip_revolution_count_is_the_per_ball_floor() {
        let sc = Scenario::cwru(FaultClass::None, 0.007, 1797.0).unwrap();
        let m = sc.model().unwrap();
        let n = m.n_balls as f64;
        for i in 0..100_000 {
            let th = -3.0 + i as f64 * 1.1e-3;
            let mut got = [0.0; MAX_BALLS];
            m.for_each_ball_in_cage(th, |j, _, _, a| got[j] = a);
            let tab = m.slip.as_ref().unwrap();
            for j in 0..m.n_balls {
                let a = TAU * j as f64 / n;
                let x = (th + a - m.slip_switch) / TAU;
                // away from the switching instant (within rounding) both counts agree
                if (x - x.round()).abs() > 1e-12 {
                    let k = (x.floor() as i64 & (SLIP_REVS as i64 - 1)) as usize;
                    assert_eq!(got[j], a + tab[j * SLIP_REVS + k].0, "th {th} ball {j}");
                }
            }
        }
    }

    #[test]
    fn sin_cos_is_within_two_ulp_of_libm() {
        let mut worst: f64 = 0.0;
        let mut x = -2e5_f64;
        let mut k = 0u64;
        while x < 2e5 {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            // a deterministic, irregular walk through the range, dense near 0
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            x += 1e-3 + (k >> 40) as f64 * 1e-9 * (1.0 + x.abs());
        }
        for x in [
            0.0,
            -0.0,
            1e-300,
            std::f64::consts::FRAC_PI_4,
            -PI,
            PI / 2.0,
            1e5,
            -1e5 + 0.5,
        ] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst <= 2.3e-16, "worst {worst:e}");
        assert!(sin_cos(f64::NAN).0.is_nan());
    }

    #[test]
    fn fast_floor_matches_floor() {
        for x in [
            -3.5,
            -3.0,
            -1e-300,
            -0.0,
            0.0,
            1e-300,
            0.5,
            1.0,
            2.999_999_999,
            1e15 + 0.5,
            -1e15 - 0.5,
        ] {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
    }
}
