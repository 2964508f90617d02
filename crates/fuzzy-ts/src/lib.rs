//! Gaussian memberships, rule-table and Takagi–Sugeno fuzzy inference, and the fuzzy
//! ARX-Laguerre model (Piltan 2020, section 5.3: eqs. 5.19–5.20, 5.29, Table 5.1).
//!
//! - [`membership`]: Gaussian sets and the seven terms NH … PH over a universe.
//! - [`rules`]: Table 5.1 as data (as printed, and with the NL row corrected).
//! - [`inference`]: J_f = infer(e, ė), product (or min) t-norm, centre-of-sets defuzzification.
//! - [`ts`]: the two-rule Takagi–Sugeno switching law of eq. 5.29.
//! - [`fal`]: the fuzzy ARX-Laguerre model of eq. 5.19 on top of `laguerre-id`.
//!
//! The crate knows nothing about bearings.
//!
//! # Dependencies and why
//! - `laguerre-id`: the ARX-Laguerre model the fuzzy term augments (eq. 5.19).
//! - `serde`: configurations and fitted models are serialisable for reports.
//! - `thiserror`: the single typed error enum [`FuzzyError`].
//! - `sampled-signal`: the workspace's one finite check of a slice (`first_non_finite`).
//!
//! # Example
//! ```
//! use fuzzy_ts::{FuzzyInference, TsSwitchingLaw, Switching};
//! let fis = FuzzyInference::dissertation();
//! let jf = fis.infer(0.1, -0.02);            // Table 5.1, e = 0.1, ė = −0.02
//! assert!(jf.abs() <= 0.08);
//! assert!(fis.infer(0.2, 0.05) < 0.0);       // positive error and rising: negative output
//! let law = TsSwitchingLaw::new(0.5, 0.1, 0.8, Switching::Crisp)?;
//! let alpha = law.step(0.0, 0.7, 0.2);       // |r| > TH: faulty gain 0.8
//! assert!((alpha - 0.16).abs() < 1e-15);
//! # Ok::<(), fuzzy_ts::FuzzyError>(())
//! ```

// Index loops mirror the equations' subscripts in the numeric kernels.
#![allow(clippy::needless_range_loop)]

pub mod compare;
pub mod error;
pub mod fal;
pub mod inference;
pub mod membership;
pub mod rules;
pub mod ts;

pub use compare::{PredictorScore, compare_predictors};
pub use error::{FuzzyError, Result};
pub use fal::{FalConfig, FalState, FuzzyArxLaguerre, FuzzyScaling};
pub use inference::{FuzzyInference, FuzzyRanges, TNorm};
pub use membership::{Gaussian, Term, TermSet};
pub use rules::{RuleTable, TABLE_5_1, TABLE_5_1_AS_PRINTED};
pub use ts::{Switching, TsSwitchingLaw};

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
