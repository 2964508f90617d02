//! `cargo xtask diagnose --false-alarm`: the training-free diagnosis (`diagnosis::diagnose`,
//! self-referenced) over a deterministic corpus of simulated healthy machines
//! (`bearing_model::machine`), noise-only low-level recordings, the same machines with a
//! localized fault, and every real healthy recording of the shared data → the false-alarm rate
//! overall and per factor level, the detection rate per fault and severity
//! → `results/diagnosis/false_alarm.{md,csv,json}`.
//!
//! The corpus design is [`corpus`]'s, fixed before any result was seen; the report is
//! [`report`]'s. No algorithm lives here: synthesis is `bearing-model`'s, the verdict
//! `diagnosis`'s, loading and decimation `bearing-data`'s and `hybrid-fdd-cli`'s.

pub mod corpus;
pub(crate) mod report;
pub(crate) mod speed_range;
pub(crate) mod unknown;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use corpus::{Entry, RealSource};
use rayon::prelude::*;

use crate::common::Context;

/// What one recording's diagnosis gave.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// `normal`, `inner`, …, or `inner+outer` …
    pub verdict: String,
    /// Scores inner, outer, ball, dB.
    pub scores: [f64; 3],
    /// Speed the analysis used, rpm.
    pub rpm_used: f64,
    /// Common band, Hz.
    pub band_hz: [f64; 2],
    /// Every numeric field of the serialised diagnosis named like a probability (`p_healthy`,
    /// `p_value`, …), by its JSON path (array elements named by their `hypothesis`).
    pub p_fields: BTreeMap<String, f64>,
    /// The slowest and fastest speed the recording was order-tracked over, rpm (`None`: read
    /// at one speed).
    pub tracked_rpm: Option<[f64; 2]>,
}

/// One recording's row.
#[derive(Debug, Clone)]
pub struct Row {
    /// The corpus entry.
    pub entry: Entry,
    /// Duration, s.
    pub duration_s: f64,
    /// Seed of a synthetic recording.
    pub seed: Option<u64>,
    /// Drawn parameters worth a column (synthetic only).
    pub drawn: Option<serde_json::Value>,
    /// The diagnosis, or the error's one line.
    pub outcome: Result<Outcome, String>,
    /// Seconds spent making (or loading) the recording.
    pub make_s: f64,
    /// Seconds spent diagnosing it.
    pub diagnose_s: f64,
}

impl Row {
    /// The verdict, or `error`.
    pub fn verdict(&self) -> &str {
        match &self.outcome {
            Ok(o) => &o.verdict,
            Err(_) => "error",
        }
    }

    /// Two CSV cells: the speed used (rpm, 2 decimals) and the error's line (commas and line
    /// breaks made `;`), each empty when the other is given.
    pub fn rpm_used_and_error_cells(&self) -> (String, String) {
        match &self.outcome {
            Ok(o) => (format!("{:.2}", o.rpm_used), String::new()),
            Err(m) => (String::new(), m.replace([',', '\n'], ";")),
        }
    }
}

/// Whether a JSON key names a probability-like field (or the detector's other decision
/// quantity, the modulation depth).
fn p_like(key: &str) -> bool {
    let k = key.to_ascii_lowercase();
    k == "modulation_depth"
        || k == "p"
        || k.starts_with("p_")
        || k.ends_with("_p")
        || k.contains("p_value")
        || k.contains("pvalue")
        || k.contains("probability")
}

/// Collect `p_like` numeric leaves of `v` under `path`.
fn collect_p(v: &serde_json::Value, path: &str, out: &mut BTreeMap<String, f64>) {
    use serde_json::Value;
    let join = |seg: &str| {
        if path.is_empty() {
            seg.to_string()
        } else {
            format!("{path}.{seg}")
        }
    };
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                match x {
                    Value::Number(n) if p_like(k) => {
                        if let Some(f) = n.as_f64() {
                            out.insert(join(k), f);
                        }
                    }
                    Value::Object(_) | Value::Array(_) => collect_p(x, &join(k), out),
                    _ => {}
                }
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                let seg = x
                    .get("hypothesis")
                    .and_then(Value::as_str)
                    .map_or_else(|| i.to_string(), str::to_string);
                collect_p(x, &join(&seg), out);
            }
        }
        _ => {}
    }
}

/// How a recording is diagnosed: with the entry's declared bearing (at its declared speed, or
/// with no speed declared), or as `--bearing unknown`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BearingAs {
    /// The entry's bearing (`diagnosis::diagnose`).
    Declared,
    /// No bearing (`diagnosis::diagnose_unknown_bearing` at the declared speed).
    Unknown,
    /// The entry's bearing and no declared speed: the speed searched over `[low, high]` rpm
    /// (`hybrid-fdd diagnose --rpm-range low-high` without `--rpm`).
    SpeedSearched([f64; 2]),
    /// The entry's bearing at its declared speed, read at one speed only, never order-tracked
    /// (`hybrid-fdd diagnose --steady-speed`).
    DeclaredSteady,
    /// The entry's bearing, the recording order-tracked from a tachometer of this many pulses a
    /// turn recorded beside it (`MachineParams::tachometer`) and diagnosed at the tachometer's
    /// mean speed (`hybrid-fdd diagnose --tach CH --pulses-per-rev N`); synthetic entries only.
    Tachometer(f64),
}

/// Diagnose `x` as the entry declares it (its bearing, or none); `tach` the tachometer recorded
/// beside it, for [`BearingAs::Tachometer`].
fn diagnose(
    x: &[f64],
    fs: f64,
    e: &Entry,
    bearing: BearingAs,
    tach: Option<&[f64]>,
) -> Result<Outcome, String> {
    let signal = diagnosis::Signal::new(x, fs)
        .map_err(diagnosis::DiagnosisError::from)
        .map_err(|e| e.to_string())?;
    let d = match bearing {
        BearingAs::Tachometer(ppr) => {
            // as `hybrid-fdd diagnose --tach` does it (the command's own tracking step)
            let tach = tach.ok_or_else(|| format!("{}: no tachometer", e.id))?;
            let loaded = |samples: &[f64]| -> Result<hybrid_fdd_cli::diagnose::Loaded, String> {
                Ok(hybrid_fdd_cli::diagnose::Loaded {
                    samples: samples.to_vec(),
                    fs_hz: fs,
                    rpm: None,
                    unit: bearing_data::SampleUnit::from_code("m/s^2")
                        .map_err(|e| e.to_string())?,
                    fault_size_in: None,
                })
            };
            let (l, t) = hybrid_fdd_cli::diagnose::order_tracked(&loaded(x)?, &loaded(tach)?, ppr)
                .map_err(|e| format!("{e:#}"))?;
            let tracked = diagnosis::Signal::new(&l.samples, l.fs_hz)
                .map_err(diagnosis::DiagnosisError::from)
                .map_err(|e| e.to_string())?;
            diagnosis::diagnose(&tracked, t.mean_rpm, &e.spec, None).map(|mut d| {
                d.order_tracking = Some(t);
                d
            })
        }
        BearingAs::Declared => diagnosis::diagnose(&signal, e.rpm_declared, &e.spec, None),
        BearingAs::SpeedSearched([low, high]) => diagnosis::diagnose_with_options(
            &signal,
            &e.spec,
            None,
            &diagnosis::DiagnoseOptions::search(low, high),
        ),
        BearingAs::DeclaredSteady => diagnosis::diagnose_with_options(
            &signal,
            &e.spec,
            None,
            &diagnosis::DiagnoseOptions::declared(e.rpm_declared).with_steady_speed(),
        ),
        BearingAs::Unknown => diagnosis::diagnose_unknown_bearing(
            &signal,
            None,
            &diagnosis::DiagnoseOptions::declared(e.rpm_declared),
        ),
    }
    .map_err(|e| e.to_string())?;
    let mut p_fields = BTreeMap::new();
    if let Ok(v) = serde_json::to_value(&d) {
        collect_p(&v, "", &mut p_fields);
    }
    Ok(Outcome {
        verdict: d.verdict.clone(),
        scores: [d.scores.inner, d.scores.outer, d.scores.ball],
        rpm_used: d.operating_point.rpm_used,
        band_hz: [d.band.low_hz, d.band.high_hz],
        p_fields,
        tracked_rpm: d.order_tracking.as_ref().map(|t| [t.min_rpm, t.max_rpm]),
    })
}

/// The drawn parameters a reader may want beside the verdict (modes, gear, mains, fault mode).
fn drawn_summary(p: &bearing_model::machine::MachineParams) -> serde_json::Value {
    let r = &p.recipe;
    let nu = r.nuisances;
    let mut v = serde_json::json!({
        "rms_ms2": match r.level {
            bearing_model::machine::Level::Running { rms_ms2 } => rms_ms2,
            bearing_model::machine::Level::NoiseOnly { rms_lsb } =>
                rms_lsb * r.adc.map_or(1.0, |a| a.lsb_ms2()),
        },
        "modes_hz": p.structure.modes.iter().map(|m| (m.freq_hz * 10.0).round() / 10.0).collect::<Vec<_>>(),
        "speed_wander_rms_pct": (p.speed.rms_fraction * 1e5).round() / 1e3,
    });
    let o = v.as_object_mut().expect("an object");
    if nu.gear_mesh {
        o.insert("gear_z1".into(), p.gear_mesh.z1.into());
        o.insert("gear_z2".into(), p.gear_mesh.z2.into());
    }
    if nu.electrical {
        o.insert(
            "line_hz".into(),
            ((p.electrical.line_hz * 1e3).round() / 1e3).into(),
        );
        if let Some(pp) = p.electrical.pole_pass_hz {
            o.insert("pole_pass_hz".into(), ((pp * 1e3).round() / 1e3).into());
        }
    }
    if nu.other_shaft {
        o.insert(
            "other_shaft_order".into(),
            ((p.other_shaft.order * 1e4).round() / 1e4).into(),
        );
        o.insert(
            "other_shaft_db".into(),
            ((p.other_shaft.level_db * 10.0).round() / 10.0).into(),
        );
    }
    if let Some(adc) = r.adc {
        o.insert("adc_bits".into(), adc.bits.into());
    }
    if let Some(w) = r.sweep {
        o.insert("sweep".into(), w.shape.name().into());
        o.insert("sweep_span".into(), w.span.into());
    }
    if let Some(f) = &p.fault {
        o.insert(
            "fault_mode_hz".into(),
            ((p.structure.modes[f.mode].freq_hz * 10.0).round() / 10.0).into(),
        );
        o.insert(
            "fault_slip_pct".into(),
            ((f.slip * 1e5).round() / 1e3).into(),
        );
    }
    v
}

/// Make (or load) and diagnose one entry.
fn run_entry(e: &Entry, data: Option<&Path>, bearing: BearingAs) -> anyhow::Result<Row> {
    let t0 = Instant::now();
    let (x, fs, seed, drawn, tach) = if let Some(r) = &e.recipe {
        let p = r
            .draw()
            .with_context(|| format!("{}: drawing the machine", e.id))?;
        let rec = p
            .synthesize()
            .with_context(|| format!("{}: synthesising", e.id))?;
        let tach = match bearing {
            BearingAs::Tachometer(ppr) => Some(
                p.tachometer(ppr)
                    .with_context(|| format!("{}: its tachometer", e.id))?,
            ),
            _ => None,
        };
        (
            rec.accel,
            rec.fs_hz,
            Some(r.seed),
            Some(drawn_summary(&p)),
            tach,
        )
    } else {
        let dir = data.ok_or_else(|| anyhow::anyhow!("{}: no data directory", e.id))?;
        let (x, fs) = load_real(e, dir)?;
        (x, fs, None, None, None)
    };
    let make_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let outcome = diagnose(&x, fs, e, bearing, tach.as_deref());
    Ok(Row {
        duration_s: x.len() as f64 / fs,
        entry: e.clone(),
        seed,
        drawn,
        outcome,
        make_s,
        diagnose_s: t1.elapsed().as_secs_f64(),
    })
}

/// A real recording's samples and rate.
fn load_real(e: &Entry, dir: &Path) -> anyhow::Result<(Vec<f64>, f64)> {
    match &e.real {
        Some(RealSource::Cwru97 { decimate }) => {
            let rec = bearing_data::load_record(dir, 97, &bearing_data::LoadOptions::default())
                .context("loading 97.mat")?;
            if *decimate == 1 {
                Ok((rec.de().to_vec(), rec.fs_hz()))
            } else {
                let x =
                    bearing_data::Decimator::new(bearing_data::DecimatorParams::new(*decimate))?
                        .decimate(rec.de())?;
                Ok((x, rec.fs_hz() / *decimate as f64))
            }
        }
        Some(RealSource::Cut {
            of,
            start_s,
            duration_s,
        }) => {
            let inner = Entry {
                real: Some((**of).clone()),
                ..e.clone()
            };
            let (x, fs) = load_real(&inner, dir)?;
            let a = (start_s * fs).round() as usize;
            let b = ((start_s + duration_s) * fs).round() as usize;
            anyhow::ensure!(
                b <= x.len(),
                "{}: the piece {start_s:.2}–{:.2} s lies beyond the recording's {:.2} s",
                e.id,
                start_s + duration_s,
                x.len() as f64 / fs
            );
            Ok((x[a..b].to_vec(), fs))
        }
        Some(RealSource::Uestc { rel_path }) => {
            // the rate is passed explicitly: the loader may not read `SampleFrequency` yet (a
            // stored rate, when it does, wins and is the same 20 kHz)
            let l = hybrid_fdd_cli::diagnose::load_with(
                &dir.join(rel_path),
                "Data",
                Some(corpus::UESTC_FS_HZ),
                hybrid_fdd_cli::diagnose::FsFlag::ForUnstated,
            )
            .with_context(|| format!("loading {rel_path}"))?;
            Ok((l.samples, l.fs_hz))
        }
        None => anyhow::bail!("{}: neither synthetic nor real", e.id),
    }
}

/// The real entries whose files are present (a message for each one missing; an error under
/// `CI=true`).
pub(crate) fn present_real(ctx: &Context) -> anyhow::Result<(Vec<Entry>, Option<&Path>)> {
    let Some(dir) = ctx.data_dir_or_skip()? else {
        println!(
            "diagnose --false-alarm: no data directory found; the real healthy recordings are skipped"
        );
        return Ok((Vec::new(), None));
    };
    let rpm_97 = match bearing_data::load_record(dir, 97, &bearing_data::LoadOptions::default()) {
        Ok(r) => Some(r.rpm().value),
        Err(err) if ctx.ci => return Err(anyhow::Error::new(err).context("loading 97.mat")),
        Err(err) => {
            println!("diagnose --false-alarm: skipping CWRU 97.mat ({err})");
            None
        }
    };
    let mut out = Vec::new();
    for e in corpus::real_entries(rpm_97.unwrap_or(0.0))? {
        let present = match &e.real {
            Some(RealSource::Cwru97 { .. }) => rpm_97.is_some(),
            Some(RealSource::Uestc { rel_path }) => {
                let ok = dir.join(rel_path).is_file();
                if !ok {
                    let msg = format!("{} is missing", dir.join(rel_path).display());
                    if ctx.ci {
                        anyhow::bail!(msg);
                    }
                    println!("diagnose --false-alarm: skipping {} ({msg})", e.id);
                }
                ok
            }
            Some(RealSource::Cut { .. }) | None => false,
        };
        if present {
            out.push(e);
        }
    }
    Ok((out, Some(dir)))
}

/// CPU time of this process so far (all threads, user + system), s: `/proc/self/stat`'s
/// utime and stime at Linux's 100 ticks per second; `None` elsewhere.
pub(crate) fn process_cpu_s() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    let after = s.rsplit_once(')')?.1;
    let f: Vec<&str> = after.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Run the task into `results/diagnosis/false_alarm.*`.
pub fn run(ctx: &Context) -> anyhow::Result<()> {
    let start = Instant::now();
    let mut entries = corpus::false_alarm_design()?;
    let (real, dir) = present_real(ctx)?;
    let cuts = corpus::real_cuts(&real);
    entries.extend(real);
    entries.extend(cuts);
    let cpu0 = process_cpu_s();
    let rows = run_entries(&entries, dir, BearingAs::Declared)?;
    // the designation design's machines again, told their exact geometry: what knowing only the
    // designation costs; the short-record design's recorded for 6 s: what the short record costs
    let again: Vec<Entry> = entries
        .iter()
        .filter(|e| e.kind.designated() || e.kind.short())
        .map(|e| corpus::with_full_length(&corpus::with_exact_geometry(e)))
        .collect();
    let again_rows = run_entries(&again, dir, BearingAs::Declared)?;
    let (exact_rows, full_rows): (Vec<Row>, Vec<Row>) = again_rows
        .into_iter()
        .partition(|r| r.entry.kind.designated());
    // the speed-sweep design's machines read at one speed: what the order tracking does
    let sweeping: Vec<Entry> = entries.iter().filter(|e| e.kind.sweep()).cloned().collect();
    let steady_rows = run_entries(&sweeping, dir, BearingAs::DeclaredSteady)?;
    let tach_rows = run_entries(
        &sweeping,
        dir,
        BearingAs::Tachometer(corpus::SWEEP_TACH_PULSES_PER_REV),
    )?;
    let wall_s = start.elapsed().as_secs_f64();
    let cpu_s = process_cpu_s().zip(cpu0).map(|(b, a)| b - a);
    let out = ctx.root.join("results/diagnosis");
    std::fs::create_dir_all(&out)?;
    report::write(
        &rows,
        &report::Again {
            exact: &exact_rows,
            full_length: &full_rows,
            steady: &steady_rows,
            tachometer: &tach_rows,
        },
        wall_s,
        cpu_s,
        &out,
    )?;
    println!(
        "wrote {}/false_alarm.{{md,csv,json}} ({} recordings, {wall_s:.0} s)",
        out.display(),
        rows.len()
    );
    Ok(())
}

/// Whether corpus id `id` is one of `patterns` (exact, or a prefix before a trailing `*`).
fn id_matches(id: &str, patterns: &[String]) -> bool {
    patterns.iter().any(|p| match p.strip_suffix('*') {
        Some(prefix) => id.starts_with(prefix),
        None => id == p,
    })
}

/// Diagnose the corpus entries (and real healthy recordings) whose ids match `patterns` and print
/// one line each — verdict, speed used, the smallest `p_healthy`, the drawn parameters — writing
/// no report. An error when nothing matches.
pub fn run_only(
    ctx: &Context,
    patterns: &[String],
    bearing: BearingAs,
    write_csv: Option<&Path>,
) -> anyhow::Result<()> {
    let mut entries = corpus::false_alarm_design()?;
    let (real, dir) = present_real(ctx)?;
    let cuts = corpus::real_cuts(&real);
    entries.extend(real);
    entries.extend(cuts);
    entries.retain(|e| id_matches(&e.id, patterns));
    if entries.is_empty() {
        anyhow::bail!(
            "--only {}: no corpus entry has such an id (ids look like H001, N01, F001, R-…)",
            patterns.join(",")
        );
    }
    if let Some(out) = write_csv {
        std::fs::create_dir_all(out)?;
        for e in &entries {
            let Some(recipe) = &e.recipe else { continue };
            let rec = recipe.draw()?.synthesize()?;
            let mut s = String::from("time_s,accel\n");
            for (i, a) in rec.accel.iter().enumerate() {
                let _ = writeln!(s, "{:.8},{a:.9e}", i as f64 / rec.fs_hz);
            }
            let path = out.join(format!("{}.csv", e.id));
            std::fs::write(&path, s).with_context(|| format!("writing {}", path.display()))?;
            println!("wrote {} ({} Hz, m/s²)", path.display(), rec.fs_hz);
        }
    }
    for r in run_entries(&entries, dir, bearing)? {
        let e = &r.entry;
        let (rpm, p) = match &r.outcome {
            Ok(o) => (
                format!("{:.2}", o.rpm_used),
                o.p_fields
                    .get("p_healthy")
                    .map_or_else(String::new, |p| format!("{p:.3e}")),
            ),
            Err(m) => (String::new(), m.clone()),
        };
        let drawn = r.drawn.as_ref().map_or_else(String::new, |d| d.to_string());
        println!(
            "{} {} {} rpm {:.2} (declared {:.2}, used {rpm}) {:.0} Hz {} → {} p_healthy {p} {drawn}",
            e.id,
            e.kind.name(),
            e.geometry,
            e.rpm_true,
            e.rpm_declared,
            e.fs_hz,
            e.nuisances,
            r.verdict()
        );
    }
    Ok(())
}

/// Make and diagnose every entry in parallel, rows in entry order.
pub fn run_entries(
    entries: &[Entry],
    dir: Option<&Path>,
    bearing: BearingAs,
) -> anyhow::Result<Vec<Row>> {
    let bar = indicatif::ProgressBar::new(entries.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} recordings, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    // the slowest first (highest rate), so the last ones do not leave a core idle
    let mut order: Vec<usize> = (0..entries.len()).collect();
    order.sort_by(|&a, &b| entries[b].fs_hz.total_cmp(&entries[a].fs_hz));
    let mut rows: Vec<(usize, Row)> = order
        .par_iter()
        .map(|&i| {
            let r = run_entry(&entries[i], dir, bearing);
            bar.inc(1);
            r.map(|r| (i, r))
        })
        .collect::<anyhow::Result<_>>()?;
    bar.finish_and_clear();
    rows.sort_by_key(|r| r.0);
    Ok(rows.into_iter().map(|r| r.1).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tiny_corpus_gives_the_same_rows_twice() {
        // 6 healthy, 2 noise-only, 1 faulty per cell (6 cells fit), 2 s each
        let entries = corpus::design(6, 2, 1, 2.0).unwrap();
        assert_eq!(entries.len(), 6 + 2 + 6);
        let a = run_entries(&entries, None, BearingAs::Declared).unwrap();
        let b = run_entries(&entries, None, BearingAs::Declared).unwrap();
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.entry, y.entry);
            assert_eq!(x.outcome, y.outcome);
            assert_eq!(x.drawn, y.drawn);
        }
    }

    #[test]
    fn probability_fields_are_found_by_name() {
        let v = serde_json::json!({
            "verdict": "normal",
            "p_healthy": 0.5,
            "evidence": [
                {"hypothesis": "inner", "p_value": 0.01, "score_db": 3.0},
                {"hypothesis": "outer", "p_value": 0.2}
            ],
            "scores": {"inner": 1.0}
        });
        let mut out = BTreeMap::new();
        collect_p(&v, "", &mut out);
        let keys: Vec<&str> = out.keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            [
                "evidence.inner.p_value",
                "evidence.outer.p_value",
                "p_healthy"
            ]
        );
    }
}
