//! The method on a simulated healthy record: prepared on a fit segment, tuned from its measured
//! bound, its residual predicts part of a held-out segment; missing models and short signals are
//! typed errors.

use pipeline::{Method, PipelineError, Prepared, SimKind, residual, simulate, window_energies};

#[test]
fn prepared_method_predicts_the_healthy_signal_and_errors_are_typed() {
    let fs = 12_000.0;
    let y = simulate(
        SimKind::Cwru,
        bearing_model::FaultClass::None,
        0.007,
        1797.0,
        fs,
        24_000,
        3,
    )
    .unwrap();
    let (fit, held) = y.split_at(12_000);
    // ARX-Laguerre only (no fuzzy model, no machine model)
    let p = Prepared::new(fit, fs, 1797.0, false, false).unwrap();
    assert!(
        p.n_a >= 2 && p.order_scores.len() >= 2,
        "{:?}",
        p.order_scores
    );
    let t = p.tune(Method::Apio).unwrap();
    assert!(t.fit_ratio < 1.0, "APIO fit ratio {}", t.fit_ratio);
    let r = residual(Method::Apio, &p, &t, held).unwrap();
    assert_eq!(r.len(), held.len());
    let e = window_energies(&r, 300, 10).unwrap();
    assert_eq!(e.len(), 10);
    assert!(e.iter().all(|v| v.is_finite() && *v > 0.0));
    // a method whose model was not prepared
    assert!(matches!(
        p.tune(Method::Hostsmo),
        Err(PipelineError::NotPrepared { .. })
    ));
    assert!(matches!(
        p.tune(Method::Afsmo),
        Err(PipelineError::NotPrepared { .. })
    ));
    // too short for one window; a zero window length; a NaN in the residual
    assert!(matches!(
        window_energies(&r[..100], 300, 1),
        Err(PipelineError::TooShort { .. })
    ));
    assert!(matches!(
        window_energies(&r, 0, 1),
        Err(PipelineError::TooShort { .. })
    ));
    let mut bad = r[..600].to_vec();
    bad[450] = f64::NAN;
    assert!(matches!(
        window_energies(&bad, 300, 2),
        Err(PipelineError::Features(_))
    ));
    // Σr² per window, the trailing partial window ignored
    let e = window_energies(&[1.0, 2.0, 3.0, 4.0, 5.0], 2, 10).unwrap();
    assert_eq!(e, vec![5.0, 25.0]);
}
