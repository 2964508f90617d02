//! The dynamics of [`BearingModel`]: ball contact forces and loads, the right-hand side
//! `ẋ = f(t, x, u)` of eq. (3.8), the measured output `y = H x + y₀` and the RK4 step.

use super::{BallFrame, BearingModel, DofVector, Input, N_DOF, STATE_DIM, State, idx};
use nalgebra::SMatrix;

impl BearingModel {
    #[inline(always)]
    pub(super) fn contact_force_frame(&self, f: &BallFrame, x: &State) -> (f64, f64) {
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
}
