//! The optional trained classifier on top of the diagnosis: trained on the evidence of labelled
//! simulated recordings (segments of one seed per class), it classifies other seeds right, saves
//! and reloads as JSON, and refuses diagnoses of another reference or a foreign file.

use bearing_model::{FaultClass, Noise, Scenario, Slip};
use diagnosis::trained::{EVIDENCE_FEATURES, segments};
use diagnosis::{
    BearingSpec, DiagnosisError, Labelled, Reference, Signal, TrainedDiagnoser, diagnose,
};

const RPM: f64 = 1797.0;
const FS: f64 = 12_000.0;

fn sim(class: FaultClass, seed: u64) -> Vec<f64> {
    Scenario::cwru(class, 0.014, RPM)
        .unwrap()
        .with_fs(FS)
        .with_duration(4.0)
        .with_noise(Noise::SnrDb(10.0))
        .with_slip(Slip::Random { fraction: 0.01 })
        .with_seed(seed)
        .simulate()
        .unwrap()
        .accel
}

const CLASSES: [(FaultClass, &str); 4] = [
    (FaultClass::None, "normal"),
    (FaultClass::Inner, "inner"),
    (FaultClass::Outer, "outer"),
    (FaultClass::Ball, "ball"),
];

#[test]
fn trained_on_one_seed_classifies_another() {
    let spec = BearingSpec::parse("6205").unwrap();
    let mut examples = Vec::new();
    for (class, label) in CLASSES {
        let x = sim(class, 11);
        // 1 s pieces: 30 turns at 1797 rpm, 27 at the slowest speed searched (20 needed)
        let x = Signal::new(&x, FS).unwrap();
        let parts = segments(&x, RPM, 1.0);
        assert_eq!(parts.len(), 4, "4 s in 1 s pieces");
        for seg in parts {
            let d = diagnose(&seg, RPM, &spec, None).unwrap();
            let f = d.evidence_features();
            assert_eq!(f.len(), EVIDENCE_FEATURES.len());
            assert!(f.iter().all(|v| v.is_finite()));
            examples.push(Labelled {
                features: f,
                label: label.into(),
                recording: format!("{label}-11"),
                load_hp: 0,
                fault_size_mils: (class != FaultClass::None).then_some(14),
                speed_rpm: Some(1797),
            });
        }
    }
    let t = TrainedDiagnoser::train(
        &examples,
        Reference::SelfReference,
        FS,
        1.0,
        &classify::ClassifierSpec::tree(),
    )
    .unwrap();
    assert_eq!(t.classes, ["ball", "inner", "normal", "outer"]);
    assert_eq!((t.examples, t.recordings), (16, 4));
    let back = TrainedDiagnoser::from_json(&t.to_json().unwrap()).unwrap();
    assert_eq!(back, t);
    for (class, label) in CLASSES {
        let x = sim(class, 23);
        let (got, per) = back
            .classify_recording(&Signal::new(&x, FS).unwrap(), RPM, &spec, None)
            .unwrap();
        assert_eq!(got, label, "{class:?}: segments {per:?}");
        assert_eq!(per.len(), 4);
    }
    // a diagnosis against a baseline is not what it was trained on
    let healthy = Signal::new(sim(FaultClass::None, 5), FS).unwrap();
    let b = diagnosis::Baseline::prepare(&healthy).unwrap();
    let outer = Signal::new(sim(FaultClass::Outer, 23), FS).unwrap();
    let d = diagnose(&outer, RPM, &spec, Some(&b)).unwrap();
    assert!(matches!(
        back.classify(&d),
        Err(DiagnosisError::ReferenceMismatch { .. })
    ));
    // another sampling rate is refused with what to do
    let x6: Vec<f64> = sim(FaultClass::Outer, 23)
        .iter()
        .step_by(2)
        .copied()
        .collect();
    let d6 = diagnose(&Signal::new(&x6, FS / 2.0).unwrap(), RPM, &spec, None).unwrap();
    let e = back.classify(&d6).unwrap_err();
    assert!(matches!(e, DiagnosisError::ClassifierRate { .. }), "{e}");
    // foreign or damaged files are refused with what is wrong
    let mut v: serde_json::Value = serde_json::from_str(&t.to_json().unwrap()).unwrap();
    v["version"] = 99.into();
    let e = TrainedDiagnoser::from_json(&v.to_string()).unwrap_err();
    assert!(e.to_string().contains("version 99"), "{e}");
    v["version"] = 1.into();
    v["features"][0] = "rms".into();
    let e = TrainedDiagnoser::from_json(&v.to_string()).unwrap_err();
    assert!(e.to_string().contains("features"), "{e}");
    assert!(TrainedDiagnoser::from_json("{}").is_err());
    // one class cannot be trained
    let one: Vec<Labelled> = examples
        .iter()
        .filter(|e| e.label == "outer")
        .cloned()
        .collect();
    assert!(
        TrainedDiagnoser::train(
            &one,
            Reference::SelfReference,
            FS,
            1.0,
            &classify::ClassifierSpec::tree()
        )
        .is_err()
    );
}

/// Pieces hold at least `MIN_TURNS` (20) shaft turns; the tail is dropped.
#[test]
fn segments_keep_twenty_turns_and_drop_the_tail() {
    let x = Signal::new(vec![0.0; 50_000], FS).unwrap();
    let s = segments(&x, RPM, 1.0);
    assert_eq!(s.len(), 4);
    assert!(s.iter().all(|p| p.len() == 12_000));
    // 0.5 s is 15 turns at 1797 rpm (the former minimum of 10 took it): the whole recording
    assert_eq!(segments(&x, RPM, 0.5).len(), 1);
    // less than two pieces: the whole recording
    let short = Signal::new(&x.samples()[..20_000], FS).unwrap();
    assert_eq!(segments(&short, RPM, 1.0).len(), 1);
}

/// Every piece `segments` cuts is long enough for `diagnose` at the same declared speed: 20
/// turns at the slowest speed `diagnose` searches (0.9 × the declared one) and the whitener's
/// start-up. A piece of 0.7 s holds 21 turns at 1797 rpm but 18.9 at 0.9 × 1797.
#[test]
fn segments_are_long_enough_for_diagnose() {
    let spec = BearingSpec::parse("6205").unwrap();
    let x = Signal::new(sim(FaultClass::None, 3), FS).unwrap();
    for seconds in [0.7, 0.75, 0.8, 1.0] {
        for seg in segments(&x, RPM, seconds) {
            let r = diagnose(&seg, RPM, &spec, None);
            assert!(r.is_ok(), "{seconds} s pieces: {:?}", r.err());
        }
    }
}
