//! What the per-rig summary counts, the peer's committed types beside ours, and the false-alarm
//! report's headline: counting only, no algorithm.

use std::collections::BTreeMap;
use std::path::Path;

use diagnosis::{Diagnosis, Hypothesis, Significance};
use hybrid_fdd_cli::diagnose::Outcome;
use serde::Serialize;

/// The peer's type of one record (`results/diagnosis/peer_openconmo.csv`).
#[derive(Debug, Clone)]
pub struct PeerRow {
    /// The peer file's label (checked against ours).
    pub label: String,
    /// DRS → fast kurtogram band → squared envelope spectrum: the argmax of three scores.
    pub peer_type: String,
    /// Cepstrum pre-whitening → full-band squared envelope spectrum, same rule.
    pub cpw_type: Option<String>,
}

/// The peer's rows by (rig, record): CWRU records by number, MFPT and UESTC by file stem.
pub type Peer = BTreeMap<(String, String), PeerRow>;

/// Read the peer's CSV; `Ok(None)` when the file is absent.
///
/// # Errors
/// A file that is there but unreadable, or without the columns named.
pub fn read_peer(path: &Path) -> anyhow::Result<Option<Peer>> {
    if !path.is_file() {
        return Ok(None);
    }
    let mut r = csv::Reader::from_path(path)?;
    let h = r.headers()?.clone();
    let col = |name: &str| {
        h.iter()
            .position(|c| c == name)
            .ok_or_else(|| anyhow::anyhow!("{}: no column `{name}`", path.display()))
    };
    let (rig, record, label, peer, cpw) = (
        col("rig")?,
        col("record")?,
        col("label")?,
        col("peer_type")?,
        col("cpw_type").ok(),
    );
    let mut out = Peer::new();
    for rec in r.records() {
        let rec = rec?;
        let get = |i: usize| rec.get(i).unwrap_or_default().to_string();
        out.insert(
            (get(rig), get(record)),
            PeerRow {
                label: get(label),
                peer_type: get(peer),
                cpw_type: cpw.map(get).filter(|s| !s.is_empty()),
            },
        );
    }
    Ok(Some(out))
}

/// The hypothesis with the smallest `p_healthy` (ties: the larger modulation depth), and its
/// reading: what a rule that must always name a fault would name.
pub fn most_significant(d: &Diagnosis) -> Option<(Hypothesis, &Significance)> {
    d.evidence
        .iter()
        .filter_map(|e| e.significance.as_ref().map(|s| (e.hypothesis, s)))
        .min_by(|a, b| {
            a.1.p_healthy
                .total_cmp(&b.1.p_healthy)
                .then(b.1.modulation_depth.total_cmp(&a.1.modulation_depth))
        })
}

/// One diagnosis of a labelled recording, as the summary counts it.
pub struct Scored<'a> {
    /// `normal`, `inner`, `outer`, `ball`.
    pub label: &'a str,
    /// Our diagnosis (or its error).
    pub outcome: &'a Result<Outcome, String>,
    /// The peer's row for this recording, when there is one.
    pub peer: Option<&'a PeerRow>,
}

/// Counts over a set of recordings (see the README's column definitions).
#[derive(Debug, Default, Clone, Serialize)]
pub struct Tally {
    /// Recordings.
    pub records: usize,
    /// Verdict == label.
    pub verdicts_right: usize,
    /// Recordings labelled normal.
    pub healthy: usize,
    /// … whose verdict is `normal`.
    pub healthy_right: usize,
    /// … whose verdict is not `normal` (and not an error): false alarms.
    pub false_alarms: usize,
    /// Recordings labelled with a fault.
    pub faulty: usize,
    /// … whose verdict is not `normal` (and not an error).
    pub detected: usize,
    /// … whose verdict is the label exactly.
    pub typed_right: usize,
    /// … whose verdict is `uncertain`.
    pub uncertain: usize,
    /// … `uncertain` with the label among the candidates.
    pub uncertain_label_named: usize,
    /// … whose most significant hypothesis (smallest `p_healthy`, ties by larger modulation
    /// depth) is the label, whatever the verdict.
    pub typed_by_most_significant: usize,
    /// Healthy recordings called `normal` although their `p_healthy` is at most α: a
    /// hypothesis significant by its lines but not deep enough, or read at a declared speed no
    /// comb confirmed (at α/2).
    pub healthy_normal_p_within_alpha: usize,
    /// The same among the faulty recordings.
    pub faulty_normal_p_within_alpha: usize,
    /// Diagnoses that failed (an error, counted in no other verdict column).
    pub errors: usize,
    /// Faulty recordings the peer typed.
    pub peer_faulty: usize,
    /// … typed right by the peer (DRS → kurtogram → SES).
    pub peer_typed_right: usize,
    /// … typed right by the peer's cepstrum-pre-whitened variant.
    pub peer_cpw_typed_right: usize,
}

impl Tally {
    /// Count `items`.
    pub fn of<'a>(items: impl IntoIterator<Item = Scored<'a>>) -> Self {
        let mut t = Self::default();
        for s in items {
            t.records += 1;
            let healthy = s.label == "normal";
            if healthy {
                t.healthy += 1;
            } else {
                t.faulty += 1;
            }
            match s.outcome {
                Err(_) => t.errors += 1,
                Ok(o) => {
                    let d = &o.diagnosis;
                    let v = d.verdict.as_str();
                    let held = v == "normal" && d.p_healthy <= d.false_alarm;
                    if healthy {
                        t.healthy_normal_p_within_alpha += usize::from(held);
                    } else {
                        t.faulty_normal_p_within_alpha += usize::from(held);
                    }
                    t.verdicts_right += usize::from(v == s.label);
                    if healthy {
                        t.healthy_right += usize::from(v == "normal");
                        t.false_alarms += usize::from(v != "normal");
                    } else {
                        t.detected += usize::from(v != "normal");
                        t.typed_right += usize::from(v == s.label);
                        if v == "uncertain" {
                            t.uncertain += 1;
                            t.uncertain_label_named +=
                                usize::from(d.candidates.iter().any(|c| c.name() == s.label));
                        }
                        t.typed_by_most_significant += usize::from(
                            most_significant(d).is_some_and(|(h, _)| h.name() == s.label),
                        );
                    }
                }
            }
            if let (false, Some(p)) = (healthy, s.peer) {
                t.peer_faulty += 1;
                t.peer_typed_right += usize::from(p.peer_type == s.label);
                t.peer_cpw_typed_right += usize::from(p.cpw_type.as_deref() == Some(s.label));
            }
        }
        t
    }
}

/// `a/n`, or `–` when `n` is 0.
pub fn frac(a: usize, n: usize) -> String {
    if n == 0 {
        "–".into()
    } else {
        format!("{a}/{n}")
    }
}

/// `a/n (p %)`, or `–` when `n` is 0.
pub fn frac_pct(a: usize, n: usize) -> String {
    if n == 0 {
        "–".into()
    } else {
        format!("{a}/{n} ({:.0} %)", 100.0 * a as f64 / n as f64)
    }
}

/// The false-alarm report's headline, from `false_alarm.json`'s records: per kind (simulated
/// healthy, noise-only, real healthy, faulty), recordings, errors, and verdicts other than
/// `normal` (false alarms on the healthy kinds, detections on the faulty) and, for the faulty,
/// the fault typed exactly.
#[derive(Debug, Default, Clone, Serialize)]
pub struct FalseAlarmHeadline {
    /// Per kind: (recordings, errors, verdict ≠ normal, typed right).
    pub kinds: BTreeMap<String, [usize; 4]>,
}

/// Read the headline from the records of every file of `paths` that is present
/// (`false_alarm.json`, `false_alarm_short.json`); `None` when the first is absent or any present
/// one is not the report's shape.
pub fn false_alarm_headline(paths: &[&Path]) -> Option<FalseAlarmHeadline> {
    let mut h = FalseAlarmHeadline::default();
    for (i, path) in paths.iter().enumerate() {
        let Ok(text) = std::fs::read_to_string(path) else {
            if i == 0 {
                return None;
            }
            continue;
        };
        let v: serde_json::Value = serde_json::from_str(&text).ok()?;
        let records = v.get("records")?.as_array()?;
        count_records(&mut h, records)?;
        // the speed-sweep design's machines diagnosed again with a tachometer: each verdict
        // counted under its record's kind, `… with a tachometer`
        if let Some(again) = v.get("with_tachometer").and_then(|a| a.as_array()) {
            let by_id: BTreeMap<&str, &serde_json::Value> = records
                .iter()
                .filter_map(|r| Some((r.get("id")?.as_str()?, r)))
                .collect();
            let mut rows = Vec::new();
            for a in again {
                let r = by_id.get(a.get("id")?.as_str()?)?;
                rows.push(serde_json::json!({
                    "kind": format!("{} with a tachometer", r.get("kind")?.as_str()?),
                    "verdict": a.get("verdict")?,
                    "fault": r.get("fault"),
                }));
            }
            count_records(&mut h, &rows)?;
        }
    }
    Some(h)
}

/// Add `records` (the report's rows) to the headline `h`.
fn count_records(h: &mut FalseAlarmHeadline, records: &[serde_json::Value]) -> Option<()> {
    for r in records {
        let kind = r.get("kind")?.as_str()?.to_string();
        let verdict = r.get("verdict")?.as_str()?;
        let fault = r.get("fault").and_then(|f| f.as_str());
        let c = h.kinds.entry(kind).or_default();
        c[0] += 1;
        if verdict == "error" {
            c[1] += 1;
        } else if verdict != "normal" {
            c[2] += 1;
        }
        c[3] += usize::from(fault.is_some_and(|f| f == verdict));
    }
    Some(())
}
