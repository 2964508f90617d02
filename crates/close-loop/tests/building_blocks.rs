//! Reference values (closed forms) and invariants of the building blocks: Welch PSD, the
//! log-spectral distance, the modulation PSD formula, the mode gain, bearing rates, bad input.

use approx::assert_relative_eq;
use close_loop::effect::{Mode, Modulation};
use close_loop::metric::{log_spectral_distance, rms};
use close_loop::scenario::{Gaussian, PhenomenologicalModel};
use close_loop::spectrum::{Welch, envelope, hann_windowed, refine_peak};
use close_loop::{
    BearingSpec, CloseLoopError, DeclaredFault, LoopConfig, OperatingPoint, close_loop, min_samples,
};
use proptest::prelude::*;
use std::f64::consts::PI;

#[test]
fn welch_integrates_to_the_variance_of_a_sinusoid() {
    // Parseval: ∫S df = A²/2 for A·sin (closed form), up to the window's leakage outside the band.
    let fs = 1000.0;
    let x: Vec<f64> = (0..20_000)
        .map(|i| 3.0 * (2.0 * PI * 97.3 * i as f64 / fs).sin())
        .collect();
    let w = Welch::new(fs, 512).unwrap();
    let s = w.try_psd(&x).unwrap();
    let total: f64 = s.iter().sum::<f64>() * w.df();
    assert_relative_eq!(total, 4.5, max_relative = 1e-3);
}

#[test]
fn welch_of_white_noise_is_flat_at_sigma2_over_half_fs() {
    // One-sided density of white noise: 2σ²/fs.
    let fs = 2000.0;
    let mut g = Gaussian::new(5);
    let x: Vec<f64> = (0..200_000).map(|_| 0.5 * g.sample()).collect();
    let w = Welch::new(fs, 256).unwrap();
    let s = w.try_psd(&x).unwrap();
    let mean: f64 = s[5..120].iter().sum::<f64>() / 115.0;
    assert_relative_eq!(mean, 2.0 * 0.25 / fs, max_relative = 0.02);
}

#[test]
fn lsd_of_a_factor_two_is_3_01_db() {
    // 10·log10(2) = 3.0103 dB in every bin.
    let a = vec![1.0; 100];
    let b = vec![2.0; 100];
    assert_relative_eq!(
        log_spectral_distance(&b, &a, 0..100),
        10.0 * 2f64.log10(),
        epsilon = 1e-12
    );
    assert_eq!(log_spectral_distance(&a, &a, 0..100), 0.0);
}

#[test]
fn envelope_of_an_am_signal_is_its_modulating_amplitude() {
    // x = (1 + 0.5 cos 2π·5t)·cos 2π·200t has the envelope 1 + 0.5 cos 2π·5t (closed form).
    let fs = 4000.0;
    let n = 8000;
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            (1.0 + 0.5 * (2.0 * PI * 5.0 * t).cos()) * (2.0 * PI * 200.0 * t).cos()
        })
        .collect();
    let e = envelope(&x).unwrap();
    for i in (500..7500).step_by(97) {
        let t = i as f64 / fs;
        assert!((e[i] - (1.0 + 0.5 * (2.0 * PI * 5.0 * t).cos())).abs() < 1e-3);
    }
}

/// Bad input to the spectral helpers is a typed error, never NaN or zeros.
#[test]
fn spectral_helpers_reject_bad_input_with_typed_errors() {
    use close_loop::spectrum::envelope_periodogram;
    assert!(matches!(
        envelope(&[]),
        Err(CloseLoopError::Spectral { .. })
    ));
    assert!(matches!(
        envelope(&[1.0, f64::NAN, 2.0]),
        Err(CloseLoopError::Spectral { .. })
    ));
    assert!(matches!(
        envelope_periodogram(&[0.0; 256], 1000.0),
        Err(CloseLoopError::Spectral { .. })
    ));
    let w = Welch::new(1000.0, 256).unwrap();
    assert!(matches!(
        w.try_psd(&[0.5; 100]),
        Err(CloseLoopError::TooShort { .. })
    ));
}

#[test]
fn refine_peak_finds_an_off_bin_frequency() {
    let fs = 12_000.0;
    let x: Vec<f64> = (0..12_000)
        .map(|i| (2.0 * PI * 1234.567 * i as f64 / fs).cos())
        .collect();
    let f = refine_peak(&hann_windowed(&x), fs, 1230.0, 1240.0);
    assert!((f - 1234.567).abs() < 1e-3, "{f}");
}

#[test]
fn modulation_psd_formula_matches_welch_of_a_modulated_signal() {
    // PSD of x·(1 + μ cos 2π fm t) = S + μ²/4 (S(f − fm) + S(f + fm)) (time-averaged autocorrelation)
    // of the modulation: checked on a line at 500 Hz, fm = 60 Hz (sidebands μ²/4 of the line).
    let fs = 4096.0;
    let x: Vec<f64> = (0..65_536)
        .map(|i| (2.0 * PI * 500.0 * i as f64 / fs).cos())
        .collect();
    let m = Modulation {
        frequency_hz: 64.0,
        depth: 0.6,
    };
    let w = Welch::new(fs, 1024).unwrap();
    let direct = w.try_psd(&m.apply(&x, 0, fs)).unwrap();
    let formula = m.apply_psd(&w.try_psd(&x).unwrap(), w.df());
    let (k0, k1) = (500 / 4, 564 / 4);
    assert_relative_eq!(direct[k0], formula[k0], max_relative = 1e-6);
    assert_relative_eq!(direct[k1], formula[k1], max_relative = 1e-6);
    assert_relative_eq!(direct[k1] / direct[k0], 0.09, max_relative = 1e-6);
}

#[test]
fn mode_peak_power_gain_is_one_plus_c_squared() {
    let m = Mode {
        frequency_hz: 1000.0,
        damping_ratio: 0.05,
        gain: 3.0,
    };
    assert_relative_eq!(m.power_gain(1000.0, 12_000.0), 16.0, max_relative = 1e-9);
    assert_relative_eq!(m.power_gain(0.0, 12_000.0), 1.0, max_relative = 1e-9);
}

#[test]
fn skf6205_rates_match_the_cwru_table() {
    // CWRU table: BPFI 5.4152, BPFO 3.5848, FTF 0.39828, BSF 4.7135.
    let b = BearingSpec::designated(bearing_model::Bearing::Skf6205);
    assert_eq!(b.name, "6205");
    assert_relative_eq!(b.orders.bpfi, 5.4152, max_relative = 2e-4);
    assert_relative_eq!(b.orders.bpfo, 3.5848, max_relative = 2e-4);
    assert_relative_eq!(b.orders.ftf, 0.39828, max_relative = 2e-4);
    assert_relative_eq!(b.orders.ball_defect, 4.7135, max_relative = 2e-4);
}

fn small_recording(n: usize) -> Vec<f64> {
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Outer,
    )
    .unwrap();
    close_loop::DeclaredModel::simulate(&PhenomenologicalModel::default(), &op, n, 12_000.0)
        .unwrap()
}

#[test]
fn bad_input_gets_typed_errors() {
    let cfg = LoopConfig::default().check().unwrap();
    let model = PhenomenologicalModel::default();
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Outer,
    )
    .unwrap();
    let short = small_recording(min_samples(&cfg) - 1);
    assert!(matches!(
        close_loop(&model, &sig(&short, 12_000.0), &op, &cfg),
        Err(CloseLoopError::TooShort { .. })
    ));
    // the advertised minimum is enough for every stage, the structural path's identification on
    // the fitting part included (it once asked for 2305 samples and then failed on 1200 < 2048)
    let just = small_recording(min_samples(&cfg));
    close_loop(&model, &sig(&just, 12_000.0), &op, &cfg).unwrap();
    close_loop(
        &close_loop::physics::PhysicsModel::default(),
        &sig(&just, 12_000.0),
        &op,
        &cfg,
    )
    .unwrap();
    assert_eq!(
        OperatingPoint::new(
            0.0,
            BearingSpec::designated(bearing_model::Bearing::Skf6205),
            DeclaredFault::None
        ),
        Err(CloseLoopError::InvalidRpm { rpm: 0.0 })
    );
    let mut bad_op = op.clone();
    bad_op.rpm = 0.0;
    let y = small_recording(12_000);
    assert_eq!(
        close_loop(&model, &sig(&y, 12_000.0), &bad_op, &cfg).unwrap_err(),
        CloseLoopError::InvalidRpm { rpm: 0.0 }
    );
    assert!(matches!(
        BearingSpec::parse("6309"),
        Err(bearing_model::ModelError::UnknownBearing(_))
    ));
    assert!(matches!(
        close_loop::parse_fault("cage"),
        Err(CloseLoopError::UnknownFault { .. })
    ));
    for (repeated, location) in [
        ("inner+inner", bearing_model::FaultLocation::Inner),
        ("outer+outer", bearing_model::FaultLocation::Outer),
        ("ball+inner+ball", bearing_model::FaultLocation::Ball),
    ] {
        let e = close_loop::parse_fault(repeated).unwrap_err();
        assert_eq!(
            e,
            CloseLoopError::RepeatedFault {
                name: repeated.into(),
                location
            }
        );
        assert!(!e.to_string().contains('\n'));
    }
    let mut nan = y.clone();
    nan[17] = f64::NAN;
    assert_eq!(
        close_loop::Signal::new(&nan, 12_000.0)
            .map_err(CloseLoopError::from)
            .unwrap_err(),
        CloseLoopError::NonFinite { index: 17 }
    );
    assert_eq!(
        close_loop(&model, &sig(&vec![1.0; 12_000], 12_000.0), &op, &cfg).unwrap_err(),
        CloseLoopError::ZeroSignal
    );
    assert!(matches!(
        close_loop::Signal::new(&y, f64::NAN).map_err(CloseLoopError::from),
        Err(CloseLoopError::InvalidSamplingRate { .. })
    ));
    assert!(matches!(
        close_loop::Signal::new(Vec::new(), 12_000.0).map_err(CloseLoopError::from),
        Err(CloseLoopError::EmptyRecording)
    ));
    let bad = LoopConfig {
        fit_fraction: 0.95,
        ..LoopConfig::default()
    };
    assert!(matches!(
        bad.check(),
        Err(CloseLoopError::ParameterOutOfRange {
            name: "fit_fraction",
            ..
        })
    ));
}

#[test]
fn ledger_round_trips_through_json() {
    let cfg = LoopConfig::default().check().unwrap();
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Outer,
    )
    .unwrap();
    let y = small_recording(12_000);
    let out = close_loop(
        &PhenomenologicalModel::default().with_seed(3),
        &sig(&y, 12_000.0),
        &op,
        &cfg,
    )
    .unwrap();
    let js = serde_json::to_string(&out.ledger).unwrap();
    let back: close_loop::Ledger = serde_json::from_str(&js).unwrap();
    assert_eq!(back, out.ledger);
    let v: serde_json::Value = serde_json::from_str(&js).unwrap();
    for key in ["error_metric", "error_before", "error_after", "effects"] {
        assert!(v.get(key).is_some(), "{key}");
    }
}

#[test]
fn loop_is_deterministic() {
    let cfg = LoopConfig::default().check().unwrap();
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Outer,
    )
    .unwrap();
    let y = small_recording(12_000);
    let m = PhenomenologicalModel::default().with_seed(3);
    let a = close_loop(&m, &sig(&y, 12_000.0), &op, &cfg).unwrap();
    let b = close_loop(&m, &sig(&y, 12_000.0), &op, &cfg).unwrap();
    assert_eq!(a, b);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn lsd_is_symmetric_scale_invariant_and_zero_on_identity(
        v in proptest::collection::vec(1e-6f64..1e6, 4..64),
        w in proptest::collection::vec(1e-6f64..1e6, 64),
        c in 1e-3f64..1e3,
    ) {
        let n = v.len();
        let w = &w[..n];
        let d = log_spectral_distance(&v, w, 0..n);
        prop_assert!((d - log_spectral_distance(w, &v, 0..n)).abs() < 1e-9);
        let vc: Vec<f64> = v.iter().map(|x| x * c).collect();
        let wc: Vec<f64> = w.iter().map(|x| x * c).collect();
        prop_assert!((d - log_spectral_distance(&vc, &wc, 0..n)).abs() < 1e-9);
        prop_assert!(log_spectral_distance(&v, &v, 0..n) == 0.0);
    }

    #[test]
    fn welch_satisfies_parseval_for_white_noise(seed in 0u64..1000, sigma in 0.1f64..10.0) {
        // Σ S·Δf equals the mean per-segment variance of the windowed data within sampling error.
        let mut g = Gaussian::new(seed);
        let x: Vec<f64> = (0..16_384).map(|_| sigma * g.sample()).collect();
        let w = Welch::new(1000.0, 256).unwrap();
        let total: f64 = w.try_psd(&x).unwrap().iter().sum::<f64>() * w.df();
        let var = rms(&x).powi(2);
        prop_assert!((total / var - 1.0).abs() < 0.06, "{} vs {}", total, var);
    }

    #[test]
    fn mode_gain_is_nonnegative_and_unit_far_away(f0 in 200.0f64..4000.0, z in 0.005f64..0.3, c in -0.95f64..20.0) {
        let m = Mode { frequency_hz: f0, damping_ratio: z, gain: c };
        prop_assert!(m.power_gain(f0 * 0.37, 12_000.0) >= 0.0);
        prop_assert!((m.power_gain(0.0, 12_000.0) - 1.0).abs() < 1e-9);
    }
}

/// A fitted mode whose damping or gain ends at its search bound is reported as such (key
/// `at_search_bound`, and the description says it is a spectral-shape correction); a resolved
/// resonance is not.
#[test]
fn modes_at_their_search_bound_are_flagged() {
    use close_loop::effect::{Effect, MODE_GAIN_RANGE, MODE_MAX_DAMPING, mode_at_bound};
    let resolved = Mode {
        frequency_hz: 3300.0,
        damping_ratio: 0.05,
        gain: 3.0,
    };
    let flagged = [
        Mode {
            gain: MODE_GAIN_RANGE.1 * 0.9998,
            ..resolved
        },
        Mode {
            gain: MODE_GAIN_RANGE.0 * 0.9998,
            ..resolved
        },
        Mode {
            damping_ratio: MODE_MAX_DAMPING * 0.9996,
            ..resolved
        },
    ];
    assert!(!mode_at_bound(&resolved));
    let e = Effect::Resonance {
        mode: resolved,
        housing: false,
    };
    assert_eq!(e.parameters()["at_search_bound"], 0.0);
    assert!(!e.describe().contains("search bound"));
    for m in flagged {
        assert!(mode_at_bound(&m), "{m:?}");
        let e = Effect::Resonance {
            mode: m,
            housing: false,
        };
        assert_eq!(e.parameters()["at_search_bound"], 1.0);
        assert!(e.describe().contains("not a resolved resonance"));
    }
}

/// A modulation whose depth reached its bound is reported as such (key `at_search_bound`, and
/// the description says the depth is a lower bound); a depth inside the range is not.
#[test]
fn modulation_depths_at_their_search_bound_are_flagged() {
    use close_loop::effect::{Effect, MODULATION_MAX_DEPTH, Modulation};
    let effect = |depth: f64| Effect::Modulation {
        modulation: Modulation {
            frequency_hz: 29.95,
            depth,
        },
        shaft_order: 1.0,
        rate: "shaft",
    };
    let inside = effect(0.4);
    assert_eq!(inside.parameters()["at_search_bound"], 0.0);
    assert!(!inside.describe().contains("bound"));
    let pinned = effect(0.99999 * MODULATION_MAX_DEPTH);
    assert_eq!(pinned.parameters()["at_search_bound"], 1.0);
    assert!(pinned.describe().contains("the depth is a lower bound"));
}

/// `y` at `fs` Hz as a checked signal (the recordings here are finite and non-empty).
fn sig(y: &[f64], fs: f64) -> close_loop::Signal<'_> {
    close_loop::Signal::new(y, fs).unwrap()
}
