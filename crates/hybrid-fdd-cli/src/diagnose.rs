//! `diagnose`: one recording or a directory of them → JSON + Markdown + PNG per recording.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{Context as _, bail};
use diagnosis::{Baseline, BearingSpec, Diagnosis, diagnose};
use rayon::prelude::*;

/// Flags of `diagnose`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Args {
    /// Recording: a CWRU `.mat` file (named by its number, e.g. `130.mat`), a one-column `.csv`,
    /// or a directory: every `.mat`/`.csv` in it is diagnosed, in parallel.
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// How the recordings are read and what machine they come from.
    #[command(flatten)]
    pub recording: RecordingFlags,
    /// JSON report path (Markdown and PNG beside it); with a directory input, an output directory.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Optional trained classifier (`hybrid-fdd train-classifier`'s JSON): its class is added
    /// to the report under `"classifier"` beside the training-free verdict.
    #[arg(long)]
    pub classifier: Option<PathBuf>,
}

/// The flags `diagnose` and `train-classifier` share: channel, rate, speed, bearing, baseline.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RecordingFlags {
    /// Channel: of a `.mat` file DE, FE or BA; of a CSV/TSV a column name or number (1 = first;
    /// by default `accel`, the only column, or the second of `time,signal`).
    #[arg(long, default_value = "DE")]
    pub channel: String,
    /// Sampling rate, Hz (required for CSV; a CWRU file's own rate otherwise).
    #[arg(long)]
    pub fs: Option<f64>,
    /// Shaft speed, rpm (a CWRU file's stored speed, else its nominal one, when omitted).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Bearing: `6205`, `6203`, `n=9,d=0.3126in,D=1.537in,angle=0deg` or
    /// `bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135`.
    #[arg(long)]
    pub bearing: Option<String>,
    /// Healthy recording of the same machine (same formats; resampled by an integer factor
    /// with an anti-aliasing FIR when its rate is a multiple of the recording's), or a machine
    /// model JSON from `cargo xtask calibrate` (its structural path is the healthy model; same
    /// sampling rate and units as the recording). Without it the evidence is self-referenced.
    #[arg(long)]
    pub baseline: Option<PathBuf>,
}

impl RecordingFlags {
    /// The plan these flags give (the bearing is required).
    ///
    /// # Errors
    /// A missing or unparsable `--bearing`.
    pub fn plan(&self) -> anyhow::Result<Plan> {
        let spec = self
            .bearing
            .as_deref()
            .context("--bearing is required (6205, 6203, a geometry or the four multiples)")?;
        Ok(Plan {
            channel: self.channel.clone(),
            fs: self.fs,
            rpm: self.rpm,
            bearing: BearingSpec::parse(spec)?,
        })
    }

    /// The baseline, when `--baseline` is given.
    ///
    /// # Errors
    /// An unreadable baseline.
    pub fn baseline_source(&self) -> anyhow::Result<Option<BaselineSource>> {
        self.baseline
            .as_deref()
            .map(|p| BaselineSource::load(p, &self.channel, None))
            .transpose()
    }
}

/// A loaded recording.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// Samples of the chosen channel.
    pub samples: Vec<f64>,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Speed stored in (or catalogued for) the file, rpm.
    pub rpm: Option<f64>,
    /// Unit of the samples, as far as known (a sentence for reports).
    pub unit: &'static str,
    /// The same as a short code: "g", "m/s^2" or "unknown".
    pub units: &'static str,
    /// Catalogued fault diameter, inches, for a CWRU record.
    pub fault_size_in: Option<f64>,
}

/// Unit statement for CWRU `.mat` samples.
pub const CWRU_UNIT: &str =
    "file units (CWRU accelerometer data; the data README states no unit, commonly read as g)";

/// Load one channel of a `.mat` (CWRU record or CWRU-style variables) or one column of a
/// delimited text file (`,`, `;` or tab; `cargo xtask simulate`'s CSV: its `accel` column, fs
/// from `time_s` when not given).
/// The one recording loader of the command-line tools (`hybrid-fdd`, `cargo xtask`).
///
/// # Errors
/// Unreadable files, unknown channel or extension, missing `--fs` where the file has no rate.
pub fn load(path: &Path, channel: &str, fs: Option<f64>) -> anyhow::Result<Loaded> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "mat" => {
            let end = match channel.to_ascii_uppercase().as_str() {
                "DE" => bearing_data::SensorEnd::DriveEnd,
                "FE" => bearing_data::SensorEnd::FanEnd,
                "BA" => bearing_data::SensorEnd::Base,
                other => bail!("unknown channel `{other}` of a .mat file (DE, FE or BA)"),
            };
            let bytes =
                std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
            let number = path
                .file_stem()
                .and_then(|s| s.to_str())
                .and_then(|s| s.parse::<u32>().ok());
            if let Some(number) = number
                && let Ok(rec) = bearing_data::parse_record(&bytes, number)
            {
                let x = rec
                    .channel(end)
                    .with_context(|| format!("{} has no {channel} channel", path.display()))?
                    .to_vec();
                return Ok(Loaded {
                    samples: x,
                    fs_hz: fs.unwrap_or(rec.fs_hz()),
                    rpm: Some(rec.rpm().value),
                    unit: CWRU_UNIT,
                    units: "g",
                    fault_size_in: bearing_data::entry(number).and_then(|e| e.fault_diameter_in()),
                });
            }
            let set = bearing_data::select_set(bearing_data::read_variable_sets(&bytes)?, None)?;
            let x = set
                .channel(end)
                .with_context(|| format!("{} has no {channel} channel", path.display()))?
                .to_vec();
            let fs = fs.context("--fs is required for a .mat file that is not a CWRU record")?;
            Ok(Loaded {
                samples: x,
                fs_hz: fs,
                rpm: set.rpm,
                unit: CWRU_UNIT,
                units: "unknown",
                fault_size_in: None,
            })
        }
        "csv" | "txt" | "tsv" => load_csv(path, channel, fs),
        other => bail!("unsupported input extension `{other}` (.mat, .csv, .tsv or .txt)"),
    }
}

/// Time-column names read as seconds.
const TIME_NAMES: [&str; 5] = ["time_s", "time", "t", "seconds", "s"];

/// A delimited text recording: the delimiter sniffed from the first data line (tab, `;` or
/// `,`); the column by `channel` (a header name, case-insensitive, or a 1-based number), else
/// `accel` (`simulate`'s CSV), else the only column, else the second of two when the first is
/// time; the rate from `fs` or from a time column in seconds.
fn load_csv(path: &Path, channel: &str, fs: Option<f64>) -> anyhow::Result<Loaded> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let first = lines.next().unwrap_or("");
    let delimiter = if first.contains('\t') {
        b'\t'
    } else if first.contains(';') {
        b';'
    } else {
        b','
    };
    let split = |l: &str| -> Vec<String> {
        l.split(char::from(delimiter))
            .map(|f| f.trim().to_string())
            .collect()
    };
    let fields = split(first);
    let has_header = fields.iter().any(|f| f.parse::<f64>().is_err());
    let names: Vec<String> = if has_header {
        fields.iter().map(|f| f.to_ascii_lowercase()).collect()
    } else {
        (1..=fields.len()).map(|i| format!("column {i}")).collect()
    };
    let listed = || names.join(", ");
    let time_col = (names.len() >= 2 && TIME_NAMES.contains(&names[0].as_str())).then_some(0);
    let want = channel.trim();
    let col = if !want.is_empty() && !want.eq_ignore_ascii_case("DE") {
        if let Some(i) = names.iter().position(|n| n.eq_ignore_ascii_case(want)) {
            i
        } else if let Ok(k) = want.parse::<usize>()
            && (1..=names.len()).contains(&k)
        {
            k - 1
        } else {
            bail!(
                "{}: no column `{want}` (columns: {}; give a name or a number, 1 = first)",
                path.display(),
                listed()
            )
        }
    } else if let Some(i) = names.iter().position(|n| n == "accel") {
        i
    } else if names.len() == 1 {
        0
    } else if names.len() == 2 && time_col.is_some() {
        1
    } else {
        bail!(
            "{}: {} columns ({}); choose the signal with --channel NAME or NUMBER",
            path.display(),
            names.len(),
            listed()
        )
    };
    let fs = match fs {
        Some(f) => f,
        None => match time_col.filter(|&t| t != col) {
            Some(t) => {
                // over the whole span (the stamps are printed to 1 ns by `simulate`), then
                // snapped to a whole Hz when within that resolution of one
                let stamps: Vec<f64> = std::iter::once(first)
                    .filter(|_| !has_header)
                    .chain(lines)
                    .filter_map(|l| split(l).get(t)?.parse().ok())
                    .collect();
                match (stamps.first(), stamps.last()) {
                    (Some(a), Some(b)) if stamps.len() >= 2 && b > a => {
                        let f = (stamps.len() - 1) as f64 / (b - a);
                        let whole = f.round();
                        if (f - whole).abs() <= 1e-6 * f {
                            whole
                        } else {
                            f
                        }
                    }
                    _ => bail!(
                        "cannot infer fs from the `{}` column (seconds expected); give --fs",
                        names[t]
                    ),
                }
            }
            None => bail!(
                "--fs is required for a text recording without a time column ({})",
                TIME_NAMES.join(", ")
            ),
        },
    };
    let mut opts = bearing_data::CsvOptions::new(fs, bearing_data::Column::Index(col));
    opts.delimiter = delimiter;
    opts.header = if has_header {
        bearing_data::HeaderRow::Present
    } else {
        bearing_data::HeaderRow::Absent
    };
    let sig = bearing_data::read_csv_file(path, &opts)?;
    // `simulate` states the unit of `accel` in its JSON sidecar (g for the calibrated rig, m/s²
    // for the 5-DOF parameter sets; m/s² when there is no sidecar)
    let is_accel = names[col] == "accel";
    let in_g = is_accel
        && std::fs::read_to_string(path.with_extension("json"))
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .is_some_and(|v| v["accel_unit"] == "g");
    Ok(Loaded {
        samples: sig.into_samples(),
        fs_hz: fs,
        rpm: None,
        unit: match (is_accel, in_g) {
            (true, true) => "g (`simulate` output, calibrated CWRU rig)",
            (true, false) => "m/s² (`simulate` output)",
            _ => "CSV units (not stated in the file)",
        },
        units: match (is_accel, in_g) {
            (true, true) => "g",
            (true, false) => "m/s^2",
            _ => "unknown",
        },
        fault_size_in: None,
    })
}

/// A prepared baseline and a note saying how it was made (rate, decimation).
pub type Prepared = Arc<(Baseline, String)>;

/// A healthy baseline: a recording's samples, prepared on demand for each recording rate it is
/// asked for, or a calibrated machine model (`cargo xtask calibrate`), whose structural path is
/// the healthy model.
#[derive(Debug)]
pub struct BaselineSource {
    /// Where it came from.
    pub path: PathBuf,
    samples: Vec<f64>,
    fs_hz: f64,
    machine: Option<Box<close_loop::machine::MachineModel>>,
    prepared: Mutex<Vec<(u64, Prepared)>>,
}

impl BaselineSource {
    /// Load a baseline file: a recording (as [`load`]), or a machine model JSON (`.json`,
    /// validated by `close_loop::machine::MachineModel::from_json`).
    ///
    /// # Errors
    /// As [`load`], or the machine model's typed format errors.
    pub fn load(path: &Path, channel: &str, fs: Option<f64>) -> anyhow::Result<Self> {
        if path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading baseline {}", path.display()))?;
            let m = close_loop::machine::MachineModel::from_json(&text)
                .with_context(|| format!("baseline machine model {}", path.display()))?;
            return Ok(Self::from_machine(path, m));
        }
        let l = load(path, channel, fs).with_context(|| format!("baseline {}", path.display()))?;
        Ok(Self::from_samples(path, l.samples, l.fs_hz))
    }

    /// A baseline from a machine model already in memory (`path` names it in reports).
    pub fn from_machine(path: &Path, m: close_loop::machine::MachineModel) -> Self {
        Self {
            path: path.to_path_buf(),
            samples: Vec::new(),
            fs_hz: m.fs_hz,
            machine: Some(Box::new(m)),
            prepared: Mutex::new(Vec::new()),
        }
    }

    /// A baseline from samples already in memory.
    pub fn from_samples(path: &Path, samples: Vec<f64>, fs_hz: f64) -> Self {
        Self {
            path: path.to_path_buf(),
            samples,
            fs_hz,
            machine: None,
            prepared: Mutex::new(Vec::new()),
        }
    }

    /// The units a machine-model baseline was calibrated in ("g", "m/s^2", "unknown"); `None`
    /// for a recording baseline.
    pub fn machine_units(&self) -> Option<&str> {
        self.machine.as_deref().map(|m| m.units.as_str())
    }

    /// The baseline from a machine model: its path's prediction-error filter and the residual
    /// statistics measured when it was calibrated. The rate is the model's (the library reports
    /// a recording at another rate as its typed mismatch error).
    fn prepare_machine(&self, m: &close_loop::machine::MachineModel) -> anyhow::Result<Prepared> {
        let name = self.path.display();
        let path = m.path.as_ref().with_context(|| {
            format!("baseline machine model {name} holds no structural path to whiten with")
        })?;
        let (Some(rms), Some(kurt)) = (m.path_residual_rms, m.path_residual_kurtosis) else {
            anyhow::bail!(
                "baseline machine model {name} has no path residual statistics (written by an older version): recalibrate it with `cargo xtask calibrate`"
            );
        };
        let w = diagnosis::ArWhitener::from_coefficients(
            path.ar.iter().map(|a| -a).collect(),
            m.fs_hz,
            "baseline machine model",
        )?;
        let samples = m.provenance.fit_samples[1];
        let b = Baseline::from_whitener(w, rms, kurt, samples)?;
        let note = format!(
            "machine model {name} (calibrated on {}, {} Hz, units {}): structural path of AR order {} as the healthy model",
            if m.provenance.recording.is_empty() {
                "an unnamed recording"
            } else {
                m.provenance.recording.as_str()
            },
            m.fs_hz,
            m.units,
            path.ar.len()
        );
        Ok(Arc::new((b, note)))
    }

    /// The baseline prepared at `fs_hz` (decimated by an integer factor when needed) and a note
    /// saying how; prepared once per rate.
    ///
    /// # Errors
    /// A rate that is neither equal nor an integer fraction of the baseline's (the library's
    /// typed mismatch error), or a baseline the AR fit rejects.
    pub fn at(&self, fs_hz: f64) -> anyhow::Result<Prepared> {
        let key = fs_hz.to_bits();
        let mut cache = self
            .prepared
            .lock()
            .map_err(|_| anyhow::anyhow!("baseline cache poisoned"))?;
        if let Some((_, b)) = cache.iter().find(|(k, _)| *k == key) {
            return Ok(b.clone());
        }
        if let Some(m) = self.machine.as_deref() {
            let b = self.prepare_machine(m)?;
            cache.push((key, b.clone()));
            return Ok(b);
        }
        let name = self.path.display();
        let (x, fs_b, note) = if let Some((x, q)) = decimated_to(&self.samples, self.fs_hz, fs_hz)?
        {
            (
                x,
                fs_hz,
                format!(
                    "{name}, {} Hz decimated by {q} (bearing-data anti-aliasing FIR) to {fs_hz} Hz",
                    self.fs_hz
                ),
            )
        } else {
            // equal rates, or a mismatch the library reports as its typed error
            (
                self.samples.clone(),
                self.fs_hz,
                format!("{name} at {} Hz", self.fs_hz),
            )
        };
        let b = Baseline::prepare(&x, fs_b).with_context(|| format!("baseline {name}"))?;
        let b = Arc::new((b, note));
        cache.push((key, b.clone()));
        Ok(b)
    }
}

/// `x` sampled at `from_hz`, decimated to `to_hz` with `bearing-data`'s anti-aliasing FIR, and
/// the factor, when `from_hz` is an integer multiple (> 1) of `to_hz`; `None` otherwise (equal
/// rates, or rates that an integer factor cannot join).
///
/// # Errors
/// The decimator's errors.
pub fn decimated_to(
    x: &[f64],
    from_hz: f64,
    to_hz: f64,
) -> anyhow::Result<Option<(Vec<f64>, usize)>> {
    let ratio = from_hz / to_hz;
    if ratio > 1.0 + 1e-9 && (ratio - ratio.round()).abs() < 1e-9 {
        let q = ratio.round() as usize;
        let d = bearing_data::Decimator::new(bearing_data::DecimatorParams::new(q))?;
        Ok(Some((d.decimate(x)?, q)))
    } else {
        Ok(None)
    }
}

/// Options shared by every recording of a run.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Channel.
    pub channel: String,
    /// Sampling rate override.
    pub fs: Option<f64>,
    /// Speed override.
    pub rpm: Option<f64>,
    /// Bearing.
    pub bearing: BearingSpec,
}

/// One recording diagnosed: the diagnosis, the baseline note, the unit statement.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The result.
    pub diagnosis: Diagnosis,
    /// How the baseline was used (`None` = self-referenced).
    pub baseline_note: Option<String>,
    /// Unit of the samples.
    pub unit: &'static str,
    /// The trained classifier's class, when one was given.
    pub trained: Option<TrainedClass>,
}

/// What an optional trained classifier says about a recording.
#[derive(Debug, Clone)]
pub struct TrainedClass {
    /// Its class (the majority over the segments).
    pub class: String,
    /// The class of each segment.
    pub segments: Vec<String>,
    /// The classifier's name.
    pub classifier: String,
    /// Examples and recordings it was trained on.
    pub examples: usize,
    /// Distinct recordings among them.
    pub recordings: usize,
    /// Where it was read from.
    pub file: String,
}

/// Read a trained classifier saved by `train-classifier`.
///
/// # Errors
/// Unreadable file, or the library's format error.
pub fn load_classifier(path: &Path) -> anyhow::Result<diagnosis::TrainedDiagnoser> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("classifier {}", path.display()))?;
    diagnosis::TrainedDiagnoser::from_json(&text)
        .with_context(|| format!("classifier {}", path.display()))
}

/// Apply a trained classifier to a recording the way it was trained: its segments diagnosed
/// against the same reference, classified, and the majority class kept.
///
/// # Errors
/// Missing speed, the library's errors (another reference than the training diagnoses).
pub fn apply_classifier(
    o: &mut Outcome,
    t: &diagnosis::TrainedDiagnoser,
    file: &Path,
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
) -> anyhow::Result<()> {
    let rpm = plan
        .rpm
        .or(l.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    // at the classifier's rate (decimated when the recording's is an integer multiple of it)
    let (x, fs) = match decimated_to(&l.samples, l.fs_hz, t.fs_hz)? {
        Some((x, _)) => (x, t.fs_hz),
        None => (l.samples.clone(), l.fs_hz),
    };
    let b = baseline.map(|src| src.at(fs)).transpose()?;
    let (class, segments) =
        t.classify_recording(&x, fs, rpm, &plan.bearing, b.as_ref().map(|b| &b.0))?;
    o.trained = Some(TrainedClass {
        class,
        segments,
        classifier: t.classifier.clone(),
        examples: t.examples,
        recordings: t.recordings,
        file: file.display().to_string(),
    });
    Ok(())
}

/// Diagnose samples already loaded.
///
/// # Errors
/// Missing speed, or the library's typed errors.
pub fn diagnose_loaded(
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
) -> anyhow::Result<Outcome> {
    let rpm = plan
        .rpm
        .or(l.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    let (d, note) = match baseline {
        Some(src) => {
            if let Some(u) = src.machine_units()
                && u != "unknown"
                && l.units != "unknown"
                && u != l.units
            {
                anyhow::bail!(
                    "baseline machine model {} is in {u} but the recording is in {}",
                    src.path.display(),
                    l.units
                );
            }
            let b = src.at(l.fs_hz)?;
            (
                diagnose(&l.samples, l.fs_hz, rpm, &plan.bearing, Some(&b.0))?,
                Some(b.1.clone()),
            )
        }
        None => (
            diagnose(&l.samples, l.fs_hz, rpm, &plan.bearing, None)?,
            None,
        ),
    };
    Ok(Outcome {
        diagnosis: d,
        baseline_note: note,
        unit: l.unit,
        trained: None,
    })
}

/// Write `<report>.json`, `.md` and `.png`.
///
/// # Errors
/// File system or drawing errors.
pub fn write_reports(o: &Outcome, report: &Path, title: &str) -> anyhow::Result<()> {
    if let Some(parent) = report.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    let mut json = serde_json::to_value(&o.diagnosis)?;
    if let (Some(t), Some(obj)) = (&o.trained, json.as_object_mut()) {
        obj.insert(
            "classifier".into(),
            serde_json::json!({
                "class": t.class,
                "segments": t.segments,
                "classifier": t.classifier,
                "examples": t.examples,
                "recordings": t.recordings,
                "file": t.file,
            }),
        );
    }
    std::fs::write(
        report.with_extension("json"),
        serde_json::to_string_pretty(&json)? + "\n",
    )?;
    std::fs::write(report.with_extension("md"), markdown(o, title))?;
    crate::figure::envelope_figure(&o.diagnosis, &report.with_extension("png"), title)?;
    Ok(())
}

/// The Markdown report.
pub fn markdown(o: &Outcome, title: &str) -> String {
    let d = &o.diagnosis;
    let op = &d.operating_point;
    let s = &d.statistics;
    let mut m = format!("# Diagnosis of {title}\n\n**Verdict: {}**\n\n", d.verdict);
    if let Some(t) = &o.trained {
        m += &format!(
            "Trained classifier ({}, {} examples from {} labelled recordings, {}): **{}** (segments: {}) — learned from the user's labels, beside the training-free verdict above.\n\n",
            t.classifier,
            t.examples,
            t.recordings,
            t.file,
            t.class,
            t.segments.join(", ")
        );
    }
    m += &format!(
        "- reference: {} ({})\n- operating point: {:.1} rpm (fr = {:.3} Hz), fs = {} Hz, bearing {}\n\
         - fault frequencies (Hz): BPFO {:.2}, BPFI {:.2}, BSF (ball-defect rate, 2× spin) {:.2}, FTF {:.2}\n\
         - samples: {}; spectra are of the squared envelope, so line prominences are power ratios (dB) and do not depend on the unit\n\
         - residual: AR({}) prediction error; RMS {:.4e} {}; kurtosis {:.2} (signal {:.2})\n",
        match d.reference {
            diagnosis::Reference::Baseline => "baseline",
            diagnosis::Reference::SelfReference => "self",
        },
        o.baseline_note
            .as_deref()
            .unwrap_or("AR model fitted on the recording itself"),
        op.rpm,
        op.shaft_hz,
        op.fs_hz,
        op.bearing,
        op.frequencies_hz.bpfo,
        op.frequencies_hz.bpfi,
        op.frequencies_hz.ball_defect,
        op.frequencies_hz.ftf,
        o.unit,
        d.whitening.order,
        s.residual_rms,
        o.unit.split(' ').next().unwrap_or(""),
        s.residual_kurtosis,
        s.signal_kurtosis,
    );
    m += &match (s.energy_ratio_db, &d.reference) {
        (Some(db), _) => format!(
            "- against the baseline residual: energy {db:+.1} dB, kurtosis ×{:.2}\n",
            s.kurtosis_ratio
        ),
        _ => format!("- kurtosis / 3 (Gaussian): ×{:.2}\n", s.kurtosis_ratio),
    };
    m += &format!(
        "- band (Hz): {:.0}–{:.0}, {} (SK {:.2}, line threshold {:.1} dB); kurtogram band {:.0}–{:.0} (SK {:.2})\n\n",
        d.band.low_hz,
        d.band.high_hz,
        d.band.chosen_by,
        d.band.spectral_kurtosis,
        d.band.line_threshold_db,
        d.kurtogram_band.low_hz,
        d.kurtogram_band.high_hz,
        d.kurtogram_band.spectral_kurtosis
    );
    m += &format!("Rule: {}.\n\n", d.thresholds.rule);
    m += "| hypothesis | score (dB) | detected | band (Hz) | line | expected (Hz) | found (Hz) | prominence (dB) | in baseline (dB) | evidence (dB) | counts |\n|---|---:|---|---|---|---:|---:|---:|---:|---:|---|\n";
    for e in &d.evidence {
        for (i, l) in e.harmonics.iter().chain(&e.sidebands).enumerate() {
            let head = if i == 0 {
                format!(
                    "{} | {:.1} | {} | {:.0}–{:.0}",
                    e.hypothesis.name(),
                    e.score_db,
                    if e.detected { "**yes**" } else { "no" },
                    e.band_hz[0],
                    e.band_hz[1]
                )
            } else {
                " | | | ".to_string()
            };
            let counts = match (l.present, l.explained_by, l.consistent) {
                (true, None, true) => "yes".to_string(),
                (true, Some(h), _) => format!("no, explained by {}", h.name()),
                (true, None, false) => "no, off the common fundamental".to_string(),
                _ => "no".to_string(),
            };
            let base = l
                .baseline_prominence_db
                .map_or("—".to_string(), |b| format!("{b:.1}"));
            m += &format!(
                "| {head} | {} | {:.2} | {:.2} | {:.1} | {base} | {:.1} | {counts} |\n",
                l.label, l.expected_hz, l.found_hz, l.prominence_db, l.evidence_db
            );
        }
    }
    m += "\nShaft harmonics in the band's envelope spectrum: ";
    m += &d
        .shaft_harmonics
        .iter()
        .map(|l| format!("{} {:.1} dB", l.label, l.prominence_db))
        .collect::<Vec<_>>()
        .join(", ");
    m += "\n";
    m
}

/// Files a directory input expands to (`.mat`, `.csv`, sorted).
fn expand(input: &Path) -> anyhow::Result<Vec<PathBuf>> {
    if !input.is_dir() {
        return Ok(vec![input.to_path_buf()]);
    }
    let mut v: Vec<PathBuf> = std::fs::read_dir(input)
        .with_context(|| format!("reading {}", input.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                ["mat", "csv", "tsv"]
                    .iter()
                    .any(|x| e.eq_ignore_ascii_case(x))
            })
        })
        .collect();
    v.sort();
    if v.is_empty() {
        bail!("{} holds no .mat, .csv or .tsv file", input.display());
    }
    Ok(v)
}

/// Run `diagnose` with these flags (one file, or a directory in parallel with a progress bar).
///
/// # Errors
/// Missing flags, unreadable files, the library's typed errors (one line each).
pub fn run(args: &Args) -> anyhow::Result<()> {
    let input = args.input.as_deref().context("--input is required")?;
    let report = args.report.as_deref().context("--report is required")?;
    let plan = args.recording.plan()?;
    let baseline = args.recording.baseline_source()?;
    let trained = args
        .classifier
        .as_deref()
        .map(|p| load_classifier(p).map(|t| (t, p)))
        .transpose()?;
    let files = expand(input)?;
    let one = |path: &Path, out: &Path| -> anyhow::Result<Outcome> {
        let l = load(path, &plan.channel, plan.fs)?;
        let mut o = diagnose_loaded(&l, &plan, baseline.as_ref())
            .with_context(|| path.display().to_string())?;
        if let Some((t, p)) = &trained {
            apply_classifier(&mut o, t, p, &l, &plan, baseline.as_ref())
                .with_context(|| path.display().to_string())?;
        }
        let title = path
            .file_name()
            .and_then(|s| s.to_str())
            .unwrap_or("recording");
        write_reports(&o, out, title)?;
        Ok(o)
    };
    if !input.is_dir() {
        let o = one(input, report)?;
        println!(
            "{}: {} ({} reference){} -> {}",
            input.display(),
            o.diagnosis.verdict,
            if o.baseline_note.is_some() {
                "baseline"
            } else {
                "self"
            },
            o.trained.as_ref().map_or(String::new(), |t| format!(
                "; trained classifier: {}",
                t.class
            )),
            report.display()
        );
        return Ok(());
    }
    std::fs::create_dir_all(report)?;
    let bar = indicatif::ProgressBar::new(files.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let results: Vec<(PathBuf, anyhow::Result<Outcome>)> = files
        .par_iter()
        .map(|p| {
            let stem = p
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("recording");
            let r = one(p, &report.join(format!("{stem}.json")));
            bar.inc(1);
            (p.clone(), r)
        })
        .collect();
    bar.finish_and_clear();
    let mut csv = String::from(
        "file,verdict,reference,score_inner_db,score_outer_db,score_ball_db,band_low_hz,band_high_hz,error\n",
    );
    let mut failed = 0;
    for (p, r) in &results {
        let name = p.file_name().and_then(|s| s.to_str()).unwrap_or("");
        match r {
            Ok(o) => {
                let d = &o.diagnosis;
                println!("{name}: {}", d.verdict);
                csv += &format!(
                    "{name},{},{},{:.2},{:.2},{:.2},{:.0},{:.0},\n",
                    d.verdict,
                    if o.baseline_note.is_some() {
                        "baseline"
                    } else {
                        "self"
                    },
                    d.scores.inner,
                    d.scores.outer,
                    d.scores.ball,
                    d.band.low_hz,
                    d.band.high_hz
                );
            }
            Err(e) => {
                failed += 1;
                let msg = format!("{e:#}").replace([',', '\n'], ";");
                eprintln!("{name}: error: {msg}");
                csv += &format!("{name},,,,,,,,{msg}\n");
            }
        }
    }
    std::fs::write(report.join("summary.csv"), csv)?;
    println!(
        "{} recordings, {failed} failed; reports in {}",
        results.len(),
        report.display()
    );
    if failed == results.len() {
        bail!("every recording failed");
    }
    Ok(())
}
