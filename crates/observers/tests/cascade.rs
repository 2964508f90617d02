//! The O(n) Laguerre-cascade path of `ArxLaguerrePredictor` against the dense O(n²) path it
//! replaces (same linear map, eqs 2.29–2.32: results must agree to rounding, 1e-12).

use observers::named::design_arx_linear;
use observers::scenarios::{ArxPlant, reference_arx_model};
use observers::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_model(rng: &mut ChaCha8Rng) -> StateSpace {
    let n_a = rng.random_range(1..=8);
    let n_b = rng.random_range(0..=8);
    let za = rng.random_range(-0.95..0.95);
    let zb = rng.random_range(-0.95..0.95);
    // |K| small enough that the parallel model A + b_y Kᵀ stays stable (bounded states).
    let scale = 0.5 / (n_a + n_b) as f64;
    let k = (0..n_a + n_b)
        .map(|_| rng.random_range(-scale..scale))
        .collect();
    StateSpace::from_poles(za, n_a, zb, n_b, k).unwrap()
}

#[test]
fn cascade_equals_dense_on_random_models_and_inputs() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x1a9e_44e5);
    for case in 0..64 {
        let model = random_model(&mut rng);
        let n = model.order();
        let f: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let kp: Vec<f64> = (0..n).map(|_| rng.random_range(-0.05..0.05)).collect();
        let (Ok(mut fast), Ok(mut dense)) = (
            ArxLaguerrePredictor::new(&model, &f, &kp),
            ArxLaguerrePredictor::new_dense(&model, &f, &kp),
        ) else {
            continue; // f invisible through K (Kᵀf ≈ 0): both reject it
        };
        assert!(fast.uses_laguerre_cascade(), "case {case}");
        assert!(!dense.uses_laguerre_cascade());
        let x0: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        fast.set_state(&x0).unwrap();
        dense.set_state(&x0).unwrap();
        for _ in 0..500 {
            let y = rng.random_range(-1.0..1.0);
            let u = rng.random_range(-1.0..1.0);
            let c = Correction {
                c1: rng.random_range(-0.1..0.1),
                c2: rng.random_range(-0.01..0.01),
                c3: rng.random_range(-1e-4..1e-4),
            };
            let e = y - dense.output();
            fast.advance(y, u, e, c);
            dense.advance(y, u, e, c);
            let xmax = dense.state().iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let scale = 1.0 + dense.output().abs().max(xmax);
            assert!(
                (fast.output() - dense.output()).abs() <= 1e-12 * scale,
                "case {case}: {} vs {}",
                fast.output(),
                dense.output()
            );
            for (a, b) in fast.state().iter().zip(dense.state()) {
                assert!((a - b).abs() <= 1e-12 * scale, "case {case}: {a} vs {b}");
            }
        }
        fast.reset();
        dense.reset();
        assert_eq!(fast.state(), &x0[..]);
        assert!((fast.output() - dense.output()).abs() <= 1e-12);
    }
}

#[test]
fn every_kind_runs_the_same_on_both_paths() {
    let model = reference_arx_model();
    let f = FaultDirection::Input.vector(&model);
    let mut plant = ArxPlant::new(&model, &f).unwrap();
    let (mut y, u) = plant.simulate(
        3000,
        |k| ((k as f64) * 0.05).sin(),
        |k| if k >= 1000 { 0.3 } else { 0.0 },
    );
    // Seeded measurement noise: without it the first samples give e = 0 exactly on the dense
    // path and ±1e-17 on the cascade, and sgn(0) = 0 vs ±1 is a legitimate discontinuity of the
    // sign laws, not a difference of the two model paths.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    y.iter_mut()
        .for_each(|v| *v += rng.random_range(-1e-3..1e-3));
    let s = ObserverSettings::new(1e-3);
    let kp = design_arx_linear(&model, &f, &s.linear).unwrap().kp;
    for kind in ObserverKind::ALL {
        let mut fast = named::arx_observer(kind, &model, &FaultDirection::Input, &s).unwrap();
        assert!(fast.predictor().uses_laguerre_cascade());
        let dense_p = ArxLaguerrePredictor::new_dense(&model, &f, &kp).unwrap();
        let mut dense = Observer::new(dense_p, *fast.law());
        let a = fast.run(&y, Some(&u)).unwrap();
        let b = dense.run(&y, Some(&u)).unwrap();
        for (name, p, q) in [
            ("residual", &a.residual, &b.residual),
            ("y_hat", &a.y_hat, &b.y_hat),
            ("fault", &a.fault, &b.fault),
        ] {
            let worst = p
                .iter()
                .zip(q)
                .map(|(x, z)| (x - z).abs())
                .fold(0.0, f64::max);
            // HOSTSMO alone (Levant terms, no linear part) amplifies rounding: c₂ ∝ |e|^⅓ has an
            // unbounded slope at e = 0, so a 1e-16 difference of ŷ becomes ~1e-9 after 3000
            // samples (measured 4.9e-9); every other kind measured ≤ 3e-13.
            let tol = if kind == ObserverKind::Hostsmo {
                1e-7
            } else {
                1e-12
            };
            assert!(worst <= tol, "{kind} {name}: {worst:e}");
        }
    }
}

#[test]
fn structure_detection() {
    // laguerre-id's explicit state space (AR form and with input) is recognised exactly.
    for (n_a, n_b) in [(4, 0), (3, 5), (8, 8)] {
        let bank_a = laguerre_id::LaguerreBank::new(laguerre_id::Pole::new(0.7).unwrap(), n_a);
        let bank_b = (n_b > 0).then(|| {
            laguerre_id::LaguerreBank::new(laguerre_id::Pole::new(-0.3).unwrap(), n_b).unwrap()
        });
        let k: Vec<f64> = (0..n_a + n_b).map(|i| 0.1 * (i as f64 + 1.0)).collect();
        let id = laguerre_id::ArxLaguerreModel::from_parts(bank_a.unwrap(), bank_b, &k).unwrap();
        let m = id.state_space().validated().unwrap();
        let s = m.laguerre_structure().expect("Laguerre structure");
        assert_eq!((s.n_a, s.n_b), (n_a, n_b));
        assert_eq!(s.zeta_a, 0.7);
        if n_b > 0 {
            assert_eq!(s.zeta_b, -0.3);
        }
    }
    // A perturbed A is a general model: the dense path is used.
    let mut m = reference_arx_model();
    m.a[9] += 1e-6;
    assert!(m.laguerre_structure().is_none());
    let f = FaultDirection::Input.vector(&m);
    let p = ArxLaguerrePredictor::new(&m, &f, &vec![0.0; m.order()]).unwrap();
    assert!(!p.uses_laguerre_cascade());
}
