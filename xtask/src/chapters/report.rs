//! The report layer: our tables beside the dissertation's, cell by cell, written as Markdown (for
//! people), CSV and JSON (for programs), with stable number formatting (one decimal for percents).
//!
//! Nothing here computes an accuracy; it only lays out what the pipeline measured.

use ::pipeline::Protocol;
use ::pipeline::dissertation::DissTable;
pub use ::pipeline::dissertation::class_label;
use serde::Serialize;
use std::fmt::Write as _;

/// The stable key a chapter report files a protocol under (JSON, CSV): the two
/// leave-one-condition-out protocols (load for CWRU tables, speed for the substitute's) share one.
pub fn protocol_key(p: Protocol) -> &'static str {
    match p {
        Protocol::RandomWindows => "random_windows",
        Protocol::TimeBlocked => "time_blocked",
        Protocol::LeaveOneFaultSizeOut => "leave_one_size_out",
        Protocol::LeaveOneLoadOut | Protocol::LeaveOneSpeedOut => "leave_one_condition_out",
        Protocol::GroupedByRecording => "grouped_by_recording",
    }
}

/// The heading of a protocol in a chapter report.
pub fn protocol_title(p: Protocol) -> &'static str {
    match p {
        Protocol::RandomWindows => "dissertation protocol (random 75/25 split of windows)",
        Protocol::TimeBlocked => "time-blocked split (first 75 % of each recording trains)",
        Protocol::LeaveOneFaultSizeOut => "leave one fault size out",
        Protocol::LeaveOneLoadOut | Protocol::LeaveOneSpeedOut => {
            "grouped by recording (leave one load/speed out)"
        }
        Protocol::GroupedByRecording => "grouped by recording",
    }
}

pub use ::pipeline::cells::Cell;

/// One row group of our table: the features of one method (or the raw signal).
#[derive(Debug, Clone, Serialize)]
pub struct SourceColumns {
    /// Method name ("HOSTSMO") or "raw signal".
    pub source: String,
    /// Whether the dissertation reports this method (the raw signal it does not).
    pub in_dissertation: bool,
    /// One cell per crack size, in the dissertation table's column order.
    pub cells: Vec<Cell>,
    /// The same cells classified on the window energy in dB (`ClassifierKind::SvmLogEnergy`;
    /// empty for the tree, whose splits do not depend on the scale).
    pub cells_db: Vec<Cell>,
}

/// Our version of one dissertation table under one protocol.
#[derive(Debug, Clone, Serialize)]
pub struct OurTable {
    /// Dissertation table id ("2.3").
    pub table: String,
    /// The protocol.
    #[serde(serialize_with = "serialize_protocol")]
    pub protocol: Protocol,
    /// What the protocol did here, and its caveats.
    pub protocol_note: String,
    /// One entry per method (dissertation order) and one for the raw signal.
    pub sources: Vec<SourceColumns>,
}

fn serialize_protocol<S: serde::Serializer>(p: &Protocol, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(protocol_key(*p))
}

/// The data behind one dissertation table.
#[derive(Debug, Clone, Serialize)]
pub struct DataNote {
    /// Dissertation table id.
    pub table: String,
    /// Plain statement of the data used.
    pub text: String,
    /// Recordings per class and crack size: `(class, crack, recording ids)`.
    pub recordings: Vec<(String, String, Vec<String>)>,
    /// Windows per class (for the first crack size), in row order.
    pub windows_per_class: Vec<usize>,
    /// Samples per window.
    pub window_len: usize,
}

/// Healthy held-out RMS(residual)/RMS(signal) per dataset and observer (the normal class's
/// scored windows, all after the fit segment).
pub type ResidualRatios =
    std::collections::BTreeMap<String, std::collections::BTreeMap<String, f64>>;

/// A chapter's complete results.
#[derive(Debug, Clone, Serialize)]
pub struct ChapterReport {
    /// "cargo xtask chapterN".
    pub generated_by: String,
    /// Chapter number.
    pub chapter: u8,
    /// Title line.
    pub title: String,
    /// Whether the CWRU part ran on simulated CWRU-like recordings (data absent).
    pub cwru_simulated: bool,
    /// Global notes (data, protocol, decisions), in order.
    pub notes: Vec<String>,
    /// Data per dissertation table.
    pub data: Vec<DataNote>,
    /// Our tables, grouped by dissertation table then protocol.
    pub tables: Vec<OurTable>,
    /// Extra Markdown sections (e.g. the learned decision rules), in order: (heading, body).
    pub extras: Vec<(String, String)>,
    /// Figure files (relative to the chapter directory).
    pub figures: Vec<String>,
    /// Healthy held-out RMS(residual)/RMS(signal), dataset → observer.
    pub residual_rms_ratio: ResidualRatios,
}

/// Percent with one decimal.
pub fn pct(v: f64) -> String {
    let r = (v * 10.0).round() / 10.0;
    // Avoid "-0.0".
    let r = if r == 0.0 { 0.0 } else { r };
    format!("{r:.1}")
}

fn signed(v: f64) -> String {
    let r = (v * 10.0).round() / 10.0;
    if r > 0.0 {
        format!("+{r:.1}")
    } else if r == 0.0 {
        "0.0".to_string()
    } else {
        format!("{r:.1}")
    }
}

/// A flat row of the CSV / a cell of the comparison.
#[derive(Debug, Clone, Serialize)]
pub struct FlatRow {
    /// Dissertation table id.
    pub table: String,
    /// Protocol key.
    pub protocol: String,
    /// Method or "raw signal".
    pub source: String,
    /// Crack size as printed (unit in `crack_unit`).
    pub crack: String,
    /// "in" or "mm".
    pub crack_unit: String,
    /// Class key, or "average".
    pub class: String,
    /// The dissertation's value (only for its protocol and its methods).
    pub dissertation: Option<f64>,
    /// Ours (None: not applicable).
    pub ours: Option<f64>,
    /// ours − dissertation.
    pub difference: Option<f64>,
    /// Ours with the window energy in dB (`ClassifierKind::SvmLogEnergy`; None: not applicable
    /// or a tree).
    pub ours_db: Option<f64>,
}

fn round1(v: f64) -> f64 {
    let r = (v * 10.0).round() / 10.0;
    if r == 0.0 { 0.0 } else { r }
}

/// Flatten a table into rows (rounded to one decimal so CSV/JSON are stable).
pub fn flatten(t: &OurTable, d: &DissTable) -> Vec<FlatRow> {
    let mut out = Vec::new();
    for s in &t.sources {
        for (ci, cell) in s.cells.iter().enumerate() {
            let crack = d.cracks[ci].clone();
            let nrows = d.classes.len() + 1;
            for r in 0..nrows {
                let cell_db = s.cells_db.get(ci);
                let (class, diss, ours, ours_db) = if r < d.classes.len() {
                    let diss = if t.protocol == Protocol::RandomWindows && s.in_dissertation {
                        d.value(r, &s.source, ci)
                    } else {
                        None
                    };
                    let ours = match cell {
                        Cell::Measured(o) => o.per_class[r],
                        Cell::NotApplicable(_) => None,
                    };
                    let ours_db = match cell_db {
                        Some(Cell::Measured(o)) => o.per_class[r],
                        _ => None,
                    };
                    (d.classes[r].clone(), diss, ours, ours_db)
                } else {
                    let diss = if t.protocol == Protocol::RandomWindows && s.in_dissertation {
                        d.avg(&s.source, ci)
                    } else {
                        None
                    };
                    let ours = match cell {
                        Cell::Measured(o) => Some(o.average),
                        Cell::NotApplicable(_) => None,
                    };
                    let ours_db = match cell_db {
                        Some(Cell::Measured(o)) => Some(o.average),
                        _ => None,
                    };
                    ("average".to_string(), diss, ours, ours_db)
                };
                let ours = ours.map(round1);
                let difference = match (ours, diss) {
                    (Some(o), Some(dv)) => Some(round1(o - dv)),
                    _ => None,
                };
                out.push(FlatRow {
                    table: t.table.clone(),
                    protocol: protocol_key(t.protocol).into(),
                    source: s.source.clone(),
                    crack: crack.clone(),
                    crack_unit: d.crack_unit.clone(),
                    class,
                    dissertation: diss,
                    ours,
                    difference,
                    ours_db: ours_db.map(round1),
                });
            }
        }
    }
    out
}

/// Markdown for one chapter: the header and notes, each dissertation table's data, notes and
/// our tables under every protocol, the extras and the figures.
pub fn markdown(rep: &ChapterReport, diss: &[&DissTable]) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "<!-- generated by {}; do not edit -->", rep.generated_by);
    let _ = writeln!(m, "# {}\n", rep.title);
    let _ = writeln!(
        m,
        "Generated by `{}`. Percent accuracies, one decimal. Each cell shows *ours* beside the dissertation's value and the difference (ours − dissertation). The dissertation's values are comparable only under its own protocol (random split of windows); the other protocols have no published counterpart.\n",
        rep.generated_by
    );
    if rep.cwru_simulated {
        let _ = writeln!(
            m,
            "> **The CWRU data was not found: every CWRU table below ran on simulated CWRU-like recordings from `bearing-model`, not on measurements.**\n"
        );
    }
    if !rep.notes.is_empty() {
        let _ = writeln!(m, "## Data and protocol\n");
        for n in &rep.notes {
            let _ = writeln!(m, "- {n}");
        }
        let _ = writeln!(m);
    }
    for d in diss {
        table_section(&mut m, rep, d);
    }
    for (h, body) in &rep.extras {
        let _ = writeln!(m, "## {h}\n\n{body}\n");
    }
    if !rep.figures.is_empty() {
        let _ = writeln!(m, "## Figures\n");
        for f in &rep.figures {
            let _ = writeln!(m, "- [{f}]({f})");
        }
        let _ = writeln!(m);
    }
    m
}

/// One dissertation table: its source, the data behind it, its transcription notes, and ours
/// under each protocol.
fn table_section(m: &mut String, rep: &ChapterReport, d: &DissTable) {
    let _ = writeln!(m, "## Table {} — {}\n", d.id, d.title.trim_end_matches('.'));
    let _ = writeln!(
        m,
        "Dissertation: Table {} (line {} of dissertation.txt), proposed method {}.\n",
        d.id, d.source_line, d.proposed
    );
    if let Some(dn) = rep.data.iter().find(|x| x.table == d.id) {
        let _ = writeln!(m, "**Data.** {}\n", dn.text);
        if !dn.recordings.is_empty() {
            let _ = writeln!(m, "| class | crack ({}) | recordings |", d.crack_unit);
            let _ = writeln!(m, "|---|---|---|");
            for (c, k, ids) in &dn.recordings {
                let _ = writeln!(m, "| {} | {} | {} |", class_label(c), k, ids.join(", "));
            }
            let _ = writeln!(m);
        }
    }
    if !d.notes.is_empty() {
        let _ = writeln!(m, "**Transcription notes.**\n");
        for n in &d.notes {
            let _ = writeln!(m, "- {n}");
        }
        let _ = writeln!(m);
    }
    for t in rep.tables.iter().filter(|t| t.table == d.id) {
        let _ = writeln!(m, "### {}\n", protocol_title(t.protocol));
        let _ = writeln!(m, "{}\n", t.protocol_note);
        protocol_table(m, d, t);
        let _ = writeln!(m);
        for e in table_footnotes(d, t) {
            let _ = writeln!(m, "- {e}");
        }
        let _ = writeln!(m);
    }
}

/// Our table under one protocol: a row per (source, class) and the average, a column per crack
/// size (under the dissertation's protocol, ours beside the dissertation's value and Δ).
fn protocol_table(m: &mut String, d: &DissTable, t: &OurTable) {
    let with_diss = t.protocol == Protocol::RandomWindows;
    // Header.
    let mut h = String::from("| method | class |");
    let mut sep = String::from("|---|---|");
    for k in &d.cracks {
        if with_diss {
            let _ = write!(h, " {k} {u} ours | diss. | Δ |", u = d.crack_unit);
            sep.push_str("---:|---:|---:|");
        } else {
            let _ = write!(h, " {k} {u} ours |", u = d.crack_unit);
            sep.push_str("---:|");
        }
    }
    let _ = writeln!(m, "{h}\n{sep}");
    for s in &t.sources {
        for r in 0..=d.classes.len() {
            let label = if r < d.classes.len() {
                class_label(&d.classes[r])
            } else {
                "**Average**".into()
            };
            let name = if r == 0 {
                s.source.clone()
            } else {
                String::new()
            };
            let mut line = format!("| {name} | {label} |");
            for (ci, cell) in s.cells.iter().enumerate() {
                let ours = match cell {
                    Cell::Measured(o) => {
                        if r < d.classes.len() {
                            o.per_class[r]
                        } else {
                            Some(o.average)
                        }
                    }
                    Cell::NotApplicable(_) => None,
                };
                let ours_s = match (cell, ours) {
                    (Cell::NotApplicable(_), _) => "n/a".to_string(),
                    (_, Some(v)) => pct(v),
                    (_, None) => "–".to_string(),
                };
                if with_diss {
                    let dv = if s.in_dissertation {
                        if r < d.classes.len() {
                            d.value(r, &s.source, ci)
                        } else {
                            d.avg(&s.source, ci)
                        }
                    } else {
                        None
                    };
                    let ds = dv.map(pct).unwrap_or_else(|| "–".into());
                    let diff = match (ours, dv) {
                        (Some(o), Some(x)) => signed(round1(o) - x),
                        _ => "–".into(),
                    };
                    let _ = write!(line, " {ours_s} | {ds} | {diff} |");
                } else {
                    let _ = write!(line, " {ours_s} |");
                }
            }
            let _ = writeln!(m, "{line}");
        }
    }
}

/// The footnotes under a protocol's table: why a cell is not applicable, the spread of the
/// first source's averages, and the averages with the energy in dB (SVM chapters, CWRU tables).
fn table_footnotes(d: &DissTable, t: &OurTable) -> Vec<String> {
    // Not-applicable reasons and spreads.
    let mut extra = Vec::new();
    for s in &t.sources {
        for (ci, cell) in s.cells.iter().enumerate() {
            match cell {
                Cell::NotApplicable(why) => {
                    let line = format!("n/a: {why}");
                    if !extra.contains(&line) {
                        extra.push(line);
                    }
                }
                Cell::Measured(o) => {
                    if let Some(sd) = o.spread {
                        if s.source == t.sources[0].source {
                            extra.push(format!(
                                "{} {} {}: average {} ± {} (sd over repetitions), {} training / {} test windows per repetition",
                                s.source,
                                d.cracks[ci],
                                d.crack_unit,
                                pct(o.average),
                                pct(sd),
                                o.n_train,
                                o.n_test
                            ));
                        }
                    }
                }
            }
        }
    }
    // the same cells with the energy in dB (SVM chapters, CWRU tables)
    if t.sources.iter().any(|s| !s.cells_db.is_empty()) {
        let per_crack: Vec<String> = (0..d.cracks.len())
            .map(|ci| {
                let v: Vec<String> = t
                    .sources
                    .iter()
                    .map(|s| {
                        let a = match s.cells_db.get(ci) {
                            Some(Cell::Measured(o)) => pct(o.average),
                            Some(Cell::NotApplicable(_)) => "n/a".into(),
                            None => "–".into(),
                        };
                        format!("{} {a}", s.source)
                    })
                    .collect();
                format!("{} {}: {}", d.cracks[ci], d.crack_unit, v.join(", "))
            })
            .collect();
        extra.push(format!(
            "Average with the energy in dB (`ours_db`): {}",
            per_crack.join("; ")
        ));
    }
    extra
}

/// CSV (long format), headed by a comment line.
pub fn csv(rep: &ChapterReport, diss: &[&DissTable]) -> anyhow::Result<String> {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    w.write_record([
        "table",
        "protocol",
        "source",
        "crack",
        "crack_unit",
        "class",
        "dissertation",
        "ours",
        "difference",
        "ours_db",
    ])?;
    for t in &rep.tables {
        let Some(d) = diss.iter().find(|d| d.id == t.table) else {
            continue;
        };
        for r in flatten(t, d) {
            let f = |v: Option<f64>| v.map(pct).unwrap_or_default();
            w.write_record([
                r.table.as_str(),
                r.protocol.as_str(),
                r.source.as_str(),
                r.crack.as_str(),
                r.crack_unit.as_str(),
                r.class.as_str(),
                &f(r.dissertation),
                &f(r.ours),
                &f(r.difference),
                &f(r.ours_db),
            ])?;
        }
    }
    let body = String::from_utf8(w.into_inner()?)?;
    Ok(format!(
        "# generated by {}; do not edit\n{body}",
        rep.generated_by
    ))
}

/// JSON with a `generated_by` field.
pub fn json(rep: &ChapterReport, diss: &[&DissTable]) -> anyhow::Result<String> {
    let mut rows = Vec::new();
    for t in &rep.tables {
        if let Some(d) = diss.iter().find(|d| d.id == t.table) {
            rows.extend(flatten(t, d));
        }
    }
    let v = serde_json::json!({
        "generated_by": rep.generated_by,
        "chapter": rep.chapter,
        "title": rep.title,
        "cwru_simulated": rep.cwru_simulated,
        "notes": rep.notes,
        "data": rep.data,
        "cells": rows,
        "protocol_notes": rep.tables.iter().map(|t| serde_json::json!({
            "table": t.table, "protocol": protocol_key(t.protocol), "note": t.protocol_note,
            "confusion": t.sources.iter().map(|s| serde_json::json!({
                "source": s.source,
                "per_crack": s.cells.iter().map(|c| match c {
                    Cell::Measured(o) => serde_json::json!({"confusion": o.confusion, "n_train": o.n_train, "n_test": o.n_test, "spread": o.spread.map(round1)}),
                    Cell::NotApplicable(w) => serde_json::json!({"not_applicable": w}),
                }).collect::<Vec<_>>()
            })).collect::<Vec<_>>()
        })).collect::<Vec<_>>(),
        "extras": rep.extras.iter().map(|(h, b)| serde_json::json!({"heading": h, "body": b})).collect::<Vec<_>>(),
        "figures": rep.figures,
        "residual_rms_ratio": rep.residual_rms_ratio,
    });
    Ok(serde_json::to_string_pretty(&v)? + "\n")
}
