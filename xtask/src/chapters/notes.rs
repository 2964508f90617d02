//! The chapter report's text: the chapter's notes, each table's protocol and data notes, the
//! observer-gain section and the headline.

use super::cells::cell_dataset;
use super::inputs::{self, Cache, RecKey};
use super::report::{Cell, DataNote, OurTable, ResidualRatios, class_label, pct, protocol_key};
use super::run::{Config, FeatMap};
use ::pipeline::dissertation::{self as tables, Condition, DissTable};
use ::pipeline::{self as pl, ClassifierKind, Method, Protocol};
use std::collections::BTreeMap;

pub fn protocol_note(cfg: &Config, d: &DissTable, p: Protocol) -> String {
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

pub fn base_notes(cfg: &Config, ch: u8, clf: ClassifierKind, cwru_sim: bool) -> Vec<String> {
    let mut n = Vec::new();
    if cfg.quick {
        n.push(format!(
            "QUICK configuration (for the `--check` test, not for reading): load {:?} hp and {:?} rpm only, at most {} windows per recording, {} seeds, no figures.",
            cfg.loads, cfg.rpms, cfg.windows_per_rec, cfg.seeds
        ));
    }
    n.push(format!(
        "Feature: the energy Σr² of non-overlapping windows of {} samples (eqs 2.46 / 3.26 / 4.31 / 5.33), in g² (the CWRU values read as g, and the simulated substitute in the same units: results/calibration/README.md, \"Units\"), the same length for every class; at most {} windows per recording (the dissertation's 400 per class), taken from the start of the scored segment.",
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
        n.push("Multi-fault tables (4.7–4.11, 5.7–5.11): the SHSE Lab data is not public. These tables run on a SIMULATED substitute: the calibrated CWRU rig (`calibrated_rig`, results/calibration/: the 5-DOF model's spalls behind the paths measured on the CWRU rig, the healthy machine of 97, units g; combined faults as the superposition of the spalls' responses) at the dissertation's conditions (eight classes: normal, IR, OR, ball, IR-OR, IR-ball, OR-ball, IR-OR-ball; 300/400/450/500 rpm; 3 and 6 mm faults — beyond the largest calibrated spall, 0.71 mm, whose severity is held; the background level calibrated at 1797 rpm is held at the lower speeds). The dissertation's data was acoustic emission at 250 kHz; ours is simulated vibration at 12 kHz. Calibrated to measured signal statistics only, never to an accuracy. They are labelled as simulated everywhere and are not measurements.".to_string());
    }
    n.push("Dissertation protocol inconsistency: the text says 1600 windows = 1200 train + 400 test, yet \"75 instances per class\" train and \"100\" (ch. 2–3) or \"25\" (ch. 4) test per class; we use the 75 % / 25 % split of 400 windows per class that the totals imply.".to_string());
    n
}

pub fn data_note(
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
    let per_class = d
        .classes
        .iter()
        .zip(&per)
        .map(|(c, n)| format!("{} {n}", class_label(c)))
        .collect::<Vec<_>>()
        .join(", ");
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
            per_class,
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
            per_class,
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
pub fn headline(ch: u8, diss: &[&DissTable], tabs: &[OurTable], methods: &[Method]) -> String {
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
pub fn tuning_section(
    methods: &[Method],
    tunings: &BTreeMap<(Method, RecKey), pl::Tuning>,
    ratios: &BTreeMap<(String, RecKey), f64>,
    cache: &Cache,
) -> anyhow::Result<((String, String), ResidualRatios)> {
    let mut b = gains_table(methods, tunings, cache)?;
    let (tables, healthy_ratio) = residual_ratio_tables(methods, ratios);
    b += &tables;
    Ok((
        (
            "Observer gains and residual size (what each observer does)".to_string(),
            b,
        ),
        healthy_ratio,
    ))
}

/// The tuning rule, each observer's gains on each healthy fit segment, and the observers that
/// predict almost nothing of it.
fn gains_table(
    methods: &[Method],
    tunings: &BTreeMap<(Method, RecKey), pl::Tuning>,
    cache: &Cache,
) -> anyhow::Result<String> {
    use std::fmt::Write as _;
    let mut b = String::new();
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
    Ok(b)
}

/// Per data set, RMS(residual) / RMS(signal) per observer and class, and the healthy class's
/// ratio per data set and observer (rounded to 3 decimals).
fn residual_ratio_tables(
    methods: &[Method],
    ratios: &BTreeMap<(String, RecKey), f64>,
) -> (String, ResidualRatios) {
    use std::fmt::Write as _;
    let mut b = String::new();
    let mut healthy_ratio = ResidualRatios::new();
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
    (b, healthy_ratio)
}
