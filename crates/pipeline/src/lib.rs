//! The dissertation's method as a library — what `cargo xtask chapter2..5` schedules: a
//! [`Method`] (model × observer) prepared on a healthy fit segment ([`Prepared`]: ARX-Laguerre
//! with N_a chosen by held-out error, fuzzy ARX-Laguerre, and the machine model `close-loop`
//! calibrates, whose structural path the physics observers run on), its gains set from the bound
//! measured on that segment ([`Prepared::tune`]), its residual over a recording ([`residual`]),
//! window energies ([`window_energies`]), each cell of a table as a `classify` dataset with its
//! windows' metadata, split by `classify`'s protocols and scored ([`cell_dataset`],
//! [`cell_plan`], [`evaluate_cell`]), the chapter-5 rules ([`tree_rules`]) and the simulated recordings of the no-data fallback and the multi-fault
//! substitute ([`simulate`]).
//!
//! Every function returns [`PipelineError`] (one line naming the stage), never panics on data.
//! Dependencies and why: the algorithm crates it composes (`bearing-model`, `laguerre-id`,
//! `fuzzy-ts`, `observers`, `residual-features`, `classify`, `close-loop`), and `thiserror` for
//! the error enum. Decisions: `docs/equations/xtask-chapters.md`, "Observers and models".

pub mod cells;
pub mod dissertation;
mod error;
pub mod evaluate;
pub mod recordings;
pub mod rig_records;
pub use error::PipelineError;
pub use evaluate::{
    CellOutcome, CellRecording, Dataset, Protocol, TEST_FRACTION, cell_dataset, cell_plan,
    evaluate_cell,
};

/// `Result` with [`PipelineError`].
pub type Result<T> = std::result::Result<T, PipelineError>;

/// An observer of the dissertation, as a column of its tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Method {
    /// Higher-order super-twisting SMO on the 5-DOF model (ch. 2, eqs 2.38–2.45).
    Hostsmo,
    /// Sliding mode observer on the 5-DOF model (ch. 2, eqs 2.36–2.37).
    Smo,
    /// ARX-Laguerre PI observer (eqs 2.33–2.35, 4.16–4.17).
    Apio,
    /// Variable-structure extended feedback-linearization observer (ch. 3, eqs 3.16–3.21).
    Pflo,
    /// Feedback-linearization observer (ch. 3, eqs 3.13–3.14).
    Flo,
    /// Sliding-mode extended-state ARX-Laguerre PI observer (ch. 4, eqs 4.18–4.30).
    Smalpio,
    /// Advanced fuzzy SMO on fuzzy ARX-Laguerre (ch. 5, eqs 5.29–5.32).
    Afsmo,
    /// Advanced (higher-order) SMO on fuzzy ARX-Laguerre (ch. 5, eqs 5.23–5.28).
    Asmo,
    /// SMO on fuzzy ARX-Laguerre (ch. 5, eqs 5.21–5.22).
    SmoFuzzy,
}

impl Method {
    /// Column name as in the dissertation.
    pub fn name(self) -> &'static str {
        match self {
            Method::Hostsmo => "HOSTSMO",
            Method::Smo | Method::SmoFuzzy => "SMO",
            Method::Apio => "APIO",
            Method::Pflo => "PFLO",
            Method::Flo => "FLO",
            Method::Smalpio => "SMALPIO",
            Method::Afsmo => "AFSMO",
            Method::Asmo => "ASMO",
        }
    }
}

/// The classifier of a chapter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClassifierKind {
    /// One-vs-one linear SVM (ch. 2–4) on the window energy `E` as printed (eq. 2.46).
    Svm,
    /// The same SVM on `log10 E`, i.e. the energy in dB (per-pair standardisation removes the
    /// factor 10): `classify`'s [`classify::FeatureTransform::Log10`]. Not the dissertation's;
    /// reported beside it because window energies scatter multiplicatively and the classes span
    /// orders of magnitude, which moves the soft-margin thresholds of a one-feature SVM
    /// (`docs/equations/xtask-chapters.md`, "The energy's scale").
    SvmLogEnergy,
    /// Gini decision tree (ch. 5).
    Tree,
}

/// A fitted decision tree, for drawing (Fig. 5.8).
#[derive(Debug, Clone)]
pub enum TreeDraw {
    /// `energy <= threshold` goes left.
    Split {
        /// Threshold on the window energy.
        threshold: f64,
        /// Left subtree.
        left: Box<TreeDraw>,
        /// Right subtree.
        right: Box<TreeDraw>,
    },
    /// A leaf predicting a class index.
    Leaf {
        /// Class index.
        class: usize,
    },
}

use bearing_model::{FaultClass, Scenario};
use classify::{ClassifierSpec, GiniTreeParams};
use laguerre_id::{ArxLaguerreConfig, PoleChoice};
use observers::{
    FaultDirection, LawFamily, LinearDesign, ModelConfig, ObserverKind, ObserverSettings,
};

/// Output orders N_a tried for the ARX-Laguerre models (AR form: CWRU has no measured force);
/// the one with the smallest held-out one-step error on the healthy fit segment wins
/// (`laguerre_id::ArxLaguerreModel::identify_order`).
pub const N_A_CANDIDATES: [usize; 6] = [2, 4, 6, 8, 12, 16];
/// Input orders N_b tried when the ARX-Laguerre models take the calibrated machine model's
/// one-step prediction as their exogenous input ([`Prepared::new`] with `physics`): N_a is
/// chosen by held-out one-step error with the first (smallest) N_b, then N_b at that N_a
/// (`laguerre_id::ArxLaguerreModel::identify_orders`).
pub const N_B_CANDIDATES: [usize; 3] = [1, 2, 4];
/// Share of the healthy fit segment held out to choose N_a (and N_b).
pub const ORDER_HOLDOUT: f64 = 0.3;
/// Share of the healthy fit segment skipped before the ARX-Laguerre models with the machine
/// model's input are identified: the machine model's observer starts from rest at the segment's
/// first sample, and its prediction is meaningless until it has settled (on the first second
/// of 97 its first 1 000 samples predict 2.4 × worse than the signal's own RMS).
pub const INPUT_SETTLE: f64 = 0.25;
/// Multiples c of the measured bound Γ₀ tried as Γ = c·Γ₀. Only c = 1: the gains follow from
/// the bound of eqs 2.44, 3.21, 5.28 measured on the healthy fit segment ([`Prepared::tune`]).
/// A prediction-error search over c always runs to the smallest c tried (on a healthy segment
/// every sliding injection beyond the uncertainty adds to the one-step error), so a search
/// would only pick the edge of whatever range it is given. The further entries are a fallback,
/// not a search: they are tried in order only when no linear design runs the law stably with
/// the previous one (the higher-order sliding laws integrate sgn e, whose random walk on a
/// broadband healthy signal can outgrow the one-step error: the simulated substitute at
/// 300–500 rpm); the tuning records the multiple used.
pub const GAMMA_MULTIPLES: [f64; 7] = [1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625];
/// Tree limits for the chapter-5 classifier (the dissertation's trees have one leaf per class).
pub const TREE_MAX_DEPTH: usize = 4;
/// Minimum training windows per leaf.
pub const TREE_MIN_LEAF: usize = 5;

/// What the observers need from the healthy fit segment: the identified ARX-Laguerre and fuzzy
/// ARX-Laguerre models, the calibrated machine model's structural path (the physics observers'
/// model), and the segment itself (the gains are set on it, see [`Prepared::tune`]).
#[derive(Debug, Clone)]
pub struct Prepared {
    arx: observers::StateSpace,
    /// The identified ARX-Laguerre model `arx` was built from (its one-step predictor,
    /// [`Prepared::record_nrmse`]).
    identified: laguerre_id::ArxLaguerreModel,
    fal: Option<Box<fuzzy_ts::FuzzyArxLaguerre>>,
    path: Option<observers::StateSpace>,
    input: Option<MachineInput>,
    fit: Vec<f64>,
    /// The machine model's input over `fit` (None in AR form), computed once for the
    /// identification and every method's tuning.
    fit_input: Option<Vec<f64>>,
    /// Pole ζ_a chosen by the identification.
    pub zeta_a: f64,
    /// Input pole ζ_b (None in AR form, without the machine model's input).
    pub zeta_b: Option<f64>,
    /// Output order N_a chosen by held-out prediction error.
    pub n_a: usize,
    /// Input order N_b chosen with N_a (0 in AR form).
    pub n_b: usize,
    /// Held-out one-step NRMSE of every (N_a, N_b) tried (N_b = 0 in AR form).
    pub order_scores: Vec<((usize, usize), f64)>,
    /// Held-out one-step NRMSE of the machine model's prediction alone on the same samples the
    /// orders are scored on (None in AR form).
    pub input_nrmse: Option<f64>,
    /// Samples per shaft revolution (the averaging window of the bound measurement).
    pub revolution: usize,
    /// Order of the calibrated structural path (AR order p).
    pub path_order: usize,
    /// Lines (shaft harmonics, tones) of the calibrated machine model the physics observers'
    /// predictor also carries ([`close_loop::machine::MachineModel::predictor_model`]).
    pub path_lines: usize,
    /// Order of the physics observers' one-step predictor (the path's plus two per line).
    pub predictor_order: usize,
    /// Structural modes of the calibrated path (complex pole pairs).
    pub path_modes: usize,
    /// Held-out error of the calibration loop on the fit segment, before → after (dB), and
    /// whether the loop itself added the path (else it was identified from the segment).
    pub calibration_error: Option<(f64, f64, bool)>,
}

/// The calibrated machine model's linear observer (FLO's law on the whole-model predictor,
/// `close_loop::machine::MachineModel::predictor_model`, its linear design chosen on the fit
/// segment as [`Prepared::tune`] chooses FLO's): its one-step prediction is the exogenous input
/// u of the ARX-Laguerre and fuzzy ARX-Laguerre models (eq. 2.33's u read as the physics
/// model's output at the sensor; `docs/equations/xtask-chapters.md`, "ARX-Laguerre on the
/// calibrated machine model").
#[derive(Debug, Clone)]
struct MachineInput {
    model: ModelConfig,
    settings: ObserverSettings,
}

impl MachineInput {
    /// u(k) = the machine model's prediction of y(k + 1) from y(0..=k): y(k+1) − r(k+1) of its
    /// observer, which is causal (its residual r(k) = y(k) − ŷ(k), ŷ(k) from y(0..k)). The last
    /// sample's u predicts beyond the recording; no prediction inside it uses it, so it is 0.
    fn prediction(&self, y: &[f64]) -> Result<Vec<f64>> {
        let mut obs = observers::build_observer(ObserverKind::Flo, &self.model, &self.settings)?;
        let r = obs.run(y)?.residual;
        let n = y.len();
        Ok((0..n)
            .map(|k| if k + 1 < n { y[k + 1] - r[k + 1] } else { 0.0 })
            .collect())
    }
}

/// The gains chosen for one observer on one healthy fit segment.
#[derive(Debug, Clone, Copy)]
pub struct Tuning {
    /// Settings handed to `observers::build_observer`.
    pub settings: ObserverSettings,
    /// The chosen multiple c of the measured bound, Γ = c·Γ₀ (None: linear law, Γ unused).
    pub multiple: Option<f64>,
    /// The measured bound Γ₀ = RMS(Δᵐ⁻¹ û), û the linear observer's lumped uncertainty d̂₀ + r₀
    /// averaged over one shaft revolution.
    pub bound: f64,
    /// Difference order m of the bound.
    pub order: usize,
    /// The linear design chosen: "default", "for_recordings" or "innovations"
    /// (`observers::LinearDesign`).
    pub design: &'static str,

    /// RMS(residual) / RMS(y) on the second half of the fit segment.
    pub fit_ratio: f64,
    /// RMS(residual) on the last quarter over that on the second quarter of the fit segment
    /// (≫ 1 would mean divergence).
    pub growth: f64,
}

use close_loop::metric::rms;

/// RMS of x / RMS of y (0 when y is silent).
pub fn rms_ratio(x: &[f64], y: &[f64]) -> f64 {
    let d = rms(y);
    if d > 0.0 { rms(x) / d } else { 0.0 }
}

/// What [`Prepared`] keeps of the machine model calibrated on the healthy segment.
struct CalibratedPath {
    /// The model the physics observers run: the calibrated machine's predictor, or (when the
    /// declared model already explained the segment and the loop added no path) a path
    /// identified from the segment.
    path: observers::StateSpace,
    /// The path's structural modes (of positive frequency).
    modes: usize,
    /// The calibration's error before and after, and whether it added a path.
    error: (f64, f64, bool),
    /// The path's order.
    order: usize,
    /// The machine model's lines.
    lines: usize,
}

/// The machine model calibrated on the healthy segment from `bearing`'s declared 5-DOF model,
/// as the physics observers run it ([`CalibratedPath`]).
fn calibrated_path(
    healthy: &[f64],
    fs: f64,
    rpm: f64,
    bearing: bearing_model::Bearing,
) -> Result<CalibratedPath> {
    let cfg = close_loop::LoopConfig::default().check()?;
    let recording =
        close_loop::Signal::new(healthy, fs).map_err(close_loop::CloseLoopError::from)?;
    let machine = close_loop::machine::calibrate(&recording, rpm, bearing, &cfg)?;
    let (path, path_modes, path_order, path_lines) = match &machine.path {
        Some(p) => (
            machine.predictor_model()?,
            machine
                .structural_modes
                .iter()
                .filter(|m| m.frequency_hz > 0.0)
                .count(),
            p.order(),
            machine.lines.len(),
        ),
        // the declared model already explained the segment: the loop added no path,
        // so the path is identified from the segment directly
        None => {
            let p = close_loop::path::identify_from_signal(healthy, fs, cfg.get().max_path_order)?;
            let modes = p.modes().iter().filter(|m| m.frequency_hz > 0.0).count();
            (observers::StateSpace::from_ar(&p.ar)?, modes, p.order(), 0)
        }
    };
    let error = (
        machine.provenance.error_before,
        machine.provenance.error_after,
        machine.path.is_some(),
    );
    Ok(CalibratedPath {
        path,
        modes: path_modes,
        error,
        order: path_order,
        lines: path_lines,
    })
}

/// The ARX-Laguerre model of `y_id` (input `u_id`, the machine model's prediction, when there
/// is one) with the orders chosen by held-out one-step error, and every order pair's score.
fn identify_arx_orders(
    y_id: &[f64],
    u_id: Option<&[f64]>,
) -> Result<(laguerre_id::ArxLaguerreModel, Vec<laguerre_id::OrderScore>)> {
    let poles = PoleChoice::DEFAULT_SEARCH;
    let identify = laguerre_id::ArxLaguerreModel::identify_orders;
    Ok(match u_id {
        // N_a with the smallest input order, then N_b at that N_a: 9 fits instead of the
        // joint grid's 18, which took `cargo xtask all` over its 60 s
        // (docs/equations/xtask-chapters.md, "ARX-Laguerre on the calibrated machine model")
        Some(u) => {
            let by_a: Vec<(usize, usize)> = N_A_CANDIDATES
                .iter()
                .map(|&a| (a, N_B_CANDIDATES[0]))
                .collect();
            let (m_a, mut scores) = identify(y_id, Some(u), &by_a, ORDER_HOLDOUT, poles)?;
            let by_b: Vec<(usize, usize)> =
                N_B_CANDIDATES.iter().map(|&b| (m_a.n_a(), b)).collect();
            let (m, scores_b) = identify(y_id, Some(u), &by_b, ORDER_HOLDOUT, poles)?;
            scores.extend(scores_b.into_iter().filter(|s| s.0.1 != N_B_CANDIDATES[0]));
            (m, scores)
        }
        None => {
            let by_a: Vec<(usize, usize)> = N_A_CANDIDATES.iter().map(|&a| (a, 0)).collect();
            identify(y_id, None, &by_a, ORDER_HOLDOUT, poles)?
        }
    })
}

impl Prepared {
    /// Identify the ARX-Laguerre model (N_a by held-out one-step error, pole by eq. 4.10's
    /// prediction-error search) and, when `fuzzy`, the fuzzy ARX-Laguerre model of eq. 5.19 on
    /// `healthy`, and, when `physics`, calibrate the machine model on it
    /// (`close_loop::machine::calibrate`: the loop from the declared healthy 5-DOF model,
    /// `LoopConfig` defaults) whose structural path is the physics observers' model (identified
    /// from the segment directly when the loop added none because the declared model already
    /// explained it).
    ///
    /// The calibration starts from the 6205's declared healthy 5-DOF model (CWRU's drive end);
    /// [`Prepared::new_for`] takes the bearing.
    pub fn new(healthy: &[f64], fs: f64, rpm: f64, fuzzy: bool, physics: bool) -> Result<Self> {
        Self::new_for(
            healthy,
            fs,
            rpm,
            bearing_model::Bearing::Skf6205,
            fuzzy,
            physics,
        )
    }

    /// [`Prepared::new`] with the machine model's calibration started from `bearing`'s declared
    /// healthy 5-DOF model (only used when `physics`).
    pub fn new_for(
        healthy: &[f64],
        fs: f64,
        rpm: f64,
        bearing: bearing_model::Bearing,
        fuzzy: bool,
        physics: bool,
    ) -> Result<Self> {
        let revolution = (fs * 60.0 / rpm).round().max(1.0) as usize;
        let (path, path_modes, calibration_error, path_order, path_lines) = if physics {
            let c = calibrated_path(healthy, fs, rpm, bearing)?;
            (Some(c.path), c.modes, Some(c.error), c.order, c.lines)
        } else {
            (None, 0, None, 0, 0)
        };
        // the machine model's linear observer, tuned on the segment as FLO is: its prediction
        // is the ARX-Laguerre models' input
        let input = match &path {
            Some(p) => {
                let model = ModelConfig::CalibratedPath(p.clone());
                let t = tune_on(
                    Method::Flo,
                    ObserverKind::Flo,
                    &model,
                    healthy,
                    revolution,
                    None,
                )?;
                Some(MachineInput {
                    model,
                    settings: t.settings,
                })
            }
            None => None,
        };
        let u_fit = input.as_ref().map(|i| i.prediction(healthy)).transpose()?;
        let skip = if u_fit.is_some() {
            (INPUT_SETTLE * healthy.len() as f64).round() as usize
        } else {
            0
        };
        let (y_id, u_id) = (&healthy[skip..], u_fit.as_ref().map(|u| &u[skip..]));
        let (m, order_scores) = identify_arx_orders(y_id, u_id)?;
        let input_nrmse = match u_id {
            Some(u) => {
                let n_fit = ((1.0 - ORDER_HOLDOUT) * y_id.len() as f64).round() as usize;
                let yhat: Vec<f64> = (n_fit..y_id.len()).map(|k| u[k - 1]).collect();
                Some(laguerre_id::FitMetrics::compute(&y_id[n_fit..], &yhat)?.nrmse)
            }
            None => None,
        };
        let (n_a, n_b) = (m.n_a(), m.n_b());
        let arx = m.state_space().validated()?;
        let fal = if fuzzy {
            let cfg = ArxLaguerreConfig::new(n_a, n_b, PoleChoice::DEFAULT_SEARCH)?;
            let f = fuzzy_ts::FuzzyArxLaguerre::identify(
                y_id,
                if n_b > 0 { u_id } else { None },
                &fuzzy_ts::FalConfig::with_base(cfg),
            )?;
            Some(Box::new(f))
        } else {
            None
        };
        Ok(Self {
            arx,
            identified: m,
            fal,
            revolution,
            path_order,
            path_lines,
            predictor_order: path.as_ref().map_or(0, |p| p.order()),
            path_modes,
            calibration_error,
            path,
            input,
            fit: healthy.to_vec(),
            fit_input: if n_b > 0 { u_fit } else { None },
            zeta_a: m.pole_a().value(),
            zeta_b: m.pole_b().map(|p| p.value()),
            n_a,
            n_b,
            order_scores,
            input_nrmse,
        })
    }

    /// One-step NRMSE over `signal[from..]` of the identified ARX-Laguerre model's predictor
    /// (eq. 4.16's ŷ(k) from y(0..k) and, with the machine model's input, u(0..k)), and of the
    /// machine model's prediction alone on the same samples (None in AR form). Run over the
    /// whole healthy recording with `from` = the fit segment's length, every scored sample is
    /// one the identification never saw, and the predictors have settled on the segment.
    ///
    /// # Errors
    /// [`PipelineError::Ident`] when `from` leaves fewer than 2 samples; the machine model's
    /// observer's errors.
    pub fn record_nrmse(&self, signal: &[f64], from: usize) -> Result<(f64, Option<f64>)> {
        // the first sample has no prediction from the past (ŷ(0) = 0)
        let from = from.max(1);
        if from + 2 > signal.len() {
            return Err(laguerre_id::IdentError::TooFewSamples {
                found: signal.len().saturating_sub(from),
                needed: 2,
            }
            .into());
        }
        let u = self.machine_input(signal)?;
        let yhat = self.identified.predict(signal, u.as_deref())?;
        let fit = laguerre_id::FitMetrics::compute(&signal[from..], &yhat[from..])?;
        let alone = match &u {
            Some(u) => {
                let prev: Vec<f64> = (from..signal.len()).map(|k| u[k - 1]).collect();
                Some(laguerre_id::FitMetrics::compute(&signal[from..], &prev)?.nrmse)
            }
            None => None,
        };
        Ok((fit.nrmse, alone))
    }

    /// The exogenous input of the ARX-Laguerre and fuzzy ARX-Laguerre observers over `signal`:
    /// the calibrated machine model's one-step prediction (None when the models are in AR form).
    /// It is the same for every such method, so a caller running several of them over one
    /// recording computes it once and hands it to [`residual_with_input`].
    ///
    /// # Errors
    /// The machine model's observer's errors.
    pub fn machine_input(&self, signal: &[f64]) -> Result<Option<Vec<f64>>> {
        match &self.input {
            Some(i) if self.n_b > 0 => Ok(Some(i.prediction(signal)?)),
            _ => Ok(None),
        }
    }

    /// Whether `method` runs on a model that takes the machine model's input
    /// ([`Prepared::machine_input`]).
    pub fn takes_input(&self, method: Method) -> bool {
        let arx_model = matches!(
            method,
            Method::Apio | Method::Smalpio | Method::Asmo | Method::Afsmo | Method::SmoFuzzy
        );
        arx_model && self.input.is_some() && self.n_b > 0
    }

    fn kind_and_model(&self, method: Method) -> Result<(ObserverKind, ModelConfig)> {
        let arx = || ModelConfig::ArxLaguerre {
            model: self.arx.clone(),
            fault: FaultDirection::OutputFilter,
        };
        let fal = || -> Result<ModelConfig> {
            Ok(ModelConfig::FuzzyArxLaguerre {
                model: self.fal.clone().ok_or(PipelineError::NotPrepared {
                    what: "the fuzzy ARX-Laguerre model",
                })?,
                fault: FaultDirection::OutputFilter,
            })
        };
        let phys = || -> Result<ModelConfig> {
            Ok(ModelConfig::CalibratedPath(self.path.clone().ok_or(
                PipelineError::NotPrepared {
                    what: "the calibrated machine model",
                },
            )?))
        };
        Ok(match method {
            Method::Hostsmo => (ObserverKind::Hostsmo, phys()?),
            Method::Smo => (ObserverKind::Smo, phys()?),
            Method::Pflo => (ObserverKind::Pflo, phys()?),
            Method::Flo => (ObserverKind::Flo, phys()?),
            Method::Apio => (ObserverKind::Apio, arx()),
            Method::Smalpio => (ObserverKind::Smalpio, arx()),
            Method::Asmo => (ObserverKind::Asmo, fal()?),
            Method::Afsmo => (ObserverKind::Afsmo, fal()?),
            Method::SmoFuzzy => (ObserverKind::Smo, fal()?),
        })
    }

    /// Set Γ and the linear design of `method` on the healthy fit segment only.
    ///
    /// The bound of eqs 2.44 / 3.21 / 4.20–4.29 / 5.28 is measured first on the segment's first
    /// half (from [`INPUT_SETTLE`] of the segment on for a model that takes the machine model's
    /// input, whose observer starts from rest at the segment's first sample): the lumped uncertainty seen by the same model under its linear (PI) law, û = d̂₀ + r₀
    /// (what its extended state estimates plus what it leaves), averaged over one shaft
    /// revolution so that the innovation — which no observer can predict and no bound has to
    /// cover — averages out, and Γ₀ = RMS(Δᵐ⁻¹ û) (m = 3 for Levant laws: second difference;
    /// m = 2 otherwise: first difference). Then Γ = Γ₀ (c = 1; the further [`GAMMA_MULTIPLES`] only
    /// when no design runs stably with the previous one), times the three linear designs (default, `for_recordings`, innovations) runs over the
    /// segment from rest; the candidate with the smallest residual RMS on the segment's second
    /// half wins (first in order on ties). The sign laws' level-1 gain uses the error scale
    /// E₀ = RMS(r₀) on the same first half (`observers::design::BoundGains::sign_scaled`). Candidates that fail to build, produce non-finite
    /// output or grow (last-quarter RMS more than twice the second-quarter RMS) are skipped.
    /// No test window and no label is used.
    pub fn tune(&self, method: Method) -> Result<Tuning> {
        let (kind, model) = self.kind_and_model(method)?;
        let u = self
            .fit_input
            .as_deref()
            .filter(|_| self.takes_input(method));
        tune_on(method, kind, &model, &self.fit, self.revolution, u)
    }
}

/// [`Prepared::tune`] for `kind` on `model` over the healthy fit segment `fit` (with the
/// model's input `input`, when it has one).
fn tune_on(
    method: Method,
    kind: ObserverKind,
    model: &ModelConfig,
    fit: &[f64],
    revolution: usize,
    input: Option<&[f64]>,
) -> Result<Tuning> {
    use observers::RunObserver;
    let order = if kind.family() == LawFamily::Levant {
        3
    } else {
        2
    };
    let n = fit.len();
    let (q2, half, q4) = (n / 4, n / 2, 3 * n / 4);
    // with the machine model's input, the bound and error scale are measured after that input
    // has settled (INPUT_SETTLE), not over its start-up transient
    let start = match input {
        Some(_) => ((INPUT_SETTLE * n as f64).round() as usize).min(half / 2),
        None => 0,
    };
    let linear_only = kind.family() == LawFamily::Linear;
    let mut best: Option<Tuning> = None;
    // Γ = Γ₀; only when no design runs stably with it, Γ₀/2, Γ₀/4, … (GAMMA_MULTIPLES)
    for fallback in 0..GAMMA_MULTIPLES.len() {
        if best.is_some() || (fallback > 0 && linear_only) {
            break;
        }
        for (design, linear) in [
            ("default", LinearDesign::default()),
            ("for_recordings", LinearDesign::for_recordings()),
            ("innovations", LinearDesign::innovations()),
        ] {
            // the bound, measured with the linear law on the same model
            let mut lin_settings = ObserverSettings::new(1.0);
            lin_settings.linear = linear;
            let Ok(mut lin) = observers::build_observer(ObserverKind::Apio, model, &lin_settings)
            else {
                continue;
            };
            let Ok(r0) = RunObserver::run(&mut lin, fit, input) else {
                continue;
            };
            // lumped uncertainty seen by the linear observer: what it estimates (d̂₀) plus what
            // it leaves (r₀), averaged over one shaft revolution so that the innovation — which
            // no observer can predict and no bound has to cover — averages out
            let w = revolution.clamp(1, (half - start) / 4);
            let u: Vec<f64> = r0.fault[start..half]
                .iter()
                .zip(&r0.residual[start..half])
                .map(|(d, r)| d + r)
                .collect();
            let mut d: Vec<f64> = u
                .windows(w)
                .map(|x| x.iter().sum::<f64>() / w as f64)
                .collect();
            for _ in 0..order - 1 {
                for i in 0..d.len() - 1 {
                    d[i] = d[i + 1] - d[i];
                }
                d.pop();
            }
            let bound = rms(&d);
            let error_scale = rms(&r0.residual[start..half]);
            if !(bound.is_finite() && bound > 0.0 && error_scale > 0.0) {
                continue;
            }
            let multiples: &[f64] = if linear_only {
                &[1.0]
            } else {
                &GAMMA_MULTIPLES[fallback..=fallback]
            };
            for &c in multiples {
                let mut settings = ObserverSettings::new(c * bound);
                settings.linear = linear;
                settings.error_scale = error_scale;
                // AFSMO's schedule (5.29): "normal" within 3σ of the healthy residual, "faulty"
                // beyond 6σ, σ = E₀ (docs/equations/observers.md, item 16)
                settings.fuzzy_thresholds = Some([3.0 * error_scale, 6.0 * error_scale]);
                let Ok(mut obs) = observers::build_observer(kind, model, &settings) else {
                    continue;
                };
                let Ok(out) = RunObserver::run(&mut obs, fit, input) else {
                    continue;
                };
                let r = &out.residual;
                if r.iter().any(|v| !v.is_finite()) {
                    continue;
                }
                let growth = rms(&r[q4..]) / rms(&r[q2..half]).max(1e-300);
                if growth > 2.0 {
                    continue;
                }
                let t = Tuning {
                    settings,
                    multiple: (!linear_only).then_some(c),
                    bound,
                    order,
                    design,
                    fit_ratio: rms_ratio(&r[half..], &fit[half..]),
                    growth,
                };
                if best.is_none_or(|b| t.fit_ratio < b.fit_ratio) {
                    best = Some(t);
                }
            }
        }
    }
    best.ok_or(PipelineError::NoStableGain {
        method: method.name(),
    })
}

/// The residual r = y − ŷ of `method` over the whole recording (eqs 2.45, 3.25, 4.30, 5.32),
/// with the gains chosen by [`Prepared::tune`].
pub fn residual(
    method: Method,
    prepared: &Prepared,
    tuning: &Tuning,
    signal: &[f64],
) -> Result<Vec<f64>> {
    residual_with_input(method, prepared, tuning, signal, None)
}

/// [`residual`] with the machine model's input over `signal` computed beforehand by
/// [`Prepared::machine_input`] (`None`: computed here when `method` needs it; ignored by methods
/// that do not).
///
/// # Errors
/// [`PipelineError::InputLength`] when `input` is not as long as `signal`; the observer's errors.
pub fn residual_with_input(
    method: Method,
    prepared: &Prepared,
    tuning: &Tuning,
    signal: &[f64],
    input: Option<&[f64]>,
) -> Result<Vec<f64>> {
    use observers::RunObserver;
    let (kind, model) = prepared.kind_and_model(method)?;
    let computed;
    let u = match input {
        _ if !prepared.takes_input(method) => None,
        Some(u) if u.len() != signal.len() => {
            return Err(PipelineError::InputLength {
                expected: signal.len(),
                found: u.len(),
            });
        }
        Some(u) => Some(u),
        None => {
            computed = prepared.machine_input(signal)?;
            computed.as_deref()
        }
    };
    let mut obs = observers::build_observer(kind, &model, &tuning.settings)?;
    Ok(RunObserver::run(&mut obs, signal, u)?.residual)
}

/// Window energies Σr² (eq. 2.46 / 5.33) of the first `count` non-overlapping windows of `len`
/// samples (at most as many as fit), cut and computed by `residual-features`' [`WindowPlan`]
/// and energy-only [`FeatureExtractor`].
///
/// [`WindowPlan`]: residual_features::WindowPlan
/// [`FeatureExtractor`]: residual_features::FeatureExtractor
pub fn window_energies(r: &[f64], len: usize, count: usize) -> Result<Vec<f64>> {
    use residual_features::{FeatureConfig, FeatureExtractor, TailPolicy, WindowPlan, Windowing};
    let n = r.len().checked_div(len).unwrap_or(0).min(count);
    if n == 0 {
        return Err(PipelineError::TooShort {
            what: "residual for one complete window",
            needed: len.max(1),
            found: r.len(),
        });
    }
    let plan = WindowPlan::new(Windowing::FixedLength { length: len }, TailPolicy::Reject)?;
    let mut extractor = FeatureExtractor::new(FeatureConfig::energy_only())?;
    let table = extractor.extract_windows(&r[..n * len], &plan)?;
    Ok(table.rows.into_iter().map(|row| row[0]).collect())
}

/// The chapter-5 tree's limits ([`TREE_MAX_DEPTH`], [`TREE_MIN_LEAF`]).
fn tree_params() -> GiniTreeParams {
    GiniTreeParams {
        max_depth: Some(TREE_MAX_DEPTH),
        min_samples_leaf: TREE_MIN_LEAF,
        ..GiniTreeParams::default()
    }
}

fn spec(kind: ClassifierKind) -> ClassifierSpec {
    match kind {
        ClassifierKind::Svm => ClassifierSpec::svm(),
        ClassifierKind::SvmLogEnergy => ClassifierSpec::svm_with(
            classify::LinearSvmParams::default().with_transform(classify::FeatureTransform::Log10),
        ),
        ClassifierKind::Tree => ClassifierSpec::GiniTree(tree_params()),
    }
}

/// Fit the chapter-5 Gini tree on every window of a cell ([`cell_dataset`]) and print its rules
/// in the form of eqs 5.35–5.36, classes named by the dataset's class names.
pub fn tree_rules(data: &Dataset) -> Result<(String, TreeDraw)> {
    let train: Vec<usize> = (0..data.n_samples()).collect();
    let tree = classify::GiniTree::fit(&tree_params(), data, &train)?;
    let names = data.feature_names().to_vec();
    let labels = data.class_names();
    let mut text = String::from(
        "Rules learned by the Gini tree on the window energy E (thresholds in the residual's units squared):\n\n```text\n",
    );
    for r in tree.rules() {
        text.push_str(&format!("{}\n", r.named(&names, labels)));
    }
    text.push_str("```\n");
    fn conv(n: &classify::Node) -> TreeDraw {
        match n {
            classify::Node::Leaf { class, .. } => TreeDraw::Leaf { class: *class },
            classify::Node::Split {
                threshold,
                left,
                right,
                ..
            } => TreeDraw::Split {
                threshold: *threshold,
                left: Box::new(conv(left)),
                right: Box::new(conv(right)),
            },
        }
    }
    Ok((text, conv(&tree.root)))
}

/// Which scenario family a simulated recording belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimKind {
    /// CWRU-like (6205, fault size in inches), the no-data fallback: the calibrated CWRU rig.
    Cwru,
    /// The SHSE multi-fault substitute (crack size in mm): the calibrated CWRU rig at the
    /// dissertation's speeds and crack sizes (the severity of the largest calibrated spall held).
    Shse,
    /// The bare 5-DOF model's housing acceleration (m/s²) at CWRU conditions (size in inches),
    /// as `bearing_model::Scenario::cwru` gives it.
    BareCwru,
}

/// The calibrated CWRU rig, parsed once.
fn rig() -> Result<&'static calibrated_rig::RigModel> {
    static RIG: std::sync::OnceLock<std::result::Result<calibrated_rig::RigModel, String>> =
        std::sync::OnceLock::new();
    RIG.get_or_init(|| calibrated_rig::cwru_rig().map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|e| {
            PipelineError::Calibration(close_loop::CloseLoopError::MachineModelFormat {
                reason: e.clone(),
            })
        })
}

/// Simulate `n` samples: the calibrated CWRU rig (g) for [`SimKind::Cwru`] and
/// [`SimKind::Shse`], the bare 5-DOF model (m/s²) for [`SimKind::BareCwru`].
pub fn simulate(
    kind: SimKind,
    class: FaultClass,
    size: f64,
    rpm: f64,
    fs: f64,
    n: usize,
    seed: u64,
) -> Result<Vec<f64>> {
    let size_mm = match kind {
        SimKind::Cwru => size * 25.4,
        SimKind::Shse => size,
        SimKind::BareCwru => {
            let rec = Scenario::cwru(class, size, rpm)?
                .with_fs(fs)
                .with_duration(n as f64 / fs)
                .with_seed(seed)
                .simulate()?;
            return take(rec.accel, n);
        }
    };
    let rig = rig()?;
    rig.check_compatible(fs, &rig.bearing)?;
    let y = rig.synthesize(&calibrated_rig::Synthesis::new(
        class, size_mm, rpm, n, seed,
    ))?;
    take(y, n)
}

/// A recording of the multi-fault substitute ([`SimKind::Shse`]): the calibrated rig (g) with
/// spalls of `size_mm` whose 5-DOF excitations are drawn from `excitation_seed` and shared
/// through `cache` ([`calibrated_rig::Synthesis::excitation_seed`]); background, strike gate
/// and random part from `seed`.
///
/// # Errors
/// The rig's errors ([`calibrated_rig::RigModel::synthesize_cached`]), a sampling rate the rig
/// was not calibrated at.
#[allow(clippy::too_many_arguments)] // simulate's arguments and the shared excitation
pub fn simulate_substitute(
    class: FaultClass,
    size_mm: f64,
    rpm: f64,
    fs: f64,
    n: usize,
    seed: u64,
    excitation_seed: u64,
    cache: &calibrated_rig::ExcitationCache,
) -> Result<Vec<f64>> {
    let rig = rig()?;
    rig.check_compatible(fs, &rig.bearing)?;
    let s = calibrated_rig::Synthesis::new(class, size_mm, rpm, n, seed)
        .with_excitation_seed(excitation_seed);
    take(rig.synthesize_cached(&s, cache)?, n)
}

fn take(mut a: Vec<f64>, n: usize) -> Result<Vec<f64>> {
    if a.len() < n {
        return Err(PipelineError::TooShort {
            what: "simulated recording",
            needed: n,
            found: a.len(),
        });
    }
    a.truncate(n);
    Ok(a)
}

/// The README's examples, compiled as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
