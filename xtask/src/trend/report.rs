//! The validation's tables: per indicator (false alarms before the onset with Clopper–Pearson
//! intervals, detections, delays, the fault named), the combined alarm per geometry and per
//! location, and the paired comparison of the observers' residual against the raw signal.

use std::collections::BTreeMap;

use serde::Serialize;

use super::validate::{COMBINED, COMBINED_ALL, FaultStatus, GEOMETRIES, RunResult};
use crate::false_alarm::report::clopper_pearson;

/// Quantile `q` of sorted values by linear interpolation (`None` when empty).
pub fn quantile(sorted: &[f64], q: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let h = q * (sorted.len() - 1) as f64;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    Some(sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo]))
}

/// One row of a summary table: an indicator's (or a group's) outcomes over the runs.
#[derive(Debug, Clone, Serialize)]
pub struct IndicatorSummary {
    /// Indicator, or the group's name.
    pub name: String,
    /// Runs with this indicator.
    pub runs: usize,
    /// Runs without a false alarm before the onset.
    pub no_false_alarm: usize,
    /// Its 95 % Clopper–Pearson interval, as a share.
    pub no_false_alarm_ci: (f64, f64),
    /// Runs detected after the onset.
    pub detected: usize,
    /// Delay quartiles over the detected runs, recordings (Q1, median, Q3).
    pub delay_q: Option<(f64, f64, f64)>,
    /// Minutes per recording (the schedule's interval).
    pub interval_min: f64,
    /// Detections naming the right fault, a wrong one, none.
    pub right: usize,
    /// See `right`.
    pub wrong: usize,
    /// See `right`.
    pub none: usize,
}

/// The summary of `name`'s outcomes over `runs`.
pub fn indicator_summary(name: &str, label: &str, runs: &[&RunResult]) -> IndicatorSummary {
    let outs: Vec<_> = runs
        .iter()
        .filter_map(|r| r.outcomes.iter().find(|o| o.indicator == name))
        .collect();
    let n = outs.len();
    let nfa = outs.iter().filter(|o| o.false_alarm.is_none()).count();
    let mut d: Vec<f64> = outs
        .iter()
        .filter_map(|o| o.delay.map(|d| d as f64))
        .collect();
    d.sort_by(f64::total_cmp);
    let q = (!d.is_empty()).then(|| {
        (
            quantile(&d, 0.25).unwrap_or(0.0),
            quantile(&d, 0.5).unwrap_or(0.0),
            quantile(&d, 0.75).unwrap_or(0.0),
        )
    });
    let count = |s: FaultStatus| outs.iter().filter(|o| o.fault == Some(s)).count();
    IndicatorSummary {
        name: label.to_string(),
        runs: n,
        no_false_alarm: nfa,
        no_false_alarm_ci: clopper_pearson(nfa, n),
        detected: d.len(),
        delay_q: q,
        interval_min: runs.first().map_or(0.0, |r| r.interval_min),
        right: count(FaultStatus::Right),
        wrong: count(FaultStatus::Wrong),
        none: count(FaultStatus::None),
    }
}

fn pct(k: usize, n: usize) -> String {
    if n == 0 {
        "—".into()
    } else {
        format!("{:.0} %", 100.0 * k as f64 / n as f64)
    }
}

fn fmt_q(q: Option<(f64, f64, f64)>, scale: f64) -> String {
    match q {
        Some((a, m, b)) => format!("{} [{}–{}]", m * scale, a * scale, b * scale),
        None => "—".into(),
    }
}

/// A Markdown table of lines.
pub fn table(first: &str, lines: &[IndicatorSummary]) -> String {
    let mut s = format!(
        "| {first} | no false alarm before onset | % | 95 % CI | detected after onset | delay, recordings: median [Q1–Q3] | delay, min | right fault at alarm | wrong | none |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for l in lines {
        s.push_str(&format!(
            "| {} | {}/{} | {} | {:.0}–{:.0} % | {}/{} | {} | {} | {}/{} | {} | {} |\n",
            l.name,
            l.no_false_alarm,
            l.runs,
            pct(l.no_false_alarm, l.runs),
            100.0 * l.no_false_alarm_ci.0,
            100.0 * l.no_false_alarm_ci.1,
            l.detected,
            l.runs,
            fmt_q(l.delay_q, 1.0),
            fmt_q(l.delay_q, l.interval_min),
            l.right,
            l.detected,
            l.wrong,
            l.none
        ));
    }
    s
}

/// The indicator names in column order (the first successful run's, then any other).
pub fn indicator_names(runs: &[RunResult]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for r in runs {
        for o in &r.outcomes {
            if o.indicator != COMBINED
                && o.indicator != COMBINED_ALL
                && !names.contains(&o.indicator)
            {
                names.push(o.indicator.clone());
            }
        }
    }
    names.push(COMBINED.into());
    names.push(COMBINED_ALL.into());
    names
}

/// One paired comparison: an observer column against a raw one, over the runs with both.
#[derive(Debug, Clone, Serialize)]
pub struct Paired {
    /// Observer column.
    pub observer: String,
    /// Raw column.
    pub against: String,
    /// Runs with both columns.
    pub runs: usize,
    /// Both detected: the observer earlier, at the same recording, later.
    pub earlier: usize,
    /// See `earlier`.
    pub same: usize,
    /// See `earlier`.
    pub later: usize,
    /// Only the observer detected; only the raw one; neither.
    pub only_observer: usize,
    /// See `only_observer`.
    pub only_raw: usize,
    /// See `only_observer`.
    pub neither: usize,
    /// Median of (observer delay − raw delay) over the runs where both detected, recordings.
    pub median_difference: Option<f64>,
}

/// The paired comparison of `observer` against `against`.
pub fn paired(runs: &[RunResult], observer: &str, against: &str) -> Paired {
    let mut p = Paired {
        observer: observer.into(),
        against: against.into(),
        runs: 0,
        earlier: 0,
        same: 0,
        later: 0,
        only_observer: 0,
        only_raw: 0,
        neither: 0,
        median_difference: None,
    };
    let mut diffs = Vec::new();
    for r in runs {
        let find = |n: &str| r.outcomes.iter().find(|o| o.indicator == n);
        let (Some(a), Some(b)) = (find(observer), find(against)) else {
            continue;
        };
        p.runs += 1;
        match (a.delay, b.delay) {
            (Some(x), Some(y)) => {
                let d = x as f64 - y as f64;
                diffs.push(d);
                match x.cmp(&y) {
                    std::cmp::Ordering::Less => p.earlier += 1,
                    std::cmp::Ordering::Equal => p.same += 1,
                    std::cmp::Ordering::Greater => p.later += 1,
                }
            }
            (Some(_), None) => p.only_observer += 1,
            (None, Some(_)) => p.only_raw += 1,
            (None, None) => p.neither += 1,
        }
    }
    diffs.sort_by(f64::total_cmp);
    p.median_difference = quantile(&diffs, 0.5);
    p
}

/// The paired table in Markdown.
pub fn paired_table(ps: &[Paired]) -> String {
    let mut s = String::from(
        "| observer indicator | against | runs | observer earlier | same | later | only observer detected | only raw detected | neither | median (observer − raw), recordings |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for p in ps {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            p.observer,
            p.against,
            p.runs,
            p.earlier,
            p.same,
            p.later,
            p.only_observer,
            p.only_raw,
            p.neither,
            p.median_difference
                .map_or("—".to_string(), |d| format!("{d:+}"))
        ));
    }
    s
}

/// Everything the report holds.
#[derive(Debug, Clone, Serialize)]
pub struct Tables {
    /// Per indicator and the combined alarm, every run.
    pub per_indicator: Vec<IndicatorSummary>,
    /// The combined alarm per geometry.
    pub combined_by_geometry: Vec<IndicatorSummary>,
    /// The combined alarm per location.
    pub combined_by_location: Vec<IndicatorSummary>,
    /// Per geometry, every indicator.
    pub per_geometry_indicator: BTreeMap<String, Vec<IndicatorSummary>>,
    /// Observers against `signal_ms` and `kurtosis`.
    pub paired: Vec<Paired>,
}

/// Build the tables.
pub fn tables(runs: &[RunResult]) -> Tables {
    let ok: Vec<&RunResult> = runs.iter().filter(|r| r.error.is_none()).collect();
    let names = indicator_names(runs);
    let per_indicator = names.iter().map(|n| indicator_summary(n, n, &ok)).collect();
    let mut combined_by_geometry = Vec::new();
    let mut per_geometry_indicator = BTreeMap::new();
    for g in GEOMETRIES {
        let sel: Vec<&RunResult> = ok.iter().copied().filter(|r| r.geometry == g).collect();
        if sel.is_empty() {
            continue;
        }
        combined_by_geometry.push(indicator_summary(COMBINED, g.name(), &sel));
        per_geometry_indicator.insert(
            g.name().to_string(),
            names
                .iter()
                .map(|n| indicator_summary(n, n, &sel))
                .collect(),
        );
    }
    let combined_by_location = bearing_model::FaultLocation::ALL
        .iter()
        .filter_map(|l| {
            let sel: Vec<&RunResult> = ok
                .iter()
                .copied()
                .filter(|r| r.location == l.name())
                .collect();
            (!sel.is_empty()).then(|| indicator_summary(COMBINED, l.name(), &sel))
        })
        .collect();
    let mut paired_rows = Vec::new();
    for n in names
        .iter()
        .filter(|n| n.ends_with("_ms") && n.as_str() != "signal_ms" || n.ends_with("_ratio"))
    {
        for against in ["signal_ms", "kurtosis"] {
            paired_rows.push(paired(runs, n, against));
        }
    }
    Tables {
        per_indicator,
        combined_by_geometry,
        combined_by_location,
        per_geometry_indicator,
        paired: paired_rows,
    }
}

/// `validation.csv`: one row per run and indicator.
pub fn csv(runs: &[RunResult]) -> String {
    let mut s = String::from(
        "geometry,seed,location,onset_index,recordings,interval_min,indicator,false_alarm,false_alarm_index,false_alarm_fault,detected,alarm_index,delay_recordings,delay_min,fault_named,fault_status,error\n",
    );
    for r in runs {
        if let Some(e) = &r.error {
            s.push_str(&format!(
                "{},{},{},,{},{},,,,,,,,,,,\"{}\"\n",
                r.geometry.name(),
                r.seed,
                r.location,
                r.recordings,
                r.interval_min,
                e.replace('"', "'")
            ));
            continue;
        }
        for o in &r.outcomes {
            let status = o.fault.map_or(String::new(), |f| {
                serde_json::to_value(f)
                    .ok()
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_default()
            });
            s.push_str(&format!(
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},\n",
                r.geometry.name(),
                r.seed,
                r.location,
                r.onset_index,
                r.recordings,
                r.interval_min,
                o.indicator,
                u8::from(o.false_alarm.is_some()),
                o.false_alarm
                    .as_ref()
                    .map_or(String::new(), |f| f.0.to_string()),
                o.false_alarm
                    .as_ref()
                    .map_or(String::new(), |f| f.1.clone()),
                u8::from(o.detection.is_some()),
                o.detection
                    .as_ref()
                    .map_or(String::new(), |d| d.0.to_string()),
                o.delay.map_or(String::new(), |d| d.to_string()),
                o.delay
                    .map_or(String::new(), |d| format!("{}", d as f64 * r.interval_min)),
                o.detection.as_ref().map_or(String::new(), |d| d.1.clone()),
                status
            ));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartiles() {
        let v = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(quantile(&v, 0.5), Some(2.5));
        assert_eq!(quantile(&v, 0.25), Some(1.75));
        assert_eq!(quantile(&[], 0.5), None);
    }
}
