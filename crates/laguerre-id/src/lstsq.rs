//! Linear least squares on tall regression matrices (faer column-pivoted QR).

use crate::error::{IdentError, Result};
use faer::Mat;
use faer::linalg::solvers::SolveLstsq;

/// Relative threshold on |R_ii| / |R_00| below which a column counts as dependent.
const RANK_TOL: f64 = 1e-11;

/// Solve min ‖Φθ − t‖² for θ. `rows` yields the regression rows; `p` is the number of columns.
pub(crate) fn solve(
    rows: usize,
    p: usize,
    fill: impl Fn(usize, usize) -> f64,
    t: &[f64],
) -> Result<Vec<f64>> {
    if rows < p {
        return Err(IdentError::TooFewSamples {
            found: rows,
            needed: p,
        });
    }
    let phi = Mat::from_fn(rows, p, fill);
    let rhs = Mat::from_fn(rows, 1, |i, _| t[i]);
    let qr = phi.col_piv_qr();
    let r = qr.thin_R();
    let r00 = r[(0, 0)].abs();
    let rank = (0..p)
        .filter(|&i| r[(i, i)].abs() > RANK_TOL * r00.max(f64::MIN_POSITIVE))
        .count();
    if r00 == 0.0 || rank < p {
        return Err(IdentError::RankDeficient {
            rank: if r00 == 0.0 { 0 } else { rank },
            columns: p,
        });
    }
    let sol = qr.solve_lstsq(&rhs);
    let theta: Vec<f64> = (0..p).map(|i| sol[(i, 0)]).collect();
    if theta.iter().any(|v| !v.is_finite()) {
        return Err(IdentError::RankDeficient {
            rank: 0,
            columns: p,
        });
    }
    Ok(theta)
}

/// Residual sum of squares ‖Φθ − t‖² via the normal equations (Cholesky, faer): used inside the
/// pole search, where only the cost matters. `gram` is ΦᵀΦ (p×p, row-major), `rhs` is Φᵀt, `tt`
/// is tᵀt. Returns `None` when ΦᵀΦ is not positive definite.
pub(crate) fn normal_rss(p: usize, gram: &[f64], rhs: &[f64], tt: f64) -> Option<f64> {
    use faer::linalg::solvers::Solve;
    let g = Mat::from_fn(p, p, |i, j| gram[i * p + j]);
    let b = Mat::from_fn(p, 1, |i, _| rhs[i]);
    let llt = g.llt(faer::Side::Lower).ok()?;
    let x = llt.solve(&b);
    // rss = tᵀt − θᵀΦᵀt at the optimum.
    let fit: f64 = (0..p).map(|i| x[(i, 0)] * rhs[i]).sum();
    let rss = tt - fit;
    rss.is_finite().then_some(rss.max(0.0))
}
