//! The thin adapter between the chapter pipelines and the algorithm crates: one function per
//! stage (observer residual, window energies, classifier, decision rules, simulation), so the
//! pipeline reads the same whatever shape the crates' APIs take.

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
    /// One-vs-one linear SVM (ch. 2–4).
    Svm,
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

use super::inputs::Rec;
use anyhow::Context as _;
use bearing_model::{FaultClass, Scenario};
use classify::{ClassifierSpec, Dataset, GiniTreeParams, WindowMeta};
use laguerre_id::{ArxLaguerreConfig, PoleChoice};
use observers::{FaultDirection, ModalParams, ModelConfig, ObserverKind, ObserverSettings};

/// ARX-Laguerre orders: N_a output filters, no input (AR form: CWRU has no measured force).
pub const N_A: usize = 6;
/// Quantile of |Δᵐy| on the healthy fit segment used as the per-sample uncertainty bound.
pub const BOUND_QUANTILE: f64 = 0.99;
/// Tree limits for the chapter-5 classifier (the dissertation's trees have one leaf per class).
pub const TREE_MAX_DEPTH: usize = 4;
/// Minimum training windows per leaf.
pub const TREE_MIN_LEAF: usize = 5;

/// What the observers need from the healthy fit segment: the identified ARX-Laguerre model and
/// the physics mode of the measured channel.
#[derive(Debug, Clone)]
pub struct Prepared {
    arx: observers::ArxLaguerreModel,
    mode: ModalParams,
    /// Per-sample bounds by difference order 2 and 3.
    bound2: f64,
    bound3: f64,
    /// Pole ζ_a chosen by the identification.
    pub zeta_a: f64,
}

impl Prepared {
    /// Identify the ARX-Laguerre model on `healthy` (eq. 4.10 pole by prediction error) and take
    /// the housing mode of the 5-DOF CWRU-rig parameter set as the physics model.
    pub fn new(healthy: &[f64], fs: f64, rpm: f64) -> anyhow::Result<Self> {
        let cfg = ArxLaguerreConfig::new(N_A, 0, PoleChoice::DEFAULT_SEARCH)?;
        let m = laguerre_id::ArxLaguerreModel::identify(healthy, None, &cfg)
            .context("identifying the ARX-Laguerre model on the healthy fit segment")?;
        let ss = m.state_space();
        let n = ss.n_states;
        let mut a = Vec::with_capacity(n * n);
        for i in 0..n {
            a.extend_from_slice(&ss.a[i][..n]);
        }
        let arx = observers::ArxLaguerreModel {
            a,
            b_y: ss.b_y[..n].to_vec(),
            b_u: ss.b_u[..n].to_vec(),
            k: ss.k[..n].to_vec(),
        };
        let spec = Scenario::new(bearing_model::ParamSet::CwruRig, bearing_model::Bearing::Skf6205, rpm).spec;
        let mode = ModalParams {
            natural_frequency_hz: spec.housing.resonance_hz.min(0.45 * fs),
            damping_ratio: spec.housing.damping_ratio,
            input_gain: 0.0,
            sample_rate_hz: fs,
        };
        Ok(Self {
            arx,
            mode,
            bound2: observers::estimate_bound(healthy, 2, BOUND_QUANTILE)?,
            bound3: observers::estimate_bound(healthy, 3, BOUND_QUANTILE)?,
            zeta_a: m.pole_a().value(),
        })
    }
}

fn kind_and_model(method: Method, p: &Prepared) -> (ObserverKind, ModelConfig, f64) {
    let arx = || ModelConfig::ArxLaguerre { model: p.arx.clone(), fault: FaultDirection::OutputFilter };
    let phys = ModelConfig::Physics(p.mode);
    match method {
        Method::Hostsmo => (ObserverKind::Hostsmo, phys, p.bound3),
        Method::Smo => (ObserverKind::Smo, phys, p.bound2),
        Method::Pflo => (ObserverKind::Pflo, phys, p.bound2),
        Method::Flo => (ObserverKind::Flo, phys, p.bound2),
        Method::Apio => (ObserverKind::Apio, arx(), p.bound2),
        Method::Smalpio => (ObserverKind::Smalpio, arx(), p.bound2),
        Method::Asmo => (ObserverKind::Asmo, arx(), p.bound3),
        Method::Afsmo => (ObserverKind::Afsmo, arx(), p.bound3),
        Method::SmoFuzzy => (ObserverKind::Smo, arx(), p.bound2),
    }
}

/// The residual r = y − ŷ of `method` over the whole recording (eqs 2.45, 3.25, 4.30, 5.32).
pub fn residual(method: Method, prepared: &Prepared, rec: &Rec) -> anyhow::Result<Vec<f64>> {
    let (kind, model, bound) = kind_and_model(method, prepared);
    let mut obs = build(kind, &model, bound)?;
    Ok(obs.run(&rec.signal)?.residual)
}

/// Build with the default settings. The crate's physics linear design (a steady-state Kalman
/// gain on the per-sample chain) can have a negative entry for a mode above ~500 Hz at 12 kHz,
/// which the law's gain check rejects; then (physics models only) the same observer is
/// assembled from the crate's public parts with the negative linear gains set to zero, and the
/// fallback is reported (`Fallback::ClampedLinearGain`).
fn build(kind: ObserverKind, model: &ModelConfig, bound: f64) -> anyhow::Result<observers::AnyObserver> {
    let settings = ObserverSettings::new(bound);
    match observers::build_observer(kind, model, &settings) {
        Ok(o) => Ok(o),
        Err(e0) => {
            let ModelConfig::Physics(mode) = model else {
                return Err(anyhow::anyhow!(e0).context(format!("building {}", kind.name())));
            };
            let p = observers::SecondOrderPredictor::new(*mode)?;
            let lin = if kind.has_linear_part() {
                observers::named::design_physics_linear(&p, &settings.linear)?.law_gains.map(|g| g.max(0.0))
            } else {
                [0.0; 3]
            };
            let nl = match kind.family() {
                observers::LawFamily::Linear => [0.0; 3],
                observers::LawFamily::Sign => observers::design::BoundGains::sign(bound)?,
                observers::LawFamily::SuperTwisting => observers::design::BoundGains::super_twisting(bound)?,
                _ => observers::design::BoundGains::levant(bound)?,
            };
            let law = observers::HomogeneousLaw::new(lin, nl, kind.family())?;
            Ok(observers::AnyObserver::Physics(observers::Observer::new(p, observers::NamedLaw::Plain(law))))
        }
    }
}

/// Whether `method` needs the clamped-gain fallback of [`build`] with this model.
pub fn needs_fallback(method: Method, prepared: &Prepared) -> bool {
    let (kind, model, bound) = kind_and_model(method, prepared);
    observers::build_observer(kind, &model, &ObserverSettings::new(bound)).is_err()
}

/// Window energies Σr² (eq. 2.46 / 5.33) of `count` non-overlapping windows of `len` samples.
pub fn window_energies(r: &[f64], len: usize, count: usize) -> anyhow::Result<Vec<f64>> {
    let mut out = Vec::with_capacity(count);
    for w in r.chunks_exact(len).take(count) {
        out.push(residual_features::energy(w)?);
    }
    anyhow::ensure!(!out.is_empty(), "no complete window of {len} samples in {} samples", r.len());
    Ok(out)
}

fn spec(kind: ClassifierKind) -> ClassifierSpec {
    match kind {
        ClassifierKind::Svm => ClassifierSpec::svm(),
        ClassifierKind::Tree => ClassifierSpec::GiniTree(GiniTreeParams {
            max_depth: Some(TREE_MAX_DEPTH),
            min_samples_leaf: TREE_MIN_LEAF,
            ..GiniTreeParams::default()
        }),
    }
}

fn dataset(x: &[f64], y: &[usize], nclass: usize) -> anyhow::Result<Dataset> {
    let rows: Vec<Vec<f64>> = x.iter().map(|&v| vec![v]).collect();
    let meta = y
        .iter()
        .enumerate()
        .map(|(i, &c)| WindowMeta {
            class: c,
            recording: String::new(),
            load_hp: 0,
            fault_size_mils: None,
            index_in_recording: i,
        })
        .collect();
    let names = (0..nclass).map(|c| c.to_string()).collect();
    Ok(Dataset::new(names, vec!["energy".into()], &rows, meta)?)
}

/// Fit the classifier on (x, y) and predict `test` (one feature: the window energy).
pub fn fit_predict(
    kind: ClassifierKind,
    x: &[f64],
    y: &[usize],
    test: &[f64],
    nclass: usize,
) -> anyhow::Result<Vec<usize>> {
    let data = dataset(x, y, nclass)?;
    let train: Vec<usize> = (0..x.len()).collect();
    let model = spec(kind).fit(&data, &train)?;
    test.iter().map(|&t| Ok(model.predict_row(&[t])?)).collect()
}

/// Fit the chapter-5 Gini tree on all windows and print its rules in the form of eqs 5.35–5.36.
pub fn tree_rules(x: &[f64], y: &[usize], labels: &[String]) -> anyhow::Result<(String, TreeDraw)> {
    let data = Dataset::new(
        labels.to_vec(),
        vec!["E".into()],
        &x.iter().map(|&v| vec![v]).collect::<Vec<_>>(),
        y.iter()
            .enumerate()
            .map(|(i, &c)| WindowMeta { class: c, recording: String::new(), load_hp: 0, fault_size_mils: None, index_in_recording: i })
            .collect(),
    )?;
    let train: Vec<usize> = (0..x.len()).collect();
    let tree = classify::GiniTree::fit(
        &GiniTreeParams { max_depth: Some(TREE_MAX_DEPTH), min_samples_leaf: TREE_MIN_LEAF, ..GiniTreeParams::default() },
        &data,
        &train,
    )?;
    let names = vec!["E".to_string()];
    let mut text = String::from("Rules learned by the Gini tree on the window energy E (thresholds in the residual's units squared):\n\n```text\n");
    for r in tree.rules() {
        text.push_str(&format!("{}\n", r.named(&names, labels)));
    }
    text.push_str("```\n");
    fn conv(n: &classify::Node) -> TreeDraw {
        match n {
            classify::Node::Leaf { class, .. } => TreeDraw::Leaf { class: *class },
            classify::Node::Split { threshold, left, right, .. } => TreeDraw::Split {
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
    /// CWRU-like (6205, inches), the no-data fallback.
    Cwru,
    /// The SHSE multi-fault substitute (mm, slip and noise).
    Shse,
}

/// Simulate `n` samples of housing acceleration with `bearing-model`'s named scenarios.
pub fn simulate(kind: SimKind, class: FaultClass, size: f64, rpm: f64, fs: f64, n: usize, seed: u64) -> anyhow::Result<Vec<f64>> {
    let sc = match kind {
        SimKind::Cwru => Scenario::cwru(class, size, rpm)?,
        SimKind::Shse => Scenario::shse(class, size, rpm)?,
    };
    let rec = sc.with_fs(fs).with_duration(n as f64 / fs).with_seed(seed).simulate()?;
    let mut a = rec.accel;
    anyhow::ensure!(a.len() >= n, "simulation returned {} samples, {n} requested", a.len());
    a.truncate(n);
    Ok(a)
}

