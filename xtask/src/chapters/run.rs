//! What each chapter runs: the methods, the datasets behind each dissertation table, and the
//! evaluation protocols; the per-cell classification loop.
//!
//! Every cell of a dissertation table is one classification problem (the table's classes at one
//! load or speed and one crack size). Features are window energies of the residual (eqs 2.46,
//! 3.26, 4.31, 5.33), one window length for every class. The classifier is the one-vs-one linear
//! SVM (chapters 2–4) or the Gini decision tree (chapter 5), both from the `classify` crate.

use super::cells::{Src, cell_dataset};
use super::inputs::{self, Cache, RecKey};
use super::notes::{base_notes, data_note, headline, protocol_note, tuning_section};
use super::report::{Cell, ChapterReport, OurTable, SourceColumns};
use crate::common::Context;
use ::pipeline::dissertation::{self as tables, Condition, DissTable};
use ::pipeline::{self as pl, ClassifierKind, Method};
use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Run configuration (full or quick).
#[derive(Debug, Clone)]
pub struct Config {
    /// Reduced configuration for the `--check` test.
    pub quick: bool,
    /// Draw figures.
    pub figures: bool,
    /// Show progress bars.
    pub progress: bool,
    /// Samples per window (every class, every recording).
    pub window_len: usize,
    /// Windows per recording at most (the dissertation's 400 per class).
    pub windows_per_rec: usize,
    /// Seeds of the random-split protocol.
    pub seeds: u64,
    /// CWRU loads run.
    pub loads: Vec<u8>,
    /// Substitute speeds run.
    pub rpms: Vec<u32>,
}

impl Config {
    /// The loads and speeds this configuration runs.
    pub fn scope(&self) -> pl::cells::Scope {
        pl::cells::Scope {
            loads: self.loads.clone(),
            rpms: self.rpms.clone(),
        }
    }

    /// The full or the quick configuration.
    pub fn new(quick: bool, figures: bool, progress: bool) -> Self {
        if quick {
            Self {
                quick,
                figures,
                progress,
                window_len: 300,
                windows_per_rec: 60,
                seeds: 2,
                loads: vec![0],
                rpms: vec![300],
            }
        } else {
            Self {
                quick,
                figures,
                progress,
                window_len: 300,
                windows_per_rec: 400,
                seeds: 3,
                loads: vec![0, 1, 2, 3],
                rpms: vec![300, 400, 450, 500],
            }
        }
    }
}

/// A chapter's output: its report, its figures and a headline for the terminal.
pub struct ChapterOutput {
    /// Tables and notes.
    pub report: ChapterReport,
    /// `figures/<name>.png` → bytes.
    pub figures: Vec<(String, Vec<u8>)>,
    /// Terminal summary.
    pub headline: String,
}

/// Methods and classifier of a chapter, in the dissertation's column order.
fn chapter_spec(ch: u8) -> anyhow::Result<(Vec<Method>, ClassifierKind, &'static str)> {
    Ok(match ch {
        2 => (
            vec![Method::Hostsmo, Method::Smo, Method::Apio],
            ClassifierKind::Svm,
            "Chapter 2 — HOSTSMO, SMO, APIO with energy features and a one-vs-one SVM",
        ),
        3 => (
            vec![Method::Pflo, Method::Flo, Method::Apio],
            ClassifierKind::Svm,
            "Chapter 3 — PFLO, FLO, APIO with energy features and a one-vs-one SVM",
        ),
        4 => (
            vec![Method::Smalpio, Method::Apio],
            ClassifierKind::Svm,
            "Chapter 4 — SMALPIO, APIO on ARX-Laguerre with energy features and a one-vs-one SVM",
        ),
        5 => (
            vec![Method::Afsmo, Method::Asmo, Method::SmoFuzzy],
            ClassifierKind::Tree,
            "Chapter 5 — AFSMO, ASMO, SMO on fuzzy ARX-Laguerre with energy features and a Gini decision tree",
        ),
        other => anyhow::bail!("no chapter {other} (chapters 2–5 have tables)"),
    })
}

/// What one (source, recording) job yields: window energies, a short residual trace for the
/// figures, and RMS(residual) / RMS(signal) over the scored windows.
type SourceOut = inputs::SourceFeatures;

/// Features of one (source, recording): window energies.
pub type FeatMap = BTreeMap<(String, RecKey), Vec<f64>>;

/// Prepared models per healthy recording.
type Models = BTreeMap<RecKey, std::sync::Arc<pl::Prepared>>;
/// Tuned gains per (observer, healthy recording).
type Tunings = BTreeMap<(Method, RecKey), pl::Tuning>;
/// Residual traces (figures) and residual / signal RMS ratios per (source, recording).
type SourceMap<T> = BTreeMap<(String, RecKey), T>;

/// What step 3 yields: window energies, residual traces and RMS ratios of every
/// (source, recording).
struct Features {
    feats: FeatMap,
    traces: SourceMap<Vec<f64>>,
    ratios: SourceMap<f64>,
}

/// Run one chapter: its recordings (1), the models on each healthy fit segment and their gains
/// (2), the residual features of every (source, recording) (3), the tables (4), chapter 5's
/// rules (5), the figures (6) and the headline (7).
pub fn run_chapter(
    ctx: &Context,
    cfg: &Config,
    ch: u8,
    cache: &mut Cache,
) -> anyhow::Result<ChapterOutput> {
    let (methods, clf, title) = chapter_spec(ch)?;
    let diss_all = tables::chapter_tables(ch);
    let diss: Vec<&DissTable> = diss_all
        .into_iter()
        .filter(|d| d.selected(&cfg.scope()))
        .collect();
    let cwru_sim = !inputs::cwru_available(ctx);
    if cwru_sim && ctx.ci {
        anyhow::bail!("CI=true but the CWRU data directory was not found (set HYBRID_FDD_DATA)");
    }
    let mut notes = base_notes(cfg, ch, clf, cwru_sim);
    let t0 = std::time::Instant::now();
    let stage = |what: &str| {
        if cfg.progress {
            eprintln!(
                "chapter {ch}: {what} done at {:.1} s",
                t0.elapsed().as_secs_f64()
            );
        }
    };

    // 1. Recordings every table needs.
    let keys = recordings_needed(&diss, cfg);
    let pb = progress(cfg, keys.len() as u64, format!("chapter {ch}: recordings"));
    cache.load_all(ctx, cfg, &keys, &pb)?;
    pb.finish_and_clear();
    stage("recordings");

    // 2. Models identified on each healthy fit segment (once per healthy recording), and the
    // gains tuned per (method, healthy recording) on the fit segment only.
    let mut healthy: Vec<RecKey> = keys.iter().map(inputs::healthy_key).collect();
    healthy.sort();
    healthy.dedup();
    let prepared = prepare_models(cache, &healthy)?;
    notes.extend(model_notes(cache, &prepared, &methods)?);
    let tunings = tune_gains(cache, &prepared, &healthy, &methods)?;
    stage("models and tuning");

    // 3. Residual features for every (source, recording), in parallel, collected in order.
    let mut sources: Vec<Option<Method>> = methods.iter().copied().map(Some).collect();
    sources.push(None);
    let features = residual_features(cfg, ch, cache, &keys, &sources, &prepared, &tunings)?;
    stage("observers");

    // 4. Tables.
    let mut data_notes = Vec::new();
    let (tuning_extra, residual_rms_ratio) =
        tuning_section(&methods, &tunings, &features.ratios, cache)?;
    let mut extras = vec![tuning_extra];
    for d in &diss {
        data_notes.push(data_note(cfg, cache, d, &features.feats, &methods)?);
    }
    let report_tables = classify_tables(cfg, ch, cache, &diss, &sources, clf, &features.feats)?;
    stage("classifiers");

    // 5. Chapter 5: the learned rules (eqs 5.35–5.36, Fig. 5.8).
    let mut figures = Vec::new();
    if clf == ClassifierKind::Tree {
        if let Some((extra, figure)) = learned_rules(cfg, cache, &diss, &features.feats, &methods)?
        {
            extras.push(extra);
            figures.extend(figure);
        }
    }

    // 6. Figures.
    if cfg.figures {
        figures.extend(super::figures::chapter_figures(
            ch,
            cache,
            &diss,
            &report_tables,
            &features.feats,
            &features.traces,
            &methods,
        )?);
    }
    let figure_names: Vec<String> = figures.iter().map(|(n, _)| n.clone()).collect();

    // 7. Headline.
    let headline = headline(ch, &diss, &report_tables, &methods);
    notes.push(format!(
        "Headline (average of the per-cell average accuracies, proposed method {}):\n{}",
        methods[0].name(),
        indent(&headline)
    ));

    Ok(ChapterOutput {
        report: ChapterReport {
            generated_by: format!("cargo xtask chapter{ch}"),
            chapter: ch,
            title: title.to_string(),
            cwru_simulated: cwru_sim,
            notes,
            data: data_notes,
            tables: report_tables,
            extras,
            figures: figure_names,
            residual_rms_ratio,
        },
        figures,
        headline: format!("chapter {ch} ({}):\n{headline}", methods[0].name()),
    })
}

/// Step 1: the recordings every table needs, in the tables' order, each once.
fn recordings_needed(diss: &[&DissTable], cfg: &Config) -> Vec<RecKey> {
    let mut keys: Vec<RecKey> = Vec::new();
    for d in diss {
        for k in d.recording_keys(&cfg.scope()) {
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
    }
    keys
}

/// Step 2: the model of every healthy recording. Every model is prepared with the fuzzy model
/// and the calibrated machine model (the physics observers run on it, its one-step prediction is
/// the ARX-Laguerre models' input), whichever chapter asks first: a later chapter then reuses it.
fn prepare_models(cache: &mut Cache, healthy: &[RecKey]) -> anyhow::Result<Models> {
    let reusable = |cache: &Cache, h: &RecKey| cache.models.get(h).map(std::sync::Arc::clone);
    let made: Vec<(RecKey, std::sync::Arc<pl::Prepared>)> = healthy
        .par_iter()
        .filter(|h| reusable(cache, h).is_none())
        .map(|h| {
            let rec = cache.get(h)?;
            let p = pl::Prepared::new(cache.healthy_for(h)?, rec.fs, rec.rpm, true, true)
                .with_context(|| format!("model identification on {}", rec.id))?;
            Ok((*h, std::sync::Arc::new(p)))
        })
        .collect::<anyhow::Result<_>>()?;
    for (h, p) in made {
        cache.models.insert(h, p);
    }
    healthy
        .iter()
        .map(|h| {
            reusable(cache, h)
                .map(|p| (*h, p))
                .ok_or_else(|| anyhow::anyhow!("no model for {h:?}"))
        })
        .collect()
}

/// Step 2, reported: per healthy recording, the identified model's orders and held-out error,
/// and the calibrated machine model the physics observers run on.
fn model_notes(
    cache: &Cache,
    prepared: &Models,
    methods: &[Method],
) -> anyhow::Result<Vec<String>> {
    let fuzzy = methods
        .iter()
        .any(|m| matches!(m, Method::Afsmo | Method::Asmo | Method::SmoFuzzy));
    let physics = |m: &Method| {
        matches!(
            m,
            Method::Hostsmo | Method::Smo | Method::Flo | Method::Pflo
        )
    };
    let mut notes = Vec::new();
    for (h, p) in prepared {
        let rec = cache.get(h)?;
        let id = &rec.id;
        // the identified predictor on the rest of the healthy recording, which no
        // identification saw (the scored normal windows are cut from it)
        let fit_len = (inputs::FIT_SECONDS * rec.fs) as usize;
        let rest = match p.record_nrmse(&rec.signal, fit_len) {
            Ok((nrmse, alone)) => format!(
                " On the rest of {id} after the fit segment ({} samples, never seen by the identification), the identified model predicts one step ahead to an NRMSE of {nrmse:.3}{}.",
                rec.signal.len().saturating_sub(fit_len),
                alone.map_or(String::new(), |a| format!(
                    " (the machine model's prediction alone {a:.3})"
                ))
            ),
            Err(e) => {
                format!(" Its one-step NRMSE on the rest of {id} could not be computed: {e}.")
            }
        };
        if methods.iter().any(|m| !physics(m)) {
            notes.push(identification_note(p, id, fuzzy, &rest));
        }
        if let Some((before, after, by_loop)) = p.calibration_error {
            notes.push(format!(
                "{} the machine model calibrated on the first {} s of {id} (the closed loop from the declared healthy 5-DOF model; held-out error {before:.2} → {after:.2} dB): its structural path from bearing to sensor{}, AR order {} with {} modes, and its {} lines (shaft harmonics and tones), together as the one-step predictor of the whole model, AR order {} (docs/equations/observers.md, \"Physics observers on the calibrated machine model\").",
                if methods.iter().any(physics) {
                    "Physics observers run on"
                } else {
                    "The ARX-Laguerre models' input comes from"
                },
                inputs::FIT_SECONDS,
                if by_loop { "" } else { " (the loop added none — the declared model already explained the segment — so the path is identified from the segment directly)" },
                p.path_order,
                p.path_modes,
                p.path_lines,
                p.predictor_order
            ));
        }
    }
    Ok(notes)
}

/// The ARX-Laguerre (or fuzzy ARX-Laguerre) model identified on `id`'s fit segment: its orders,
/// the held-out error of each order tried, its poles; `rest` its error on the rest of `id`.
fn identification_note(p: &pl::Prepared, id: &str, fuzzy: bool, rest: &str) -> String {
    let scores: Vec<String> = p
        .order_scores
        .iter()
        .map(|((a, b), e)| {
            if p.n_b > 0 {
                format!("{a}/{b}: {e:.3}")
            } else {
                format!("{a}: {e:.3}")
            }
        })
        .collect();
    let what = if fuzzy {
        "Fuzzy ARX-Laguerre (eq. 5.19, Table 5.1 rules, N_f = 2, ±3σ universes; its ARX-Laguerre part)"
    } else {
        "ARX-Laguerre"
    };
    match (p.zeta_b, p.input_nrmse) {
        (Some(zeta_b), Some(alone)) if p.n_b > 0 => format!(
            "{what} model identified on the first {} s of {id} with the calibrated machine model's one-step prediction as its exogenous input u (eq. 2.33's u read as the physics model's output at the sensor; docs/equations/xtask-chapters.md, \"ARX-Laguerre on the calibrated machine model\"), after the first {:.0} % of the segment (the machine model's observer settling): (N_a, N_b) = ({}, {}) chosen by held-out one-step NRMSE on the last {:.0} % (N_a/N_b: NRMSE = {}; the machine model's prediction alone {alone:.3}), poles ζ_a = {:.4}, ζ_b = {zeta_b:.4}.{rest}",
            inputs::FIT_SECONDS,
            100.0 * pl::INPUT_SETTLE,
            p.n_a,
            p.n_b,
            100.0 * pl::ORDER_HOLDOUT,
            scores.join(", "),
            p.zeta_a
        ),
        _ => format!(
            "{what} model (AR form) identified on the first {} s of {id}: N_a = {} chosen by held-out one-step NRMSE on the last {:.0} % of that segment (N_a: NRMSE = {}), pole ζ_a = {:.4}.{rest}",
            inputs::FIT_SECONDS,
            p.n_a,
            100.0 * pl::ORDER_HOLDOUT,
            scores.join(", "),
            p.zeta_a
        ),
    }
}

/// Step 2b: the gains of every (method, healthy recording), tuned on the fit segment only (each
/// once: a later chapter reuses the cache's).
fn tune_gains(
    cache: &mut Cache,
    prepared: &Models,
    healthy: &[RecKey],
    methods: &[Method],
) -> anyhow::Result<Tunings> {
    let tune_jobs: Vec<(Method, RecKey)> = methods
        .iter()
        .flat_map(|m| healthy.iter().map(move |h| (*m, *h)))
        .collect();
    let tuned: Vec<((Method, RecKey), pl::Tuning)> = tune_jobs
        .par_iter()
        .filter(|j| !cache.tunings.contains_key(j))
        .map(|(m, h)| {
            let p = prepared.get(h).ok_or_else(|| anyhow::anyhow!("no model"))?;
            let t = p.tune(*m).with_context(|| {
                format!(
                    "tuning {} on {}",
                    m.name(),
                    cache.get(h).map(|r| r.id.as_str()).unwrap_or("?")
                )
            })?;
            Ok(((*m, *h), t))
        })
        .collect::<anyhow::Result<_>>()?;
    cache.tunings.extend(tuned);
    tune_jobs
        .iter()
        .map(|j| {
            cache
                .tunings
                .get(j)
                .map(|t| (*j, *t))
                .ok_or_else(|| anyhow::anyhow!("no tuning for {j:?}"))
        })
        .collect()
}

/// Step 3: window energies, residual trace and RMS ratio of every (source, recording), in
/// parallel, collected in order (each computed once: a later chapter reuses the cache's).
fn residual_features(
    cfg: &Config,
    ch: u8,
    cache: &mut Cache,
    keys: &[RecKey],
    sources: &[Option<Method>],
    prepared: &Models,
    tunings: &Tunings,
) -> anyhow::Result<Features> {
    let jobs: Vec<(Option<Method>, RecKey)> = sources
        .iter()
        .flat_map(|s| keys.iter().map(move |k| (*s, *k)))
        .collect();
    for k in keys {
        cache.machine_inputs.entry(*k).or_default();
    }
    let pb = progress(cfg, jobs.len() as u64, format!("chapter {ch}: observers"));
    let cache_ref: &Cache = cache;
    let results: Vec<anyhow::Result<SourceOut>> = jobs
        .par_iter()
        .map(|(src, key)| {
            let out = source_features(cache_ref, prepared, tunings, *src, key);
            pb.inc(1);
            out
        })
        .collect();
    for (job, r) in jobs.iter().zip(&results) {
        if let Ok(out) = r {
            cache.features.entry(*job).or_insert_with(|| out.clone());
        }
    }
    pb.finish_and_clear();
    let mut features = Features {
        feats: FeatMap::new(),
        traces: BTreeMap::new(),
        ratios: BTreeMap::new(),
    };
    for ((src, key), r) in jobs.iter().zip(results) {
        let (e, tr, ratio) = r?;
        features.feats.insert((source_name(*src), *key), e);
        features.traces.insert((source_name(*src), *key), tr);
        if src.is_some() {
            features.ratios.insert((source_name(*src), *key), ratio);
        }
    }
    Ok(features)
}

/// One (source, recording) of step 3: the cache's when computed before, else the observer (or
/// the raw signal) on the recording with its healthy model's gains, the machine model's input
/// computed once per recording.
fn source_features(
    cache: &Cache,
    prepared: &Models,
    tunings: &Tunings,
    src: Option<Method>,
    key: &RecKey,
) -> anyhow::Result<SourceOut> {
    if let Some(done) = cache.features.get(&(src, *key)) {
        return Ok(done.clone());
    }
    let rec = cache.get(key)?;
    let hk = inputs::healthy_key(key);
    let prep = prepared
        .get(&hk)
        .ok_or_else(|| anyhow::anyhow!("no model for {}", rec.id))?;
    let method = match src {
        Some(m) => {
            let t = tunings
                .get(&(m, hk))
                .ok_or_else(|| anyhow::anyhow!("no tuning for {}", rec.id))?;
            Some((m, prep.as_ref(), t))
        }
        None => None,
    };
    let input = match method {
        Some((m, p, _)) if p.takes_input(m) => {
            let cell = cache
                .machine_inputs
                .get(key)
                .ok_or_else(|| anyhow::anyhow!("no input cell for {}", rec.id))?;
            let made = cell.get_or_init(|| {
                p.machine_input(&rec.signal)
                    .map(|u| u.map(std::sync::Arc::new))
                    .map_err(|e| e.to_string())
            });
            match made {
                Ok(u) => u.clone(),
                Err(e) => anyhow::bail!("the machine model's input on {}: {e}", rec.id),
            }
        }
        _ => None,
    };
    let f = pl::recordings::source_features(method, rec, input.as_deref().map(|u| u.as_slice()))
        .with_context(|| format!("{} on recording {}", source_name(src), rec.id))?;
    Ok((f.energies, f.trace, f.rms_ratio))
}

/// Step 4: every (table, protocol, source, crack) cell, classified in parallel and collected in
/// the tables' order. The SVM chapters classify the energy as printed and, beside it on the
/// CWRU tables, in dB.
fn classify_tables(
    cfg: &Config,
    ch: u8,
    cache: &Cache,
    diss: &[&DissTable],
    sources: &[Option<Method>],
    clf: ClassifierKind,
    feats: &FeatMap,
) -> anyhow::Result<Vec<OurTable>> {
    let pb = progress(cfg, 1, format!("chapter {ch}: classifiers"));
    let kinds = |d: &DissTable| -> Vec<ClassifierKind> {
        match clf {
            ClassifierKind::Svm if d.dataset == "cwru" => vec![clf, ClassifierKind::SvmLogEnergy],
            _ => vec![clf],
        }
    };
    let mut cell_jobs = Vec::new();
    for (di, d) in diss.iter().enumerate() {
        for protocol in d.protocols() {
            for (si, _) in sources.iter().enumerate() {
                for ci in 0..d.cracks.len() {
                    for kind in kinds(d) {
                        cell_jobs.push((di, protocol, si, ci, kind));
                    }
                }
            }
        }
    }
    pb.set_length(cell_jobs.len() as u64);
    let cells: Vec<anyhow::Result<Cell>> = cell_jobs
        .par_iter()
        .map(|&(di, protocol, si, ci, kind)| {
            let d = diss[di];
            let name = source_name(sources[si]);
            let src = Src {
                cache,
                feats,
                source: &name,
            };
            let r = pl::cells::evaluate_table_cell(
                d,
                &cfg.scope(),
                &src,
                ci,
                protocol,
                cfg.seeds,
                kind,
            )
            .with_context(|| format!("table {} {} crack {}", d.id, name, d.cracks[ci]));
            pb.inc(1);
            r
        })
        .collect();
    let mut it = cell_jobs.iter().zip(cells);
    let mut report_tables = Vec::new();
    for d in diss {
        for protocol in d.protocols() {
            let mut cols = Vec::new();
            for src in sources {
                let (mut cs, mut cs_db) = (Vec::new(), Vec::new());
                for _ in 0..d.cracks.len() {
                    for _ in kinds(d) {
                        let (&(.., kind), c) = it
                            .next()
                            .ok_or_else(|| anyhow::anyhow!("cell bookkeeping"))?;
                        if kind == ClassifierKind::SvmLogEnergy {
                            cs_db.push(c?);
                        } else {
                            cs.push(c?);
                        }
                    }
                }
                cols.push(SourceColumns {
                    source: source_name(*src),
                    in_dissertation: src.is_some(),
                    cells: cs,
                    cells_db: cs_db,
                });
            }
            report_tables.push(OurTable {
                table: d.id.clone(),
                protocol,
                protocol_note: protocol_note(cfg, d, protocol),
                sources: cols,
            });
        }
    }
    pb.finish_and_clear();
    Ok(report_tables)
}

/// A chapter's extra section: a title and its text.
type Extra = (String, String);
/// A figure: its path under the chapter's results and its PNG bytes.
type Figure = (String, Vec<u8>);

/// Step 5 (chapter 5): the rules the tree learned (eqs 5.35–5.36, Fig. 5.8) for the largest
/// crack at the last load run (3 hp, or the quick configuration's load), and the tree's figure
/// when figures are drawn; `None` when no CWRU table runs at that load.
fn learned_rules(
    cfg: &Config,
    cache: &Cache,
    diss: &[&DissTable],
    feats: &FeatMap,
    methods: &[Method],
) -> anyhow::Result<Option<(Extra, Option<Figure>)>> {
    let Some(d) = diss.iter().find(|d| {
        d.dataset == "cwru"
            && matches!(d.condition, Condition::FixedLoad { load_hp } if load_hp == *cfg.loads.last().unwrap_or(&3))
    }) else {
        return Ok(None);
    };
    let ci = d.cracks.len() - 1;
    let data = cell_dataset(cfg, cache, d, feats, methods[0].name(), Some(ci))?;
    let labels = data.class_names().to_vec();
    let (rules, tree) = pl::tree_rules(&data)?;
    let load = match d.condition {
        Condition::FixedLoad { load_hp } => load_hp,
        _ => 0,
    };
    let extra = (
        format!(
            "Learned decision rules (eqs 5.35–5.36, Fig. 5.8): {} residual energy, {} in, {} hp, all windows",
            methods[0].name(),
            d.cracks[ci],
            load
        ),
        rules,
    );
    let figure = if cfg.figures {
        Some((
            "figures/fig5_8_decision_tree.png".to_string(),
            super::figures::decision_tree(&tree, &labels)?,
        ))
    } else {
        None
    };
    Ok(Some((extra, figure)))
}

fn indent(s: &str) -> String {
    s.lines()
        .map(|l| format!("    {l}"))
        .collect::<Vec<_>>()
        .join("\n")
}

fn source_name(s: Option<Method>) -> String {
    match s {
        Some(m) => m.name().to_string(),
        None => "raw signal".to_string(),
    }
}

fn progress(cfg: &Config, n: u64, msg: String) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(
        Some(n),
        if cfg.progress {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    if let Ok(style) = ProgressStyle::with_template("{msg:32} [{bar:30}] {pos}/{len} {elapsed}") {
        pb.set_style(style.progress_chars("=> "));
    }
    pb.set_message(msg);
    pb
}
