//! The ARX-Laguerre predictor with the observer chain: the O(n) Laguerre cascade, the O(n)
//! shift update of AR-form paths, and the dense O(n²) reference.

use super::Predictor;
use super::{LaguerreStructure, StateSpace};
use crate::error::ObserverError;
use crate::law::Correction;

/// Fixed-size vectors of the O(n) Laguerre path (n ≤ `laguerre_id::MAX_STATES`, no heap).
type Fixed = [f64; laguerre_id::MAX_STATES];

/// The O(n) update of a model with [`LaguerreStructure`]: the two bank cascades fused with the
/// injection K_p e + f s and the output Kᵀ X̂(k+1).
#[derive(Debug, Clone, PartialEq)]
struct CascadeKernel {
    s: LaguerreStructure,
    gain_a: f64,
    gain_b: f64,
    /// AᵀK, so that Kᵀ X̂(k+1) = wᵀX̂(k) + β Ŷ(k) + γ u + κ e + (Kᵀf) s.
    w: Fixed,
    /// (Kᵀb_y, Kᵀb_u, KᵀK_p, Kᵀf).
    kb: [f64; 4],
    k: Fixed,
    kp: Fixed,
    f: Fixed,
    x: Fixed,
    x0: Fixed,
}

/// One bank: x ← A_bank x + b_bank drive (cascade) + kp e + f s.
///
/// The cascade runs on the model part alone (`pure`): xᵢ(k+1) − injectionᵢ =
/// ζ xᵢ(k) + xᵢ₋₁(k) − ζ (xᵢ₋₁(k+1) − injectionᵢ₋₁), an identity of the block matrix that holds
/// for any X̂(k).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn cascade_bank(z: f64, g: f64, drive: f64, e: f64, s: f64, x: &mut [f64], kp: &[f64], f: &[f64]) {
    let (Some((x0, xr)), Some((kp0, kpr)), Some((f0, fr))) =
        (x.split_first_mut(), kp.split_first(), f.split_first())
    else {
        return;
    };
    let mut prev_old = *x0;
    let mut prev_pure = z * prev_old + g * drive;
    *x0 = prev_pure + kp0 * e + f0 * s;
    for ((xi, kpi), fi) in xr.iter_mut().zip(kpr).zip(fr) {
        let old = *xi;
        let pure = z * old + prev_old - z * prev_pure;
        prev_old = old;
        prev_pure = pure;
        *xi = pure + kpi * e + fi * s;
    }
}

/// wᵀx over the first `chunks` groups of four of the fixed-size arrays, with four partial sums
/// (the padding past the model's states is zero, so the sum is the same for any `chunks` that
/// covers them).
#[inline(always)]
fn dot_fixed(w: &Fixed, x: &Fixed, chunks: usize) -> f64 {
    let mut acc = [0.0; 4];
    for (wc, xc) in w.chunks_exact(4).zip(x.chunks_exact(4)).take(chunks) {
        for i in 0..4 {
            acc[i] += wc[i] * xc[i];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

impl CascadeKernel {
    /// Advance X̂ and return Ŷ(k+1) = Kᵀ X̂(k+1), computed from X̂(k) through w = AᵀK so that the
    /// output does not wait for the cascade (the two dependency chains run in parallel).
    #[inline(always)]
    fn advance(&mut self, y_hat: f64, u: f64, e: f64, s: f64) -> f64 {
        let [kby, kbu, kkp, kf] = self.kb;
        let na = self.s.n_a;
        let n = na + self.s.n_b;
        let y_next = dot_fixed(&self.w, &self.x, n.div_ceil(4))
            + (kby * y_hat + kbu * u)
            + (kkp * e + kf * s);
        let (xa, xb) = self.x[..n].split_at_mut(na);
        let (kpa, kpb) = self.kp[..n].split_at(na);
        let (fa, fb) = self.f[..n].split_at(na);
        cascade_bank(self.s.zeta_a, self.gain_a, y_hat, e, s, xa, kpa, fa);
        cascade_bank(self.s.zeta_b, self.gain_b, u, e, s, xb, kpb, fb);
        y_next
    }
}

/// The general O(n²) update X̂(k+1) = A X̂ + b_y Ŷ + b_u u + K_p e + f s.
#[derive(Debug, Clone, PartialEq)]
struct DenseKernel {
    a: Vec<f64>,
    b_y: Vec<f64>,
    b_u: Vec<f64>,
    k: Vec<f64>,
    kp: Vec<f64>,
    f: Vec<f64>,
    /// 1 when the fault enters the output directly (f is then zero), else 0.
    s_out: f64,
    x: Vec<f64>,
    x0: Vec<f64>,
    tmp: Vec<f64>,
}

impl DenseKernel {
    #[inline(always)]
    fn advance(&mut self, y_hat: f64, u: f64, e: f64, s: f64) -> f64 {
        let n = self.k.len();
        let mut y_next = 0.0;
        for i in 0..n {
            let row = &self.a[i * n..(i + 1) * n];
            let v = dot(row, &self.x)
                + self.b_y[i] * y_hat
                + self.b_u[i] * u
                + self.kp[i] * e
                + self.f[i] * s;
            self.tmp[i] = v;
            y_next += self.k[i] * v;
        }
        std::mem::swap(&mut self.x, &mut self.tmp);
        y_next + self.s_out * s
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Kernel {
    // Boxed: the fixed-size arrays are ~850 bytes and would bloat every observer enum.
    Cascade(Box<CascadeKernel>),
    Dense(Box<DenseKernel>),
    Shift(Box<ShiftKernel>),
}

/// The O(n) update of a model in shift (AR) form ([`StateSpace::is_shift_form`]):
/// X̂(k+1) = S X̂(k) + e₁ Ŷ(k) + K_p e with S the down-shift (A X̂ is a copy), and the fault
/// entering the output directly: Ŷ(k+1) = Kᵀ X̂(k+1) + s. The state holds the (corrected)
/// output history, so an injection is not fed back as if it had been measured; a unit d̂ moves
/// the next prediction by one unit, as on the other models.
#[derive(Debug, Clone, PartialEq)]
struct ShiftKernel {
    k: Vec<f64>,
    kp: Vec<f64>,
    /// Zeros: the fault does not enter the state (see above).
    f: Vec<f64>,
    x: Vec<f64>,
    x0: Vec<f64>,
    /// K_p is zero past its first entry (the innovations design).
    first_only: bool,
}

impl ShiftKernel {
    #[inline(always)]
    fn advance(&mut self, y_hat: f64, e: f64, s: f64) -> f64 {
        let n = self.x.len();
        self.x.copy_within(0..n - 1, 1);
        self.x[0] = y_hat;
        if self.first_only {
            self.x[0] += self.kp[0] * e;
        } else {
            for (xi, kpi) in self.x.iter_mut().zip(&self.kp) {
                *xi += kpi * e;
            }
        }
        dot(&self.k, &self.x) + s
    }
}

/// The ARX-Laguerre observer's predictor (eqs 2.33, 3.9, 4.16, 4.18, 5.21):
///
/// X̂(k+1) = A X̂(k) + b_y Ŷ(k) + b_u u(k) + K_p e(k) + f (d̂(k) + c₁),
/// d̂(k+1) = d̂(k) + c₂ + χ̂(k), χ̂(k+1) = χ̂(k) + c₃, Ŷ(k) = Kᵀ X̂(k),
///
/// with the fault direction f normalised to Kᵀ f = 1 (so d̂ is in output units: a unit d̂ moves
/// the next prediction by one unit).
///
/// Models with the Laguerre structure ([`StateSpace::laguerre_structure`]: every
/// `from_poles` model and every `laguerre-id` model up to `laguerre_id::MAX_STATES` states)
/// run the O(n) bank cascade on fixed-size arrays; any other A runs the dense O(n²) product.
/// The two paths agree to rounding ([`ArxLaguerrePredictor::new_dense`] forces the dense one).
#[derive(Debug, Clone, PartialEq)]
pub struct ArxLaguerrePredictor {
    n: usize,
    kernel: Kernel,
    d: f64,
    chi: f64,
    y_hat: f64,
    /// Whether d̂ and c₁ add to the prediction directly (innovations and path predictors)
    /// instead of entering the state along f.
    output_fault: bool,
    /// The injection d̂ + c₁ added to the current ŷ when `output_fault` (else 0).
    s_out: f64,
}

impl ArxLaguerrePredictor {
    /// Build from a model, the fault direction (normalised here so that Kᵀf = 1) and the
    /// proportional output-injection vector K_p. Uses the O(n) Laguerre cascade when the model
    /// has the Laguerre structure, the dense product otherwise.
    pub fn new(
        model: &StateSpace,
        fault_direction: &[f64],
        kp: &[f64],
    ) -> Result<Self, ObserverError> {
        Self::build(model, fault_direction, kp, true, false)
    }

    /// The predictor of the innovations design (K_p = b_y, [`crate::design_innovations`]) of
    /// an ARX-Laguerre model: its state is then the Laguerre filter bank of the *measured*
    /// output (b_y Ŷ + K_p e = b_y y), exact, so there is no state error for the fault to
    /// correct; the fault estimate d̂ and the law's level-1 injection add to the next
    /// prediction directly, Ŷ(k+1) = Kᵀ X̂(k+1) + d̂ + c₁, instead of entering the state as if
    /// they had been measured (where the model's filters would carry every past injection into
    /// later predictions and a sign law would fight its own history). As the shift-form path
    /// predictor ([`ArxLaguerrePredictor::new_path`]) does; `fault_direction` is then zero.
    ///
    /// # Errors
    /// As [`ArxLaguerrePredictor::new`], and [`ObserverError::InvalidParameter`] when K_p is
    /// not b_y.
    pub fn new_innovations(model: &StateSpace, kp: &[f64]) -> Result<Self, ObserverError> {
        if kp != model.b_y.as_slice() {
            return Err(ObserverError::InvalidParameter {
                name: "K_p",
                value: kp.first().copied().unwrap_or(f64::NAN),
                reason: "the innovations predictor needs K_p = b_y",
            });
        }
        Self::build(model, &model.b_y, kp, true, true)
    }

    /// The predictor of a shift-form (AR) model ([`StateSpace::from_ar`]) with the
    /// proportional injection K_p, run by an O(n) shift update; the fault d̂ (and the law's
    /// level-1 injection) adds to the next prediction directly instead of entering the state,
    /// so [`ArxLaguerrePredictor::fault_direction`] is zero.
    ///
    /// # Errors
    /// [`ObserverError::InvalidParameter`] when the model is not in shift form or K_p is not
    /// finite; [`ObserverError::DimensionMismatch`] when K_p has another length.
    pub fn new_path(model: &StateSpace, kp: &[f64]) -> Result<Self, ObserverError> {
        model.validate()?;
        if !model.is_shift_form() {
            return Err(ObserverError::InvalidParameter {
                name: "model",
                value: model.order() as f64,
                reason: "not in shift (AR) form: build it with StateSpace::from_ar",
            });
        }
        let n = model.order();
        if kp.len() != n {
            return Err(ObserverError::DimensionMismatch {
                expected: n,
                found: kp.len(),
            });
        }
        if let Some(v) = kp.iter().find(|v| !v.is_finite()) {
            return Err(ObserverError::InvalidParameter {
                name: "K_p",
                value: *v,
                reason: "must be finite",
            });
        }
        Ok(Self {
            n,
            kernel: Kernel::Shift(Box::new(ShiftKernel {
                k: model.k.clone(),
                kp: kp.to_vec(),
                f: vec![0.0; n],
                x: vec![0.0; n],
                x0: vec![0.0; n],
                first_only: kp[1..].iter().all(|v| *v == 0.0),
            })),
            d: 0.0,
            chi: 0.0,
            y_hat: 0.0,
            output_fault: true,
            s_out: 0.0,
        })
    }

    /// As [`ArxLaguerrePredictor::new`] but always with the dense O(n²) update (the reference
    /// path; results agree with the cascade to rounding).
    pub fn new_dense(
        model: &StateSpace,
        fault_direction: &[f64],
        kp: &[f64],
    ) -> Result<Self, ObserverError> {
        Self::build(model, fault_direction, kp, false, false)
    }

    fn build(
        model: &StateSpace,
        fault_direction: &[f64],
        kp: &[f64],
        allow_cascade: bool,
        output_fault: bool,
    ) -> Result<Self, ObserverError> {
        model.validate()?;
        let n = model.order();
        for len in [fault_direction.len(), kp.len()] {
            if len != n {
                return Err(ObserverError::DimensionMismatch {
                    expected: n,
                    found: len,
                });
            }
        }
        let kf: f64 = model
            .k
            .iter()
            .zip(fault_direction)
            .map(|(a, b)| a * b)
            .sum();
        let fnorm: f64 = fault_direction.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !output_fault && (!kf.is_finite() || kf.abs() <= 1e-9 * fnorm.max(1e-300)) {
            return Err(ObserverError::FaultDirectionInvisible { value: kf.abs() });
        }
        if let Some(v) = kp.iter().find(|v| !v.is_finite()) {
            return Err(ObserverError::InvalidParameter {
                name: "K_p",
                value: *v,
                reason: "must be finite",
            });
        }
        // normalised so that Kᵀf = 1; zero when the fault enters the output directly
        let f: Vec<f64> = if output_fault {
            vec![0.0; n]
        } else {
            fault_direction.iter().map(|v| v / kf).collect()
        };
        let s_out = if output_fault { 1.0 } else { 0.0 };
        let structure = if allow_cascade {
            model.laguerre_structure()
        } else {
            None
        };
        let kernel = match structure {
            Some(s) => {
                let fixed = |v: &[f64]| {
                    let mut a: Fixed = [0.0; laguerre_id::MAX_STATES];
                    a[..n].copy_from_slice(v);
                    a
                };
                let mut w: Fixed = [0.0; laguerre_id::MAX_STATES];
                for (i, ki) in model.k.iter().enumerate() {
                    for (j, wj) in w[..n].iter_mut().enumerate() {
                        *wj += model.a[i * n + j] * ki;
                    }
                }
                Kernel::Cascade(Box::new(CascadeKernel {
                    s,
                    gain_a: (1.0 - s.zeta_a * s.zeta_a).sqrt(),
                    gain_b: (1.0 - s.zeta_b * s.zeta_b).sqrt(),
                    w,
                    kb: [
                        dot(&model.k, &model.b_y),
                        dot(&model.k, &model.b_u),
                        dot(&model.k, kp),
                        dot(&model.k, &f) + s_out,
                    ],
                    k: fixed(&model.k),
                    kp: fixed(kp),
                    f: fixed(&f),
                    x: [0.0; laguerre_id::MAX_STATES],
                    x0: [0.0; laguerre_id::MAX_STATES],
                }))
            }
            None => Kernel::Dense(Box::new(DenseKernel {
                a: model.a.clone(),
                b_y: model.b_y.clone(),
                b_u: model.b_u.clone(),
                k: model.k.clone(),
                kp: kp.to_vec(),
                f,
                s_out,
                x: vec![0.0; n],
                x0: vec![0.0; n],
                tmp: vec![0.0; n],
            })),
        };
        Ok(Self {
            n,
            kernel,
            d: 0.0,
            chi: 0.0,
            y_hat: 0.0,
            output_fault,
            s_out: 0.0,
        })
    }

    /// Whether the O(n) Laguerre cascade is in use (else the dense O(n²) product).
    pub fn uses_laguerre_cascade(&self) -> bool {
        matches!(self.kernel, Kernel::Cascade(_))
    }

    /// Whether the O(n) shift (AR-form) update is in use.
    pub fn uses_shift_form(&self) -> bool {
        matches!(self.kernel, Kernel::Shift(_))
    }

    fn parts(&self) -> (&[f64], &[f64], &[f64], &[f64]) {
        let n = self.n;
        match &self.kernel {
            Kernel::Cascade(c) => (&c.k[..n], &c.f[..n], &c.x[..n], &c.x0[..n]),
            Kernel::Dense(d) => (&d.k, &d.f, &d.x, &d.x0),
            Kernel::Shift(d) => (&d.k, &d.f, &d.x, &d.x0),
        }
    }

    fn state_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        let n = self.n;
        match &mut self.kernel {
            Kernel::Cascade(c) => (&mut c.x[..n], &mut c.x0[..n]),
            Kernel::Dense(d) => (&mut d.x[..], &mut d.x0[..]),
            Kernel::Shift(d) => (&mut d.x[..], &mut d.x0[..]),
        }
    }

    /// Set the initial state estimate (length n; also what [`Predictor::reset`] returns to);
    /// keeps d̂ and χ̂.
    pub fn set_state(&mut self, x: &[f64]) -> Result<(), ObserverError> {
        if x.len() != self.n {
            return Err(ObserverError::DimensionMismatch {
                expected: self.n,
                found: x.len(),
            });
        }
        let (cur, init) = self.state_mut();
        cur.copy_from_slice(x);
        init.copy_from_slice(x);
        let (k, _, xs, _) = self.parts();
        self.y_hat = dot(k, xs);
        self.s_out = 0.0;
        Ok(())
    }

    /// The normalised fault direction f (Kᵀ f = 1).
    pub fn fault_direction(&self) -> &[f64] {
        self.parts().1
    }

    /// Current state estimate.
    pub fn state(&self) -> &[f64] {
        self.parts().2
    }

    /// Whether the fault estimate and the level-1 injection add to the prediction directly
    /// (the innovations predictor [`ArxLaguerrePredictor::new_innovations`] and the path
    /// predictor [`ArxLaguerrePredictor::new_path`]) rather than entering the state along f.
    pub fn fault_enters_output(&self) -> bool {
        self.output_fault
    }

    /// The model part of ŷ(k): KᵀX̂(k), without the injection d̂ + c₁ that an output-fault
    /// predictor ([`ArxLaguerrePredictor::fault_enters_output`]) adds to it; for a state-injection
    /// predictor, ŷ(k) itself. Under the innovations design this is the identified model's own
    /// one-step prediction from the measured output.
    pub fn model_output(&self) -> f64 {
        self.y_hat - self.s_out
    }
}

#[inline(always)]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Predictor for ArxLaguerrePredictor {
    #[inline(always)]
    fn output(&self) -> f64 {
        self.y_hat
    }
    #[inline(always)]
    fn advance(&mut self, _y: f64, u: f64, e: f64, c: Correction) {
        let s = self.d + c.c1;
        let yh = self.y_hat;
        self.y_hat = match &mut self.kernel {
            Kernel::Cascade(k) => k.advance(yh, u, e, s),
            Kernel::Dense(k) => k.advance(yh, u, e, s),
            Kernel::Shift(k) => k.advance(yh, e, s),
        };
        if self.output_fault {
            self.s_out = s;
        }
        self.d += c.c2 + self.chi;
        self.chi += c.c3;
    }
    #[inline(always)]
    fn fault_estimate(&self) -> f64 {
        self.d
    }
    #[inline(always)]
    fn equivalent_fault(&self, c: &Correction) -> f64 {
        c.c1
    }
    #[inline(always)]
    fn magnitude(&self) -> f64 {
        self.y_hat.abs().max(self.d.abs()).max(self.chi.abs())
    }
    fn reset(&mut self) {
        let (cur, init) = self.state_mut();
        cur.copy_from_slice(init);
        self.d = 0.0;
        self.chi = 0.0;
        self.s_out = 0.0;
        let (k, _, xs, _) = self.parts();
        self.y_hat = dot(k, xs);
    }
    fn order(&self) -> usize {
        self.n
    }
}
