//! The optional trained classifier on top of the diagnosis: trained on the evidence of labelled
//! simulated recordings (segments of one seed per class), it classifies other seeds right, saves
//! and reloads as JSON, and refuses diagnoses of another reference or a foreign file.

use bearing_model::{FaultClass, Noise, Scenario, Slip};
use diagnosis::trained::{EVIDENCE_FEATURES, segments};
use diagnosis::{BearingSpec, DiagnosisError, Labelled, Reference, TrainedDiagnoser, diagnose};

const RPM: f64 = 1797.0;
const FS: f64 = 12_000.0;

fn sim(class: FaultClass, seed: u64) -> Vec<f64> {
    Scenario::cwru(class, 0.014, RPM)
        .unwrap()
        .with_fs(FS)
        .with_duration(2.0)
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
        let parts = segments(&x, FS, RPM, 0.5);
        assert_eq!(parts.len(), 4, "2 s in 0.5 s pieces");
        for seg in parts {
            let d = diagnose(seg, FS, RPM, &spec, None).unwrap();
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
        0.5,
        &classify::ClassifierSpec::tree(),
    )
    .unwrap();
    assert_eq!(t.classes, ["ball", "inner", "normal", "outer"]);
    assert_eq!((t.examples, t.recordings), (16, 4));
    let back = TrainedDiagnoser::from_json(&t.to_json().unwrap()).unwrap();
    assert_eq!(back, t);
    for (class, label) in CLASSES {
        let x = sim(class, 23);
        let (got, per) = back.classify_recording(&x, FS, RPM, &spec, None).unwrap();
        assert_eq!(got, label, "{class:?}: segments {per:?}");
        assert_eq!(per.len(), 4);
    }
    // a diagnosis against a baseline is not what it was trained on
    let b = diagnosis::Baseline::prepare(&sim(FaultClass::None, 5), FS).unwrap();
    let d = diagnose(&sim(FaultClass::Outer, 23), FS, RPM, &spec, Some(&b)).unwrap();
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
    let d6 = diagnose(&x6, FS / 2.0, RPM, &spec, None).unwrap();
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
            0.5,
            &classify::ClassifierSpec::tree()
        )
        .is_err()
    );
}

#[test]
fn segments_keep_ten_turns_and_drop_the_tail() {
    let x = vec![0.0; 25_000];
    let s = segments(&x, FS, RPM, 0.5);
    assert_eq!(s.len(), 4);
    assert!(s.iter().all(|p| p.len() == 6000));
    // 0.2 s is 6 turns at 1797 rpm: too short, the whole recording is one piece
    assert_eq!(segments(&x, FS, RPM, 0.2).len(), 1);
    // less than two pieces: the whole recording
    assert_eq!(segments(&x[..8000], FS, RPM, 0.5).len(), 1);
}
