//! One-step prediction of the three model families side by side — ARX (eq. 5.5), ARX-Laguerre
//! (eq. 4.11) and fuzzy ARX-Laguerre (eq. 5.19) — plus an ARX with 8× the lags as a reference
//! (is the Laguerre gain only memory length?), fitted on one segment and scored on another: the
//! comparison of the dissertation's Figs 5.2 and 5.3.

use laguerre_id::{ArxLaguerreConfig, ArxModel, ArxOrders, FitMetrics, PoleChoice};

use crate::{FalConfig, FuzzyArxLaguerre, Result};

/// One scored predictor.
#[derive(Debug, Clone, PartialEq)]
pub struct PredictorScore {
    /// "ARX", "ARX (8× lags)", "ARX-Laguerre" or "fuzzy ARX-Laguerre".
    pub model: &'static str,
    /// Orders and identified poles / fuzzy coefficients, for reports.
    pub params: String,
    /// Fit metrics on the scored segment.
    pub metrics: FitMetrics,
}

/// Fit the four predictors on `y[..fit_len]` (and `u`, when given, as the exogenous input with
/// `n_b` lags / Laguerre functions) with output order `n_a`, run them over the whole record and
/// score the one-step prediction on `y[test]`. Poles by the prediction-error search
/// ([`PoleChoice::DEFAULT_SEARCH`]); fuzzy term as [`FalConfig::with_base`].
///
/// # Errors
/// Any identification or metric error (too short a segment, orders out of range, a range
/// outside `y`, non-finite data).
pub fn compare_predictors(
    y: &[f64],
    u: Option<&[f64]>,
    n_a: usize,
    n_b: usize,
    fit_len: usize,
    test: std::ops::Range<usize>,
) -> Result<Vec<PredictorScore>> {
    let fit_y = y
        .get(..fit_len)
        .ok_or(laguerre_id::IdentError::TooFewSamples {
            found: y.len(),
            needed: fit_len,
        })?;
    let fit_u = u.and_then(|u| u.get(..fit_len));
    let target = y
        .get(test.clone())
        .ok_or(laguerre_id::IdentError::TooFewSamples {
            found: y.len(),
            needed: test.end,
        })?;
    let score = |pred: Vec<f64>| FitMetrics::compute(target, &pred[test.clone()]);
    let mut out = Vec::with_capacity(4);
    let arx = ArxModel::identify(fit_y, fit_u, ArxOrders::new(n_a, n_b)?)?;
    out.push(PredictorScore {
        model: "ARX",
        params: format!("n_a={n_a} n_b={n_b}"),
        metrics: score(arx.predict(y, u)?)?,
    });
    // Input lags grow with the output's only for a broadband input (n_b > 2); a sinusoid and its
    // lags span two dimensions, so more lags would be rank deficient.
    let (hi_a, hi_b) = (8 * n_a, if n_b > 2 { 8 * n_b } else { n_b });
    let arx_hi = ArxModel::identify(fit_y, fit_u, ArxOrders::new(hi_a, hi_b)?)?;
    out.push(PredictorScore {
        model: "ARX (8× lags)",
        params: format!("n_a={hi_a} n_b={hi_b}"),
        metrics: score(arx_hi.predict(y, u)?)?,
    });
    let cfg = ArxLaguerreConfig::new(n_a, n_b, PoleChoice::DEFAULT_SEARCH)?;
    let fal = FuzzyArxLaguerre::identify(fit_y, fit_u, &FalConfig::with_base(cfg))?;
    let al = fal.base();
    let poles = match al.pole_b() {
        Some(b) => format!("ζ_a={:.4} ζ_b={:.4}", al.pole_a().value(), b.value()),
        None => format!("ζ_a={:.4}", al.pole_a().value()),
    };
    out.push(PredictorScore {
        model: "ARX-Laguerre",
        params: format!("N_a={n_a} N_b={n_b} {poles}"),
        metrics: score(al.predict(y, u)?)?,
    });
    let kf: Vec<String> = fal
        .fuzzy_coefficients()
        .iter()
        .map(|v| format!("{v:.4e}"))
        .collect();
    out.push(PredictorScore {
        model: "fuzzy ARX-Laguerre",
        params: format!("N_f=2 ζ_f=0 λ_f=[{}]", kf.join(", ")),
        metrics: score(fal.predict(y, u)?)?,
    });
    Ok(out)
}
