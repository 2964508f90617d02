//! A directory input: the files it expands to, their report names, and the batch run over
//! them in parallel with `summary.csv`.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use rayon::prelude::*;

use super::Outcome;
use super::loader::sniff;

/// Files a directory input expands to, sorted: `.mat`, `.csv`, `.tsv`, and files named without an
/// extension or with an all-digit one (IMS names its records by date, `2004.02.12.10.32.39`)
/// whose content is a MAT-file or text (read by content, as the loader sniffs them).
pub fn expand(input: &Path) -> anyhow::Result<Vec<PathBuf>> {
    if !input.is_dir() {
        return Ok(vec![input.to_path_buf()]);
    }
    let mut v: Vec<PathBuf> = std::fs::read_dir(input)
        .with_context(|| format!("reading {}", input.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .filter(|p| match p.extension().and_then(|e| e.to_str()) {
            Some(e)
                if ["mat", "csv", "tsv"]
                    .iter()
                    .any(|x| e.eq_ignore_ascii_case(x)) =>
            {
                true
            }
            Some(e) if !e.bytes().all(|b| b.is_ascii_digit()) => false,
            _ => sniff(p).is_ok(),
        })
        .collect();
    v.sort();
    if v.is_empty() {
        bail!(
            "{} holds no .mat, .csv or .tsv file (nor a MAT or text file named without an extension)",
            input.display()
        );
    }
    Ok(v)
}

/// The report name (without extension) of each batch input, in order: its stem, or
/// `<stem>_<ext>` (`x_csv`, `x_tsv`) when several inputs share the stem (compared ignoring
/// case), and `<name>_<k>` (k = 1-based position among `files`) for any name still taken twice.
/// Deterministic: depends on the file names only.
pub fn report_names(files: &[PathBuf]) -> Vec<String> {
    let stem = |p: &PathBuf| {
        p.file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("recording")
            .to_string()
    };
    let count =
        |names: &[String], n: &str| names.iter().filter(|m| m.eq_ignore_ascii_case(n)).count();
    let stems: Vec<String> = files.iter().map(stem).collect();
    let names: Vec<String> = files
        .iter()
        .zip(&stems)
        .map(|(p, s)| {
            if count(&stems, s) > 1 {
                let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
                format!("{s}_{ext}")
            } else {
                s.clone()
            }
        })
        .collect();
    names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            if count(&names, n) > 1 {
                format!("{n}_{}", k + 1)
            } else {
                n.clone()
            }
        })
        .collect()
}

/// The directory batch of [`run`](super::run): `one` (a recording and its report path → its
/// outcome and notes) on every file of `files` in parallel, one report each in `report` and
/// `summary.csv`; `read` are the files the run reads (never overwritten).
///
/// # Errors
/// Outputs that would overwrite an input, file system errors, and any file that failed (after
/// every report and `summary.csv` are written).
pub(super) fn run_batch<F>(
    input: &Path,
    report: &Path,
    files: &[PathBuf],
    read: &[&Path],
    one: &F,
) -> anyhow::Result<()>
where
    F: Fn(&Path, &Path) -> anyhow::Result<(Outcome, Vec<String>)> + Sync,
{
    let names = report_names(files);
    if crate::resolved(input).is_some() && crate::resolved(input) == crate::resolved(report) {
        bail!(
            "--report {} is the input directory: the reports would be mixed with the recordings (and read as recordings by the next run); choose another directory",
            report.display()
        );
    }
    let mut outputs: Vec<PathBuf> = names
        .iter()
        .flat_map(|n| crate::report_files(&report.join(format!("{n}.json"))))
        .collect();
    outputs.push(report.join("summary.csv"));
    crate::refuse_overwrite("--report", &outputs, read)?;
    std::fs::create_dir_all(report)?;
    let bar = indicatif::ProgressBar::new(files.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    type Done = (PathBuf, String, anyhow::Result<(Outcome, Vec<String>)>);
    let results: Vec<Done> = files
        .par_iter()
        .zip(&names)
        .map(|(p, n)| {
            let json = format!("{n}.json");
            let r = one(p, &report.join(&json));
            bar.inc(1);
            (p.clone(), json, r)
        })
        .collect();
    bar.finish_and_clear();
    let mut csv = String::from(
        "file,report,verdict,reference,score_inner_db,score_outer_db,score_ball_db,band_low_hz,band_high_hz,error\n",
    );
    let mut failed = 0;
    for (p, json, r) in &results {
        let name = p.file_name().and_then(|s| s.to_str()).unwrap_or("");
        match r {
            Ok((o, notes)) => {
                for n in notes {
                    eprintln!("note: {n}");
                }
                let d = &o.diagnosis;
                crate::say!("{name}: {} -> {json}", d.verdict);
                csv += &format!(
                    "{name},{json},{},{},{:.2},{:.2},{:.2},{:.0},{:.0},\n",
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
                csv += &format!("{name},,,,,,,,,{msg}\n");
            }
        }
    }
    std::fs::write(report.join("summary.csv"), csv)?;
    crate::say!(
        "{} recordings, {failed} failed; reports in {}",
        results.len(),
        report.display()
    );
    if failed > 0 {
        bail!(
            "{failed} of {} recordings failed (their errors are in {})",
            results.len(),
            report.join("summary.csv").display()
        );
    }
    Ok(())
}
