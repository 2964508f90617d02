//! Analysis of [`BearingModel`] beyond simulation: the linear parts `M, C, K`, the numerical
//! Jacobian and a natural-frequency bound, the lumped term λ, the static equilibrium, the
//! linearised response from a contact force to the measured output, and the mechanical energy.

use super::{
    BearingModel, DofMatrix, DofVector, Input, LinearParts, N_DOF, STATE_DIM, State, StateMatrix,
    idx,
};
use crate::error::{ModelError, Result};
use nalgebra::{Complex, SMatrix, SVector};

impl BearingModel {
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

    /// Power response |T(f)|² of the measured output (the sprung mass's acceleration, eq. 2.26
    /// `Y`) to a vertical contact force — equal and opposite on shaft and pedestal, as a ball's
    /// contact acts (eqs. 2.12–2.13) — of the model linearised at its healthy static
    /// equilibrium at t = 0: `T(f) = C (j2πf I − A)⁻¹ B` with `A` the Jacobian of
    /// [`BearingModel::jacobian`] (ball contacts included at their tangent stiffness), `C` the
    /// output row, `B` the force pair over the masses. Units (m/s²/N)².
    ///
    /// What it is for: the ratio of two models' responses that differ in a linear part (the
    /// housing mode's frequency, eq. 2.14) is how the PSD of a simulation changes when that part
    /// changes, without simulating again — the impacts drive the structure as a force source,
    /// and the linear structure filters them. On the CWRU rig (outer race, 1797 rpm, 12 kHz,
    /// housing 3300 Hz moved by ±5 … ±20 %) the ratio reproduces the ratio of simulated Welch
    /// PSDs to 0.01–0.03 dB RMS over 200–5000 Hz (the housing's own base-excitation filter
    /// alone is 1.5–3.5 dB off: the sprung mass's reaction moves the pedestal).
    ///
    /// # Errors
    /// [`ModelError::EquilibriumNotFound`] from the static equilibrium;
    /// [`ModelError::SingularResponse`] at a non-finite frequency or where the dynamic stiffness
    /// is singular.
    pub fn contact_force_response(&self, freqs_hz: &[f64]) -> Result<Vec<f64>> {
        let healthy = self.nominal()?;
        let x0 = healthy.static_equilibrium(0.0)?;
        let a = healthy.jacobian(0.0, &x0, &Input::zeros());
        let c = healthy.output_row();
        let mut b = SVector::<Complex<f64>, STATE_DIM>::zeros();
        b[idx::VEL + idx::YS] = Complex::new(healthy.inv_ms, 0.0);
        b[idx::VEL + idx::YP] = Complex::new(-healthy.inv_mp, 0.0);
        let minus_a: SMatrix<Complex<f64>, STATE_DIM, STATE_DIM> = a.map(|v| Complex::new(-v, 0.0));
        freqs_hz
            .iter()
            .map(|&f| {
                let singular = ModelError::SingularResponse { frequency_hz: f };
                if !f.is_finite() {
                    return Err(singular);
                }
                let mut z = minus_a;
                let w = std::f64::consts::TAU * f;
                for i in 0..STATE_DIM {
                    z[(i, i)] += Complex::new(0.0, w);
                }
                let x = z.lu().solve(&b).ok_or(singular.clone())?;
                let y: Complex<f64> = (0..STATE_DIM).map(|i| x[i] * c[i]).sum();
                let p = y.norm_sqr();
                if p.is_finite() { Ok(p) } else { Err(singular) }
            })
            .collect()
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
