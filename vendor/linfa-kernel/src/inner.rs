use linfa::Float;
use ndarray::prelude::*;
use ndarray::Data;
use sprs::{CsMat, CsMatView};
use std::ops::Mul;

/// Specifies the methods an inner matrix of a kernel must
/// be able to provide
pub trait Inner {
    type Elem: Float;

    fn dot(&self, rhs: &ArrayView2<Self::Elem>) -> Array2<Self::Elem>;
    fn sum(&self) -> Array1<Self::Elem>;
    fn size(&self) -> usize;
    fn column(&self, i: usize) -> Vec<Self::Elem>;
    fn to_upper_triangle(&self) -> Vec<Self::Elem>;
    fn is_dense(&self) -> bool;
    fn diagonal(&self) -> Array1<Self::Elem>;
}

/// Allows a kernel to have either a dense or a sparse inner
/// matrix in a way that is transparent to the user
#[derive(Debug, Clone, PartialEq)]
pub enum KernelInner<K1: Inner, K2: Inner> {
    Dense(K1),
    Sparse(K2),
    /// hybrid-fdd patch (see vendor/README.md): a dense linear kernel kept as its records,
    /// every entry computed when it is read.
    Linear(LinearRows<K1::Elem>),
}

/// hybrid-fdd patch (see vendor/README.md): the dense linear kernel `K = X·Xᵀ` of `n` records of
/// `d` features, held as the records (n·d numbers instead of n²). An entry is computed when read,
/// with the same products and summation order as [`crate::KernelMethod::distance`], so every
/// entry equals the materialised dense kernel's bit for bit. The SMO solver reads a few
/// columns per iteration; on the one-feature problems of hybrid-fdd's chapters building all n²
/// entries up front was a fifth to a third of the CPU time.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearRows<F> {
    rows: Vec<F>,
    n: usize,
    d: usize,
}

impl<F: Float> LinearRows<F> {
    /// The kernel of the records `x` (one per row).
    pub fn new<D: Data<Elem = F>>(x: &ArrayBase<D, Ix2>) -> Self {
        Self {
            rows: x.iter().copied().collect(),
            n: x.nrows(),
            d: x.ncols(),
        }
    }

    /// The records when there is one feature (see `Kernel::single_feature_linear`).
    pub fn single_feature(&self) -> Option<&[F]> {
        (self.d == 1).then_some(self.rows.as_slice())
    }

    fn row(&self, i: usize) -> &[F] {
        &self.rows[i * self.d..(i + 1) * self.d]
    }

    /// Entry (i, j), with `buf` of length d as scratch.
    #[inline]
    fn entry(&self, i: usize, j: usize, buf: &mut [F]) -> F {
        crate::products_into(buf, self.row(i), self.row(j));
        crate::unrolled_sum(buf)
    }

    /// The materialised matrix (for the rarely used whole-matrix operations): the dense
    /// kernel `Kernel::new` would otherwise have built.
    fn to_dense(&self) -> Array2<F> {
        let x = ArrayView2::from_shape((self.n, self.d), &self.rows)
            .expect("n × d records for an n × d shape");
        crate::dense_from_fn(&x, &crate::KernelMethod::Linear)
    }
}

impl<F: Float> Inner for LinearRows<F> {
    type Elem = F;

    fn dot(&self, rhs: &ArrayView2<F>) -> Array2<F> {
        self.to_dense().dot(rhs)
    }
    fn sum(&self) -> Array1<F> {
        self.to_dense().sum_axis(Axis(1))
    }
    fn size(&self) -> usize {
        self.n
    }
    fn column(&self, i: usize) -> Vec<F> {
        if self.d == 1 {
            // One feature: `unrolled_sum(&[x_j·x_i])` is `0 + x_j·x_i` (so a product of −0
            // comes out +0, as upstream's sum makes it); written out so the column vectorises
            // like the copy of a materialised one.
            let xi = self.rows[i];
            return self.rows.iter().map(|&xj| F::zero() + xj * xi).collect();
        }
        let mut buf = vec![F::zero(); self.d];
        (0..self.n).map(|j| self.entry(j, i, &mut buf)).collect()
    }
    fn to_upper_triangle(&self) -> Vec<F> {
        let mut buf = vec![F::zero(); self.d];
        let mut out = Vec::with_capacity(self.n * self.n.saturating_sub(1) / 2);
        for i in 0..self.n {
            for j in i + 1..self.n {
                out.push(self.entry(i, j, &mut buf));
            }
        }
        out
    }
    fn diagonal(&self) -> Array1<F> {
        let mut buf = vec![F::zero(); self.d];
        Array1::from_iter((0..self.n).map(|i| self.entry(i, i, &mut buf)))
    }
    fn is_dense(&self) -> bool {
        true
    }
}

impl<F: Float, D: Data<Elem = F>> Inner for ArrayBase<D, Ix2> {
    type Elem = F;

    fn dot(&self, rhs: &ArrayView2<F>) -> Array2<F> {
        self.dot(rhs)
    }
    fn sum(&self) -> Array1<F> {
        self.sum_axis(Axis(1))
    }
    fn size(&self) -> usize {
        self.ncols()
    }
    fn column(&self, i: usize) -> Vec<F> {
        self.column(i).to_vec()
    }
    fn to_upper_triangle(&self) -> Vec<F> {
        self.indexed_iter()
            .filter(|((row, col), _)| col > row)
            .map(|(_, val)| *val)
            .collect()
    }

    fn diagonal(&self) -> Array1<F> {
        self.diag().to_owned()
    }

    fn is_dense(&self) -> bool {
        true
    }
}

impl<F: Float> Inner for CsMat<F> {
    type Elem = F;

    fn dot(&self, rhs: &ArrayView2<F>) -> Array2<F> {
        self.mul(rhs)
    }
    fn sum(&self) -> Array1<F> {
        let mut sum = Array1::zeros(self.cols());
        for (val, i) in self.iter() {
            let (_, col) = i;
            sum[col] += *val;
        }

        sum
    }
    fn size(&self) -> usize {
        self.cols()
    }
    fn column(&self, i: usize) -> Vec<F> {
        (0..self.size())
            .map(|j| *self.get(j, i).unwrap_or(&F::neg_zero()))
            .collect::<Vec<_>>()
    }
    fn to_upper_triangle(&self) -> Vec<F> {
        let mat = self.to_dense();
        mat.indexed_iter()
            .filter(|((row, col), _)| col > row)
            .map(|(_, val)| *val)
            .collect()
    }

    fn diagonal(&self) -> Array1<F> {
        let diag_sprs = self.diag();
        let mut diag = Array1::zeros(diag_sprs.dim());
        for (sparse_i, sparse_elem) in diag_sprs.iter() {
            diag[sparse_i] = *sparse_elem;
        }
        diag
    }

    fn is_dense(&self) -> bool {
        false
    }
}

impl<F: Float> Inner for CsMatView<'_, F> {
    type Elem = F;

    fn dot(&self, rhs: &ArrayView2<F>) -> Array2<F> {
        self.mul(rhs)
    }
    fn sum(&self) -> Array1<F> {
        let mut sum = Array1::zeros(self.cols());
        for (val, i) in self.iter() {
            let (_, col) = i;
            sum[col] += *val;
        }

        sum
    }
    fn size(&self) -> usize {
        self.cols()
    }
    fn column(&self, i: usize) -> Vec<F> {
        (0..self.size())
            .map(|j| *self.get(j, i).unwrap_or(&F::neg_zero()))
            .collect::<Vec<_>>()
    }
    fn to_upper_triangle(&self) -> Vec<F> {
        let mat = self.to_dense();
        mat.indexed_iter()
            .filter(|((row, col), _)| col > row)
            .map(|(_, val)| *val)
            .collect()
    }
    fn diagonal(&self) -> Array1<F> {
        let diag_sprs = self.diag();
        let mut diag = Array1::zeros(diag_sprs.dim());
        for (sparse_i, sparse_elem) in diag_sprs.iter() {
            diag[sparse_i] = *sparse_elem;
        }
        diag
    }
    fn is_dense(&self) -> bool {
        false
    }
}
