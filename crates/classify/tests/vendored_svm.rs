//! The vendored linfa-svm's one-feature fast path (vendor/README.md) changes no bit of a solution.
//!
//! With one feature, the patched `PermutableKernel` reads the kernel's records in the solver's
//! order instead of building a column and gathering it. The reference is the upstream path:
//! the same records with a second feature that is exactly `+0.0`, whose kernel entries
//! `(0 + x_i·x_j) + 0·0` equal the one-feature entries `0 + x_i·x_j` bit for bit (signed zeros
//! included), so the SMO solver must take the same steps and return the same bits.

use linfa::prelude::*;
use linfa_svm::Svm;
use ndarray::{Array1, Array2};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Overlapping classes (many bounded alphas, many solver steps), a few exact zeros and
/// negative zeros, and ties.
fn problem(seed: u64, n: usize) -> (Array2<f64>, Array1<bool>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = Array2::<f64>::zeros((n, 1));
    let mut y = Array1::<bool>::from_elem(n, false);
    for i in 0..n {
        let positive = rng.random::<f64>() < 0.4;
        let centre = if positive { 0.6 } else { -0.4 };
        let v: f64 = centre + rng.random::<f64>() * 2.0 - 1.0;
        x[[i, 0]] = match i % 37 {
            0 => 0.0,
            1 => -0.0,
            2 => 0.25,
            _ => v,
        };
        y[i] = positive;
    }
    (x, y)
}

fn fit(x: Array2<f64>, y: Array1<bool>, c: (f64, f64)) -> Svm<f64, bool> {
    Svm::<f64, bool>::params()
        .pos_neg_weights(c.0, c.1)
        .eps(1e-3)
        .linear_kernel()
        .fit(&Dataset::new(x, y))
        .expect("a feasible problem")
}

#[test]
fn the_one_feature_fast_path_returns_the_upstream_solution_bit_for_bit() {
    for (seed, n, c) in [
        (1, 300, (1.0, 1.0)),
        (2, 801, (0.7, 2.3)),
        (3, 64, (10.0, 10.0)),
    ] {
        let (x, y) = problem(seed, n);
        let mut x2 = Array2::<f64>::zeros((n, 2));
        x2.column_mut(0).assign(&x.column(0));
        let fast = fit(x.clone(), y.clone(), c);
        let reference = fit(x2, y.clone(), c);

        assert_eq!(fast.alpha.len(), n);
        let bits = |a: &[f64]| a.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&fast.alpha),
            bits(&reference.alpha),
            "seed {seed}: alphas differ"
        );
        assert_eq!(fast.rho.to_bits(), reference.rho.to_bits(), "seed {seed}");
        // Not a trivial solution: some alphas free, some at a bound.
        let bound = |a: f64| a > 0.0 && a < c.0.min(c.1);
        assert!(fast.alpha.iter().any(|&a| bound(a)), "seed {seed}");
        assert!(fast.nsupport() > 2, "seed {seed}");
        // The same decisions.
        let probe = Array1::from_vec(vec![0.1]);
        let probe2 = Array1::from_vec(vec![0.1, 0.0]);
        assert_eq!(
            fast.weighted_sum(&probe).to_bits(),
            reference.weighted_sum(&probe2).to_bits()
        );
    }
}
