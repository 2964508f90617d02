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
/// Share of the healthy fit segment held out to choose N_a.
pub const ORDER_HOLDOUT: f64 = 0.3;
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
    arx: observers::LinearModel,
    fal: Option<Box<fuzzy_ts::FuzzyArxLaguerre>>,
    path: Option<observers::LinearModel>,
    fit: Vec<f64>,
    /// Pole ζ_a chosen by the identification.
    pub zeta_a: f64,
    /// Output order N_a chosen by held-out prediction error.
    pub n_a: usize,
    /// Held-out one-step NRMSE of every N_a tried.
    pub order_scores: Vec<(usize, f64)>,
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

impl Prepared {
    /// Identify the ARX-Laguerre model (N_a by held-out one-step error, pole by eq. 4.10's
    /// prediction-error search) and, when `fuzzy`, the fuzzy ARX-Laguerre model of eq. 5.19 on
    /// `healthy`, and, when `physics`, calibrate the machine model on it
    /// (`close_loop::machine::calibrate`: the loop from the declared healthy 5-DOF model,
    /// `LoopConfig` defaults) whose structural path is the physics observers' model (identified
    /// from the segment directly when the loop added none because the declared model already
    /// explained it).
    pub fn new(healthy: &[f64], fs: f64, rpm: f64, fuzzy: bool, physics: bool) -> Result<Self> {
        let (m, order_scores) = laguerre_id::ArxLaguerreModel::identify_order(
            healthy,
            &N_A_CANDIDATES,
            ORDER_HOLDOUT,
            PoleChoice::DEFAULT_SEARCH,
        )?;
        let n_a = m.n_a();
        let arx = observers::LinearModel::from_state_space(&m.state_space())?;
        let fal = if fuzzy {
            let cfg = ArxLaguerreConfig::new(n_a, 0, PoleChoice::DEFAULT_SEARCH)?;
            let f = fuzzy_ts::FuzzyArxLaguerre::identify(
                healthy,
                None,
                &fuzzy_ts::FalConfig::with_base(cfg),
            )?;
            Some(Box::new(f))
        } else {
            None
        };
        let (path, path_modes, calibration_error, path_order, path_lines) = if physics {
            let cfg = close_loop::LoopConfig::default().check()?;
            let machine = close_loop::machine::calibrate(
                healthy,
                fs,
                rpm,
                bearing_model::Bearing::Skf6205,
                &cfg,
            )?;
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
                    let p = close_loop::path::identify_from_signal(
                        healthy,
                        fs,
                        cfg.get().max_path_order,
                    )?;
                    let modes = p.modes().iter().filter(|m| m.frequency_hz > 0.0).count();
                    (observers::LinearModel::from_ar(&p.ar)?, modes, p.order(), 0)
                }
            };
            let err = (
                machine.provenance.error_before,
                machine.provenance.error_after,
                machine.path.is_some(),
            );
            (Some(path), path_modes, Some(err), path_order, path_lines)
        } else {
            (None, 0, None, 0, 0)
        };
        Ok(Self {
            arx,
            fal,
            revolution: (fs * 60.0 / rpm).round().max(1.0) as usize,
            path_order,
            path_lines,
            predictor_order: path.as_ref().map_or(0, |p| p.order()),
            path_modes,
            calibration_error,
            path,
            fit: healthy.to_vec(),
            zeta_a: m.pole_a().value(),
            n_a,
            order_scores,
        })
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
    /// half: the lumped uncertainty seen by the same model under its linear (PI) law, û = d̂₀ + r₀
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
        let order = if kind.family() == LawFamily::Levant {
            3
        } else {
            2
        };
        let n = self.fit.len();
        let (q2, half, q4) = (n / 4, n / 2, 3 * n / 4);
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
                let Ok(mut lin) =
                    observers::build_observer(ObserverKind::Apio, &model, &lin_settings)
                else {
                    continue;
                };
                let Ok(r0) = lin.run(&self.fit) else {
                    continue;
                };
                // lumped uncertainty seen by the linear observer: what it estimates (d̂₀) plus what
                // it leaves (r₀), averaged over one shaft revolution so that the innovation — which
                // no observer can predict and no bound has to cover — averages out
                let w = self.revolution.clamp(1, half / 4);
                let u: Vec<f64> = r0.fault[..half]
                    .iter()
                    .zip(&r0.residual[..half])
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
                let error_scale = rms(&r0.residual[..half]);
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
                    let Ok(mut obs) = observers::build_observer(kind, &model, &settings) else {
                        continue;
                    };
                    let Ok(out) = obs.run(&self.fit) else {
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
                        fit_ratio: rms_ratio(&r[half..], &self.fit[half..]),
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
}

/// The residual r = y − ŷ of `method` over the whole recording (eqs 2.45, 3.25, 4.30, 5.32),
/// with the gains chosen by [`Prepared::tune`].
pub fn residual(
    method: Method,
    prepared: &Prepared,
    tuning: &Tuning,
    signal: &[f64],
) -> Result<Vec<f64>> {
    let (kind, model) = prepared.kind_and_model(method)?;
    let mut obs = observers::build_observer(kind, &model, &tuning.settings)?;
    Ok(obs.run(signal)?.residual)
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
fn rig() -> Result<&'static close_loop::rig::RigModel> {
    static RIG: std::sync::OnceLock<std::result::Result<close_loop::rig::RigModel, String>> =
        std::sync::OnceLock::new();
    RIG.get_or_init(|| close_loop::rig::cwru_rig().map_err(|e| e.to_string()))
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
    let y = rig.synthesize(&close_loop::rig::Synthesis::new(
        class, size_mm, rpm, n, seed,
    ))?;
    take(y, n)
}

/// A recording of the multi-fault substitute ([`SimKind::Shse`]): the calibrated rig (g) with
/// spalls of `size_mm` whose 5-DOF excitations are drawn from `excitation_seed` and shared
/// through `cache` ([`close_loop::rig::Synthesis::excitation_seed`]); background, strike gate
/// and random part from `seed`.
///
/// # Errors
/// The rig's errors ([`close_loop::rig::RigModel::synthesize_cached`]), a sampling rate the rig
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
    cache: &close_loop::rig::ExcitationCache,
) -> Result<Vec<f64>> {
    let rig = rig()?;
    rig.check_compatible(fs, &rig.bearing)?;
    let s = close_loop::rig::Synthesis::new(class, size_mm, rpm, n, seed)
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
