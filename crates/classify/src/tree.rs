//! Gini decision tree (Piltan 2020, ch. 5: eq. 5.34 split criterion, rules of eqs. 5.35–5.36) on
//! `linfa-trees`.
//!
//! The split search is linfa-trees' CART with the Gini diversity index
//! `GDI = 1 − Σ_k p_k²` (eq. 5.34). The fitted tree is then converted into a small serde-friendly
//! [`GiniTree`] whose thresholds are in the original feature units, so the learned rules read like
//! eqs. 5.35–5.36 ("if E ≤ ζ_n → Normal …"). Three corrections to linfa-trees 0.8.1 are applied
//! during the conversion (see `docs/equations/classify.md`):
//! 1. linfa fits on standardised features, because it treats values closer than 1e-5 (absolute)
//!    as equal, which would merge distinct raw energies;
//! 2. each threshold is recomputed as the midpoint between the largest training value that goes
//!    left and the smallest that goes right *within the node* (the CART/scikit-learn rule; linfa
//!    uses the next value in the global sort order, which may belong to another node);
//! 3. leaf classes are recomputed from the training counts with ties to the lowest class index
//!    (linfa breaks ties in HashMap order, which varies run to run), and sibling leaves that now
//!    agree are merged.

use std::fmt;

use linfa::prelude::*;
use linfa_trees::{DecisionTree, SplitQuality, TreeNode as LinfaNode};
use ndarray::{Array1, Array2};
use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::{ClassifyError, Result};
use crate::scale::Standardizer;
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
    /// Minimum Gini decrease for a split (> 0; linfa requires it positive). Default 1e-7.
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

struct Ctx<'a> {
    z: &'a [Vec<f64>],
    raw: &'a [Vec<f64>],
    y: &'a [usize],
    n_classes: usize,
}

impl Ctx<'_> {
    fn leaf(&self, idx: &[usize]) -> Node {
        let mut counts = vec![0; self.n_classes];
        for &i in idx {
            counts[self.y[i]] += 1;
        }
        Node::Leaf {
            class: argmax_first(&counts),
            counts,
        }
    }

    fn convert(&self, node: &LinfaNode<f64, usize>, idx: &[usize]) -> Node {
        if node.is_leaf() {
            return self.leaf(idx);
        }
        let children = node.children();
        let (Some(l), Some(r)) = (children[0].as_ref(), children[1].as_ref()) else {
            return self.leaf(idx);
        };
        let (feature, thr, _) = node.split();
        let (li, ri): (Vec<usize>, Vec<usize>) =
            idx.iter().partition(|&&i| self.z[i][feature] <= thr);
        if li.is_empty() || ri.is_empty() {
            return self.leaf(idx);
        }
        let lmax = li
            .iter()
            .map(|&i| self.raw[i][feature])
            .fold(f64::NEG_INFINITY, f64::max);
        let rmin = ri
            .iter()
            .map(|&i| self.raw[i][feature])
            .fold(f64::INFINITY, f64::min);
        let mut threshold = 0.5 * (lmax + rmin);
        if threshold >= rmin {
            threshold = lmax; // rounding when lmax and rmin are adjacent floats
        }
        let left = self.convert(l, &li);
        let right = self.convert(r, &ri);
        merge_if_same(Node::Split {
            feature,
            threshold,
            left: Box::new(left),
            right: Box::new(right),
        })
    }
}

fn merge_if_same(node: Node) -> Node {
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
    /// Train on the windows `train` of `data` (raw features; see the module docs for the
    /// standardisation used internally).
    ///
    /// # Errors
    /// Invalid parameters, empty/out-of-range indices, [`ClassifyError::SingleClass`], linfa errors.
    pub fn fit(params: &GiniTreeParams, data: &Dataset, train: &[usize]) -> Result<Self> {
        params.validate()?;
        data.check_indices(train, "training indices")?;
        let d = data.n_features();
        let scaler = Standardizer::fit(data, train)?;
        let raw: Vec<Vec<f64>> = train.iter().map(|&i| data.row(i).to_vec()).collect();
        let z: Vec<Vec<f64>> = raw.iter().map(|r| scaler.transform(r)).collect();
        let y: Vec<usize> = train.iter().map(|&i| data.label(i)).collect();
        let first = y[0];
        if y.iter().all(|&c| c == first) {
            return Err(ClassifyError::SingleClass { class: first });
        }
        let mut x = Array2::<f64>::zeros((z.len(), d));
        for (r, row) in z.iter().enumerate() {
            for (k, v) in row.iter().enumerate() {
                x[[r, k]] = *v;
            }
        }
        let ds = linfa::Dataset::new(x, Array1::from(y.clone()));
        let model = DecisionTree::<f64, usize>::params()
            .split_quality(SplitQuality::Gini)
            .max_depth(params.max_depth)
            .min_weight_split(params.min_samples_split as f32)
            .min_weight_leaf(params.min_samples_leaf as f32)
            .min_impurity_decrease(params.min_impurity_decrease)
            .fit(&ds)?;
        let ctx = Ctx {
            z: &z,
            raw: &raw,
            y: &y,
            n_classes: data.n_classes(),
        };
        let all: Vec<usize> = (0..y.len()).collect();
        let root = ctx.convert(model.root_node(), &all);
        Ok(Self {
            root,
            n_features: d,
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
