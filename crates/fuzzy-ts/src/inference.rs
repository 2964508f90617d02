//! Rule-table fuzzy inference J_f = infer(e, ė) over Table 5.1 (eqs. 5.19–5.20).
//!
//! Method: Gaussian antecedents ([`TermSet`]), rule firing strength w_r = μ_A(e) · μ_B(ė)
//! (product t-norm, or min), and centre-of-sets (weighted-average) defuzzification
//! J_f = Σ_r w_r c_r / Σ_r w_r, where c_r is the centre of the consequent's Gaussian output set.
//! Because Gaussians never vanish and inputs are saturated to their universes, Σ w_r > 0 and
//! J_f always lies within [min c, max c], i.e. the output universe.

use crate::error::{FuzzyError, Result};
use crate::membership::TermSet;
use crate::rules::RuleTable;
use serde::{Deserialize, Serialize};

/// How the two antecedent degrees of a rule are combined ("and" of eq. 5.20).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TNorm {
    /// w = μ_A · μ_B (smooth output; the default).
    Product,
    /// w = min(μ_A, μ_B) (Mamdani's original).
    Min,
}

/// Ranges of the three universes (section 5.3 defaults: 0.3, 0.1, 0.08).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FuzzyRanges {
    /// Half-width of the error universe.
    pub error: f64,
    /// Half-width of the change-of-error universe.
    pub change_of_error: f64,
    /// Half-width of the output universe.
    pub output: f64,
}

impl FuzzyRanges {
    /// The dissertation's universes: e ∈ [−0.3, 0.3], ė ∈ [−0.1, 0.1], J_f ∈ [−0.08, 0.08].
    pub const DISSERTATION: FuzzyRanges = FuzzyRanges {
        error: 0.3,
        change_of_error: 0.1,
        output: 0.08,
    };
}

/// A complete rule-table inference system: three term sets, a rule table and a t-norm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FuzzyInference {
    e: TermSet,
    de: TermSet,
    out_centers: [f64; 7],
    table_idx: [[u8; 7]; 7],
    table: RuleTable,
    tnorm: TNorm,
}

impl FuzzyInference {
    /// Build from ranges (each half-width finite and > 0), a table and a t-norm.
    pub fn new(ranges: FuzzyRanges, table: RuleTable, tnorm: TNorm) -> Result<Self> {
        for (which, v) in [
            ("error", ranges.error),
            ("change_of_error", ranges.change_of_error),
            ("output", ranges.output),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(FuzzyError::InvalidParameter { which, value: v });
            }
        }
        let e = TermSet::symmetric(ranges.error)?;
        let de = TermSet::symmetric(ranges.change_of_error)?;
        let out = TermSet::symmetric(ranges.output)?;
        let mut out_centers = [0.0; 7];
        for t in crate::membership::Term::ALL {
            out_centers[t.index()] = out.center(t);
        }
        let mut table_idx = [[0u8; 7]; 7];
        for (i, row) in table.out.iter().enumerate() {
            for (j, t) in row.iter().enumerate() {
                table_idx[i][j] = t.index() as u8;
            }
        }
        Ok(Self {
            e,
            de,
            out_centers,
            table_idx,
            table,
            tnorm,
        })
    }

    /// The dissertation's system: section 5.3 ranges, corrected Table 5.1, product t-norm.
    pub fn dissertation() -> Self {
        // The constants are valid by construction.
        Self::new(
            FuzzyRanges::DISSERTATION,
            RuleTable::table_5_1(),
            TNorm::Product,
        )
        .unwrap_or_else(|_| unreachable!("dissertation constants are valid"))
    }

    /// The rule table.
    pub fn table(&self) -> &RuleTable {
        &self.table
    }
    /// Error term set.
    pub fn error_terms(&self) -> &TermSet {
        &self.e
    }
    /// Change-of-error term set.
    pub fn change_terms(&self) -> &TermSet {
        &self.de
    }
    /// Output half-width (the largest |J_f|).
    pub fn output_half_width(&self) -> f64 {
        self.out_centers[6]
    }

    /// J_f = infer(e, ė): Table 5.1 inference with centre-of-sets defuzzification. Pure,
    /// allocation free, 14 exponentials and 49 products; NaN inputs are treated as zero.
    #[inline]
    pub fn infer(&self, e: f64, de: f64) -> f64 {
        let me = self.e.degrees(e);
        let md = self.de.degrees(de);
        let mut num = 0.0;
        let mut den = 0.0;
        for i in 0..7 {
            for j in 0..7 {
                let w = match self.tnorm {
                    TNorm::Product => me[i] * md[j],
                    TNorm::Min => me[i].min(md[j]),
                };
                num += w * self.out_centers[self.table_idx[i][j] as usize];
                den += w;
            }
        }
        if den > 0.0 { num / den } else { 0.0 }
    }
}
