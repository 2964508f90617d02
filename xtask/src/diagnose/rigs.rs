//! The two other rigs of the shared data, MFPT and UESTC: which files, their labels, declared
//! speeds and bearings, loaded as the command-line tool loads them
//! (`hybrid_fdd_cli::diagnose::load`) and diagnosed self-referenced and, for UESTC, against the
//! same rig's normal recording at the same set speed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use diagnosis::BearingSpec;
use hybrid_fdd_cli::diagnose::{BaselineSource, Outcome, Plan, diagnose_loaded, load};
use rayon::prelude::*;

/// A rig other than CWRU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Rig {
    /// MFPT Society's NICE-bearing rig (`<data>/mfpt/`).
    Mfpt,
    /// UESTC's UCPH 20 pillow block (`<data>/uestc/Data/`).
    Uestc,
}

impl Rig {
    /// `mfpt`, `uestc`: the peer CSV's `rig` and the file names.
    pub fn key(self) -> &'static str {
        match self {
            Self::Mfpt => "mfpt",
            Self::Uestc => "uestc",
        }
    }

    /// `MFPT`, `UESTC`.
    pub fn title(self) -> &'static str {
        match self {
            Self::Mfpt => "MFPT",
            Self::Uestc => "UESTC",
        }
    }

    /// The bearing designation diagnosed with (`hybrid-fdd bearings`).
    pub fn bearing(self) -> &'static str {
        match self {
            Self::Mfpt => "MFPT-NICE",
            Self::Uestc => "UC204",
        }
    }
}

/// MFPT's declared speed when a file stores none, rpm (the nameplate `rate` = 25 Hz).
pub const MFPT_NAMEPLATE_RPM: f64 = 1500.0;

/// One recording of MFPT or UESTC and its diagnoses.
pub struct OtherRow {
    /// The rig.
    pub rig: Rig,
    /// The file stem (`train_data_InnerRaceFault_vload_1`, `N_1000_1`): the peer CSV's `record`.
    pub stem: String,
    /// The file, relative to the data directory.
    pub file: String,
    /// `normal`, `inner`, `outer`, `ball` (from the file name).
    pub label: &'static str,
    /// Sampling rate read from the file, Hz.
    pub fs_hz: f64,
    /// Samples.
    pub samples: usize,
    /// Declared speed, rpm: MFPT's stored `rate`, UESTC's set speed.
    pub declared_rpm: f64,
    /// UESTC: set speed (rpm) and segment.
    pub set: Option<(u32, u8)>,
    /// Self-referenced.
    pub own: Result<Outcome, String>,
    /// UESTC: against the same set speed's normal recording of the other segment (its stem),
    /// `None` for MFPT.
    pub base: Option<(String, Result<Outcome, String>)>,
}

/// A file found for a rig: stem, path, label, UESTC set speed and segment.
struct Found {
    stem: String,
    path: PathBuf,
    rel: String,
    label: &'static str,
    set: Option<(u32, u8)>,
}

/// The `.mat` files of `dir` (extension in any case), each with its file stem.
fn mat_files(dir: &Path) -> anyhow::Result<Vec<(std::path::PathBuf, String)>> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let path = e?.path();
        if !path
            .extension()
            .is_some_and(|x| x.eq_ignore_ascii_case("mat"))
        {
            continue;
        }
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        out.push((path, stem));
    }
    Ok(out)
}

/// MFPT's fault files (`*InnerRaceFault*` → inner, `*OuterRaceFault*` → outer), sorted by name;
/// other `.mat` files (none in the shared copy) are left out with a message.
fn mfpt_files(dir: &Path) -> anyhow::Result<Vec<Found>> {
    let mut out = Vec::new();
    for (path, stem) in mat_files(dir)? {
        let label = if stem.contains("InnerRaceFault") {
            "inner"
        } else if stem.contains("OuterRaceFault") {
            "outer"
        } else {
            println!("diagnose --all-real: {stem}.mat has no fault label in its name; left out");
            continue;
        };
        out.push(Found {
            rel: format!("mfpt/{stem}.mat"),
            stem,
            path,
            label,
            set: None,
        });
    }
    out.sort_by(|a, b| a.stem.cmp(&b.stem));
    Ok(out)
}

/// The label of a UESTC condition code.
fn uestc_label(code: &str) -> Option<&'static str> {
    match code {
        "N" => Some("normal"),
        "I" => Some("inner"),
        "O" => Some("outer"),
        "B" => Some("ball"),
        _ => None,
    }
}

/// `N_1000_1` → (`normal`, 1000, 1).
fn parse_uestc(stem: &str) -> Option<(&'static str, u32, u8)> {
    let mut it = stem.split('_');
    let label = uestc_label(it.next()?)?;
    let rpm = it.next()?.parse().ok()?;
    let seg = it.next()?.parse().ok()?;
    it.next().is_none().then_some((label, rpm, seg))
}

/// UESTC's `Data/*/*.mat`, sorted by label (normal, inner, outer, ball), set speed, segment.
fn uestc_files(dir: &Path) -> anyhow::Result<Vec<Found>> {
    let mut out = Vec::new();
    for sub in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let sub = sub?.path();
        if !sub.is_dir() {
            continue;
        }
        for (path, stem) in mat_files(&sub)? {
            let Some((label, rpm, seg)) = parse_uestc(&stem) else {
                println!(
                    "diagnose --all-real: {} is not named X_rpm_segment; left out",
                    path.display()
                );
                continue;
            };
            let folder = sub.file_name().and_then(|s| s.to_str()).unwrap_or_default();
            out.push(Found {
                rel: format!("uestc/Data/{folder}/{stem}.mat"),
                stem,
                path,
                label,
                set: Some((rpm, seg)),
            });
        }
    }
    let order = |l: &str| {
        ["normal", "inner", "outer", "ball"]
            .iter()
            .position(|x| *x == l)
    };
    out.sort_by_key(|f| (order(f.label), f.set));
    Ok(out)
}

/// The signal of each rig's files, as `hybrid-fdd diagnose --channel` names it.
fn channel(rig: Rig) -> &'static str {
    match rig {
        Rig::Mfpt => "bearing.gs",
        Rig::Uestc => "Data",
    }
}

/// What was found of the two rigs: rows, and a note per rig left out (no directory).
pub struct Others {
    /// Every recording, MFPT first, then UESTC.
    pub rows: Vec<OtherRow>,
    /// Rigs not found, with why.
    pub missing: Vec<(Rig, String)>,
}

/// Diagnose every MFPT and UESTC recording under `data` (in parallel).
pub fn run(data: &Path) -> anyhow::Result<Others> {
    let mut missing = Vec::new();
    let mut jobs: Vec<(Rig, Found)> = Vec::new();
    for (rig, dir) in [
        (Rig::Mfpt, data.join("mfpt")),
        (Rig::Uestc, data.join("uestc/Data")),
    ] {
        if !dir.is_dir() {
            missing.push((rig, format!("{} not found", dir.display())));
            continue;
        }
        let files = match rig {
            Rig::Mfpt => mfpt_files(&dir)?,
            Rig::Uestc => uestc_files(&dir)?,
        };
        jobs.extend(files.into_iter().map(|f| (rig, f)));
    }
    // UESTC's baselines: each set speed's normal recordings, by (set speed, segment)
    let mut baselines: BTreeMap<(u32, u8), (String, BaselineSource)> = BTreeMap::new();
    for (_, f) in jobs
        .iter()
        .filter(|(r, f)| *r == Rig::Uestc && f.label == "normal")
    {
        let l = load(&f.path, channel(Rig::Uestc), None)
            .with_context(|| format!("loading baseline {}", f.rel))?;
        let src =
            BaselineSource::from_samples(Path::new(&format!("{}.mat", f.stem)), l.samples, l.fs_hz);
        // prepared once here (the AR fit), read by every record of that speed below
        src.at(l.fs_hz, f64::from(f.set.map_or(0, |s| s.0)))?;
        if let Some(set) = f.set {
            baselines.insert(set, (f.stem.clone(), src));
        }
    }
    let bar = indicatif::ProgressBar::new(jobs.len() as u64);
    let rows = jobs
        .par_iter()
        .map(|(rig, f)| -> anyhow::Result<OtherRow> {
            let mut l =
                load(&f.path, channel(*rig), None).with_context(|| format!("loading {}", f.rel))?;
            let declared = match (rig, f.set) {
                (Rig::Uestc, Some((rpm, _))) => f64::from(rpm),
                _ => l.rpm.unwrap_or(MFPT_NAMEPLATE_RPM),
            };
            l.rpm = Some(declared);
            let plan = Plan {
                channel: channel(*rig).into(),
                fs: None,
                rpm: Some(declared),
                bearing: BearingSpec::parse(rig.bearing())?,
            };
            let own = diagnose_loaded(&l, &plan, None).map_err(|e| format!("{e:#}"));
            let base = f.set.map(|(rpm, seg)| {
                let other = if seg == 1 { 2 } else { 1 };
                match baselines.get(&(rpm, other)) {
                    Some((name, src)) => (
                        name.clone(),
                        diagnose_loaded(&l, &plan, Some(src)).map_err(|e| format!("{e:#}")),
                    ),
                    None => (
                        format!("N_{rpm}_{other}"),
                        Err(format!("no normal recording N_{rpm}_{other} in the data")),
                    ),
                }
            });
            bar.inc(1);
            Ok(OtherRow {
                rig: *rig,
                stem: f.stem.clone(),
                file: f.rel.clone(),
                label: f.label,
                fs_hz: l.fs_hz,
                samples: l.samples.len(),
                declared_rpm: declared,
                set: f.set,
                own,
                base,
            })
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    bar.finish_and_clear();
    Ok(Others { rows, missing })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uestc_names_give_label_speed_and_segment() {
        assert_eq!(parse_uestc("N_1000_1"), Some(("normal", 1000, 1)));
        assert_eq!(parse_uestc("B_800_2"), Some(("ball", 800, 2)));
        assert_eq!(parse_uestc("X_800_2"), None);
        assert_eq!(parse_uestc("I_800"), None);
        assert_eq!(parse_uestc("I_800_1_2"), None);
    }
}
