//! Thresholds from the baseline recordings' own statistics, the m-of-n onset rule, the fault
//! named at an alarm, and the severity trend after it.

use crate::config::{MIN_EVIDENCE_SPREAD, MIN_LOG_SPREAD};

/// How an indicator's values are compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Domain {
    /// log10 of the value (positive indicators whose scatter is multiplicative).
    Log10,
    /// The value itself (the diagnosis' evidence, already −log10 of a probability).
    Linear,
}

/// One indicator's threshold: median + k·σ̂ of the baseline values in its domain,
/// σ̂ = max(1.4826·MAD, floor).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Threshold {
    /// Domain the statistics are taken in.
    pub domain: Domain,
    /// Median of the baseline values (in the indicator's unit).
    pub median: f64,
    /// σ̂ in the domain (decades for [`Domain::Log10`]).
    pub spread: f64,
    /// Whether σ̂ is the floor (the baselines' MAD was smaller).
    pub spread_floored: bool,
    /// k.
    pub k: f64,
    /// The threshold, in the indicator's unit.
    pub value: f64,
    /// Baseline values it was computed from.
    pub baselines: usize,
}

/// Median of finite values (`None` when empty).
pub fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let m = s.len() / 2;
    Some(if s.len() % 2 == 1 {
        s[m]
    } else {
        0.5 * (s[m - 1] + s[m])
    })
}

/// The threshold of one indicator from its baseline values (`None` entries — not computed —
/// and non-positive values in the log domain are left out); `None` when fewer than `min` remain.
pub fn threshold(
    baseline: &[Option<f64>],
    domain: Domain,
    k: f64,
    min: usize,
) -> Option<Threshold> {
    let t: Vec<f64> = baseline
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .filter_map(|&v| match domain {
            Domain::Log10 => (v > 0.0).then(|| v.log10()),
            Domain::Linear => Some(v),
        })
        .collect();
    if t.len() < min.max(1) {
        return None;
    }
    let med = median(&t)?;
    let dev: Vec<f64> = t.iter().map(|v| (v - med).abs()).collect();
    let mad = 1.4826 * median(&dev)?;
    let floor = match domain {
        Domain::Log10 => MIN_LOG_SPREAD,
        Domain::Linear => MIN_EVIDENCE_SPREAD,
    };
    let spread = mad.max(floor);
    let back = |v: f64| match domain {
        Domain::Log10 => 10f64.powf(v),
        Domain::Linear => v,
    };
    Some(Threshold {
        domain,
        median: back(med),
        spread,
        spread_floored: mad < floor,
        k,
        value: back(med + k * spread),
        baselines: t.len(),
    })
}

/// The first recording at which `above` holds in at least `m` of the last `n` recordings, the
/// window starting no earlier than `start` (the first recording after the baseline): the index
/// where the rule is met (the m-th exceedance) and the window's first exceedance.
pub fn m_of_n(above: &[bool], start: usize, m: usize, n: usize) -> Option<(usize, usize)> {
    (start..above.len()).find_map(|j| {
        let lo = start.max((j + 1).saturating_sub(n));
        let window = &above[lo..=j];
        (above[j] && window.iter().filter(|&&a| a).count() >= m).then(|| {
            let first = lo + window.iter().position(|&a| a).unwrap_or(0);
            (j, first)
        })
    })
}

/// The fault the diagnosis names among `verdicts` (those of the recordings that fired): the
/// most frequent verdict that is neither `normal` nor `uncertain` (ties: the latest), else
/// `uncertain` if any, else `normal`; `None` entries (not diagnosed) are skipped, and
/// `not diagnosed` when all are `None`.
pub fn fault_named(verdicts: &[Option<&str>]) -> String {
    if verdicts.iter().all(Option::is_none) {
        return "not diagnosed".into();
    }
    let mut best: Option<(&str, usize, usize)> = None;
    for (i, v) in verdicts.iter().enumerate() {
        let Some(v) = *v else { continue };
        if v == "normal" || v == "uncertain" {
            continue;
        }
        let c = verdicts.iter().filter(|w| **w == Some(v)).count();
        if best.is_none_or(|(_, bc, bi)| c > bc || (c == bc && i > bi)) {
            best = Some((v, c, i));
        }
    }
    match best {
        Some((v, _, _)) => v.to_string(),
        None if verdicts.contains(&Some("uncertain")) => "uncertain".into(),
        None => "normal".into(),
    }
}

/// How the fault at an onset or alarm was named.
pub const BASIS_DIAGNOSIS: &str = "diagnosis";
/// See [`BASIS_DIAGNOSIS`]: the evidence's own trend named it (the diagnosis said `normal` or
/// `uncertain` on every recording of the window).
pub const BASIS_EVIDENCE_TREND: &str = "evidence trend";

/// The fault named over an onset's window: the diagnosis' ([`fault_named`] over `verdicts`,
/// those of the window's recordings that fired); when that is `normal` or `uncertain`, the
/// hypothesis whose evidence indicator stands above its own baseline threshold on the most
/// recordings of the window (`evidence`: per hypothesis, its above-threshold flags over the
/// window and its value at the onset's recording; ties: the larger value), if any stands above
/// at all. Returns the name and its basis ([`BASIS_DIAGNOSIS`] or [`BASIS_EVIDENCE_TREND`]).
///
/// The diagnosis tests each recording against a healthy machine in general (a false-alarm
/// probability per recording); the trend compares each hypothesis' evidence with this machine's
/// own baseline, which sees a fault's lines rising while they are still too weak for a verdict.
pub fn fault_named_with_trend(
    verdicts: &[Option<&str>],
    evidence: &[(&str, Vec<bool>, Option<f64>)],
) -> (String, &'static str) {
    let named = fault_named(verdicts);
    if named != "normal" && named != "uncertain" {
        return (named, BASIS_DIAGNOSIS);
    }
    let mut best: Option<(&str, usize, f64)> = None;
    for (h, flags, value) in evidence {
        let count = flags.iter().filter(|&&a| a).count();
        if count == 0 {
            continue;
        }
        let v = value.unwrap_or(f64::NEG_INFINITY);
        if best.is_none_or(|(_, bc, bv)| count > bc || (count == bc && v > bv)) {
            best = Some((h, count, v));
        }
    }
    match best {
        Some((h, _, _)) => (h.to_string(), BASIS_EVIDENCE_TREND),
        None => (named, BASIS_DIAGNOSIS),
    }
}

/// An indicator's trend after its alarm.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Severity {
    /// Least-squares slope of the (speed-normalised) indicator over time from the alarm on,
    /// indicator unit per `rate_unit` (`None` with fewer than two recordings).
    pub slope: Option<f64>,
    /// The slope's time unit (`h` or `recording`).
    pub rate_unit: String,
    /// Recordings the slope was fitted on.
    pub points: usize,
    /// The stated level, indicator unit.
    pub level: f64,
    /// What the level is (`10 x threshold`, `ISO 20816-3 zone C boundary …`).
    pub level_basis: String,
    /// The time the level was first reached or exceeded, on the run's axis (`None`: not yet).
    pub reached_at: Option<f64>,
    /// Time from the alarm to the level, in `rate_unit`: observed when reached, else the
    /// fitted line's crossing (`None`: not reached and the slope is not positive).
    pub time_to_level: Option<f64>,
    /// Whether `time_to_level` is extrapolated from the slope.
    pub extrapolated: bool,
}

/// Severity of `values` (with `times`, on an axis whose time unit is `per` of `rate_unit`:
/// hours = seconds × 1/3600) from index `from` on against `level`.
pub fn severity(
    times: &[f64],
    values: &[Option<f64>],
    from: usize,
    level: f64,
    level_basis: &str,
    rate_unit: (&str, f64),
) -> Severity {
    let (unit, per) = rate_unit;
    let t0 = times.get(from).copied().unwrap_or(0.0);
    let pts: Vec<(f64, f64)> = times
        .iter()
        .zip(values)
        .skip(from)
        .filter_map(|(&t, v)| v.filter(|v| v.is_finite()).map(|v| ((t - t0) * per, v)))
        .collect();
    let slope = (pts.len() >= 2)
        .then(|| {
            let n = pts.len() as f64;
            let mt = pts.iter().map(|p| p.0).sum::<f64>() / n;
            let mv = pts.iter().map(|p| p.1).sum::<f64>() / n;
            let sxx: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
            let sxy: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - mv)).sum();
            (sxx > 0.0).then(|| (sxy / sxx, mv - sxy / sxx * mt))
        })
        .flatten();
    let reached = times
        .iter()
        .zip(values)
        .skip(from)
        .find(|(_, v)| v.is_some_and(|v| v >= level))
        .map(|(&t, _)| t);
    let (time_to_level, extrapolated) = match (reached, slope) {
        (Some(t), _) => (Some((t - t0) * per), false),
        (None, Some((a, b))) if a > 0.0 => (Some((level - b) / a), true),
        _ => (None, false),
    };
    Severity {
        slope: slope.map(|s| s.0),
        rate_unit: unit.to_string(),
        points: pts.len(),
        level,
        level_basis: level_basis.to_string(),
        reached_at: reached,
        time_to_level,
        extrapolated,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_evidence_trend_names_a_fault_only_when_the_diagnosis_does_not() {
        let ev = vec![
            ("inner", vec![false, true, false], Some(2.0)),
            ("outer", vec![true, true, true], Some(1.5)),
            ("ball", vec![false, false, false], Some(9.0)),
        ];
        // a verdict wins
        assert_eq!(
            fault_named_with_trend(&[Some("ball"), Some("normal")], &ev),
            ("ball".to_string(), BASIS_DIAGNOSIS)
        );
        // normal: the hypothesis above its baseline on most recordings
        assert_eq!(
            fault_named_with_trend(&[Some("normal"), Some("normal")], &ev),
            ("outer".to_string(), BASIS_EVIDENCE_TREND)
        );
        // ties: the larger evidence at the onset
        let tie = vec![
            ("inner", vec![true, false], Some(3.0)),
            ("outer", vec![false, true], Some(1.0)),
        ];
        assert_eq!(
            fault_named_with_trend(&[Some("uncertain")], &tie).0,
            "inner"
        );
        // no evidence above: the diagnosis' word stands
        let none = vec![("inner", vec![false], Some(5.0))];
        assert_eq!(
            fault_named_with_trend(&[Some("normal")], &none),
            ("normal".to_string(), BASIS_DIAGNOSIS)
        );
    }

    #[test]
    fn mad_threshold() {
        let b: Vec<Option<f64>> = [1.0, 2.0, 3.0, 4.0, 100.0]
            .iter()
            .map(|&v| Some(v))
            .collect();
        let t = threshold(&b, Domain::Linear, 3.0, 5).unwrap();
        assert_eq!(t.median, 3.0);
        // MAD = median(|[-2,-1,0,1,97]|) = 1, σ̂ = 1.4826
        assert!((t.value - (3.0 + 3.0 * 1.4826)).abs() < 1e-12);
        assert!(threshold(&b[..4], Domain::Linear, 3.0, 5).is_none());
        // identical baselines: the floor
        let same = vec![Some(2.0); 6];
        let t = threshold(&same, Domain::Log10, 5.0, 5).unwrap();
        assert!(t.spread_floored);
        assert!((t.value / 2.0 - 10f64.powf(5.0 * MIN_LOG_SPREAD)).abs() < 1e-12);
    }

    #[test]
    fn m_of_n_rule() {
        let a = [true, true, true, false, true, false, true, true, false];
        // the baseline 0..3 never counts
        assert_eq!(m_of_n(&a, 3, 3, 4), Some((7, 4)));
        assert_eq!(m_of_n(&a[..7], 3, 3, 4), None);
        assert_eq!(m_of_n(&a, 3, 2, 4), Some((6, 4)));
        assert_eq!(m_of_n(&a, 3, 1, 1), Some((4, 4)));
        assert_eq!(m_of_n(&[false; 5], 0, 1, 1), None);
    }

    #[test]
    fn fault_naming() {
        assert_eq!(
            fault_named(&[Some("normal"), Some("outer"), Some("inner"), Some("outer")]),
            "outer"
        );
        assert_eq!(fault_named(&[Some("inner"), Some("outer")]), "outer");
        assert_eq!(fault_named(&[Some("normal"), None]), "normal");
        assert_eq!(
            fault_named(&[Some("uncertain"), Some("normal")]),
            "uncertain"
        );
    }

    #[test]
    fn severity_slope_and_level() {
        let t = [0.0, 3600.0, 7200.0, 10_800.0];
        let v = [Some(1.0), Some(2.0), Some(3.0), Some(4.0)];
        let s = severity(&t, &v, 1, 10.0, "10 x threshold", ("h", 1.0 / 3600.0));
        assert!((s.slope.unwrap() - 1.0).abs() < 1e-12);
        assert!(s.extrapolated);
        // line 2 + 1·h reaches 10 after 8 h from the alarm
        assert!((s.time_to_level.unwrap() - 8.0).abs() < 1e-9);
        let s = severity(&t, &v, 1, 3.0, "x", ("h", 1.0 / 3600.0));
        assert_eq!(s.reached_at, Some(7200.0));
        assert_eq!(s.time_to_level, Some(1.0));
        assert!(!s.extrapolated);
    }
}
