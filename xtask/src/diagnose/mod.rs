//! `cargo xtask diagnose`: the `hybrid-fdd diagnose` command (same flags, same code, from the
//! `hybrid-fdd-cli` library), plus `--all-real`: every recording of the shared data's three
//! rigs — CWRU (against the healthy baseline 97.mat, self-referenced and against the machine
//! model calibrated on 97, beside its label and Smith & Randall's grade), MFPT (self-referenced)
//! and UESTC (self-referenced and against the same rig's normal recording) — beside the peer's
//! committed types → `results/diagnosis/`; `--false-alarm`: the false-alarm corpus of
//! [`crate::false_alarm`].
//!
//! [`rigs`] finds and diagnoses MFPT and UESTC, [`summary`] counts, [`report`] writes. No
//! algorithm lives here.

mod report;
mod rigs;
mod summary;

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context as _;
use bearing_data::{LoadOptions, load_record};
use diagnosis::BearingSpec;
use hybrid_fdd_cli::diagnose::{BaselineSource, Loaded, Outcome, Plan, diagnose_loaded};
use hybrid_fdd_cli::train::{ExampleMeta, cross_validate, examples};
use rayon::prelude::*;

use crate::common::Context;

/// Flags of this task.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    cmd: hybrid_fdd_cli::diagnose::Args,
    /// Diagnose every recording of the shared data — CWRU (97, the 60 12 kHz and 13 48 kHz
    /// drive-end records), MFPT (14) and UESTC (32) — into `results/diagnosis/`.
    #[arg(long, conflicts_with = "false_alarm")]
    all_real: bool,
    /// Diagnose a deterministic corpus of simulated healthy machines (and the same machines with
    /// a fault) and every real healthy recording of the shared data, self-referenced: the
    /// false-alarm rate per factor level and the detection rate per fault and severity, into
    /// `results/diagnosis/false_alarm.{md,csv,json}`.
    #[arg(long)]
    false_alarm: bool,
    /// With `--false-alarm`: diagnose the corpus' healthy, noise-only and real healthy
    /// recordings as `--bearing unknown` does (the search over non-integer orders, at the declared
    /// speed), into `results/diagnosis/false_alarm_unknown.{md,csv}`.
    #[arg(long, requires = "false_alarm")]
    unknown_bearing: bool,
    // With `--false-alarm`, `--rpm-range LOW-HIGH` (the diagnose flag) diagnoses the corpus with
    // its bearings and no declared speed, the speed searched over the range, into
    // `results/diagnosis/false_alarm_speed_range.{md,csv}` (or, with `--only`, prints the lines).
    /// With `--false-alarm`: diagnose only the corpus entries with these ids (comma-separated;
    /// a trailing `*` matches a prefix, e.g. `H6*`) and print one line per entry with its drawn
    /// parameters; no report is written. For reading a machine the tables point at.
    #[arg(long, requires = "false_alarm", value_delimiter = ',')]
    only: Vec<String>,
    /// With `--only`: also write each simulated recording as `<dir>/<id>.csv` (`time_s,accel`,
    /// m/s²), for `hybrid-fdd diagnose --input <dir>/<id>.csv --report out.json`.
    #[arg(long, requires = "only")]
    write_csv: Option<std::path::PathBuf>,
}

/// Hand-written: the detector in short, what the data lacks, and what was changed after seeing
/// which labelled outputs. Kept to what the tables above show; numbers are read there.
const NOTES: &str = "
## The detector in short

For each fault hypothesis (BPFO, BPFI, the ball-defect rate) a template — harmonics 1–3 in their
slip windows plus the distinguishing sidebands (BPFI ± fr, BSF ± FTF) — is read in every band of
the filter bank, each line against the same band's windows of the same width that no bearing
kinematics explains (the *clear windows*; shaft orders, half orders and mains multiples masked
where the band shows their comb). A line's probability under \"healthy\" is the share of clear
windows at least as strong (a generalised Pareto tail beyond them, never below 1e-4 for one line);
the lines combine by Fisher's method; the search over bands (and over speeds, when no comb
confirmed the speed) is paid for by Bonferroni: `p_healthy`. A fault is reported when
`p_healthy` ≤ α/3 (α = 1 % per recording) **and** its harmonics modulate the band's envelope with
depth ≥ 0.5 (a defect's impacts, not a healthy bearing's smooth ball-pass modulation); several
significant faults are taken deepest first, each re-tested with the stronger ones' line families
masked; two that explain each other's lines with depths within a factor 1.5 give `uncertain`.
Source: `crates/diagnosis/src/detect/mod.rs` (and `linetest.rs`, `template.rs`, `view.rs` beside
it); the residual, bands, speed search and baseline discounting: `docs/equations/diagnosis.md`,
whose section *Band choice, CFAR, score and decision* and `Diagnosis::explain_against` still
describe the line rule this detector replaced (6 dB, 2 of 3 harmonics, rank CFAR) — the
*Wrong verdicts* lists above are therefore read from the detector's own fields.

## What the data lacks, and the limits this run shows

- **UESTC's geometry is assumed** (UC204-class, the catalogue's typical row): every fault window
  is widened by the catalogue's typical-geometry uncertainty (table *The three bearings*), so
  the templates are wide and a band holds few clear windows to compare them with (`null_size` in
  `records_other_rigs.json`); a line can then be no rarer than one in a few windows.
- **UESTC inner and outer line families coincide.** BPFI − BPFO is close to 2 fr for this
  geometry (table above): BPFO + 2 fr ≈ BPFI, and the inner race's shaft-sideband comb
  BPFI + j·fr passes near every BPFO harmonic (BPFO×1 ≈ BPFI − 2 fr, ×2 ≈ BPFI + fr, ×3 ≈
  BPFI + 4 fr), inside windows widened for the typical geometry — the figure of `I_1000_1`
  shows that comb read as BPFO×1–3. Most `I_*` records read both faults
  significant with similar depths: `uncertain (inner|outer)`, the label always among the
  candidates (summary table). Which of the two is \"stronger\" is decided by modulation depth,
  not `p_healthy`: on several `I_*` records against the baseline, inner has the smaller
  `p_healthy` yet is explained by outer (`records_other_rigs.json`). Conversely, most `O_*`
  records detected as `outer` have inner as their most significant hypothesis.
- **UESTC's ball-defect rate sits on the 4th shaft order** (ball defect − nearest shaft order in
  the table above, inside the widened window): where a band shows the shaft comb its order 4 is
  masked and the ball's first harmonic with it; where it does not, order 4 is in the reference.
  No `B_*` record shows ball lines above about 7 dB in either reference (*Wrong verdicts*): none
  is detected (the peer's types of them are in the per-record table).
- **UESTC outer-race records at 1000 and 1200 rpm** (`O_1000_*`, `O_1200_*`) are `normal`: BPFO×1
  is weak there while ×2 and ×3 stand well out, and with few clear windows three lines of which
  one is absent do not reach α/3.
- **Running speed.** UESTC's running speed is several per cent off the set speed (rpm used,
  mostly from the spectrum's shaft comb; `B_1400_*` furthest, near the ± 10 % edge of the
  search); MFPT's found speeds sit slightly below the nameplate 25 Hz. Where no comb was found
  (`declared`), the templates searched the range themselves at α/2.
- **`p_healthy` ≤ α on healthy recordings.** Several healthy diagnoses (UESTC `N_*`, self and
  against the other segment, and 97 against its machine model) have `p_healthy` ≤ α and stay
  `normal` only because the lines are shallow (summary table, column *`normal` with p_healthy ≤
  α*): on these rigs the probability alone over-states how rare such lines are on a healthy
  machine, and the false-alarm rate rests on the modulation-depth gate as much as on α. Faulty
  recordings held `normal` the same way are counted in that column too (CWRU ball faults among
  them).
- **MFPT** has no healthy recording in the shared copy (self-referenced only), so its false
  alarms cannot be counted there. **CWRU**: ball faults are mostly `normal` (confusion
  matrices); 3001–3008 are analysed with 6205 kinematics CWRU does not confirm.

## What was changed after seeing labelled outputs

The detector's constants — α, the one-line floor, the tail fit, the modulation depth 0.5 — were
fixed on the healthy corpus (`false_alarm.md`: simulated healthy machines and the real healthy
recordings, among them UESTC's `N_*` and CWRU's 97) and on physics, not on fault labels.
`SPEED_OFFSET` (+0.33 %) is older: a CWRU-specific allowance set from CWRU's outer-race lines
under the former rule (`crates/diagnosis/src/lib.rs`). While the detector was written, UESTC's
labelled outputs were looked at, and these design changes were made after (no threshold moved
onto them): window padding 1 bin → half a bin; the clear-window reference kept off every
hypothesis's lattice (with shaft shifts, `LATTICE_SHAFT_ORDERS`), not only the tested one's;
significant hypotheses ordered by modulation depth; a speed comb refined from its lines
accepted; the typical-geometry widening of catalogue rows marked typical. After MFPT's and
UESTC's outputs were looked at once more: two faults that explain each other's lines told apart
by probability or depth (else `uncertain`); shaft-order and mains combs recognised outside the
faults' own windows (a 6203's ball rate at 900 rpm is not a mains comb); the turns a segment
needs counted at the slowest speed searched. After MFPT's `train_data_InnerRaceFault_vload_3`
was looked at (read `ball` at its declared speed, 1 % off the running one): where no comb
confirms the speed and both readings find a fault, the reading over the range names it when
its finding is two decades rarer on a healthy machine than the declared reading's (the
corpus's faulty machines were read before any labelled run with it; no recording's alarm
changes under it, only the fault named). UESTC's and MFPT's numbers here are therefore not a
blind test; CWRU was run after these changes, and none of its verdicts moved with the last.
The rigs in no repository stay the judge.
";

/// Records whose figure goes into `results/diagnosis/figures/`.
const FIGURES: [u32; 5] = [97, 105, 130, 222, 3005];
/// MFPT and UESTC recordings whose figure goes there too (self-referenced for MFPT, against
/// its baseline for UESTC), chosen by name before the run.
const FIGURES_OTHER: [&str; 2] = ["train_data_OuterRaceFault_vload_1", "I_1000_1"];

/// Run the task.
pub fn run(ctx: &Context, args: Args) -> anyhow::Result<()> {
    if args.false_alarm {
        let bearing = match (args.unknown_bearing, args.cmd.recording.search()?.rpm_range) {
            (true, _) => crate::false_alarm::BearingAs::Unknown,
            (false, Some(range)) => crate::false_alarm::BearingAs::SpeedSearched(range),
            (false, None) => crate::false_alarm::BearingAs::Declared,
        };
        if !args.only.is_empty() {
            return crate::false_alarm::run_only(
                ctx,
                &args.only,
                bearing,
                args.write_csv.as_deref(),
            );
        }
        if args.unknown_bearing {
            return crate::false_alarm::unknown::run(ctx);
        }
        if let Some(range) = args.cmd.recording.search()?.rpm_range {
            // the range's own check (empty, inverted, non-finite) before a 10-minute run
            diagnosis::DiagnoseOptions::search(range[0], range[1]).check()?;
            return crate::false_alarm::speed_range::run(ctx, range);
        }
        return crate::false_alarm::run(ctx);
    }
    if !args.all_real {
        return hybrid_fdd_cli::diagnose::run(&args.cmd);
    }
    let Some(dir) = ctx.data_dir_or_skip()? else {
        println!("diagnose: no data directory found; skipping the real-data batch");
        return Ok(());
    };
    all_real(dir, &ctx.root.join("results/diagnosis"))
}

/// A CWRU record and its drive-end channel as the commands load it (speed from the file).
fn cwru_loaded(
    dir: &Path,
    e: &bearing_data::CatalogEntry,
) -> anyhow::Result<(bearing_data::Recording, Loaded)> {
    let rec = load_record(dir, e.number, &LoadOptions::default())
        .with_context(|| format!("loading {}", e.number))?;
    let l = Loaded {
        samples: rec.de().to_vec(),
        fs_hz: rec.fs_hz(),
        rpm: Some(rec.rpm().value),
        unit: bearing_data::SampleUnit::cwru(),
        fault_size_in: e.fault_diameter_in(),
    };
    Ok((rec, l))
}

/// A record selector for the accuracy table.
type Pick = Box<dyn Fn(&Row) -> bool>;

/// One record's two diagnoses.
struct Row {
    number: u32,
    fs: f64,
    class: String,
    label: &'static str,
    load_hp: u8,
    rpm: f64,
    grade: Option<char>,
    base: Result<Outcome, String>,
    own: Result<Outcome, String>,
    machine: Result<Outcome, String>,
    /// The trained classifier's examples from this record (12 kHz fault records only).
    examples: Vec<diagnosis::Labelled>,
}

fn verdict(r: &Result<Outcome, String>) -> &str {
    match r {
        Ok(o) => &o.diagnosis.verdict,
        Err(_) => "error",
    }
}

/// Every recording of the shared data's three rigs diagnosed, the figures drawn, the trained
/// classifier cross-validated and `results/diagnosis/` written (see the module's doc).
fn all_real(dir: &Path, out: &Path) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    let cpu0 = crate::false_alarm::process_cpu_s();
    let entries: Vec<_> = bearing_data::catalog()
        .filter(|e| e.in_shared_copy)
        .collect();
    let plan = Plan {
        channel: "DE".into(),
        fs: None,
        rpm: None,
        bearing: BearingSpec::parse("6205")?,
    };
    let refs = References::prepare(dir, &entries)?;
    let rows = diagnose_cwru(dir, &entries, &plan, &refs)?;
    let cwru_s = start.elapsed().as_secs_f64();
    let t1 = std::time::Instant::now();
    let others = rigs::run(dir)?;
    let others_s = t1.elapsed().as_secs_f64();
    write_figures(out, &rows, &others)?;
    let trained = trained_classifier(refs, &plan, &rows)?;
    let peer_path = out.join("peer_openconmo.csv");
    let peer = summary::read_peer(&peer_path)
        .with_context(|| format!("reading {}", peer_path.display()))?;
    let false_alarm = summary::false_alarm_headline(&[
        &out.join("false_alarm.json"),
        &out.join("false_alarm_short.json"),
        &out.join("false_alarm_sweep.json"),
    ]);
    let run = report::RunInfo {
        wall_s: start.elapsed().as_secs_f64(),
        cwru_s,
        others_s,
        threads: rayon::current_num_threads(),
        cpu_s: crate::false_alarm::process_cpu_s()
            .zip(cpu0)
            .map(|(b, a)| b - a),
        load: std::fs::read_to_string("/proc/loadavg")
            .ok()
            .and_then(|l| l.split_whitespace().next().map(str::to_string)),
    };
    report::write_outputs(
        &report::Inputs {
            rows: &rows,
            others: &others,
            peer: peer.as_ref(),
            false_alarm: false_alarm.as_ref(),
            trained: &trained,
            run,
        },
        out,
    )?;
    println!("wrote {}", out.display());
    Ok(())
}

/// The three references a CWRU record is diagnosed against besides itself: the healthy
/// recording 97 and the machine model calibrated on it at 48 and at 12 kHz.
struct References {
    /// 97.mat as a recording baseline (both rates prepared).
    baseline: BaselineSource,
    /// The machine model calibrated on 97 at 48 kHz.
    m48: BaselineSource,
    /// The machine model calibrated on 97 decimated to 12 kHz.
    m12: BaselineSource,
    /// 97's drive-end channel decimated to 12 kHz (the trained classifier's normal class).
    x12: Vec<f64>,
    /// 97's speed, rpm.
    rpm97: f64,
}

impl References {
    /// Load 97, prepare its baseline at both rates, calibrate the machine model on it at both
    /// rates and synthesise each model's healthy envelope at every record's speed, serially.
    fn prepare(dir: &Path, entries: &[&bearing_data::CatalogEntry]) -> anyhow::Result<Self> {
        let b97 = load_record(dir, 97, &LoadOptions::default()).context("loading 97.mat")?;
        let rpm97 = b97.rpm().value;
        let baseline =
            BaselineSource::from_samples(Path::new("97.mat"), b97.de().to_vec(), b97.fs_hz());
        // prepare both rates first (a recording baseline does not depend on the speed; the cache
        // would also prepare each once under the parallel part)
        baseline.at(48_000.0, rpm97)?;
        baseline.at(12_000.0, rpm97)?;
        // the machine model calibrated on 97 (the closed loop from the healthy 5-DOF model), at
        // both rates: its whole model is the third reference's healthy model, and its healthy
        // envelope is synthesised once per rate and record speed
        let cfg = close_loop::LoopConfig::default().check()?;
        let m48 = machine_reference(b97.de(), 48_000.0, rpm97, &cfg)?;
        let x12 = bearing_data::Decimator::new(bearing_data::DecimatorParams::new(4))?
            .decimate(b97.de())?;
        let m12 = machine_reference(&x12, 12_000.0, rpm97, &cfg)?;
        // each model's healthy synthesis at every record speed (the catalog's; the file's is the
        // same) first, serially (0.2–0.4 s each), so the parallel part only reads the caches and
        // its scheduling — hence which thread's FFT plans compute what — stays as before
        for e in entries {
            let msrc = if e.fs() == 48_000.0 { &m48 } else { &m12 };
            msrc.at(e.fs(), e.rpm())?;
        }
        Ok(Self {
            baseline,
            m48,
            m12,
            x12,
            rpm97,
        })
    }
}

/// The machine model calibrated on 97's samples `x` at `fs` Hz, in g, as a reference.
fn machine_reference(
    x: &[f64],
    fs: f64,
    rpm97: f64,
    cfg: &close_loop::CheckedConfig,
) -> anyhow::Result<BaselineSource> {
    let recording = close_loop::Signal::new(x, fs).map_err(close_loop::CloseLoopError::from)?;
    let mut m =
        close_loop::machine::calibrate(&recording, rpm97, bearing_model::Bearing::Skf6205, cfg)
            .with_context(|| format!("calibrating the machine model on 97.mat at {fs} Hz"))?;
    m.units = "g".into();
    m.provenance.recording = "97.mat".into();
    Ok(BaselineSource::from_machine(
        Path::new(&format!("97.mat machine model ({} kHz)", fs / 1000.0)),
        m,
    ))
}

/// Every CWRU record diagnosed in parallel against 97, against itself and against the machine
/// model of its rate, with the trained classifier's examples of the 12 kHz records.
fn diagnose_cwru(
    dir: &Path,
    entries: &[&bearing_data::CatalogEntry],
    plan: &Plan,
    refs: &References,
) -> anyhow::Result<Vec<Row>> {
    let bar = indicatif::ProgressBar::new(entries.len() as u64);
    let rows: Vec<Row> = entries
        .par_iter()
        .map(|e| -> anyhow::Result<Row> {
            let (rec, l) = cwru_loaded(dir, e)?;
            let base =
                diagnose_loaded(&l, plan, Some(&refs.baseline)).map_err(|e| format!("{e:#}"));
            let own = diagnose_loaded(&l, plan, None).map_err(|e| format!("{e:#}"));
            let msrc = if l.fs_hz == 48_000.0 {
                &refs.m48
            } else {
                &refs.m12
            };
            let machine = diagnose_loaded(&l, plan, Some(msrc)).map_err(|e| format!("{e:#}"));
            let examples = if l.fs_hz == 12_000.0 {
                let meta = ExampleMeta {
                    label: e.fault.as_str().into(),
                    recording: e.number.to_string(),
                    load_hp: u32::from(e.load_hp),
                    fault_size_mils: e.diameter_mils.map(u32::from),
                };
                examples(&l, plan, None, SEGMENT_S, &meta)
                    .with_context(|| format!("examples of {}", e.number))?
            } else {
                Vec::new()
            };
            bar.inc(1);
            Ok(Row {
                number: e.number,
                fs: rec.fs_hz(),
                class: e.class_name(),
                label: e.fault.as_str(),
                load_hp: e.load_hp,
                rpm: rec.rpm().value,
                grade: bearing_data::smith_randall_grade(e.number),
                base,
                own,
                machine,
                examples,
            })
        })
        .collect::<anyhow::Result<_>>()?;
    bar.finish_and_clear();
    Ok(rows)
}

/// The envelope figures of the chosen CWRU records (against 97) and of the chosen MFPT and UESTC
/// recordings (against their baseline, else self-referenced) into `figures/`.
fn write_figures(out: &Path, rows: &[Row], others: &rigs::Others) -> anyhow::Result<()> {
    std::fs::create_dir_all(out.join("figures"))?;
    for r in rows.iter().filter(|r| FIGURES.contains(&r.number)) {
        if let Ok(o) = &r.base {
            hybrid_fdd_cli::figure::envelope_figure(
                &o.diagnosis,
                &out.join(format!("figures/{}_baseline.png", r.number)),
                &format!("{}.mat ({})", r.number, r.class),
            )?;
        }
    }
    for r in others
        .rows
        .iter()
        .filter(|r| FIGURES_OTHER.contains(&r.stem.as_str()))
    {
        let (o, which) = match &r.base {
            Some((_, o)) => (o, "baseline"),
            None => (&r.own, "self"),
        };
        if let Ok(o) = o {
            hybrid_fdd_cli::figure::envelope_figure(
                &o.diagnosis,
                &out.join(format!("figures/{}_{}_{which}.png", r.rig.key(), r.stem)),
                &format!("{} / {} ({})", r.rig.title(), r.stem, r.label),
            )?;
        }
    }
    Ok(())
}

/// The trained classifier's section: its normal class from 97 at 12 kHz, its fault classes from
/// the 12 kHz fault records' examples.
fn trained_classifier(refs: References, plan: &Plan, rows: &[Row]) -> anyhow::Result<String> {
    // the normal class of the trained classifier: 97 at 12 kHz
    let normal = Loaded {
        samples: refs.x12,
        fs_hz: 12_000.0,
        rpm: Some(refs.rpm97),
        unit: bearing_data::SampleUnit::cwru(),
        fault_size_in: None,
    };
    let meta97 = ExampleMeta {
        label: "normal".into(),
        recording: "97".into(),
        load_hp: 0,
        fault_size_mils: None,
    };
    let mut all = examples(&normal, plan, None, SEGMENT_S, &meta97)?;
    let faulty = rows.iter().filter(|r| !r.examples.is_empty()).count();
    all.extend(rows.iter().flat_map(|r| r.examples.iter().cloned()));
    trained_section(&all, faulty)
}

/// (right, total) over rows matching `pick`, for the baseline, the self-referenced and the
/// machine-model run.
fn tally(rows: &[Row], pick: impl Fn(&Row) -> bool) -> [(usize, usize); 3] {
    let sel: Vec<&Row> = rows.iter().filter(|r| pick(r)).collect();
    let right = |f: &dyn Fn(&Row) -> &str| sel.iter().filter(|r| f(r) == r.label).count();
    [
        (right(&|r| verdict(&r.base)), sel.len()),
        (right(&|r| verdict(&r.own)), sel.len()),
        (right(&|r| verdict(&r.machine)), sel.len()),
    ]
}

fn pct((a, n): (usize, usize)) -> String {
    if n == 0 {
        "–".into()
    } else {
        format!("{a}/{n} ({:.1} %)", 100.0 * a as f64 / n as f64)
    }
}

/// Seconds per example of the optional trained classifier.
const SEGMENT_S: f64 = 2.5;

/// The optional trained classifier on top, evaluated on `all` — the examples (self-referenced
/// evidence of 2.5 s segments) of 97 decimated to 12 kHz and of the `faulty` 12 kHz drive-end
/// records, made where each record is loaded — with a Gini tree and a linear SVM under grouped
/// protocols only (no recording on both sides).
fn trained_section(all: &[diagnosis::Labelled], faulty: usize) -> anyhow::Result<String> {
    let mut m = format!(
        "\n## Optional trained classifier on top (for users with labelled data)\n\n\
         `hybrid-fdd train-classifier` / `diagnosis::TrainedDiagnoser`: the training-free \
         diagnosis's evidence ({} features: the three hypothesis scores, counting harmonics and \
         sidebands, kurtosis and energy against the reference, the band's spectral kurtosis and \
         position) of {SEGMENT_S} s segments, self-referenced, of the {} 12 kHz drive-end records \
         and 97.mat decimated to 12 kHz ({} examples). Here the labels are used — to train, \
         under protocols that keep every recording on one side of each split (97, the only \
         normal recording, is split in time, its first segments training: one normal test segment \
         per fold, against ~60 fault segments). Accuracy over all test examples (ACA, eq. 5.37) \
         and per class, mean over folds:\n\n| classifier | protocol | ACA (%) | per class (%) |\n|---|---|---:|---|\n",
        diagnosis::EVIDENCE_FEATURES.len(),
        faulty,
        all.len()
    );
    use hybrid_fdd_cli::train::ClassifierKind;
    for (name, model) in [
        ("Gini tree", ClassifierKind::Tree),
        ("linear SVM", ClassifierKind::Svm),
    ] {
        let spec = model.spec();
        for (protocol, r) in cross_validate(all, &spec) {
            match r {
                Ok((avg, per)) => {
                    let _ = writeln!(m, "| {name} | {protocol} | {avg:.1} | {per} |");
                }
                Err(e) => {
                    let _ = writeln!(m, "| {name} | {protocol} | – | not evaluated: {e} |");
                }
            }
        }
    }
    Ok(m)
}
