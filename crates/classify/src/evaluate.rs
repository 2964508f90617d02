//! Run a classifier over every fold of a [`SplitPlan`] and summarise per-class accuracy
//! (the rows of the dissertation's tables) and the average accuracy of eq. (5.37).

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::Result;
use crate::metrics::ConfusionMatrix;
use crate::model::ClassifierSpec;
use crate::protocol::{Protocol, SplitPlan};

/// Confusion matrix of one fold.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FoldResult {
    /// Fold name from the plan.
    pub name: String,
    /// Test-set confusion matrix.
    pub confusion: ConfusionMatrix,
}

/// Mean and spread of a percentage over folds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Mean over folds, percent.
    pub mean: f64,
    /// Sample standard deviation over folds (0 for a single fold), percentage points.
    pub std: f64,
    /// Number of folds that contributed.
    pub folds: usize,
}

impl Summary {
    fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let std = if values.len() > 1 {
            (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            0.0
        };
        Some(Self {
            mean,
            std,
            folds: values.len(),
        })
    }
}

/// Results of one classifier under one protocol.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The protocol.
    pub protocol: Protocol,
    /// Classifier name.
    pub classifier: String,
    /// Class names.
    pub class_names: Vec<String>,
    /// Per-fold results.
    pub folds: Vec<FoldResult>,
    /// The plan's caveats.
    pub notes: Vec<String>,
}

impl Evaluation {
    /// Per-class accuracy (percent) over the folds in which the class was tested.
    pub fn per_class_accuracy(&self) -> Vec<Option<Summary>> {
        (0..self.class_names.len())
            .map(|c| {
                let v: Vec<f64> = self
                    .folds
                    .iter()
                    .filter_map(|f| f.confusion.per_class_accuracy()[c])
                    .collect();
                Summary::of(&v)
            })
            .collect()
    }

    /// Average classification accuracy, eq. (5.37), over folds.
    pub fn average_accuracy(&self) -> Option<Summary> {
        let v: Vec<f64> = self
            .folds
            .iter()
            .filter_map(|f| f.confusion.average_accuracy())
            .collect();
        Summary::of(&v)
    }

    /// Sum of the fold confusion matrices.
    pub fn pooled_confusion(&self) -> ConfusionMatrix {
        let mut m = ConfusionMatrix::zeros(self.class_names.len());
        for f in &self.folds {
            m.add(&f.confusion);
        }
        m
    }

    /// A Markdown report: protocol, per-class table (mean ± std over folds), ACA, pooled
    /// confusion matrix and the notes.
    pub fn report(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "### {} — {} ({} folds)\n",
            self.classifier,
            self.protocol,
            self.folds.len()
        );
        let _ = writeln!(s, "| class | accuracy (%) | folds tested |\n|---|---|---|");
        for (name, acc) in self.class_names.iter().zip(self.per_class_accuracy()) {
            match acc {
                Some(a) => {
                    let _ = writeln!(s, "| {name} | {:.1} ± {:.1} | {} |", a.mean, a.std, a.folds);
                }
                None => {
                    let _ = writeln!(s, "| {name} | not tested | 0 |");
                }
            }
        }
        if let Some(a) = self.average_accuracy() {
            let _ = writeln!(
                s,
                "| **ACA (eq. 5.37)** | **{:.1} ± {:.1}** | {} |",
                a.mean, a.std, a.folds
            );
        }
        let m = self.pooled_confusion();
        let _ = writeln!(
            s,
            "\nPooled confusion matrix (rows true, columns predicted):\n"
        );
        let _ = writeln!(
            s,
            "| | {} |\n|---|{}",
            self.class_names.join(" | "),
            "---|".repeat(self.class_names.len())
        );
        for (name, row) in self.class_names.iter().zip(&m.counts) {
            let cells: Vec<String> = row.iter().map(usize::to_string).collect();
            let _ = writeln!(s, "| {name} | {} |", cells.join(" | "));
        }
        if !self.notes.is_empty() {
            let _ = writeln!(s, "\nNotes:");
            for n in &self.notes {
                let _ = writeln!(s, "- {n}");
            }
        }
        s
    }
}

/// Train `spec` on each fold's training windows and score it on the fold's test windows.
///
/// # Errors
/// Training errors (e.g. a fold whose training side has a single class).
pub fn evaluate(data: &Dataset, plan: &SplitPlan, spec: &ClassifierSpec) -> Result<Evaluation> {
    let mut folds = Vec::with_capacity(plan.folds.len());
    for fold in &plan.folds {
        let model = spec.fit(data, &fold.train)?;
        let pred = model.predict(data, &fold.test)?;
        let truth: Vec<usize> = fold.test.iter().map(|&i| data.label(i)).collect();
        folds.push(FoldResult {
            name: fold.name.clone(),
            confusion: ConfusionMatrix::from_predictions(data.n_classes(), &truth, &pred)?,
        });
    }
    Ok(Evaluation {
        protocol: plan.protocol,
        classifier: spec.name().to_string(),
        class_names: data.class_names().to_vec(),
        folds,
        notes: plan.notes.clone(),
    })
}
