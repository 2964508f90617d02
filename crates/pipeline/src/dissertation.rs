//! The dissertation's result tables (2.3–2.7, 3.1–3.5, 4.2–4.11, 5.2–5.11), transcribed once into
//! `dissertation_tables.json` and embedded at compile time.
//!
//! The JSON was produced by a script from the tab-separated tables of
//! `/work/shared/seed/dissertation.txt` and checked by eye; each table carries the line it starts
//! on (`source_line`) and notes on internal inconsistencies (e.g. an Average row that is not the
//! mean of its column). Values are percents.

use serde::Deserialize;
use std::sync::OnceLock;

/// The embedded transcription.
const TABLES_JSON: &str = include_str!("dissertation_tables.json");

/// The whole transcription.
#[derive(Debug, Deserialize)]
pub struct Transcription {
    /// Where the numbers come from.
    pub source: String,
    /// Every transcribed table.
    pub tables: Vec<DissTable>,
}

/// One dissertation table: rows = classes, columns = method × crack size.
#[derive(Debug, Deserialize, Clone)]
pub struct DissTable {
    /// "2.3", "5.11", ...
    pub id: String,
    /// Chapter number.
    pub chapter: u8,
    /// Caption as printed.
    pub title: String,
    /// Line of the caption in dissertation.txt.
    pub source_line: usize,
    /// Methods in column-group order (the proposed method first).
    pub methods: Vec<String>,
    /// The proposed method.
    pub proposed: String,
    /// "in" (CWRU) or "mm" (SHSE substitute).
    pub crack_unit: String,
    /// Crack sizes as printed, in column order within a method group.
    pub cracks: Vec<String>,
    /// Class keys in row order ("normal", "ball", "outer", "inner", "inner_ball", ...).
    pub classes: Vec<String>,
    /// `values[row][method * cracks.len() + crack]`, percent.
    pub values: Vec<Vec<f64>>,
    /// The printed Average/ACA row, percent.
    pub average: Vec<f64>,
    /// `cwru` or `shse_multi`.
    pub dataset: String,
    /// Operating condition of the table.
    pub condition: Condition,
    /// Transcription notes (inconsistencies, typos).
    pub notes: Vec<String>,
}

/// Operating condition of a table.
#[derive(Debug, Deserialize, Clone, Copy, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Condition {
    /// One motor load (CWRU).
    FixedLoad {
        /// Load in hp.
        load_hp: u8,
    },
    /// The four loads pooled (CWRU custom load-variant dataset).
    LoadVariant,
    /// One shaft speed (SHSE).
    FixedSpeed {
        /// Shaft speed in rpm.
        rpm: u32,
    },
    /// The four speeds pooled (SHSE speed-variant dataset).
    SpeedVariant,
}

impl DissTable {
    /// The table's class labels in row order ([`class_label`] of each class key).
    pub fn class_labels(&self) -> Vec<String> {
        self.classes.iter().map(|c| class_label(c)).collect()
    }
    /// The printed value for (class row, method, crack index), if the method is in the table.
    pub fn value(&self, row: usize, method: &str, crack: usize) -> Option<f64> {
        let m = self.methods.iter().position(|x| x == method)?;
        self.values
            .get(row)?
            .get(m * self.cracks.len() + crack)
            .copied()
    }
    /// The printed average for (method, crack index).
    pub fn avg(&self, method: &str, crack: usize) -> Option<f64> {
        let m = self.methods.iter().position(|x| x == method)?;
        self.average.get(m * self.cracks.len() + crack).copied()
    }
}

/// Human label of a class key.
pub fn class_label(key: &str) -> String {
    match key {
        "normal" => "Normal".into(),
        "ball" => "Ball".into(),
        "outer" => "OR".into(),
        "inner" => "IR".into(),
        "inner_ball" => "IR-Ball".into(),
        "outer_ball" => "OR-Ball".into(),
        "inner_outer" => "IR-OR".into(),
        "inner_outer_ball" => "IR-OR-Ball".into(),
        other => other.into(),
    }
}

/// The parsed transcription (parsed once).
pub fn transcription() -> &'static Transcription {
    static T: OnceLock<Transcription> = OnceLock::new();
    T.get_or_init(|| {
        serde_json::from_str(TABLES_JSON)
            .expect("embedded dissertation_tables.json is valid (tested)")
    })
}

/// The tables of one chapter, in dissertation order.
pub fn chapter_tables(chapter: u8) -> Vec<&'static DissTable> {
    transcription()
        .tables
        .iter()
        .filter(|t| t.chapter == chapter)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transcription_is_consistent() {
        let t = transcription();
        assert_eq!(t.tables.len(), 30);
        for tab in &t.tables {
            let width = tab.methods.len() * tab.cracks.len();
            assert_eq!(tab.average.len(), width, "table {}", tab.id);
            assert_eq!(tab.values.len(), tab.classes.len(), "table {}", tab.id);
            for row in &tab.values {
                assert_eq!(row.len(), width, "table {}", tab.id);
                assert!(row.iter().all(|v| (0.0..=100.0).contains(v)));
            }
            // Every Average that is not the mean of its column is documented in the notes.
            for c in 0..width {
                let mean: f64 =
                    tab.values.iter().map(|r| r[c]).sum::<f64>() / tab.values.len() as f64;
                if (mean - tab.average[c]).abs() > 0.01 {
                    assert!(
                        tab.notes
                            .iter()
                            .any(|n| n.contains(&format!("{}", tab.average[c]))),
                        "table {} column {c}: average {} vs mean {mean} undocumented",
                        tab.id,
                        tab.average[c]
                    );
                }
            }
        }
        // Spot checks against the printed text (Table 2.3 HOSTSMO ball 0.014 = 97 %,
        // Table 5.6 AFSMO OF 0.007 = 75 %, Table 4.10 APIO 6 mm average 82.8).
        let t23 = t.tables.iter().find(|t| t.id == "2.3").unwrap();
        assert_eq!(t23.value(1, "HOSTSMO", 1), Some(97.0));
        let t56 = t.tables.iter().find(|t| t.id == "5.6").unwrap();
        assert_eq!(t56.value(2, "AFSMO", 0), Some(75.0));
        let t410 = t.tables.iter().find(|t| t.id == "4.10").unwrap();
        assert_eq!(t410.avg("APIO", 1), Some(82.8));
    }
}
