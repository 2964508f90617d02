//! `cargo xtask close-loop`: the single-record loop is `hybrid_fdd_cli::close_loop` (also
//! `hybrid-fdd close-loop`); with `--all-real`, the CWRU batch into `results/close-loop/`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use bearing_model::FaultClass;
use close_loop::machine::MachineModel;
use close_loop::{EffectKind, Outcome};
use hybrid_fdd_cli::close_loop::{LoopFlags, calibrate_one, effect_list, run_one};
use hybrid_fdd_cli::flags::SignalFlags;

use crate::common::Context;

/// Flags of this task: the single-record flags plus `--all-real`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub one: hybrid_fdd_cli::close_loop::Args,
    /// Run every recording of the shared data into `results/close-loop/`: 97 calibrated as the
    /// rig's machine model (at 48 kHz and decimated to 12 kHz), every fault record from it.
    #[arg(long)]
    pub all_real: bool,
}

/// Run the task.
pub fn run(ctx: &Context, args: Args) -> anyhow::Result<()> {
    if args.all_real {
        let Some(dir) = ctx.data_dir_or_skip()? else {
            println!("close-loop: no data directory found; skipping the real-data batch");
            return Ok(());
        };
        return all_real(ctx, dir, &args.one);
    }
    hybrid_fdd_cli::close_loop::run(args.one)
}

/// One row of the batch table: record, class, grade, rpm, fs, outcome.
type Row = (u32, String, String, f64, f64, Outcome);

/// A calibrated rig: its sampling rate (Hz) and its machine model.
type Rig = (f64, MachineModel);

/// Every recording of the shared data: 97 calibrated into the rig's machine model (48 kHz, and
/// decimated by 4 for the 12 kHz records), every fault record from the model of its rate.
fn all_real(
    ctx: &Context,
    dir: &Path,
    args: &hybrid_fdd_cli::close_loop::Args,
) -> anyhow::Result<()> {
    let out_dir = ctx.root.join("results/close-loop");
    std::fs::create_dir_all(&out_dir)?;
    let (rigs, mut rows) = calibrate_rigs(dir, &out_dir, args)?;
    rows.extend(run_fault_records(dir, &out_dir, args, &rigs)?);
    rows[2..].sort_by_key(|r| (r.4 as u64, r.0));
    let (mut md, csv) = table(&rows);
    md.push_str(&grade_y_summary(&rows));
    md.push_str(&rate_summary(&rows));
    md.push_str(&bound_summary(&rows));
    md.push_str(&added_fault_summary(&rows));
    std::fs::write(out_dir.join("README.md"), md)?;
    std::fs::write(out_dir.join("summary.csv"), csv)?;
    println!("wrote {} ({} records)", out_dir.display(), rows.len());
    Ok(())
}

/// The single-record flags for one recording of the batch: the shared flags of `args`, the
/// recording's own `input` and `report`, no fault declared, no machine model, no decimation.
fn record_args(
    args: &hybrid_fdd_cli::close_loop::Args,
    input: PathBuf,
    report: PathBuf,
) -> hybrid_fdd_cli::close_loop::Args {
    hybrid_fdd_cli::close_loop::Args {
        input: Some(input),
        common: LoopFlags {
            signal: SignalFlags {
                channel: args.common.signal.channel.clone(),
                fs: None,
            },
            rpm: None,
            bearing: args.common.bearing.clone(),
            model: args.common.model,
            units: None,
            decimate: 1,
            line_frequency: args.common.line_frequency,
        },
        fault: FaultClass::None,
        seconds: args.seconds,
        max_effects: args.max_effects,
        report: Some(report),
        machine: None,
        fault_size_in: None,
    }
}

/// The rig, calibrated on the healthy record 97 at both rates (decimated by 4 → `rig-12k`, as
/// recorded → `rig-48k`): each machine model written beside its report, with its rate, and the
/// two calibrations' rows of the table.
fn calibrate_rigs(
    dir: &Path,
    out_dir: &Path,
    args: &hybrid_fdd_cli::close_loop::Args,
) -> anyhow::Result<(Vec<Rig>, Vec<Row>)> {
    let normal = bearing_data::record_path(dir, 97)?;
    let mut rigs: Vec<Rig> = Vec::new();
    let mut rows: Vec<Row> = Vec::new();
    for (dec, name) in [(4usize, "rig-12k"), (1, "rig-48k")] {
        let t = Instant::now();
        let mut a = record_args(
            args,
            normal.clone(),
            out_dir.join(format!("{name}.report.json")),
        );
        a.common.decimate = dec;
        a.max_effects = args
            .max_effects
            .max(close_loop::machine::CALIBRATE_MAX_EFFECTS);
        let (o, rpm, fs) = calibrate_one(&a)?;
        let mut m = o.machine.clone();
        m.provenance.recording = format!(
            "97.mat (DE{})",
            if dec > 1 { ", decimated by 4" } else { "" }
        );
        std::fs::write(out_dir.join(format!("{name}.json")), m.to_json()? + "\n")?;
        println!(
            "97 -> {name}: {:.3} -> {:.3} dB, {:.1} s",
            o.ledger.error_before,
            o.ledger.error_after,
            t.elapsed().as_secs_f64()
        );
        rigs.push((fs, m));
        rows.push((97, format!("normal ({name})"), "–".into(), rpm, fs, o));
    }
    Ok((rigs, rows))
}

/// Every drive-end fault record of the catalogue present on disk, in parallel, each from the
/// machine model of its rate with its catalogued fault declared: their rows, in catalogue order.
fn run_fault_records(
    dir: &Path,
    out_dir: &Path,
    args: &hybrid_fdd_cli::close_loop::Args,
    rigs: &[Rig],
) -> anyhow::Result<Vec<Row>> {
    use rayon::prelude::*;
    let records: Vec<&bearing_data::CatalogEntry> = bearing_data::catalog()
        .filter(|e| e.number != 97 && e.fault_end() == Some(bearing_data::SensorEnd::DriveEnd))
        .filter(|e| bearing_data::record_path(dir, e.number).is_ok_and(|p| p.exists()))
        .collect();
    let bar = indicatif::ProgressBar::new(records.len() as u64);
    let done: Vec<anyhow::Result<Row>> = records
        .par_iter()
        .map(|e| {
            let mut a = record_args(
                args,
                bearing_data::record_path(dir, e.number)?,
                out_dir.join(format!("{}.json", e.number)),
            );
            a.fault = FaultClass::from(e.fault);
            let prior = rigs
                .iter()
                .find(|(fs, _)| (*fs - e.fs()).abs() < 1.0)
                .map(|r| &r.1);
            let (o, rpm, fs) = run_one(&a, prior)?;
            bar.inc(1);
            Ok((
                e.number,
                e.class_name(),
                bearing_data::smith_randall_grade(e.number)
                    .map_or_else(|| "–".into(), String::from),
                rpm,
                fs,
                o,
            ))
        })
        .collect();
    bar.finish_and_clear();
    done.into_iter().collect()
}

/// The README's heading, preamble and table, and `summary.csv`: one row per record.
fn table(rows: &[Row]) -> (String, String) {
    let mut md = String::from(
        "# Closed loop on every CWRU recording of the shared data\n\n\
         Generated by `cargo xtask close-loop --all-real`; do not edit.\n\n\
         97.mat (healthy, 0 hp, 48 kHz) is calibrated into the rig's machine model twice: decimated by 4 \
         for the 12 kHz records (`rig-12k.json`) and at 48 kHz (`rig-48k.json`). Every fault record starts \
         from the machine model of its rate with its catalogued fault declared, and the loop adds what the \
         record holds beyond it. Error: held-out floor-regularised log-spectral distance (dB; second half \
         of each record; see `docs/equations/close-loop.md`). Placement: P = physics, M = measurement \
         channel. Units: g as CWRU stores them. Grade: Smith & Randall (2015) Y/P/N.\n\n\
         | record | class | grade | rpm | fs (Hz) | error before (dB) | error after (dB) | after/before | effects (in order) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    let mut csv =
        String::from("record,class,grade,rpm,fs_hz,error_before_db,error_after_db,effects\n");
    for (n, class, grade, rpm, fs, o) in rows {
        let l = &o.ledger;
        let eff = effect_list(o);
        md.push_str(&format!(
            "| {n} | {class} | {grade} | {rpm:.0} | {fs:.0} | {:.3} | {:.3} | {:.2} | {eff} |\n",
            l.error_before,
            l.error_after,
            l.error_after / l.error_before.max(1e-12)
        ));
        csv.push_str(&format!(
            "{n},{class},{grade},{rpm:.0},{fs:.0},{:.4},{:.4},\"{}\"\n",
            l.error_before, l.error_after, eff
        ));
    }
    (md, csv)
}

/// How many grade-Y records had their error at least halved.
fn grade_y_summary(rows: &[Row]) -> String {
    let y: Vec<_> = rows.iter().filter(|r| r.2 == "Y").collect();
    let halved = y
        .iter()
        .filter(|r| r.5.ledger.error_after <= 0.5 * r.5.ledger.error_before)
        .count();
    format!(
        "\nGrade-Y records with the error at least halved: {halved} of {}.\n",
        y.len()
    )
}

/// Speed or defect rate: which the shaft lines called each step of the fault lines' rate.
fn rate_summary(rows: &[Row]) -> String {
    let (mut defect, mut speed_read, mut speed_unread) = (0usize, 0usize, 0usize);
    for (.., o) in rows {
        for e in &o.ledger.effects {
            match e.kind {
                EffectKind::DefectRate => defect += 1,
                EffectKind::SpeedOffset if e.parameters.get("shaft_measured") == Some(&1.0) => {
                    speed_read += 1
                }
                EffectKind::SpeedOffset => speed_unread += 1,
                _ => {}
            }
        }
    }
    format!(
        "
A step of the fault lines' rate is a `speed_offset` only if the record's shaft lines \
         moved with it (`docs/journal/close-loop.md`, \"Speed or defect rate\"): {defect} \
         `defect_rate` effects (the fault's rate off its geometry's at the shaft's measured \
         speed, with the effective contact angle), {speed_read} speed offsets read from the \
         shaft lines, {speed_unread} where the shaft lines are too weak to tell the two apart.\n"
    )
}

/// How many `resonance` and `slip` effects end at their search bound: broad corrections, not
/// resolved resonances or measured slips.
fn bound_summary(rows: &[Row]) -> String {
    let (mut at_bound, mut resonances) = (0usize, 0usize);
    let (mut slip_at_bound, mut slips) = (0usize, 0usize);
    for (.., o) in rows {
        for e in &o.ledger.effects {
            let bound = e.parameters.get("at_search_bound") == Some(&1.0);
            match e.kind {
                EffectKind::Resonance => {
                    resonances += 1;
                    at_bound += usize::from(bound);
                }
                EffectKind::Slip => {
                    slips += 1;
                    slip_at_bound += usize::from(bound);
                }
                _ => {}
            }
        }
    }
    format!(
        "\nOf the {resonances} `resonance` effects, {at_bound} end with their damping (0.7) or gain \
         (+200 / −0.97) at the search bound (`parameters.at_search_bound` = 1): broad corrections \
         of the spectral shape that lower the error, not resolved resonances; their descriptions \
         say so.\n"
    ) + &format!(
        "\nOf the {slips} `slip` effects, {slip_at_bound} take the largest slip the search tries \
         (the model's largest, 10 % for the 5-DOF model; `parameters.at_search_bound` = 1): a \
         broad correction, not a measured slip (docs/journal/close-loop.md, \"What the slip \
         at the model's bound does not mean\").\n"
    )
}

/// Faults nobody declared: the records where the diagnosis's envelope evidence added a spall,
/// and where.
fn added_fault_summary(rows: &[Row]) -> String {
    let added: Vec<String> = rows
        .iter()
        .filter_map(|(n, class, .., o)| {
            let at: Vec<&str> = o
                .ledger
                .effects
                .iter()
                .filter(|e| e.kind == EffectKind::BearingFault)
                .filter_map(|e| e.kinematic_rate.as_deref())
                .collect();
            (!at.is_empty()).then(|| format!("{n} ({class}): {}", at.join(" + ")))
        })
        .collect();
    format!(
        "\nA fault nobody declared (`bearing_fault`: a spall at a location the self-referenced \
         diagnosis detects on the fitting segment and again on the held-out segment, and the \
         declared fault leaves healthy, kept by the held-out error) was added on {} of {} records{}\n",
        added.len(),
        rows.len(),
        if added.is_empty() {
            ".".to_string()
        } else {
            format!(": {}.", added.join("; "))
        }
    )
}
