//! Reference tests: Laguerre orthonormality (closed form), known ARX systems recovered,
//! state-space form ≡ filter-bank form, typed errors on bad input.

#![allow(clippy::needless_range_loop)]

use laguerre_id::basis::laguerre_first;
use laguerre_id::{
    ArxLaguerreConfig, ArxLaguerreModel, ArxModel, ArxOrders, FitMetrics, IdentError, LaguerreBank,
    LaguerreState, Pole, PoleChoice,
};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn white(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n).map(|_| rng.random::<f64>() * 2.0 - 1.0).collect()
}

/// Known plant: y(k) = 1.5 y(k−1) − 0.7 y(k−2) + 0.5 u(k−1) + 0.25 u(k−2) + e(k).
fn known_arx(n: usize, noise: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let u = white(n, seed);
    let e = white(n, seed + 1000);
    let mut y = vec![0.0; n];
    for k in 0..n {
        let mut v = noise * e[k];
        if k >= 1 {
            v += 1.5 * y[k - 1] + 0.5 * u[k - 1];
        }
        if k >= 2 {
            v += -0.7 * y[k - 2] + 0.25 * u[k - 2];
        }
        y[k] = v;
    }
    (y, u)
}

#[test]
fn first_laguerre_function_matches_closed_form() {
    // l_0(i) = √(1−ζ²) ζ^{i−1} (inverse z-transform of √(1−ζ²)/(z−ζ)).
    for &z in &[-0.9, -0.3, 0.0, 0.5, 0.95] {
        let p = Pole::new(z).unwrap();
        let l = LaguerreBank::new(p, 3).unwrap().impulse_responses(50);
        for i in 1..=50 {
            assert!((l[0][i - 1] - laguerre_first(p, i)).abs() < 1e-14);
        }
    }
}

#[test]
fn second_laguerre_function_matches_closed_form() {
    // L_1(z) = √(1−ζ²)(1−ζz)/(z−ζ)²  ⇒  l_1(i) = √(1−ζ²) ζ^{i−2} ((i−1)(1−ζ²) − ζ²)/… ; checked via
    // the difference equation l_1(i+1) = ζ l_1(i) + l_0(i) − ζ l_0(i+1), l_1(1) = −ζ√(1−ζ²).
    let z: f64 = 0.6;
    let p = Pole::new(z).unwrap();
    let l = LaguerreBank::new(p, 2).unwrap().impulse_responses(30);
    assert!((l[1][0] + z * p.gain()).abs() < 1e-15);
    for i in 1..30 {
        let expect = z * l[1][i - 1] + l[0][i - 1] - z * l[0][i];
        assert!((l[1][i] - expect).abs() < 1e-14);
    }
}

#[test]
fn zero_pole_is_pure_delay() {
    // ζ = 0: L_n(z) = z^{−(n+1)}, so x_n(k) = s(k−n−1).
    let bank = LaguerreBank::new(Pole::new(0.0).unwrap(), 4).unwrap();
    let s = white(20, 3);
    let f = bank.filter(&s).unwrap();
    for n in 0..4 {
        for k in 0..20 {
            let expect = if k > n { s[k - n - 1] } else { 0.0 };
            assert_eq!(f[n][k], expect);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn laguerre_functions_are_orthonormal(z in -0.9f64..0.9, order in 1usize..=8) {
        let bank = LaguerreBank::new(Pole::new(z).unwrap(), order).unwrap();
        // Horizon long enough that the tail (≈ i^{N} |ζ|^{2i}) is below 1e-12.
        let horizon = 2000;
        let l = bank.impulse_responses(horizon);
        for n in 0..order {
            for m in 0..order {
                let ip: f64 = l[n].iter().zip(&l[m]).map(|(a, b)| a * b).sum();
                let d = if n == m { 1.0 } else { 0.0 };
                prop_assert!((ip - d).abs() < 1e-9, "<l{n},l{m}> = {ip} for zeta {z}");
            }
        }
    }

    #[test]
    fn state_space_form_equals_filter_bank(z_a in -0.9f64..0.9, z_b in -0.9f64..0.9,
                                           na in 1usize..=8, nb in 0usize..=8, seed in 0u64..1000) {
        let ba = LaguerreBank::new(Pole::new(z_a).unwrap(), na).unwrap();
        let bb = if nb > 0 { Some(LaguerreBank::new(Pole::new(z_b).unwrap(), nb).unwrap()) } else { None };
        let k = white(na + nb, seed + 7);
        let m = ArxLaguerreModel::from_parts(ba, bb, &k).unwrap();
        let ss = m.state_space();
        let y = white(200, seed);
        let u = white(200, seed + 1);
        let mut s1 = LaguerreState::default();
        let mut s2 = vec![0.0; na + nb];
        let fy = ba.filter(&y).unwrap();
        for t in 0..200 {
            // Filter-bank form (eq. 4.6): state entries are the filtered signals.
            for n in 0..na {
                prop_assert!((s1.x[n] - fy[n][t]).abs() < 1e-12);
            }
            let (n1, y1) = m.predict_next(&s1, y[t], u[t]);
            let (n2, y2) = ss.step(&s2, y[t], u[t]);
            prop_assert!((y1 - y2).abs() < 1e-12);
            for i in 0..na + nb {
                prop_assert!((n1.x[i] - n2[i]).abs() < 1e-12);
            }
            s1 = n1;
            s2 = n2;
        }
    }
}

#[test]
fn state_space_blocks_match_eq_2_30_to_2_32() {
    let z = 0.4;
    let bank = LaguerreBank::new(Pole::new(z).unwrap(), 4).unwrap();
    let a = bank.a_matrix();
    let c = 1.0 - z * z;
    let expect = [
        [z, 0.0, 0.0, 0.0],
        [c, z, 0.0, 0.0],
        [-z * c, c, z, 0.0],
        [z * z * c, -z * c, c, z],
    ];
    for i in 0..4 {
        for j in 0..4 {
            assert!((a[i][j] - expect[i][j]).abs() < 1e-15, "A[{i}][{j}]");
        }
    }
    let b = bank.b_vector();
    let g = c.sqrt();
    for (i, e) in [g, -z * g, z * z * g, -z * z * z * g].iter().enumerate() {
        assert!((b[i] - e).abs() < 1e-15);
    }
}

#[test]
fn arx_recovers_known_system_noiseless() {
    let (y, u) = known_arx(2000, 0.0, 1);
    let m = ArxModel::identify(&y, Some(&u), ArxOrders::new(2, 2).unwrap()).unwrap();
    for (got, want) in
        m.a.iter()
            .zip([1.5, -0.7])
            .chain(m.b.iter().zip([0.5, 0.25]))
    {
        assert!((got - want).abs() < 1e-8, "{got} vs {want}");
    }
}

#[test]
fn arx_consistent_with_noise() {
    // Equation-error noise (the ARX noise model): LS is consistent, error ~ 1/√n.
    let (y, u) = known_arx(40_000, 0.1, 2);
    let m = ArxModel::identify(&y, Some(&u), ArxOrders::new(2, 2).unwrap()).unwrap();
    for (got, want) in
        m.a.iter()
            .zip([1.5, -0.7])
            .chain(m.b.iter().zip([0.5, 0.25]))
    {
        assert!((got - want).abs() < 0.01, "{got} vs {want}");
    }
}

#[test]
fn arx_laguerre_with_zero_pole_is_arx() {
    let (y, u) = known_arx(2000, 0.0, 3);
    let cfg = ArxLaguerreConfig::new(
        2,
        2,
        PoleChoice::Fixed {
            zeta_a: 0.0,
            zeta_b: 0.0,
        },
    )
    .unwrap();
    let m = ArxLaguerreModel::identify(&y, Some(&u), &cfg).unwrap();
    for (got, want) in m.coefficients().iter().zip([1.5, -0.7, 0.5, 0.25]) {
        assert!((got - want).abs() < 1e-8, "{got} vs {want}");
    }
}

/// A plant that is exactly ARX-Laguerre with known poles and coefficients (infinite ARX lags).
fn known_laguerre_plant(n: usize, noise: f64, seed: u64) -> (ArxLaguerreModel, Vec<f64>, Vec<f64>) {
    let ba = LaguerreBank::new(Pole::new(0.55).unwrap(), 3).unwrap();
    let bb = LaguerreBank::new(Pole::new(-0.3).unwrap(), 2).unwrap();
    let truth = ArxLaguerreModel::from_parts(ba, Some(bb), &[0.6, -0.4, 0.15, 1.0, 0.3]).unwrap();
    let u = white(n, seed);
    let e = white(n, seed + 99);
    let mut y = vec![0.0; n];
    let mut st = LaguerreState::default();
    for k in 0..n {
        y[k] = truth.output(&st) + noise * e[k];
        truth.advance(&mut st, y[k], u[k]);
    }
    (truth, y, u)
}

#[test]
fn arx_laguerre_recovers_known_coefficients_noiseless() {
    let (truth, y, u) = known_laguerre_plant(3000, 0.0, 5);
    let cfg = ArxLaguerreConfig::new(
        3,
        2,
        PoleChoice::Fixed {
            zeta_a: 0.55,
            zeta_b: -0.3,
        },
    )
    .unwrap();
    let m = ArxLaguerreModel::identify(&y, Some(&u), &cfg).unwrap();
    for (g, w) in m.coefficients().iter().zip(truth.coefficients()) {
        assert!((g - w).abs() < 1e-8, "{g} vs {w}");
    }
}

#[test]
fn arx_laguerre_consistent_with_noise_and_search_finds_poles() {
    let (truth, y, u) = known_laguerre_plant(30_000, 0.05, 6);
    let cfg = ArxLaguerreConfig::new(3, 2, PoleChoice::DEFAULT_SEARCH).unwrap();
    let m = ArxLaguerreModel::identify(&y, Some(&u), &cfg).unwrap();
    assert!(
        (m.pole_a().value() - 0.55).abs() < 0.03,
        "zeta_a {}",
        m.pole_a().value()
    );
    assert!(
        (m.pole_b().unwrap().value() + 0.3).abs() < 0.03,
        "zeta_b {:?}",
        m.pole_b()
    );
    // The implied ARX impulse responses agree even where the poles differ slightly.
    let (ea, et) = (m.equivalent_arx(60), truth.equivalent_arx(60));
    for (g, w) in ea.a.iter().zip(&et.a).chain(ea.b.iter().zip(&et.b)) {
        assert!((g - w).abs() < 0.02, "{g} vs {w}");
    }
}

#[test]
fn arx_projection_pole_choice_recovers_pole() {
    // A little equation noise: noiseless data would make the 40-lag ARX regression singular.
    let (_, y, u) = known_laguerre_plant(20_000, 0.01, 8);
    let cfg = ArxLaguerreConfig::new(3, 2, PoleChoice::ArxProjection { arx_order: 40 }).unwrap();
    let m = ArxLaguerreModel::identify(&y, Some(&u), &cfg).unwrap();
    assert!(
        (m.pole_a().value() - 0.55).abs() < 0.02,
        "zeta_a {}",
        m.pole_a().value()
    );
    let yhat = m.predict(&y, Some(&u)).unwrap();
    let fit = FitMetrics::compute(&y[100..], &yhat[100..]).unwrap();
    // Residual near the noise floor (variance of 0.01·U(−1, 1) is 3.33e-5); the projected poles
    // are close to, not at, the true ones, so allow 50 % excess.
    assert!(fit.residual_variance < 1.5 * 1e-4 / 3.0, "{fit:?}");
}

#[test]
fn free_run_of_noiseless_plant_tracks_output() {
    let (truth, y, u) = known_laguerre_plant(500, 0.0, 9);
    let sim = truth.simulate(&y, Some(&u), 0).unwrap();
    for k in 0..500 {
        assert!((sim[k] - y[k]).abs() < 1e-10);
    }
    let arx = ArxModel::identify(
        &known_arx(500, 0.0, 4).0,
        Some(&known_arx(500, 0.0, 4).1),
        ArxOrders::new(2, 2).unwrap(),
    )
    .unwrap();
    let (y2, u2) = known_arx(500, 0.0, 4);
    let sim2 = arx.simulate(&y2, Some(&u2)).unwrap();
    for k in 0..500 {
        assert!((sim2[k] - y2[k]).abs() < 1e-8);
    }
}

#[test]
fn ar_form_without_input() {
    // AR(2) driven by noise: the no-input ARX-Laguerre model still predicts well.
    let e = white(20_000, 11);
    let mut y = vec![0.0; e.len()];
    for k in 2..y.len() {
        y[k] = 1.6 * y[k - 1] - 0.8 * y[k - 2] + e[k];
    }
    let cfg = ArxLaguerreConfig::new(4, 0, PoleChoice::DEFAULT_SEARCH).unwrap();
    let m = ArxLaguerreModel::identify(&y, None, &cfg).unwrap();
    let yhat = m.predict(&y, None).unwrap();
    let fit = FitMetrics::compute(&y[1000..], &yhat[1000..]).unwrap();
    // Innovation variance 1/3 of a uniform(−1,1): residual variance at its floor.
    assert!((fit.residual_variance - 1.0 / 3.0).abs() < 0.02, "{fit:?}");
}

#[test]
fn bad_input_gets_typed_errors() {
    let y = white(1000, 1);
    assert!(matches!(
        Pole::new(1.0),
        Err(IdentError::PoleOutOfRange { .. })
    ));
    assert!(matches!(
        Pole::new(-1.5),
        Err(IdentError::PoleOutOfRange { .. })
    ));
    assert!(matches!(
        Pole::new(f64::NAN),
        Err(IdentError::PoleOutOfRange { .. })
    ));
    assert!(matches!(
        ArxOrders::new(0, 1),
        Err(IdentError::OrderOutOfRange { .. })
    ));
    assert!(matches!(
        ArxLaguerreConfig::new(0, 0, PoleChoice::DEFAULT_SEARCH),
        Err(IdentError::OrderOutOfRange { .. })
    ));
    assert!(matches!(
        ArxLaguerreConfig::new(laguerre_id::MAX_ORDER + 1, 0, PoleChoice::DEFAULT_SEARCH),
        Err(IdentError::OrderOutOfRange { .. })
    ));
    assert!(matches!(
        ArxLaguerreConfig::new(
            2,
            1,
            PoleChoice::Fixed {
                zeta_a: 0.2,
                zeta_b: 1.0
            }
        ),
        Err(IdentError::PoleOutOfRange { .. })
    ));
    let cfg = ArxLaguerreConfig::new(
        2,
        0,
        PoleChoice::Fixed {
            zeta_a: 0.2,
            zeta_b: 0.0,
        },
    )
    .unwrap();
    assert!(matches!(
        ArxLaguerreModel::identify(&y[..5], None, &cfg),
        Err(IdentError::TooFewSamples { .. })
    ));
    let mut bad = y.clone();
    bad[17] = f64::NAN;
    assert_eq!(
        ArxLaguerreModel::identify(&bad, None, &cfg),
        Err(IdentError::NonFinite {
            which: "y",
            index: 17
        })
    );
    assert!(matches!(
        ArxLaguerreModel::identify(&y, Some(&y), &cfg),
        Err(IdentError::InputMismatch { .. })
    ));
    let cfg2 = ArxLaguerreConfig::new(
        2,
        1,
        PoleChoice::Fixed {
            zeta_a: 0.2,
            zeta_b: 0.0,
        },
    )
    .unwrap();
    assert!(matches!(
        ArxLaguerreModel::identify(&y, None, &cfg2),
        Err(IdentError::InputMismatch { .. })
    ));
    assert!(matches!(
        ArxLaguerreModel::identify(&y, Some(&y[..10]), &cfg2),
        Err(IdentError::LengthMismatch { .. })
    ));
    assert!(matches!(
        ArxModel::identify(&y[..6], None, ArxOrders::new(4, 0).unwrap()),
        Err(IdentError::TooFewSamples { .. })
    ));
    // Constant-zero data do not excite the model.
    let zeros = vec![0.0; 1000];
    assert!(matches!(
        ArxLaguerreModel::identify(&zeros, None, &cfg),
        Err(IdentError::RankDeficient { .. })
    ));
    let mut inf = y.clone();
    inf[3] = f64::INFINITY;
    assert!(matches!(
        FitMetrics::compute(&inf, &y),
        Err(IdentError::NonFinite { .. })
    ));
}

/// Held-out order choice: an AR(4) process with two resonant pole pairs (r = 0.9), written as
/// an AR-Laguerre model with pole 0 (the Laguerre functions are then pure delays, K = −a),
/// driven by white noise. Orders below 4 leave predictable structure (clearly larger held-out
/// error), order 8 adds nothing, so the choice is 4; bad settings are typed errors.
#[test]
fn identify_order_picks_the_true_order_by_held_out_error() {
    // (1 − 2r cos(0.5) z⁻¹ + r² z⁻²)(1 − 2r cos(1.5) z⁻¹ + r² z⁻²), r = 0.9
    let (r, c1, c2) = (0.9f64, 0.5f64.cos(), 1.5f64.cos());
    let (p1, p2) = ([1.0, -2.0 * r * c1, r * r], [1.0, -2.0 * r * c2, r * r]);
    let mut a = [0.0; 5];
    for i in 0..3 {
        for j in 0..3 {
            a[i + j] += p1[i] * p2[j];
        }
    }
    let k: Vec<f64> = a[1..].iter().map(|v| -v).collect();
    let ba = LaguerreBank::new(Pole::new(0.0).unwrap(), 4).unwrap();
    let truth = ArxLaguerreModel::from_parts(ba, None, &k).unwrap();
    let e = white(6000, 17);
    let mut y = vec![0.0; e.len()];
    let mut st = LaguerreState::default();
    for k in 0..e.len() {
        y[k] = truth.output(&st) + e[k];
        truth.advance(&mut st, y[k], 0.0);
    }
    let poles = PoleChoice::Fixed {
        zeta_a: 0.0,
        zeta_b: 0.0,
    };
    let (m, scores) = ArxLaguerreModel::identify_order(&y, &[1, 2, 4, 8], 0.3, poles).unwrap();
    assert_eq!(scores.len(), 4, "{scores:?}");
    assert_eq!(m.n_a(), 4, "{scores:?}");
    let s = |n: usize| scores.iter().find(|s| s.0 == n).unwrap().1;
    assert!(s(2) > 1.2 * s(4), "{scores:?}");
    assert!(matches!(
        ArxLaguerreModel::identify_order(&y, &[2], 0.9, poles),
        Err(IdentError::InvalidParameter { .. })
    ));
    assert!(matches!(
        ArxLaguerreModel::identify_order(&y, &[], 0.3, poles),
        Err(IdentError::OrderOutOfRange { .. })
    ));
}

/// Joint (N_a, N_b) choice with an exogenous input: y is an AR(1) process plus an input whose
/// two past values enter (pure delays, pole 0). Without the input (N_b = 0) or with one input
/// function the held-out error stays clearly larger; the choice is the smallest pair that
/// reaches the best error, (1, 2), and a missing input is a typed error.
#[test]
fn identify_orders_chooses_the_input_order_with_the_output_order() {
    let e = white(6000, 23);
    let u = white(6000, 29);
    let mut y = vec![0.0; e.len()];
    for k in 0..e.len() {
        let past = |v: &[f64], i: usize| if k >= i { v[k - i] } else { 0.0 };
        y[k] = 0.6 * past(&y, 1) + 1.5 * past(&u, 1) - 1.0 * past(&u, 2) + 0.3 * e[k];
    }
    let poles = PoleChoice::Fixed {
        zeta_a: 0.0,
        zeta_b: 0.0,
    };
    let pairs = [(1, 0), (2, 0), (1, 1), (1, 2), (2, 2), (4, 4)];
    let (m, scores) = ArxLaguerreModel::identify_orders(&y, Some(&u), &pairs, 0.3, poles).unwrap();
    assert_eq!(scores.len(), pairs.len(), "{scores:?}");
    assert_eq!((m.n_a(), m.n_b()), (1, 2), "{scores:?}");
    let s = |p: (usize, usize)| scores.iter().find(|s| s.0 == p).unwrap().1;
    assert!(s((1, 0)) > 2.0 * s((1, 2)), "{scores:?}");
    assert!(s((1, 1)) > 1.25 * s((1, 2)), "{scores:?}");
    // the AR-form wrapper gives the same as the pairs with N_b = 0
    let (ar, ar_scores) = ArxLaguerreModel::identify_order(&y, &[1, 2], 0.3, poles).unwrap();
    assert_eq!(ar_scores, vec![(1, s((1, 0))), (2, s((2, 0)))]);
    assert_eq!(ar.n_b(), 0);
    assert!(ArxLaguerreModel::identify_orders(&y, None, &[(1, 2)], 0.3, poles).is_err());
}
