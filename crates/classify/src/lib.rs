//! One-vs-one linear SVM on linfa and deterministic Gini trees, with honest evaluation protocols.
//!
//! The decision stage of Piltan (2020): window features of a residual (energy, eq. 2.46 / 5.33)
//! are classified by a one-against-one linear SVM (ch. 2–4) or a Gini decision tree whose
//! thresholds read as rules (ch. 5, eqs. 5.34–5.36), scored by per-class accuracy and the average
//! classification accuracy (eq. 5.37). Each window carries metadata (class, recording, load,
//! fault size) so that four named protocols can be run: the dissertation's random window split,
//! grouped by recording, leave one load out and leave one fault size out. Every protocol states
//! in its output what it could not apply to the data present.
//!
//! The SVM's defaults ([`LinearSvmParams::default`]: C = 10, standardisation fitted per class
//! pair, balanced class weights per pair) differ from scikit-learn's on purpose: with global
//! scaling and C = 1 a minority class squeezed between louder ones (CWRU's normal windows) is
//! given up entirely. [`LinearSvmParams::sklearn`] keeps scikit-learn's settings for comparison.
//!
//! Knows nothing about observers or signals: it takes feature rows.
//!
//! # As a linfa model
//! [`LinearSvmParams`] and [`GiniTreeParams`] implement linfa's `Fit` on a `linfa::DatasetBase`
//! of `f64` records and `usize` targets; [`OvoLinearSvm`] and [`GiniTree`] implement
//! `PredictInplace` (hence `predict` on a records matrix or a dataset), so linfa's
//! `confusion_matrix` and cross-validation helpers take them as they take linfa's own models.
//! linfa's `predict` has no error path and panics on a row that cannot be classified;
//! `predict_records` is the same with a [`ClassifyError`] instead.
//!
//! ```
//! use classify::LinearSvmParams;
//! use linfa::prelude::*;
//! use ndarray::{Array1, Array2};
//!
//! let x = Array2::from_shape_fn((40, 1), |(i, _)| if i < 20 { i as f64 } else { 50.0 + i as f64 });
//! let y = Array1::from_shape_fn(40, |i| usize::from(i >= 20));
//! let data = DatasetBase::new(x, y);
//! let svm = LinearSvmParams::default().fit(&data)?;
//! assert_eq!(svm.predict(&data).confusion_matrix(&data)?.accuracy(), 1.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Dependencies and why
//! - `linfa`, `linfa-svm`: the Rust ML toolkit's SMO solver (a libsvm port); we wrap it rather
//!   than re-implement it.
//! - The Gini tree is grown by this crate's own small CART engine, not by `linfa-trees`:
//!   linfa-trees 0.8.1 sums Gini terms over a `std::collections::HashMap<_, f32>`, whose
//!   iteration order follows the random per-process hash seed, so tied splits were resolved
//!   differently from one process to the next. `linfa-trees` remains a dev-dependency: a test
//!   checks both give the same tree on tie-free data.
//! - `ndarray`: only because linfa takes `ndarray` matrices.
//! - `rand` 0.9 + `rand_xoshiro`: SplitMix64, the workspace's seeded generator (also the closed
//!   loop's), for splits specified bit for bit and platform-independent (we never pass an RNG
//!   into linfa, so linfa's internal rand 0.8 is not needed here). `rand_chacha` is only a
//!   dev-dependency (test data).
//! - `rayon`: the one-vs-one pair machines are independent and train in parallel.
//! - `serde` / `serde_json`: trained classifiers, plans and evaluations are saved and reloaded.
//! - `thiserror`: the crate's one error enum.
//!
//! # Example
//! ```
//! use classify::*;
//! // two classes, 1-D "energy", two recordings each at two loads
//! let mut b = Dataset::builder(vec!["normal".into(), "faulty".into()], vec!["energy".into()]);
//! for (class, base) in [(0usize, 1.0), (1, 5.0)] {
//!     for (r, load) in [(0u32, 0u32), (1, 1)] {
//!         let info = RecordingInfo {
//!             class,
//!             recording: format!("{class}-{r}"),
//!             load_hp: load,
//!             fault_size_mils: (class == 1).then_some(7 + 7 * r),
//!             speed_rpm: None,
//!         };
//!         b.add_recording(&info, (0..20).map(|k| vec![base + 0.01 * k as f64]).collect());
//!     }
//! }
//! let data = b.build()?;
//! let plan = leave_one_load_out(&data, DegenerateClassPolicy::default())?;
//! let eval = evaluate(&data, &plan, &ClassifierSpec::tree())?;
//! assert_eq!(eval.average_accuracy().unwrap().mean, 100.0);
//! println!("{}", eval.report());
//! # Ok::<(), classify::ClassifyError>(())
//! ```

mod dataset;
mod error;
mod evaluate;
mod linfa_api;
mod metrics;
mod model;
mod protocol;
mod scale;
mod svm;
mod tree;
#[cfg(test)]
mod tree_linfa_check;

pub use dataset::{Dataset, DatasetBuilder, RecordingInfo, WindowMeta};
pub use error::{ClassifyError, Result};
pub use evaluate::{Evaluation, FoldResult, Summary, evaluate};
pub use metrics::ConfusionMatrix;
pub use model::{ClassifierSpec, TrainedClassifier};
pub use protocol::{
    DegenerateClassPolicy, Fold, GroupedConfig, OperatingCondition, Protocol, RANDOM_SPLIT_STREAM,
    RandomSplitConfig, SplitPlan, grouped_by_recording, leave_one_condition_out,
    leave_one_fault_size_out, leave_one_load_out, random_window_split, time_blocked,
};
pub use scale::Standardizer;
pub use svm::{ClassWeight, FeatureTransform, LinearSvmParams, OvoLinearSvm, PairMachine, Scaling};
pub use tree::{Condition, GiniTree, GiniTreeParams, NamedRule, Node, Rule};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
