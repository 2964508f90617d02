//! Simulated recordings from `bearing-model` of each fault class, on other bearings, speeds
//! and sampling rates, must get the right verdict; a healthy one must be `normal`; bad inputs
//! must be the right typed error.

use bearing_model::{
    Bearing, BearingGeometry, FaultClass, FaultSet, ModelSpec, Noise, ParamSet, Scenario, Slip,
    Spall,
};
use diagnosis::{Baseline, BearingSpec, Diagnosis, DiagnosisError, Reference, Signal, diagnose};

mod common;
use common::{add_comb, ring_downs, show, sig, significance, white};

const SNR_DB: f64 = 10.0;
const DURATION_S: f64 = 2.0;

fn scenario(
    geometry: BearingGeometry,
    class: FaultClass,
    rpm: f64,
    fs: f64,
    seed: u64,
) -> Scenario {
    let mut s = Scenario::new(ParamSet::CwruRig, Bearing::Skf6205, rpm)
        .with_fs(fs)
        .with_duration(DURATION_S)
        .with_noise(Noise::SnrDb(SNR_DB))
        .with_seed(seed)
        .with_slip(Slip::Random { fraction: 0.01 });
    s.spec = ModelSpec { geometry, ..s.spec };
    s.spec.faults = FaultSet::of_class(
        class,
        Spall::new(0.014 * 0.0254).with_depth(bearing_model::scenario::CWRU_DEPTH_M),
    );
    s
}

fn sim(geometry: BearingGeometry, class: FaultClass, rpm: f64, fs: f64, seed: u64) -> Vec<f64> {
    scenario(geometry, class, rpm, fs, seed)
        .simulate()
        .unwrap()
        .accel
}

fn run(
    geometry: BearingGeometry,
    spec: &BearingSpec,
    class: FaultClass,
    rpm: f64,
    fs: f64,
    baseline: bool,
) -> Diagnosis {
    let x = sim(geometry, class, rpm, fs, 7);
    let b = baseline.then(|| {
        Baseline::prepare(&sig(&sim(geometry, FaultClass::None, rpm, fs, 99), fs)).unwrap()
    });
    let d = diagnose(&sig(&x, fs), rpm, spec, b.as_ref()).unwrap();
    show(
        &format!(
            "{class:?} {rpm} rpm {fs} Hz {} baseline={baseline}",
            spec.name
        ),
        &d,
    );
    d
}

fn expect(class: FaultClass) -> &'static str {
    match class {
        FaultClass::None => "normal",
        FaultClass::Inner => "inner",
        FaultClass::Outer => "outer",
        FaultClass::Ball => "ball",
        FaultClass::InnerOuter => "inner+outer",
        _ => unreachable!(),
    }
}

#[test]
fn each_class_6205_1797rpm_12k_baseline_and_self() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    for class in [
        FaultClass::None,
        FaultClass::Inner,
        FaultClass::Outer,
        FaultClass::Ball,
    ] {
        for baseline in [true, false] {
            let d = run(g, &spec, class, 1797.0, 12_000.0, baseline);
            assert_eq!(d.verdict, expect(class), "{class:?} baseline={baseline}");
            assert_eq!(
                d.reference,
                if baseline {
                    Reference::Baseline
                } else {
                    Reference::SelfReference
                }
            );
        }
    }
}

/// Against a baseline, a line the healthy machine already holds is read by what it has grown
/// (`evidence_db`, its prominence less the baseline's): a machine whose reference recording
/// already had an inner-race defect shows the BPFI lines with the baseline's subtracted, still
/// reads a new outer-race defect, and the same recording self-referenced reads `inner`; a
/// baseline of another length is compared too; a recording against itself is `normal`.
#[test]
fn lines_the_baseline_holds_are_not_evidence() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    let (rpm, fs) = (1797.0, 12_000.0);
    let reference = Baseline::prepare(&sig(&sim(g, FaultClass::Inner, rpm, fs, 99), fs)).unwrap();
    let same = sim(g, FaultClass::Inner, rpm, fs, 7);
    let d = diagnose(&sig(&same, fs), rpm, &spec, Some(&reference)).unwrap();
    show("inner against an inner baseline", &d);
    let inner = &d.evidence[0];
    assert!(
        inner
            .harmonics
            .iter()
            .any(|l| l.prominence_db >= 6.0 && l.evidence_db < l.prominence_db),
        "the BPFI lines are there and the baseline's are subtracted: {:?}",
        inner.harmonics
    );
    assert!(
        d.evidence
            .iter()
            .flat_map(|e| e.harmonics.iter())
            .all(|l| l.baseline_prominence_db.is_some())
    );
    let d = diagnose(&sig(&same, fs), rpm, &spec, None).unwrap();
    show("inner self-referenced", &d);
    assert_eq!(d.verdict, "inner");
    // a baseline of another length than the recording (CWRU's 97 holds 5 s at 12 kHz, its fault
    // records 10 s): its band envelopes come at another rate, and its lines are still compared
    // (until 2026-11-27 no line was: every `baseline_prominence_db` was null)
    let long = sim(g, FaultClass::Inner, rpm, fs, 99);
    let shorter = Baseline::prepare(&sig(&long[..long.len() * 7 / 10], fs)).unwrap();
    let d = diagnose(&sig(&same, fs), rpm, &spec, Some(&shorter)).unwrap();
    show("inner against a shorter inner baseline", &d);
    assert!(
        d.evidence
            .iter()
            .flat_map(|e| e.harmonics.iter())
            .all(|l| l.baseline_prominence_db.is_some()),
        "a baseline of another length is compared: {:?}",
        d.evidence[0].harmonics
    );
    let outer = sim(g, FaultClass::Outer, rpm, fs, 7);
    let d = diagnose(&sig(&outer, fs), rpm, &spec, Some(&reference)).unwrap();
    show("outer against an inner baseline", &d);
    assert_eq!(
        d.verdict, "outer",
        "a new fault against a baseline with another"
    );
    // a recording against itself is unchanged, whatever it holds
    for class in [FaultClass::Inner, FaultClass::Outer, FaultClass::Ball] {
        let x = sim(g, class, rpm, fs, 5);
        let own = Baseline::prepare(&sig(&x, fs)).unwrap();
        let d = diagnose(&sig(&x, fs), rpm, &spec, Some(&own)).unwrap();
        show(&format!("{class:?} against itself"), &d);
        assert_eq!(d.verdict, "normal", "{class:?} against itself");
    }
}

/// A machine whose reference recording already had an inner-race defect reads `normal` when
/// nothing has changed (another stretch of the same state, the whole reference or 70 % of it):
/// the lines the baseline holds have not grown.
#[test]
fn an_unchanged_fault_against_its_own_state_reads_normal() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    let (rpm, fs) = (1797.0, 12_000.0);
    let long = sim(g, FaultClass::Inner, rpm, fs, 99);
    let same = sim(g, FaultClass::Inner, rpm, fs, 7);
    for (what, reference) in [
        ("its own state", Baseline::prepare(&sig(&long, fs)).unwrap()),
        (
            "a shorter stretch of its own state",
            Baseline::prepare(&sig(&long[..long.len() * 7 / 10], fs)).unwrap(),
        ),
    ] {
        let d = diagnose(&sig(&same, fs), rpm, &spec, Some(&reference)).unwrap();
        show(&format!("unchanged inner defect against {what}"), &d);
        assert_eq!(d.verdict, "normal", "unchanged inner defect against {what}");
    }
}

#[test]
fn combined_inner_outer_is_joined() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    let d = run(g, &spec, FaultClass::InnerOuter, 1797.0, 12_000.0, true);
    assert_eq!(d.verdict, "inner+outer");
}

/// Another bearing, speed and rate: a 6203 at 900 rpm, 48 kHz, 2 s (30 turns), against a
/// healthy baseline: healthy reads `normal`, an outer-race fault `outer`.
#[test]
fn skf_6203_at_900_rpm_48k() {
    let g = BearingGeometry::skf_6203();
    let spec = BearingSpec::parse("6203").unwrap();
    for class in [FaultClass::None, FaultClass::Outer] {
        let d = run(g, &spec, class, 900.0, 48_000.0, true);
        assert_eq!(d.verdict, expect(class), "6203 {class:?}");
    }
}

/// The same 6203 with an inner-race or a ball fault. At 900 rpm fr = 15 Hz: the ball-defect
/// rate (3.988 fr = 59.8 Hz) lies on the 4th shaft order and on 60 Hz, BPFI (4.947 fr) 1 %
/// below the 5th order; the faults' own lines at shaft orders make the band show a shaft comb
/// and a 60 Hz "mains" comb, whose masks (± a bin of fr/8 at 30 turns) take harmonics 1–2 of
/// both. A vibration engineer would still call both faults from the lines left (BPFI×3 20 dB,
/// BSF×1–3 10/6/5 dB over a quiet floor).
#[test]
#[ignore = "detector: 6203 inner and ball faults at 900 rpm read normal (inner p_healthy 1.0, 2 lines read, harmonics 1-2 masked; ball p_healthy 1.5e-2 > α/6, depth 0.76): the faults' own combs are masked as shaft and 60 Hz mains combs"]
fn skf_6203_at_900_rpm_48k_inner_and_ball() {
    let g = BearingGeometry::skf_6203();
    let spec = BearingSpec::parse("6203").unwrap();
    for class in [FaultClass::Inner, FaultClass::Ball] {
        let d = run(g, &spec, class, 900.0, 48_000.0, true);
        assert_eq!(d.verdict, expect(class), "6203 {class:?}");
    }
}

/// A 6203's inner-race family k·BPFI ± m·fr is a near-comb at 0.989 fr (BPFI = 4.947 fr):
/// self-referenced, 6 s at 25.6 kHz (bins of 1/6 Hz, wider than the 1 % between the combs), the
/// envelope speed search found that near-comb and its refinement agreed on the flanks of the
/// shaft's own 1× and 2× lines at the edges of their windows: the record was analysed at
/// 891.4 rpm and its BPFI − fr line read as the ball-defect rate (verdict `ball`,
/// `residual_features::speed`'s `refine_ignores_lines_outside_their_windows`). The speed must
/// stay (the verdict: [`skf_6203_inner_race_with_a_near_comb_is_found`]).
#[test]
fn skf_6203_inner_race_near_comb_does_not_move_the_speed() {
    let spec = BearingSpec::parse("6203").unwrap();
    let (rpm, fs) = (900.0, 25_600.0);
    let x = near_comb_record(rpm, fs);
    let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
    show("6203 inner race, near-comb", &d);
    let used = d.operating_point.rpm_used;
    assert!((used / rpm - 1.0).abs() < 2e-3, "analysed at {used} rpm");
    assert_ne!(d.verdict, "ball", "BPFI − fr read as the ball-defect rate");
}

fn near_comb_record(rpm: f64, fs: f64) -> Vec<f64> {
    scenario(BearingGeometry::skf_6203(), FaultClass::Inner, rpm, fs, 3)
        .with_duration(6.0)
        .simulate()
        .unwrap()
        .accel
}

/// The record of [`skf_6203_inner_race_near_comb_does_not_move_the_speed`] reads `inner`: its
/// BPFI lines stand 20–22 dB over the local median.
#[test]
fn skf_6203_inner_race_with_a_near_comb_is_found() {
    let spec = BearingSpec::parse("6203").unwrap();
    let (rpm, fs) = (900.0, 25_600.0);
    let d = diagnose(&sig(&near_comb_record(rpm, fs), fs), rpm, &spec, None).unwrap();
    show("6203 inner race, near-comb", &d);
    assert_eq!(d.verdict, "inner");
}

#[test]
fn made_up_bearing_at_1750_rpm_self_referenced() {
    let spec = BearingSpec::parse("n=12,d=0.25in,D=1.6in,angle=0deg").unwrap();
    let g = spec.geometry.unwrap();
    for class in [
        FaultClass::None,
        FaultClass::Inner,
        FaultClass::Outer,
        FaultClass::Ball,
    ] {
        let d = run(g, &spec, class, 1750.0, 12_000.0, false);
        assert_eq!(d.verdict, expect(class), "made-up {class:?}");
    }
}

#[test]
fn report_serialises_without_nan() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    let d = run(g, &spec, FaultClass::Outer, 1797.0, 12_000.0, true);
    // serde_json writes NaN as null: the only nulls allowed are "not explained", "not on a shaft
    // order", "no mains comb masked", the measured speed of a record too short to resolve it,
    // the band limit of a baseline that holds the whole band, the former rule's constants
    // (keys kept for scripts, `null` since the detector of 2026-12) and, when self-referenced,
    // the energy ratios and the lines' baseline prominences
    const FORMER: [&str; 4] = [
        "min_harmonics",
        "sk_sigmas",
        "cfar_quantile",
        "second_band_line_db",
    ];
    const ABSENT: [&str; 4] = ["explained_by", "measured_speed", "shaft_order", "mains_hz"];
    fn nulls(v: &serde_json::Value, key: &str, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Null => out.push(key.to_string()),
            serde_json::Value::Array(a) => a.iter().for_each(|x| nulls(x, key, out)),
            serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| nulls(x, k, out)),
            _ => {}
        }
    }
    let v = serde_json::to_value(&d).unwrap();
    assert_eq!(v["reference"], "baseline");
    let mut n = Vec::new();
    nulls(&v, "", &mut n);
    assert!(
        n.iter().all(|k| ABSENT.contains(&k.as_str())
            || FORMER.contains(&k.as_str())
            || k == "compared_below_hz"),
        "{n:?}"
    );
    for k in FORMER {
        assert!(v["thresholds"][k].is_null(), "{k}");
    }
    let d = run(g, &spec, FaultClass::None, 1797.0, 12_000.0, false);
    let v = serde_json::to_value(&d).unwrap();
    assert_eq!(v["reference"], "self");
    let mut n = Vec::new();
    nulls(&v, "", &mut n);
    n.retain(|k| {
        !(ABSENT.contains(&k.as_str())
            || FORMER.contains(&k.as_str())
            || k == "baseline_prominence_db")
    });
    assert_eq!(n, ["compared_below_hz", "energy_ratio", "energy_ratio_db"]);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let spec = BearingSpec::parse("6205").unwrap();
    let fs = 12_000.0;
    let x = sim(BearingGeometry::skf_6205(), FaultClass::None, 1797.0, fs, 1);
    let err = |r: Result<Diagnosis, DiagnosisError>| {
        let e = r.unwrap_err();
        assert!(!e.to_string().contains('\n'), "one line: {e}");
        e
    };
    // the recording and the baseline as the command builds them: a bad rate, no samples or a
    // non-finite sample cannot make a `Signal`, and say so in the diagnosis's words
    let diag =
        |x: &[f64], f: f64, rpm: f64, b: Option<&Baseline>| -> Result<Diagnosis, DiagnosisError> {
            diagnose(&Signal::new(x, f)?, rpm, &spec, b)
        };
    let prepare = |x: &[f64], f: f64| -> Result<Baseline, DiagnosisError> {
        Baseline::prepare(&Signal::new(x, f).map_err(|e| DiagnosisError::signal("baseline", e))?)
    };
    assert!(matches!(
        BearingSpec::parse("6299"),
        Err(bearing_model::ModelError::UnknownBearing(_))
    ));
    for rpm in [0.0, -5.0, f64::NAN, f64::INFINITY, 1.0e6] {
        assert!(matches!(
            err(diag(&x, fs, rpm, None)),
            DiagnosisError::RpmOutOfRange { .. }
        ));
    }
    for f in [0.0, f64::NAN, 10.0, 1e9] {
        assert!(matches!(
            err(diag(&x, f, 1797.0, None)),
            DiagnosisError::SampleRateOutOfRange { .. }
        ));
    }
    assert!(matches!(
        err(diag(&x, 2_000.0, 20_000.0, None)),
        DiagnosisError::SampleRateTooLow { .. }
    ));
    // 5 shaft turns; and 15 (0.5 s), which the former minimum of 10 turns accepted: now 20
    // turns at the slowest speed searched (0.9 × the declared one) are needed
    assert!(matches!(
        err(diag(&x[..2000], fs, 1797.0, None)),
        DiagnosisError::TooShort { .. }
    ));
    let e = err(diag(&x[..6000], fs, 1797.0, None));
    assert!(
        matches!(
            e,
            DiagnosisError::TooShort {
                min_turns: 20.0,
                ..
            }
        ),
        "{e}"
    );
    assert!(matches!(
        err(diag(&[], fs, 1797.0, None)),
        DiagnosisError::Empty { what: "recording" }
    ));
    let mut bad = x.clone();
    bad[500] = f64::NAN;
    assert!(matches!(
        err(diag(&bad, fs, 1797.0, None)),
        DiagnosisError::NonFinite {
            what: "recording",
            index: 500,
            ..
        }
    ));
    bad[500] = f64::INFINITY;
    assert!(matches!(
        prepare(&bad, fs),
        Err(DiagnosisError::NonFinite {
            what: "baseline",
            ..
        })
    ));
    let b48 = prepare(&x, 48_000.0).unwrap();
    assert!(matches!(
        err(diag(&x, fs, 1797.0, Some(&b48))),
        DiagnosisError::SampleRateMismatch { .. }
    ));
    assert!(matches!(
        prepare(&x[..100], fs),
        Err(DiagnosisError::BaselineTooShort { .. })
    ));
    let flat = vec![1.0; x.len()];
    assert!(matches!(
        err(diag(&flat, fs, 1797.0, None)),
        DiagnosisError::Degenerate { .. }
    ));
    assert!(matches!(
        prepare(&flat, fs),
        Err(DiagnosisError::Degenerate { .. })
    ));
}

/// A baseline decimated from a higher rate holds nothing between its anti-aliasing filter's
/// passband edge and the new Nyquist, where its whitener's gain is as deep as the filter's
/// stopband. A healthy recording of the same machine acquired at the lower rate (content up to
/// 0.95 of its Nyquist) then read tens of dB of "energy" against it; compared below the
/// passband edge (`Baseline::band_limited`) it reads about 0 dB. Bad limits are typed errors.
#[test]
fn a_decimated_baseline_compares_energy_below_its_passband_edge() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    let (fs_hi, q) = (48_000.0, 4);
    let fs = fs_hi / q as f64;
    let decimate = |x: &[f64], fraction: f64| {
        let p = bearing_data::DecimatorParams {
            passband_fraction: fraction,
            ..bearing_data::DecimatorParams::new(q)
        };
        bearing_data::Decimator::new(p)
            .unwrap()
            .decimate(x)
            .unwrap()
    };
    let base_x = decimate(&sim(g, FaultClass::None, 1797.0, fs_hi, 99), 0.8);
    // the same machine acquired at 12 kHz behind a sharper anti-aliasing filter
    let x = decimate(&sim(g, FaultClass::None, 1797.0, fs_hi, 7), 0.95);
    let whole = Baseline::prepare(&sig(&base_x, fs)).unwrap();
    let edge = bearing_data::DecimatorParams::new(q).passband_edge_hz(fs_hi);
    assert_eq!(edge, 4_800.0);
    let limited = whole.clone().band_limited(edge).unwrap();
    assert_eq!(limited.band_limit_hz, Some(edge));
    let db = |b: &Baseline| {
        let d = diagnose(&sig(&x, fs), 1797.0, &spec, Some(b)).unwrap();
        show(
            "a_decimated_baseline_compares_energy_below_its_passband_edge: &x",
            &d,
        );
        (
            d.statistics.energy_ratio_db.unwrap(),
            d.statistics.compared_below_hz,
            d.verdict,
        )
    };
    let (db_whole, below_whole, v_whole) = db(&whole);
    let (db_limited, below_limited, v_limited) = db(&limited);
    eprintln!("energy against the whole band {db_whole:.1} dB, below {edge} Hz {db_limited:.1} dB");
    assert!(
        db_whole > 10.0,
        "the artefact this guards against: {db_whole:.1} dB"
    );
    assert!(
        db_limited.abs() < 2.0,
        "healthy against healthy: {db_limited:.1} dB"
    );
    assert_eq!((below_whole, below_limited), (None, Some(edge)));
    assert_eq!(v_whole, v_limited, "the ratios do not enter the verdict");
    // a limit at or above Nyquist leaves the baseline as it is; bad limits are typed errors
    assert_eq!(whole.clone().band_limited(fs / 2.0).unwrap(), whole);
    for bad in [f64::NAN, 0.0, -1.0] {
        assert!(matches!(
            whole.clone().band_limited(bad),
            Err(DiagnosisError::Degenerate { .. })
        ));
    }
    let model = Baseline::from_whitener(whole.whitener.clone(), 1.0, 3.0, 100).unwrap();
    assert!(matches!(
        model.band_limited(edge),
        Err(DiagnosisError::Degenerate { .. })
    ));
}

/// A baseline rebuilt from its whitener's coefficients and residual statistics
/// (`ArWhitener::from_coefficients`, `Baseline::from_whitener`: how a calibrated machine model
/// becomes a baseline) diagnoses exactly as the prepared one; bad parts are typed errors.
#[test]
fn baseline_from_a_model_matches_the_prepared_one() {
    let g = BearingGeometry::skf_6205();
    let spec = BearingSpec::parse("6205").unwrap();
    let fs = 12_000.0;
    let prepared = Baseline::prepare(&sig(&sim(g, FaultClass::None, 1797.0, fs, 99), fs)).unwrap();
    let w = diagnosis::ArWhitener::from_coefficients(
        prepared.whitener.coefficients.clone(),
        fs,
        "model",
    )
    .unwrap();
    let rebuilt = Baseline::from_whitener(
        w,
        prepared.residual_rms,
        prepared.residual_kurtosis,
        prepared.samples,
    )
    .unwrap();
    let x = sim(g, FaultClass::Outer, 1797.0, fs, 7);
    let a = diagnose(&sig(&x, fs), 1797.0, &spec, Some(&prepared)).unwrap();
    let b = diagnose(&sig(&x, fs), 1797.0, &spec, Some(&rebuilt)).unwrap();
    assert_eq!(a.verdict, b.verdict);
    assert_eq!(a.scores, b.scores);
    assert!(matches!(
        diagnosis::ArWhitener::from_coefficients(vec![], fs, "model"),
        Err(DiagnosisError::Degenerate { .. })
    ));
    assert!(matches!(
        diagnosis::ArWhitener::from_coefficients(vec![0.5, f64::NAN], fs, "model"),
        Err(DiagnosisError::Degenerate { .. })
    ));
    let w = diagnosis::ArWhitener::from_coefficients(vec![0.5], fs, "model").unwrap();
    assert!(matches!(
        Baseline::from_whitener(w, f64::NAN, 3.0, 10),
        Err(DiagnosisError::Degenerate { .. })
    ));
}

/// Dense outer-race impacts (another rig: 12 balls, 3600 rpm, BPFO ≈ 286 Hz against a 3 kHz
/// ring-down of ~2.5 ms) overlap into a band of low spectral kurtosis, yet their envelope holds
/// BPFO and its harmonics far above the background: the verdict is `outer`, read in a band
/// holding the resonance, with and without a baseline; the healthy record stays `normal`.
/// Sampled at 16 kHz: at the former 8 kHz the bands the detector needs (≥ 2.66 kHz wide and
/// above 2.66 kHz, for its null's reach at up to 1.1 × 3600 rpm) do not fit below Nyquist, an
/// input error (`SampleRateTooLow`) now.
#[test]
#[ignore = "detector: dense impacts read normal (outer p_healthy 2.8e-3 after the speed search, BPFO×1-3 at 15/10/8 dB, modulation depth 0.45 < 0.5)"]
fn dense_impacts_of_low_kurtosis_are_read_on_periodicity() {
    use rand::SeedableRng;
    let (fs, rpm) = (16_000.0, 3600.0);
    let spec = BearingSpec::parse("n=12,d=7.94mm,D=38.5mm,angle=0deg").unwrap();
    let bpfo = spec.orders.bpfo * rpm / 60.0;
    let n = (4.0 * fs) as usize;
    let record = |fault: bool, seed: u64| -> Vec<f64> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut x = white(n, 0.35, &mut rng);
        if fault {
            ring_downs(
                &mut x,
                fs,
                bpfo,
                3000.0,
                0.02,
                0.012,
                0.01,
                &mut rng,
                |_| 1.0,
            );
        }
        x
    };
    let healthy = record(false, 3);
    let base = Baseline::prepare(&sig(&record(false, 4), fs)).unwrap();
    let faulty = record(true, 5);
    for b in [None, Some(&base)] {
        let d = diagnose(&sig(&faulty, fs), rpm, &spec, b).unwrap();
        show(&format!("dense impacts, baseline {}", b.is_some()), &d);
        assert_eq!(d.verdict, "outer");
        // read where the impacts ring
        let s = significance(&d, "outer");
        assert!(s.band_hz[0] <= 3000.0 && 3000.0 <= s.band_hz[1], "{s:?}");
        let h = diagnose(&sig(&healthy, fs), rpm, &spec, b).unwrap();
        show(
            &format!("dense impacts healthy, baseline {}", b.is_some()),
            &h,
        );
        assert_eq!(h.verdict, "normal", "{:?}", h.scores);
    }
}

/// A speed declared 1.5–4 % off (a nameplate speed): the recording's shaft-harmonic comb gives the
/// speed the fault lines are read at, and the outer-race fault is found; white noise has no comb
/// to trust and keeps the declared speed.
#[test]
fn speed_is_measured_from_the_shaft_comb_when_the_declared_one_is_off() {
    use rand::SeedableRng;
    let (fs, rpm) = (12_000.0, 1480.0);
    let spec = BearingSpec::parse("6205").unwrap();
    let fr = rpm / 60.0;
    let bpfo = spec.orders.bpfo * fr;
    let n = (8.0 * fs) as usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let mut x = white(n, 0.3, &mut rng);
    add_comb(&mut x, fs, fr, 6, |h| 0.05 / h, |h| 0.3 * h);
    ring_downs(
        &mut x,
        fs,
        bpfo,
        3200.0,
        0.05,
        0.004,
        0.005,
        &mut rng,
        |_| 0.8,
    );
    // an induction motor's nameplate speed is off by its slip: up to 3–5 %
    for off in [-0.04, -0.025, 0.015, 0.04] {
        let d = diagnose(&sig(&x, fs), rpm * (1.0 + off), &spec, None).unwrap();
        show(
            "speed_is_measured_from_the_shaft_comb_when_the_declared_one_is_off: &x",
            &d,
        );
        let m = d.operating_point.measured_speed.expect("speed measured");
        assert!(m.accepted, "{off}: {m:?}");
        assert!(
            (d.operating_point.rpm_used / rpm - 1.0).abs() < 0.001,
            "{off}: {m:?}"
        );
        assert_eq!(d.verdict, "outer", "{off}: {:?}", d.scores);
    }
    let declared = rpm * 1.015;
    let noise = white(n, 1.0, &mut rng);
    let d = diagnose(&sig(&noise, fs), declared, &spec, None).unwrap();
    show(
        "speed_is_measured_from_the_shaft_comb_when_the_declared_one_is_off: &noise",
        &d,
    );
    assert_eq!(d.operating_point.rpm_used, declared);
    assert!(!d.operating_point.measured_speed.unwrap().accepted);
}

/// Mains harmonics (50…300 Hz) on a 4-pole machine at 1480 rpm are the even orders of a comb at
/// 25 Hz, 1.3 % above the shaft: with no shaft comb in the record the measured speed is not
/// trusted, the declared one is kept, and the inner-race fault is found. A 6203's ball-defect
/// rate (3.988 fr) next to a pure 4×-order comb (a four-blade fan) is not a ball fault.
#[test]
#[ignore = "detector: a four-blade fan at 4 fr on a 6203 at 1500 rpm reads ball (p_healthy 1.1e-3, depth 0.56): the ball-defect rate 3.988 fr puts every harmonic window on an integer order, the pure 4x comb is no complete shaft comb so nothing masks it, and the cage sidebands that would tell a ball defect (0.8, 2.5 dB) are not required"]
fn mains_combs_and_shaft_orders_are_not_taken_for_the_shaft_or_a_fault() {
    use rand::SeedableRng;
    let two_pi = 2.0 * std::f64::consts::PI;
    let (fs, rpm) = (20_000.0, 1480.0);
    let spec = BearingSpec::parse("n=12,d=7.94mm,D=38.5mm,angle=0deg").unwrap();
    let fr = rpm / 60.0;
    let bpfi = spec.orders.bpfi * fr;
    let n = (4.0 * fs) as usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
    let mut x = white(n, 0.3, &mut rng);
    add_comb(&mut x, fs, 50.0, 6, |h| 0.6 / h, |h| h);
    // inner-race impacts at BPFI, amplitude modulated at fr (load zone)
    ring_downs(
        &mut x,
        fs,
        bpfi,
        3500.0,
        0.05,
        0.003,
        0.005,
        &mut rng,
        |t0| 0.6 * (1.0 + 0.8 * (two_pi * fr * t0).cos()),
    );
    let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
    show(
        "mains_combs_and_shaft_orders_are_not_taken_for_the_shaft_or_a_fault: &x",
        &d,
    );
    assert_eq!(
        d.operating_point.rpm_used, rpm,
        "{:?}",
        d.operating_point.measured_speed
    );
    assert_eq!(d.verdict, "inner", "{:?}", d.scores);

    let spec = BearingSpec::parse("6203").unwrap();
    let (fs, rpm) = (20_000.0, 1500.0);
    let fr = rpm / 60.0;
    let mut y = white(n, 1.0, &mut rng);
    // a four-blade fan: pressure pulses at 4 fr ringing a 2.5 kHz mode
    ring_downs(
        &mut y,
        fs,
        4.0 * fr,
        2500.0,
        0.04,
        0.004,
        0.0,
        &mut rng,
        |_| 1.5,
    );
    let d = diagnose(&sig(&y, fs), rpm, &spec, None).unwrap();
    show(
        "mains_combs_and_shaft_orders_are_not_taken_for_the_shaft_or_a_fault: &y",
        &d,
    );
    assert_eq!(d.verdict, "normal", "{:#?}", d.evidence);
}

/// A nameplate speed 2.7 % above the shaft's, on a record whose own spectrum holds no shaft
/// comb (mains lines only): the inner-race impacts, struck only while the defect turns through
/// the load zone, carry the shaft comb in their squared envelope, which gives the speed
/// (`envelope_speed`), and the fault is found. At the declared speed the BPFI lines lie 2.7 %
/// outside their window (without the envelope's speed this record reads `normal`). An
/// outer-race fault (not modulated at fr) has no envelope comb, and its declared speed is kept.
#[test]
fn speed_is_read_from_the_envelope_when_the_spectrum_shows_no_shaft_comb() {
    use rand::SeedableRng;
    let two_pi = 2.0 * std::f64::consts::PI;
    let (fs, rpm, declared) = (20_000.0, 1460.0, 1500.0);
    let fr = rpm / 60.0;
    let n = (6.0 * fs) as usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(31);
    // white noise and mains lines, and impacts at `rate_hz` ringing 3.5 kHz, in the load zone
    // of a radially loaded bearing with clearance when `load_zone` (Stribeck's distribution,
    // ε = 0.1: q ∝ [1 − (1 − cos θ)/(2ε)]^1.5 within ± 37° of the load, none outside: a pulse
    // train at fr rich in shaft harmonics), else of constant amplitude
    let mut record = |rate_hz: f64, load_zone: bool| {
        let mut x = white(n, 0.3, &mut rng);
        add_comb(&mut x, fs, 50.0, 6, |h| 0.6 / h, |h| h);
        let q = |t0: f64| (1.0 - (1.0 - (two_pi * fr * t0).cos()) / 0.2).max(0.0);
        ring_downs(
            &mut x,
            fs,
            rate_hz,
            3500.0,
            0.05,
            0.003,
            0.005,
            &mut rng,
            |t0| {
                if load_zone {
                    2.0 * q(t0).powf(1.5)
                } else {
                    0.6
                }
            },
        );
        x
    };
    let spec = BearingSpec::parse("6205").unwrap();
    let d = diagnose(
        &sig(&record(spec.orders.bpfi * fr, true), fs),
        declared,
        &spec,
        None,
    )
    .unwrap();
    let op = &d.operating_point;
    assert!(
        !op.measured_speed.is_some_and(|m| m.accepted),
        "{:?}",
        op.measured_speed
    );
    let m = op.envelope_speed.expect("no envelope speed");
    assert!(m.envelope_band_hz.is_some(), "{m:?}");
    assert!((op.rpm_used / rpm - 1.0).abs() < 0.001, "{m:?}");
    assert_eq!(d.verdict, "inner", "{:?}", d.scores);

    let d = diagnose(
        &sig(&record(spec.orders.bpfo * fr, false), fs),
        rpm,
        &spec,
        None,
    )
    .unwrap();
    show(
        "speed_is_read_from_the_envelope_when_the_spectrum_shows_no_shaft_comb: &record(spec.orders.bpfo * fr",
        &d,
    );
    assert_eq!(d.operating_point.rpm_used, rpm, "{:?}", d.operating_point);
    assert_eq!(d.verdict, "outer", "{:?}", d.scores);

    // a 6203's inner-race family k·BPFI ± m·fr (BPFI = 4.947 fr) forms a near-comb at 0.989 fr
    // in the same envelope: it must not move a right declared speed
    let spec = BearingSpec::parse("6203").unwrap();
    let d = diagnose(
        &sig(&record(spec.orders.bpfi * fr, true), fs),
        rpm,
        &spec,
        None,
    )
    .unwrap();
    show(
        "speed_is_read_from_the_envelope_when_the_spectrum_shows_no_shaft_comb: &record(spec.orders.bpfi * fr",
        &d,
    );
    assert!(
        (d.operating_point.rpm_used / rpm - 1.0).abs() < 0.001,
        "{:?}",
        d.operating_point
    );
    assert_eq!(d.verdict, "inner", "{:?}", d.scores);
}

/// Two faults whose impacts ring different resonances: inner-race impacts (BPFI, modulated at
/// fr as the defect turns through the load zone) ring 2.4 kHz strongly, outer-race impacts
/// (BPFO) ring 4.6 kHz at a third of the amplitude. Each hypothesis is read in the band where
/// it reads strongest, the outer race's holding 4.6 kHz and not 2.4 kHz; the fault whose
/// harmonics modulate its envelope less, re-tested with the other's line family masked, stays
/// significant (a second fault, not lines of the first), and the report lists it under
/// `secondary` with its own band, the one its impacts ring. Each fault alone stays a single verdict, and the healthy
/// record `normal`, on another bearing and speed than CWRU's.
#[test]
fn a_second_fault_in_a_band_of_its_own_is_joined() {
    use rand::SeedableRng;
    let (fs, rpm) = (16_000.0, 1320.0);
    let spec = BearingSpec::parse("n=9,d=7.94mm,D=39.04mm,angle=0deg").unwrap();
    let fr = rpm / 60.0;
    let (bpfi, bpfo) = (spec.orders.bpfi * fr, spec.orders.bpfo * fr);
    let n = (6.0 * fs) as usize;
    let record = |inner: bool, outer: bool, seed: u64| -> Vec<f64> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut x = white(n, 0.3, &mut rng);
        if inner {
            let w = 2.0 * std::f64::consts::PI * fr;
            ring_downs(&mut x, fs, bpfi, 2400.0, 0.04, 0.004, 0.01, &mut rng, |t| {
                2.0 * (1.0 + 0.6 * (w * t).cos())
            });
        }
        if outer {
            ring_downs(
                &mut x,
                fs,
                bpfo,
                4600.0,
                0.04,
                0.003,
                0.01,
                &mut rng,
                |_| 0.6,
            );
        }
        x
    };
    let base = Baseline::prepare(&sig(&record(false, false, 1), fs)).unwrap();
    for b in [None, Some(&base)] {
        let d = diagnose(&sig(&record(true, true, 2), fs), rpm, &spec, b).unwrap();
        show(&format!("inner and outer, baseline {}", b.is_some()), &d);
        assert_eq!(d.verdict, "inner+outer");
        let outer = significance(&d, "outer");
        assert!(
            outer.band_hz[0] <= 4600.0 && 4600.0 <= outer.band_hz[1] && outer.band_hz[0] > 2400.0,
            "{outer:?}"
        );
        let alpha = d.false_alarm;
        let inner = significance(&d, "inner");
        for x in [&inner, &outer] {
            assert!(x.significant && x.explained_by.is_none(), "{x:?}");
        }
        // faults are taken by modulation depth: the shallower is re-tested with the deeper
        // one's line family masked and stays significant (a second fault, not its lines)
        let second = if inner.modulation_depth < outer.modulation_depth {
            &inner
        } else {
            &outer
        };
        assert!(
            second.p_given_stronger.is_some_and(|p| p <= alpha / 3.0),
            "tested with the other race's family masked: {second:?}"
        );
        // the report's secondary fault (the one beside the primary) in a band of its own: the
        // one it reads in, not the other fault's
        assert_eq!(d.secondary.len(), 1, "{:#?}", d.secondary);
        let s = &d.secondary[0];
        let (own, other) = match s.hypothesis {
            diagnosis::Hypothesis::Inner => (&inner, &outer),
            diagnosis::Hypothesis::Outer => (&outer, &inner),
            h => panic!("secondary {h:?}"),
        };
        assert_eq!([s.band.low_hz, s.band.high_hz], own.band_hz, "{:?}", s.band);
        assert_ne!(own.band_hz, other.band_hz, "{own:?} {other:?}");
        for (inner, outer, want) in [
            (true, false, "inner"),
            (false, true, "outer"),
            (false, false, "normal"),
        ] {
            let d = diagnose(&sig(&record(inner, outer, 3), fs), rpm, &spec, b).unwrap();
            show(&format!("{want}, baseline {}", b.is_some()), &d);
            assert_eq!(d.verdict, want);
        }
    }
}

/// A ball defect strikes at the ball-defect rate and passes through the load zone once per cage
/// turn, so its envelope holds cage harmonics; the 9th of a 6205's is at BPFO. The cage slips on
/// its own (here 1.5 %, the ball-spin line not at all): those harmonics sit 1.5 % below the
/// kinematic BPFO, inside the outer race's slip window. They belong to the ball fault's family
/// and are no outer-race fault: the verdict is `ball`, with and without a baseline.
#[test]
fn a_slipping_cage_s_harmonics_are_not_an_outer_race_fault() {
    use rand::SeedableRng;
    let (fs, rpm) = (12_000.0, 1797.0);
    let spec = BearingSpec::parse("6205").unwrap();
    let fr = rpm / 60.0;
    let bsf = spec.orders.ball_defect * fr;
    let cage = 0.985 * spec.orders.ftf * fr;
    let n = (8.0 * fs) as usize;
    let record = |fault: bool, seed: u64| -> Vec<f64> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut x = white(n, 0.3, &mut rng);
        if fault {
            // strikes only in the load zone: a sharp half-wave of the cage angle
            let w = 2.0 * std::f64::consts::PI * cage;
            ring_downs(&mut x, fs, bsf, 3300.0, 0.03, 0.004, 0.003, &mut rng, |t| {
                3.0 * (w * t).cos().max(0.0).powi(3)
            });
        }
        x
    };
    let base = Baseline::prepare(&sig(&record(false, 1), fs)).unwrap();
    for b in [None, Some(&base)] {
        let d = diagnose(&sig(&record(true, 2), fs), rpm, &spec, b).unwrap();
        show(
            "a_slipping_cage_s_harmonics_are_not_an_outer_race_fault: &record(true",
            &d,
        );
        assert_eq!(d.verdict, "ball", "{:?} {:#?}", d.scores, d.evidence);
    }
}

/// A ball fault (cage-modulated impacts ringing 2.4 kHz) with an outer-race fault ringing
/// 4.6 kHz: the ball's cage harmonics include BPFO = n·FTF, but where the ball's own lines do
/// not show, they explain nothing — the outer race is found in its own band: `outer+ball`.
#[test]
#[ignore = "detector: reads ball only (outer p_healthy 3.1e-8, depth 0.65, but p 1.0 once the ball's family is masked in every band: its cage harmonics j·FTF cover k·BPFO = k·n·FTF on any bearing)"]
fn an_outer_race_beside_a_stronger_ball_fault_is_found_in_its_own_band() {
    use rand::SeedableRng;
    let (fs, rpm) = (12_000.0, 1797.0);
    let spec = BearingSpec::parse("6205").unwrap();
    let fr = rpm / 60.0;
    let (bsf, bpfo) = (spec.orders.ball_defect * fr, spec.orders.bpfo * fr);
    let cage = spec.orders.ftf * fr;
    let n = (8.0 * fs) as usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
    let mut x = white(n, 0.3, &mut rng);
    let w = 2.0 * std::f64::consts::PI * cage;
    ring_downs(&mut x, fs, bsf, 2400.0, 0.04, 0.004, 0.01, &mut rng, |t| {
        2.0 * (0.6 + 0.4 * (w * t).cos())
    });
    ring_downs(
        &mut x,
        fs,
        bpfo,
        4600.0,
        0.04,
        0.003,
        0.01,
        &mut rng,
        |_| 1.2,
    );
    let d = diagnose(&sig(&x, fs), rpm, &spec, None).unwrap();
    show("outer beside a stronger ball fault", &d);
    assert_eq!(d.verdict, "outer+ball");
    let outer = significance(&d, "outer");
    assert!(
        outer.band_hz[0] <= 4600.0 && 4600.0 <= outer.band_hz[1],
        "{outer:?}"
    );
}

/// Two faults ringing one resonance whose rates lie within a search window of each other: the
/// inner race's lower sideband BPFI − fr 2 % below the ball-defect rate (a bearing given by its
/// four multiples, 1200 rpm), inside the ball's slip window, the inner race strongly modulated at
/// fr (8 s at 12 kHz).
fn inner_and_ball_record(inner: bool, ball: bool, seed: u64) -> (Vec<f64>, BearingSpec) {
    use rand::SeedableRng;
    let (fs, rpm) = (12_000.0, 1200.0);
    let fr = rpm / 60.0;
    let (bpfi, bsf) = (9.9, (9.9 - 1.0) / 0.98);
    let spec = BearingSpec::parse(&format!("bpfo=6.1,bpfi={bpfi},ftf=0.41,bsf={bsf:.6}")).unwrap();
    let n = (8.0 * fs) as usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut x = white(n, 0.3, &mut rng);
    if inner {
        let w = 2.0 * std::f64::consts::PI * fr;
        ring_downs(
            &mut x,
            fs,
            bpfi * fr,
            3000.0,
            0.04,
            0.002,
            0.002,
            &mut rng,
            |t| 2.0 * (1.0 + 0.9 * (w * t).cos()),
        );
    }
    if ball {
        ring_downs(
            &mut x,
            fs,
            bsf * fr,
            3000.0,
            0.04,
            0.002,
            0.002,
            &mut rng,
            |_| 1.0,
        );
    }
    (x, spec)
}

/// [`inner_and_ball_record`] with both faults: the ball window's strongest peak is the inner
/// race's sideband, the ball's own line about six bins above it. The inner race is the deeper
/// modulation; the ball, re-tested with the inner race's family masked (which takes that
/// sideband), stands on its own line: `inner+ball`.
#[test]
#[ignore = "detector: reads inner only (ball p_healthy 6.3e-3 > α/6 at the declared speed, depth 0.56, its harmonic 1 read on the inner sideband at 0.981 BSF; never re-tested)"]
fn a_ball_line_beside_an_inner_race_sideband_is_read_past_it() {
    let (x, spec) = inner_and_ball_record(true, true, 5);
    let d = diagnose(&sig(&x, 12_000.0), 1200.0, &spec, None).unwrap();
    show("inner and ball", &d);
    assert_eq!(d.verdict, "inner+ball");
    let ball = significance(&d, "ball");
    assert!(ball.explained_by.is_none(), "{ball:?}");
    assert!(
        ball.p_given_stronger
            .is_some_and(|p| p <= d.false_alarm / 3.0),
        "the ball stands with the inner race's family masked: {ball:?}"
    );
}

/// [`inner_and_ball_record`] with one fault: each keeps its own verdict (the inner race's
/// sideband 2 % below the ball-defect rate is no ball fault).
#[test]
fn an_inner_race_sideband_beside_the_ball_rate_is_no_ball_fault() {
    for (inner, ball, want) in [(true, false, "inner"), (false, true, "ball")] {
        let (x, spec) = inner_and_ball_record(inner, ball, 6);
        let d = diagnose(&sig(&x, 12_000.0), 1200.0, &spec, None).unwrap();
        show(want, &d);
        assert_eq!(d.verdict, want);
    }
}
