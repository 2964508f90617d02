//! The method on a simulated healthy record: prepared on a fit segment, tuned from its measured
//! bound, its residual predicts part of a held-out segment; missing models and short signals are
//! typed errors.

use pipeline::{Method, PipelineError, Prepared, SimKind, residual, simulate, window_energies};

/// 2 s of a simulated healthy CWRU-like record at 12 kHz, 1797 rpm.
fn healthy_record(seed: u64) -> Vec<f64> {
    simulate(
        SimKind::Cwru,
        bearing_model::FaultClass::None,
        0.007,
        1797.0,
        12_000.0,
        24_000,
        seed,
    )
    .unwrap()
}

#[test]
fn prepared_method_predicts_the_healthy_signal_and_errors_are_typed() {
    let fs = 12_000.0;
    let y = healthy_record(3);
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

/// With the machine model prepared, the ARX-Laguerre models take its one-step prediction as
/// their exogenous input: the orders include N_b ≥ 1, APIO predicts the held-out healthy signal
/// better than the same observer on the AR-form model, a precomputed input gives the same bits
/// as one computed inside, and an input of the wrong length is a typed error.
#[test]
fn arx_laguerre_on_the_machine_model_takes_its_prediction_as_input() {
    let fs = 12_000.0;
    let y = healthy_record(5);
    let (fit, held) = y.split_at(12_000);
    let ar = Prepared::new(fit, fs, 1797.0, false, false).unwrap();
    let hybrid = Prepared::new(fit, fs, 1797.0, false, true).unwrap();
    assert_eq!(ar.n_b, 0);
    assert!(ar.input_nrmse.is_none());
    assert!(hybrid.n_b >= 1, "{:?}", hybrid.order_scores);
    assert!(hybrid.input_nrmse.is_some_and(|e| e.is_finite() && e > 0.0));
    assert!(hybrid.takes_input(Method::Apio) && !hybrid.takes_input(Method::Flo));
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    let tail = |r: Vec<f64>| rms(&r[2_000..]);
    let r_ar = residual(Method::Apio, &ar, &ar.tune(Method::Apio).unwrap(), held).unwrap();
    let t = hybrid.tune(Method::Apio).unwrap();
    let r = residual(Method::Apio, &hybrid, &t, held).unwrap();
    let (e_ar, e) = (tail(r_ar), tail(r.clone()));
    assert!(
        e < 0.95 * e_ar,
        "held-out residual RMS {e} vs AR form {e_ar}"
    );
    let u = hybrid.machine_input(held).unwrap().unwrap();
    assert_eq!(u.len(), held.len());
    let again = pipeline::residual_with_input(Method::Apio, &hybrid, &t, held, Some(&u)).unwrap();
    assert!(
        again
            .iter()
            .zip(&r)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    assert!(matches!(
        pipeline::residual_with_input(Method::Apio, &hybrid, &t, held, Some(&u[1..])),
        Err(PipelineError::InputLength { .. })
    ));
    // the identified predictors on the samples after the fit segment: the machine model's input
    // predicts better than the AR form, and better than the machine model's prediction alone
    let (n_ar, alone_ar) = ar.record_nrmse(&y, fit.len()).unwrap();
    let (n_h, alone_h) = hybrid.record_nrmse(&y, fit.len()).unwrap();
    assert!(alone_ar.is_none());
    let alone_h = alone_h.unwrap();
    assert!(
        n_h.is_finite() && n_h > 0.0 && n_h < n_ar,
        "{n_h} vs AR form {n_ar}"
    );
    assert!(n_h <= alone_h * 1.001, "{n_h} vs the input alone {alone_h}");
    assert!(matches!(
        hybrid.record_nrmse(&y, y.len() - 1),
        Err(PipelineError::Ident(_))
    ));
}
