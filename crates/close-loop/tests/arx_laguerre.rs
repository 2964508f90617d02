//! `--model arx-laguerre`: the declared model is an ARX-Laguerre model identified on the fitting
//! segment (`laguerre-id`), run open loop for the spectra and through ALPIO (`observers`) for the
//! observer residual. An undeclared pick-up tone must be found, put in the measurement channel,
//! and lower both held-out metrics.

use close_loop::observe::{ArxLaguerreDeclared, ResidualObserver};
use close_loop::scenario::{add_noise, add_tone};

use close_loop::{
    BearingSpec, DeclaredFault, DeclaredModel, EffectKind, LoopConfig, OperatingPoint, Placement,
    close_loop, fit_len,
};

const FS: f64 = 12_000.0;

#[test]
fn arx_laguerre_declared_model_finds_an_undeclared_tone() {
    // a stochastic vibration the ARX-Laguerre model can describe: a 2.1 kHz mode (poles
    // 0.95·e^{±j·2π·2100/12000}) driven by white noise; then the undeclared pick-up
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::None,
    )
    .unwrap();
    let mut e = vec![0.0; 24_000];
    add_noise(&mut e, 1.0, 5);
    let (r, w) = (0.95f64, 2.0 * std::f64::consts::PI * 2100.0 / FS);
    let (a1, a2) = (2.0 * r * w.cos(), -r * r);
    let mut y = vec![0.0; e.len()];
    for k in 0..e.len() {
        let y1 = if k >= 1 { y[k - 1] } else { 0.0 };
        let y2 = if k >= 2 { y[k - 2] } else { 0.0 };
        y[k] = a1 * y1 + a2 * y2 + e[k];
    }
    let a = close_loop::metric::rms(&y);
    add_tone(&mut y, FS, 1234.5, 0.3 * a, 0.4);
    let cfg = LoopConfig {
        max_effects: 2,
        ..LoopConfig::default()
    }
    .check()
    .unwrap();
    let model = ArxLaguerreDeclared::identify(&y[..fit_len(y.len(), &cfg)]).unwrap();
    assert_eq!(model.residual_observer(FS), ResidualObserver::ArxLaguerre);
    let o = close_loop(&model, &sig(&y, FS), &op, &cfg).unwrap();
    eprintln!("{}", o.ledger.to_markdown("arx-laguerre"));
    assert_eq!(o.ledger.declared.model, "arx-laguerre");
    // The identified model absorbed the tone as a broad bump (measured: the loop first cuts it,
    // a channel mode at 1303 Hz with gain −0.35, then adds the line).
    let e = o
        .ledger
        .effects
        .iter()
        .find(|e| e.kind == EffectKind::Tone)
        .expect("no tone");
    assert_eq!(e.placement, Placement::Measurement);
    assert!((e.frequency_hz.unwrap() / 1234.5 - 1.0).abs() < 0.01);
    assert!(e.error_after < e.error_before);
    assert!(e.residual_rms_after.unwrap() < e.residual_rms_before.unwrap());
    assert!(o.ledger.residual_rms_after.unwrap() < o.ledger.residual_rms_before.unwrap());
    assert!(o.ledger.error_after < o.ledger.error_before);
}

#[test]
fn arx_laguerre_simulation_is_seeded_and_finite() {
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::None,
    )
    .unwrap();
    let mut y = vec![0.0; 6000];
    add_noise(&mut y, 1.0, 9);
    let m = ArxLaguerreDeclared::identify(&y).unwrap();
    let a = m.simulate(&op, 4000, FS).unwrap();
    let b = m.simulate(&op, 4000, FS).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.len(), 4000);
    // white input: the identified model predicts little, so the simulation has about unit RMS
    let r = close_loop::metric::rms(&a);
    assert!((r - 1.0).abs() < 0.15, "{r}");
}

/// `y` at `fs` Hz as a checked signal (the recordings here are finite and non-empty).
fn sig(y: &[f64], fs: f64) -> close_loop::Signal<'_> {
    close_loop::Signal::new(y, fs).unwrap()
}
