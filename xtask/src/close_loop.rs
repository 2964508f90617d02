//! `cargo xtask close-loop`: run the declared model against a recording, trace the residual to
//! effects the model lacks, add them, and write the ledger (JSON + Markdown + PNG figure).
//! With `--all-real`, run the CWRU batch into `results/close-loop/`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context as _, bail};
use close_loop::machine::MachineModel;
use close_loop::observe::ArxLaguerreDeclared;
use close_loop::physics::PhysicsModel;
use close_loop::scenario::PhenomenologicalModel;
use close_loop::{
    BearingRates, DeclaredModel, LoopConfig, OperatingPoint, Outcome, close_loop_from, parse_fault,
};

use crate::common::Context;

/// Flags of this task.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Recording: a CWRU `.mat` file (named by its number, e.g. `105.mat`), a one-column `.csv`,
    /// or `cargo xtask simulate`'s CSV (its `accel` column is read, fs from `time_s`).
    #[arg(long, required_unless_present = "all_real")]
    pub input: Option<PathBuf>,
    /// Channel of a `.mat` file: DE, FE or BA.
    #[arg(long, default_value = "DE")]
    pub channel: String,
    /// Sampling rate, Hz (required for CSV; a CWRU file's own rate otherwise).
    #[arg(long)]
    pub fs: Option<f64>,
    /// Declared shaft speed, rpm (a CWRU file's stored speed when omitted).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Bearing designation.
    #[arg(long, default_value = "6205")]
    pub bearing: String,
    /// Declared fault: none|outer|inner|ball.
    #[arg(long, default_value = "none")]
    pub fault: String,
    /// Declared model: physics (5-DOF), arx-laguerre (identified on the fitting segment) or
    /// phenomenological (impact train).
    #[arg(long, default_value = "physics")]
    pub model: String,
    /// Mains frequency of the rig (a line nearer its multiples than fr's is a tone); 0 = unknown.
    #[arg(long, default_value_t = 60.0)]
    pub line_frequency: f64,
    /// Use at most this many seconds of the recording (from its start).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Maximum number of effects.
    #[arg(long, default_value_t = 8)]
    pub max_effects: usize,
    /// JSON report path (Markdown and PNG are written beside it).
    #[arg(long, required_unless_present = "all_real")]
    pub report: Option<PathBuf>,
    /// Start from a calibrated machine model (`cargo xtask calibrate`) instead of the bare
    /// declared model.
    #[arg(long)]
    pub machine: Option<PathBuf>,
    /// Units of the recording: g, m/s^2 or unknown (default: g for CWRU .mat files, m/s^2 for
    /// `simulate`'s CSV, unknown otherwise).
    #[arg(long)]
    pub units: Option<String>,
    /// Decimate the recording by this integer factor first (anti-aliased), e.g. 4 for 48 → 12 kHz.
    #[arg(long, default_value_t = 1)]
    pub decimate: usize,
    /// Spall width of the declared fault, inches (CWRU sizes 0.007 / 0.014 / 0.021 / 0.028;
    /// a CWRU record's own when omitted).
    #[arg(long)]
    pub fault_size_in: Option<f64>,
    /// Run every recording of the shared data into `results/close-loop/`: 97 calibrated as the
    /// rig's machine model (at 48 kHz and decimated to 12 kHz), every fault record from it.
    #[arg(long)]
    pub all_real: bool,
}

/// Flags of `cargo xtask calibrate`.
#[derive(clap::Args, Debug)]
pub struct CalibrateArgs {
    /// Healthy recording (`.mat` or `.csv`).
    #[arg(long)]
    pub input: PathBuf,
    /// Channel of a `.mat` file: DE, FE or BA.
    #[arg(long, default_value = "DE")]
    pub channel: String,
    /// Sampling rate, Hz (required for a plain CSV).
    #[arg(long)]
    pub fs: Option<f64>,
    /// Declared shaft speed, rpm (a CWRU file's stored speed when omitted).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Bearing designation.
    #[arg(long, default_value = "6205")]
    pub bearing: String,
    /// Units of the recording (as `close-loop --units`).
    #[arg(long)]
    pub units: Option<String>,
    /// Decimate by this integer factor first (4: 48 kHz → 12 kHz).
    #[arg(long, default_value_t = 1)]
    pub decimate: usize,
    /// Mains frequency of the rig; 0 = unknown.
    #[arg(long, default_value_t = 60.0)]
    pub line_frequency: f64,
    /// Maximum number of effects.
    #[arg(long, default_value_t = 16)]
    pub max_effects: usize,
    /// Machine model JSON to write (the loop's ledger, Markdown and figure go beside it as
    /// `<out>.report.json|md|png`).
    #[arg(long)]
    pub out: PathBuf,
}

/// `cargo xtask calibrate`: the loop on a healthy recording, its result saved as a machine model.
pub fn calibrate(_ctx: &Context, a: CalibrateArgs) -> anyhow::Result<()> {
    let t = Instant::now();
    let args = Args {
        input: Some(a.input.clone()),
        channel: a.channel,
        fs: a.fs,
        rpm: a.rpm,
        bearing: a.bearing,
        fault: "none".into(),
        model: "physics".into(),
        line_frequency: a.line_frequency,
        seconds: None,
        max_effects: a.max_effects,
        report: Some(report_beside(&a.out)),
        machine: None,
        units: a.units,
        decimate: a.decimate,
        fault_size_in: None,
        all_real: false,
    };
    let (o, _, _) = run_one(&args, None)?;
    write_machine(&o, &a.out)?;
    println!(
        "{}: machine model with {} structural mode(s), {} line(s), speed ratio {:.5}; held-out {} {:.3} -> {:.3} dB; {:.2} s -> {}",
        a.input.display(),
        o.machine
            .structural_modes
            .iter()
            .filter(|m| m.frequency_hz > 0.0)
            .count(),
        o.machine.lines.len(),
        o.machine.speed_ratio,
        o.ledger.error_metric,
        o.ledger.error_before,
        o.ledger.error_after,
        t.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}

/// `rig.json` → `rig.report.json`.
fn report_beside(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("machine");
    out.with_file_name(format!("{stem}.report.json"))
}

fn write_machine(o: &Outcome, out: &Path) -> anyhow::Result<()> {
    if let Some(parent) = out.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(out, o.machine.to_json()? + "\n")?;
    Ok(())
}

/// Load and validate a machine model file.
pub fn load_machine(path: &Path) -> anyhow::Result<MachineModel> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    Ok(MachineModel::from_json(&text)?)
}

/// Run the task.
pub fn run(ctx: &Context, args: Args) -> anyhow::Result<()> {
    if args.all_real {
        let Some(dir) = ctx.data_dir_or_skip()? else {
            println!("close-loop: no data directory found; skipping the real-data batch");
            return Ok(());
        };
        return all_real(ctx, dir, &args);
    }
    let prior = args.machine.as_deref().map(load_machine).transpose()?;
    let t = Instant::now();
    let (o, _, _) = run_one(&args, prior.as_ref())?;
    println!(
        "{}: {} {:.3} dB -> {:.3} dB, {} effect(s): {}; {:.2} s",
        args.input
            .as_deref()
            .map(Path::display)
            .map(|d| d.to_string())
            .unwrap_or_default(),
        o.ledger.error_metric,
        o.ledger.error_before,
        o.ledger.error_after,
        o.ledger.effects.len(),
        effect_list(&o),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}

fn effect_list(o: &Outcome) -> String {
    let eff: Vec<String> = o
        .ledger
        .effects
        .iter()
        .map(|e| {
            let p = match e.placement {
                close_loop::Placement::Physics => "P",
                close_loop::Placement::Measurement => "M",
            };
            let order = e
                .parameters
                .get("order")
                .map_or(String::new(), |k| format!(" {k}x"));
            match e.frequency_hz {
                Some(f) => format!("{}{order} {:.1} Hz ({p})", e.kind.as_str(), f),
                None => match (e.parameters.get("ratio"), e.parameters.get("fraction")) {
                    (Some(r), _) => format!("{} x{r:.4} ({p})", e.kind.as_str()),
                    (None, Some(f)) => format!("{} {:.2} % ({p})", e.kind.as_str(), 100.0 * f),
                    _ => format!("{} ({p})", e.kind.as_str()),
                },
            }
        })
        .collect();
    if eff.is_empty() {
        "–".to_string()
    } else {
        eff.join("; ")
    }
}

/// Smith & Randall (2015) grade of a record from `cwru/smith_randall_grades.csv`, if present.
fn grades(dir: &Path) -> std::collections::BTreeMap<u32, String> {
    let mut m = std::collections::BTreeMap::new();
    if let Ok(text) = std::fs::read_to_string(dir.join("cwru/smith_randall_grades.csv")) {
        for line in text.lines().skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            if let (Some(n), Some(g)) = (f.first().and_then(|n| n.parse().ok()), f.last()) {
                m.insert(n, g.trim().to_string());
            }
        }
    }
    m
}

/// One row of the batch table: record, class, grade, rpm, fs, outcome.
type Row = (u32, String, String, f64, f64, Outcome);

/// Every recording of the shared data: 97 calibrated into the rig's machine model (48 kHz, and
/// decimated by 4 for the 12 kHz records), every fault record from the model of its rate.
fn all_real(ctx: &Context, dir: &Path, args: &Args) -> anyhow::Result<()> {
    use rayon::prelude::*;
    let out_dir = ctx.root.join("results/close-loop");
    std::fs::create_dir_all(&out_dir)?;
    let grades = grades(dir);
    let base = |input: PathBuf, report: PathBuf| Args {
        input: Some(input),
        channel: args.channel.clone(),
        fs: None,
        rpm: None,
        bearing: args.bearing.clone(),
        fault: "none".into(),
        model: args.model.clone(),
        line_frequency: args.line_frequency,
        seconds: args.seconds,
        max_effects: args.max_effects,
        report: Some(report),
        machine: None,
        units: None,
        decimate: 1,
        fault_size_in: None,
        all_real: false,
    };
    // the rig, calibrated on the healthy record at both rates
    let normal = bearing_data::record_path(dir, 97)?;
    let mut rigs: Vec<(f64, MachineModel)> = Vec::new();
    let mut rows: Vec<Row> = Vec::new();
    for (dec, name) in [(4usize, "rig-12k"), (1, "rig-48k")] {
        let t = Instant::now();
        let mut a = base(normal.clone(), out_dir.join(format!("{name}.report.json")));
        a.decimate = dec;
        a.max_effects = args.max_effects.max(16);
        let (o, rpm, fs) = run_one(&a, None)?;
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
    let records: Vec<&bearing_data::CatalogEntry> = bearing_data::catalog()
        .filter(|e| e.number != 97 && e.fault_end() == Some(bearing_data::SensorEnd::DriveEnd))
        .filter(|e| bearing_data::record_path(dir, e.number).is_ok_and(|p| p.exists()))
        .collect();
    let bar = indicatif::ProgressBar::new(records.len() as u64);
    let done: Vec<anyhow::Result<Row>> = records
        .par_iter()
        .map(|e| {
            let fault = match e.fault {
                bearing_data::FaultLocation::InnerRace => "inner",
                bearing_data::FaultLocation::OuterRace => "outer",
                bearing_data::FaultLocation::Ball => "ball",
                bearing_data::FaultLocation::Normal => "none",
            };
            let mut a = base(
                bearing_data::record_path(dir, e.number)?,
                out_dir.join(format!("{}.json", e.number)),
            );
            a.fault = fault.into();
            let prior = rigs
                .iter()
                .find(|(fs, _)| (*fs - e.fs()).abs() < 1.0)
                .map(|r| &r.1);
            let (o, rpm, fs) = run_one(&a, prior)?;
            bar.inc(1);
            Ok((
                e.number,
                e.class_name(),
                grades.get(&e.number).cloned().unwrap_or_else(|| "–".into()),
                rpm,
                fs,
                o,
            ))
        })
        .collect();
    bar.finish_and_clear();
    for r in done {
        rows.push(r?);
    }
    rows[2..].sort_by_key(|r| (r.4 as u64, r.0));
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
    for (n, class, grade, rpm, fs, o) in &rows {
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
    let y: Vec<_> = rows.iter().filter(|r| r.2 == "Y").collect();
    let halved = y
        .iter()
        .filter(|r| r.5.ledger.error_after <= 0.5 * r.5.ledger.error_before)
        .count();
    md.push_str(&format!(
        "\nGrade-Y records with the error at least halved: {halved} of {}.\n",
        y.len()
    ));
    std::fs::write(out_dir.join("README.md"), md)?;
    std::fs::write(out_dir.join("summary.csv"), csv)?;
    println!("wrote {} ({} records)", out_dir.display(), rows.len());
    Ok(())
}

fn run_one(args: &Args, prior: Option<&MachineModel>) -> anyhow::Result<(Outcome, f64, f64)> {
    let input = args.input.as_deref().context("--input is required")?;
    let report = args.report.as_deref().context("--report is required")?;
    let loaded = hybrid_fdd_cli::diagnose::load(input, &args.channel, args.fs)?;
    let units = args
        .units
        .clone()
        .unwrap_or_else(|| loaded.units.to_string());
    if !matches!(units.as_str(), "g" | "m/s^2" | "unknown") {
        bail!("unknown units `{units}` (g, m/s^2 or unknown)");
    }
    let (mut y, mut fs) = (loaded.samples, loaded.fs_hz);
    if args.decimate > 1 {
        y = bearing_data::decimate(&y, args.decimate)?;
        fs /= args.decimate as f64;
    } else if args.decimate == 0 {
        bail!("--decimate must be >= 1");
    }
    if let Some(s) = args.seconds {
        y.truncate((s * fs).round() as usize);
    }
    let rpm = args
        .rpm
        .or(loaded.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    let bearing = BearingRates::from_name(&args.bearing)?;
    let fault = parse_fault(&args.fault)?;
    let op = OperatingPoint::new(rpm, bearing, fault)?;
    if let Some(m) = prior {
        m.check_compatible(fs, bearing.name)?;
        m.check_units(&units)?;
    }
    let cfg = LoopConfig {
        max_effects: args.max_effects,
        line_frequency_hz: (args.line_frequency > 0.0).then_some(args.line_frequency),
        ..LoopConfig::default()
    }
    .check()?;
    let model: Box<dyn DeclaredModel> = match args.model.as_str() {
        "physics" => {
            let b = match bearing.name {
                "6203" => bearing_model::Bearing::Skf6203,
                _ => bearing_model::Bearing::Skf6205,
            };
            let size = args
                .fault_size_in
                .or(loaded.fault_size_in)
                .unwrap_or(PhysicsModel::default().fault_size_in);
            Box::new(PhysicsModel {
                bearing: b,
                fault_size_in: size,
                ..PhysicsModel::default()
            })
        }
        "phenomenological" => Box::new(PhenomenologicalModel {
            resonance_hz: 3300.0f64.min(0.4 * fs),
            ..PhenomenologicalModel::default()
        }),
        "arx-laguerre" => {
            // identified on the fitting segment only (the held-out part stays unseen)
            let n_fit = close_loop::fit_len(y.len(), &cfg);
            Box::new(ArxLaguerreDeclared::identify(&y[..n_fit])?)
        }
        other => bail!("unknown model `{other}` (physics, arx-laguerre, phenomenological)"),
    };
    let mut out = close_loop_from(model.as_ref(), prior, &y, fs, &op, &cfg)?;
    out.machine.units = units;
    out.machine.provenance.recording = input
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("recording")
        .to_string();
    if let Some(parent) = report.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(report, serde_json::to_string_pretty(&out.ledger)? + "\n")?;
    let title = input
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or("recording")
        .to_string();
    std::fs::write(report.with_extension("md"), out.ledger.to_markdown(&title))?;
    figure(&out, &report.with_extension("png"), &title)?;
    Ok((out, rpm, fs))
}

/// Register DejaVu Sans with plotters if it exists; `false` means draw without text.
fn font_available() -> bool {
    static ONCE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ONCE.get_or_init(|| {
        let path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
        match std::fs::read(path) {
            Ok(bytes) => {
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                plotters::style::register_font(
                    "sans-serif",
                    plotters::style::FontStyle::Normal,
                    bytes,
                )
                .is_ok()
            }
            Err(_) => false,
        }
    })
}

/// Two panels: held-out PSD (measured, model before, model after) and the residual log ratio
/// 10·log10(S_y/S_m) before and after, effects marked by vertical lines.
fn figure(out: &Outcome, path: &Path, title: &str) -> anyhow::Result<()> {
    use plotters::prelude::*;
    let text = font_available();
    let s = &out.spectra;
    let l = &out.ledger;
    let (f_lo, f_hi) = (l.protocol.band_hz[0], l.protocol.band_hz[1]);
    let idx: Vec<usize> = (0..s.frequency_hz.len())
        .filter(|&k| s.frequency_hz[k] >= f_lo && s.frequency_hz[k] <= f_hi)
        .collect();
    let db = |v: f64| 10.0 * v.max(1e-300).log10();
    let series = |v: &[f64]| -> Vec<(f64, f64)> {
        decimate(idx.iter().map(|&k| (s.frequency_hz[k], db(v[k]))).collect())
    };
    let meas = series(&s.measured);
    let before = series(&s.model_before);
    let after = series(&s.model_after);
    let ratio = |m: &[f64]| -> Vec<(f64, f64)> {
        decimate(
            idx.iter()
                .map(|&k| (s.frequency_hz[k], db(s.measured[k]) - db(m[k])))
                .collect(),
        )
    };
    let rb = ratio(&s.model_before);
    let ra = ratio(&s.model_after);
    let (mut ymin, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY);
    for &(_, v) in meas.iter().chain(&before).chain(&after) {
        ymin = ymin.min(v);
        ymax = ymax.max(v);
    }
    let ymin = ymin.max(ymax - 120.0);
    let rmax = rb
        .iter()
        .chain(&ra)
        .map(|p| p.1.abs())
        .fold(3.0f64, f64::max)
        .min(60.0);

    let root = BitMapBackend::new(path, (FIG_W, FIG_H)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(FIG_H / 2);
    let mut c1 = chart(
        &top,
        text,
        (f_lo, f_hi),
        &format!(
            "{title}: held-out PSD, measured vs model (LSD {:.2} -> {:.2} dB)",
            l.error_before, l.error_after
        ),
        ymin,
        ymax + 3.0,
        "PSD (dB)",
    )?;
    let gray = RGBColor(120, 120, 120);
    c1.draw_series(LineSeries::new(meas, &gray))?
        .label("measured")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], gray));
    c1.draw_series(LineSeries::new(before, &BLUE))?
        .label("declared model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    c1.draw_series(LineSeries::new(after, &RED))?
        .label("augmented model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    if text {
        c1.configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
    }
    let mut c2 = chart(
        &bottom,
        text,
        (f_lo, f_hi),
        "residual spectrum 10·log10(S_measured / S_model): before (blue), after (red)",
        -rmax,
        rmax,
        "dB",
    )?;
    c2.draw_series(LineSeries::new(rb, &BLUE.mix(0.6)))?;
    c2.draw_series(LineSeries::new(ra, &RED))?;
    c2.draw_series(LineSeries::new(vec![(f_lo, 0.0), (f_hi, 0.0)], &BLACK))?;
    for (i, e) in l.effects.iter().enumerate() {
        if let Some(f) = e.frequency_hz {
            let col = Palette99::pick(i + 2).to_rgba();
            c2.draw_series(LineSeries::new(
                vec![(f, -rmax), (f, rmax)],
                col.stroke_width(2),
            ))?;
            if text {
                c2.draw_series(std::iter::once(Text::new(
                    format!("{} {}", i + 1, e.kind.as_str()),
                    (f, rmax * (0.9 - 0.08 * (i % 5) as f64)),
                    ("sans-serif", 11).into_font().color(&col),
                )))?;
            }
        }
    }
    root.present()?;
    Ok(())
}

/// Figure size, pixels (keeps each PNG well under 150 kB).
const FIG_W: u32 = 660;
/// Figure height, pixels.
const FIG_H: u32 = 420;
/// Points per drawn curve: one (max, min) pair per bucket, about one bucket per 4 pixels.
const FIG_BUCKETS: usize = 150;

/// Min–max decimation for drawing: split the curve into [`FIG_BUCKETS`] runs of bins and keep
/// each run's largest and smallest value (in frequency order), so lines stay visible.
fn decimate(v: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if v.len() <= 2 * FIG_BUCKETS {
        return v;
    }
    let per = v.len().div_ceil(FIG_BUCKETS);
    let mut out = Vec::with_capacity(2 * FIG_BUCKETS);
    for run in v.chunks(per) {
        let hi = run
            .iter()
            .copied()
            .fold(run[0], |a, b| if b.1 > a.1 { b } else { a });
        let lo = run
            .iter()
            .copied()
            .fold(run[0], |a, b| if b.1 < a.1 { b } else { a });
        if hi.0 <= lo.0 {
            out.extend([hi, lo]);
        } else {
            out.extend([lo, hi]);
        }
    }
    out
}

type Chart<'a, 'b> = plotters::prelude::ChartContext<
    'a,
    plotters::prelude::BitMapBackend<'b>,
    plotters::prelude::Cartesian2d<
        plotters::coord::types::RangedCoordf64,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// One panel with a mesh; without a font, no caption, labels or axis text.
fn chart<'a, 'b>(
    area: &'a plotters::prelude::DrawingArea<
        plotters::prelude::BitMapBackend<'b>,
        plotters::coord::Shift,
    >,
    text: bool,
    x: (f64, f64),
    cap: &str,
    y0: f64,
    y1: f64,
    ylab: &str,
) -> anyhow::Result<Chart<'a, 'b>> {
    use plotters::prelude::*;
    let mut b = ChartBuilder::on(area);
    b.margin(12);
    if text {
        b.caption(cap, ("sans-serif", 13))
            .x_label_area_size(40)
            .y_label_area_size(60);
    }
    let mut c = b.build_cartesian_2d(x.0..x.1, y0..y1)?;
    let mut m = c.configure_mesh();
    // no minor grid: it costs PNG size and no information
    m.light_line_style(TRANSPARENT);
    if text {
        m.x_desc("frequency (Hz)").y_desc(ylab);
    } else {
        m.x_labels(0).y_labels(0);
    }
    m.draw()?;
    Ok(c)
}
