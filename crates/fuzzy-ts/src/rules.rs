//! The 49-rule table of Table 5.1 (eq. 5.20: "if e is A and ė is B then J_f is C"), as data.
//!
//! Rows are the error e (NH … PH), columns the change of error ė (NH … PH). Every row except
//! "NL" follows the anti-diagonal law out = sat(−(level(e) + level(ė))). Row NL as printed ends
//! "… Z, PL, PM" instead of "… Z, NL, NM": a sign typo (see `docs/equations/fuzzy-ts.md`);
//! [`RuleTable::table_5_1`] is the corrected table, [`RuleTable::table_5_1_as_printed`] the
//! verbatim one.

use crate::membership::Term;
use crate::membership::Term::{NH, NL, NM, PH, PL, PM, Z};
use serde::{Deserialize, Serialize};

/// Table 5.1 verbatim (row NL included as printed).
pub const TABLE_5_1_AS_PRINTED: [[Term; 7]; 7] = [
    [PH, PH, PH, PH, PM, PL, Z],
    [PH, PH, PH, PM, PL, Z, NL],
    [PH, PH, PM, PL, Z, PL, PM],
    [PH, PM, PL, Z, NL, NM, NH],
    [PM, PL, Z, NL, NM, NH, NH],
    [PL, Z, NL, NM, NH, NH, NH],
    [Z, NL, NM, NH, NH, NH, NH],
];

/// Table 5.1 with row NL corrected to the anti-diagonal law of its neighbours.
pub const TABLE_5_1: [[Term; 7]; 7] = [
    [PH, PH, PH, PH, PM, PL, Z],
    [PH, PH, PH, PM, PL, Z, NL],
    [PH, PH, PM, PL, Z, NL, NM],
    [PH, PM, PL, Z, NL, NM, NH],
    [PM, PL, Z, NL, NM, NH, NH],
    [PL, Z, NL, NM, NH, NH, NH],
    [Z, NL, NM, NH, NH, NH, NH],
];

/// A complete 7 × 7 rule table: `out[e][ė]` is the consequent term.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct RuleTable {
    /// Consequents, indexed `[error term][change-of-error term]`.
    pub out: [[Term; 7]; 7],
}

impl RuleTable {
    /// Table 5.1 with the NL row corrected (the default).
    pub fn table_5_1() -> Self {
        Self { out: TABLE_5_1 }
    }
    /// Table 5.1 exactly as printed.
    pub fn table_5_1_as_printed() -> Self {
        Self {
            out: TABLE_5_1_AS_PRINTED,
        }
    }
    /// The anti-diagonal law out = sat(−(level(e) + level(ė))) every printed row but NL obeys.
    pub fn anti_diagonal() -> Self {
        let mut out = [[Z; 7]; 7];
        for (i, row) in out.iter_mut().enumerate() {
            for (j, o) in row.iter_mut().enumerate() {
                *o = Term::from_level(-(Term::ALL[i].level() + Term::ALL[j].level()));
            }
        }
        Self { out }
    }
    /// The consequent of the rule (e is `e`, ė is `de`).
    pub fn consequent(&self, e: Term, de: Term) -> Term {
        self.out[e.index()][de.index()]
    }
    /// The 49 rules as (e, ė, output) triples, row by row.
    pub fn rules(&self) -> impl Iterator<Item = (Term, Term, Term)> + '_ {
        Term::ALL.into_iter().flat_map(move |e| {
            Term::ALL
                .into_iter()
                .map(move |d| (e, d, self.consequent(e, d)))
        })
    }
}
