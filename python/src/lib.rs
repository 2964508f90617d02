//! `hybrid_fdd._native`: the Rust side of the Python package `hybrid_fdd` (python/README.md).
//!
//! Every function runs the code the `hybrid-fdd` command runs, from `hybrid-fdd-cli`'s library:
//! [`hybrid_fdd_cli::diagnose::read_recording`] reads a recording as `diagnose --input` does, the
//! bearing, speed range and false-alarm level are parsed by the command's own
//! [`RecordingFlags`], a baseline is a [`BaselineSource`], and the diagnosis is
//! [`hybrid_fdd_cli::diagnose::diagnose_loaded_with`]. A diagnosis crosses into Python as the
//! JSON the command writes (`serde_json` of the same [`diagnosis::Diagnosis`]), which the Python
//! layer (`hybrid_fdd/__init__.py`) parses; so `to_dict()` equals the command's report key for
//! key.
//!
//! The work runs with the interpreter released ([`Python::detach`]); batches run on rayon's
//! threads. A Rust error becomes a one-line Python exception ([`InputError`], a `ValueError`, for
//! input the diagnosis refuses; [`DataError`], an `OSError`, for a file that cannot be read), and
//! a panic becomes an [`InternalError`] (a `RuntimeError`) instead of crossing the boundary.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use hybrid_fdd_cli::diagnose::{
    BaselineSource, FsFlag, Loaded, Plan, RecordingFlags, Search, diagnose_loaded_with,
    read_recording, read_recording_tracked,
};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

create_exception!(
    hybrid_fdd,
    InputError,
    PyValueError,
    "Input the diagnosis refuses: a bad array (NaN, too short), an unknown bearing, a speed or rate out of range, a bad speed range or false-alarm level."
);
create_exception!(
    hybrid_fdd,
    DataError,
    PyOSError,
    "A recording or baseline file that cannot be read or parsed, or whose stored rate disagrees with the one given."
);
create_exception!(
    hybrid_fdd,
    InternalError,
    PyRuntimeError,
    "A bug: the Rust code panicked (the panic's message is kept). Please report it."
);

/// Which exception a failure becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// [`InputError`].
    Input,
    /// [`DataError`].
    Data,
    /// [`InternalError`].
    Internal,
}

impl Kind {
    /// The name the Python layer maps back to the exception class.
    fn name(self) -> &'static str {
        match self {
            Kind::Input => "InputError",
            Kind::Data => "DataError",
            Kind::Internal => "InternalError",
        }
    }
}

/// A failure: its kind and its one-line message (anyhow's `{:#}`: contexts joined by `: `).
#[derive(Debug, Clone)]
struct Failure {
    kind: Kind,
    message: String,
}

impl Failure {
    fn new(kind: Kind, e: &anyhow::Error) -> Self {
        Self {
            kind,
            message: one_line(&format!("{e:#}")),
        }
    }

    fn into_py(self) -> PyErr {
        match self.kind {
            Kind::Input => InputError::new_err(self.message),
            Kind::Data => DataError::new_err(self.message),
            Kind::Internal => InternalError::new_err(self.message),
        }
    }
}

/// [`Kind::Data`] when the error comes from reading a file (an I/O error or `bearing-data`'s
/// parse errors anywhere in its chain), else `default`.
fn kind_of(e: &anyhow::Error, default: Kind) -> Kind {
    let file = e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>().is_some()
            || c.downcast_ref::<bearing_data::DataError>().is_some()
    });
    if file { Kind::Data } else { default }
}

/// A message on one line (line breaks become `; `).
fn one_line(s: &str) -> String {
    s.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// `f()`, with a panic turned into an [`Kind::Internal`] failure.
fn guarded<T>(f: impl FnOnce() -> Result<T, Failure>) -> Result<T, Failure> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| {
        let what = p
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        Err(Failure {
            kind: Kind::Internal,
            message: one_line(&format!("hybrid_fdd panicked (a bug): {what}")),
        })
    })
}

/// What is the same for every recording of a call: the plan (bearing, channel), the speed
/// search and false-alarm level, the baseline.
struct Setup {
    plan: Plan,
    search: Search,
    baseline: Option<Arc<BaselineSource>>,
}

/// The arguments [`Setup::new`] takes, as the Python layer passes them.
struct SetupArgs<'a> {
    bearing: &'a str,
    channel: &'a str,
    rpm_range: Option<(f64, f64)>,
    alpha: Option<f64>,
    baseline_path: Option<PathBuf>,
    baseline_samples: Option<Vec<f64>>,
    baseline_fs: Option<f64>,
    baseline_machine: Option<String>,
    baseline_prepared: Option<Arc<BaselineSource>>,
    steady_speed: bool,
}

/// A baseline from one of: a file (read by [`BaselineSource::load`], `fs` for a text file that
/// stores no rate), samples at `fs`, or a machine model's JSON text; `None` when none is given.
fn baseline_source(
    path: Option<PathBuf>,
    samples: Option<Vec<f64>>,
    fs: Option<f64>,
    machine: Option<String>,
    channel: &str,
) -> Result<Option<BaselineSource>, Failure> {
    let given = usize::from(path.is_some())
        + usize::from(samples.is_some())
        + usize::from(machine.is_some());
    if given > 1 {
        return Err(Failure {
            kind: Kind::Input,
            message: "give one baseline: a file, samples or a machine model".into(),
        });
    }
    if let Some(p) = path {
        return BaselineSource::load(&p, channel, fs)
            .map(Some)
            .map_err(|e| Failure::new(Kind::Data, &e));
    }
    if let Some(x) = samples {
        let fs = fs.ok_or_else(|| Failure {
            kind: Kind::Input,
            message: "baseline samples need their sampling rate (baseline_fs)".into(),
        })?;
        return Ok(Some(BaselineSource::from_samples(
            Path::new("<baseline array>"),
            x,
            fs,
        )));
    }
    if let Some(text) = machine {
        let m = close_loop::machine::MachineModel::from_json(&text)
            .map_err(|e| Failure::new(Kind::Input, &anyhow::Error::from(e)))?;
        return Ok(Some(BaselineSource::from_machine(
            Path::new("<machine model>"),
            m,
        )));
    }
    Ok(None)
}

/// A healthy baseline read once and shared by every call it is passed to: its preparation at
/// each recording rate (and, for a machine model, each speed) is cached, as the command's
/// directory batch caches it.
#[pyclass(frozen, name = "PreparedBaseline", module = "hybrid_fdd._native")]
struct PreparedBaseline {
    src: Arc<BaselineSource>,
}

#[pymethods]
impl PreparedBaseline {
    /// Read a baseline: `path` (a recording, or a machine model `.json`), `samples` at `fs`, or
    /// `machine` (a machine model's JSON text); exactly one.
    #[new]
    #[pyo3(signature = (path = None, samples = None, fs = None, machine = None, channel = "DE"))]
    fn new(
        py: Python<'_>,
        path: Option<PathBuf>,
        samples: Option<PyReadonlyArray1<'_, f64>>,
        fs: Option<f64>,
        machine: Option<String>,
        channel: &str,
    ) -> PyResult<Self> {
        let x = samples.as_ref().map(samples_of);
        let channel = channel.to_string();
        let src = py
            .detach(move || guarded(|| baseline_source(path, x, fs, machine, &channel)))
            .map_err(Failure::into_py)?
            .ok_or_else(|| InputError::new_err("give a baseline: path, samples or machine"))?;
        Ok(Self { src: Arc::new(src) })
    }

    /// Where the baseline came from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.src.path.clone()
    }
}

impl Setup {
    /// The command's own flags parsed: `--bearing` by [`RecordingFlags::plan`] (`unknown`, a
    /// designation, a geometry, the four multiples), `--alpha`, `--rpm-range`; a baseline file
    /// read by [`BaselineSource::load`] (the recording's `baseline_fs` for a text baseline that
    /// stores no rate), or samples in memory ([`BaselineSource::from_samples`]).
    fn new(a: SetupArgs<'_>) -> Result<Self, Failure> {
        let flags = RecordingFlags {
            signal: hybrid_fdd_cli::flags::SignalFlags {
                channel: a.channel.to_string(),
                fs: None,
            },
            bearing: Some(a.bearing.to_string()),
            alpha: a.alpha.unwrap_or(diagnosis::DEFAULT_FALSE_ALARM),
            steady_speed: a.steady_speed,
            ..RecordingFlags::default()
        };
        let plan = flags.plan().map_err(|e| Failure::new(Kind::Input, &e))?;
        let mut search = flags.search().map_err(|e| Failure::new(Kind::Input, &e))?;
        if let Some((lo, hi)) = a.rpm_range {
            search.rpm_range = Some([lo, hi]);
        }
        let baseline = match a.baseline_prepared {
            Some(b) => {
                if a.baseline_path.is_some()
                    || a.baseline_samples.is_some()
                    || a.baseline_machine.is_some()
                {
                    return Err(Failure {
                        kind: Kind::Input,
                        message: "give one baseline: a file, samples, a machine model or a prepared baseline".into(),
                    });
                }
                Some(b)
            }
            None => baseline_source(
                a.baseline_path,
                a.baseline_samples,
                a.baseline_fs,
                a.baseline_machine,
                a.channel,
            )?
            .map(Arc::new),
        };
        Ok(Self {
            plan,
            search,
            baseline,
        })
    }

    /// Diagnose a loaded recording with `rpm` declared (else the file's own speed), as
    /// `diagnose` does.
    fn diagnose(&self, l: &Loaded, rpm: Option<f64>) -> Result<Done, Failure> {
        self.diagnose_tracked(l, rpm, None)
    }

    /// [`Setup::diagnose`] of a recording order tracked from its tachometer (`tracking`, which
    /// the report then states).
    fn diagnose_tracked(
        &self,
        l: &Loaded,
        rpm: Option<f64>,
        tracking: Option<residual_features::OrderTracked>,
    ) -> Result<Done, Failure> {
        let plan = Plan {
            rpm,
            ..self.plan.clone()
        };
        let t = std::time::Instant::now();
        let mut o = diagnose_loaded_with(l, &plan, self.baseline.as_deref(), &self.search)
            .map_err(|e| Failure::new(Kind::Input, &e))?;
        if tracking.is_some() {
            o.diagnosis.order_tracking = tracking;
        }
        let rust_s = t.elapsed().as_secs_f64();
        let json = serde_json::to_string(&o.diagnosis).map_err(|e| Failure {
            kind: Kind::Internal,
            message: format!("serialising the diagnosis: {e}"),
        })?;
        Ok(Done {
            json,
            envelope: o.diagnosis.envelope.clone(),
            rust_s,
            baseline_note: o.baseline_note,
            unit: o.unit.code.clone(),
            unit_statement: o.unit.statement.clone(),
            notes: Vec::new(),
        })
    }
}

/// One diagnosis as it crosses into Python.
struct Done {
    json: String,
    /// The chosen band's squared envelope spectrum (not in the report's JSON: the figure's).
    envelope: diagnosis::EnvelopeSpectrum,
    /// Seconds spent in the Rust diagnosis itself (`diagnose_loaded_with`: no copy, no JSON):
    /// what the binding's overhead is measured against.
    rust_s: f64,
    baseline_note: Option<String>,
    unit: String,
    unit_statement: String,
    notes: Vec<String>,
}

/// A recording in memory: its samples, rate and unit as a [`Loaded`].
fn loaded(samples: Vec<f64>, fs: f64, unit: Option<&str>) -> Loaded {
    let code = unit.unwrap_or("unknown").to_string();
    Loaded {
        samples,
        fs_hz: fs,
        rpm: None,
        unit: bearing_data::SampleUnit {
            statement: format!("array from Python (unit {code})"),
            code,
        },
        fault_size_in: None,
    }
}

/// The result of one item of a call, as a Python object: `("ok", dict)` or
/// `("InputError" | "DataError" | "InternalError", message)`.
fn to_py<'py>(py: Python<'py>, r: Result<Done, Failure>) -> PyResult<(String, Bound<'py, PyAny>)> {
    match r {
        Ok(d) => {
            let out = PyDict::new(py);
            out.set_item("json", d.json)?;
            out.set_item("baseline_note", d.baseline_note)?;
            out.set_item("unit", d.unit)?;
            out.set_item("unit_statement", d.unit_statement)?;
            out.set_item("notes", d.notes)?;
            out.set_item("rust_seconds", d.rust_s)?;
            let env = PyDict::new(py);
            env.set_item("band_hz", d.envelope.band_hz.to_vec())?;
            env.set_item("resolution_hz", d.envelope.resolution_hz)?;
            env.set_item("spectral_kurtosis", d.envelope.spectral_kurtosis)?;
            env.set_item("segments", d.envelope.segments)?;
            env.set_item("power", d.envelope.power.into_pyarray(py))?;
            out.set_item("envelope", env)?;
            Ok(("ok".into(), out.into_any()))
        }
        Err(f) => Ok((
            f.kind.name().into(),
            f.message.into_pyobject(py)?.into_any(),
        )),
    }
}

/// Run `f` over `n` items on rayon's threads (`threads` of them, or all cores), in input order.
fn par_map<T: Send>(
    n: usize,
    threads: Option<usize>,
    f: impl Fn(usize) -> T + Sync + Send,
) -> Result<Vec<T>, Failure> {
    match threads {
        Some(0) => Err(Failure {
            kind: Kind::Input,
            message: "threads must be at least 1 (None: all cores)".into(),
        }),
        Some(t) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .map_err(|e| Failure {
                    kind: Kind::Internal,
                    message: format!("building a thread pool of {t}: {e}"),
                })?;
            Ok(pool.install(|| (0..n).into_par_iter().map(&f).collect()))
        }
        None => Ok((0..n).into_par_iter().map(&f).collect()),
    }
}

/// Read a recording as `hybrid-fdd diagnose --input PATH` reads it (a CWRU `.mat`, any other
/// MAT-file, CSV/TSV/text, IMS's date-named files): a dict with `samples` (float64 array), `fs`,
/// `rpm` (the speed the command would declare: the file's own, or a `simulate` sidecar's;
/// `None` when the file stores none), `rpm_source`, `unit`, `unit_statement`, `fault_size_in`,
/// `bearing` (a `simulate` sidecar's), `path`, `channel` and `notes`.
///
/// Raises `DataError` for a file that cannot be read.
#[pyfunction]
#[pyo3(signature = (path, channel = None, fs = None))]
fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
    channel: Option<String>,
    fs: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let channel = channel.unwrap_or_else(|| "DE".into());
    let p = path.clone();
    let ch = channel.clone();
    let r = py.detach(move || {
        guarded(|| {
            let (l, rpm, notes) = read_recording(&p, &ch, fs, None, FsFlag::MustAgree)
                .map_err(|e| Failure::new(Kind::Data, &e))?;
            let bearing = hybrid_fdd_cli::diagnose::sidecar_bearing(&p);
            Ok((l, rpm, notes, bearing))
        })
    });
    let (l, rpm, notes, bearing) = r.map_err(Failure::into_py)?;
    let out = PyDict::new(py);
    let (rpm, source) = match (rpm, l.rpm) {
        (Some(r), _) => (Some(r), Some("sidecar")),
        (None, Some(r)) => (Some(r), Some("file")),
        (None, None) => (None, None),
    };
    out.set_item("fs", l.fs_hz)?;
    out.set_item("rpm", rpm)?;
    out.set_item("rpm_source", source)?;
    out.set_item("unit", l.unit.code.clone())?;
    out.set_item("unit_statement", l.unit.statement.clone())?;
    out.set_item("fault_size_in", l.fault_size_in)?;
    out.set_item("bearing", bearing)?;
    out.set_item("path", path)?;
    out.set_item("channel", channel)?;
    out.set_item("notes", notes)?;
    out.set_item("samples", l.samples.into_pyarray(py))?;
    Ok(out)
}

/// Copy a 1-D float64 array (any strides) into a vector.
fn samples_of(x: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    match x.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => x.as_array().iter().copied().collect(),
    }
}

/// Diagnose arrays: `signals[i]` sampled at `fs[i]` Hz, declared at `rpm[i]` (or `None` with a
/// `rpm_range`), in `unit[i]`, against one baseline. With more than one signal they run in
/// parallel on rayon's threads (`threads`, default all cores) with the interpreter released;
/// results in input order, each `("ok", dict with the report's JSON)` or `(error class name,
/// message)`.
#[pyfunction]
#[pyo3(signature = (signals, fs, rpm, unit, bearing, rpm_range = None, alpha = None,
    baseline_path = None, baseline_samples = None, baseline_fs = None, baseline_machine = None,
    baseline_prepared = None, channel = "DE", threads = None, steady_speed = false))]
#[allow(clippy::too_many_arguments)]
fn diagnose_arrays<'py>(
    py: Python<'py>,
    signals: Vec<PyReadonlyArray1<'py, f64>>,
    fs: Vec<f64>,
    rpm: Vec<Option<f64>>,
    unit: Vec<Option<String>>,
    bearing: &str,
    rpm_range: Option<(f64, f64)>,
    alpha: Option<f64>,
    baseline_path: Option<PathBuf>,
    baseline_samples: Option<PyReadonlyArray1<'py, f64>>,
    baseline_fs: Option<f64>,
    baseline_machine: Option<String>,
    baseline_prepared: Option<Bound<'py, PreparedBaseline>>,
    channel: &str,
    threads: Option<usize>,
    steady_speed: bool,
) -> PyResult<Vec<(String, Bound<'py, PyAny>)>> {
    let n = signals.len();
    if fs.len() != n || rpm.len() != n || unit.len() != n {
        return Err(InputError::new_err(format!(
            "{n} signals but {} rates, {} speeds and {} units",
            fs.len(),
            rpm.len(),
            unit.len()
        )));
    }
    let xs: Vec<Vec<f64>> = signals.iter().map(samples_of).collect();
    let bx = baseline_samples.as_ref().map(samples_of);
    let prepared = baseline_prepared.map(|b| b.get().src.clone());
    let bearing = bearing.to_string();
    let channel = channel.to_string();
    let results = py.detach(move || {
        let setup = guarded(|| {
            Setup::new(SetupArgs {
                bearing: &bearing,
                channel: &channel,
                rpm_range,
                alpha,
                baseline_path,
                baseline_samples: bx,
                baseline_fs,
                baseline_machine,
                baseline_prepared: prepared,
                steady_speed,
            })
        })?;
        par_map(n, threads, |i| {
            guarded(|| {
                let l = loaded(xs[i].clone(), fs[i], unit[i].as_deref());
                setup.diagnose(&l, rpm[i])
            })
        })
    });
    let results = results.map_err(Failure::into_py)?;
    results.into_iter().map(|r| to_py(py, r)).collect()
}

/// Diagnose files as `hybrid-fdd diagnose --input` does: each read by the command's loader
/// (`fs` for files that store no rate; with `one_file`, a `fs` that disagrees with a file's own
/// rate is an error, as for one `--input` file; else the file's own rate wins, as in a
/// directory batch), `rpm` declared (else the file's or its `simulate` sidecar's speed), in
/// parallel on rayon's threads with the interpreter released; results in input order, each
/// `("ok", dict)` or `(error class name, message)`.
#[pyfunction]
#[pyo3(signature = (paths, bearing, channel = "DE", fs = None, rpm = None, rpm_range = None,
    alpha = None, baseline_path = None, baseline_samples = None, baseline_fs = None,
    baseline_machine = None, baseline_prepared = None, one_file = false, threads = None,
    tach = None, pulses_per_rev = 1.0, steady_speed = false))]
#[allow(clippy::too_many_arguments)]
fn diagnose_files<'py>(
    py: Python<'py>,
    paths: Vec<PathBuf>,
    bearing: &str,
    channel: &str,
    fs: Option<f64>,
    rpm: Option<f64>,
    rpm_range: Option<(f64, f64)>,
    alpha: Option<f64>,
    baseline_path: Option<PathBuf>,
    baseline_samples: Option<PyReadonlyArray1<'py, f64>>,
    baseline_fs: Option<f64>,
    baseline_machine: Option<String>,
    baseline_prepared: Option<Bound<'py, PreparedBaseline>>,
    one_file: bool,
    threads: Option<usize>,
    tach: Option<String>,
    pulses_per_rev: f64,
    steady_speed: bool,
) -> PyResult<Vec<(String, Bound<'py, PyAny>)>> {
    if tach.is_some() && steady_speed {
        return Err(Failure {
            kind: Kind::Input,
            message: "tach with steady_speed: the tachometer's order tracking is asked for; leave one of them out".into(),
        }
        .into_py());
    }
    if tach.is_some()
        && (baseline_path.is_some()
            || baseline_samples.is_some()
            || baseline_machine.is_some()
            || baseline_prepared.is_some())
    {
        return Err(Failure {
            kind: Kind::Input,
            message: "tach with a baseline is not supported: the baseline would need the same order tracking (diagnose the tracked recording self-referenced)".into(),
        }
        .into_py());
    }
    if tach.is_some() && (rpm.is_some() || rpm_range.is_some()) {
        return Err(Failure {
            kind: Kind::Input,
            message: "tach measures the speed: leave out rpm and rpm_range (the recording is diagnosed at the tachometer's mean speed)".into(),
        }
        .into_py());
    }
    let bx = baseline_samples.as_ref().map(samples_of);
    let prepared = baseline_prepared.map(|b| b.get().src.clone());
    let bearing = bearing.to_string();
    let channel = channel.to_string();
    let flag = if one_file {
        FsFlag::MustAgree
    } else {
        FsFlag::ForUnstated
    };
    let results = py.detach(move || {
        let setup = guarded(|| {
            Setup::new(SetupArgs {
                bearing: &bearing,
                channel: &channel,
                rpm_range,
                alpha,
                // the command reads a text baseline without a time column at --fs
                baseline_fs: baseline_fs.or(fs),
                baseline_path,
                baseline_samples: bx,
                baseline_machine,
                baseline_prepared: prepared,
                steady_speed,
            })
        })?;
        par_map(paths.len(), threads, |i| {
            guarded(|| {
                let p = &paths[i];
                let tach = tach.as_deref().map(|c| (c, pulses_per_rev));
                let (l, declared, notes, tracking) =
                    read_recording_tracked(p, &channel, tach, fs, rpm, flag)
                        .map_err(|e| Failure::new(Kind::Data, &e))?;
                let mut d = setup
                    .diagnose_tracked(&l, declared, tracking)
                    .map_err(|f| Failure {
                        message: format!("{}: {}", p.display(), f.message),
                        ..f
                    })?;
                d.notes = notes;
                Ok(d)
            })
        })
    });
    let results = results.map_err(Failure::into_py)?;
    results.into_iter().map(|r| to_py(py, r)).collect()
}

/// The recordings a directory holds, as `diagnose --input DIR` expands it (sorted: `.mat`,
/// `.csv`, `.tsv`, and MAT or text files named without an extension or with an all-digit one).
#[pyfunction]
fn recordings_in(py: Python<'_>, directory: PathBuf) -> PyResult<Vec<PathBuf>> {
    py.detach(move || {
        guarded(|| {
            if !directory.is_dir() {
                return Err(Failure {
                    kind: Kind::Data,
                    message: format!("{} is not a directory", directory.display()),
                });
            }
            hybrid_fdd_cli::diagnose::expand(&directory).map_err(|e| Failure::new(Kind::Data, &e))
        })
    })
    .map_err(Failure::into_py)
}

/// `x` (at `fs` Hz) resampled at equal shaft angles from the tachometer `tach` recorded beside
/// it (`pulses_per_rev` pulses a turn; `residual_features::order::order_track`, as `diagnose
/// --tach`): the resampled samples and, as JSON, what the tracking did (`mean_rpm`,
/// `equivalent_fs_hz`, `samples_per_rev`, `max_order`, `min_rpm`, `max_rpm`, `source`).
#[pyfunction]
fn order_track<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    tach: PyReadonlyArray1<'py, f64>,
    fs: f64,
    pulses_per_rev: f64,
) -> PyResult<(Bound<'py, numpy::PyArray1<f64>>, String)> {
    let (x, tach) = (samples_of(&x), samples_of(&tach));
    let r = py.detach(move || {
        guarded(|| {
            let mut engine = residual_features::SpectralEngine::new();
            let mut t = residual_features::order_track(&mut engine, &x, &tach, fs, pulses_per_rev)
                .map_err(|e| Failure::new(Kind::Input, &anyhow::Error::from(e)))?;
            let samples = std::mem::take(&mut t.samples);
            let json = serde_json::to_string(&t).map_err(|e| Failure {
                kind: Kind::Internal,
                message: format!("serialising the order tracking: {e}"),
            })?;
            Ok((samples, json))
        })
    });
    let (samples, json) = r.map_err(Failure::into_py)?;
    Ok((samples.into_pyarray(py), json))
}

/// The bearing `spec` names, parsed as `--bearing` parses it (a catalogue designation, a
/// geometry `n=…,d=…,D=…[,angle=…]`, or the four multiples), as JSON: `name`, `given`,
/// `geometry` (metres, radians; `null` for multiples) and `orders` (× shaft rate; `ball_defect`
/// is CWRU's BSF).
#[pyfunction]
fn bearing(spec: &str) -> PyResult<String> {
    guarded(|| {
        let b = hybrid_fdd_cli::parse_bearing(spec).map_err(|e| Failure::new(Kind::Input, &e))?;
        serde_json::to_string(&b).map_err(|e| Failure {
            kind: Kind::Internal,
            message: format!("serialising the bearing: {e}"),
        })
    })
    .map_err(Failure::into_py)
}

/// A directory for the reports the command's loop writes beside its result (`report`, or a
/// fresh one under the system's temporary directory, removed after the call), and the report
/// path in it.
struct ReportDir {
    dir: PathBuf,
    keep: bool,
}

impl ReportDir {
    fn new(report: Option<PathBuf>) -> Result<(Self, PathBuf), Failure> {
        if let Some(r) = report {
            let dir = r.parent().map(Path::to_path_buf).unwrap_or_default();
            return Ok((Self { dir, keep: true }, r));
        }
        static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let k = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("hybrid-fdd-py-{}-{k}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| Failure {
            kind: Kind::Data,
            message: format!("creating {}: {e}", dir.display()),
        })?;
        let r = dir.join("report.json");
        Ok((Self { dir, keep: false }, r))
    }
}

impl Drop for ReportDir {
    fn drop(&mut self) {
        if !self.keep {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

/// The loop's options as the command's `close-loop` flags.
#[allow(clippy::too_many_arguments)]
fn loop_args(
    path: PathBuf,
    channel: &str,
    fs: Option<f64>,
    rpm: Option<f64>,
    bearing: Option<String>,
    fault: &str,
    model: &str,
    units: Option<String>,
    decimate: usize,
    line_frequency: f64,
    max_effects: usize,
    seconds: Option<f64>,
    fault_size_in: Option<f64>,
    report: PathBuf,
) -> Result<hybrid_fdd_cli::close_loop::Args, Failure> {
    use hybrid_fdd_cli::close_loop::{DeclaredModelKind, LoopFlags};
    let input = |e: anyhow::Error| Failure::new(Kind::Input, &e);
    // the command's own parsers: bearing-model's fault classes, the `--model` values
    let fault = close_loop::parse_fault(fault).map_err(|e| input(e.into()))?;
    let model = <DeclaredModelKind as clap::ValueEnum>::from_str(model, false).map_err(|_| {
        input(anyhow::anyhow!(
            "unknown model `{model}` (physics, arx-laguerre, phenomenological)"
        ))
    })?;
    Ok(hybrid_fdd_cli::close_loop::Args {
        input: Some(path),
        common: LoopFlags {
            signal: hybrid_fdd_cli::flags::SignalFlags {
                channel: channel.to_string(),
                fs,
            },
            rpm,
            bearing,
            model,
            units,
            decimate,
            line_frequency,
        },
        fault,
        seconds,
        max_effects,
        report: Some(report),
        machine: None,
        fault_size_in,
    })
}

/// The JSON of the outcome: `(machine model as `calibrate` writes it, the ledger as `close-loop`
/// writes its report)`.
fn outcome_json(o: &close_loop::Outcome) -> Result<(String, String), Failure> {
    let internal = |e: String| Failure {
        kind: Kind::Internal,
        message: e,
    };
    let machine = o
        .machine
        .to_json()
        .map_err(|e| internal(format!("serialising the machine model: {e}")))?;
    let ledger = serde_json::to_string(&o.ledger)
        .map_err(|e| internal(format!("serialising the ledger: {e}")))?;
    Ok((machine, ledger))
}

/// Calibrate a machine model on a healthy recording, as `hybrid-fdd calibrate --input PATH`
/// (the closed loop from the declared model, then its verification passes). Returns `(machine
/// model JSON, the loop's ledger JSON)`; the machine model JSON is what `calibrate --out` writes.
/// `report`: where to keep the loop's JSON/Markdown/PNG report (`calibrate` writes it beside
/// `--out` as `<out>.report.json`); by default it is not kept.
#[pyfunction]
#[pyo3(signature = (path, rpm = None, bearing = None, channel = "DE", fs = None, decimate = 1,
    model = "physics", units = None, line_frequency = 60.0, max_effects = None, report = None))]
#[allow(clippy::too_many_arguments)]
fn calibrate(
    py: Python<'_>,
    path: PathBuf,
    rpm: Option<f64>,
    bearing: Option<String>,
    channel: &str,
    fs: Option<f64>,
    decimate: usize,
    model: &str,
    units: Option<String>,
    line_frequency: f64,
    max_effects: Option<usize>,
    report: Option<PathBuf>,
) -> PyResult<(String, String)> {
    let channel = channel.to_string();
    let model = model.to_string();
    py.detach(move || {
        guarded(|| {
            let (_dir, r) = ReportDir::new(report)?;
            let args = loop_args(
                path,
                &channel,
                fs,
                rpm,
                bearing,
                "none",
                &model,
                units,
                decimate,
                line_frequency,
                max_effects.unwrap_or(close_loop::machine::CALIBRATE_MAX_EFFECTS),
                None,
                None,
                r,
            )?;
            let (o, _, _) = hybrid_fdd_cli::close_loop::calibrate_one(&args)
                .map_err(|e| Failure::new(kind_of(&e, Kind::Input), &e))?;
            outcome_json(&o)
        })
    })
    .map_err(Failure::into_py)
}

/// Close the loop on a recording, as `hybrid-fdd close-loop --input PATH`: from the declared
/// model (or `machine`, a machine model's JSON text) find what the model misses, add it, and
/// measure the held-out error before and after. Returns `(the augmented machine model JSON, the
/// ledger JSON = the command's `--report`)`. `report`: where to keep the JSON/Markdown/PNG
/// report; by default it is not kept.
#[pyfunction]
#[pyo3(signature = (path, fault = "none", machine = None, rpm = None, bearing = None,
    channel = "DE", fs = None, decimate = 1, model = "physics", units = None,
    line_frequency = 60.0, max_effects = 8, seconds = None, fault_size_in = None, report = None))]
#[allow(clippy::too_many_arguments)]
fn close_loop_file(
    py: Python<'_>,
    path: PathBuf,
    fault: &str,
    machine: Option<String>,
    rpm: Option<f64>,
    bearing: Option<String>,
    channel: &str,
    fs: Option<f64>,
    decimate: usize,
    model: &str,
    units: Option<String>,
    line_frequency: f64,
    max_effects: usize,
    seconds: Option<f64>,
    fault_size_in: Option<f64>,
    report: Option<PathBuf>,
) -> PyResult<(String, String)> {
    let channel = channel.to_string();
    let model = model.to_string();
    let fault = fault.to_string();
    py.detach(move || {
        guarded(|| {
            let prior = machine
                .as_deref()
                .map(close_loop::machine::MachineModel::from_json)
                .transpose()
                .map_err(|e| Failure::new(Kind::Input, &anyhow::Error::from(e)))?;
            let (_dir, r) = ReportDir::new(report)?;
            let args = loop_args(
                path,
                &channel,
                fs,
                rpm,
                bearing,
                &fault,
                &model,
                units,
                decimate,
                line_frequency,
                max_effects,
                seconds,
                fault_size_in,
                r,
            )?;
            let (o, _, _) = hybrid_fdd_cli::close_loop::run_one(&args, prior.as_ref())
                .map_err(|e| Failure::new(kind_of(&e, Kind::Input), &e))?;
            outcome_json(&o)
        })
    })
    .map_err(Failure::into_py)
}

/// A machine model's JSON validated (`MachineModel::from_json`) and written back as `calibrate`
/// writes it.
#[pyfunction]
fn machine_model(text: &str) -> PyResult<String> {
    guarded(|| {
        let m = close_loop::machine::MachineModel::from_json(text)
            .map_err(|e| Failure::new(Kind::Input, &anyhow::Error::from(e)))?;
        m.to_json().map_err(|e| Failure {
            kind: Kind::Internal,
            message: format!("serialising the machine model: {e}"),
        })
    })
    .map_err(Failure::into_py)
}

/// `hybrid-fdd simulate`'s flags, parsed by the command's own definition.
#[derive(clap::Parser)]
#[command(name = "simulate")]
struct SimulateCli {
    #[command(flatten)]
    a: hybrid_fdd_cli::simulate::Args,
}

/// Run `hybrid-fdd simulate FLAGS --out OUT` (the command's own code: its CSV and JSON sidecar
/// are written at `out`, and its lines printed on standard output). `flags` are the command's
/// flags and values as strings (`["--fault", "outer", "--rpm", "1797"]`).
#[pyfunction]
fn simulate_to(py: Python<'_>, flags: Vec<String>, out: PathBuf) -> PyResult<()> {
    use clap::Parser as _;
    py.detach(move || {
        guarded(|| {
            let mut argv = vec!["simulate".to_string()];
            argv.extend(flags);
            argv.push("--out".into());
            argv.push(out.to_string_lossy().into_owned());
            let cli = SimulateCli::try_parse_from(argv).map_err(|e| Failure {
                kind: Kind::Input,
                // clap's first paragraph (its usage lines follow)
                message: one_line(
                    e.to_string()
                        .split("\n\n")
                        .next()
                        .unwrap_or_default()
                        .trim_start_matches("error: "),
                ),
            })?;
            hybrid_fdd_cli::simulate::run(cli.a).map_err(|e| Failure::new(Kind::Input, &e))
        })
    })
    .map_err(Failure::into_py)
}

/// A trend computed by [`trend_files`] or [`trend_arrays`]: `hybrid-fdd trend`'s result, kept
/// in Rust so that `write` produces the command's four files.
#[pyclass(frozen, name = "TrendResult", module = "hybrid_fdd._native")]
struct TrendResult {
    t: Arc<hybrid_fdd_cli::trend::Trend>,
}

#[pymethods]
impl TrendResult {
    /// `trend.json`'s text, as the command writes it.
    fn json(&self) -> PyResult<String> {
        guarded(|| {
            self.t.json_text().map_err(|e| Failure {
                kind: Kind::Internal,
                message: format!("serialising the trend: {e:#}"),
            })
        })
        .map_err(Failure::into_py)
    }

    /// `trend.csv`'s text.
    fn csv(&self) -> String {
        hybrid_fdd_cli::trend::csv(&self.t.report)
    }

    /// `summary.md`'s text.
    fn summary(&self) -> String {
        let t = &self.t;
        hybrid_fdd_cli::trend::summary(&t.report, &t.source, &t.layout, &t.channel, &t.run_notes)
    }

    /// Each row's time as the outputs print it (`2004-02-12T10:32:39`, or the number).
    fn time_texts(&self) -> Vec<String> {
        let r = &self.t.report;
        r.rows.iter().map(|row| r.axis.format(row.time)).collect()
    }

    /// Write `trend.csv`, `trend.json`, `summary.md` and `trend.png` into `dir` (created).
    fn write(&self, py: Python<'_>, dir: PathBuf) -> PyResult<()> {
        let t = self.t.clone();
        py.detach(move || {
            guarded(|| {
                std::fs::create_dir_all(&dir)
                    .map_err(|e| Failure {
                        kind: Kind::Data,
                        message: format!("creating {}: {e}", dir.display()),
                    })
                    .and_then(|()| t.write(&dir).map_err(|e| Failure::new(Kind::Data, &e)))
            })
        })
        .map_err(Failure::into_py)
    }
}

/// The options of `hybrid-fdd trend` as the Python layer passes them.
#[derive(Clone)]
struct TrendOptions {
    bearing: String,
    rpm: Option<f64>,
    fs: Option<f64>,
    channel: Option<String>,
    baseline_count: usize,
    unit: Option<String>,
    machine_group: Option<String>,
    alarm: String,
    k: f64,
    alarm_on: Option<Vec<String>>,
    speed_exponent: f64,
    observers: bool,
    decimate_to: Option<f64>,
}

/// `hybrid-fdd trend`'s flags, parsed by the command's own definition.
#[derive(clap::Parser)]
#[command(name = "trend")]
struct TrendCli {
    #[command(flatten)]
    a: hybrid_fdd_cli::trend::Args,
}

/// The command's [`hybrid_fdd_cli::trend::Args`] from the options, through its own flag parser
/// (so defaults and value checks are the command's); `report` is not used by the callers (they
/// pass it to `compute` themselves).
fn trend_args(
    o: &TrendOptions,
    input: Option<&Path>,
    index: Option<&Path>,
) -> Result<hybrid_fdd_cli::trend::Args, Failure> {
    use clap::Parser as _;
    let mut argv: Vec<std::ffi::OsString> = vec!["trend".into()];
    let mut flag = |f: &str, v: std::ffi::OsString| {
        argv.push(format!("--{f}").into());
        argv.push(v);
    };
    if let Some(p) = input {
        flag("input", p.into());
    }
    if let Some(p) = index {
        flag("index", p.into());
    }
    flag("bearing", o.bearing.clone().into());
    let num = |v: f64| std::ffi::OsString::from(format!("{v}"));
    if let Some(v) = o.rpm {
        flag("rpm", num(v));
    }
    if let Some(v) = o.fs {
        flag("fs", num(v));
    }
    if let Some(c) = &o.channel {
        flag("channel", c.clone().into());
    }
    flag("baseline-count", o.baseline_count.to_string().into());
    if let Some(g) = &o.machine_group {
        flag("machine-group", g.clone().into());
    }
    if let Some(u) = &o.unit {
        flag("unit", u.clone().into());
    }
    flag("k", num(o.k));
    flag("alarm", o.alarm.clone().into());
    if let Some(a) = &o.alarm_on {
        flag("alarm-on", a.join(",").into());
    }
    flag("speed-exponent", num(o.speed_exponent));
    if let Some(v) = o.decimate_to {
        flag("decimate-to", num(v));
    }
    flag("report", "<unused>".into());
    if !o.observers {
        argv.push("--no-observers".into());
    }
    TrendCli::try_parse_from(argv)
        .map(|c| c.a)
        .map_err(|e| Failure {
            kind: Kind::Input,
            message: one_line(
                e.to_string()
                    .split("\n\n")
                    .next()
                    .unwrap_or_default()
                    .trim_start_matches("error: "),
            ),
        })
}

/// [`Kind::Data`] for a trend error about the files (unreadable, named without a time,
/// duplicate or mixed times, a bad index, mixed rates, layouts or channel counts, a bad
/// recording), else [`Kind::Input`] (the options: bearing, alarm rule, k, too few recordings
/// for the baseline asked for).
fn trend_kind(e: &anyhow::Error) -> Kind {
    use trend::TrendError as T;
    let files = e.chain().any(|c| {
        matches!(
            c.downcast_ref::<T>(),
            Some(
                T::Timestamp { .. }
                    | T::DuplicateTime { .. }
                    | T::MixedNaming { .. }
                    | T::IndexCsv { .. }
                    | T::MixedRates { .. }
                    | T::BadRecording { .. }
                    | T::NotOrdered { .. }
            )
        )
    });
    if files {
        Kind::Data
    } else {
        kind_of(e, Kind::Input)
    }
}

/// Run `hybrid-fdd trend` on a directory (`input`) or an index CSV (`index`): the command's
/// own reading, ordering and analysis (`hybrid_fdd_cli::trend::compute`), with the interpreter
/// released; with `report`, the command's four files are written there too.
#[pyfunction]
#[pyo3(signature = (input, index, bearing, rpm, fs, channel, baseline_count, unit,
    machine_group, alarm, k, alarm_on, speed_exponent, observers, decimate_to, report, progress))]
#[allow(clippy::too_many_arguments)]
fn trend_files(
    py: Python<'_>,
    input: Option<PathBuf>,
    index: Option<PathBuf>,
    bearing: String,
    rpm: Option<f64>,
    fs: Option<f64>,
    channel: Option<String>,
    baseline_count: usize,
    unit: Option<String>,
    machine_group: Option<String>,
    alarm: String,
    k: f64,
    alarm_on: Option<Vec<String>>,
    speed_exponent: f64,
    observers: bool,
    decimate_to: Option<f64>,
    report: Option<PathBuf>,
    progress: bool,
) -> PyResult<TrendResult> {
    let o = TrendOptions {
        bearing,
        rpm,
        fs,
        channel,
        baseline_count,
        unit,
        machine_group,
        alarm,
        k,
        alarm_on,
        speed_exponent,
        observers,
        decimate_to,
    };
    let t = py
        .detach(move || {
            guarded(|| {
                let args = trend_args(&o, input.as_deref(), index.as_deref())?;
                let t = hybrid_fdd_cli::trend::compute(&args, report.as_deref(), progress)
                    .map_err(|e| Failure::new(trend_kind(&e), &e))?;
                if let Some(dir) = &report {
                    t.write(dir).map_err(|e| Failure::new(Kind::Data, &e))?;
                }
                Ok(t)
            })
        })
        .map_err(Failure::into_py)?;
    Ok(TrendResult { t: Arc::new(t) })
}

/// A time given from Python: a number (a position: the recordings' order and spacing) or text
/// (a calendar time `2024-03-01T12:00:00`, as a file name gives it; or a number).
fn name_time(v: &Bound<'_, PyAny>, name: &str) -> Result<trend::NameTime, Failure> {
    if let Ok(s) = v.extract::<String>() {
        return trend::order::parse_time(&s).map_err(|e| Failure {
            kind: Kind::Input,
            message: format!("{name}: time {s:?}: {e}"),
        });
    }
    match v.extract::<f64>() {
        Ok(t) if t.is_finite() => Ok(trend::NameTime {
            time: t,
            axis: trend::TimeAxis::Index,
        }),
        _ => Err(Failure {
            kind: Kind::Input,
            message: format!(
                "{name}: a time must be a finite number, a datetime or an ISO date-time string"
            ),
        }),
    }
}

/// Run `hybrid-fdd trend`'s analysis on recordings in memory (`hybrid_fdd_cli::trend::
/// compute_in_memory`: ordered by their times, `decimate_to`, `rpm`, `unit` applied as for
/// files), with the interpreter released; with `report`, the four files are written there.
#[pyfunction]
#[pyo3(signature = (names, times, signals, fs, rpm, units, bearing, baseline_count, unit,
    machine_group, alarm, k, alarm_on, speed_exponent, observers, decimate_to, report, progress,
    default_rpm))]
#[allow(clippy::too_many_arguments)]
fn trend_arrays(
    py: Python<'_>,
    names: Vec<String>,
    times: Vec<Bound<'_, PyAny>>,
    signals: Vec<PyReadonlyArray1<'_, f64>>,
    fs: Vec<f64>,
    rpm: Vec<Option<f64>>,
    units: Vec<Option<String>>,
    bearing: String,
    baseline_count: usize,
    unit: Option<String>,
    machine_group: Option<String>,
    alarm: String,
    k: f64,
    alarm_on: Option<Vec<String>>,
    speed_exponent: f64,
    observers: bool,
    decimate_to: Option<f64>,
    report: Option<PathBuf>,
    progress: bool,
    default_rpm: Option<f64>,
) -> PyResult<TrendResult> {
    let n = names.len();
    if [times.len(), signals.len(), fs.len(), rpm.len(), units.len()]
        .iter()
        .any(|&l| l != n)
    {
        return Err(InternalError::new_err(
            "trend_arrays: names, times, signals, fs, rpm and units differ in length",
        ));
    }
    let times: Vec<trend::NameTime> = times
        .iter()
        .zip(&names)
        .map(|(t, name)| name_time(t, name))
        .collect::<Result<_, _>>()
        .map_err(Failure::into_py)?;
    let recs: Vec<hybrid_fdd_cli::trend::InMemory> = (0..n)
        .map(|i| hybrid_fdd_cli::trend::InMemory {
            name: names[i].clone(),
            time: times[i],
            samples: samples_of(&signals[i]),
            fs_hz: fs[i],
            rpm: rpm[i],
            unit: units[i].clone(),
        })
        .collect();
    let o = TrendOptions {
        bearing,
        rpm: default_rpm,
        fs: None,
        channel: None,
        baseline_count,
        unit,
        machine_group,
        alarm,
        k,
        alarm_on,
        speed_exponent,
        observers,
        decimate_to,
    };
    let t = py
        .detach(move || {
            guarded(|| {
                let args = trend_args(&o, None, None)?;
                if let Some(dir) = &report {
                    std::fs::create_dir_all(dir).map_err(|e| Failure {
                        kind: Kind::Data,
                        message: format!("creating {}: {e}", dir.display()),
                    })?;
                }
                let t = hybrid_fdd_cli::trend::compute_in_memory(&args, recs, progress)
                    .map_err(|e| Failure::new(kind_of(&e, Kind::Input), &e))?;
                if let Some(dir) = &report {
                    t.write(dir).map_err(|e| Failure::new(Kind::Data, &e))?;
                }
                Ok(t)
            })
        })
        .map_err(Failure::into_py)?;
    Ok(TrendResult { t: Arc::new(t) })
}

/// The native module: `read`, `diagnose_arrays`, `diagnose_files`, `recordings_in`, `bearing`
/// and the exception classes; `hybrid_fdd/__init__.py` is the API over it.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PreparedBaseline>()?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_files, m)?)?;
    m.add_function(wrap_pyfunction!(recordings_in, m)?)?;
    m.add_function(wrap_pyfunction!(bearing, m)?)?;
    m.add_function(wrap_pyfunction!(order_track, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(close_loop_file, m)?)?;
    m.add_function(wrap_pyfunction!(machine_model, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_to, m)?)?;
    m.add_class::<TrendResult>()?;
    m.add_function(wrap_pyfunction!(trend_files, m)?)?;
    m.add_function(wrap_pyfunction!(trend_arrays, m)?)?;
    m.add("TREND_DEFAULT_K", trend::DEFAULT_K)?;
    m.add(
        "TREND_DEFAULT_SPEED_EXPONENT",
        trend::DEFAULT_SPEED_EXPONENT,
    )?;
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add("DataError", m.py().get_type::<DataError>())?;
    m.add("InternalError", m.py().get_type::<InternalError>())?;
    m.add("DEFAULT_FALSE_ALARM", diagnosis::DEFAULT_FALSE_ALARM)?;
    Ok(())
}
