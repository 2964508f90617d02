//! Gini decision tree (Piltan 2020, ch. 5: eq. 5.34 split criterion, rules of eqs. 5.35–5.36).
//!
//! CART with the Gini diversity index `GDI = 1 − Σ_k p_k²` (eq. 5.34), grown by this crate's own
//! deterministic engine; the fitted [`GiniTree`] keeps thresholds in the original feature units,
//! so the learned rules read like eqs. 5.35–5.36 ("if E ≤ ζ_n → Normal …").
//!
//! # Why not linfa-trees
//! linfa-trees 0.8.1 keeps class frequencies in a `std::collections::HashMap<L, f32>` and sums the
//! Gini terms over the map's values in f32. A `HashMap`'s iteration order depends on its random
//! per-process hash seed, so the rounding of the sum — and therefore which of two equal (or
//! nearly equal) candidate splits wins — changes from one process to the next: the chapter-5
//! pipeline moved by about one test window between runs. linfa-trees is kept as a test-only
//! cross-check (`src/tree_linfa_check.rs`: same trees on tie-free data).
//!
//! # The engine (see `docs/equations/classify.md`)
//! - Features are scanned in index order; within a node the candidate thresholds are the
//!   midpoints between consecutive *distinct* sorted values of that node (exact `==`; no
//!   tolerance, so tiny raw energies need no rescaling).
//! - A candidate is scored by the size-weighted child Gini, compared **exactly**: minimising it
//!   is maximising `Σ_k n_{L,k}²/n_L + Σ_k n_{R,k}²/n_R` (scikit-learn's proxy), a ratio of
//!   integers compared by cross-multiplication in `u128`. No floating-point rounding decides a
//!   split.
//! - Strict improvement only: ties go to the first feature, then the lowest threshold
//!   (scikit-learn's rule when it does not shuffle features).
//! - Stopping as in linfa-trees: fewer than `min_samples_split` windows, `max_depth` reached, a
//!   pure node, a child below `min_samples_leaf`, or a Gini decrease (parent minus weighted
//!   children, computed in f64) below `min_impurity_decrease`.
//! - Leaves predict the training majority, ties to the lowest class index; sibling leaves that
//!   predict the same class are merged.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::{ClassifyError, Result};
use crate::svm::{argmax_first, check_row};

/// Hyper-parameters of the Gini tree.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GiniTreeParams {
    /// Maximum depth (`None`: grow until pure or the other limits stop it).
    pub max_depth: Option<usize>,
    /// Minimum number of training windows in a node to try a split (≥ 2).
    pub min_samples_split: usize,
    /// Minimum number of training windows in each child (≥ 1).
    pub min_samples_leaf: usize,
    /// Minimum Gini decrease (parent minus size-weighted children, not scaled by the node's
    /// share of the data) for a split (> 0). Default 1e-7.
    pub min_impurity_decrease: f64,
}

impl Default for GiniTreeParams {
    fn default() -> Self {
        Self {
            max_depth: None,
            min_samples_split: 2,
            min_samples_leaf: 1,
            min_impurity_decrease: 1e-7,
        }
    }
}

impl GiniTreeParams {
    /// Check the ranges.
    ///
    /// # Errors
    /// [`ClassifyError::InvalidParameter`].
    pub fn validate(&self) -> Result<()> {
        if self.max_depth == Some(0) {
            return Err(ClassifyError::InvalidParameter {
                name: "max_depth",
                value: 0.0,
                reason: "must be >= 1",
            });
        }
        if self.min_samples_split < 2 {
            return Err(ClassifyError::InvalidParameter {
                name: "min_samples_split",
                value: self.min_samples_split as f64,
                reason: "must be >= 2",
            });
        }
        if self.min_samples_leaf < 1 {
            return Err(ClassifyError::InvalidParameter {
                name: "min_samples_leaf",
                value: 0.0,
                reason: "must be >= 1",
            });
        }
        if !(self.min_impurity_decrease.is_finite() && self.min_impurity_decrease > 0.0) {
            return Err(ClassifyError::InvalidParameter {
                name: "min_impurity_decrease",
                value: self.min_impurity_decrease,
                reason: "must be finite and > 0",
            });
        }
        Ok(())
    }
}

/// A node of a fitted [`GiniTree`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Node {
    /// Terminal node.
    Leaf {
        /// Predicted class (training majority, ties to the lowest index).
        class: usize,
        /// Training windows per class that reached this leaf.
        counts: Vec<usize>,
    },
    /// Internal node: `x[feature] <= threshold` goes left.
    Split {
        /// Feature (column) index.
        feature: usize,
        /// Threshold in original feature units.
        threshold: f64,
        /// Subtree for `x[feature] <= threshold`.
        left: Box<Node>,
        /// Subtree for `x[feature] > threshold`.
        right: Box<Node>,
    },
}

/// A fitted Gini decision tree with thresholds in original feature units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GiniTree {
    /// Root node.
    pub root: Node,
    /// Number of features expected per row.
    pub n_features: usize,
    /// Number of declared classes.
    pub n_classes: usize,
}

/// One comparison of a rule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Condition {
    /// Feature index.
    pub feature: usize,
    /// `true`: `x ≤ threshold`; `false`: `x > threshold`.
    pub at_most: bool,
    /// Threshold in original units.
    pub threshold: f64,
}

/// A root-to-leaf path, the form of eqs. 5.35–5.36 (conditions simplified to at most one lower
/// and one upper bound per feature).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Rule {
    /// Conjunction of conditions.
    pub conditions: Vec<Condition>,
    /// Class predicted by the leaf.
    pub class: usize,
    /// Training windows reaching the leaf.
    pub support: usize,
}

/// A rule with names, ready to print.
#[derive(Debug, Clone)]
pub struct NamedRule<'a> {
    rule: &'a Rule,
    feature_names: &'a [String],
    class_names: &'a [String],
}

fn fmt_num(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) {
        format!("{v:.6e}")
    } else {
        format!("{v:.6}")
    }
}

impl fmt::Display for NamedRule<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = |j: usize| {
            self.feature_names
                .get(j)
                .cloned()
                .unwrap_or_else(|| format!("x{j}"))
        };
        let class = self
            .class_names
            .get(self.rule.class)
            .cloned()
            .unwrap_or_else(|| format!("class {}", self.rule.class));
        if self.rule.conditions.is_empty() {
            return write!(f, "always -> {class} (n={})", self.rule.support);
        }
        let conds: Vec<String> = self
            .rule
            .conditions
            .iter()
            .map(|c| {
                let op = if c.at_most { "<=" } else { ">" };
                format!("{} {op} {}", name(c.feature), fmt_num(c.threshold))
            })
            .collect();
        write!(
            f,
            "if {} -> {class} (n={})",
            conds.join(" & "),
            self.rule.support
        )
    }
}

impl Rule {
    /// Attach names for printing.
    pub fn named<'a>(
        &'a self,
        feature_names: &'a [String],
        class_names: &'a [String],
    ) -> NamedRule<'a> {
        NamedRule {
            rule: self,
            feature_names,
            class_names,
        }
    }
}

/// The deterministic CART engine: recursive binary splitting on the Gini index (eq. 5.34).
///
/// Every decision is made in exact integer arithmetic on class counts, so a fit depends on
/// nothing but the data, the parameters and the order of the features.
struct Engine<'a> {
    /// Raw feature rows of the training windows.
    x: &'a [Vec<f64>],
    /// Class of each training window.
    y: &'a [usize],
    n_classes: usize,
    params: &'a GiniTreeParams,
}

/// The best split of a node found so far.
struct Best {
    feature: usize,
    /// Largest value going left.
    below: f64,
    /// Smallest value going right.
    above: f64,
    /// `Σ_k n_{L,k}² / n_L + Σ_k n_{R,k}² / n_R` as numerator / denominator.
    proxy_num: u128,
    proxy_den: u128,
}

/// `a/b > c/d` for positive denominators, exactly when the products fit in `u128`.
fn ratio_greater(a: u128, b: u128, c: u128, d: u128) -> bool {
    match (a.checked_mul(d), c.checked_mul(b)) {
        (Some(l), Some(r)) => l > r,
        // Beyond ~2·10⁷ windows per node: deterministic f64 comparison instead.
        _ => (a as f64 / b as f64) > (c as f64 / d as f64),
    }
}

/// Midpoint of two consecutive distinct values `a < b`, never equal to `b` (so `x ≤ t` keeps
/// exactly the values `≤ a` on the left).
fn midpoint(a: f64, b: f64) -> f64 {
    let mut t = 0.5 * (a + b);
    if !t.is_finite() {
        t = 0.5 * a + 0.5 * b;
    }
    if t >= b || t < a { a } else { t }
}

impl Engine<'_> {
    fn grow(&self, idx: &[usize], depth: usize) -> Node {
        let mut counts = vec![0usize; self.n_classes];
        for &i in idx {
            counts[self.y[i]] += 1;
        }
        let n = idx.len();
        let stop = n < self.params.min_samples_split
            || self.params.max_depth.is_some_and(|m| depth >= m)
            || counts.iter().filter(|&&c| c > 0).count() < 2;
        let best = if stop {
            None
        } else {
            self.best_split(idx, &counts)
        };
        let Some(best) = best else {
            return Node::Leaf {
                class: argmax_first(&counts),
                counts,
            };
        };
        // Gini decrease (parent − size-weighted children, as in linfa-trees):
        // (1 − S_P/n²) − (1 − proxy/n) = proxy/n − S_P/n².
        let nf = n as f64;
        let sp: u128 = counts.iter().map(|&c| (c as u128) * (c as u128)).sum();
        let decrease = best.proxy_num as f64 / best.proxy_den as f64 / nf - sp as f64 / (nf * nf);
        if decrease < self.params.min_impurity_decrease {
            return Node::Leaf {
                class: argmax_first(&counts),
                counts,
            };
        }
        let threshold = midpoint(best.below, best.above);
        let (li, ri): (Vec<usize>, Vec<usize>) = idx
            .iter()
            .partition(|&&i| self.x[i][best.feature] <= threshold);
        let left = self.grow(&li, depth + 1);
        let right = self.grow(&ri, depth + 1);
        merge_if_same(Node::Split {
            feature: best.feature,
            threshold,
            left: Box::new(left),
            right: Box::new(right),
        })
    }

    /// Scan features in index order and, per feature, the gaps between consecutive distinct
    /// sorted values in ascending order; keep a candidate only if strictly better. Ties go to
    /// the first feature, then the lowest threshold.
    fn best_split(&self, idx: &[usize], counts: &[usize]) -> Option<Best> {
        let n = idx.len();
        let min_leaf = self.params.min_samples_leaf;
        let d = self.x.first().map_or(0, Vec::len);
        let mut best: Option<Best> = None;
        let mut sorted: Vec<(f64, usize)> = Vec::with_capacity(n);
        for feature in 0..d {
            sorted.clear();
            sorted.extend(idx.iter().map(|&i| (self.x[i][feature], self.y[i])));
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut left = vec![0u64; self.n_classes];
            let mut right: Vec<u64> = counts.iter().map(|&c| c as u64).collect();
            let mut sl: u128 = 0;
            let mut sr: u128 = right.iter().map(|&c| u128::from(c) * u128::from(c)).sum();
            for k in 0..n - 1 {
                let c = sorted[k].1;
                sl += 2 * u128::from(left[c]) + 1;
                left[c] += 1;
                sr -= 2 * u128::from(right[c]) - 1;
                right[c] -= 1;
                // `==` (not total order): −0.0 and 0.0 are one value.
                if sorted[k].0 == sorted[k + 1].0 {
                    continue;
                }
                let nl = k + 1;
                let nr = n - nl;
                if nl < min_leaf || nr < min_leaf {
                    continue;
                }
                let (nl, nr) = (nl as u128, nr as u128);
                let num = sl * nr + sr * nl;
                let den = nl * nr;
                let better = best
                    .as_ref()
                    .is_none_or(|b| ratio_greater(num, den, b.proxy_num, b.proxy_den));
                if better {
                    best = Some(Best {
                        feature,
                        below: sorted[k].0,
                        above: sorted[k + 1].0,
                        proxy_num: num,
                        proxy_den: den,
                    });
                }
            }
        }
        best
    }
}

pub(crate) fn merge_if_same(node: Node) -> Node {
    if let Node::Split { left, right, .. } = &node {
        if let (
            Node::Leaf {
                class: a,
                counts: ca,
            },
            Node::Leaf {
                class: b,
                counts: cb,
            },
        ) = (left.as_ref(), right.as_ref())
        {
            if a == b {
                let counts: Vec<usize> = ca.iter().zip(cb).map(|(x, y)| x + y).collect();
                return Node::Leaf {
                    class: argmax_first(&counts),
                    counts,
                };
            }
        }
    }
    node
}

impl GiniTree {
    /// Train on the windows `train` of `data` (raw features) with the deterministic CART engine
    /// described in the module docs: the result depends only on the data and the parameters,
    /// bit for bit, in every process.
    ///
    /// # Errors
    /// Invalid parameters, empty/out-of-range indices, [`ClassifyError::SingleClass`].
    pub fn fit(params: &GiniTreeParams, data: &Dataset, train: &[usize]) -> Result<Self> {
        params.validate()?;
        data.check_indices(train, "training indices")?;
        let x: Vec<Vec<f64>> = train.iter().map(|&i| data.row(i).to_vec()).collect();
        let y: Vec<usize> = train.iter().map(|&i| data.label(i)).collect();
        let first = y[0];
        if y.iter().all(|&c| c == first) {
            return Err(ClassifyError::SingleClass { class: first });
        }
        let engine = Engine {
            x: &x,
            y: &y,
            n_classes: data.n_classes(),
            params,
        };
        let all: Vec<usize> = (0..y.len()).collect();
        Ok(Self {
            root: engine.grow(&all, 0),
            n_features: data.n_features(),
            n_classes: data.n_classes(),
        })
    }

    /// Predicted class of one raw feature row.
    ///
    /// # Errors
    /// [`ClassifyError::LengthMismatch`], [`ClassifyError::NonFinite`].
    pub fn predict_row(&self, row: &[f64]) -> Result<usize> {
        check_row(row, self.n_features)?;
        let mut node = &self.root;
        loop {
            match node {
                Node::Leaf { class, .. } => return Ok(*class),
                Node::Split {
                    feature,
                    threshold,
                    left,
                    right,
                } => {
                    node = if row[*feature] <= *threshold {
                        left
                    } else {
                        right
                    };
                }
            }
        }
    }

    /// Sorted thresholds used on `feature` (the ζ of eqs. 5.35–5.36 for a 1-D energy tree).
    pub fn thresholds(&self, feature: usize) -> Vec<f64> {
        fn walk(n: &Node, f: usize, out: &mut Vec<f64>) {
            if let Node::Split {
                feature,
                threshold,
                left,
                right,
            } = n
            {
                if *feature == f {
                    out.push(*threshold);
                }
                walk(left, f, out);
                walk(right, f, out);
            }
        }
        let mut out = Vec::new();
        walk(&self.root, feature, &mut out);
        out.sort_by(f64::total_cmp);
        out
    }

    /// Number of leaves.
    pub fn n_leaves(&self) -> usize {
        fn count(n: &Node) -> usize {
            match n {
                Node::Leaf { .. } => 1,
                Node::Split { left, right, .. } => count(left) + count(right),
            }
        }
        count(&self.root)
    }

    /// The tree as rules (eqs. 5.35–5.36), one per leaf, left to right.
    pub fn rules(&self) -> Vec<Rule> {
        fn walk(n: &Node, path: &mut Vec<Condition>, out: &mut Vec<Rule>) {
            match n {
                Node::Leaf { class, counts } => out.push(Rule {
                    conditions: simplify(path),
                    class: *class,
                    support: counts.iter().sum(),
                }),
                Node::Split {
                    feature,
                    threshold,
                    left,
                    right,
                } => {
                    path.push(Condition {
                        feature: *feature,
                        at_most: true,
                        threshold: *threshold,
                    });
                    walk(left, path, out);
                    path.pop();
                    path.push(Condition {
                        feature: *feature,
                        at_most: false,
                        threshold: *threshold,
                    });
                    walk(right, path, out);
                    path.pop();
                }
            }
        }
        let mut out = Vec::new();
        walk(&self.root, &mut Vec::new(), &mut out);
        out
    }
}

/// Keep the tightest lower (`>`) and upper (`≤`) bound per feature, lower bound first.
fn simplify(path: &[Condition]) -> Vec<Condition> {
    let mut features: Vec<usize> = path.iter().map(|c| c.feature).collect();
    features.sort_unstable();
    features.dedup();
    let mut out = Vec::new();
    for f in features {
        let lower = path
            .iter()
            .filter(|c| c.feature == f && !c.at_most)
            .map(|c| c.threshold)
            .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.max(t))));
        let upper = path
            .iter()
            .filter(|c| c.feature == f && c.at_most)
            .map(|c| c.threshold)
            .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.min(t))));
        if let Some(t) = lower {
            out.push(Condition {
                feature: f,
                at_most: false,
                threshold: t,
            });
        }
        if let Some(t) = upper {
            out.push(Condition {
                feature: f,
                at_most: true,
                threshold: t,
            });
        }
    }
    out
}
