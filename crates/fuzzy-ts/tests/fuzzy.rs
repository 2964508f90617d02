//! Reference and property tests: memberships in [0, 1], coverage of the input space, output
//! inside its universe, Table 5.1 as data, eq. 5.29, and the FAL model on a known plant.

#![allow(clippy::needless_range_loop)]

use fuzzy_ts::{
    FalConfig, FuzzyArxLaguerre, FuzzyError, FuzzyInference, FuzzyRanges, FuzzyScaling, RuleTable,
    Switching, TNorm, Term, TermSet, TsSwitchingLaw,
};
use laguerre_id::{ArxLaguerreConfig, FitMetrics, PoleChoice};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn table_5_1_rows_follow_anti_diagonal_except_printed_nl() {
    let law = RuleTable::anti_diagonal();
    assert_eq!(RuleTable::table_5_1(), law);
    let printed = RuleTable::table_5_1_as_printed();
    let mut diffs = vec![];
    for (e, d, t) in printed.rules() {
        if law.consequent(e, d) != t {
            diffs.push((e, d, t));
        }
    }
    // Exactly the last two cells of row NL differ (PL, PM printed where NL, NM are expected).
    assert_eq!(
        diffs,
        vec![
            (Term::NL, Term::PM, Term::PL),
            (Term::NL, Term::PH, Term::PM)
        ]
    );
    assert_eq!(printed.rules().count(), 49);
}

#[test]
fn membership_crossings_and_peaks() {
    let ts = TermSet::dissertation_error();
    // Centres at −0.3, −0.2, …, 0.3; a term is 1 at its centre and neighbours cross at 0.5.
    for (i, t) in Term::ALL.into_iter().enumerate() {
        let c = -0.3 + 0.1 * i as f64;
        assert!((ts.center(t) - c).abs() < 1e-15);
        assert!((ts.degrees(c)[i] - 1.0).abs() < 1e-12); // recurrence rounding
    }
    let mid = ts.degrees(-0.25);
    assert!((mid[0] - 0.5).abs() < 1e-12 && (mid[1] - 0.5).abs() < 1e-12);
}

#[test]
fn inference_reference_values() {
    let fis = FuzzyInference::dissertation();
    // At the centre of the table the output is exactly zero by symmetry.
    assert!(fis.infer(0.0, 0.0).abs() < 1e-15);
    // Odd symmetry of the corrected table: infer(−e, −ė) = −infer(e, ė).
    for &(e, d) in &[(0.1, 0.03), (-0.25, 0.07), (0.3, -0.1)] {
        assert!((fis.infer(e, d) + fis.infer(-e, -d)).abs() < 1e-14);
    }
    // Deep in the NH/NH corner the output approaches PH = 0.08 (min t-norm ⇒ within 1 %).
    let fis_min = FuzzyInference::new(
        FuzzyRanges::DISSERTATION,
        RuleTable::table_5_1(),
        TNorm::Min,
    )
    .unwrap();
    assert!(fis_min.infer(-1.0, -1.0) > 0.075);
    assert!(fis.infer(-1.0, -1.0) > 0.07);
    // Monotone along the diagonal.
    let mut last = f64::INFINITY;
    for i in 0..=20 {
        let x = -0.3 + 0.03 * i as f64;
        let v = fis.infer(x, x / 3.0);
        assert!(v <= last + 1e-12);
        last = v;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn memberships_in_unit_interval_and_cover(x in -10.0f64..10.0, h in 0.001f64..100.0) {
        let ts = TermSet::symmetric(h).unwrap();
        let d = ts.degrees(x * h);
        for v in d {
            prop_assert!((0.0..=1.0).contains(&v));
        }
        // Coverage: every input fires some term at least 0.5.
        prop_assert!(d.iter().cloned().fold(0.0, f64::max) >= 0.5 - 1e-12);
    }

    #[test]
    fn output_stays_in_universe(e in -5.0f64..5.0, de in -5.0f64..5.0, out in 0.001f64..10.0, min in proptest::bool::ANY) {
        let fis = FuzzyInference::new(
            FuzzyRanges { error: 0.3, change_of_error: 0.1, output: out },
            RuleTable::table_5_1(),
            if min { TNorm::Min } else { TNorm::Product },
        ).unwrap();
        let y = fis.infer(e, de);
        prop_assert!(y.is_finite());
        prop_assert!(y.abs() <= out * (1.0 + 1e-12));
    }

    #[test]
    fn ts_gain_between_rule_gains(r in -10.0f64..10.0, th in 0.0f64..5.0, gn in -5.0f64..5.0, gf in -5.0f64..5.0, w in 0.01f64..2.0) {
        for sw in [Switching::Crisp, Switching::Smooth { width: w }] {
            let law = TsSwitchingLaw::new(th, gn, gf, sw).unwrap();
            let g = law.gain(r);
            prop_assert!(g >= gn.min(gf) - 1e-12 && g <= gn.max(gf) + 1e-12);
        }
    }
}

#[test]
fn nan_inputs_are_handled() {
    let fis = FuzzyInference::dissertation();
    assert!(fis.infer(f64::NAN, 0.0).abs() < 1e-15);
    let law = TsSwitchingLaw::new(1.0, 0.1, 0.9, Switching::Smooth { width: 0.1 }).unwrap();
    assert!(law.gain(f64::NAN).is_finite());
}

#[test]
fn ts_switching_law_eq_5_29() {
    let law = TsSwitchingLaw::new(0.5, 0.1, 0.8, Switching::Crisp).unwrap();
    assert_eq!(law.step(1.0, 0.2, 2.0), 1.0 + 0.1 * 2.0); // normal: |r| ≤ TH
    assert_eq!(law.step(1.0, -0.9, 2.0), 1.0 + 0.8 * 2.0); // faulty: |r| > TH
    let smooth = TsSwitchingLaw::new(0.5, 0.1, 0.8, Switching::Smooth { width: 0.05 }).unwrap();
    assert!((smooth.gain(0.5) - 0.45).abs() < 1e-12); // halfway at the threshold
}

#[test]
fn bad_parameters_get_typed_errors() {
    assert!(matches!(
        TermSet::uniform(1.0, 1.0),
        Err(FuzzyError::InvalidRange { .. })
    ));
    assert!(matches!(
        TermSet::uniform(f64::NAN, 1.0),
        Err(FuzzyError::InvalidRange { .. })
    ));
    assert!(matches!(
        FuzzyInference::new(
            FuzzyRanges {
                error: 0.0,
                change_of_error: 0.1,
                output: 0.1
            },
            RuleTable::table_5_1(),
            TNorm::Product
        ),
        Err(FuzzyError::InvalidParameter { .. })
    ));
    assert!(matches!(
        TsSwitchingLaw::new(-1.0, 0.1, 0.2, Switching::Crisp),
        Err(FuzzyError::InvalidParameter { .. })
    ));
    assert!(matches!(
        TsSwitchingLaw::new(1.0, 0.1, 0.2, Switching::Smooth { width: 0.0 }),
        Err(FuzzyError::InvalidParameter { .. })
    ));
    let base = ArxLaguerreConfig::new(
        2,
        0,
        PoleChoice::Fixed {
            zeta_a: 0.3,
            zeta_b: 0.0,
        },
    )
    .unwrap();
    let mut cfg = FalConfig::with_base(base);
    cfg.fuzzy_pole = 1.0;
    let y: Vec<f64> = (0..500).map(|k| (k as f64 * 0.3).sin()).collect();
    assert!(matches!(
        FuzzyArxLaguerre::identify(&y, None, &cfg),
        Err(FuzzyError::Ident(_))
    ));
    let mut cfg = FalConfig::with_base(base);
    cfg.fuzzy_order = 0;
    assert!(matches!(
        FuzzyArxLaguerre::identify(&y, None, &cfg),
        Err(FuzzyError::InvalidParameter { .. })
    ));
    let mut bad = y.clone();
    bad[9] = f64::NAN;
    let cfg = FalConfig::with_base(base);
    assert!(matches!(
        FuzzyArxLaguerre::identify(&bad, None, &cfg),
        Err(FuzzyError::Ident(_))
    ));
}

/// A plant whose ARX-Laguerre residual carries a saturating nonlinearity of its own past error:
/// y(k) = 0.8 y(k−1) + v(k), v(k) = w(k) − 0.5·tanh(4 w(k−1)), w white. A linear AR model leaves
/// the nonlinear part in its residual; the fuzzy term should recover some of it.
#[test]
fn fal_is_no_worse_than_arx_laguerre_and_helps_on_nonlinear_residual() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let n = 40_000;
    let w: Vec<f64> = (0..n).map(|_| rng.random::<f64>() - 0.5).collect();
    let mut y = vec![0.0; n];
    for k in 1..n {
        y[k] = 0.8 * y[k - 1] + w[k] - 0.5 * (4.0 * w[k - 1]).tanh();
    }
    let base = ArxLaguerreConfig::new(
        2,
        0,
        PoleChoice::Fixed {
            zeta_a: 0.5,
            zeta_b: 0.0,
        },
    )
    .unwrap();
    let (fit, test) = y.split_at(30_000);
    let cfg = FalConfig::with_base(base);
    let fal = FuzzyArxLaguerre::identify(fit, None, &cfg).unwrap();
    let al = fal.base();
    let p_al = al.predict(&y, None).unwrap();
    let p_fal = fal.predict(&y, None).unwrap();
    let m_al = FitMetrics::compute(test, &p_al[30_000..]).unwrap();
    let m_fal = FitMetrics::compute(test, &p_fal[30_000..]).unwrap();
    assert!(
        m_fal.rmse <= m_al.rmse * 1.001,
        "FAL {m_fal:?} vs AL {m_al:?}"
    );
    // Deterministic: same output twice.
    let again = FuzzyArxLaguerre::identify(fit, None, &cfg).unwrap();
    assert_eq!(again.fuzzy_coefficients(), fal.fuzzy_coefficients());
    let mut d = cfg;
    d.scaling = FuzzyScaling::Dissertation;
    assert!(FuzzyArxLaguerre::identify(fit, None, &d).is_ok());
}
