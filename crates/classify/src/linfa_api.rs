//! linfa's `Fit` / `Predict` for this crate's models, so they read like any linfa model to a linfa
//! user: the parameters fit a `linfa::DatasetBase` of `f64` records and `usize` class targets, and
//! the fitted model predicts an `Array1<usize>` from a records matrix (or a dataset, whose targets
//! it fills), ready for linfa's `confusion_matrix`.
//!
//! The crate's own API ([`OvoLinearSvm::fit`], [`GiniTree::fit`] on a [`Dataset`] with window
//! metadata and the evaluation protocols) stays the primary one; this layer converts at the edge:
//! a linfa dataset becomes a [`Dataset`] with one recording per window (the protocols' metadata
//! is not part of a linfa dataset), class `k` named `"k"`, and every row is checked as the crate
//! checks its own (finite; positive under [`crate::FeatureTransform::Log10`]).
//!
//! linfa's prediction trait has no error path: a records matrix of another width than the model
//! was trained on, or a row with a non-finite feature, makes `predict` panic with a one-line
//! message (linfa's own models assert the width the same way). Where the records come from data
//! rather than from the caller's own code, use [`OvoLinearSvm::predict_records`] /
//! [`GiniTree::predict_records`], which return a [`ClassifyError`] instead.
//!
//! ```
//! use classify::{GiniTreeParams, LinearSvmParams};
//! use linfa::prelude::*;
//! use ndarray::{Array1, Array2};
//!
//! // two classes on one feature, as linfa takes them
//! let x = Array2::from_shape_fn((40, 1), |(i, _)| if i < 20 { i as f64 * 0.01 } else { 5.0 + i as f64 * 0.01 });
//! let y = Array1::from_shape_fn(40, |i| usize::from(i >= 20));
//! let data = DatasetBase::new(x, y);
//!
//! let svm = LinearSvmParams::default().fit(&data)?;
//! let tree = GiniTreeParams::default().fit(&data)?;
//! for predicted in [svm.predict(&data), tree.predict(&data)] {
//!     let cm = predicted.confusion_matrix(&data)?;
//!     assert_eq!(cm.accuracy(), 1.0);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use linfa::dataset::{AsSingleTargets, DatasetBase};
use linfa::traits::{Fit, PredictInplace};
use ndarray::{Array1, ArrayBase, Data, Ix2};

use crate::{ClassifyError, Dataset, GiniTree, GiniTreeParams, LinearSvmParams, OvoLinearSvm};
use crate::{Result, WindowMeta};

/// A linfa dataset (records `n × d`, one `usize` class per record) as a [`Dataset`] whose
/// classes are `0..=max(target)`, named by their index, each window its own recording.
fn to_dataset<D, T>(data: &DatasetBase<ArrayBase<D, Ix2>, T>) -> Result<Dataset>
where
    D: Data<Elem = f64>,
    T: AsSingleTargets<Elem = usize>,
{
    let targets = data.as_single_targets();
    let x = &data.records;
    if targets.len() != x.nrows() {
        return Err(ClassifyError::LengthMismatch {
            what: "targets vs records",
            expected: x.nrows(),
            found: targets.len(),
        });
    }
    let n_classes = targets.iter().max().map_or(0, |&m| m + 1);
    let class_names = (0..n_classes).map(|k| k.to_string()).collect();
    let feature_names = (0..x.ncols()).map(|j| format!("x{j}")).collect();
    let rows: Vec<Vec<f64>> = x.rows().into_iter().map(|r| r.to_vec()).collect();
    let meta = targets
        .iter()
        .enumerate()
        .map(|(i, &class)| WindowMeta {
            class,
            recording: i.to_string(),
            load_hp: 0,
            fault_size_mils: None,
            speed_rpm: None,
            index_in_recording: 0,
        })
        .collect();
    Dataset::new(class_names, feature_names, &rows, meta)
}

impl<D, T> Fit<ArrayBase<D, Ix2>, T, ClassifyError> for LinearSvmParams
where
    D: Data<Elem = f64>,
    T: AsSingleTargets<Elem = usize>,
{
    type Object = OvoLinearSvm;

    /// [`OvoLinearSvm::fit`] on every record of `dataset`.
    fn fit(&self, dataset: &DatasetBase<ArrayBase<D, Ix2>, T>) -> Result<OvoLinearSvm> {
        let data = to_dataset(dataset)?;
        let all: Vec<usize> = (0..data.n_samples()).collect();
        OvoLinearSvm::fit(self, &data, &all)
    }
}

impl<D, T> Fit<ArrayBase<D, Ix2>, T, ClassifyError> for GiniTreeParams
where
    D: Data<Elem = f64>,
    T: AsSingleTargets<Elem = usize>,
{
    type Object = GiniTree;

    /// [`GiniTree::fit`] on every record of `dataset`.
    fn fit(&self, dataset: &DatasetBase<ArrayBase<D, Ix2>, T>) -> Result<GiniTree> {
        let data = to_dataset(dataset)?;
        let all: Vec<usize> = (0..data.n_samples()).collect();
        GiniTree::fit(self, &data, &all)
    }
}

/// Each row's class by `predict_row`, or the first row's error.
fn predict_rows<D: Data<Elem = f64>>(
    x: &ArrayBase<D, Ix2>,
    predict_row: impl Fn(&[f64]) -> Result<usize>,
) -> Result<Array1<usize>> {
    let mut out = Array1::zeros(x.nrows());
    for (i, r) in x.rows().into_iter().enumerate() {
        out[i] = predict_row(&r.to_vec()).map_err(|e| match e {
            ClassifyError::NonFinite { column, value, .. } => ClassifyError::NonFinite {
                row: i,
                column,
                value,
            },
            ClassifyError::NonPositive { column, value, .. } => ClassifyError::NonPositive {
                row: i,
                column,
                value,
            },
            other => other,
        })?;
    }
    Ok(out)
}

impl OvoLinearSvm {
    /// The class of every row of `x` (linfa's `predict` with a typed error instead of a panic).
    ///
    /// # Errors
    /// As [`OvoLinearSvm::votes`], with the row index of the first row that cannot be classified.
    pub fn predict_records<D: Data<Elem = f64>>(
        &self,
        x: &ArrayBase<D, Ix2>,
    ) -> Result<Array1<usize>> {
        predict_rows(x, |r| self.predict_row(r))
    }
}

impl GiniTree {
    /// The class of every row of `x` (linfa's `predict` with a typed error instead of a panic).
    ///
    /// # Errors
    /// As [`GiniTree::predict_row`], with the row index of the first row that cannot be
    /// classified.
    pub fn predict_records<D: Data<Elem = f64>>(
        &self,
        x: &ArrayBase<D, Ix2>,
    ) -> Result<Array1<usize>> {
        predict_rows(x, |r| self.predict_row(r))
    }
}

impl<D: Data<Elem = f64>> PredictInplace<ArrayBase<D, Ix2>, Array1<usize>> for OvoLinearSvm {
    /// # Panics
    /// When a row cannot be classified (width, non-finite feature): linfa's trait has no error
    /// path; [`OvoLinearSvm::predict_records`] returns the error instead.
    fn predict_inplace(&self, x: &ArrayBase<D, Ix2>, y: &mut Array1<usize>) {
        match self.predict_records(x) {
            Ok(p) => y.assign(&p),
            Err(e) => panic!("OvoLinearSvm::predict: {e}"),
        }
    }

    fn default_target(&self, x: &ArrayBase<D, Ix2>) -> Array1<usize> {
        Array1::zeros(x.nrows())
    }
}

impl<D: Data<Elem = f64>> PredictInplace<ArrayBase<D, Ix2>, Array1<usize>> for GiniTree {
    /// # Panics
    /// When a row cannot be classified (width, non-finite feature): linfa's trait has no error
    /// path; [`GiniTree::predict_records`] returns the error instead.
    fn predict_inplace(&self, x: &ArrayBase<D, Ix2>, y: &mut Array1<usize>) {
        match self.predict_records(x) {
            Ok(p) => y.assign(&p),
            Err(e) => panic!("GiniTree::predict: {e}"),
        }
    }

    fn default_target(&self, x: &ArrayBase<D, Ix2>) -> Array1<usize> {
        Array1::zeros(x.nrows())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FeatureTransform;
    use linfa::prelude::*;
    use ndarray::{Array2, array};

    fn three_classes() -> linfa::Dataset<f64, usize, ndarray::Ix1> {
        let x = Array2::from_shape_fn((60, 2), |(i, j)| {
            let c = (i / 20) as f64;
            1.0 + 3.0 * c + 0.05 * ((i * 7 + j * 3) % 11) as f64
        });
        let y = Array1::from_shape_fn(60, |i| i / 20);
        linfa::DatasetBase::new(x, y)
    }

    #[test]
    fn linfa_fit_equals_the_crate_fit_on_the_same_rows() {
        let data = three_classes();
        let own = to_dataset(&data).unwrap();
        let all: Vec<usize> = (0..own.n_samples()).collect();
        let svm = LinearSvmParams::default().fit(&data).unwrap();
        assert_eq!(
            svm,
            OvoLinearSvm::fit(&LinearSvmParams::default(), &own, &all).unwrap()
        );
        let tree = GiniTreeParams::default().fit(&data).unwrap();
        assert_eq!(
            tree,
            GiniTree::fit(&GiniTreeParams::default(), &own, &all).unwrap()
        );
        let p = svm.predict(&data);
        assert_eq!(p.confusion_matrix(&data).unwrap().accuracy(), 1.0);
        assert_eq!(tree.predict(data.records()), *data.targets());
    }

    #[test]
    fn bad_records_are_typed_errors_on_the_checked_path() {
        let data = three_classes();
        let tree = GiniTreeParams::default().fit(&data).unwrap();
        let bad = array![[1.0, 2.0], [f64::NAN, 1.0]];
        assert!(matches!(
            tree.predict_records(&bad),
            Err(ClassifyError::NonFinite {
                row: 1,
                column: 0,
                ..
            })
        ));
        let narrow = array![[1.0]];
        assert!(matches!(
            tree.predict_records(&narrow),
            Err(ClassifyError::LengthMismatch { .. })
        ));
        // fitting: a non-finite record, a single class, a log of a non-positive feature
        let x = array![[1.0], [f64::INFINITY]];
        let one = linfa::DatasetBase::new(x, array![0usize, 1]);
        assert!(matches!(
            GiniTreeParams::default().fit(&one),
            Err(ClassifyError::NonFinite { .. })
        ));
        let single = linfa::DatasetBase::new(array![[1.0], [2.0]], array![1usize, 1]);
        assert!(matches!(
            LinearSvmParams::default().fit(&single),
            Err(ClassifyError::SingleClass { class: 1 })
        ));
        let zero = linfa::DatasetBase::new(array![[0.0], [2.0]], array![0usize, 1]);
        let log = LinearSvmParams::default().with_transform(FeatureTransform::Log10);
        assert!(matches!(
            log.fit(&zero),
            Err(ClassifyError::NonPositive { row: 0, .. })
        ));
    }

    #[test]
    #[should_panic(expected = "GiniTree::predict")]
    fn the_trait_path_panics_with_a_message_on_a_bad_row() {
        let tree = GiniTreeParams::default().fit(&three_classes()).unwrap();
        let _ = tree.predict(&array![[f64::NAN, 1.0]]);
    }
}
