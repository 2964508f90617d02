//! `cargo xtask trend --staged`: the staged real sequences of issue 57 part 5 — **staged
//! sequences, not lives**: a healthy recording cut in segments as the baseline, then faulty
//! recordings of the same machine as if they came later. Run through the `hybrid-fdd trend`
//! command itself (`hybrid_fdd_cli::trend::run` on an index CSV), whose outputs land in
//! `results/trend/staged/<name>/`.

use std::path::{Path, PathBuf};

use anyhow::Context as _;

/// The label every staged output carries.
pub const LABEL: &str = "staged sequence, not a life";

/// One segment of a file: its path relative to the data directory, start and duration, s.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// Path under the data directory (`cwru/normal/97.mat`).
    pub rel_path: String,
    /// Start, s.
    pub start_s: f64,
    /// Duration, s.
    pub duration_s: f64,
}

/// One staged sequence.
#[derive(Debug, Clone, PartialEq)]
pub struct Staged {
    /// Directory name under `results/trend/staged/`.
    pub name: String,
    /// What it is, in words.
    pub description: String,
    /// Bearing designation.
    pub bearing: String,
    /// Declared speed, rpm (`None`: the file's stored speed).
    pub rpm: Option<f64>,
    /// Baseline recordings (the healthy segments).
    pub baseline_count: usize,
    /// Decimate to this rate, Hz.
    pub decimate_to: Option<f64>,
    /// The fault location of the faulty segments.
    pub location: String,
    /// The segments, in order.
    pub segments: Vec<Segment>,
}

fn segs(rel: &str, n: usize, dur: f64) -> Vec<Segment> {
    (0..n)
        .map(|i| Segment {
            rel_path: rel.to_string(),
            start_s: i as f64 * dur,
            duration_s: dur,
        })
        .collect()
}

/// CWRU's 12 kHz drive-end records at 0 hp: per location, 0.007, 0.014, 0.021 in.
pub const CWRU: [(&str, [u32; 3]); 3] = [
    ("inner", [105, 169, 209]),
    ("ball", [118, 185, 222]),
    ("outer", [130, 197, 234]),
];
/// UESTC's set speeds, rpm.
pub const UESTC_RPM: [u32; 4] = [800, 1000, 1200, 1400];
/// UESTC's fault codes and locations.
pub const UESTC_FAULTS: [(&str, &str); 3] = [("I", "inner"), ("O", "outer"), ("B", "ball")];

/// The sequences, every file checked present under `data`.
///
/// CWRU: 97.mat (48 kHz, decimated to 12 kHz) in five 1 s segments (its 5.08 s) as the
/// baseline — five, the trend crate's minimum — then per location the 0.007, 0.014, 0.021 in
/// records, three 1 s segments each (the records' stored speeds declared). UESTC (bearing
/// UC204-class, the set speed declared): per set speed, `N_<rpm>_1` and `_2` in six 2 s segments
/// each (12, the baseline), then the inner, outer and ball faults in turn, _1 and _2 of each in
/// two 2 s segments (one sequence per speed: the results stay small; the alarm and the fault
/// named concern the first fault, inner).
///
/// # Errors
/// A missing file: one line naming the sequence and the file.
pub fn sequences(data: &Path) -> anyhow::Result<Vec<Staged>> {
    let mut out = Vec::new();
    for (loc, records) in CWRU {
        let mut segments = segs("cwru/normal/97.mat", 5, 1.0);
        for r in records {
            segments.extend(segs(&format!("cwru/12k_drive_end/{r}.mat"), 3, 1.0));
        }
        out.push(Staged {
            name: format!("cwru_{loc}"),
            description: format!(
                "CWRU 12 kHz drive end, 0 hp: 97.mat (48 kHz decimated to 12 kHz) in five 1 s segments, then {loc} 0.007, 0.014, 0.021 in ({}), three 1 s segments each",
                records.map(|r| format!("{r}.mat")).join(", ")
            ),
            bearing: "6205".into(),
            rpm: None,
            baseline_count: 5,
            decimate_to: Some(12_000.0),
            location: loc.into(),
            segments,
        });
    }
    for rpm in UESTC_RPM {
        let mut segments = Vec::new();
        for k in 1..=2 {
            segments.extend(segs(&format!("uestc/Data/N_{rpm}/N_{rpm}_{k}.mat"), 6, 2.0));
        }
        for (code, _) in UESTC_FAULTS {
            for k in 1..=2 {
                segments.extend(segs(
                    &format!("uestc/Data/{code}_{rpm}/{code}_{rpm}_{k}.mat"),
                    2,
                    2.0,
                ));
            }
        }
        out.push(Staged {
            name: format!("uestc_{rpm}"),
            description: format!(
                "UESTC {rpm} rpm (set speed): N_{rpm}_1, N_{rpm}_2 in six 2 s segments each, then I_{rpm} (inner), O_{rpm} (outer), B_{rpm} (ball), _1 and _2 of each in two 2 s segments each"
            ),
            bearing: "UC204".into(),
            rpm: Some(rpm as f64),
            baseline_count: 12,
            decimate_to: None,
            location: "inner (then outer, ball)".into(),
            segments,
        });
    }
    for s in &out {
        for seg in &s.segments {
            let p = data.join(&seg.rel_path);
            if !p.is_file() {
                anyhow::bail!(
                    "staged sequence {}: {} is missing (the shared data directory {})",
                    s.name,
                    p.display(),
                    data.display()
                );
            }
        }
    }
    Ok(out)
}

/// Write the sequence's index CSV into `work` (beside symbolic links to the data files, so that
/// the recordings are named by their file names) and return its path.
fn index(s: &Staged, data: &Path, work: &Path) -> anyhow::Result<PathBuf> {
    std::fs::create_dir_all(work).with_context(|| format!("creating {}", work.display()))?;
    let mut csv = String::from("file,time,start_s,duration_s\n");
    for (i, seg) in s.segments.iter().enumerate() {
        let file = Path::new(&seg.rel_path)
            .file_name()
            .context("a file name")?
            .to_string_lossy()
            .into_owned();
        let link = work.join(&file);
        if !link.exists() {
            std::os::unix::fs::symlink(data.join(&seg.rel_path), &link)
                .with_context(|| format!("linking {}", link.display()))?;
        }
        csv.push_str(&format!(
            "{file},{},{},{}\n",
            i + 1,
            seg.start_s,
            seg.duration_s
        ));
    }
    let p = work.join("index.csv");
    std::fs::write(&p, csv)?;
    Ok(p)
}

/// One line of the staged table.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StagedLine {
    /// Sequence.
    pub name: String,
    /// Recordings, baseline.
    pub recordings: usize,
    /// See `recordings`.
    pub baseline: usize,
    /// The first faulty recording (0-based).
    pub first_faulty: usize,
    /// Alarm: recording index, name, indicators, fault named.
    pub alarm: Option<(usize, String, Vec<String>, String)>,
    /// The truth's location.
    pub location: String,
    /// Earliest onset among the observers' columns, among the raw signal's, among the evidence.
    pub first_observer: Option<usize>,
    /// See `first_observer`.
    pub first_raw: Option<usize>,
    /// See `first_observer`.
    pub first_evidence: Option<usize>,
    /// Onsets before the first faulty recording (false alarms on the healthy segments).
    pub onsets_before_fault: Vec<String>,
}

/// Whether an indicator is one of the observers' columns.
pub fn is_observer(name: &str) -> bool {
    trend::OBSERVERS
        .iter()
        .any(|m| name.starts_with(&format!("{}_", m.name().to_ascii_lowercase())))
}

fn line_of(s: &Staged, json: &serde_json::Value) -> StagedLine {
    let rows = json["rows"].as_array().map_or(0, Vec::len);
    let first_faulty = s
        .segments
        .iter()
        .position(|g| !g.rel_path.contains("normal/") && !g.rel_path.contains("/N_"))
        .unwrap_or(s.segments.len());
    let onsets: Vec<(String, usize)> = json["onsets"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|o| {
            Some((
                o["indicator"].as_str()?.to_string(),
                o["index"].as_u64()? as usize,
            ))
        })
        .collect();
    let first =
        |f: &dyn Fn(&str) -> bool| onsets.iter().filter(|(n, _)| f(n)).map(|(_, i)| *i).min();
    let alarm = json["alarm"].as_object().map(|a| {
        (
            a["index"].as_u64().unwrap_or(0) as usize,
            a["name"].as_str().unwrap_or("").to_string(),
            a["indicators"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|v| v.as_str().map(String::from))
                .collect(),
            a["fault"].as_str().unwrap_or("").to_string(),
        )
    });
    StagedLine {
        name: s.name.clone(),
        recordings: rows,
        baseline: s.baseline_count,
        first_faulty,
        alarm,
        location: s.location.clone(),
        first_observer: first(&|n| is_observer(n)),
        first_raw: first(&|n| !is_observer(n) && !n.starts_with("evidence_")),
        first_evidence: first(&|n| n.starts_with("evidence_")),
        onsets_before_fault: onsets
            .iter()
            .filter(|(_, i)| *i < first_faulty)
            .map(|(n, i)| format!("{n}@{i}"))
            .collect(),
    }
}

/// Run every sequence through the command into `out/<name>/`; returns the table's lines.
///
/// # Errors
/// Missing data (one line), the command's errors.
pub fn run_all(data: &Path, out: &Path, work: &Path) -> anyhow::Result<Vec<StagedLine>> {
    let seqs = sequences(data)?;
    let mut lines = Vec::new();
    for s in &seqs {
        eprintln!("staged sequence {} ({LABEL})", s.name);
        let idx = index(s, data, &work.join(&s.name))?;
        let report = out.join(&s.name);
        let args = hybrid_fdd_cli::trend::Args {
            input: None,
            index: Some(idx),
            bearing: s.bearing.clone(),
            rpm: s.rpm,
            fs: None,
            channel: None,
            baseline_count: s.baseline_count,
            machine_group: None,
            unit: None,
            k: trend::DEFAULT_K,
            alarm: format!("{}/{}", trend::DEFAULT_M, trend::DEFAULT_N),
            alarm_on: None,
            speed_exponent: trend::DEFAULT_SPEED_EXPONENT,
            decimate_to: s.decimate_to,
            no_observers: false,
            report: report.clone(),
        };
        hybrid_fdd_cli::trend::run(&args).with_context(|| format!("staged sequence {}", s.name))?;
        // the label, on the command's own summary, and the index relative to the data
        let sum = report.join("summary.md");
        let text = std::fs::read_to_string(&sum)?;
        std::fs::write(
            &sum,
            format!(
                "> **{LABEL}.** {}. The recordings are not one machine degrading over time: a healthy recording cut in segments, then faulty ones put after it. Index (paths under the shared data directory) in `index.csv`.\n\n{text}",
                s.description
            ),
        )?;
        let mut csv = String::from("file,time,start_s,duration_s\n");
        for (i, g) in s.segments.iter().enumerate() {
            csv.push_str(&format!(
                "{},{},{},{}\n",
                g.rel_path,
                i + 1,
                g.start_s,
                g.duration_s
            ));
        }
        std::fs::write(report.join("index.csv"), csv)?;
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(report.join("trend.json"))?)?;
        lines.push(line_of(s, &json));
    }
    Ok(lines)
}

/// The staged table in Markdown.
pub fn table(lines: &[StagedLine]) -> String {
    let mut s = String::from(
        "| sequence (staged, not a life) | recordings (baseline) | first faulty | alarm at | alarm on | fault named / truth | first onset: observers / raw / evidence | onsets on healthy segments |\n|---|---:|---:|---|---|---|---|---|\n",
    );
    let o = |v: Option<usize>| v.map_or("—".to_string(), |v| (v + 1).to_string());
    for l in lines {
        let (at, on, fault) = match &l.alarm {
            Some((i, n, ind, f)) => (
                format!("{} ({})", i + 1, n),
                ind.join(", "),
                format!("{f} / {}", l.location),
            ),
            None => ("no alarm".into(), "—".into(), format!("— / {}", l.location)),
        };
        s.push_str(&format!(
            "| {} | {} ({}) | {} | {at} | {on} | {fault} | {} / {} / {} | {} |\n",
            l.name,
            l.recordings,
            l.baseline,
            l.first_faulty + 1,
            o(l.first_observer),
            o(l.first_raw),
            o(l.first_evidence),
            if l.onsets_before_fault.is_empty() {
                "none".to_string()
            } else {
                l.onsets_before_fault.join(", ")
            }
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_data_is_a_one_line_error() {
        let e = sequences(Path::new("/nonexistent/hybrid-fdd-data")).unwrap_err();
        let msg = format!("{e:#}");
        assert!(!msg.contains('\n'), "{msg}");
        assert!(msg.contains("staged sequence cwru_inner"), "{msg}");
        assert!(msg.contains("97.mat is missing"), "{msg}");
    }

    #[test]
    fn the_shared_data_gives_every_sequence() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
        let data = match bearing_data::DataLocation::resolve(None, root)
            .ok()
            .and_then(|d| {
                d.require(bearing_data::ci_from_env())
                    .ok()
                    .flatten()
                    .map(Path::to_path_buf)
            }) {
            Some(d) => d,
            None => {
                assert!(
                    !bearing_data::ci_from_env(),
                    "CI=true but no data directory"
                );
                eprintln!("skipped: no data directory");
                return;
            }
        };
        let s = sequences(&data).unwrap();
        assert_eq!(s.len(), 3 + 4);
        for q in &s {
            assert!(q.segments.len() > q.baseline_count);
            assert!(q.baseline_count >= trend::MIN_BASELINES);
        }
    }
}
