//! Simulated **degradation runs** with known truth: `K` recordings of one machine taken at a
//! fixed interval, a healthy stretch, then a spall at one location (inner race, outer race or a
//! ball) that appears at a known recording (the true onset) and grows monotonically to the end of
//! the run, with the nuisances a condition-monitoring trend must not alarm on — slow speed drift,
//! load steps and sensor-gain steps — present **before** the onset as well as after it.
//! `docs/equations/life.md` states every law and default and why.
//!
//! The run is split in two:
//!
//! * the **schedule** ([`Schedule`], [`plan_schedule`]): what happens when — the onset index,
//!   the speed, load and gain of every recording, the growth fraction of the spall after the
//!   onset. It knows nothing of the signal, so the calibrated CWRU rig
//!   (`calibrated_rig::life`) uses the very same schedule with its own renderer;
//! * the **renderer**: here the phenomenological machine of [`crate::machine`] (m/s²), one
//!   machine drawn once from the run's seed (structure, modes, lines and the fault's impact
//!   parameters), each recording rendered with its own noise, its speed, load, gain and
//!   severity.
//!
//! Every recording depends on `(seed, index)` only ([`simulate_recording`]): a caller may
//! generate them in any order or in parallel (`(0..k).into_par_iter()`) and gets the samples of
//! [`simulate_run`], bit for bit.
//!
//! ```
//! use bearing_model::FaultLocation;
//! use bearing_model::life::{LifeConfig, LifeMachine, simulate_run};
//! let mut cfg = LifeConfig::new(LifeMachine::preset("UC204")?, FaultLocation::Outer);
//! cfg.schedule.recordings = 6;
//! cfg.schedule.duration_s = 0.1;
//! let (recs, truth) = simulate_run(&cfg, 3)?;
//! assert_eq!(recs.len(), 6);
//! assert!(truth.recordings[truth.onset_index].faulty);
//! assert_eq!(recs[0].unit, "m/s^2");
//! # Ok::<(), bearing_model::life::LifeError>(())
//! ```

use crate::catalog;
use crate::error::ModelError;
use crate::fault::FaultLocation;
use crate::geometry::{BearingGeometry, FaultOrders};
use crate::machine::{LocalizedFault, MachineParams, MachineRecipe, Nuisances};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Default number of recordings in a run.
pub const DEFAULT_RECORDINGS: usize = 40;
/// Default duration of one recording, s.
pub const DEFAULT_DURATION_S: f64 = 2.0;
/// Default interval between the starts of two recordings, s (10 minutes, IMS's cadence).
pub const DEFAULT_INTERVAL_S: u64 = 600;
/// Default start of the run: 2026-01-01 00:00:00 UTC, s since the Unix epoch.
pub const DEFAULT_START_UNIX_S: i64 = 1_767_225_600;
/// Default range of the onset, as fractions of the run: the onset index is drawn uniformly in
/// `ceil(0.4·K) ..= floor(0.7·K)` (clipped to `1 ..= K−1`).
pub const DEFAULT_ONSET_FRACTION: (f64, f64) = (0.4, 0.7);
/// Default speed drift across the run: the true mean speed of a recording stays within ± this
/// fraction of the nominal speed (3 %).
pub const DEFAULT_SPEED_DRIFT: f64 = 0.03;
/// Default number of load steps in a run (the first always before the onset).
pub const DEFAULT_LOAD_STEPS: usize = 2;
/// Default size of one load step: the load level is multiplied or divided by a ratio drawn
/// log-uniformly in this range.
pub const DEFAULT_LOAD_STEP_RATIO: (f64, f64) = (1.1, 1.25);
/// The load level (relative to nominal) is kept inside this range: a step that would leave it
/// goes the other way.
pub const LOAD_RANGE: (f64, f64) = (0.7, 1.4);
/// Default number of sensor-gain steps in a run (anywhere, before or after the onset).
pub const DEFAULT_GAIN_STEPS: usize = 1;
/// Default size of one gain step: the gain is multiplied or divided by a ratio drawn
/// log-uniformly in this range (so a step is ×0.71 … ×0.91 or ×1.1 … ×1.4).
pub const DEFAULT_GAIN_STEP_RATIO: (f64, f64) = (1.1, 1.4);
/// The sensor gain (relative to the first recording's) is kept inside this range.
pub const GAIN_RANGE: (f64, f64) = (0.5, 2.0);
/// Default severity of the phenomenological machine's spall at the onset and at the last
/// recording: 20·log₁₀(impacts' RMS / healthy RMS), dB.
pub const DEFAULT_SEVERITY_DB: (f64, f64) = (-25.0, 0.0);
/// Most recordings a run may hold.
pub const MAX_RECORDINGS: usize = 100_000;
/// Longest recording, s.
pub const MAX_DURATION_S: f64 = 3_600.0;
/// The unit of the phenomenological machine's recordings.
pub const UNIT_MS2: &str = "m/s^2";

/// ChaCha8 streams of a run's seed: each part of the schedule and the machine apart, so that
/// changing, say, the number of load steps does not move the onset.
#[derive(Clone, Copy)]
enum Stream {
    Onset = 0x4C1F_0001,
    Speed = 0x4C1F_0002,
    Load = 0x4C1F_0003,
    Gain = 0x4C1F_0004,
    Machine = 0x4C1F_0005,
}

/// Streams `RECORDING_STREAM + index` give each recording its own draws.
const RECORDING_STREAM: u64 = 1 << 40;

fn rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(stream);
    r
}

/// The per-recording generator of recording `index` of the run drawn from `seed` (for
/// renderers of other crates: noise seeds and phases of one recording, independent of every
/// other recording's).
pub fn recording_rng(seed: u64, index: usize) -> ChaCha8Rng {
    rng(seed, RECORDING_STREAM + index as u64)
}

/// Everything that can be wrong with a degradation run's configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LifeError {
    /// A configuration value is out of its documented range.
    #[error("life config `{field}` = {value} is invalid (expected {expected})")]
    InvalidConfig {
        /// The field, as written in the docs.
        field: &'static str,
        /// The value given, printed.
        value: String,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// A bearing designation the presets do not hold.
    #[error(
        "no degradation-run preset for bearing `{0}` (presets: 6205, UC204, 6308; or build a LifeMachine)"
    )]
    UnknownPreset(String),
    /// An index past the run's last recording.
    #[error("recording {index} asked of a run of {recordings}")]
    NoSuchRecording {
        /// The index asked for.
        index: usize,
        /// Recordings in the run.
        recordings: usize,
    },
    /// The machine model refused a recording (its typed error).
    #[error(transparent)]
    Model(#[from] ModelError),
}

fn invalid(
    field: &'static str,
    value: impl std::fmt::Display,
    expected: &'static str,
) -> LifeError {
    LifeError::InvalidConfig {
        field,
        value: value.to_string(),
        expected,
    }
}

fn check_pair(
    field: &'static str,
    (lo, hi): (f64, f64),
    min: f64,
    max: f64,
    expected: &'static str,
) -> Result<(), LifeError> {
    if !(lo.is_finite() && hi.is_finite() && lo >= min && hi <= max && lo <= hi) {
        return Err(invalid(field, format!("({lo}, {hi})"), expected));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// schedule

/// When things happen in a run (the same for every renderer). Defaults: the `DEFAULT_*`
/// constants of this module.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// Recordings in the run, `K` (2 ..= [`MAX_RECORDINGS`]).
    pub recordings: usize,
    /// Duration of each recording, s (> 0, ≤ [`MAX_DURATION_S`] and ≤ `interval_s`).
    pub duration_s: f64,
    /// Time from the start of one recording to the next, whole seconds (≥ 1).
    pub interval_s: u64,
    /// Start of the first recording, s since 1970-01-01 00:00:00 UTC (0 ..= year 9999): the
    /// timestamps of the file names.
    pub start_unix_s: i64,
    /// The onset index is drawn uniformly in `ceil(lo·K) ..= floor(hi·K)`, clipped to
    /// `1 ..= K−1` (so there is at least one healthy and one faulty recording);
    /// `0 < lo ≤ hi < 1` and the range must hold an index.
    pub onset_fraction: (f64, f64),
    /// Speed drift: each recording's true mean speed is `rpm·(1 + a·sin(2π·c·k/(K−1) + φ))`
    /// with `a` uniform in `[drift/2, drift]`, `c` uniform in 0.25 … 1 cycles per run and `φ`
    /// uniform: a slow drift within ± `drift` (0 ..= 0.2).
    pub speed_drift: f64,
    /// Load steps (0 ..= K−1): the first at a recording drawn in `1 ..= onset−1` (the healthy
    /// stretch), the others anywhere in `1 ..= K−1`, all distinct.
    pub load_steps: usize,
    /// Each load step multiplies or divides (sign drawn) the load level by a ratio drawn
    /// log-uniformly in this range (1 ..= 2 each); the level stays in [`LOAD_RANGE`].
    pub load_step_ratio: (f64, f64),
    /// Sensor-gain steps (0 ..= K−1), at distinct recordings drawn in `1 ..= K−1` (before or
    /// after the onset).
    pub gain_steps: usize,
    /// Each gain step multiplies or divides the gain by a ratio drawn log-uniformly in this
    /// range (1 ..= 2 each); the gain stays in [`GAIN_RANGE`].
    pub gain_step_ratio: (f64, f64),
}

impl Default for Schedule {
    fn default() -> Self {
        Self {
            recordings: DEFAULT_RECORDINGS,
            duration_s: DEFAULT_DURATION_S,
            interval_s: DEFAULT_INTERVAL_S,
            start_unix_s: DEFAULT_START_UNIX_S,
            onset_fraction: DEFAULT_ONSET_FRACTION,
            speed_drift: DEFAULT_SPEED_DRIFT,
            load_steps: DEFAULT_LOAD_STEPS,
            load_step_ratio: DEFAULT_LOAD_STEP_RATIO,
            gain_steps: DEFAULT_GAIN_STEPS,
            gain_step_ratio: DEFAULT_GAIN_STEP_RATIO,
        }
    }
}

/// Latest start accepted, s since 1970 (about year 5985: half of the last second of 9999).
const MAX_START_UNIX_S: i64 = MAX_END_UNIX_S / 2;
/// Latest start of a run's last recording: 9999-12-31 23:59:59 UTC.
const MAX_END_UNIX_S: i64 = 253_402_300_799;

impl Schedule {
    /// The range the onset index is drawn from, `(first, last)` inclusive (unchecked: see
    /// [`Schedule::validate`]).
    pub fn onset_range(&self) -> (usize, usize) {
        let k = self.recordings as f64;
        let lo = ((self.onset_fraction.0 * k).ceil() as usize).max(1);
        let hi =
            ((self.onset_fraction.1 * k).floor() as usize).min(self.recordings.saturating_sub(1));
        (lo, hi)
    }

    /// Check every field against its documented range.
    ///
    /// # Errors
    /// [`LifeError::InvalidConfig`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), LifeError> {
        let k = self.recordings;
        if !(2..=MAX_RECORDINGS).contains(&k) {
            return Err(invalid("recordings", k, "2 ..= 100000"));
        }
        let d = self.duration_s;
        if !(d.is_finite() && d > 0.0 && d <= MAX_DURATION_S) {
            return Err(invalid("duration_s", d, "> 0 and <= 3600 s"));
        }
        if self.interval_s == 0 || (self.interval_s as f64) < d {
            return Err(invalid(
                "interval_s",
                self.interval_s,
                ">= 1 s and >= duration_s (recordings do not overlap)",
            ));
        }
        if !(0..=MAX_START_UNIX_S).contains(&self.start_unix_s) {
            return Err(invalid(
                "start_unix_s",
                self.start_unix_s,
                "0 ..= 126701150399 (s since 1970)",
            ));
        }
        let end = (k as u64 - 1)
            .checked_mul(self.interval_s)
            .and_then(|span| i64::try_from(span).ok())
            .and_then(|span| span.checked_add(self.start_unix_s));
        if end.is_none_or(|e| e > MAX_END_UNIX_S) {
            return Err(invalid(
                "interval_s",
                self.interval_s,
                "a run ending by 9999-12-31T23:59:59Z",
            ));
        }
        let (f0, f1) = self.onset_fraction;
        if !(f0.is_finite() && f1.is_finite() && f0 > 0.0 && f0 <= f1 && f1 < 1.0) {
            return Err(invalid(
                "onset_fraction",
                format!("({f0}, {f1})"),
                "0 < lo <= hi < 1",
            ));
        }
        let (lo, hi) = self.onset_range();
        if lo > hi {
            return Err(invalid(
                "onset_fraction",
                format!("({f0}, {f1}) of {k} recordings"),
                "a range holding at least one index in 1 ..= K-1",
            ));
        }
        let s = self.speed_drift;
        if !(s.is_finite() && (0.0..=0.2).contains(&s)) {
            return Err(invalid("speed_drift", s, "0 ..= 0.2"));
        }
        if self.load_steps > k - 1 {
            return Err(invalid("load_steps", self.load_steps, "0 ..= recordings-1"));
        }
        if self.load_steps > 0 && lo < 2 {
            return Err(invalid(
                "load_steps",
                self.load_steps,
                "0 when the onset can be recording 1 (no healthy recording after the first to step at)",
            ));
        }
        check_pair(
            "load_step_ratio",
            self.load_step_ratio,
            1.0,
            2.0,
            "1 <= lo <= hi <= 2",
        )?;
        if self.gain_steps > k - 1 {
            return Err(invalid("gain_steps", self.gain_steps, "0 ..= recordings-1"));
        }
        check_pair(
            "gain_step_ratio",
            self.gain_step_ratio,
            1.0,
            2.0,
            "1 <= lo <= hi <= 2",
        )
    }
}

/// What the schedule draws for one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The first faulty recording.
    pub onset_index: usize,
    /// Each recording's true mean speed over the nominal.
    pub speed_factor: Vec<f64>,
    /// Each recording's load level (1 = nominal).
    pub load: Vec<f64>,
    /// Each recording's sensor gain (1 = the first recording's).
    pub gain: Vec<f64>,
    /// Each recording's growth fraction: `None` before the onset, `(k − onset)/(K − 1 − onset)`
    /// from it on (0 at the onset, 1 at the last recording; 0 when the onset is the last).
    pub growth: Vec<Option<f64>>,
    /// Recordings at which the load steps, ascending.
    pub load_step_indices: Vec<usize>,
    /// Recordings at which the gain steps, ascending.
    pub gain_step_indices: Vec<usize>,
}

/// `n` distinct indices: the first (when `first_in` is given) drawn in that range, the others
/// in `1 ..= k−1`, ascending.
fn step_indices(
    r: &mut ChaCha8Rng,
    n: usize,
    k: usize,
    first_in: Option<(usize, usize)>,
) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::with_capacity(n);
    if n == 0 {
        return out;
    }
    if let Some((a, b)) = first_in {
        out.push(r.random_range(a..=b));
    }
    let mut pool: Vec<usize> = (1..k).filter(|i| !out.contains(i)).collect();
    while out.len() < n && !pool.is_empty() {
        let j = r.random_range(0..pool.len());
        out.push(pool.swap_remove(j));
    }
    out.sort_unstable();
    out
}

/// A piecewise-constant level starting at 1, stepping at `steps` by a ratio log-uniform in
/// `ratio` up or down (drawn), kept inside `range`.
fn stepped_level(
    r: &mut ChaCha8Rng,
    k: usize,
    steps: &[usize],
    ratio: (f64, f64),
    range: (f64, f64),
) -> Vec<f64> {
    let mut level = 1.0;
    let mut out = vec![1.0; k];
    let mut next = 0;
    for (i, o) in out.iter_mut().enumerate() {
        if next < steps.len() && steps[next] == i {
            let m = (ratio.0.ln() + (ratio.1.ln() - ratio.0.ln()) * r.random::<f64>()).exp();
            let up = r.random::<bool>();
            let cand = if up { level * m } else { level / m };
            level = if cand < range.0 || cand > range.1 {
                // the other way (clamped: with a ratio near 2 both ways can leave the range)
                (if up { level / m } else { level * m }).clamp(range.0, range.1)
            } else {
                cand
            };
            next += 1;
        }
        *o = level;
    }
    out
}

/// Draw the schedule of the run of `seed`.
///
/// # Errors
/// [`Schedule::validate`]'s.
pub fn plan_schedule(s: &Schedule, seed: u64) -> Result<Plan, LifeError> {
    s.validate()?;
    let k = s.recordings;
    let (lo, hi) = s.onset_range();
    let onset = rng(seed, Stream::Onset as u64).random_range(lo..=hi);
    let mut r = rng(seed, Stream::Speed as u64);
    let amp = s.speed_drift * (0.5 + 0.5 * r.random::<f64>());
    let cycles = 0.25 + 0.75 * r.random::<f64>();
    let phi = TAU * r.random::<f64>();
    let speed_factor = (0..k)
        .map(|i| 1.0 + amp * (TAU * cycles * i as f64 / (k - 1) as f64 + phi).sin())
        .collect();
    let mut r = rng(seed, Stream::Load as u64);
    let load_step_indices = step_indices(&mut r, s.load_steps, k, Some((1, onset - 1)));
    let load = stepped_level(&mut r, k, &load_step_indices, s.load_step_ratio, LOAD_RANGE);
    let mut r = rng(seed, Stream::Gain as u64);
    let gain_step_indices = step_indices(&mut r, s.gain_steps, k, None);
    let gain = stepped_level(&mut r, k, &gain_step_indices, s.gain_step_ratio, GAIN_RANGE);
    let span = (k - 1 - onset) as f64;
    let growth = (0..k)
        .map(|i| {
            (i >= onset).then(|| {
                if span > 0.0 {
                    (i - onset) as f64 / span
                } else {
                    0.0
                }
            })
        })
        .collect();
    Ok(Plan {
        onset_index: onset,
        speed_factor,
        load,
        gain,
        growth,
        load_step_indices,
        gain_step_indices,
    })
}

// ---------------------------------------------------------------------------------------------
// timestamps

/// Civil date (year, month, day) of a day count since 1970-01-01 (H. Hinnant's algorithm).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (if m <= 2 { y + 1 } else { y }, m, d)
}

fn civil(unix_s: i64) -> (i64, u32, u32, i64, i64, i64) {
    let (y, mo, d) = civil_from_days(unix_s.div_euclid(86_400));
    let sod = unix_s.rem_euclid(86_400);
    (y, mo, d, sod / 3600, sod % 3600 / 60, sod % 60)
}

/// `YYYY-MM-DDThh:mm:ssZ` (UTC) of `unix_s` seconds since 1970.
pub fn iso_timestamp(unix_s: i64) -> String {
    let (y, mo, d, h, mi, s) = civil(unix_s);
    format!("{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}Z")
}

/// The IMS data set's file name of a recording started at `unix_s`: `YYYY.MM.DD.hh.mm.ss`
/// (UTC), which sorts in time order.
pub fn ims_name(unix_s: i64) -> String {
    let (y, mo, d, h, mi, s) = civil(unix_s);
    format!("{y:04}.{mo:02}.{d:02}.{h:02}.{mi:02}.{s:02}")
}

// ---------------------------------------------------------------------------------------------
// truth

/// The truth of one recording.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordingTruth {
    /// Index in the run (0-based).
    pub index: usize,
    /// Start time from the start of the run, s.
    pub time_s: f64,
    /// Start time, UTC, ISO 8601.
    pub timestamp: String,
    /// Start time, s since 1970 (UTC).
    pub unix_s: i64,
    /// Whether the spall is present (index ≥ onset).
    pub faulty: bool,
    /// Planned severity of the phenomenological machine's spall,
    /// 20·log₁₀(impacts' RMS / healthy RMS), dB (`None` before the onset and on the rig).
    pub severity_db: Option<f64>,
    /// Spall width on the calibrated rig, mm (`None` before the onset and on other machines).
    pub spall_width_mm: Option<f64>,
    /// True mean shaft speed, rpm.
    pub rpm_true: f64,
    /// Load level, relative to nominal (scales the machine's vibration; see life.md).
    pub load: f64,
    /// Sensor gain, relative to the first recording's.
    pub gain: f64,
}

/// The truth of a run: what the trend should find, and every nuisance it should not alarm on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LifeTruth {
    /// Which renderer made the samples (and its unit).
    pub generator: String,
    /// Bearing label.
    pub bearing: String,
    /// Fault orders of the bearing (× shaft rate).
    pub fault_orders: FaultOrders,
    /// Where the spall is.
    pub fault_location: FaultLocation,
    /// The first faulty recording.
    pub onset_index: usize,
    /// Its start time from the start of the run, s.
    pub onset_time_s: f64,
    /// The run's seed.
    pub seed: u64,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Unit of the samples (`m/s^2` or `g`).
    pub unit: String,
    /// Nominal (nameplate) speed, rpm.
    pub rpm_nominal: f64,
    /// Speed a user would declare (the nominal one: the drift is unknown to them), rpm.
    pub rpm_declared: f64,
    /// The severity growth law, in words.
    pub severity_law: String,
    /// Recordings at which the load steps.
    pub load_step_indices: Vec<usize>,
    /// Recordings at which the sensor gain steps.
    pub gain_step_indices: Vec<usize>,
    /// The schedule the run was drawn with.
    pub schedule: Schedule,
    /// One entry per recording.
    pub recordings: Vec<RecordingTruth>,
    /// Anything a reader must know (e.g. a rig spall outside its calibrated sizes).
    pub notes: Vec<String>,
}

impl LifeTruth {
    /// Recording `index`'s truth.
    ///
    /// # Errors
    /// [`LifeError::NoSuchRecording`] past the run's end.
    pub fn recording(&self, index: usize) -> Result<&RecordingTruth, LifeError> {
        self.recordings
            .get(index)
            .ok_or(LifeError::NoSuchRecording {
                index,
                recordings: self.recordings.len(),
            })
    }

    /// Truth skeleton of a planned run (severity fields left `None`; the renderer fills them).
    #[allow(clippy::too_many_arguments)]
    pub fn from_plan(
        plan: &Plan,
        schedule: &Schedule,
        seed: u64,
        generator: &str,
        bearing: &str,
        fault_orders: FaultOrders,
        location: FaultLocation,
        fs_hz: f64,
        unit: &str,
        rpm_nominal: f64,
        severity_law: &str,
    ) -> Self {
        let recordings = (0..schedule.recordings)
            .map(|i| {
                let unix_s = schedule.start_unix_s + (i as u64 * schedule.interval_s) as i64;
                RecordingTruth {
                    index: i,
                    time_s: (i as u64 * schedule.interval_s) as f64,
                    timestamp: iso_timestamp(unix_s),
                    unix_s,
                    faulty: i >= plan.onset_index,
                    severity_db: None,
                    spall_width_mm: None,
                    rpm_true: rpm_nominal * plan.speed_factor[i],
                    load: plan.load[i],
                    gain: plan.gain[i],
                }
            })
            .collect();
        Self {
            generator: generator.to_string(),
            bearing: bearing.to_string(),
            fault_orders,
            fault_location: location,
            onset_index: plan.onset_index,
            onset_time_s: (plan.onset_index as u64 * schedule.interval_s) as f64,
            seed,
            fs_hz,
            unit: unit.to_string(),
            rpm_nominal,
            rpm_declared: rpm_nominal,
            severity_law: severity_law.to_string(),
            load_step_indices: plan.load_step_indices.clone(),
            gain_step_indices: plan.gain_step_indices.clone(),
            schedule: *schedule,
            recordings,
            notes: Vec::new(),
        }
    }
}

/// One recording of a run, in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct LifeRecording {
    /// Index in the run.
    pub index: usize,
    /// Start time from the start of the run, s.
    pub time_s: f64,
    /// The accelerometer's samples, in `unit`.
    pub samples: Vec<f64>,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// True mean shaft speed, rpm.
    pub rpm_true: f64,
    /// Declared (nominal) speed, rpm.
    pub rpm_declared: f64,
    /// Unit of `samples`: `m/s^2` (phenomenological machine) or `g` (calibrated rig).
    pub unit: String,
    /// RMS of the recording without its fault component, as recorded (gain applied), `unit`.
    pub healthy_rms: f64,
    /// RMS of the fault component, as recorded (0 before the onset), `unit`.
    pub fault_rms: f64,
}

// ---------------------------------------------------------------------------------------------
// the phenomenological machine

/// The machine a run is recorded on ([`crate::machine`], m/s²).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LifeMachine {
    /// Bearing label for reports.
    pub label: String,
    /// The bearing under the sensor.
    pub geometry: BearingGeometry,
    /// Nominal shaft speed, rpm (30 ..= 30 000 including the drift).
    pub rpm: f64,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// RMS of a healthy recording at nominal load and gain 1, m/s².
    pub rms_ms2: f64,
    /// Machine-over-sensor-noise SNR at nominal load, dB.
    pub snr_db: f64,
    /// Machine nuisance components (the same all run long).
    pub nuisances: Nuisances,
}

/// Nuisances of the presets: a motor-driven machine's shaft comb and electrical lines.
pub const PRESET_NUISANCES: Nuisances = Nuisances {
    shaft_comb: true,
    electrical: true,
    ..Nuisances::NONE
};

impl LifeMachine {
    /// The presets, by bearing designation (case-insensitive, the catalogue's spelling):
    ///
    /// * `6205`: the SKF 6205 (CWRU drive end) at 1797 rpm, 12 kHz, RMS 2 m/s² — the
    ///   phenomenological machine, **not** the calibrated rig (that is `calibrated_rig::life`);
    /// * `UC204`: a UC204-class insert at 2100 rpm (XJTU-SY's first condition), 25.6 kHz,
    ///   RMS 1.5 m/s²;
    /// * `6308`: a 6308-class bearing at 1480 rpm (a 4-pole motor), 20 kHz, RMS 3 m/s².
    ///
    /// Each with SNR 20 dB and [`PRESET_NUISANCES`].
    ///
    /// # Errors
    /// [`LifeError::UnknownPreset`] for another designation.
    pub fn preset(designation: &str) -> Result<Self, LifeError> {
        let unknown = || LifeError::UnknownPreset(designation.trim().to_string());
        let e = catalog::lookup(designation).map_err(|_| unknown())?;
        let (label, rpm, fs_hz, rms_ms2) = match e.designation {
            "6205" => ("6205", 1797.0, 12_000.0, 2.0),
            "UC204" => ("UC204", 2100.0, 25_600.0, 1.5),
            "6308" => ("6308", 1480.0, 20_000.0, 3.0),
            _ => return Err(unknown()),
        };
        Ok(Self {
            label: label.to_string(),
            geometry: e.geometry(),
            rpm,
            fs_hz,
            rms_ms2,
            snr_db: 20.0,
            nuisances: PRESET_NUISANCES,
        })
    }
}

/// A degradation run on the phenomenological machine.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LifeConfig {
    /// The machine.
    pub machine: LifeMachine,
    /// Where the spall is.
    pub location: FaultLocation,
    /// Severity at the onset and at the last recording, dB (−60 ..= 40, start < end): linear
    /// in dB between them, i.e. the impacts' amplitude grows exponentially in time.
    pub severity_db: (f64, f64),
    /// When things happen.
    pub schedule: Schedule,
}

impl LifeConfig {
    /// `machine` with a spall at `location`, [`DEFAULT_SEVERITY_DB`], the default schedule.
    pub fn new(machine: LifeMachine, location: FaultLocation) -> Self {
        Self {
            machine,
            location,
            severity_db: DEFAULT_SEVERITY_DB,
            schedule: Schedule::default(),
        }
    }

    /// Check the schedule, the severities and the machine at the drifted speeds.
    ///
    /// # Errors
    /// [`LifeError::InvalidConfig`] or the machine model's [`LifeError::Model`].
    pub fn validate(&self) -> Result<(), LifeError> {
        self.schedule.validate()?;
        let (a, b) = self.severity_db;
        if !(a.is_finite() && b.is_finite() && a >= -60.0 && b <= 40.0 && a < b) {
            return Err(invalid(
                "severity_db",
                format!("({a}, {b})"),
                "-60 <= start < end <= 40 dB",
            ));
        }
        let m = &self.machine;
        let sn = m.snr_db;
        if !(sn.is_finite() && (-20.0..=80.0).contains(&sn)) {
            return Err(invalid("snr_db", sn, "-20 ..= 80 dB"));
        }
        for f in [
            1.0 - self.schedule.speed_drift,
            1.0 + self.schedule.speed_drift,
        ] {
            MachineRecipe::healthy(m.geometry, m.rpm * f, m.fs_hz, self.schedule.duration_s, 0)?
                .with_rms_ms2(m.rms_ms2 * LOAD_RANGE.0)
                .validate()?;
        }
        Ok(())
    }

    /// The severity law, in words.
    pub fn severity_law(&self) -> String {
        format!(
            "severity_db = {} + ({} - {})·u, u = (k - onset)/(K - 1 - onset): linear in dB, the impacts' RMS exponential in time; \
             dB = 20·log10(impacts' RMS / healthy RMS of the same recording)",
            self.severity_db.0, self.severity_db.1, self.severity_db.0
        )
    }
}

/// Draw the run's schedule and its truth (no samples).
///
/// # Errors
/// [`LifeConfig::validate`]'s.
pub fn plan_run(cfg: &LifeConfig, seed: u64) -> Result<(Plan, LifeTruth), LifeError> {
    cfg.validate()?;
    let plan = plan_schedule(&cfg.schedule, seed)?;
    let m = &cfg.machine;
    let mut truth = LifeTruth::from_plan(
        &plan,
        &cfg.schedule,
        seed,
        "bearing_model::life (phenomenological machine, bearing_model::machine; m/s^2)",
        &m.label,
        m.geometry.orders(),
        cfg.location,
        m.fs_hz,
        UNIT_MS2,
        m.rpm,
        &cfg.severity_law(),
    );
    for (t, g) in truth.recordings.iter_mut().zip(&plan.growth) {
        t.severity_db = g.map(|u| cfg.severity_db.0 + (cfg.severity_db.1 - cfg.severity_db.0) * u);
    }
    truth.notes.push(format!(
        "load scales the machine's vibration (healthy RMS {} m/s^2 x load) with the sensor noise held; gain scales the whole recording",
        m.rms_ms2
    ));
    Ok((plan, truth))
}

/// The run's machine: every parameter drawn once from the run's seed (structure, lines, the
/// fault's impact parameters); the recordings differ only in what [`simulate_recording`]
/// changes.
fn machine_params(cfg: &LifeConfig, seed: u64) -> Result<MachineParams, LifeError> {
    let m = &cfg.machine;
    let machine_seed: u64 = rng(seed, Stream::Machine as u64).random();
    Ok(MachineRecipe::healthy(
        m.geometry,
        m.rpm,
        m.fs_hz,
        cfg.schedule.duration_s,
        machine_seed,
    )?
    .with_nuisances(m.nuisances)
    .with_snr_db(m.snr_db)
    .with_rms_ms2(m.rms_ms2)
    .with_fault(LocalizedFault {
        location: cfg.location,
        severity_db: cfg.severity_db.0,
    })
    .draw()?)
}

/// Render recording `index` of the run of `seed` (depends on `(cfg, seed, index)` only).
///
/// The machine of the run at the recording's speed, its load (healthy RMS × load, SNR raised
/// so that the sensor noise stays), fresh noise, speed-wander phases and fault angle from the
/// recording's own stream; the spall (from the onset on) at the planned severity; the whole
/// multiplied by the sensor gain.
///
/// # Errors
/// [`LifeError::NoSuchRecording`], and as [`plan_run`] and the machine model.
pub fn simulate_recording(
    cfg: &LifeConfig,
    seed: u64,
    index: usize,
) -> Result<LifeRecording, LifeError> {
    let (plan, truth) = plan_run(cfg, seed)?;
    render(cfg, seed, &plan, &truth, index, true)
}

/// Render one recording of a planned run; `with_fault: false` leaves the spall out (the
/// healthy counterpart of a faulty recording: same noise, same everything else).
fn render(
    cfg: &LifeConfig,
    seed: u64,
    plan: &Plan,
    truth: &LifeTruth,
    index: usize,
    with_fault: bool,
) -> Result<LifeRecording, LifeError> {
    let t = truth.recording(index)?;
    let base = machine_params(cfg, seed)?;
    let mut p = base.clone();
    let mut r = recording_rng(seed, index);
    let noise_seed: u64 = r.random();
    let m = &cfg.machine;
    let load = plan.load[index];
    let gain = plan.gain[index];
    p.recipe.seed = noise_seed;
    p.recipe.rpm = t.rpm_true;
    p.recipe = p.recipe.with_rms_ms2(m.rms_ms2 * load);
    // sensor noise held: σ² = rms²/(1 + S) at nominal load ⇒ 1 + S' = load²·(1 + S)
    let s0 = 10f64.powf(m.snr_db / 10.0);
    p.recipe.snr_db = 10.0 * (load * load * (1.0 + s0) - 1.0).max(1e-4).log10();
    for tone in &mut p.speed.tones {
        tone[2] = TAU * r.random::<f64>();
    }
    let fault_angle = TAU * r.random::<f64>();
    match (t.severity_db, base.fault, with_fault) {
        (Some(sev), Some(f), true) => {
            p.recipe.fault = Some(LocalizedFault {
                location: cfg.location,
                severity_db: sev,
            });
            let mut f = f;
            f.severity_db = sev;
            f.angle_rad = fault_angle;
            p.fault = Some(f);
        }
        _ => {
            p.recipe.fault = None;
            p.fault = None;
        }
    }
    let rec = p.synthesize()?;
    let samples = rec.accel.iter().map(|v| v * gain).collect();
    Ok(LifeRecording {
        index,
        time_s: t.time_s,
        samples,
        fs_hz: m.fs_hz,
        rpm_true: t.rpm_true,
        rpm_declared: truth.rpm_declared,
        unit: UNIT_MS2.to_string(),
        healthy_rms: rec.rms.healthy * gain,
        fault_rms: rec.rms.fault * gain,
    })
}

/// The whole run: every recording ([`simulate_recording`], in index order) and the truth.
///
/// # Errors
/// As [`simulate_recording`].
pub fn simulate_run(
    cfg: &LifeConfig,
    seed: u64,
) -> Result<(Vec<LifeRecording>, LifeTruth), LifeError> {
    let (plan, truth) = plan_run(cfg, seed)?;
    let recs = (0..cfg.schedule.recordings)
        .map(|i| render(cfg, seed, &plan, &truth, i, true))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((recs, truth))
}

/// Recording `index` with its spall left out (the same noise and nuisances): what the
/// recording would have been on a healthy bearing. For tests and for indicators' references.
///
/// # Errors
/// As [`simulate_recording`].
pub fn simulate_recording_healthy(
    cfg: &LifeConfig,
    seed: u64,
    index: usize,
) -> Result<LifeRecording, LifeError> {
    let (plan, truth) = plan_run(cfg, seed)?;
    render(cfg, seed, &plan, &truth, index, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small(designation: &str, location: FaultLocation) -> LifeConfig {
        let mut c = LifeConfig::new(LifeMachine::preset(designation).unwrap(), location);
        c.schedule.recordings = 12;
        c.schedule.duration_s = 0.25;
        c
    }

    #[test]
    fn same_seed_same_run_other_seed_other_run() {
        let c = small("6308", FaultLocation::Inner);
        let (a, ta) = simulate_run(&c, 5).unwrap();
        let (b, tb) = simulate_run(&c, 5).unwrap();
        assert_eq!(a, b);
        assert_eq!(ta, tb);
        let (c2, _) = simulate_run(&c, 6).unwrap();
        assert_ne!(a[0].samples, c2[0].samples);
        // one recording alone is the run's, bit for bit (parallel-friendly)
        for i in [0, 7, 11] {
            assert_eq!(simulate_recording(&c, 5, i).unwrap(), a[i]);
        }
        assert!(matches!(
            simulate_recording(&c, 5, 12),
            Err(LifeError::NoSuchRecording { .. })
        ));
    }

    #[test]
    fn severity_grows_monotonically_after_onset_and_is_absent_before() {
        for (d, loc) in [
            ("6205", FaultLocation::Outer),
            ("UC204", FaultLocation::Ball),
            ("6308", FaultLocation::Inner),
        ] {
            let c = small(d, loc);
            for seed in 0..3 {
                let (recs, truth) = simulate_run(&c, seed).unwrap();
                let on = truth.onset_index;
                let (lo, hi) = c.schedule.onset_range();
                assert!((lo..=hi).contains(&on));
                let sev: Vec<f64> = truth.recordings[on..]
                    .iter()
                    .map(|t| t.severity_db.unwrap())
                    .collect();
                assert_eq!(sev[0], c.severity_db.0);
                assert_eq!(*sev.last().unwrap(), c.severity_db.1);
                assert!(sev.windows(2).all(|w| w[1] > w[0]), "{sev:?}");
                for (i, r) in recs.iter().enumerate() {
                    let h = simulate_recording_healthy(&c, seed, i).unwrap();
                    if i < on {
                        assert!(truth.recordings[i].severity_db.is_none());
                        assert!(!truth.recordings[i].faulty);
                        assert_eq!(r.fault_rms, 0.0);
                        // exactly the healthy machine
                        assert_eq!(r.samples, h.samples);
                    } else {
                        assert!(r.fault_rms > 0.0);
                        assert_ne!(r.samples, h.samples);
                        // the fault adds to the same healthy recording at the planned dB
                        let d: f64 = r
                            .samples
                            .iter()
                            .zip(&h.samples)
                            .map(|(a, b)| (a - b) * (a - b))
                            .sum::<f64>()
                            / r.samples.len() as f64;
                        let db = 20.0 * (d.sqrt() / r.healthy_rms).log10();
                        let want = truth.recordings[i].severity_db.unwrap();
                        assert!((db - want).abs() < 1e-6, "{db} vs {want}");
                    }
                }
            }
        }
    }

    #[test]
    fn nuisances_occur_before_the_onset() {
        let mut gain_before = 0;
        for seed in 0..20 {
            let c = small("UC204", FaultLocation::Outer);
            let (recs, truth) = simulate_run(&c, seed).unwrap();
            let on = truth.onset_index;
            // a load step in the healthy stretch, changing the healthy RMS
            let first = truth.load_step_indices[0];
            assert!(first >= 1 && first < on, "{first} {on}");
            let l = &truth.recordings;
            assert_ne!(l[first].load, l[first - 1].load);
            let ratio = recs[first].healthy_rms / recs[first - 1].healthy_rms;
            let want = l[first].load * l[first].gain / (l[first - 1].load * l[first - 1].gain);
            assert!((ratio / want - 1.0).abs() < 1e-9);
            // the speed drifts within the healthy stretch
            let rpm: Vec<f64> = l[..on].iter().map(|t| t.rpm_true).collect();
            let spread = rpm.iter().cloned().fold(f64::MIN, f64::max)
                - rpm.iter().cloned().fold(f64::MAX, f64::min);
            assert!(spread > 0.0);
            assert!(rpm.iter().all(|r| (r / 2100.0 - 1.0).abs() <= 0.03 + 1e-12));
            assert!(recs.iter().all(|r| r.rpm_declared == 2100.0));
            // gain: one step, ×0.71–0.91 or ×1.1–1.4
            let g = truth.gain_step_indices[0];
            let step = l[g].gain / l[g - 1].gain;
            let m = step.max(1.0 / step);
            assert!((1.1 - 1e-12..=1.4 + 1e-12).contains(&m), "{step}");
            if g < on {
                gain_before += 1;
            }
        }
        // the gain steps before the onset in some runs and after it in others
        assert!(gain_before > 0 && gain_before < 20, "{gain_before}");
    }

    #[test]
    fn truth_round_trips_through_serde() {
        let c = small("6205", FaultLocation::Ball);
        let (_, truth) = plan_run(&c, 1).unwrap();
        let json = serde_json::to_string(&truth).unwrap();
        let t2: LifeTruth = serde_json::from_str(&json).unwrap();
        assert_eq!(t2, truth);
        assert!(json.contains("\"fault_location\":\"ball\""));
        assert_eq!(truth.recordings.len(), 12);
        assert_eq!(truth.recordings[1].time_s, 600.0);
        assert_eq!(truth.recordings[0].timestamp, "2026-01-01T00:00:00Z");
    }

    proptest::proptest! {
        /// Any valid schedule: the onset in its range, the first load step in the healthy
        /// stretch, every level in its range, steps only where stated, growth from 0 to 1.
        #[test]
        fn schedules_keep_their_promises(
            seed in 0u64..1_000_000,
            k in 4usize..80,
            loads in 0usize..4,
            gains in 0usize..4,
            ratio in 1.0f64..2.0,
        ) {
            let s = Schedule {
                recordings: k,
                load_steps: loads.min(k - 1),
                gain_steps: gains.min(k - 1),
                load_step_ratio: (1.0, ratio),
                gain_step_ratio: (1.0, ratio),
                ..Schedule::default()
            };
            proptest::prop_assume!(s.validate().is_ok());
            let p = plan_schedule(&s, seed).unwrap();
            let (lo, hi) = s.onset_range();
            proptest::prop_assert!((lo..=hi).contains(&p.onset_index));
            proptest::prop_assert!(p.onset_index >= 1 && p.onset_index < k);
            proptest::prop_assert_eq!(p.load_step_indices.len(), s.load_steps);
            proptest::prop_assert_eq!(p.gain_step_indices.len(), s.gain_steps);
            if let Some(&f) = p.load_step_indices.first() {
                proptest::prop_assert!(f >= 1 && f < p.onset_index);
            }
            for i in 1..k {
                if p.load[i] != p.load[i - 1] {
                    proptest::prop_assert!(p.load_step_indices.contains(&i));
                }
                if p.gain[i] != p.gain[i - 1] {
                    proptest::prop_assert!(p.gain_step_indices.contains(&i));
                }
            }
            proptest::prop_assert!(p.load.iter().all(|l| (LOAD_RANGE.0..=LOAD_RANGE.1).contains(l)));
            proptest::prop_assert!(p.gain.iter().all(|g| (GAIN_RANGE.0..=GAIN_RANGE.1).contains(g)));
            proptest::prop_assert!(p.speed_factor.iter().all(|f| (f - 1.0).abs() <= s.speed_drift + 1e-12));
            proptest::prop_assert_eq!(p.growth[p.onset_index], Some(0.0));
            if p.onset_index < k - 1 {
                proptest::prop_assert_eq!(p.growth[k - 1], Some(1.0));
            }
            proptest::prop_assert!(p.growth[..p.onset_index].iter().all(Option::is_none));
        }
    }

    #[test]
    fn timestamps_and_names() {
        assert_eq!(iso_timestamp(0), "1970-01-01T00:00:00Z");
        assert_eq!(ims_name(1_076_581_959), "2004.02.12.10.32.39");
        assert_eq!(iso_timestamp(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(ims_name(DEFAULT_START_UNIX_S + 600), "2026.01.01.00.10.00");
    }

    #[test]
    fn bad_configs_are_typed_errors() {
        let ok = small("6308", FaultLocation::Outer);
        assert!(ok.validate().is_ok());
        let bad = |f: &dyn Fn(&mut LifeConfig)| {
            let mut c = ok.clone();
            f(&mut c);
            let e = plan_run(&c, 0).unwrap_err();
            assert!(
                matches!(e, LifeError::InvalidConfig { .. } | LifeError::Model(_)),
                "{e}"
            );
            e
        };
        bad(&|c| c.schedule.recordings = 1);
        bad(&|c| c.schedule.duration_s = f64::NAN);
        bad(&|c| c.schedule.duration_s = 0.0);
        bad(&|c| c.schedule.interval_s = 0);
        bad(&|c| c.schedule.onset_fraction = (0.7, 0.4));
        bad(&|c| c.schedule.onset_fraction = (0.0, 0.5));
        bad(&|c| c.schedule.onset_fraction = (0.5, 1.0));
        bad(&|c| c.schedule.onset_fraction = (0.51, 0.52));
        bad(&|c| c.schedule.speed_drift = -0.1);
        bad(&|c| c.schedule.load_steps = 12);
        bad(&|c| c.schedule.gain_step_ratio = (0.5, 1.2));
        bad(&|c| c.schedule.load_step_ratio = (1.2, f64::INFINITY));
        bad(&|c| c.schedule.start_unix_s = -1);
        bad(&|c| c.schedule.interval_s = u64::MAX);
        bad(&|c| c.schedule.interval_s = 30_000_000_000);
        bad(&|c| c.severity_db = (0.0, -10.0));
        bad(&|c| c.severity_db = (-80.0, 0.0));
        bad(&|c| c.machine.snr_db = f64::NAN);
        bad(&|c| c.machine.rpm = 10.0);
        bad(&|c| c.machine.fs_hz = 100.0);
        let e = bad(&|c| {
            c.schedule.interval_s = 1;
            c.schedule.duration_s = 2.0;
        });
        assert!(e.to_string().contains("interval_s"), "{e}");
        assert!(matches!(
            LifeMachine::preset("6203"),
            Err(LifeError::UnknownPreset(_))
        ));
        assert!(LifeMachine::preset("uc204").is_ok());
    }
}
