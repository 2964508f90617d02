//! `cargo xtask trend --validate`: simulated degradation runs with known truth through
//! `trend::analyse`, and per run and indicator the bookkeeping against the truth (false alarm
//! before the onset, detection delay after it, the fault named at the alarm).
//!
//! The design ([`GEOMETRIES`], [`SEEDS`], [`location_of`], the generators' default schedules,
//! the trend crate's default configuration) was fixed before any result was seen. Synthesis is
//! `bearing_model::life`'s and `calibrated_rig::life`'s, the analysis `trend`'s (the m-of-n rule
//! from a given recording is [`trend::TrendReport::rule_met_from`]); this module only schedules
//! the runs and compares with the truth.

use std::ops::RangeInclusive;

use anyhow::Context as _;
use bearing_model::FaultLocation;
use bearing_model::life::{LifeConfig, LifeMachine, LifeRecording, LifeTruth, Schedule};
use calibrated_rig::RigModel;
use calibrated_rig::life::RigLifeConfig;
use rayon::prelude::*;
use serde::Serialize;

/// The seeds of every geometry.
pub const SEEDS: RangeInclusive<u64> = 1..=20;

/// The name of the combined alarm in the tables (the report's `alarm`: the earliest onset over
/// its alarm indicators, by default the gain-immune ones).
pub const COMBINED: &str = "alarm (combined)";

/// The alarm over every indicator, amplitudes and energies included (`--alarm-on all`; the
/// trend crate's default before the first validation run showed the load and gain steps
/// raising it).
pub const COMBINED_ALL: &str = "alarm over every indicator";

/// A machine the runs are simulated on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Geometry {
    /// The calibrated CWRU rig (6205 drive end, 12 kHz, g): `calibrated_rig::life`.
    Rig6205,
    /// The phenomenological machine with a UC204 (2100 rpm, 25.6 kHz, m/s²).
    Uc204,
    /// The phenomenological machine with a 6308 (1480 rpm, 20 kHz, m/s²).
    B6308,
}

/// Every geometry, in table order.
pub const GEOMETRIES: [Geometry; 3] = [Geometry::Rig6205, Geometry::Uc204, Geometry::B6308];

impl Geometry {
    /// Short name (tables, file names).
    pub fn name(self) -> &'static str {
        match self {
            Geometry::Rig6205 => "rig6205",
            Geometry::Uc204 => "uc204",
            Geometry::B6308 => "6308",
        }
    }

    /// The bearing designation the trend is told.
    pub fn bearing(self) -> &'static str {
        match self {
            Geometry::Rig6205 => "6205",
            Geometry::Uc204 => "UC204",
            Geometry::B6308 => "6308",
        }
    }

    /// The samples' unit.
    pub fn unit(self) -> trend::Unit {
        match self {
            Geometry::Rig6205 => trend::Unit::G,
            _ => trend::Unit::MetersPerSecondSquared,
        }
    }
}

/// The fault location of a seed: `seed % 3` → 0 inner, 1 outer, 2 ball (every location on
/// every geometry: seeds 1..=20 give 6 inner, 7 outer, 7 ball).
pub fn location_of(seed: u64) -> FaultLocation {
    match seed % 3 {
        0 => FaultLocation::Inner,
        1 => FaultLocation::Outer,
        _ => FaultLocation::Ball,
    }
}

/// A kept run: its report and truth (for the figure).
pub type Kept = (trend::TrendReport, LifeTruth);

/// One run to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// Machine.
    pub geometry: Geometry,
    /// Seed.
    pub seed: u64,
    /// Schedule (the generators' default for the committed results).
    pub schedule: Schedule,
}

/// Whether the fault named is the truth's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FaultStatus {
    /// The truth's location exactly.
    Right,
    /// Another fault (a combination that includes the truth counts here).
    Wrong,
    /// `normal`, `uncertain` or not diagnosed.
    None,
}

/// The status of `named` against `truth`.
pub fn fault_status(named: &str, truth: FaultLocation) -> FaultStatus {
    match named {
        "normal" | "uncertain" | "not diagnosed" => FaultStatus::None,
        n if n == truth.name() => FaultStatus::Right,
        _ => FaultStatus::Wrong,
    }
}

/// One indicator's (or the combined alarm's) outcome on one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    /// Indicator name, or [`COMBINED`].
    pub indicator: String,
    /// The report's onset (the m-of-n rule from the baseline's end) when it is before the true
    /// onset: its recording index and the fault named there.
    pub false_alarm: Option<(usize, String)>,
    /// The detection: the report's onset when at or after the true onset; after a false alarm,
    /// the rule restarted at the true onset (windows of faulty recordings only). Recording
    /// index and the fault named there.
    pub detection: Option<(usize, String)>,
    /// Recordings from the true onset to the detection (`detection − onset`).
    pub delay: Option<usize>,
    /// The detection's fault against the truth.
    pub fault: Option<FaultStatus>,
}

/// The bookkeeping of one indicator set against a known onset: `from_baseline` is the rule
/// from the baseline's end (the report's onset or alarm), `from_onset` the rule restarted at
/// the true onset (asked only after a false alarm).
pub fn outcome(
    indicator: &str,
    from_baseline: Option<trend::RuleMet>,
    from_onset: impl FnOnce() -> Option<trend::RuleMet>,
    onset: usize,
    truth: FaultLocation,
) -> Outcome {
    let (false_alarm, detection) = match from_baseline {
        Some(m) if m.index < onset => (Some((m.index, m.fault)), from_onset()),
        other => (None, other),
    };
    let detection = detection.map(|m| (m.index, m.fault));
    Outcome {
        indicator: indicator.to_string(),
        false_alarm,
        delay: detection.as_ref().map(|d| d.0 - onset),
        fault: detection.as_ref().map(|d| fault_status(&d.1, truth)),
        detection,
    }
}

/// Every indicator's outcome and the combined alarm's, on a report whose truth is `truth`.
pub fn outcomes(r: &trend::TrendReport, truth: &LifeTruth) -> Vec<Outcome> {
    let nb = r.config.get().baseline_count;
    let onset = truth.onset_index;
    let loc = truth.fault_location;
    let mut out: Vec<Outcome> = r
        .indicators
        .iter()
        .enumerate()
        .map(|(j, i)| {
            outcome(
                &i.name,
                r.rule_met_from(&[j], nb),
                || r.rule_met_from(&[j], onset),
                onset,
                loc,
            )
        })
        .collect();
    let on: Vec<usize> = (0..r.indicators.len())
        .filter(|&j| r.alarm_on.contains(&r.indicators[j].name))
        .collect();
    out.push(outcome(
        COMBINED,
        r.rule_met_from(&on, nb),
        || r.rule_met_from(&on, onset),
        onset,
        loc,
    ));
    let all: Vec<usize> = (0..r.indicators.len()).collect();
    out.push(outcome(
        COMBINED_ALL,
        r.rule_met_from(&all, nb),
        || r.rule_met_from(&all, onset),
        onset,
        loc,
    ));
    out
}

/// One run's result.
#[derive(Debug, Clone, Serialize)]
pub struct RunResult {
    /// Machine.
    pub geometry: Geometry,
    /// Seed.
    pub seed: u64,
    /// Fault location (truth).
    pub location: String,
    /// The true onset, recording index (0-based).
    pub onset_index: usize,
    /// Recordings in the run.
    pub recordings: usize,
    /// Minutes from one recording to the next.
    pub interval_min: f64,
    /// Load steps, gain steps (recording indices).
    pub load_steps: Vec<usize>,
    /// See `load_steps`.
    pub gain_steps: Vec<usize>,
    /// Per indicator and the combined alarm.
    pub outcomes: Vec<Outcome>,
    /// The report's run-level notes.
    pub notes: Vec<String>,
    /// The error's one line when the run could not be done.
    pub error: Option<String>,
    /// Wall-clock times, s: generating, analysing.
    #[serde(skip)]
    pub secs: (f64, f64),
}

/// Generate a run's recordings (in parallel) and its truth.
///
/// # Errors
/// The generators' typed errors, one line naming the run.
pub fn generate(
    spec: &RunSpec,
    rig: Option<&RigModel>,
    tick: &(dyn Fn() + Sync),
) -> anyhow::Result<(Vec<LifeRecording>, LifeTruth)> {
    let loc = location_of(spec.seed);
    let what = || format!("{} seed {}", spec.geometry.name(), spec.seed);
    match spec.geometry {
        Geometry::Rig6205 => {
            let rig = rig.context("the calibrated rig was not loaded")?;
            let mut cfg = RigLifeConfig::new(loc);
            cfg.schedule = spec.schedule;
            let (_, truth) =
                calibrated_rig::life::plan_rig_run(rig, &cfg, spec.seed).with_context(what)?;
            let recs = (0..cfg.schedule.recordings)
                .into_par_iter()
                .map(|i| {
                    let r = calibrated_rig::life::simulate_rig_recording(rig, &cfg, spec.seed, i);
                    tick();
                    r
                })
                .collect::<Result<Vec<_>, _>>()
                .with_context(what)?;
            Ok((recs, truth))
        }
        g => {
            let machine = LifeMachine::preset(g.bearing()).with_context(what)?;
            let mut cfg = LifeConfig::new(machine, loc);
            cfg.schedule = spec.schedule;
            let (_, truth) = bearing_model::life::plan_run(&cfg, spec.seed).with_context(what)?;
            let recs = (0..cfg.schedule.recordings)
                .into_par_iter()
                .map(|i| {
                    let r = bearing_model::life::simulate_recording(&cfg, spec.seed, i);
                    tick();
                    r
                })
                .collect::<Result<Vec<_>, _>>()
                .with_context(what)?;
            Ok((recs, truth))
        }
    }
}

/// The recordings as the trend reads them: named by their timestamp, times in seconds from the
/// run's start, the declared (nominal) speed.
pub fn recordings(recs: &[LifeRecording], truth: &LifeTruth) -> Vec<trend::TrendRecording> {
    recs.iter()
        .zip(&truth.recordings)
        .map(|(r, t)| trend::TrendRecording {
            name: t.timestamp.clone(),
            time: r.time_s,
            samples: r.samples.clone(),
            fs_hz: r.fs_hz,
            rpm: truth.rpm_declared,
        })
        .collect()
}

/// Do one run: generate, analyse with `cfg` (its unit set to the geometry's), compare with
/// the truth. Returns the result and, when `keep`, the report and truth (for the figure).
pub fn run_one(
    spec: &RunSpec,
    rig: Option<&RigModel>,
    cfg: &trend::TrendConfig,
    keep: bool,
    tick: &(dyn Fn() + Sync),
) -> (RunResult, Option<Kept>) {
    let mut res = RunResult {
        geometry: spec.geometry,
        seed: spec.seed,
        location: location_of(spec.seed).name().to_string(),
        onset_index: 0,
        recordings: spec.schedule.recordings,
        interval_min: spec.schedule.interval_s as f64 / 60.0,
        load_steps: vec![],
        gain_steps: vec![],
        outcomes: vec![],
        notes: vec![],
        error: None,
        secs: (0.0, 0.0),
    };
    let t0 = std::time::Instant::now();
    let done = (|| -> anyhow::Result<(trend::TrendReport, LifeTruth)> {
        let (recs, truth) = generate(spec, rig, tick)?;
        let t1 = std::time::Instant::now();
        res.secs.0 = (t1 - t0).as_secs_f64();
        let recs = recordings(&recs, &truth);
        let checked = trend::TrendConfig {
            unit: spec.geometry.unit(),
            ..cfg.clone()
        }
        .check()?;
        let bearing = bearing_model::BearingSpec::parse(spec.geometry.bearing())?;
        let report =
            trend::analyse_with_progress(&recs, trend::TimeAxis::Seconds, &bearing, &checked, tick)
                .with_context(|| format!("{} seed {}", spec.geometry.name(), spec.seed))?;
        res.secs.1 = t1.elapsed().as_secs_f64();
        Ok((report, truth))
    })();
    match done {
        Ok((report, truth)) => {
            res.onset_index = truth.onset_index;
            res.load_steps = truth.load_step_indices.clone();
            res.gain_steps = truth.gain_step_indices.clone();
            res.outcomes = outcomes(&report, &truth);
            res.notes = report.notes.clone();
            (res, keep.then_some((report, truth)))
        }
        Err(e) => {
            res.error = Some(format!("{e:#}"));
            (res, None)
        }
    }
}

/// Check that the schedule's onsets all come after the baseline (the rule never looks there).
///
/// # Errors
/// One line when the earliest onset is within the baseline.
pub fn check_onsets_after_baseline(s: &Schedule, baseline_count: usize) -> anyhow::Result<()> {
    s.validate()?;
    let (lo, _) = s.onset_range();
    if lo <= baseline_count {
        anyhow::bail!(
            "the earliest onset (recording {lo}) must come after the {baseline_count} baseline recordings"
        );
    }
    Ok(())
}

/// Every run, in parallel (the runs and the recordings within them), with a progress bar.
/// Returns the results in spec order and the kept run's report and truth.
pub fn run_all(
    specs: &[RunSpec],
    cfg: &trend::TrendConfig,
    keep: Option<(Geometry, u64)>,
) -> anyhow::Result<(Vec<RunResult>, Option<Kept>)> {
    for s in specs {
        check_onsets_after_baseline(&s.schedule, cfg.baseline_count)?;
    }
    let rig = if specs.iter().any(|s| s.geometry == Geometry::Rig6205) {
        Some(calibrated_rig::cwru_rig().context("loading the calibrated rig")?)
    } else {
        None
    };
    let total: u64 = specs.iter().map(|s| 2 * s.schedule.recordings as u64).sum();
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} recordings generated + analysed, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let tick = || bar.inc(1);
    let out: Vec<(RunResult, Option<Kept>)> = specs
        .par_iter()
        .map(|s| {
            let k = keep == Some((s.geometry, s.seed));
            run_one(s, rig.as_ref(), cfg, k, &tick)
        })
        .collect();
    bar.finish_and_clear();
    let mut kept = None;
    let mut results = Vec::new();
    for (r, k) in out {
        if k.is_some() {
            kept = k;
        }
        results.push(r);
    }
    Ok((results, kept))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn met(index: usize, fault: &str) -> trend::RuleMet {
        trend::RuleMet {
            index,
            indicators: vec!["x".into()],
            fault: fault.into(),
            fault_basis: trend::alarm::BASIS_DIAGNOSIS.into(),
        }
    }

    #[test]
    fn bookkeeping_against_a_known_onset() {
        let inner = FaultLocation::Inner;
        // an onset before the truth is a false alarm; the detection is the rule restarted
        let o = outcome(
            "x",
            Some(met(12, "outer")),
            || Some(met(20, "inner")),
            15,
            inner,
        );
        assert_eq!(o.false_alarm, Some((12, "outer".into())));
        assert_eq!(o.detection, Some((20, "inner".into())));
        assert_eq!(o.delay, Some(5));
        assert_eq!(o.fault, Some(FaultStatus::Right));
        // at the onset: no false alarm, delay 0; the restart is not asked
        let o = outcome("x", Some(met(15, "ball")), || panic!("asked"), 15, inner);
        assert_eq!(o.false_alarm, None);
        assert_eq!((o.delay, o.fault), (Some(0), Some(FaultStatus::Wrong)));
        // never: missed
        let o = outcome("x", None, || panic!("asked"), 15, inner);
        assert_eq!((o.false_alarm, o.detection, o.delay), (None, None, None));
        // a false alarm and nothing after: missed
        let o = outcome("x", Some(met(11, "normal")), || None, 15, inner);
        assert_eq!(o.false_alarm, Some((11, "normal".into())));
        assert_eq!((o.detection, o.delay), (None, None));
        assert_eq!(fault_status("uncertain", inner), FaultStatus::None);
        assert_eq!(fault_status("inner+outer", inner), FaultStatus::Wrong);
    }

    #[test]
    fn the_design_is_fixed() {
        assert_eq!(SEEDS.count(), 20);
        for g in GEOMETRIES {
            for loc in FaultLocation::ALL {
                assert!(
                    SEEDS.clone().any(|s| location_of(s) == loc),
                    "{g:?} {loc:?}"
                );
            }
        }
        // the default schedule's onsets all come after the default baseline
        check_onsets_after_baseline(
            &Schedule::default(),
            trend::TrendConfig::default().baseline_count,
        )
        .unwrap();
    }

    /// A small run on each generic machine: the harness's counts agree with the report's own
    /// onsets and the truth (a false alarm iff an onset precedes it, delay = alarm − onset).
    #[test]
    fn small_runs_are_counted_against_their_truth() {
        let schedule = Schedule {
            recordings: 24,
            duration_s: 0.5,
            onset_fraction: (0.5, 0.7),
            ..Schedule::default()
        };
        let specs: Vec<RunSpec> = [(Geometry::Uc204, 1), (Geometry::B6308, 3)]
            .into_iter()
            .map(|(geometry, seed)| RunSpec {
                geometry,
                seed,
                schedule,
            })
            .collect();
        let cfg = trend::TrendConfig {
            observers: false,
            ..Default::default()
        };
        for s in &specs {
            let (res, kept) = run_one(s, None, &cfg, true, &|| {});
            assert!(res.error.is_none(), "{:?}", res.error);
            let (report, truth) = kept.expect("kept");
            assert_eq!(res.onset_index, truth.onset_index);
            assert!(truth.onset_index > 10);
            for (j, o) in res
                .outcomes
                .iter()
                .take(report.indicators.len())
                .enumerate()
            {
                assert_eq!(o.indicator, report.indicators[j].name);
                let on = report.onsets[j].as_ref();
                assert_eq!(
                    o.false_alarm.is_some(),
                    on.is_some_and(|on| on.index < truth.onset_index),
                    "{o:?}"
                );
                if let (Some(on), None) = (on, &o.false_alarm) {
                    assert_eq!(o.delay, Some(on.index - truth.onset_index));
                    assert_eq!(o.detection.as_ref().map(|d| &d.1), Some(&on.fault));
                }
                if let Some(d) = &o.detection {
                    assert!(d.0 >= truth.onset_index);
                }
            }
            let c = res
                .outcomes
                .iter()
                .find(|o| o.indicator == COMBINED)
                .expect("combined");
            let a = report.alarm.as_ref();
            assert_eq!(
                c.false_alarm.is_some(),
                a.is_some_and(|a| a.index < truth.onset_index)
            );
            if let (Some(a), None) = (a, &c.false_alarm) {
                assert_eq!(c.delay, Some(a.index - truth.onset_index));
            }
        }
    }
}
