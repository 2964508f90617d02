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
//!
//! # Layout
//!
//! This module holds the state layout, [`BallFrame`] and [`BearingModel`] with its
//! constructor; the model's methods live in the submodules by concept: `balls` (ball
//! directions, slip, spall gaps: the time-only [`BallFrame`]), `dynamics` (contact forces, the
//! right-hand side, the measured output, RK4), `analysis` (linear parts, Jacobian, lumped term,
//! static equilibrium, energy) and `angles` (fast sin/cos, floor and angle wrapping).

mod analysis;
mod angles;
mod balls;
mod dynamics;

use crate::error::Result;
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

pub use crate::geometry::MAX_BALLS;

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
}
