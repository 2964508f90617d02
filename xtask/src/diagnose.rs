//! `cargo xtask diagnose`: the `hybrid-fdd diagnose` command (same flags, same code, from the
//! `hybrid-fdd-cli` library), plus `--all-real`: every recording of the shared CWRU data
//! diagnosed against the healthy baseline 97.mat and self-referenced, beside its label and
//! Smith & Randall's grade → `results/diagnosis/`; `--false-alarm`: the false-alarm corpus of
//! [`crate::false_alarm`].

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
    /// Diagnose every recording of the shared CWRU data (97, the 60 12 kHz and 13 48 kHz
    /// drive-end records) into `results/diagnosis/`.
    #[arg(long, conflicts_with = "false_alarm")]
    all_real: bool,
    /// Diagnose a deterministic corpus of simulated healthy machines (and the same machines with
    /// a fault) and every real healthy recording of the shared data, self-referenced: the
    /// false-alarm rate per factor level and the detection rate per fault and severity, into
    /// `results/diagnosis/false_alarm.{md,csv,json}`.
    #[arg(long)]
    false_alarm: bool,
}

/// Hand-written reading of the wrong verdicts and the design history (kept honest: the rules
/// were changed after the first CWRU run, without moving a threshold constant).
const NOTES: &str = "
## Reading the wrong verdicts

- **OR014@6 (197–200, 201)**: no BPFO series stands out in any impulsive band; the data README's
  sanity check finds no clear BPFO line in these files either (Smith & Randall grade 198–200 P/N).
- **Ball faults B007 and B014 (118–121, 185–188, 122, 189)**: the ball-defect series is at or
  below the line threshold; several read `outer` (BPFO series) or `normal`. The data README finds
  no clear ball line in B007 and only cage modulation in B014; Smith & Randall grade them N/P
  except 121.
- **B021 (222–226)**: the envelope holds a clear BPFI series with ± fr sidebands — an inner-race
  signature — so the verdict is `inner`. The rule reads what the spectrum shows; whether the seeded
  bearing also had inner-race damage cannot be decided from these files.
- **IR028 (3001–3004) and B028 (3005–3008)**: NTN-equivalent bearings whose geometry CWRU does
  not publish, analysed with SKF 6205 kinematics and the nominal speed (the files store none); the
  data README notes that 3001–3004 show BPFO rather than BPFI.
- **174** (1.33 s, IR014 at 48 kHz): no line in 40 shaft turns.
- **97 (normal)**: `normal` against itself (the baseline column; a consistency check, not a test)
  and against the machine model, `inner` self-referenced: its envelope holds lines at 161.8 and
  485.4 Hz, 0.2 % below BPFI and 3 × BPFI at 1796 rpm, 6–8 dB over the local median — just over
  the 6 dB floor, in one of ~200 impulsive 48 kHz bands searched. Whether they are the multiple-
  comparison cost of the band search or a real mark on the healthy bearing, a self-referenced
  diagnosis cannot tell; a baseline can (lines it already holds are not evidence).

## Design history (what was changed after seeing CWRU results)

The thresholds (6 dB, 2 of 3 harmonics) and the slip windows were fixed on simulated data before
any CWRU run and never changed. The first CWRU run (each hypothesis in its own best band, any
largest bin as a line, 6 dB) was right on 6/44 Y records with the baseline and 6/44 self-referenced,
7/74 overall: real envelope spectra are crowded with lines (shaft and mains modulation, sidebands
of the true fault), and weak coincidences made nearly every record a combination. The rules were
then changed on physical grounds, not on labels: only impulsive bands (spectral kurtosis
significant against a Gaussian's), one common band for all hypotheses, a harmonic must sit at
h × the series' own fundamental, shaft-rate sidebands join every line family (17/44 and 23/44 Y);
then a line must be a local maximum (a window edge cutting a strong neighbour's skirt is not a
line) and must beat nine in ten of the spectrum's kinematically unexplained lines (rank CFAR).
The CWRU labels were never used to choose a number, but they were seen between these steps, so
the result below is not a blind test.

2026-11-25: against a baseline recording, a line the healthy machine already holds counts only by
what it has grown (before, 97.mat read `inner` against itself); and Welch segments were shortened
by ≤ 2 % to fast FFT lengths (92 → 43 ms per 10 s, 12 kHz record). The second change alone moved
borderline verdicts: grade-Y right went 38/40/40 → 38/41/39 (baseline / self / machine model;
121, 158, 222 stay wrong in every column; 197 is now right with baseline and self, 3006 now reads
`outer+ball` with the baseline and 3008 with the machine model; 97 reads `normal` against the
machine model too). That jitter — one or two Y records under a 2 % change of an analysis length —
is the method's resolution on these records.

2026-11-25 (later): a fault not detected in the common band is added from a band of its own where
it is the strongest signature with ≥ 2 harmonics at ≥ 10 dB that no fault of the common band
explains (made for simulated combinations whose second fault rings another resonance or is
masked in the first's band; docs/equations/diagnosis.md). A probe run over these records was seen
before the 10 dB level was fixed. Grade-Y right unchanged (39 / 42 / 40); 97 stays `normal`;
3003 self-referenced `normal` → `inner`; 222 self-referenced `inner` → `inner+ball`, 224
`inner` → `inner+outer`, 122 self-referenced `outer` → `inner+outer` (wrong before and after).
Then a ball fault's cage harmonics explain lines over the whole slip window (the cage slips on its
own; a simulated ball fault's 9th cage harmonic, 1.5 % below BPFO, read as an outer-race fault):
grade-Y right 39 / 42 / 40 → 41 / 42 / 41 (3006, 3008 lose their `outer`); 3001 (grade N) reads
`inner+ball` against the machine model. A common-band fault's family explains lines in another
band only where its own lines show there (else an outer race beside a ball fault, BPFO = n·FTF,
was never found): 199 with the baseline `inner` → `inner+outer`.

2026-11-27 (later): a machine-model baseline discounts the envelope lines its model holds, as a
baseline recording does: a 10 s recording synthesised from the model (seed 1, at the record's
speed: path, floor, lines, modulations, declared healthy physics) is whitened by the same
predictor and its envelope read in the same bands and resolutions (seed and length fixed before
this run; 26 rate and speed pairs, synthesised first, serially, ≈ 0.2 s each at 12 kHz and
0.35 s at 48 kHz). Measured: no verdict changed in any column; machine-model grade-Y right
stays 40 / 44 (197 still `inner`), overall 50 / 74. The mechanism works (every machine-model line now has a
`baseline_prominence_db`), but 97's models hold nothing to discount: neither calibration took a
modulation, and the synthesised envelope's largest line at a fault or shaft frequency in the
chosen bands is 2.9 dB, under the 6 dB at which a baseline line is subtracted. 97's own BPFI
lines (5.399 orders, 11–13 dB in its 1.5–3 kHz bands) are an envelope feature the loop, fitting
the spectrum, does not see. The baseline and self columns differ from the previous run only in
the last digits (thread-local FFT plans now see other lengths first), no verdict among them.
";

/// Records whose figure goes into `results/diagnosis/figures/`.
const FIGURES: [u32; 5] = [97, 105, 130, 222, 3005];

/// Run the task.
pub fn run(ctx: &Context, args: Args) -> anyhow::Result<()> {
    if args.false_alarm {
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

fn all_real(dir: &Path, out: &Path) -> anyhow::Result<()> {
    let entries: Vec<_> = bearing_data::catalog()
        .filter(|e| e.in_shared_copy)
        .collect();
    let b97 = load_record(dir, 97, &LoadOptions::default()).context("loading 97.mat")?;
    let baseline =
        BaselineSource::from_samples(Path::new("97.mat"), b97.de().to_vec(), b97.fs_hz());
    let plan = Plan {
        channel: "DE".into(),
        fs: None,
        rpm: None,
        bearing: BearingSpec::parse("6205")?,
    };
    // prepare both rates first (a recording baseline does not depend on the speed; the cache
    // would also prepare each once under the parallel part)
    baseline.at(48_000.0, b97.rpm().value)?;
    baseline.at(12_000.0, b97.rpm().value)?;
    // the machine model calibrated on 97 (the closed loop from the healthy 5-DOF model), at
    // both rates: its whole model is the third reference's healthy model, and its healthy
    // envelope is synthesised once per rate and record speed
    let cfg = close_loop::LoopConfig::default().check()?;
    let machine_at = |x: &[f64], fs: f64| -> anyhow::Result<BaselineSource> {
        let mut m = close_loop::machine::calibrate(
            x,
            fs,
            b97.rpm().value,
            bearing_model::Bearing::Skf6205,
            &cfg,
        )
        .with_context(|| format!("calibrating the machine model on 97.mat at {fs} Hz"))?;
        m.units = "g".into();
        m.provenance.recording = "97.mat".into();
        Ok(BaselineSource::from_machine(
            Path::new(&format!("97.mat machine model ({} kHz)", fs / 1000.0)),
            m,
        ))
    };
    let m48 = machine_at(b97.de(), 48_000.0)?;
    let x12 =
        bearing_data::Decimator::new(bearing_data::DecimatorParams::new(4))?.decimate(b97.de())?;
    let m12 = machine_at(&x12, 12_000.0)?;
    // each model's healthy synthesis at every record speed (the catalog's; the file's is the
    // same) first, serially (0.2–0.4 s each), so the parallel part only reads the caches and
    // its scheduling — hence which thread's FFT plans compute what — stays as before
    for e in &entries {
        let msrc = if e.fs() == 48_000.0 { &m48 } else { &m12 };
        msrc.at(e.fs(), e.rpm())?;
    }
    let bar = indicatif::ProgressBar::new(entries.len() as u64);
    let rows: Vec<Row> = entries
        .par_iter()
        .map(|e| -> anyhow::Result<Row> {
            let (rec, l) = cwru_loaded(dir, e)?;
            let base = diagnose_loaded(&l, &plan, Some(&baseline)).map_err(|e| format!("{e:#}"));
            let own = diagnose_loaded(&l, &plan, None).map_err(|e| format!("{e:#}"));
            let msrc = if l.fs_hz == 48_000.0 { &m48 } else { &m12 };
            let machine = diagnose_loaded(&l, &plan, Some(msrc)).map_err(|e| format!("{e:#}"));
            let examples = if l.fs_hz == 12_000.0 {
                let meta = ExampleMeta {
                    label: e.fault.as_str().into(),
                    recording: e.number.to_string(),
                    load_hp: u32::from(e.load_hp),
                    fault_size_mils: e.diameter_mils.map(u32::from),
                };
                examples(&l, &plan, None, SEGMENT_S, &meta)
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
    // the normal class of the trained classifier: 97 at 12 kHz
    let normal = Loaded {
        samples: x12,
        fs_hz: 12_000.0,
        rpm: Some(b97.rpm().value),
        unit: bearing_data::SampleUnit::cwru(),
        fault_size_in: None,
    };
    let meta97 = ExampleMeta {
        label: "normal".into(),
        recording: "97".into(),
        load_hp: 0,
        fault_size_mils: None,
    };
    let mut all = examples(&normal, &plan, None, SEGMENT_S, &meta97)?;
    let faulty = rows.iter().filter(|r| !r.examples.is_empty()).count();
    all.extend(rows.iter().flat_map(|r| r.examples.iter().cloned()));
    let trained = trained_section(&all, faulty)?;
    write_outputs(&rows, &trained, out)?;
    println!("wrote {}", out.display());
    Ok(())
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

/// Why a verdict differs from the label, from the evidence.
fn reason(r: &Row, o: &Result<Outcome, String>) -> String {
    match o {
        Ok(o) => o.diagnosis.explain_against(r.label),
        Err(e) => format!("error: {e}"),
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
    for (name, model) in [("Gini tree", "tree"), ("linear SVM", "svm")] {
        let spec = hybrid_fdd_cli::train::spec_named(model)?;
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

fn write_outputs(rows: &[Row], trained: &str, out: &Path) -> anyhow::Result<()> {
    // CSV
    let mut csv = String::from(
        "record,fs_hz,class,label,load_hp,rpm,grade,verdict_baseline,right_baseline,verdict_self,right_self,score_inner_db,score_outer_db,score_ball_db,band_low_hz,band_high_hz,energy_ratio_db,kurtosis_ratio,residual_kurtosis,verdict_machine,right_machine\n",
    );
    for r in rows {
        let (si, so, sb, bl, bh, e, k, rk) = match &r.base {
            Ok(o) => {
                let d = &o.diagnosis;
                (
                    format!("{:.2}", d.scores.inner),
                    format!("{:.2}", d.scores.outer),
                    format!("{:.2}", d.scores.ball),
                    format!("{:.0}", d.band.low_hz),
                    format!("{:.0}", d.band.high_hz),
                    d.statistics
                        .energy_ratio_db
                        .map_or(String::new(), |v| format!("{v:.2}")),
                    format!("{:.3}", d.statistics.kurtosis_ratio),
                    format!("{:.3}", d.statistics.residual_kurtosis),
                )
            }
            Err(_) => Default::default(),
        };
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{si},{so},{sb},{bl},{bh},{e},{k},{rk},{},{}",
            r.number,
            r.fs,
            r.class,
            r.label,
            r.load_hp,
            r.rpm,
            r.grade.map_or(String::new(), String::from),
            verdict(&r.base),
            verdict(&r.base) == r.label,
            verdict(&r.own),
            verdict(&r.own) == r.label,
            verdict(&r.machine),
            verdict(&r.machine) == r.label,
        );
    }
    std::fs::write(out.join("records.csv"), csv)?;
    // JSON (AR coefficients left out to keep the file small; the order is kept)
    let strip = |o: &Result<Outcome, String>| -> serde_json::Value {
        match o {
            Ok(o) => {
                let mut d = o.diagnosis.clone();
                d.whitening.coefficients.clear();
                serde_json::json!({ "baseline": o.baseline_note, "diagnosis": d })
            }
            Err(e) => serde_json::json!({ "error": e }),
        }
    };
    let json: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "record": r.number, "fs_hz": r.fs, "class": r.class, "label": r.label,
                "load_hp": r.load_hp, "rpm": r.rpm,
                "grade": r.grade.map(String::from),
                "baseline_reference": strip(&r.base),
                "self_reference": strip(&r.own),
                "machine_reference": strip(&r.machine),
            })
        })
        .collect();
    std::fs::write(
        out.join("records.json"),
        serde_json::to_string(&json)? + "\n",
    )?;

    // README
    let mut m = String::from(
        "# Training-free diagnosis of every CWRU recording\n\n\
         Generated by `cargo xtask diagnose --all-real`; do not edit. Method: the `diagnosis` crate \
         (AR residual of a healthy model → kurtogram filter bank → squared envelope spectrum → \
         fault-line evidence with fixed thresholds; see `crates/diagnosis/README.md` and \
         `docs/equations/diagnosis.md`). Nothing was trained or tuned on these labels: the \
         thresholds (a line ≥ 6 dB over the local median at ≥ 2 of 3 harmonics, or at harmonic 1 \
         with a distinguishing sideband) were fixed on simulated recordings before this run.\n\n\
         - **baseline**: AR model fitted on the healthy 97.mat (0 hp, 48 kHz; decimated by 4 with \
         `bearing-data`'s anti-aliasing FIR for the 12 kHz records). 97 diagnosed against itself \
         is a consistency check, not a test.\n\
         - **self**: AR model fitted on the recording itself (AR pre-whitening), no baseline.\n\
         - **machine model**: the machine model calibrated on 97.mat by the closed loop \
         (`close_loop::machine::calibrate`, from the declared healthy 5-DOF model; at 48 kHz, and \
         at 12 kHz on 97 decimated by 4): the whole model — structural path, floor and lines — \
         is the healthy model, whitening with its one-step predictor, and its held-out residual \
         through that predictor the reference statistics (`--baseline rig.json`); the healthy \
         envelope lines come from a 10 s recording synthesised from the model at each record's \
         speed (seed 1) through the same predictor.\n\
         - Drive-end channel, speed stored in the file (nominal for 3001–3008, which store none), \
         SKF 6205 kinematics for every record (3001–3008 are NTN-equivalent bearings whose \
         geometry CWRU does not give). Samples are in file units (the data README states none; \
         commonly read as g); the decision uses power ratios only.\n\
         - Grades: Smith & Randall (MSSP 64–65, 2015), Y = clearly diagnosable by envelope \
         analysis, P = partly, N = not; embedded in `crates/bearing-data/src/smith_randall_grades.csv` from \
         `shared/data/cwru/smith_randall_grades.csv` (the table in `shared/docs/references.md`).\n\
         - A verdict is right when it equals the label exactly (`inner+outer` for an inner \
         record is wrong).\n\n## Accuracy\n\n| records | baseline reference | self reference | machine-model reference |\n|---|---|---|---|\n",
    );
    let twelve = |r: &Row| r.fs == 12_000.0 && r.label != "normal";
    let groups: Vec<(&str, Pick)> = vec![
        (
            "12 kHz DE, grade Y (44)",
            Box::new(move |r: &Row| twelve(r) && r.grade == Some('Y')),
        ),
        (
            "12 kHz DE, grade P (6)",
            Box::new(move |r: &Row| twelve(r) && r.grade == Some('P')),
        ),
        (
            "12 kHz DE, grade N (10)",
            Box::new(move |r: &Row| twelve(r) && r.grade == Some('N')),
        ),
        ("12 kHz DE, all 60", Box::new(twelve)),
        (
            "48 kHz DE, 0 hp (13)",
            Box::new(|r: &Row| r.fs == 48_000.0 && r.label != "normal"),
        ),
        ("normal 97.mat", Box::new(|r: &Row| r.label == "normal")),
        ("overall (74)", Box::new(|_: &Row| true)),
    ];
    for (name, f) in &groups {
        let [b, s, mm] = tally(rows, f);
        let _ = writeln!(m, "| {name} | {} | {} | {} |", pct(b), pct(s), pct(mm));
    }
    for (name, pick) in [("baseline", 0usize), ("self", 1), ("machine-model", 2)] {
        let _ = write!(
            m,
            "\n## Confusion matrix, {name} reference (rows: label, columns: verdict)\n\n"
        );
        let cols = ["normal", "inner", "outer", "ball", "combination", "error"];
        m += "| label | ";
        m += &cols.join(" | ");
        m += " |\n|---|---:|---:|---:|---:|---:|---:|\n";
        for label in ["normal", "inner", "outer", "ball"] {
            let mut counts = [0usize; 6];
            for r in rows.iter().filter(|r| r.label == label) {
                let v = verdict(match pick {
                    0 => &r.base,
                    1 => &r.own,
                    _ => &r.machine,
                });
                let c = cols.iter().position(|c| *c == v).unwrap_or(4);
                counts[c] += 1;
            }
            let _ = writeln!(
                m,
                "| {label} | {} |",
                counts
                    .iter()
                    .map(|c| c.to_string())
                    .collect::<Vec<_>>()
                    .join(" | ")
            );
        }
    }
    m += "\n## Every record\n\n| record | fs (kHz) | class | load (hp) | rpm | grade | label | verdict (baseline) | verdict (self) | verdict (machine model) | scores i/o/b (dB, baseline) | band (Hz, baseline) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let mark = |v: &str| {
            if v == r.label {
                format!("{v} ✓")
            } else {
                format!("**{v}** ✗")
            }
        };
        let (sc, band) = match &r.base {
            Ok(o) => (
                format!(
                    "{:.0}/{:.0}/{:.0}",
                    o.diagnosis.scores.inner, o.diagnosis.scores.outer, o.diagnosis.scores.ball
                ),
                format!(
                    "{:.0}–{:.0}",
                    o.diagnosis.band.low_hz, o.diagnosis.band.high_hz
                ),
            ),
            Err(_) => ("–".into(), "–".into()),
        };
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {sc} | {band} |",
            r.number,
            r.fs / 1000.0,
            r.class,
            r.load_hp,
            r.rpm,
            r.grade.map_or("–".to_string(), String::from),
            r.label,
            mark(verdict(&r.base)),
            mark(verdict(&r.own)),
            mark(verdict(&r.machine)),
        );
    }
    m += "\n## Wrong verdicts (baseline reference) and why\n\nLine prominences in dB over the local median of the squared envelope spectrum of the common band; ₓ = explained by a stronger detected fault, ≠ = not at h × the fundamental of the strongest harmonic.\n\n";
    for r in rows.iter().filter(|r| verdict(&r.base) != r.label) {
        let _ = writeln!(
            m,
            "- **{}** ({}, grade {}): {} — {}",
            r.number,
            r.class,
            r.grade.map_or("–".to_string(), String::from),
            verdict(&r.base),
            reason(r, &r.base)
        );
    }
    m += trained;
    m += NOTES;
    m += "\nFigures (baseline reference): `figures/<record>_baseline.png` for ";
    m += &FIGURES
        .iter()
        .map(|n| n.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    m += ". Per-record numbers: `records.csv`; every diagnosis in full: `records.json`.\n";
    std::fs::write(out.join("README.md"), m)?;
    Ok(())
}
