//! What each chapter runs: the methods, the datasets behind each dissertation table, and the
//! evaluation protocols; the per-cell classification loop.
//!
//! Every cell of a dissertation table is one classification problem (the table's classes at one
//! load or speed and one crack size). Features are window energies of the residual (eqs 2.46,
//! 3.26, 4.31, 5.33), one window length for every class. The classifier is the one-vs-one linear
//! SVM (chapters 2–4) or the Gini decision tree (chapter 5), both from the `classify` crate.

use super::inputs::{self, Cache, RecKey};
use super::report::{
    Cell, ChapterReport, DataNote, OurTable, ResidualRatios, SourceColumns, class_label, pct,
    protocol_key,
};
use crate::common::Context;
use ::pipeline::dissertation::{self as tables, Condition, DissTable};
use ::pipeline::{self as pl, ClassifierKind, Method, Protocol};
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
type SourceOut = (Vec<f64>, Vec<f64>, f64);

/// Features of one (source, recording): window energies.
type FeatMap = BTreeMap<(String, RecKey), Vec<f64>>;

/// Run one chapter.
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

    // 1. Recordings every table needs.
    let mut keys: Vec<RecKey> = Vec::new();
    for d in &diss {
        for k in d.recording_keys(&cfg.scope()) {
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
    }
    let t0 = std::time::Instant::now();
    let stage = |what: &str| {
        if cfg.progress {
            eprintln!(
                "chapter {ch}: {what} done at {:.1} s",
                t0.elapsed().as_secs_f64()
            );
        }
    };
    let pb = progress(cfg, keys.len() as u64, format!("chapter {ch}: recordings"));
    cache.load_all(ctx, cfg, &keys, &pb)?;
    pb.finish_and_clear();
    stage("recordings");

    // 2. Models identified on each healthy fit segment (once per healthy recording).
    let mut healthy: Vec<RecKey> = keys.iter().map(inputs::healthy_key).collect();
    healthy.sort();
    healthy.dedup();
    let fuzzy = methods
        .iter()
        .any(|m| matches!(m, Method::Afsmo | Method::Asmo | Method::SmoFuzzy));
    let physics = methods.iter().any(|m| {
        matches!(
            m,
            Method::Hostsmo | Method::Smo | Method::Flo | Method::Pflo
        )
    });
    let prepared: BTreeMap<RecKey, pl::Prepared> = healthy
        .par_iter()
        .map(|h| {
            let rec = cache.get(h)?;
            let p = pl::Prepared::new(cache.healthy_for(h)?, rec.fs, rec.rpm, fuzzy, physics)
                .with_context(|| format!("model identification on {}", rec.id))?;
            Ok((*h, p))
        })
        .collect::<anyhow::Result<_>>()?;

    for (h, p) in &prepared {
        let id = &cache.get(h)?.id;
        if methods.iter().any(|m| {
            !matches!(
                m,
                Method::Hostsmo | Method::Smo | Method::Flo | Method::Pflo
            )
        }) {
            let scores: Vec<String> = p
                .order_scores
                .iter()
                .map(|(n, e)| format!("{n}: {e:.3}"))
                .collect();
            notes.push(format!(
                "{} model (AR form) identified on the first {} s of {id}: N_a = {} chosen by held-out one-step NRMSE on the last {:.0} % of that segment (N_a: NRMSE = {}), pole ζ_a = {:.4}.",
                if fuzzy { "Fuzzy ARX-Laguerre (eq. 5.19, Table 5.1 rules, N_f = 2, ±3σ universes; its ARX-Laguerre part)" } else { "ARX-Laguerre" },
                inputs::FIT_SECONDS,
                p.n_a,
                100.0 * pl::ORDER_HOLDOUT,
                scores.join(", "),
                p.zeta_a
            ));
        }
        if let Some((before, after, by_loop)) = p.calibration_error {
            notes.push(format!(
                "Physics observers run on the machine model calibrated on the first {} s of {id} (the closed loop from the declared healthy 5-DOF model; held-out error {before:.2} → {after:.2} dB): its structural path from bearing to sensor{}, AR order {} with {} modes, and its {} lines (shaft harmonics and tones), together as the one-step predictor of the whole model, AR order {} (docs/equations/observers.md, \"Physics observers on the calibrated machine model\").",
                inputs::FIT_SECONDS,
                if by_loop { "" } else { " (the loop added none — the declared model already explained the segment — so the path is identified from the segment directly)" },
                p.path_order,
                p.path_modes,
                p.path_lines,
                p.predictor_order
            ));
        }
    }

    // 2b. Gains tuned per (method, healthy recording) on the fit segment only.
    let tune_jobs: Vec<(Method, RecKey)> = methods
        .iter()
        .flat_map(|m| healthy.iter().map(move |h| (*m, *h)))
        .collect();
    let tunings: BTreeMap<(Method, RecKey), pl::Tuning> = tune_jobs
        .par_iter()
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
    stage("models and tuning");

    // 3. Residual features for every (source, recording), in parallel, collected in order.
    let mut sources: Vec<Option<Method>> = methods.iter().copied().map(Some).collect();
    sources.push(None);
    let jobs: Vec<(Option<Method>, RecKey)> = sources
        .iter()
        .flat_map(|s| keys.iter().map(move |k| (*s, *k)))
        .collect();
    let pb = progress(cfg, jobs.len() as u64, format!("chapter {ch}: observers"));
    let results: Vec<anyhow::Result<SourceOut>> = jobs
        .par_iter()
        .map(|(src, key)| {
            let rec = cache.get(key)?;
            let hk = inputs::healthy_key(key);
            let prep = prepared
                .get(&hk)
                .ok_or_else(|| anyhow::anyhow!("no model for {}", rec.id))?;
            let method = match src {
                Some(m) => {
                    let t = tunings
                        .get(&(*m, hk))
                        .ok_or_else(|| anyhow::anyhow!("no tuning for {}", rec.id))?;
                    Some((*m, prep, t))
                }
                None => None,
            };
            let f = pl::recordings::source_features(method, rec)
                .with_context(|| format!("{} on recording {}", source_name(*src), rec.id))?;
            pb.inc(1);
            Ok((f.energies, f.trace, f.rms_ratio))
        })
        .collect();
    pb.finish_and_clear();
    stage("observers");
    let mut feats = FeatMap::new();
    let mut traces: BTreeMap<(String, RecKey), Vec<f64>> = BTreeMap::new();
    let mut ratios: BTreeMap<(String, RecKey), f64> = BTreeMap::new();
    for ((src, key), r) in jobs.iter().zip(results) {
        let (e, tr, ratio) = r?;
        feats.insert((source_name(*src), *key), e);
        traces.insert((source_name(*src), *key), tr);
        if src.is_some() {
            ratios.insert((source_name(*src), *key), ratio);
        }
    }

    // 3. Tables.
    let mut report_tables = Vec::new();
    let mut data_notes = Vec::new();
    let mut figures = Vec::new();
    let (tuning_extra, residual_rms_ratio) = tuning_section(&methods, &tunings, &ratios, cache)?;
    let mut extras = vec![tuning_extra];
    let pb = progress(cfg, 1, format!("chapter {ch}: classifiers"));
    for d in &diss {
        data_notes.push(data_note(cfg, cache, d, &feats, &methods)?);
    }
    // Every (table, protocol, source, crack) cell is independent: run them in parallel and
    // collect in order.
    // The SVM chapters classify the energy as printed and, beside it on the CWRU tables, in dB.
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
                feats: &feats,
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
    for d in &diss {
        for protocol in d.protocols() {
            let mut cols = Vec::new();
            for src in &sources {
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
    stage("classifiers");

    // 4. Chapter 5: the learned rules (eqs 5.35–5.36, Fig. 5.8) for 0.021 in at 3 hp (or the
    // quick configuration's load).
    if clf == ClassifierKind::Tree {
        if let Some(d) = diss.iter().find(|d| {
            d.dataset == "cwru"
                && matches!(d.condition, Condition::FixedLoad { load_hp } if load_hp == *cfg.loads.last().unwrap_or(&3))
        }) {
            let ci = d.cracks.len() - 1;
            let data = cell_dataset(cfg, cache, d, &feats, methods[0].name(), Some(ci))?;
            let labels = data.class_names().to_vec();
            let (rules, tree) = pl::tree_rules(&data)?;
            let load = match d.condition {
                Condition::FixedLoad { load_hp } => load_hp,
                _ => 0,
            };
            extras.push((
                format!(
                    "Learned decision rules (eqs 5.35–5.36, Fig. 5.8): {} residual energy, {} in, {} hp, all windows",
                    methods[0].name(),
                    d.cracks[ci],
                    load
                ),
                rules,
            ));
            if cfg.figures {
                figures.push((
                    "figures/fig5_8_decision_tree.png".to_string(),
                    super::figures::decision_tree(&tree, &labels)?,
                ));
            }
        }
    }

    // 5. Figures.
    if cfg.figures {
        figures.extend(super::figures::chapter_figures(
            ch,
            cache,
            &diss,
            &report_tables,
            &feats,
            &traces,
            &methods,
        )?);
    }
    let figure_names: Vec<String> = figures.iter().map(|(n, _)| n.clone()).collect();

    // 6. Headline.
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

/// A source's window energies and recording ids, as the library's cells read them.
struct Src<'a> {
    cache: &'a Cache,
    feats: &'a FeatMap,
    source: &'a str,
}

impl pl::cells::CellSource for Src<'_> {
    fn id(&self, k: &RecKey) -> pl::Result<String> {
        self.cache
            .get(k)
            .map(|r| r.id.clone())
            .map_err(|e| pl::PipelineError::Missing {
                what: e.to_string(),
            })
    }
    fn energies(&self, k: &RecKey) -> pl::Result<&[f64]> {
        self.feats
            .get(&(self.source.to_string(), *k))
            .map(Vec::as_slice)
            .ok_or_else(|| pl::PipelineError::Missing {
                what: format!("window energies of {} on {k:?}", self.source),
            })
    }
}

/// The dataset of one cell (one crack size `ci`, or every size with `ci = None`), classes named
/// by their table labels.
fn cell_dataset(
    cfg: &Config,
    cache: &Cache,
    d: &DissTable,
    feats: &FeatMap,
    source: &str,
    ci: Option<usize>,
) -> anyhow::Result<pl::Dataset> {
    let src = Src {
        cache,
        feats,
        source,
    };
    Ok(pl::cells::table_cell_dataset(d, &cfg.scope(), &src, ci)?)
}

fn protocol_note(cfg: &Config, d: &DissTable, p: Protocol) -> String {
    let cond = if d.is_cwru() { "load" } else { "speed" };
    let pooled = matches!(
        d.condition,
        Condition::LoadVariant | Condition::SpeedVariant
    );
    match p {
        Protocol::RandomWindows => format!(
            "Windows of all recordings of the cell pooled, stratified random split 75 % train / 25 % test per class, repeated over {} seeds; per-class accuracy from the confusion matrix summed over seeds. Neighbouring windows of one recording land on both sides, so this protocol measures recognition of recordings seen in training.",
            cfg.seeds
        ),
        Protocol::TimeBlocked => "Each recording's first 75 % of windows train, its last 25 % test (one fold). Still one recording per class on both sides, but no test window is interleaved with training windows.".to_string(),
        Protocol::LeaveOneFaultSizeOut => {
            let n = if d.is_cwru() { "97 (the single normal recording)" } else { "the simulated normal recording" };
            format!(
                "Column = the crack size held out: faults of the other {} train, faults of this size test{}. The normal class has no size: {n} is split in time (first 75 % of its windows train, last 25 % test) — the only way it can appear on both sides.",
                if d.cracks.len() == 2 { "size" } else { "two sizes" },
                if pooled { format!(", every {cond} pooled") } else { String::new() }
            )
        }
        Protocol::LeaveOneLoadOut | Protocol::LeaveOneSpeedOut | Protocol::GroupedByRecording => {
            if pooled {
                let normal = if d.is_cwru() {
                    "The normal class is one recording (97, 0 hp, 48 kHz decimated to 12 kHz) reused at every load: it is cut into one contiguous segment per load, and the held-out load's segment tests."
                } else {
                    "The normal class has its own simulated recording at each speed."
                };
                format!(
                    "Grouped by recording: one fold per {cond}; train on the other {cond}s, test on the held-out one; confusions summed over folds, spread over folds. With one recording per class and {cond}, grouping by recording is leaving one {cond} out. {normal}"
                )
            } else {
                format!(
                    "Not applicable within one {cond}: each class has one recording, so holding a recording out removes its class from training. See the {cond}-variant table (2.7, 3.5, 4.6, 5.6; 4.11, 5.11) for the grouped protocol."
                )
            }
        }
    }
}

fn base_notes(cfg: &Config, ch: u8, clf: ClassifierKind, cwru_sim: bool) -> Vec<String> {
    let mut n = Vec::new();
    if cfg.quick {
        n.push(format!(
            "QUICK configuration (for the `--check` test, not for reading): load {:?} hp and {:?} rpm only, at most {} windows per recording, {} seeds, no figures.",
            cfg.loads, cfg.rpms, cfg.windows_per_rec, cfg.seeds
        ));
    }
    n.push(format!(
        "Feature: the energy Σr² of non-overlapping windows of {} samples (eqs 2.46 / 3.26 / 4.31 / 5.33), the same length for every class; at most {} windows per recording (the dissertation's 400 per class), taken from the start of the scored segment.",
        cfg.window_len, cfg.windows_per_rec
    ));
    n.push(match clf {
        ClassifierKind::Svm => "Classifier: one-vs-one linear SVM (`classify` crate, linfa-svm), features standardised on the training split. Beside it, on the CWRU tables, the same SVM on the energy in dB (10·log10 E; column `ours_db` of tables.csv / tables.json, lines \"E in dB\" of the headline): not the dissertation's feature, reported because the scale alone moves the accuracies by several points and changes which protocol the observers help (docs/equations/xtask-chapters.md, \"The energy's scale\").".to_string(),
        ClassifierKind::Tree => "Classifier: Gini decision tree (`classify` crate, linfa-trees), eq. 5.34.".to_string(),
        ClassifierKind::SvmLogEnergy => "Classifier: one-vs-one linear SVM on log10 of the window energy (the energy in dB).".to_string(),
    });
    n.push(format!(
        "CWRU data: 12 kHz drive-end recordings (DE channel) at loads 0–3 hp; fault recordings OR at 6 o'clock. {}",
        if cwru_sim {
            "NOT FOUND: every CWRU table ran on simulated CWRU-like recordings from `bearing-model`."
        } else {
            "The only normal recording is 97.mat (0 hp, 48 kHz): it is decimated by 4 to 12 kHz and reused as the normal class at 1, 2 and 3 hp."
        }
    ));
    n.push(format!(
        "Model fitting: every observer model (ARX-Laguerre, fuzzy ARX-Laguerre, and the machine model the physics observers run on) is identified or calibrated on the first {} s of the healthy recording only; normal windows are cut only after that segment, so no scored window was seen by the identification or the calibration.",
        inputs::FIT_SECONDS
    ));
    n.push("Pooled (load- or speed-variant) tables keep every n-th window of each fault recording (n = number of pooled conditions), so every class has about as many windows as in a single-condition cell; the normal recording, shared by all conditions, keeps all its windows, cut into one contiguous segment per condition.".to_string());
    n.push(format!(
        "Dissertation values: {}.",
        tables::transcription().source
    ));
    if ch >= 4 {
        n.push(format!("Multi-fault substitute windows: {} samples at {} Hz ({} ms), at most {} per recording (simulation cost).", inputs::MULTI_WINDOW, inputs::MULTI_FS, inputs::MULTI_WINDOW as f64 / inputs::MULTI_FS * 1000.0, if cfg.quick { cfg.windows_per_rec.min(inputs::MULTI_WINDOWS) } else { inputs::MULTI_WINDOWS }));
        n.push("Multi-fault tables (4.7–4.11, 5.7–5.11): the SHSE Lab data is not public. These tables run on a SIMULATED substitute: the calibrated CWRU rig (`close_loop::rig`, results/calibration/: the 5-DOF model's spalls behind the paths measured on the CWRU rig, the healthy machine of 97, units g; combined faults as the superposition of the spalls' responses) at the dissertation's conditions (eight classes: normal, IR, OR, ball, IR-OR, IR-ball, OR-ball, IR-OR-ball; 300/400/450/500 rpm; 3 and 6 mm faults — beyond the largest calibrated spall, 0.71 mm, whose severity is held; the background level calibrated at 1797 rpm is held at the lower speeds). The dissertation's data was acoustic emission at 250 kHz; ours is simulated vibration at 12 kHz. Calibrated to measured signal statistics only, never to an accuracy. They are labelled as simulated everywhere and are not measurements.".to_string());
    }
    n.push("Dissertation protocol inconsistency: the text says 1600 windows = 1200 train + 400 test, yet \"75 instances per class\" train and \"100\" (ch. 2–3) or \"25\" (ch. 4) test per class; we use the 75 % / 25 % split of 400 windows per class that the totals imply.".to_string());
    n
}

fn data_note(
    cfg: &Config,
    cache: &Cache,
    d: &DissTable,
    feats: &FeatMap,
    methods: &[Method],
) -> anyhow::Result<DataNote> {
    let mut recs = Vec::new();
    let conds = d.conditions(&cfg.scope());
    for c in &d.classes {
        let cracks: Vec<usize> = if c == "normal" {
            vec![0]
        } else {
            (0..d.cracks.len()).collect()
        };
        for ci in cracks {
            let ids: Vec<String> = conds
                .iter()
                .map(|&cd| cache.get(&d.recording_key(c, cd, ci)).map(|r| r.id.clone()))
                .collect::<anyhow::Result<_>>()?;
            let mut ids2 = Vec::new();
            for i in ids {
                if !ids2.contains(&i) {
                    ids2.push(i);
                }
            }
            let crack = if c == "normal" {
                "all".to_string()
            } else {
                d.cracks[ci].clone()
            };
            recs.push((c.clone(), crack, ids2));
        }
    }
    let w = cell_dataset(cfg, cache, d, feats, methods[0].name(), Some(0))?;
    let mut per = vec![0usize; d.classes.len()];
    for m in w.meta() {
        per[m.class] += 1;
    }
    let text = if d.is_cwru() {
        let sim = cache.cwru_simulated();
        format!(
            "{}CWRU 12 kHz drive-end, {}. Windows per class (first crack size): {}. Normal = 97.mat (0 hp, 48 kHz → 12 kHz by 4){}.",
            if sim {
                "SIMULATED CWRU-like recordings (data absent), "
            } else {
                ""
            },
            match d.condition {
                Condition::FixedLoad { load_hp } => format!("{load_hp} hp"),
                _ => format!("loads {:?} hp pooled", cfg.loads),
            },
            d.classes
                .iter()
                .zip(&per)
                .map(|(c, n)| format!("{} {n}", class_label(c)))
                .collect::<Vec<_>>()
                .join(", "),
            match d.condition {
                Condition::FixedLoad { load_hp } if load_hp > 0 =>
                    ", reused at this load (no normal recording at 1–3 hp in the shared data)",
                Condition::LoadVariant =>
                    ", reused for every load as one contiguous segment per load",
                _ => "",
            }
        )
    } else {
        format!(
            "SIMULATED substitute for the private SHSE data ({}), the calibrated CWRU rig (5-DOF spalls behind the measured paths, g; simulated vibration, not the dissertation's 250 kHz acoustic emission), {} Hz. Windows per class: {}. Crack sizes 3 and 6 mm.",
            match d.condition {
                Condition::FixedSpeed { rpm } => format!("{rpm} rpm"),
                _ => format!("speeds {:?} rpm pooled", cfg.rpms),
            },
            inputs::MULTI_FS,
            d.classes
                .iter()
                .zip(&per)
                .map(|(c, n)| format!("{} {n}", class_label(c)))
                .collect::<Vec<_>>()
                .join(", "),
        )
    };
    Ok(DataNote {
        table: d.id.clone(),
        text,
        recordings: recs,
        windows_per_class: per,
        window_len: cfg.window_len,
    })
}

/// Mean over tables' cells of the proposed method's average accuracy, per protocol, beside the
/// dissertation's mean.
fn headline(ch: u8, diss: &[&DissTable], tabs: &[OurTable], methods: &[Method]) -> String {
    let mut s = String::new();
    for dataset in ["cwru", "shse_multi"] {
        let ds: Vec<&&DissTable> = diss.iter().filter(|d| d.dataset == dataset).collect();
        if ds.is_empty() {
            continue;
        }
        let label = if dataset == "cwru" {
            "CWRU"
        } else {
            "simulated multi-fault substitute"
        };
        for (m, db) in [false, true].into_iter().flat_map(|db| {
            methods
                .iter()
                .map(|m| m.name().to_string())
                .chain(["raw signal".to_string()])
                .map(move |m| (m, db))
        }) {
            let mut parts = Vec::new();
            let diss_vals: Vec<f64> = ds
                .iter()
                .flat_map(|d| {
                    (0..d.cracks.len())
                        .filter_map(|ci| d.avg(&m, ci))
                        .collect::<Vec<_>>()
                })
                .collect();
            if !diss_vals.is_empty() && !db {
                parts.push(format!(
                    "dissertation {}",
                    pct(diss_vals.iter().sum::<f64>() / diss_vals.len() as f64)
                ));
            }
            for key in [
                Protocol::RandomWindows,
                Protocol::TimeBlocked,
                Protocol::LeaveOneFaultSizeOut,
                Protocol::LeaveOneLoadOut,
            ]
            .map(protocol_key)
            {
                let vals: Vec<f64> = tabs
                    .iter()
                    .filter(|t| {
                        protocol_key(t.protocol) == key && ds.iter().any(|d| d.id == t.table)
                    })
                    .flat_map(|t| t.sources.iter().filter(|c| c.source == m))
                    .flat_map(|c| {
                        if db {
                            c.cells_db.iter()
                        } else {
                            c.cells.iter()
                        }
                    })
                    .filter_map(|c| match c {
                        Cell::Measured(o) => Some(o.average),
                        Cell::NotApplicable(_) => None,
                    })
                    .collect();
                if !vals.is_empty() {
                    parts.push(format!(
                        "{} {}",
                        key,
                        pct(vals.iter().sum::<f64>() / vals.len() as f64)
                    ));
                }
            }
            if parts.is_empty() {
                continue;
            }
            let m = if db { format!("{m}, E in dB") } else { m };
            s.push_str(&format!("  ch{ch} {label}, {m}: {}\n", parts.join(", ")));
        }
    }
    s
}

/// The gains each observer got from the fit segment, and what its residual does per class:
/// RMS(residual) / RMS(signal) over the scored windows, mean over the recordings of the class.
fn tuning_section(
    methods: &[Method],
    tunings: &BTreeMap<(Method, RecKey), pl::Tuning>,
    ratios: &BTreeMap<(String, RecKey), f64>,
    cache: &Cache,
) -> anyhow::Result<((String, String), ResidualRatios)> {
    use std::fmt::Write as _;
    let mut b = String::new();
    let mut healthy_ratio = ResidualRatios::new();
    let _ = writeln!(
        b,
        "Gains are set on the healthy fit segment only (rule: docs/equations/xtask-chapters.md). The bound of eqs 2.44 / 3.21 / 4.20–4.29 / 5.28 is measured first on the segment's first half: Γ₀ = RMS(Δᵐ⁻¹û), û the lumped uncertainty of the same model under its linear (PI) law (its extended state d̂₀ plus its residual r₀) averaged over one shaft revolution, so that the unpredictable innovation averages out (m = 3 for Levant laws, 2 otherwise); then Γ = Γ₀ (no search over c: on a healthy segment any sliding injection beyond the uncertainty adds to the one-step error, so a search would run to the smallest c it is offered; only when no linear design runs the law stably with Γ₀ are the fallbacks c = {:?} tried in that order, and the c used is in the table) and the linear design default, `for_recordings` or innovations (K_p = b_y: the identified one-step predictor itself), whichever gives the smallest residual RMS on the segment's second half without growing (linear laws have no Γ). No test window and no label is used.\n",
        &pl::GAMMA_MULTIPLES[1..]
    );
    let _ = writeln!(
        b,
        "| Observer | Healthy fit segment | Γ₀ (measured bound) | c (Γ = c·Γ₀) | m | Linear design | Fit-segment RMS(r)/RMS(y) | Growth (last/2nd quarter) |"
    );
    let _ = writeln!(b, "|---|---|---|---|---|---|---|---|");
    for m in methods {
        for ((tm, h), t) in tunings.iter().filter(|((tm, _), _)| tm == m) {
            let _ = writeln!(
                b,
                "| {} | {} | {} | {} | {} | {} | {:.3} | {:.2} |",
                tm.name(),
                cache.get(h)?.id,
                if t.multiple.is_some() {
                    format!("{:.3e}", t.bound)
                } else {
                    "—".into()
                },
                t.multiple.map_or("—".to_string(), |c| c.to_string()),
                if t.multiple.is_some() {
                    t.order.to_string()
                } else {
                    "—".into()
                },
                t.design,
                t.fit_ratio,
                t.growth
            );
        }
    }
    let flat: Vec<String> = tunings
        .iter()
        .filter(|(_, t)| t.fit_ratio >= 0.95)
        .map(|((m, h), _)| Ok(format!("{} on {}", m.name(), cache.get(h)?.id)))
        .collect::<anyhow::Result<_>>()?;
    if !flat.is_empty() {
        let _ = writeln!(
            b,
            "\n**Observers that predict almost nothing of the healthy signal** (fit-segment ratio ≥ 0.95, whatever Γ and design): {}. Their residual is essentially the signal, so their energy feature, and their accuracy, is essentially the raw signal's.",
            flat.join(", ")
        );
    }
    let mut datasets: Vec<&str> = Vec::new();
    for (_, k) in ratios.keys() {
        let ds = k.dataset();
        if !datasets.contains(&ds) {
            datasets.push(ds);
        }
    }
    for ds in datasets {
        let mut labels: Vec<(usize, String)> = ratios
            .keys()
            .map(|(_, k)| k)
            .filter(|k| k.dataset() == ds)
            .map(|k| (k.class_index(), k.class_label()))
            .collect();
        labels.sort();
        labels.dedup();
        let _ = writeln!(
            b,
            "\nRMS(residual) / RMS(signal) over the scored windows, {ds}, mean over the recordings of each class (1 = the observer predicts nothing; a residual ≈ the signal makes the observer's energy feature the raw signal's):\n"
        );
        let _ = writeln!(
            b,
            "| Observer | {} |",
            labels
                .iter()
                .map(|(_, l)| l.as_str())
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(b, "|---|{}", "---|".repeat(labels.len()));
        for m in methods {
            let mut row = Vec::new();
            for (ci, _) in &labels {
                let v: Vec<f64> = ratios
                    .iter()
                    .filter(|((s, k), _)| {
                        s == m.name() && k.dataset() == ds && k.class_index() == *ci
                    })
                    .map(|(_, r)| *r)
                    .collect();
                row.push(if v.is_empty() {
                    "—".to_string()
                } else {
                    let mean = v.iter().sum::<f64>() / v.len() as f64;
                    if *ci == 0 {
                        healthy_ratio
                            .entry(ds.to_string())
                            .or_default()
                            .insert(m.name().to_string(), (mean * 1000.0).round() / 1000.0);
                    }
                    format!("{mean:.3}")
                });
            }
            let _ = writeln!(b, "| {} | {} |", m.name(), row.join(" | "));
        }
    }
    Ok((
        (
            "Observer gains and residual size (what each observer does)".to_string(),
            b,
        ),
        healthy_ratio,
    ))
}
