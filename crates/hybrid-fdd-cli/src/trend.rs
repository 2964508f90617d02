//! `trend`: a directory of recordings of one machine (or an index CSV `file,time`) → one row
//! per recording of health indicators, thresholds from the first N, the onset alarm and the fault
//! named (the `trend` crate), as `trend.csv`, `trend.json`, `summary.md` and `trend.png`.
//!
//! Layouts read as they come: IMS (ASCII, tab-separated, no header, 4 or 8 columns, files named
//! by their timestamp without extension, 20 kHz by default), XJTU-SY (CSV with the header
//! `Horizontal_vibration_signals,Vertical_vibration_signals`, files `1.csv`, `2.csv`, …,
//! 25.6 kHz by default), and whatever `diagnose` reads (`.mat`, CSV with a JSON sidecar).

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use rayon::prelude::*;

use crate::diagnose::{FsFlag, load_with, rpm_or_sidecar};

/// Default sampling rate of IMS-layout files, Hz (the IMS data set's README: 20 kHz).
pub const IMS_FS_HZ: f64 = 20_000.0;
/// Default sampling rate of XJTU-SY-layout files, Hz (the XJTU-SY data set: 25.6 kHz).
pub const XJTU_FS_HZ: f64 = 25_600.0;
/// XJTU-SY's header.
pub const XJTU_HEADER: [&str; 2] = ["Horizontal_vibration_signals", "Vertical_vibration_signals"];

/// Flags of `trend`.
#[derive(clap::Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Directory of recordings of one machine, ordered by the time in their names (IMS's
    /// `2004.02.12.10.32.39`, ISO dates such as `2024-03-01T12:00:00` or `20240301T120000`, or
    /// numbers as XJTU-SY's `1.csv`, `2.csv`, … in numeric order).
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// Index CSV `file,time[,start_s,duration_s]` instead of `--input`: files absolute or
    /// relative to the index's directory (anywhere: a staged sequence without copying data),
    /// times numbers (order only) or calendar times, optional segments in seconds.
    #[arg(long)]
    pub index: Option<PathBuf>,
    /// Bearing: a catalogue designation (`hybrid-fdd bearings`), a geometry
    /// `n=…,d=…,D=…[,angle=…]`, or `unknown`.
    #[arg(long)]
    pub bearing: String,
    /// Declared shaft speed, rpm (searched ± 10 % per recording by the diagnosis); by default a
    /// file's stored speed or its `simulate` sidecar's.
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Sampling rate, Hz, of files that store none (default: 20 000 for IMS-layout files,
    /// 25 600 for XJTU-SY-layout files).
    #[arg(long)]
    pub fs: Option<f64>,
    /// Channel: a column name or number (1 = first) of a text file (default: column 1 of IMS
    /// files, `Horizontal_vibration_signals` of XJTU-SY files), DE/FE/BA of a CWRU `.mat`.
    #[arg(long)]
    pub channel: Option<String>,
    /// The first N recordings (in time order) are the healthy baseline.
    #[arg(long, default_value_t = 10)]
    pub baseline_count: usize,
    /// ISO 20816-3 machine group and foundation, for the velocity's zone: group1-rigid,
    /// group1-flexible, group2-rigid, group2-flexible.
    #[arg(long)]
    pub machine_group: Option<String>,
    /// Unit of the samples: g or m/s2 (default: what the files state, else unknown).
    #[arg(long)]
    pub unit: Option<String>,
    /// k of the thresholds median + k·1.4826·MAD.
    #[arg(long, default_value_t = trend::DEFAULT_K)]
    pub k: f64,
    /// Alarm rule: above the threshold in M of N consecutive recordings, as `M/N`.
    #[arg(long, default_value = "3/4")]
    pub alarm: String,
    /// The indicators whose onset makes the run's alarm, comma-separated, e.g.
    /// `kurtosis,evidence_outer,hostsmo_ratio`; `all` for every indicator. Default: the
    /// gain-immune ones (crest, kurtosis, the evidence, the observers' `*_ratio`): an amplitude
    /// or an energy rises with a load step or a sensor's gain as with a fault, so it is trended
    /// and thresholded but does not raise the alarm unless named here.
    #[arg(long, value_delimiter = ',')]
    pub alarm_on: Option<Vec<String>>,
    /// Exponent p of the speed normalisation of amplitudes (energies take 2p; fitted per
    /// indicator instead when the baseline's speeds span 10 % or more).
    #[arg(long, default_value_t = trend::DEFAULT_SPEED_EXPONENT)]
    pub speed_exponent: f64,
    /// Decimate files sampled at an integer multiple of this rate (Hz) to it, with the
    /// anti-aliasing decimator `diagnose` uses for baselines (e.g. CWRU's 48 kHz 97.mat in a
    /// 12 kHz staged sequence); without it, mixed rates are an error.
    #[arg(long)]
    pub decimate_to: Option<f64>,
    /// Skip the dissertation's observers (their calibration on the baseline takes seconds).
    #[arg(long)]
    pub no_observers: bool,
    /// Output directory: trend.csv, trend.json, summary.md, trend.png.
    #[arg(long)]
    pub report: PathBuf,
}

/// How the files of a run are laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// IMS: headerless tab-separated text, 4 or 8 columns.
    Ims,
    /// XJTU-SY: CSV with the two-column header.
    Xjtu,
    /// Anything `diagnose` reads.
    Other,
}

impl Layout {
    fn name(self) -> &'static str {
        match self {
            Layout::Ims => "IMS (tab-separated, no header)",
            Layout::Xjtu => "XJTU-SY (CSV, horizontal/vertical header)",
            Layout::Other => "diagnose's readers (.mat, CSV)",
        }
    }
}

/// The layout of one file and its column count (text files; 0 for others).
///
/// # Errors
/// Unreadable files.
pub fn layout_of(path: &Path) -> anyhow::Result<(Layout, usize)> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if ext == "mat" {
        return Ok((Layout::Other, 0));
    }
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .with_context(|| format!("reading {}", path.display()))?;
    if head.starts_with(b"MATLAB")
        || std::str::from_utf8(&head).is_err_and(|e| e.error_len().is_some())
    {
        return Ok((Layout::Other, 0));
    }
    let text = String::from_utf8_lossy(&head);
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap_or("");
    let first = first.trim_start_matches('\u{feff}');
    let delim = if first.contains('\t') {
        '\t'
    } else if first.contains(';') {
        ';'
    } else {
        ','
    };
    let fields: Vec<&str> = first
        .split(delim)
        .map(|f| f.trim().trim_matches('"'))
        .collect();
    let numeric = fields.iter().all(|f| f.parse::<f64>().is_ok());
    if fields.len() == 2
        && fields
            .iter()
            .zip(XJTU_HEADER)
            .all(|(f, h)| f.eq_ignore_ascii_case(h))
    {
        return Ok((Layout::Xjtu, 2));
    }
    if numeric && delim == '\t' && matches!(fields.len(), 4 | 8) && ext.is_empty()
        || numeric
            && delim == '\t'
            && matches!(fields.len(), 4 | 8)
            && ext.bytes().all(|b| b.is_ascii_digit())
    {
        return Ok((Layout::Ims, fields.len()));
    }
    Ok((Layout::Other, fields.len()))
}

/// The files of a run with their names (as shown) and times, in time order, and the axis.
/// A file of a run: its path, the name shown, its time, and the segment (start, duration) in
/// seconds an index row asks for.
type Entry = (PathBuf, String, f64, (Option<f64>, Option<f64>));

fn files_in_order(args: &Args) -> anyhow::Result<(Vec<Entry>, trend::TimeAxis)> {
    if args.index.is_some() && args.input.is_some() {
        bail!("give --input DIR or --index FILE, not both");
    }
    if let Some(index) = &args.index {
        let text = std::fs::read_to_string(index)
            .with_context(|| format!("reading {}", index.display()))?;
        let entries = trend::parse_index(&index.display().to_string(), &text)?;
        let base = index
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let names: Vec<String> = entries
            .iter()
            .map(|e| match (e.start_s, e.duration_s) {
                (None, None) => e.file.clone(),
                (a, d) => format!(
                    "{}[{}+{}s]",
                    e.file,
                    a.unwrap_or(0.0),
                    d.map_or("end".to_string(), |d| d.to_string())
                ),
            })
            .collect();
        let times: Vec<(usize, trend::NameTime)> = entries
            .iter()
            .enumerate()
            .map(|(i, e)| (i, e.time))
            .collect();
        let (order, axis) = trend::order::order_times(&names, &times)?;
        let mut out = Vec::new();
        for (i, t) in order {
            let e = &entries[i];
            let p = Path::new(&e.file);
            let path = if p.is_absolute() {
                p.to_path_buf()
            } else {
                base.join(p)
            };
            if !path.is_file() {
                bail!(
                    "{}: line {}: {} is not a file",
                    index.display(),
                    e.line,
                    path.display()
                );
            }
            out.push((path, names[i].clone(), t, (e.start_s, e.duration_s)));
        }
        return Ok((out, axis));
    }
    let input = args
        .input
        .as_deref()
        .context("--input DIR or --index FILE is required")?;
    if !input.is_dir() {
        // an I/O error (the Python package's DataError); the message is the same
        return Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("--input {} is not a directory", input.display()),
        )
        .into());
    }
    let files = crate::diagnose::expand(input)?;
    let names: Vec<String> = files
        .iter()
        .map(|p| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        })
        .collect();
    let (order, axis) = trend::order_names(&names)?;
    Ok((
        order
            .into_iter()
            .map(|(i, t)| (files[i].clone(), names[i].clone(), t, (None, None)))
            .collect(),
        axis,
    ))
}

/// A trend computed: the report and what the command's outputs say beside it.
#[derive(Debug, Clone)]
pub struct Trend {
    /// The `trend` crate's report.
    pub report: trend::TrendReport,
    /// Where the recordings came from (`directory DIR`, `index FILE`, or arrays in memory).
    pub source: String,
    /// The files' layout, as named in the outputs.
    pub layout: String,
    /// The channel read.
    pub channel: String,
    /// Notes on the run (decimation, a speed from a sidecar, units that disagree).
    pub run_notes: Vec<String>,
}

impl Trend {
    /// `trend.json` as a JSON value: the report plus `source`, `layout`, `channel`, `run_notes`.
    ///
    /// # Errors
    /// Serialisation errors.
    pub fn json(&self) -> anyhow::Result<serde_json::Value> {
        let mut json = serde_json::to_value(&self.report)?;
        json["source"] = serde_json::Value::String(self.source.clone());
        json["layout"] = serde_json::Value::String(self.layout.clone());
        json["channel"] = serde_json::Value::String(self.channel.clone());
        json["run_notes"] = serde_json::to_value(&self.run_notes)?;
        Ok(json)
    }

    /// `trend.json`'s text, as the command writes it.
    ///
    /// # Errors
    /// Serialisation errors.
    pub fn json_text(&self) -> anyhow::Result<String> {
        Ok(serde_json::to_string_pretty(&self.json()?)? + "\n")
    }

    /// Write `trend.csv`, `trend.json`, `summary.md` and `trend.png` into `out` (which exists).
    ///
    /// # Errors
    /// Output errors.
    pub fn write(&self, out: &Path) -> anyhow::Result<()> {
        std::fs::write(out.join("trend.csv"), csv(&self.report))?;
        std::fs::write(out.join("trend.json"), self.json_text()?)?;
        std::fs::write(
            out.join("summary.md"),
            summary(
                &self.report,
                &self.source,
                &self.layout,
                &self.channel,
                &self.run_notes,
            ),
        )?;
        figure(&self.report, &out.join("trend.png"))
    }
}

/// The flags every run parses before reading anything: the bearing, and the configuration
/// (checked) with the unit declared, if any.
struct Parsed {
    bearing: diagnosis::BearingSpec,
    cfg: trend::TrendConfig,
    declared_unit: Option<trend::Unit>,
}

fn parse_flags(args: &Args) -> anyhow::Result<Parsed> {
    let bearing = if args
        .bearing
        .trim()
        .eq_ignore_ascii_case(crate::diagnose::UNKNOWN_BEARING)
    {
        crate::diagnose::unknown_bearing()
    } else {
        crate::parse_bearing(&args.bearing)?
    };
    let (m, n) = args
        .alarm
        .split_once('/')
        .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
        .with_context(|| format!("--alarm {}: expected M/N, e.g. 3/4", args.alarm))?;
    let group = args
        .machine_group
        .as_deref()
        .map(trend::MachineGroup::parse)
        .transpose()?;
    let declared_unit = args.unit.as_deref().map(trend::Unit::parse).transpose()?;
    if let Some(f) = args.fs
        && !(f.is_finite() && f > 0.0)
    {
        bail!("--fs {f}: must be a positive number of Hz");
    }
    if let Some(r) = args.rpm
        && !(r.is_finite() && r > 0.0)
    {
        bail!("--rpm {r}: must be a positive number of rpm");
    }
    // check the configuration before reading anything
    let cfg = trend::TrendConfig {
        baseline_count: args.baseline_count,
        k: args.k,
        m,
        n,
        speed_exponent: args.speed_exponent,
        machine_group: group,
        observers: !args.no_observers,
        alarm_on: args.alarm_on.clone(),
        ..Default::default()
    };
    cfg.clone().check()?;
    Ok(Parsed {
        bearing,
        cfg,
        declared_unit,
    })
}

/// The progress bar of a run of `len` steps (hidden when `show` is false).
fn progress_bar(len: usize, show: bool) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// One recording as read, before the run's checks: samples, rate, the speed given with it (the
/// file's own) and the unit it states.
struct Raw {
    name: String,
    time: f64,
    samples: Vec<f64>,
    fs_hz: f64,
    rpm: Option<f64>,
    unit: String,
}

/// `--decimate-to` and the speed (`--rpm`, else the recording's own, else `fallback`'s) applied
/// to a recording read: the `trend` crate's recording, its unit and notes.
fn finish_recording(
    args: &Args,
    mut r: Raw,
    fallback: impl FnOnce() -> (Option<f64>, Option<String>),
) -> anyhow::Result<(trend::TrendRecording, String, Vec<String>)> {
    let name = r.name;
    let mut notes = Vec::new();
    if let Some(to) = args.decimate_to
        && let Some((x, q)) =
            crate::diagnose::decimated_to(&r.samples, r.fs_hz, to).with_context(|| name.clone())?
    {
        notes.push(format!(
            "{name}: decimated by {q} from {} Hz to {to} Hz",
            r.fs_hz
        ));
        r.samples = x;
        r.fs_hz = to;
    }
    let rpm = match args.rpm.or(r.rpm) {
        Some(v) => v,
        None => {
            let (v, note) = fallback();
            notes.extend(note);
            v.with_context(|| format!("{name}: no speed stored in the file; give --rpm"))?
        }
    };
    Ok((
        trend::TrendRecording {
            name,
            time: r.time,
            samples: r.samples,
            fs_hz: r.fs_hz,
            rpm,
        },
        r.unit,
        notes,
    ))
}

/// The run's unit, the configuration checked with it, and [`trend::analyse_with_progress`].
fn analyse_read(
    parsed: Parsed,
    read: Vec<(trend::TrendRecording, String, Vec<String>)>,
    axis: trend::TimeAxis,
    bar: &indicatif::ProgressBar,
) -> anyhow::Result<(trend::TrendReport, Vec<String>)> {
    let file_units: Vec<&str> = read.iter().map(|r| r.1.as_str()).collect();
    let mut run_notes: Vec<String> = read.iter().flat_map(|r| r.2.clone()).collect();
    let unit = match parsed.declared_unit {
        Some(u) => u,
        None if file_units.iter().all(|u| *u == file_units[0]) => {
            trend::Unit::parse(file_units[0]).unwrap_or(trend::Unit::Unknown)
        }
        None => {
            run_notes.push(
                "the files state different units: unit taken as unknown (give --unit)".into(),
            );
            trend::Unit::Unknown
        }
    };
    let cfg = trend::TrendConfig { unit, ..parsed.cfg }.check()?;
    let recs: Vec<trend::TrendRecording> = read.into_iter().map(|r| r.0).collect();
    bar.set_message("analysing");
    let report = trend::analyse_with_progress(&recs, axis, &parsed.bearing, &cfg, &|| bar.inc(1))?;
    bar.finish_and_clear();
    Ok((report, run_notes))
}

/// Read and analyse the run `args` names (`--input` or `--index`), without writing anything
/// but `report` (created, and refused when it is the input directory), with a progress bar on
/// standard error when `progress`. [`run`] is this, [`Trend::write`] and its lines.
///
/// # Errors
/// As [`run`].
pub fn compute(args: &Args, report: Option<&Path>, progress: bool) -> anyhow::Result<Trend> {
    let parsed = parse_flags(args)?;
    // outputs never go into the input directory
    if let Some(report) = report {
        std::fs::create_dir_all(report)
            .with_context(|| format!("creating {}", report.display()))?;
        if let Some(input) = &args.input {
            let (a, b) = (std::fs::canonicalize(input), std::fs::canonicalize(report));
            if let (Ok(a), Ok(b)) = (a, b)
                && a == b
            {
                bail!(
                    "--report {} is the input directory: choose another",
                    report.display()
                );
            }
        }
    }
    let (files, axis) = files_in_order(args)?;
    if files.len() < args.baseline_count {
        return Err(trend::TrendError::TooFewRecordings {
            needed: args.baseline_count,
            found: files.len(),
        }
        .into());
    }
    // one layout and one column count for the whole run
    let layouts: Vec<(Layout, usize)> = files
        .iter()
        .map(|(p, _, _, _)| layout_of(p))
        .collect::<anyhow::Result<_>>()?;
    let (layout, cols) = layouts[0];
    for ((l, c), (_, name, _, _)) in layouts.iter().zip(&files) {
        // an I/O error of kind InvalidData: a file's problem, not a flag's (the Python
        // package's DataError); the message is the same
        let mixed = |m: String| std::io::Error::new(std::io::ErrorKind::InvalidData, m);
        if *l != layout {
            return Err(mixed(format!(
                "{name}: laid out as {}, but {} as {}: one layout per run",
                l.name(),
                files[0].1,
                layout.name()
            ))
            .into());
        }
        if *c != cols {
            return Err(mixed(format!(
                "{name}: {c} columns, but {} has {cols}: one channel count per run",
                files[0].1
            ))
            .into());
        }
    }
    let channel = args.channel.clone().unwrap_or_else(|| match layout {
        Layout::Ims => "1".into(),
        Layout::Xjtu => XJTU_HEADER[0].into(),
        Layout::Other => "DE".into(),
    });
    let fs = args.fs.or(match layout {
        Layout::Ims => Some(IMS_FS_HZ),
        Layout::Xjtu => Some(XJTU_FS_HZ),
        Layout::Other => None,
    });
    let bar = progress_bar(2 * files.len(), progress);
    bar.set_message("reading");
    type Read = (trend::TrendRecording, String, Vec<String>);
    let read: Vec<Read> = files
        .par_iter()
        .map(|(path, name, time, (start, duration))| {
            let mut l =
                load_with(path, &channel, fs, FsFlag::ForUnstated).with_context(|| name.clone())?;
            if start.is_some() || duration.is_some() {
                let a = (start.unwrap_or(0.0) * l.fs_hz).round() as usize;
                let b = duration.map_or(l.samples.len(), |d| a + (d * l.fs_hz).round() as usize);
                if b > l.samples.len() || a >= b {
                    bail!(
                        "{name}: the segment asks for samples {a}..{b}, the file has {}",
                        l.samples.len()
                    );
                }
                l.samples = l.samples[a..b].to_vec();
            }
            let raw = Raw {
                name: name.clone(),
                time: *time,
                samples: l.samples,
                fs_hz: l.fs_hz,
                rpm: l.rpm,
                unit: l.unit.code.clone(),
            };
            let r = finish_recording(args, raw, || rpm_or_sidecar(path, None))?;
            bar.inc(1);
            Ok(r)
        })
        .collect::<anyhow::Result<_>>()?;
    let (report, run_notes) = analyse_read(parsed, read, axis, &bar)?;
    let source = match (&args.index, &args.input) {
        (Some(i), _) => format!("index {}", i.display()),
        (None, Some(d)) => format!("directory {}", d.display()),
        (None, None) => String::new(),
    };
    Ok(Trend {
        report,
        source,
        layout: layout.name().into(),
        channel,
        run_notes,
    })
}

/// A recording held in memory (from the Python package): its name, time, samples, rate, speed
/// (else `--rpm`) and unit (`g`, `m/s2`; else `--unit` or unknown).
#[derive(Debug, Clone)]
pub struct InMemory {
    /// Shown in the outputs and errors.
    pub name: String,
    /// Its time: a number (a position) or a calendar time.
    pub time: trend::NameTime,
    /// The samples of its one channel.
    pub samples: Vec<f64>,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Its shaft speed, rpm (else `--rpm`).
    pub rpm: Option<f64>,
    /// The unit its samples are in.
    pub unit: Option<String>,
}

/// What [`compute`] does with recordings in memory instead of files: ordered by their times
/// (one kind of time, no duplicates), `--decimate-to`, `--rpm`, `--unit` and the configuration
/// applied as for files; `--input`, `--index`, `--fs` and `--channel` are not used.
///
/// # Errors
/// As [`compute`]: duplicate or mixed times, too few recordings, mixed rates, bad flags.
pub fn compute_in_memory(
    args: &Args,
    recordings: Vec<InMemory>,
    progress: bool,
) -> anyhow::Result<Trend> {
    let parsed = parse_flags(args)?;
    let names: Vec<String> = recordings.iter().map(|r| r.name.clone()).collect();
    let times: Vec<(usize, trend::NameTime)> = recordings
        .iter()
        .enumerate()
        .map(|(i, r)| (i, r.time))
        .collect();
    let (order, axis) = trend::order::order_times(&names, &times)?;
    if recordings.len() < args.baseline_count {
        return Err(trend::TrendError::TooFewRecordings {
            needed: args.baseline_count,
            found: recordings.len(),
        }
        .into());
    }
    let bar = progress_bar(2 * recordings.len(), progress);
    bar.set_message("reading");
    let mut slots: Vec<Option<InMemory>> = recordings.into_iter().map(Some).collect();
    let ordered: Vec<(InMemory, f64)> = order
        .into_iter()
        .filter_map(|(i, t)| slots[i].take().map(|r| (r, t)))
        .collect();
    let read: Vec<(trend::TrendRecording, String, Vec<String>)> = ordered
        .into_par_iter()
        .map(|(r, t)| {
            let raw = Raw {
                name: r.name,
                time: t,
                samples: r.samples,
                fs_hz: r.fs_hz,
                rpm: r.rpm,
                unit: r.unit.unwrap_or_else(|| "unknown".into()),
            };
            let out = finish_recording(args, raw, || (None, None))?;
            bar.inc(1);
            Ok(out)
        })
        .collect::<anyhow::Result<_>>()?;
    let (report, run_notes) = analyse_read(parsed, read, axis, &bar)?;
    Ok(Trend {
        report,
        source: "recordings in memory".into(),
        layout: "arrays in memory".into(),
        channel: "as given".into(),
        run_notes,
    })
}

/// Run `trend`.
///
/// # Errors
/// Bad flags, unreadable or mixed files (one line naming the file), the `trend` crate's typed
/// errors, output errors.
pub fn run(args: &Args) -> anyhow::Result<()> {
    let t = compute(args, Some(&args.report), true)?;
    let out = &args.report;
    t.write(out)?;
    let report = &t.report;
    let n = report.rows.len();
    let tm = report.timing;
    eprintln!(
        "{n} recordings; prepare {:.2} s; per recording: signal indicators {:.4} s, diagnosis {:.3} s, observers {:.3} s (CPU on one thread)",
        tm.prepare_s, tm.signal_s, tm.diagnosis_s, tm.observers_s
    );
    match &report.alarm {
        Some(a) => crate::say!(
            "alarm at {} ({}) on {}: fault named {} (by the {})",
            a.name,
            report.axis.format(a.time),
            a.indicators.join(", "),
            a.fault,
            a.fault_basis
        ),
        None => crate::say!("no alarm over {n} recordings"),
    }
    crate::say!("report in {}", out.display());
    Ok(())
}

/// A number for a table: 6 significant digits, empty when absent.
fn num(v: Option<f64>) -> String {
    match v {
        Some(v) if v.is_finite() => format!("{v:.6e}")
            .parse::<f64>()
            .map(|x| format!("{x}"))
            .unwrap_or_default(),
        _ => String::new(),
    }
}

/// `trend.csv`: one row per recording — time, file, baseline flag, speed used, verdict,
/// p_healthy, ISO zone, each indicator as measured, each indicator's above-threshold flag (on
/// the speed-normalised value), and the diagnosis' modulation depth per hypothesis.
pub fn csv(r: &trend::TrendReport) -> String {
    let mut s = String::from("time,time_text,file,baseline,rpm,verdict,p_healthy,zone");
    for i in &r.indicators {
        s.push_str(&format!(",{}", i.name));
    }
    for i in &r.indicators {
        s.push_str(&format!(",above_{}", i.name));
    }
    s.push_str(",depth_inner,depth_outer,depth_ball");
    s.push('\n');
    for row in &r.rows {
        let name = if row.name.contains([',', '"']) {
            format!("\"{}\"", row.name.replace('"', "\"\""))
        } else {
            row.name.clone()
        };
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{}",
            row.time,
            r.axis.format(row.time),
            name,
            row.baseline,
            num(Some(row.rpm)),
            row.verdict.clone().unwrap_or_default(),
            num(row.p_healthy),
            row.zone.map(|z| format!("{z:?}")).unwrap_or_default()
        ));
        for v in &row.values {
            s.push_str(&format!(",{}", num(*v)));
        }
        for a in &row.above {
            s.push_str(&format!(",{}", u8::from(*a)));
        }
        for h in ["inner", "outer", "ball"] {
            s.push_str(&format!(",{}", num(row.modulation_depth.get(h).copied())));
        }
        s.push('\n');
    }
    s
}

/// `summary.md`.
pub fn summary(
    r: &trend::TrendReport,
    source: &str,
    layout: &str,
    channel: &str,
    run_notes: &[String],
) -> String {
    let mut s = format!(
        "# Trend of {} recordings\n\nSource: {source} ({}; channel `{channel}`; {} Hz). Bearing {}. Samples in {}. Time axis: {}.\n\n",
        r.rows.len(),
        layout,
        r.fs_hz,
        r.bearing,
        r.unit.code(),
        r.time_unit
    );
    alarm_section(&mut s, r);
    thresholds_section(&mut s, r);
    s.push_str("\n## Observers\n\n");
    match &r.observers {
        Some(o) => s.push_str(&format!(
            "{} prepared once on the first {} samples of {} (the machine model calibrated from the {}'s declared healthy 5-DOF model, ARX-Laguerre and fuzzy ARX-Laguerre identified, gains from the bound measured there: `pipeline::Prepared`); each recording's residual mean square skips its first {:.0} % (the observers start from rest). `*_ms` is in the signal's unit squared, `*_ratio` is it over the signal's own mean square on the same samples.\n\n",
            o.methods.join(", "),
            o.fit_samples,
            o.fit_recording,
            o.declared_bearing,
            100.0 * o.settle_fraction
        )),
        None => s.push_str("Not run.\n\n"),
    }
    s.push_str("## What is not seen\n\n- The baseline is assumed healthy; a machine already faulty in it raises the thresholds and hides the fault.\n- Load is not measured: a load step moves the amplitude indicators (RMS, peak, velocity, energies); only speed is normalised.\n- A sensor-gain change moves the amplitude indicators too; the dimensionless ones are immune. By default only the gain-immune indicators (crest, kurtosis, the evidence, the observers' residual share) raise the alarm (`--alarm-on all` for every indicator).\n- The severity level and its projection are a straight line through the indicator after the alarm, not a remaining-life model.\n- The velocity zone (ISO 20816-3) needs the unit and a machine group; on a bearing housing at high frequency it is a machine-condition measure, not a bearing-fault measure.\n");
    let notes: Vec<&String> = run_notes.iter().chain(&r.notes).collect();
    if !notes.is_empty() {
        s.push_str("\n## Notes\n\n");
        for n in notes {
            s.push_str(&format!("- {n}\n"));
        }
    }
    let row_notes: Vec<String> = r
        .rows
        .iter()
        .filter(|row| !row.notes.is_empty())
        .map(|row| format!("- {}: {}", row.name, row.notes.join("; ")))
        .collect();
    if !row_notes.is_empty() {
        s.push_str("\n## Recordings with something not computed\n\n");
        s.push_str(&row_notes.join("\n"));
        s.push('\n');
    }
    s
}

/// `summary.md`'s alarm: when and on what, the fault named, the severity after it.
fn alarm_section(s: &mut String, r: &trend::TrendReport) {
    let c = r.config.get();
    let (ru, _) = r.axis.rate_unit();
    s.push_str("## Alarm\n\n");
    match &r.alarm {
        Some(a) => {
            s.push_str(&format!(
                "**Alarm at {} ({})**, recording {} of {}, on {} (above the threshold in {} of {} consecutive recordings after the baseline).\n\n",
                a.name,
                r.axis.format(a.time),
                a.index + 1,
                r.rows.len(),
                a.indicators.join(", "),
                c.m,
                c.n
            ));
            let verdicts = if a.verdicts.is_empty() {
                "none diagnosed".to_string()
            } else {
                a.verdicts.join(", ")
            };
            if a.fault_basis == trend::alarm::BASIS_EVIDENCE_TREND {
                s.push_str(&format!(
                    "Fault named at the alarm: **{}**, from the trend of the diagnosis' evidence: no recording of the alarm window had a verdict other than normal or uncertain ({verdicts}), and this fault's evidence stood above its own baseline threshold on the most of them. A fault seen against this machine's baseline, not yet at the diagnosis' false-alarm level.\n\n",
                    a.fault
                ));
            } else {
                s.push_str(&format!(
                    "Fault named by the diagnosis at the alarm: **{}** (the most frequent verdict other than normal among the recordings of the alarm window where these indicators were above; their verdicts: {verdicts}).\n\n",
                    a.fault
                ));
            }
            s.push_str("Severity after the alarm (least squares from the alarm on):\n\n| indicator | slope | points | level | level reached / projected |\n|---|---|---|---|---|\n");
            for (name, sv) in a.indicators.iter().zip(&a.severity) {
                let unit = r
                    .indicator(name)
                    .map(|j| r.indicators[j].unit.clone())
                    .unwrap_or_default();
                let reach = match (sv.reached_at, sv.time_to_level) {
                    (Some(t), Some(d)) => format!(
                        "reached at {} ({d:.3} {ru} after the alarm)",
                        r.axis.format(t)
                    ),
                    (None, Some(d)) => {
                        format!("projected {d:.3} {ru} after the alarm (extrapolated)")
                    }
                    _ => "not reached, not rising".into(),
                };
                s.push_str(&format!(
                    "| {name} | {} {unit}/{ru} | {} | {} {unit} ({}) | {reach} |\n",
                    num(sv.slope),
                    sv.points,
                    num(Some(sv.level)),
                    sv.level_basis
                ));
            }
            s.push('\n');
        }
        None => s.push_str("No alarm: no indicator stayed above its threshold long enough.\n\n"),
    }
}

/// `summary.md`'s thresholds: how they are set, and each indicator's with its onset.
fn thresholds_section(s: &mut String, r: &trend::TrendReport) {
    let c = r.config.get();
    s.push_str(&format!(
        "## Thresholds\n\nFrom the first {} recordings (the baseline, assumed healthy): per indicator, median + k·σ̂ with σ̂ = 1.4826·MAD of the baseline values (floored at {} decades in log10, {} decades for the evidence), k = {}, in log10 for positive indicators and linear for the diagnosis' evidence −log10 p_healthy. Amplitudes are normalised to the baseline's median speed {:.1} rpm by (rpm/rpm_ref)^p (energies by its square), p in the table: {} unless the baseline's speeds span 10 % or more, when it is fitted per indicator on the baseline (log-log least squares, clamped to [0, 4]); the speed is the one the diagnosis found in each recording (± 10 % around the declared; the declared one where the recording was not diagnosed). Dimensionless indicators (crest, kurtosis, evidence, observer residual ratios) are neither normalised nor moved by a sensor-gain change.\n\n| indicator | unit | speed exponent p | baseline median | σ̂ | threshold | onset | fault at onset |\n|---|---|---|---|---|---|---|---|\n",
        c.baseline_count,
        trend::MIN_LOG_SPREAD,
        trend::MIN_EVIDENCE_SPREAD,
        c.k,
        r.rpm_reference,
        c.speed_exponent
    ));
    for (((i, t), o), p) in r
        .indicators
        .iter()
        .zip(&r.thresholds)
        .zip(&r.onsets)
        .zip(&r.speed_exponents)
    {
        let p = p.map_or("—".to_string(), |p| format!("{p:.2}"));
        let (med, sp, th) = match t {
            Some(t) => (
                num(Some(t.median)),
                format!(
                    "{}{}",
                    num(Some(t.spread)),
                    if t.spread_floored { " (floor)" } else { "" }
                ),
                num(Some(t.value)),
            ),
            None => ("—".into(), "—".into(), "none".into()),
        };
        let (on, f) = match o {
            Some(o) => (
                format!("{} ({})", r.rows[o.index].name, r.axis.format(o.time)),
                o.fault.clone(),
            ),
            None => ("—".into(), "—".into()),
        };
        s.push_str(&format!(
            "| {} | {} | {p} | {med} | {sp} | {th} | {on} | {f} |\n",
            i.name, i.unit
        ));
    }
}

/// `trend.png`: every indicator over time as a small multiple, divided by its threshold (the
/// threshold is the line at 1), the baseline shaded, the alarm marked.
///
/// # Errors
/// Drawing or file errors.
pub fn figure(r: &trend::TrendReport, path: &Path) -> anyhow::Result<()> {
    figure_marked(r, path, None)
}

/// [`figure`] with an optional marker: a vertical green line at a time on the run's axis (e.g.
/// the true onset of a simulated run, whose truth is known).
///
/// # Errors
/// Drawing or file errors.
pub fn figure_marked(
    r: &trend::TrendReport,
    path: &Path,
    marker: Option<f64>,
) -> anyhow::Result<()> {
    use plotters::prelude::*;
    let text = crate::figure::font_available();
    let k = r.indicators.len().max(1);
    let cols = 3usize;
    let rows = k.div_ceil(cols);
    let (w, h) = (1200u32, 220 * rows as u32);
    let bytes = crate::figure::render_png(w, h, |root| {
        let areas = root.split_evenly((rows, cols));
        let (_, per) = r.axis.rate_unit();
        let t0 = r.rows.first().map_or(0.0, |x| x.time);
        let x = |t: f64| (t - t0) * per;
        let xmax = r.rows.last().map_or(1.0, |l| x(l.time)).max(1e-9);
        let nb = r.config.get().baseline_count;
        for (j, area) in areas.iter().enumerate().take(k) {
            let info = &r.indicators[j];
            let th = r.thresholds[j].map(|t| t.value).filter(|v| *v > 0.0);
            let pts: Vec<(f64, f64)> = r
                .rows
                .iter()
                .filter_map(|row| row.normalised[j].map(|v| (x(row.time), th.map_or(v, |t| v / t))))
                .collect();
            let ymax = pts
                .iter()
                .map(|p| p.1)
                .fold(if th.is_some() { 1.2 } else { 0.0 }, f64::max)
                * 1.05;
            let ymin = pts.iter().map(|p| p.1).fold(0.0f64, f64::min);
            let ymax = if ymax > ymin { ymax } else { ymin + 1.0 };
            let mut b = ChartBuilder::on(area);
            b.margin(6);
            if text {
                let cap = match th {
                    Some(_) => format!("{} / threshold", info.name),
                    None => format!("{} ({}; no threshold)", info.name, info.unit),
                };
                b.caption(cap, ("sans-serif", 13))
                    .x_label_area_size(22)
                    .y_label_area_size(38);
            }
            let mut c = b.build_cartesian_2d(0.0..xmax * 1.02, ymin..ymax)?;
            let mut mesh = c.configure_mesh();
            mesh.light_line_style(TRANSPARENT).x_labels(5).y_labels(4);
            if text {
                mesh.x_desc(match r.axis {
                    trend::TimeAxis::Seconds => "hours since the first recording",
                    trend::TimeAxis::Index => "recordings since the first",
                });
            } else {
                mesh.x_labels(0).y_labels(0);
            }
            mesh.draw()?;
            if nb > 0 && nb <= r.rows.len() {
                let xb = x(r.rows[nb - 1].time);
                c.draw_series(std::iter::once(Rectangle::new(
                    [(0.0, ymin), (xb, ymax)],
                    RGBColor(200, 200, 200).mix(0.35).filled(),
                )))?;
            }
            if th.is_some() {
                c.draw_series(LineSeries::new(
                    vec![(0.0, 1.0), (xmax * 1.02, 1.0)],
                    RGBColor(214, 39, 40).stroke_width(1),
                ))?;
            }
            if let Some(t) = marker {
                let xm = x(t);
                c.draw_series(LineSeries::new(
                    vec![(xm, ymin), (xm, ymax)],
                    RGBColor(44, 160, 44).stroke_width(2),
                ))?;
            }
            if let Some(a) = &r.alarm {
                let xa = x(a.time);
                c.draw_series(LineSeries::new(
                    vec![(xa, ymin), (xa, ymax)],
                    RGBColor(255, 127, 14).stroke_width(2),
                ))?;
            }
            c.draw_series(LineSeries::new(pts.clone(), RGBColor(31, 119, 180)))?;
            c.draw_series(
                pts.iter()
                    .zip(r.rows.iter().filter(|row| row.normalised[j].is_some()))
                    .map(|(p, row)| {
                        let col = if row.above[j] {
                            RGBColor(214, 39, 40)
                        } else {
                            RGBColor(31, 119, 180)
                        };
                        Circle::new(*p, 2, col.filled())
                    }),
            )?;
        }
        Ok(())
    })?;
    std::fs::write(path, bytes).with_context(|| format!("writing {}", path.display()))
}
