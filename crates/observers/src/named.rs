//! The ten named observers of the dissertation as compositions of a model and a law, and a
//! run-time entry point ([`build_observer`]) for the chapter pipelines.
//!
//! | kind | linear part | nonlinear family | home model |
//! |---|---|---|---|
//! | APIO (2.33–2.35, 3.9–3.10) | PI / Kalman, LMI 2.34 verified | – | ARX-Laguerre |
//! | ALPIO (4.16–4.17) | same as APIO | – | ARX-Laguerre |
//! | FLO (3.13–3.14) | Luenberger (same design) | – | physics |
//! | SMO (2.36–2.37 / 5.21–5.22) | yes | sign | physics / fuzzy ARX-Laguerre |
//! | VSO (3.15) | none | sign | physics |
//! | PFLO (3.16–3.21) | yes | super-twisting | physics |
//! | SMALPIO (4.18–4.19) | yes | super-twisting | ARX-Laguerre |
//! | HOSTSMO (2.38–2.45) | none | Levant | physics |
//! | ASMO (5.23–5.28) | yes | Levant | fuzzy ARX-Laguerre |
//! | AFSMO (5.29–5.32) | yes | Levant + fuzzy-scheduled integral | fuzzy ARX-Laguerre |
//!
//! Every kind can be built on every model (the laws act on the common three-level chain).

use crate::design::{BoundGains, LinearDesign, kalman_predictor_gain, max_decay_rate};
use crate::error::ObserverError;
use crate::law::{
    Correction, CorrectionLaw, FuzzyScheduleParams, FuzzyScheduled, HomogeneousLaw, LawFamily,
};
use crate::observer::{Observer, ObserverOutput, RunObserver};
use crate::predictor::{
    ArxLaguerrePredictor, FalPredictor, ModalParams, Predictor, SecondOrderPredictor, StateSpace,
};
use nalgebra::{DMatrix, DVector};

/// The observers the dissertation defines or compares against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ObserverKind {
    /// ARX-Laguerre PI observer (ch. 2–3).
    Apio,
    /// Sliding mode observer (2.36–2.37; 5.21–5.22).
    Smo,
    /// Higher-order super-twisting SMO (2.38–2.45).
    Hostsmo,
    /// Feedback linearization observer (3.13–3.14).
    Flo,
    /// Variable structure observer (3.15).
    Vso,
    /// Variable-structure feedback linearization observer (3.16–3.21).
    Pflo,
    /// ARX-Laguerre PI observer (ch. 4 name, 4.16–4.17).
    Alpio,
    /// Sliding-mode extended-state ARX-Laguerre PI observer (4.18–4.30).
    Smalpio,
    /// Advanced (higher-order super-twisting) SMO (5.23–5.28).
    Asmo,
    /// Advanced fuzzy SMO (5.29–5.32).
    Afsmo,
}

impl ObserverKind {
    /// All ten kinds.
    pub const ALL: [ObserverKind; 10] = [
        Self::Apio,
        Self::Smo,
        Self::Hostsmo,
        Self::Flo,
        Self::Vso,
        Self::Pflo,
        Self::Alpio,
        Self::Smalpio,
        Self::Asmo,
        Self::Afsmo,
    ];

    /// Short upper-case name as in the dissertation.
    pub fn name(self) -> &'static str {
        match self {
            Self::Apio => "APIO",
            Self::Smo => "SMO",
            Self::Hostsmo => "HOSTSMO",
            Self::Flo => "FLO",
            Self::Vso => "VSO",
            Self::Pflo => "PFLO",
            Self::Alpio => "ALPIO",
            Self::Smalpio => "SMALPIO",
            Self::Asmo => "ASMO",
            Self::Afsmo => "AFSMO",
        }
    }

    /// Whether the kind has a linear (PI / Luenberger) part.
    pub fn has_linear_part(self) -> bool {
        !matches!(self, Self::Vso | Self::Hostsmo)
    }

    /// The nonlinear family of the kind.
    pub fn family(self) -> LawFamily {
        match self {
            Self::Apio | Self::Alpio | Self::Flo => LawFamily::Linear,
            Self::Smo | Self::Vso => LawFamily::Sign,
            Self::Pflo | Self::Smalpio => LawFamily::SuperTwisting,
            Self::Hostsmo | Self::Asmo | Self::Afsmo => LawFamily::Levant,
        }
    }
}

impl std::str::FromStr for ObserverKind {
    type Err = ObserverError;
    /// Parse a dissertation name, case-insensitive ("hostsmo", "AFSMO", …).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s.trim()))
            .ok_or(ObserverError::UnknownKind { length: s.len() })
    }
}

impl std::fmt::Display for ObserverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The law of a named observer: a homogeneous law, optionally fuzzy-scheduled (AFSMO).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NamedLaw {
    /// Linear + homogeneous sliding-mode terms.
    Plain(HomogeneousLaw),
    /// With the T–S scheduled integral of eq. (5.29).
    Fuzzy(FuzzyScheduled<HomogeneousLaw>),
}

impl CorrectionLaw for NamedLaw {
    #[inline(always)]
    fn correct(&mut self, e: f64) -> Correction {
        match self {
            Self::Plain(l) => l.correct(e),
            Self::Fuzzy(l) => l.correct(e),
        }
    }
    fn reset(&mut self) {
        match self {
            Self::Plain(l) => l.reset(),
            Self::Fuzzy(l) => l.reset(),
        }
    }
}

/// Settings shared by all named observers.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ObserverSettings {
    /// Γ: per-sample bound of the perturbation entering the law's last chain level, in output
    /// units (H⁺ of eq. 2.44, J⁺ of 3.21, Γ of 5.28 expressed per sample; see
    /// [`crate::design::estimate_bound`] and the `per_sample_*` helpers).
    pub uncertainty_bound: f64,
    /// Weights of the linear design.
    pub linear: LinearDesign,
    /// Fuzzy scheduling for AFSMO; `None` derives it from the bound and the integral gain.
    pub fuzzy: Option<FuzzyScheduleParams>,
    /// Error scale E₀ (output units) of the first-order sliding laws' level-1 gain
    /// 1.5 (Γ·E₀)^½ ([`BoundGains::sign_scaled`]); 1 output unit by default.
    #[serde(default = "unit_error_scale")]
    pub error_scale: f64,
    /// AFSMO's thresholds (TH_n, TH_f) of eq. (5.29) on |r|, when `fuzzy` is not given; `None`
    /// keeps the bound-based defaults (3Γ, 30Γ). Thresholds from the healthy residual's spread
    /// (e.g. 3σ and 6σ) make the schedule read "normal" on a healthy record.
    #[serde(default)]
    pub fuzzy_thresholds: Option<[f64; 2]>,
}

fn unit_error_scale() -> f64 {
    1.0
}

impl ObserverSettings {
    /// Settings with the given bound and default linear design.
    pub fn new(uncertainty_bound: f64) -> Self {
        Self {
            uncertainty_bound,
            linear: LinearDesign::default(),
            fuzzy: None,
            error_scale: 1.0,
            fuzzy_thresholds: None,
        }
    }
}

/// Per-sample bound for Levant laws on a physics mode from |ḋ| ≤ H (units of X₁/s³): Γ = H T³.
pub fn per_sample_bound_levant(h: f64, dt: f64) -> f64 {
    h * dt * dt * dt
}

/// Per-sample bound for super-twisting / sign laws on a physics mode from |d − d̂| ≤ J
/// (units of X₁/s²): Γ = J T².
pub fn per_sample_bound_super_twisting(j: f64, dt: f64) -> f64 {
    j * dt * dt
}

fn nonlinear_gains(kind: ObserverKind, s: &ObserverSettings) -> Result<[f64; 3], ObserverError> {
    let bound = s.uncertainty_bound;
    match kind.family() {
        LawFamily::Linear => {
            if !(bound.is_finite() && bound > 0.0) {
                return Err(ObserverError::InvalidParameter {
                    name: "uncertainty_bound",
                    value: bound,
                    reason: "must be finite and > 0",
                });
            }
            Ok([0.0; 3])
        }
        LawFamily::Sign => BoundGains::sign_scaled(bound, s.error_scale),
        LawFamily::SuperTwisting => BoundGains::super_twisting(bound),
        LawFamily::Levant => BoundGains::levant(bound),
    }
}

fn make_law(
    kind: ObserverKind,
    linear: [f64; 3],
    integral_gain: f64,
    s: &ObserverSettings,
) -> Result<NamedLaw, ObserverError> {
    let nl = nonlinear_gains(kind, s)?;
    let lin = if kind.has_linear_part() {
        linear
    } else {
        [0.0; 3]
    };
    let base = HomogeneousLaw::new(lin, nl, kind.family())?;
    if kind == ObserverKind::Afsmo {
        let [threshold_normal, threshold_fault] = s
            .fuzzy_thresholds
            .unwrap_or([3.0 * s.uncertainty_bound, 30.0 * s.uncertainty_bound]);
        let p = s.fuzzy.unwrap_or(FuzzyScheduleParams {
            zeta_normal: 0.0,
            zeta_fault: integral_gain.max(0.0),
            threshold_normal,
            threshold_fault,
        });
        Ok(NamedLaw::Fuzzy(FuzzyScheduled::new(base, p)?))
    } else {
        Ok(NamedLaw::Plain(base))
    }
}

/// Report of a linear design.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearReport {
    /// Linear gains on the three chain levels (for ARX-Laguerre: `[0, K_I, 0]`).
    pub law_gains: [f64; 3],
    /// K_p (ARX-Laguerre) or empty (physics).
    pub kp: Vec<f64>,
    /// Largest γ for which the LMI (2.34) holds for the closed-loop error matrix.
    pub decay_rate: f64,
}

/// Linear design for a physics mode: Kalman gain on the augmented per-sample chain
/// (z₁, z₂, z₃), verified with the LMI (2.34).
pub fn design_physics_linear(
    p: &SecondOrderPredictor,
    d: &LinearDesign,
) -> Result<LinearReport, ObserverError> {
    d.validate()?;
    let a = p.chain_matrix();
    let a = DMatrix::from_row_slice(3, 3, &a);
    let c = DVector::from_vec(vec![1.0, 0.0, 0.0]);
    let q = DVector::from_vec(vec![d.state_weight, d.state_weight, d.fault_weight]);
    let l = kalman_predictor_gain(&a, &c, &q)?;
    let a_cl = &a - &l * c.transpose();
    let decay_rate = max_decay_rate(&a_cl).ok_or(ObserverError::LmiNotSatisfied { gamma: 0.0 })?;
    Ok(LinearReport {
        law_gains: [l[0], l[1], l[2]],
        kp: Vec::new(),
        decay_rate,
    })
}

/// Linear (APIO) design for an ARX-Laguerre model: Kalman gain for
/// A_γ = [[A + b_y Kᵀ, f], [0, 1]], C = [Kᵀ, 0] (eq. 2.34 with the fault entering along f),
/// giving K_p and K_I; the LMI (2.34) is verified and its largest decay rate reported.
pub fn design_arx_linear(
    model: &StateSpace,
    fault_direction: &[f64],
    d: &LinearDesign,
) -> Result<LinearReport, ObserverError> {
    d.validate()?;
    model.validate()?;
    let n = model.order();
    // Normalise f as the predictor does.
    let probe = ArxLaguerrePredictor::new(model, fault_direction, &vec![0.0; n])?;
    let f = probe.fault_direction();
    let acl = model.closed_loop_matrix();
    let mut a = DMatrix::zeros(n + 1, n + 1);
    for i in 0..n {
        for j in 0..n {
            a[(i, j)] = acl[i * n + j];
        }
        a[(i, n)] = f[i];
    }
    a[(n, n)] = 1.0;
    let mut c = DVector::zeros(n + 1);
    for i in 0..n {
        c[i] = model.k[i];
    }
    let mut q = DVector::from_element(n + 1, d.state_weight);
    q[n] = d.fault_weight;
    let l = kalman_predictor_gain(&a, &c, &q)?;
    let a_cl = &a - &l * c.transpose();
    let decay_rate = max_decay_rate(&a_cl).ok_or(ObserverError::LmiNotSatisfied { gamma: 0.0 })?;
    Ok(LinearReport {
        law_gains: [0.0, l[n], 0.0],
        kp: l.iter().take(n).copied().collect(),
        decay_rate,
    })
}

/// The innovations design of an ARX-Laguerre or path model: K_p = b_y, which makes the
/// observer's model part the identified one-step predictor itself (A + b_y Kᵀ − K_p Kᵀ = A: the
/// prediction error of the model part decays as the model's own filters, deadbeat in n samples
/// for a shift-form path), and the integral gain K_I of the scalar steady-state Kalman filter of
/// the fault random walk seen through a unit-variance innovation, K_I = P/(P + 1),
/// P = (q_d + √(q_d² + 4 q_d))/2 with q_d = `fault_weight` (eq. 2.34's design reduced to the one
/// state left once the model part is the predictor; the LMI (2.34) then holds for any
/// γ < (1 − (1 − K_I)²)/2, reported as the decay rate). No Riccati iteration on the n + 1
/// states, which matters for paths of a hundred states.
pub fn design_innovations(
    model: &StateSpace,
    d: &LinearDesign,
) -> Result<LinearReport, ObserverError> {
    d.validate()?;
    model.validate()?;
    let q = d.fault_weight;
    let p = 0.5 * (q + (q * q + 4.0 * q).sqrt());
    let ki = p / (p + 1.0);
    let rho = (1.0 - ki).abs();
    Ok(LinearReport {
        law_gains: [0.0, ki, 0.0],
        kp: model.b_y.clone(),
        decay_rate: 0.5 * (1.0 - rho * rho),
    })
}

/// Linear design for a shift-form (AR) path model ([`StateSpace::from_ar`]): always the
/// innovations design ([`design_innovations`]; `d.innovations` is implied).
pub fn design_path_linear(
    model: &StateSpace,
    d: &LinearDesign,
) -> Result<LinearReport, ObserverError> {
    if !model.is_shift_form() {
        return Err(ObserverError::InvalidParameter {
            name: "model",
            value: model.order() as f64,
            reason: "not in shift (AR) form",
        });
    }
    design_innovations(model, d)
}

/// Build any kind on a shift-form (AR) path model — the calibrated structural path of a
/// machine model — with the gains of [`design_path_linear`] and the law of `kind`; the fault
/// estimate d̂ adds to the prediction directly ([`ArxLaguerrePredictor::new_path`]).
pub fn path_observer(
    kind: ObserverKind,
    model: &StateSpace,
    s: &ObserverSettings,
) -> Result<ArxObserver, ObserverError> {
    let rep = design_path_linear(model, &s.linear)?;
    let p = ArxLaguerrePredictor::new_path(model, &rep.kp)?;
    let law = make_law(kind, rep.law_gains, rep.law_gains[1], s)?;
    Ok(Observer::new(p, law))
}

/// A physics-model observer (ch. 2–3).
pub type PhysicsObserver = Observer<SecondOrderPredictor, NamedLaw>;
/// An ARX-Laguerre observer (ch. 4; ch. 5 with the fuzzy term handled by the model).
pub type ArxObserver = Observer<ArxLaguerrePredictor, NamedLaw>;

/// A fuzzy ARX-Laguerre observer (ch. 5).
pub type FalObserver = Observer<FalPredictor, NamedLaw>;

/// Build any kind on a fuzzy ARX-Laguerre model (eq. 5.19); the linear gains are designed on
/// its ARX-Laguerre part.
pub fn fal_observer(
    kind: ObserverKind,
    model: &fuzzy_ts::FuzzyArxLaguerre,
    fault: &FaultDirection,
    s: &ObserverSettings,
) -> Result<FalObserver, ObserverError> {
    let base = FalPredictor::base_model(model)?;
    let arx = arx_observer(kind, &base, fault, s)?;
    let law = *arx.law();
    let p = FalPredictor::new(arx.predictor().clone(), *model);
    Ok(Observer::new(p, law))
}

/// Build any kind on a physics mode.
pub fn physics_observer(
    kind: ObserverKind,
    mode: ModalParams,
    s: &ObserverSettings,
) -> Result<PhysicsObserver, ObserverError> {
    let p = SecondOrderPredictor::new(mode)?;
    let lin = if kind.has_linear_part() {
        design_physics_linear(&p, &s.linear)?.law_gains
    } else {
        [0.0; 3]
    };
    let law = make_law(kind, lin, lin[2], s)?;
    Ok(Observer::new(p, law))
}

/// Where the fault enters an ARX-Laguerre model.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum FaultDirection {
    /// Along b_u (eq. 2.34's A_γ); falls back to b_y when b_u is zero.
    Input,
    /// Along b_y (an additive output disturbance filtered like the output).
    OutputFilter,
    /// A given vector.
    Custom(Vec<f64>),
}

impl FaultDirection {
    /// The direction vector for `model`.
    pub fn vector(&self, model: &StateSpace) -> Vec<f64> {
        match self {
            Self::Input if model.b_u.iter().any(|v| *v != 0.0) => model.b_u.clone(),
            Self::Input | Self::OutputFilter => model.b_y.clone(),
            Self::Custom(v) => v.clone(),
        }
    }
}

/// Build any kind on an ARX-Laguerre model. The proportional injection K_p is always present
/// (it is what keeps the parallel model A + b_y Kᵀ stable); kinds without a linear part
/// (VSO, HOSTSMO) drop the integral gain K_I.
pub fn arx_observer(
    kind: ObserverKind,
    model: &StateSpace,
    fault: &FaultDirection,
    s: &ObserverSettings,
) -> Result<ArxObserver, ObserverError> {
    let f = fault.vector(model);
    let rep = if s.linear.innovations {
        design_innovations(model, &s.linear)?
    } else {
        design_arx_linear(model, &f, &s.linear)?
    };
    let p = if s.linear.innovations {
        ArxLaguerrePredictor::new_innovations(model, &rep.kp)?
    } else {
        ArxLaguerrePredictor::new(model, &f, &rep.kp)?
    };
    let law = make_law(kind, rep.law_gains, rep.law_gains[1], s)?;
    Ok(Observer::new(p, law))
}

impl PhysicsObserver {
    /// SMO, eqs (2.36)–(2.37).
    pub fn smo(mode: ModalParams, s: &ObserverSettings) -> Result<Self, ObserverError> {
        physics_observer(ObserverKind::Smo, mode, s)
    }
    /// HOSTSMO, eqs (2.38)–(2.45).
    pub fn hostsmo(mode: ModalParams, s: &ObserverSettings) -> Result<Self, ObserverError> {
        physics_observer(ObserverKind::Hostsmo, mode, s)
    }
    /// FLO, eqs (3.13)–(3.14).
    pub fn flo(mode: ModalParams, s: &ObserverSettings) -> Result<Self, ObserverError> {
        physics_observer(ObserverKind::Flo, mode, s)
    }
    /// VSO, eq. (3.15).
    pub fn vso(mode: ModalParams, s: &ObserverSettings) -> Result<Self, ObserverError> {
        physics_observer(ObserverKind::Vso, mode, s)
    }
    /// PFLO, eqs (3.16)–(3.21).
    pub fn pflo(mode: ModalParams, s: &ObserverSettings) -> Result<Self, ObserverError> {
        physics_observer(ObserverKind::Pflo, mode, s)
    }
}

impl ArxObserver {
    /// APIO, eqs (2.33)–(2.35), (3.9)–(3.10).
    pub fn apio(
        model: &StateSpace,
        f: &FaultDirection,
        s: &ObserverSettings,
    ) -> Result<Self, ObserverError> {
        arx_observer(ObserverKind::Apio, model, f, s)
    }
    /// ALPIO, eqs (4.16)–(4.17).
    pub fn alpio(
        model: &StateSpace,
        f: &FaultDirection,
        s: &ObserverSettings,
    ) -> Result<Self, ObserverError> {
        arx_observer(ObserverKind::Alpio, model, f, s)
    }
    /// SMALPIO, eqs (4.18)–(4.19).
    pub fn smalpio(
        model: &StateSpace,
        f: &FaultDirection,
        s: &ObserverSettings,
    ) -> Result<Self, ObserverError> {
        arx_observer(ObserverKind::Smalpio, model, f, s)
    }
    /// ASMO, eqs (5.25)–(5.28).
    pub fn asmo(
        model: &StateSpace,
        f: &FaultDirection,
        s: &ObserverSettings,
    ) -> Result<Self, ObserverError> {
        arx_observer(ObserverKind::Asmo, model, f, s)
    }
    /// AFSMO, eqs (5.29)–(5.32).
    pub fn afsmo(
        model: &StateSpace,
        f: &FaultDirection,
        s: &ObserverSettings,
    ) -> Result<Self, ObserverError> {
        arx_observer(ObserverKind::Afsmo, model, f, s)
    }
}

/// The model an observer runs on.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ModelConfig {
    /// A physics mode of the measured channel (from the 5-DOF model, or given).
    Physics(ModalParams),
    /// An ARX-Laguerre model and where the fault enters.
    ArxLaguerre {
        /// The model.
        model: StateSpace,
        /// Fault direction.
        fault: FaultDirection,
    },
    /// The calibrated structural path of a machine model as a shift-form (AR) predictor
    /// ([`StateSpace::from_ar`]; built by [`path_observer`]).
    CalibratedPath(StateSpace),
    /// A fuzzy ARX-Laguerre model (`fuzzy-ts`) and where the fault enters.
    FuzzyArxLaguerre {
        /// The model.
        model: Box<fuzzy_ts::FuzzyArxLaguerre>,
        /// Fault direction.
        fault: FaultDirection,
    },
}

/// A built observer of any kind on any model, with `.run(&y)`.
#[derive(Debug, Clone)]
pub enum AnyObserver {
    /// On a physics mode.
    Physics(PhysicsObserver),
    /// On an ARX-Laguerre model.
    Arx(ArxObserver),
    /// On a fuzzy ARX-Laguerre model.
    Fal(Box<FalObserver>),
}

impl AnyObserver {
    /// Run over a record without input (see [`Observer::run`]).
    pub fn run(&mut self, y: &[f64]) -> Result<ObserverOutput, ObserverError> {
        RunObserver::run(self, y, None)
    }

    /// Current fault estimate.
    pub fn fault_estimate(&self) -> f64 {
        match self {
            Self::Physics(o) => o.predictor().fault_estimate(),
            Self::Arx(o) => o.predictor().fault_estimate(),
            Self::Fal(o) => o.predictor().fault_estimate(),
        }
    }
}

impl RunObserver for AnyObserver {
    fn run(&mut self, y: &[f64], u: Option<&[f64]>) -> Result<ObserverOutput, ObserverError> {
        match self {
            Self::Physics(o) => o.run(y, u),
            Self::Arx(o) => o.run(y, u),
            Self::Fal(o) => o.run(y, u),
        }
    }
    fn run_into(
        &mut self,
        y: &[f64],
        u: Option<&[f64]>,
        out: &mut ObserverOutput,
    ) -> Result<(), ObserverError> {
        match self {
            Self::Physics(o) => o.run_into(y, u, out),
            Self::Arx(o) => o.run_into(y, u, out),
            Self::Fal(o) => o.run_into(y, u, out),
        }
    }
    fn reset(&mut self) {
        match self {
            Self::Physics(o) => o.reset(),
            Self::Arx(o) => o.reset(),
            Self::Fal(o) => o.reset(),
        }
    }
}

/// Build observer `kind` on `model` with `settings` (the pipelines' entry point).
pub fn build_observer(
    kind: ObserverKind,
    model: &ModelConfig,
    settings: &ObserverSettings,
) -> Result<AnyObserver, ObserverError> {
    Ok(match model {
        ModelConfig::Physics(m) => AnyObserver::Physics(physics_observer(kind, *m, settings)?),
        ModelConfig::ArxLaguerre { model, fault } => {
            AnyObserver::Arx(arx_observer(kind, model, fault, settings)?)
        }
        ModelConfig::CalibratedPath(model) => {
            AnyObserver::Arx(path_observer(kind, model, settings)?)
        }
        ModelConfig::FuzzyArxLaguerre { model, fault } => {
            AnyObserver::Fal(Box::new(fal_observer(kind, model, fault, settings)?))
        }
    })
}
