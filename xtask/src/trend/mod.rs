//! `cargo xtask trend --validate | --staged`: issue 57's validation with known truth
//! (simulated degradation runs, [`validate`]) and its staged real sequences ([`staged`]), into
//! `results/trend/`. The algorithms are the `trend` crate's and the generators'; this module
//! schedules runs and writes reports ([`report`]).

pub mod report;
pub mod staged;
pub mod validate;

use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use bearing_model::life::Schedule;

use crate::common::Context;
use crate::false_alarm::process_cpu_s;
use validate::{GEOMETRIES, Geometry, RunSpec, SEEDS};

/// Flags of `cargo xtask trend`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Simulated degradation runs with known truth (3 geometries × 20 seeds) into
    /// `results/trend/validation.{md,csv,json}`, `results/trend/README.md` and one life's figure.
    #[arg(long)]
    validate: bool,
    /// With `--validate`: 4 seeds per geometry, 1 s recordings, into
    /// `target/trend-validate-quick/` (a smoke run; the committed results are the full one).
    #[arg(long, requires = "validate")]
    quick: bool,
    /// The staged real sequences (CWRU 97 then a fault at 0.007/0.014/0.021 in; UESTC normal then
    /// faulty, per set speed) through `hybrid-fdd trend` into `results/trend/staged/<name>/`.
    #[arg(long)]
    staged: bool,
    /// Only rewrite `results/trend/README.md` from what is on disk (`notes.md`, the validation's
    /// and the staged sequences' reports).
    #[arg(long)]
    readme: bool,
}

/// The run whose figure is drawn (chosen before any result: the calibrated rig, the first seed).
pub const FIGURE_RUN: (Geometry, u64) = (Geometry::Rig6205, 1);

const DETAIL: &str = "<!-- per-geometry detail -->";

/// Run the task.
///
/// # Errors
/// Missing data for `--staged`, a failed write; a run that fails is reported, not an error.
pub fn run(ctx: &Context, a: Args) -> anyhow::Result<()> {
    let out = ctx.root.join("results/trend");
    if a.readme {
        return write_readme(&out);
    }
    if !a.validate && !a.staged {
        anyhow::bail!("give --validate and/or --staged (or --readme)");
    }
    if a.validate {
        let dir = if a.quick {
            ctx.root.join("target/trend-validate-quick")
        } else {
            out.clone()
        };
        run_validate(&dir, a.quick)?;
    }
    if a.staged {
        let data = ctx.data_dir()?;
        let t0 = Instant::now();
        let cpu0 = process_cpu_s();
        let lines = staged::run_all(
            data,
            &out.join("staged"),
            &ctx.root.join("target/trend-staged"),
        )?;
        let wall = t0.elapsed().as_secs_f64();
        let cpu = process_cpu_s().zip(cpu0).map(|(b, a)| b - a);
        let mut s = format!(
            "# Staged real sequences ({})\n\nRun by `cargo xtask trend --staged` through `hybrid-fdd trend` (the command's own outputs in each directory: summary.md, trend.csv, trend.json, trend.png; `index.csv` lists the segments, paths under the shared data directory). Recording numbers are 1-based positions in the sequence. The trend crate's defaults (k = {}, {} of {}), the baseline as stated per sequence.\n\n",
            staged::LABEL,
            trend::DEFAULT_K,
            trend::DEFAULT_M,
            trend::DEFAULT_N
        );
        s.push_str(&staged::table(&lines));
        s.push_str(&format!(
            "\nTime: {wall:.0} s wall, {} CPU (release, 2 cores shared).\n\n{}",
            cpu.map_or("—".to_string(), |c| format!("{c:.0} s")),
            STAGED_CANNOT
        ));
        std::fs::create_dir_all(out.join("staged"))?;
        std::fs::write(out.join("staged/README.md"), &s)?;
        std::fs::write(
            out.join("staged/staged.json"),
            serde_json::to_string_pretty(&lines)? + "\n",
        )?;
        println!("staged sequences: {} in {wall:.0} s", lines.len());
    }
    write_readme(&out)?;
    Ok(())
}

const STAGED_CANNOT: &str = "What a staged sequence cannot show: a detection delay (the fault is full-size from its first recording, there is no incipient stage), the growth of a fault or a time to a level (the severities are separate bearings, not one growing spall; CWRU's 0.014 in records are quieter than its 0.007 in ones), false alarms over a long healthy stretch under speed, load and gain nuisances (the healthy stretch is one recording cut in segments), or that the alarm fires on the bearing that changed rather than on any change of recording (each faulty recording is another bearing mounted anew). It shows that the command reads the real files, that the thresholds hold on the healthy segments, and which fault the diagnosis names when the alarm fires.\n";

fn run_validate(dir: &Path, quick: bool) -> anyhow::Result<()> {
    let schedule = if quick {
        Schedule {
            duration_s: 1.0,
            ..Schedule::default()
        }
    } else {
        Schedule::default()
    };
    let seeds: Vec<u64> = if quick {
        SEEDS.take(4).collect()
    } else {
        SEEDS.collect()
    };
    let specs: Vec<RunSpec> = GEOMETRIES
        .iter()
        .flat_map(|&geometry| {
            seeds.iter().map(move |&seed| RunSpec {
                geometry,
                seed,
                schedule,
            })
        })
        .collect();
    let cfg = trend::TrendConfig::default();
    let t0 = Instant::now();
    let cpu0 = process_cpu_s();
    let (runs, kept) = validate::run_all(&specs, &cfg, Some(FIGURE_RUN))?;
    let wall = t0.elapsed().as_secs_f64();
    let cpu = process_cpu_s().zip(cpu0).map(|(b, a)| b - a);
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let tables = report::tables(&runs);
    let gen_s: f64 = runs.iter().map(|r| r.secs.0).sum();
    let ana_s: f64 = runs.iter().map(|r| r.secs.1).sum();
    let timing = format!(
        "{} runs in {wall:.0} s wall, {} CPU (release build, 2 cores shared with another build; runs and recordings in parallel); summed per-run wall: generating {gen_s:.0} s, analysing {ana_s:.0} s.",
        runs.len(),
        cpu.map_or("—".to_string(), |c| format!("{c:.0} s"))
    );
    let figure = match &kept {
        Some((report, truth)) => {
            let name = format!("life_{}_seed{}.png", FIGURE_RUN.0.name(), FIGURE_RUN.1);
            hybrid_fdd_cli::trend::figure_marked(
                report,
                &dir.join(&name),
                Some(truth.onset_time_s),
            )?;
            format!(
                "![one simulated life]({name})\n\n`{name}`: {} seed {} ({} race; true onset at recording {} of {}, green line; the report's alarm in orange; each indicator over its threshold, the baseline shaded), drawn by `hybrid-fdd trend`'s figure code.\n",
                FIGURE_RUN.0.name(),
                FIGURE_RUN.1,
                truth.fault_location.name(),
                truth.onset_index + 1,
                truth.recordings.len()
            )
        }
        None => "The figure's run failed (see the errors).\n".into(),
    };
    let errors: Vec<String> = runs
        .iter()
        .filter_map(|r| {
            r.error
                .as_ref()
                .map(|e| format!("- {} seed {}: {e}", r.geometry.name(), r.seed))
        })
        .collect();
    let md = validation_md(&tables, &runs, &timing, &figure, &errors, quick);
    std::fs::write(dir.join("validation.md"), md)?;
    std::fs::write(dir.join("validation.csv"), report::csv(&runs))?;
    let json = serde_json::json!({
        "design": design_json(quick),
        "tables": tables,
        "runs": runs,
        "timing": timing,
    });
    std::fs::write(
        dir.join("validation.json"),
        serde_json::to_string_pretty(&json)? + "\n",
    )?;
    println!("validation: {timing}");
    Ok(())
}

fn design_json(quick: bool) -> serde_json::Value {
    serde_json::json!({
        "geometries": GEOMETRIES.iter().map(|g| g.name()).collect::<Vec<_>>(),
        "seeds": if quick { "1..=4" } else { "1..=20" },
        "location": "seed % 3: 0 inner, 1 outer, 2 ball",
        "schedule": if quick { "default, 1 s recordings" } else { "generators' default" },
        "trend": "trend::TrendConfig::default() (baseline 10, k = 5, 3 of 4, the alarm over the gain-immune indicators), unit g on the rig, m/s^2 otherwise, declared speed the nominal one",
        "figure_run": format!("{} seed {}", FIGURE_RUN.0.name(), FIGURE_RUN.1),
    })
}

fn validation_md(
    t: &report::Tables,
    runs: &[validate::RunResult],
    timing: &str,
    figure: &str,
    errors: &[String],
    quick: bool,
) -> String {
    let s0 = Schedule::default();
    let (lo, hi) = s0.onset_range();
    let mut s = format!(
        "# Trend validation with known truth{}\n\n\
        **Design (fixed before any result was seen).** Three machines: the calibrated CWRU rig (6205 drive end, 12 kHz, samples in g; `calibrated_rig::life`, spall width growing 0.02 → 0.178 mm), and the phenomenological machine (`bearing_model::life`, m/s²) with a UC204 (2100 rpm, 25.6 kHz) and a 6308 (1480 rpm, 20 kHz); seeds {}; the fault location by seed (`seed % 3`: 0 inner, 1 outer, 2 ball — 6 inner, 7 outer, 7 ball runs per machine). The generators' default schedule: {} recordings of {} s every {} min, the onset drawn in recordings {}..={} (0-based; 40–70 % of the run; after the 10 baseline recordings, checked), speed drift up to ±{:.0} %, {} load steps (the first in the healthy stretch), {} sensor-gain step (anywhere, before or after the onset). Each run through `trend::analyse` with the trend crate's defaults (baseline 10, thresholds median + 5·1.4826·MAD, alarm 3 of 4, speed exponent 1.5 or fitted), the declared speed the nominal one (the drift unknown to the user), the bearing declared by designation. Nothing was tuned on these results.\n\n\
        **Bookkeeping** (`xtask/src/trend/validate.rs`, the rule itself `trend::TrendReport::rule_met_from`). Per run and indicator (and the combined alarm, the report's `alarm`: the earliest onset over its alarm indicators — by the trend crate's default the gain-immune ones, crest, kurtosis, the evidence and the observers' `*_ratio`; and beside it the alarm over every indicator, `--alarm-on all`, which was the default when this validation was first run: that run showed the load and gain steps of the healthy stretch raising it through the amplitudes and energies, and the default was changed after seeing it): a *false alarm* when the report's onset (the m-of-n rule from the end of the baseline) is at a recording before the true onset; the *detection* is that onset when it is at or after the true onset, and after a false alarm the rule restarted at the true onset (windows of faulty recordings only); *delay* = detection − true onset, in recordings (× 10 min); the *fault named* is the diagnosis' verdict the report gives at that onset (most frequent non-normal verdict among the window's exceeding recordings): right (the truth's location), wrong (another, a combination included), none (normal, uncertain). Targets (issue 57): no false alarm before onset on ≥ 95 % of runs, the right fault named at the alarm on ≥ 95 %. 95 % CI: Clopper–Pearson.\n\n",
        if quick {
            " (quick: 4 seeds, 1 s recordings — not the committed result)"
        } else {
            ""
        },
        if quick { "1..=4" } else { "1..=20" },
        s0.recordings,
        if quick { 1.0 } else { s0.duration_s },
        s0.interval_s / 60,
        lo,
        hi,
        100.0 * s0.speed_drift,
        s0.load_steps,
        s0.gain_steps
    );
    let comb = t
        .per_indicator
        .iter()
        .find(|l| l.name == validate::COMBINED);
    if let Some(c) = comb {
        s.push_str(&format!(
            "**Against the targets (combined alarm).** No false alarm before onset: {}/{} ({:.0} %, 95 % CI {:.0}–{:.0} %) — target ≥ 95 %: {}. Right fault at the alarm: {}/{} detected ({}) — target ≥ 95 %: {}.\n\n",
            c.no_false_alarm,
            c.runs,
            100.0 * c.no_false_alarm as f64 / c.runs.max(1) as f64,
            100.0 * c.no_false_alarm_ci.0,
            100.0 * c.no_false_alarm_ci.1,
            if c.runs > 0 && c.no_false_alarm as f64 >= 0.95 * c.runs as f64 { "met" } else { "not met" },
            c.right,
            c.detected,
            if c.detected > 0 { format!("{:.0} %", 100.0 * c.right as f64 / c.detected as f64) } else { "—".into() },
            if c.detected > 0 && c.right as f64 >= 0.95 * c.detected as f64 { "met" } else { "not met" },
        ));
    }
    s.push_str("## Per indicator, every run\n\n");
    s.push_str(&report::table("indicator", &t.per_indicator));
    s.push_str("\n## Combined alarm (default: gain-immune indicators) per machine\n\n");
    s.push_str(&report::table("machine", &t.combined_by_geometry));
    s.push_str("\n## Combined alarm (default: gain-immune indicators) per fault location\n\n");
    s.push_str(&report::table("location", &t.combined_by_location));
    s.push_str("\n## Does the observers' residual warn earlier than the raw signal?\n\nPer run, the detection delay of each observer column minus that of `signal_ms` (the raw signal's mean square, the energy the residual is computed from) and of `kurtosis`; counted over the runs where both detected, the others counted apart.\n\n");
    s.push_str(&report::paired_table(&t.paired));
    s.push_str(&format!(
        "\n## One simulated life\n\n{figure}\n## Timing\n\n{timing}\n"
    ));
    if !errors.is_empty() {
        s.push_str(&format!(
            "\n## Runs that failed ({})\n\n{}\n",
            errors.len(),
            errors.join("\n")
        ));
    }
    let notes: std::collections::BTreeSet<&String> = runs
        .iter()
        .flat_map(|r| r.notes.iter())
        .filter(|n| !n.contains("speed exponent"))
        .collect();
    if !notes.is_empty() {
        s.push_str("\n## Run notes (distinct, speed-exponent fits left out)\n\n");
        for n in notes {
            s.push_str(&format!("- {n}\n"));
        }
    }
    s.push_str(&format!("\n{DETAIL}\n\n## Per machine, every indicator\n"));
    for (g, lines) in &t.per_geometry_indicator {
        s.push_str(&format!("\n### {g}\n\n"));
        s.push_str(&report::table("indicator", lines));
    }
    s
}

/// `results/trend/README.md`: the hand-written reading (`notes.md`, when present), the
/// validation's summary (validation.md up to its per-machine detail) and the staged table, from
/// what is on disk.
fn write_readme(out: &Path) -> anyhow::Result<()> {
    let v = std::fs::read_to_string(out.join("validation.md")).ok();
    let st = std::fs::read_to_string(out.join("staged/README.md")).ok();
    if v.is_none() && st.is_none() {
        return Ok(());
    }
    let mut s = String::from(
        "# Trend: validation with known truth, and staged real sequences (issue 57 parts 4 and 5)\n\nMade by `cargo xtask trend --validate` (simulated lives: `validation.md`, `validation.csv` one row per run and indicator, `validation.json`) and `cargo xtask trend --staged` (`staged/`). The method: `docs/equations/trend.md`.\n\n",
    );
    if let Ok(n) = std::fs::read_to_string(out.join("notes.md")) {
        s.push_str(&n);
        s.push('\n');
    }
    if let Some(v) = v {
        let head = v.split(DETAIL).next().unwrap_or(&v);
        // demote the headings one level under this README's title
        for l in head.lines() {
            if l.starts_with('#') {
                s.push('#');
            }
            s.push_str(l);
            s.push('\n');
        }
        s.push_str("\nPer machine and indicator: `validation.md`.\n\n");
    }
    if let Some(st) = st {
        for l in st.lines() {
            if l.starts_with('#') {
                s.push('#');
            }
            s.push_str(l);
            s.push('\n');
        }
    }
    std::fs::write(out.join("README.md"), s)?;
    Ok(())
}
