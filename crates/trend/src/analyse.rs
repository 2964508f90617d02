//! The run: indicators of every recording (in parallel), thresholds from the baseline, the
//! per-indicator onsets, the run's alarm, the fault named and the severity after it.

use std::collections::BTreeMap;
use std::time::Instant;

use rayon::prelude::*;

use crate::alarm::{self, Domain, Severity, Threshold};
use crate::config::{CheckedTrendConfig, MIN_BASELINES, SPEED_FIT_MIN_SPAN, TrendConfig};
use crate::error::{Result, TrendError};
use crate::indicators::{self, Unit, Zone};
use crate::order::TimeAxis;

/// The dissertation's proposed observers whose residual energy is trended (ch. 2–5).
pub const OBSERVERS: [pipeline::Method; 4] = [
    pipeline::Method::Hostsmo,
    pipeline::Method::Pflo,
    pipeline::Method::Smalpio,
    pipeline::Method::Afsmo,
];

/// Seconds of baseline recordings the diagnosis' healthy reference is fitted on, at most (the
/// baseline recordings joined end to end).
pub const DIAGNOSIS_BASELINE_SECONDS: f64 = 10.0;

/// One recording of a trend sequence, in memory: one channel's samples, its time on the run's
/// axis and its declared speed (a recording as read from a file is `bearing_data::Recording`).
#[derive(Debug, Clone)]
pub struct TrendRecording {
    /// Its name (a file name), for reports and errors.
    pub name: String,
    /// Its time on the run's [`TimeAxis`].
    pub time: f64,
    /// The samples of one channel (acceleration).
    pub samples: Vec<f64>,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Declared shaft speed, rpm (the diagnosis searches ± 10 % around it).
    pub rpm: f64,
}

/// `alarm_on = ["all"]`: the run's alarm over every indicator (amplitudes and energies too), not
/// only the gain-immune ones of the default.
pub const ALARM_ON_ALL: &str = "all";

/// What an indicator measures, which decides its threshold domain, its speed normalisation
/// and whether a sensor-gain change moves it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// An amplitude (× gain; normalised by (rpm/rpm_ref)^p).
    Amplitude,
    /// An energy, amplitude² (× gain²; normalised by (rpm/rpm_ref)^2p).
    Energy,
    /// A ratio of the signal to itself (gain-immune, not normalised).
    Dimensionless,
    /// The diagnosis' evidence −log10 p_healthy (gain-immune, not normalised).
    Evidence,
}

impl Scale {
    /// The threshold domain.
    pub fn domain(self) -> Domain {
        match self {
            Scale::Evidence => Domain::Linear,
            _ => Domain::Log10,
        }
    }

    /// Power of the speed ratio in the normalisation, in units of p.
    pub fn speed_power(self) -> f64 {
        match self {
            Scale::Amplitude => 1.0,
            Scale::Energy => 2.0,
            _ => 0.0,
        }
    }

    /// Whether a change of the sensor's gain leaves the indicator unchanged.
    pub fn gain_immune(self) -> bool {
        matches!(self, Scale::Dimensionless | Scale::Evidence)
    }
}

/// One indicator (a column of the table).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IndicatorInfo {
    /// Column name (`rms`, `kurtosis`, `evidence_outer`, `hostsmo_ms`, …).
    pub name: String,
    /// Its scale.
    pub scale: Scale,
    /// Its unit.
    pub unit: String,
    /// One line on what it is.
    pub description: String,
}

/// One recording's row.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Row {
    /// Name.
    pub name: String,
    /// Time on the run's axis.
    pub time: f64,
    /// Whether it is one of the baseline recordings.
    pub baseline: bool,
    /// The speed the normalisation used: the diagnosis' (`rpm_used`) when diagnosed, else the
    /// declared one, rpm.
    pub rpm: f64,
    /// Each indicator as measured (`None`: not computed, see `notes`).
    pub values: Vec<Option<f64>>,
    /// Each indicator after the speed normalisation (what the thresholds apply to).
    pub normalised: Vec<Option<f64>>,
    /// Each indicator above its threshold.
    pub above: Vec<bool>,
    /// The diagnosis' verdict (`None`: not diagnosed).
    pub verdict: Option<String>,
    /// The diagnosis' p_healthy (3 × min over hypotheses, capped at 1).
    pub p_healthy: Option<f64>,
    /// Modulation depth per hypothesis (`inner`, `outer`, `ball`) where the diagnosis read one.
    pub modulation_depth: BTreeMap<String, f64>,
    /// ISO 20816-3 zone of the (not normalised) velocity, when a group is given and the unit
    /// known.
    pub zone: Option<Zone>,
    /// What was not computed, and why.
    pub notes: Vec<String>,
}

/// An indicator's onset under the m-of-n rule.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Onset {
    /// Indicator.
    pub indicator: String,
    /// Row where the rule was first met.
    pub index: usize,
    /// Its time.
    pub time: f64,
    /// Row of the first exceedance in that window.
    pub first_exceedance_index: usize,
    /// The fault the diagnosis named over the window's exceeding recordings (or, when it said
    /// `normal`, the hypothesis whose evidence rose above this machine's baseline: `fault_basis`).
    pub fault: String,
    /// How `fault` was named: `diagnosis` or `evidence trend` ([`alarm::fault_named_with_trend`]).
    pub fault_basis: String,
    /// The severity trend of this indicator from the onset on.
    pub severity: Severity,
}

/// The run's alarm: the earliest onset among the alarm indicators.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Alarm {
    /// Row.
    pub index: usize,
    /// Its name.
    pub name: String,
    /// Its time.
    pub time: f64,
    /// The indicators whose onset is at that row.
    pub indicators: Vec<String>,
    /// The fault named: the most frequent non-normal verdict among the recordings of the
    /// m-of-n window where one of these indicators was above its threshold; when there is none,
    /// the hypothesis whose evidence rose above this machine's baseline (`fault_basis`).
    pub fault: String,
    /// How `fault` was named: `diagnosis` or `evidence trend` ([`alarm::fault_named_with_trend`]).
    pub fault_basis: String,
    /// The verdicts of those recordings.
    pub verdicts: Vec<String>,
    /// Severity after the alarm, per alarm indicator.
    pub severity: Vec<Severity>,
}

/// How the observers' healthy model was prepared.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ObserverSetup {
    /// The observers trended.
    pub methods: Vec<String>,
    /// Samples of the fit segment.
    pub fit_samples: usize,
    /// The recording(s) it came from (`a .. b (joined)` when the first baseline recording is
    /// shorter than the fit segment).
    pub fit_recording: String,
    /// The declared 5-DOF bearing the machine model's calibration started from.
    pub declared_bearing: String,
    /// Share of every recording skipped before the residual energy (observer start-up).
    pub settle_fraction: f64,
}

/// Wall-clock times of a run (not serialised: they vary run to run).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timing {
    /// Preparing the diagnosis reference and the observers, s.
    pub prepare_s: f64,
    /// Mean per recording: signal indicators, s (CPU time on one thread).
    pub signal_s: f64,
    /// Mean per recording: diagnosis, s.
    pub diagnosis_s: f64,
    /// Mean per recording: all observers' residuals, s.
    pub observers_s: f64,
}

/// A run's result.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrendReport {
    /// The time axis.
    pub axis: TimeAxis,
    /// Its unit.
    pub time_unit: String,
    /// The samples' unit.
    pub unit: Unit,
    /// The bearing declared.
    pub bearing: String,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// The baseline's speed every amplitude is normalised to (median of the baseline rows'
    /// speeds), rpm.
    pub rpm_reference: f64,
    /// The parameters.
    pub config: CheckedTrendConfig,
    /// The indicators, in column order.
    pub indicators: Vec<IndicatorInfo>,
    /// Threshold per indicator (`None`: fewer than the minimum baseline values).
    pub thresholds: Vec<Option<Threshold>>,
    /// Speed exponent p per indicator (amplitudes divided by (rpm/rpm_ref)^p, energies by
    /// its square; `None`: not normalised).
    pub speed_exponents: Vec<Option<f64>>,
    /// One row per recording, in time order.
    pub rows: Vec<Row>,
    /// Onset per indicator (`None`: never met the rule).
    pub onsets: Vec<Option<Onset>>,
    /// The indicators the alarm is taken over.
    pub alarm_on: Vec<String>,
    /// The run's alarm.
    pub alarm: Option<Alarm>,
    /// The observers' setup (`None`: not prepared, see `notes`).
    pub observers: Option<ObserverSetup>,
    /// What was not computed, and why (run level).
    pub notes: Vec<String>,
    /// Wall-clock times.
    #[serde(skip)]
    pub timing: Timing,
}

/// Where the m-of-n rule is first met on a set of indicators, from a given recording on
/// ([`TrendReport::rule_met_from`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RuleMet {
    /// Row where the rule was first met (the earliest over the indicators).
    pub index: usize,
    /// The indicators whose rule is met at that row.
    pub indicators: Vec<String>,
    /// The fault named over the window's recordings where one of them was above (as the
    /// report's [`Alarm::fault`]).
    pub fault: String,
    /// How `fault` was named (as [`Alarm::fault_basis`]).
    pub fault_basis: String,
}

impl TrendReport {
    /// Index of the indicator named `name`.
    pub fn indicator(&self, name: &str) -> Option<usize> {
        self.indicators.iter().position(|i| i.name == name)
    }

    /// The m-of-n rule on the indicators `columns` (taken together: the earliest of them)
    /// with every window starting no earlier than row `start` (and never in the baseline), on
    /// the rows' `above` flags: the report's own onsets and alarm are this with `start` =
    /// `baseline_count` (one column: [`Onset::index`] and [`Onset::fault`]; the `alarm_on`
    /// columns: [`Alarm`]). With `start` at a known fault onset it is the first alarm whose
    /// window holds only recordings from that onset on (validation with known truth). `None`:
    /// the rule is never met, or no column is valid.
    pub fn rule_met_from(&self, columns: &[usize], start: usize) -> Option<RuleMet> {
        let c = self.config.get();
        let start = start.max(c.baseline_count);
        let ncol = self.indicators.len();
        let met: Vec<(usize, usize)> = columns
            .iter()
            .filter(|&&j| j < ncol)
            .filter_map(|&j| {
                let a: Vec<bool> = self.rows.iter().map(|r| r.above[j]).collect();
                alarm::m_of_n(&a, start, c.m, c.n).map(|(idx, _)| (j, idx))
            })
            .collect();
        let idx = met.iter().map(|m| m.1).min()?;
        let firing: Vec<usize> = met.iter().filter(|m| m.1 == idx).map(|m| m.0).collect();
        let lo = start.max((idx + 1).saturating_sub(c.n));
        let fired: Vec<Option<&str>> = (lo..=idx)
            .filter(|&k| firing.iter().any(|&j| self.rows[k].above[j]))
            .map(|k| self.rows[k].verdict.as_deref())
            .collect();
        let evidence = evidence_window(
            &self.indicators,
            |k, j| self.rows[k].above[j],
            |k, j| self.rows[k].values[j],
            lo,
            idx,
        );
        let (fault, basis) = alarm::fault_named_with_trend(&fired, &evidence);
        Some(RuleMet {
            index: idx,
            indicators: firing
                .iter()
                .map(|&j| self.indicators[j].name.clone())
                .collect(),
            fault,
            fault_basis: basis.to_string(),
        })
    }
}

/// Per hypothesis with an evidence column (`evidence_<h>`): its above-threshold flags over rows
/// `lo..=idx` and its value at `idx` (for [`alarm::fault_named_with_trend`]).
fn evidence_window(
    indicators: &[IndicatorInfo],
    above: impl Fn(usize, usize) -> bool,
    value: impl Fn(usize, usize) -> Option<f64>,
    lo: usize,
    idx: usize,
) -> Vec<(&str, Vec<bool>, Option<f64>)> {
    indicators
        .iter()
        .enumerate()
        .filter_map(|(j, i)| {
            let h = i.name.strip_prefix("evidence_")?;
            Some((h, (lo..=idx).map(|k| above(k, j)).collect(), value(idx, j)))
        })
        .collect()
}

fn info(name: &str, scale: Scale, unit: &str, description: &str) -> IndicatorInfo {
    IndicatorInfo {
        name: name.into(),
        scale,
        unit: unit.into(),
        description: description.into(),
    }
}

/// The indicator columns of a run.
fn columns(unit: Unit, diagnosis: bool, observers: &[pipeline::Method]) -> Vec<IndicatorInfo> {
    let u = match unit {
        Unit::Unknown => "unit",
        _ => unit.code(),
    };
    let u2 = match unit {
        Unit::G => "g²".to_string(),
        Unit::MetersPerSecondSquared => "(m/s^2)²".to_string(),
        Unit::Unknown => "unit²".to_string(),
    };
    let v = if unit.to_si().is_some() {
        "mm/s".to_string()
    } else {
        "unit·s".to_string()
    };
    let mut c = vec![
        info("rms", Scale::Amplitude, u, "RMS of the signal"),
        info("peak", Scale::Amplitude, u, "largest |sample|"),
        info("crest", Scale::Dimensionless, "1", "peak / RMS"),
        info(
            "kurtosis",
            Scale::Dimensionless,
            "1",
            "m4/m2² (3 = Gaussian)",
        ),
        info(
            "velocity_rms",
            Scale::Amplitude,
            &v,
            "velocity RMS 10–1000 Hz (frequency-domain integration)",
        ),
        info(
            "signal_ms",
            Scale::Energy,
            &u2,
            "mean square of the signal (the raw energy the observers' residual energy is compared with)",
        ),
    ];
    if diagnosis {
        for h in ["inner", "outer", "ball"] {
            c.push(info(
                &format!("evidence_{h}"),
                Scale::Evidence,
                "decades",
                &format!("−log10 p_healthy of the {h}-race hypothesis (diagnosis)"),
            ));
        }
    }
    for m in observers {
        let n = m.name().to_ascii_lowercase();
        c.push(info(
            &format!("{n}_ms"),
            Scale::Energy,
            &u2,
            &format!(
                "mean square of the {} residual on the baseline's healthy model",
                m.name()
            ),
        ));
        c.push(info(
            &format!("{n}_ratio"),
            Scale::Dimensionless,
            "1",
            &format!(
                "{} residual mean square / signal mean square (same samples)",
                m.name()
            ),
        ));
    }
    c
}

/// The observers' healthy model, prepared once on the baseline.
struct Observers {
    prepared: pipeline::Prepared,
    tuned: Vec<(pipeline::Method, pipeline::Tuning)>,
}

/// Prepare the observers on the first `fit_seconds` of the baseline recordings joined end to
/// end (the first recording's alone when it is that long).
fn prepare_observers(
    baseline: &[TrendRecording],
    fit_seconds: f64,
    bearing: &diagnosis::BearingSpec,
    notes: &mut Vec<String>,
) -> Option<(Observers, ObserverSetup)> {
    let first = &baseline[0];
    let cap = (fit_seconds * first.fs_hz).round() as usize;
    let fit: Vec<f64> = baseline
        .iter()
        .flat_map(|r| r.samples.iter().copied())
        .take(cap)
        .collect();
    let n = fit.len();
    let joined = baseline
        .iter()
        .scan(0usize, |acc, r| {
            let start = *acc;
            *acc += r.samples.len();
            Some(start)
        })
        .take_while(|&start| start < n)
        .count();
    let fit_recording = if joined > 1 {
        format!("{} .. {} (joined)", first.name, baseline[joined - 1].name)
    } else {
        first.name.clone()
    };
    let declared = bearing
        .name
        .parse::<bearing_model::Bearing>()
        .or_else(|_| bearing.given.parse::<bearing_model::Bearing>());
    let declared_bearing = match declared {
        Ok(b) => b,
        Err(_) => {
            notes.push(format!(
                "the observers' machine model was calibrated from the 6205's declared healthy 5-DOF model (the built-in physics has only the 6205 and 6203; {} enters the diagnosis only): the structural path and lines are identified from the baseline either way",
                bearing.echo()
            ));
            bearing_model::Bearing::Skf6205
        }
    };
    let prepared = match pipeline::Prepared::new_for(
        &fit,
        first.fs_hz,
        first.rpm,
        declared_bearing,
        true,
        true,
    ) {
        Ok(p) => p,
        Err(e) => {
            notes.push(format!(
                "observers not prepared on {fit_recording} ({n} samples): {e}"
            ));
            return None;
        }
    };
    let mut tuned = Vec::new();
    for m in OBSERVERS {
        match prepared.tune(m) {
            Ok(t) => tuned.push((m, t)),
            Err(e) => notes.push(format!("{} not tuned on the baseline: {e}", m.name())),
        }
    }
    if tuned.is_empty() {
        return None;
    }
    let setup = ObserverSetup {
        methods: tuned.iter().map(|(m, _)| m.name().to_string()).collect(),
        fit_samples: n,
        fit_recording,
        declared_bearing: declared_bearing.designation().to_string(),
        settle_fraction: pipeline::INPUT_SETTLE,
    };
    Some((Observers { prepared, tuned }, setup))
}

/// Everything measured on one recording before the thresholds.
struct Measured {
    values: Vec<Option<f64>>,
    rpm: f64,
    verdict: Option<String>,
    p_healthy: Option<f64>,
    modulation_depth: BTreeMap<String, f64>,
    notes: Vec<String>,
    secs: [f64; 3],
}

fn measure(
    r: &TrendRecording,
    cfg: &CheckedTrendConfig,
    bearing: &diagnosis::BearingSpec,
    reference: Option<&diagnosis::Baseline>,
    obs: Option<&Observers>,
) -> Result<Measured> {
    let c = cfg.get();
    let t0 = Instant::now();
    let s = indicators::signal_indicators(&r.name, &r.samples, r.fs_hz, c.unit)?;
    let mut values = vec![
        Some(s.rms),
        Some(s.peak),
        Some(s.crest),
        Some(s.kurtosis),
        Some(s.velocity_rms),
        Some(s.mean_square),
    ];
    let t1 = Instant::now();
    let mut notes = Vec::new();
    let (mut rpm, mut verdict, mut p_healthy) = (r.rpm, None, None);
    let mut depth = BTreeMap::new();
    if c.diagnosis {
        let options = diagnosis::DiagnoseOptions::declared(r.rpm).with_false_alarm(c.false_alarm);
        let d = diagnosis::Signal::new(&r.samples, r.fs_hz)
            .map_err(diagnosis::DiagnosisError::from)
            .and_then(|signal| {
                if bearing.name == "unknown" {
                    diagnosis::diagnose_unknown_bearing(&signal, reference, &options)
                } else {
                    diagnosis::diagnose_with_options(&signal, bearing, reference, &options)
                }
            });
        match d {
            Ok(d) => {
                for h in diagnosis::Hypothesis::ALL {
                    let sig = d
                        .evidence
                        .iter()
                        .find(|e| e.hypothesis == h)
                        .and_then(|e| e.significance.as_ref());
                    // + 0.0: −log10 1 is −0, printed "-0"
                    values.push(sig.map(|s| -s.p_healthy.max(1e-300).log10().min(300.0) + 0.0));
                    if let Some(s) = sig.filter(|s| s.modulation_depth.is_finite()) {
                        depth.insert(h.name().to_string(), s.modulation_depth);
                    }
                }
                rpm = d.operating_point.rpm_used;
                verdict = Some(d.verdict.clone());
                p_healthy = Some(d.p_healthy);
            }
            Err(e) => {
                notes.push(format!("not diagnosed: {e}"));
                values.extend([None, None, None]);
            }
        }
    }
    let t2 = Instant::now();
    if let Some(o) = obs {
        let n = r.samples.len();
        let skip = ((pipeline::INPUT_SETTLE * n as f64).round() as usize).min(n.saturating_sub(1));
        let sig_ms = close_loop::metric::mean_square(&r.samples[skip..]);
        // the machine model's input is shared by the observers that take it
        let input = match o.prepared.machine_input(&r.samples) {
            Ok(u) => u,
            Err(e) => {
                notes.push(format!("machine model input: {e}"));
                None
            }
        };
        for (m, t) in &o.tuned {
            let res =
                pipeline::residual_with_input(*m, &o.prepared, t, &r.samples, input.as_deref());
            match res {
                Ok(e) if e.iter().all(|v| v.is_finite()) => {
                    let ms = close_loop::metric::mean_square(&e[skip..]);
                    values.push(Some(ms));
                    values.push((sig_ms > 0.0).then(|| ms / sig_ms));
                }
                Ok(_) => {
                    notes.push(format!("{}: non-finite residual", m.name()));
                    values.extend([None, None]);
                }
                Err(e) => {
                    notes.push(format!("{}: {e}", m.name()));
                    values.extend([None, None]);
                }
            }
        }
    }
    let t3 = Instant::now();
    Ok(Measured {
        values,
        rpm,
        verdict,
        p_healthy,
        modulation_depth: depth,
        notes,
        secs: [
            (t1 - t0).as_secs_f64(),
            (t2 - t1).as_secs_f64(),
            (t3 - t2).as_secs_f64(),
        ],
    })
}

/// The speed exponent p of each indicator (`None`: not normalised): fitted on the baseline rows
/// by least squares of ln v against ln rpm (divided by the scale's power, clamped to [0, 4])
/// when their speeds span at least [`SPEED_FIT_MIN_SPAN`] and `fit_speed_exponent`, else the
/// configured `speed_exponent`.
fn speed_exponents(
    baseline: &[Measured],
    indicators: &[IndicatorInfo],
    c: &crate::config::TrendConfig,
    notes: &mut Vec<String>,
) -> Vec<Option<f64>> {
    let rpms: Vec<f64> = baseline.iter().map(|m| m.rpm).collect();
    let (lo, hi) = rpms
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    let fit = c.fit_speed_exponent && lo > 0.0 && hi / lo - 1.0 >= SPEED_FIT_MIN_SPAN;
    indicators
        .iter()
        .enumerate()
        .map(|(j, info)| {
            let power = info.scale.speed_power();
            if power == 0.0 {
                return None;
            }
            if !fit {
                return Some(c.speed_exponent);
            }
            let pts: Vec<(f64, f64)> = baseline
                .iter()
                .filter_map(|m| m.values[j].filter(|v| *v > 0.0).map(|v| (m.rpm.ln(), v.ln())))
                .collect();
            let n = pts.len() as f64;
            let (mx, my) = (
                pts.iter().map(|p| p.0).sum::<f64>() / n,
                pts.iter().map(|p| p.1).sum::<f64>() / n,
            );
            let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
            let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
            let p = if pts.len() >= MIN_BASELINES && sxx > 0.0 {
                (sxy / sxx / power).clamp(0.0, 4.0)
            } else {
                c.speed_exponent
            };
            notes.push(format!(
                "{}: speed exponent {p:.2} fitted on the baseline (its speeds span {lo:.0}–{hi:.0} rpm)",
                info.name
            ));
            Some(p)
        })
        .collect()
}

/// Check the recordings: enough of them, one sampling rate, finite samples, positive speed,
/// increasing times.
fn check(recs: &[TrendRecording], baseline_count: usize) -> Result<()> {
    if baseline_count < MIN_BASELINES {
        return Err(TrendError::TooFewBaselines {
            needed: MIN_BASELINES,
            found: baseline_count,
        });
    }
    if recs.len() < baseline_count {
        return Err(TrendError::TooFewRecordings {
            needed: baseline_count,
            found: recs.len(),
        });
    }
    let first = &recs[0];
    for (i, r) in recs.iter().enumerate() {
        let bad = |reason: String| TrendError::BadRecording {
            name: r.name.clone(),
            reason,
        };
        if !(r.fs_hz.is_finite() && r.fs_hz > 0.0) {
            return Err(bad(format!("sampling rate {} Hz", r.fs_hz)));
        }
        if (r.fs_hz - first.fs_hz).abs() > 1e-9 * first.fs_hz {
            return Err(TrendError::MixedRates {
                name: r.name.clone(),
                fs_hz: r.fs_hz,
                first: first.name.clone(),
                expected_hz: first.fs_hz,
            });
        }
        if !(r.rpm.is_finite() && r.rpm > 0.0) {
            return Err(bad(format!("declared speed {} rpm", r.rpm)));
        }
        if !r.time.is_finite() {
            return Err(bad(format!("time {}", r.time)));
        }
        if i > 0 && r.time <= recs[i - 1].time {
            return Err(TrendError::NotOrdered {
                name: r.name.clone(),
                time: r.time,
                previous: recs[i - 1].time,
            });
        }
        if let Some(k) = r.samples.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!("sample {k} is not finite")));
        }
    }
    Ok(())
}

/// [`analyse_with_progress`] without progress.
///
/// # Errors
/// As [`analyse_with_progress`].
pub fn analyse(
    recs: &[TrendRecording],
    axis: TimeAxis,
    bearing: &diagnosis::BearingSpec,
    cfg: &CheckedTrendConfig,
) -> Result<TrendReport> {
    analyse_with_progress(recs, axis, bearing, cfg, &|| {})
}

/// Analyse recordings in time order (`recs[k].time` increasing on `axis`): the first
/// `baseline_count` are the healthy baseline. `tick` is called once per recording measured
/// (from rayon's threads).
///
/// Steps: (1) the diagnosis' healthy reference (`diagnosis::Baseline::prepare` on the baseline
/// recordings joined, at most [`DIAGNOSIS_BASELINE_SECONDS`]) and the observers' healthy model
/// (`pipeline::Prepared::new_for` on the first baseline recording's first `fit_seconds`, each of
/// [`OBSERVERS`] tuned on it by `Prepared::tune`); (2) every recording's indicators, in
/// parallel; (3) the speed normalisation; (4) thresholds from the baseline rows; (5) the m-of-n
/// onset of each indicator, the alarm over `alarm_on`, the fault named and the severity after.
///
/// # Errors
/// Too few recordings or baselines, mixed sampling rates, non-finite samples, times not
/// increasing, an `alarm_on` naming no indicator: one line naming the recording. A recording
/// the diagnosis or an observer cannot read is not an error: its value is `None` and the row's
/// notes say why.
pub fn analyse_with_progress(
    recs: &[TrendRecording],
    axis: TimeAxis,
    bearing: &diagnosis::BearingSpec,
    cfg: &CheckedTrendConfig,
    tick: &(dyn Fn() + Sync),
) -> Result<TrendReport> {
    let c = cfg.get();
    let nb = c.baseline_count;
    check(recs, nb)?;
    let fs = recs[0].fs_hz;
    let mut notes = Vec::new();
    // 1. the healthy references, on the baseline only
    let tp = Instant::now();
    let reference = diagnosis_reference(&recs[..nb], fs, c.diagnosis, &mut notes);
    let obs = if c.observers {
        prepare_observers(&recs[..nb], c.fit_seconds, bearing, &mut notes)
    } else {
        notes.push("observers not run (disabled)".into());
        None
    };
    let prepare_s = tp.elapsed().as_secs_f64();
    let methods: Vec<pipeline::Method> = obs
        .as_ref()
        .map(|(o, _)| o.tuned.iter().map(|t| t.0).collect())
        .unwrap_or_default();
    let indicators = columns(c.unit, c.diagnosis, &methods);
    // 2. every recording's indicators, in parallel
    let measured: Vec<Measured> = recs
        .par_iter()
        .map(|r| {
            let m = measure(
                r,
                cfg,
                bearing,
                reference.as_ref(),
                obs.as_ref().map(|o| &o.0),
            );
            tick();
            m
        })
        .collect::<Result<_>>()?;
    let nr = recs.len() as f64;
    let mean = |k: usize| measured.iter().map(|m| m.secs[k]).sum::<f64>() / nr;
    let timing = Timing {
        prepare_s,
        signal_s: mean(0),
        diagnosis_s: mean(1),
        observers_s: mean(2),
    };
    // 3. speed normalisation to the baseline's median speed, thresholds from the baseline
    let rpm_reference = alarm::median(&measured[..nb].iter().map(|m| m.rpm).collect::<Vec<_>>())
        .unwrap_or(recs[0].rpm);
    let speed_exponents = speed_exponents(&measured[..nb], &indicators, c, &mut notes);
    let normalised = normalise(&measured, &indicators, &speed_exponents, rpm_reference);
    let thresholds = thresholds_of(&normalised, nb, &indicators, c.k, &mut notes);
    let above = above_of(&normalised, &thresholds);
    // 4. each indicator's onset, the alarm over the alarm indicators
    let alarm_on = alarm_indicators(c.alarm_on.as_deref(), &indicators)?;
    let (onsets, alarm) = {
        let table = Table {
            c,
            axis,
            recs,
            indicators: &indicators,
            measured: &measured,
            normalised: &normalised,
            thresholds: &thresholds,
            above: &above,
        };
        let onsets: Vec<Option<Onset>> = (0..indicators.len()).map(|j| table.onset(j)).collect();
        let alarm = table.alarm(&alarm_on, &onsets);
        (onsets, alarm)
    };
    // 5. the rows
    let rows = rows_of(recs, measured, normalised, above, c);
    Ok(TrendReport {
        axis,
        time_unit: axis.unit().to_string(),
        unit: c.unit,
        bearing: bearing.echo().to_string(),
        fs_hz: fs,
        rpm_reference,
        config: cfg.clone(),
        indicators,
        thresholds,
        speed_exponents,
        rows,
        onsets,
        alarm_on,
        alarm,
        observers: obs.map(|o| o.1),
        notes,
        timing,
    })
}

/// The diagnosis' healthy reference, fitted on the baseline recordings joined (at most
/// [`DIAGNOSIS_BASELINE_SECONDS`]); `None`, with a note, when the diagnosis is off or the fit
/// fails (every recording is then diagnosed self-referenced).
fn diagnosis_reference(
    baseline: &[TrendRecording],
    fs: f64,
    diagnose: bool,
    notes: &mut Vec<String>,
) -> Option<diagnosis::Baseline> {
    if !diagnose {
        notes.push("diagnosis not run: no evidence indicators, no fault named".into());
        return None;
    }
    let cap = (DIAGNOSIS_BASELINE_SECONDS * fs) as usize;
    let joined: Vec<f64> = baseline
        .iter()
        .flat_map(|r| r.samples.iter().copied())
        .take(cap)
        .collect();
    let prepared = diagnosis::Signal::new(joined, fs)
        .map_err(|e| diagnosis::DiagnosisError::signal("baseline", e))
        .and_then(|signal| diagnosis::Baseline::prepare(&signal));
    match prepared {
        Ok(b) => Some(b),
        Err(e) => {
            notes.push(format!(
                "the diagnosis' healthy reference could not be fitted on the baseline ({e}); every recording is diagnosed self-referenced"
            ));
            None
        }
    }
}

/// Each recording's indicators divided by (rpm / `rpm_reference`)^(p·power of its scale): the
/// values the thresholds apply to (non-finite ones dropped).
fn normalise(
    measured: &[Measured],
    indicators: &[IndicatorInfo],
    speed_exponents: &[Option<f64>],
    rpm_reference: f64,
) -> Vec<Vec<Option<f64>>> {
    measured
        .iter()
        .map(|m| {
            let ratio = m.rpm / rpm_reference;
            m.values
                .iter()
                .zip(indicators)
                .zip(speed_exponents)
                .map(|((v, i), p)| {
                    v.map(|v| v / ratio.powf(p.unwrap_or(0.0) * i.scale.speed_power()))
                        .filter(|v| v.is_finite())
                })
                .collect()
        })
        .collect()
}

/// Each indicator's threshold from its first `nb` (baseline) normalised values; a note for each
/// one without ([`MIN_BASELINES`]).
fn thresholds_of(
    normalised: &[Vec<Option<f64>>],
    nb: usize,
    indicators: &[IndicatorInfo],
    k: f64,
    notes: &mut Vec<String>,
) -> Vec<Option<Threshold>> {
    let thresholds: Vec<Option<Threshold>> = (0..indicators.len())
        .map(|j| {
            let b: Vec<Option<f64>> = normalised[..nb].iter().map(|row| row[j]).collect();
            alarm::threshold(&b, indicators[j].scale.domain(), k, MIN_BASELINES)
        })
        .collect();
    for (i, t) in indicators.iter().zip(&thresholds) {
        if t.is_none() {
            notes.push(format!(
                "{}: no threshold (fewer than {MIN_BASELINES} baseline values)",
                i.name
            ));
        }
    }
    thresholds
}

/// Per recording and indicator: above its threshold.
fn above_of(normalised: &[Vec<Option<f64>>], thresholds: &[Option<Threshold>]) -> Vec<Vec<bool>> {
    normalised
        .iter()
        .map(|row| {
            row.iter()
                .zip(thresholds)
                .map(|(v, t)| matches!((v, t), (Some(v), Some(t)) if *v > t.value))
                .collect()
        })
        .collect()
}

/// The indicators whose onsets make the run's alarm: those named (every one named must be a
/// column of the run), every indicator for [`ALARM_ON_ALL`], by default the gain-immune ones —
/// an amplitude or an energy cannot tell a fault from a load step or a sensor's gain
/// (docs/equations/trend.md, "Onset alarm").
fn alarm_indicators(named: Option<&[String]>, indicators: &[IndicatorInfo]) -> Result<Vec<String>> {
    Ok(match named {
        Some([all]) if all == ALARM_ON_ALL => indicators.iter().map(|i| i.name.clone()).collect(),
        Some(list) => {
            for n in list {
                if !indicators.iter().any(|i| &i.name == n) {
                    return Err(TrendError::Config(format!(
                        "alarm indicator `{n}` is not among this run's indicators ({})",
                        indicators
                            .iter()
                            .map(|i| i.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )));
                }
            }
            list.to_vec()
        }
        None => indicators
            .iter()
            .filter(|i| i.scale.gain_immune())
            .map(|i| i.name.clone())
            .collect(),
    })
}

/// What the onsets and the alarm are read from: the run's recordings, indicators, measured and
/// normalised values, thresholds and exceedances.
struct Table<'a> {
    c: &'a TrendConfig,
    axis: TimeAxis,
    recs: &'a [TrendRecording],
    indicators: &'a [IndicatorInfo],
    measured: &'a [Measured],
    normalised: &'a [Vec<Option<f64>>],
    thresholds: &'a [Option<Threshold>],
    above: &'a [Vec<bool>],
}

impl Table<'_> {
    /// The level the severity after an onset of indicator `j` is projected to: the ISO 20816-3
    /// zone B/C boundary for the velocity when a machine group and the unit are given, else
    /// `level_factor` × its threshold; `None` without a threshold.
    fn level_of(&self, j: usize) -> Option<(f64, String)> {
        let c = self.c;
        if self.indicators[j].name == "velocity_rms"
            && let (Some(g), Some(_)) = (c.machine_group, c.unit.to_si())
        {
            let l = g.boundaries_mm_s()[1];
            return Some((l, format!("ISO 20816-3 zone B/C boundary ({l} mm/s)")));
        }
        self.thresholds[j].map(|t| {
            (
                c.level_factor * t.value,
                format!("{} x threshold", c.level_factor),
            )
        })
    }

    /// The fault named over rows `lo..=idx` (the recordings in `fired` those that fired): the
    /// diagnosis' verdicts, else the evidence's trend ([`alarm::fault_named_with_trend`]).
    fn fault(&self, lo: usize, idx: usize, fired: &[usize]) -> (String, &'static str) {
        let verdicts: Vec<Option<&str>> = fired
            .iter()
            .map(|&k| self.measured[k].verdict.as_deref())
            .collect();
        let evidence = evidence_window(
            self.indicators,
            |k, j| self.above[k][j],
            |k, j| self.measured[k].values[j],
            lo,
            idx,
        );
        alarm::fault_named_with_trend(&verdicts, &evidence)
    }

    fn times(&self) -> Vec<f64> {
        self.recs.iter().map(|r| r.time).collect()
    }

    /// Indicator `j`'s onset: the m-of-n rule from the end of the baseline, the fault named over
    /// its window, its severity after.
    fn onset(&self, j: usize) -> Option<Onset> {
        let (c, nb) = (self.c, self.c.baseline_count);
        let a: Vec<bool> = self.above.iter().map(|r| r[j]).collect();
        let (idx, first) = alarm::m_of_n(&a, nb, c.m, c.n)?;
        let lo = nb.max((idx + 1).saturating_sub(c.n));
        let fired: Vec<usize> = (lo..=idx).filter(|&k| a[k]).collect();
        let (level, basis) = self.level_of(j)?;
        let (fault, fault_basis) = self.fault(lo, idx, &fired);
        let times = self.times();
        let col: Vec<Option<f64>> = self.normalised.iter().map(|r| r[j]).collect();
        Some(Onset {
            indicator: self.indicators[j].name.clone(),
            index: idx,
            time: times[idx],
            first_exceedance_index: first,
            fault,
            fault_basis: fault_basis.to_string(),
            severity: alarm::severity(&times, &col, idx, level, &basis, self.axis.rate_unit()),
        })
    }

    /// The run's alarm: the earliest onset over the indicators named in `alarm_on`, with every
    /// one whose onset is at that recording.
    fn alarm(&self, alarm_on: &[String], onsets: &[Option<Onset>]) -> Option<Alarm> {
        let (c, nb) = (self.c, self.c.baseline_count);
        let alarm_idx: Vec<usize> = (0..self.indicators.len())
            .filter(|&j| alarm_on.contains(&self.indicators[j].name))
            .collect();
        let idx = alarm_idx
            .iter()
            .filter_map(|&j| onsets[j].as_ref().map(|o| o.index))
            .min()?;
        let firing: Vec<usize> = alarm_idx
            .iter()
            .copied()
            .filter(|&j| onsets[j].as_ref().is_some_and(|o| o.index == idx))
            .collect();
        let lo = nb.max((idx + 1).saturating_sub(c.n));
        let fired: Vec<usize> = (lo..=idx)
            .filter(|&k| firing.iter().any(|&j| self.above[k][j]))
            .collect();
        let (fault, fault_basis) = self.fault(lo, idx, &fired);
        Some(Alarm {
            index: idx,
            name: self.recs[idx].name.clone(),
            time: self.recs[idx].time,
            indicators: firing
                .iter()
                .map(|&j| self.indicators[j].name.clone())
                .collect(),
            fault,
            fault_basis: fault_basis.to_string(),
            verdicts: fired
                .iter()
                .filter_map(|&k| self.measured[k].verdict.clone())
                .collect(),
            severity: firing
                .iter()
                .filter_map(|&j| onsets[j].as_ref().map(|o| o.severity.clone()))
                .collect(),
        })
    }
}

/// The report's rows: each recording with its values, normalised values, exceedances, verdict
/// and zone.
fn rows_of(
    recs: &[TrendRecording],
    measured: Vec<Measured>,
    normalised: Vec<Vec<Option<f64>>>,
    above: Vec<Vec<bool>>,
    c: &TrendConfig,
) -> Vec<Row> {
    recs.iter()
        .zip(measured)
        .zip(normalised)
        .zip(above)
        .enumerate()
        .map(|(k, (((r, m), nv), ab))| {
            let zone = match (c.machine_group, c.unit.to_si()) {
                (Some(g), Some(_)) => m.values[4].map(|v| g.zone(v)),
                _ => None,
            };
            Row {
                name: r.name.clone(),
                time: r.time,
                baseline: k < c.baseline_count,
                rpm: m.rpm,
                values: m.values,
                normalised: nv,
                above: ab,
                verdict: m.verdict,
                p_healthy: m.p_healthy,
                modulation_depth: m.modulation_depth,
                zone,
                notes: m.notes,
            }
        })
        .collect()
}
