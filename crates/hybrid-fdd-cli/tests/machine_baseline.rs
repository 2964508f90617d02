//! A calibrated machine model as the diagnosis baseline (`--baseline rig.json`): loaded and
//! validated, its whole model (path, floor, lines) is the healthy model, a healthy recording of the same rig
//! reads normal, and a recording of other units or another rate is refused with a typed error;
//! the envelope lines its model holds are discounted through a synthesised recording, and a
//! model that cannot be synthesised says so.

use close_loop::LoopConfig;
use hybrid_fdd_cli::diagnose::{BaselineSource, Loaded, Plan, diagnose_loaded};

const FS: f64 = 12_000.0;
const RPM: f64 = 1797.0;

/// A healthy "rig": a 2.8 kHz resonance rung by broadband excitation, plus a 1× line.
fn rig(n: usize, seed: u64) -> Vec<f64> {
    let mut st = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let e: Vec<f64> = (0..n)
        .map(|_| {
            st ^= st << 13;
            st ^= st >> 7;
            st ^= st << 17;
            (st >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect();
    let (r, w) = (0.97f64, 2.0 * std::f64::consts::PI * 2800.0 / FS);
    let (a1, a2) = (-2.0 * r * w.cos(), r * r);
    let mut y = vec![0.0; n];
    for k in 0..n {
        let mut v = e[k];
        if k >= 1 {
            v -= a1 * y[k - 1];
        }
        if k >= 2 {
            v -= a2 * y[k - 2];
        }
        y[k] = v;
    }
    let fr = RPM / 60.0;
    for (k, v) in y.iter_mut().enumerate() {
        *v += 0.5 * (2.0 * std::f64::consts::PI * fr * k as f64 / FS).sin();
    }
    y
}

fn loaded(samples: Vec<f64>, fs_hz: f64, units: &'static str) -> Loaded {
    Loaded {
        samples,
        fs_hz,
        rpm: Some(RPM),
        unit: bearing_data::SampleUnit::stated(units, "test units").unwrap(),
        fault_size_in: None,
    }
}

/// `m` written to `dir/name.json`, loaded as a baseline and prepared at [`FS`].
fn prepared_from(
    dir: &std::path::Path,
    name: &str,
    m: &close_loop::machine::MachineModel,
) -> anyhow::Result<hybrid_fdd_cli::diagnose::BaselineAtRate> {
    let json = dir.join(format!("{name}.json"));
    std::fs::write(&json, m.to_json().unwrap()).unwrap();
    BaselineSource::load(&json, "DE", None).unwrap().at(FS, RPM)
}

/// The machine model calibrated on the healthy rig's recording (48 kHz, seed 1) with the
/// loop's default settings.
fn calibrated_rig() -> close_loop::machine::MachineModel {
    let cfg = LoopConfig::default().check().unwrap();
    close_loop::machine::calibrate(
        &close_loop::Signal::new(rig(48_000, 1), FS).unwrap(),
        RPM,
        bearing_model::Bearing::Skf6205,
        &cfg,
    )
    .unwrap()
}

#[test]
fn machine_model_is_a_diagnosis_baseline() {
    let mut m = calibrated_rig();
    let order = m
        .path
        .as_ref()
        .expect("the loop adds the rig's path")
        .ar
        .len();
    m.units = "g".into();
    let dir = std::env::temp_dir().join(format!(
        "hybrid-fdd-machine-baseline-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("rig.json");
    std::fs::write(&json, m.to_json().unwrap()).unwrap();

    let src = BaselineSource::load(&json, "DE", None).unwrap();
    assert_eq!(src.machine_units(), Some("g"));
    let prepared = src.at(FS, RPM).unwrap();
    // it whitens with the whole model's one-step predictor: the path's order plus two per line
    assert!(m.predictor_residual_rms.is_some() && m.predictor_residual_kurtosis.is_some());
    assert_eq!(
        prepared.0.whitener.order,
        order + 2 * m.lines.len(),
        "{}",
        prepared.1
    );
    assert!(prepared.1.contains("machine model"), "{}", prepared.1);
    assert!(prepared.1.contains("whole model"), "{}", prepared.1);
    // a model written before the predictor's residual statistics whitens with its path alone
    let mut older = m.clone();
    (
        older.predictor_residual_rms,
        older.predictor_residual_kurtosis,
    ) = (None, None);
    let p_older = prepared_from(&dir, "older", &older).unwrap();
    assert_eq!(p_older.0.whitener.order, order, "{}", p_older.1);
    assert!(p_older.1.contains("structural path"), "{}", p_older.1);

    let plan = Plan {
        channel: "DE".into(),
        fs: None,
        rpm: None,
        bearing: diagnosis::BearingSpec::parse("6205").unwrap(),
    };
    // another healthy recording of the same rig, in the same units: normal
    let o = diagnose_loaded(&loaded(rig(48_000, 2), FS, "g"), &plan, Some(&src)).unwrap();
    assert_eq!(o.diagnosis.verdict, "normal");
    assert_eq!(o.diagnosis.reference, diagnosis::Reference::Baseline);
    // other units: refused
    let e = diagnose_loaded(&loaded(rig(48_000, 2), FS, "m/s^2"), &plan, Some(&src)).unwrap_err();
    assert!(format!("{e:#}").contains("is in g"), "{e:#}");
    // another rate: the library's typed mismatch
    let e =
        diagnose_loaded(&loaded(rig(192_000, 3), 48_000.0, "g"), &plan, Some(&src)).unwrap_err();
    assert!(
        e.chain().any(|c| matches!(
            c.downcast_ref::<diagnosis::DiagnosisError>(),
            Some(diagnosis::DiagnosisError::SampleRateMismatch { .. })
        )),
        "{e:#}"
    );
    // a machine model without a path cannot whiten
    let mut bare = m.clone();
    bare.path = None;
    let e = prepared_from(&dir, "bare", &bare).unwrap_err();
    assert!(format!("{e:#}").contains("no structural path"), "{e:#}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A healthy machine whose vibration is amplitude-modulated at BPFI and its harmonics (a
/// source in the machine, not the bearing: a healthy machine's envelope can hold lines at a
/// fault rate) is calibrated into a machine model holding the modulations; a recording of the
/// same machine shows the BPFI lines. Against the machine model they are the healthy machine's
/// and discounted, as a baseline recording's lines are: the model's synthesised healthy
/// recording holds them (`baseline_prominence_db` non-null, evidence below prominence), and
/// the verdict is `normal`. The same whitener without the synthesis (how a machine baseline
/// was prepared before) compares no line and reads them as a fault.
#[test]
fn machine_baseline_discounts_the_envelope_lines_its_model_holds() {
    use close_loop::effect::Modulation;
    let mut m = calibrated_rig();
    m.units = "g".into();
    let bpfi_hz = m.bearing_orders[1] * m.calibration_shaft_hz();
    let am: Vec<Modulation> = (1..=3)
        .map(|k| Modulation {
            frequency_hz: k as f64 * bpfi_hz,
            depth: 0.5,
        })
        .collect();
    m.modulations.extend(am.iter().copied());
    let mut y = rig(96_000, 2);
    for md in &am {
        y = md.apply(&y, 0, FS);
    }
    let rec = loaded(y, FS, "g");
    let plan = Plan {
        channel: "DE".into(),
        fs: None,
        rpm: None,
        bearing: diagnosis::BearingSpec::parse("6205").unwrap(),
    };
    let src = BaselineSource::from_machine(std::path::Path::new("modulated.json"), m.clone());
    let prepared = src.at(FS, RPM).unwrap();
    assert!(prepared.0.residual.is_some(), "{}", prepared.1);
    for part in ["synthesised", "10.0 s at 1797 rpm", "seed 1"] {
        assert!(prepared.1.contains(part), "`{part}` in {}", prepared.1);
    }
    // once per rate and speed: the same preparation again, another one at another speed
    assert!(std::sync::Arc::ptr_eq(&prepared, &src.at(FS, RPM).unwrap()));
    assert!(src.at(FS, 1750.0).unwrap().1.contains("1750 rpm"));

    let o = diagnose_loaded(&rec, &plan, Some(&src)).unwrap();
    let inner = o
        .diagnosis
        .evidence
        .iter()
        .find(|e| e.hypothesis == diagnosis::Hypothesis::Inner)
        .unwrap();
    assert!(
        inner
            .harmonics
            .iter()
            .all(|l| l.baseline_prominence_db.is_some()),
        "{:?}",
        inner.harmonics
    );
    assert!(
        inner
            .harmonics
            .iter()
            .any(|l| l.prominence_db >= 6.0 && l.evidence_db < l.prominence_db),
        "the BPFI lines are there and the healthy machine's are subtracted: {:?}",
        inner.harmonics
    );
    assert_eq!(o.diagnosis.verdict, "normal", "{:?}", inner.harmonics);

    // the same whitener without a healthy envelope: nothing compared, the lines are a fault
    let mut bare = prepared.0.clone();
    bare.residual = None;
    let recording = diagnosis::Signal::new(&rec.samples, FS).unwrap();
    let d = diagnosis::diagnose(&recording, RPM, &plan.bearing, Some(&bare)).unwrap();
    assert!(
        d.evidence
            .iter()
            .flat_map(|e| e.harmonics.iter())
            .all(|l| l.baseline_prominence_db.is_none())
    );
    assert!(d.verdict.contains("inner"), "{}", d.verdict);
}

/// A machine model that cannot be synthesised keeps today's baseline — its whitener and
/// statistics, no healthy envelope — and the note says why; nothing panics and no envelope of
/// zeros stands in for one.
#[test]
fn machine_baseline_that_cannot_be_synthesised_says_so() {
    let m = calibrated_rig();
    // physics seen through a path of its own (no time-domain synthesis), a model calibrated
    // on a recording declared faulty, a declared model whose parameters the file lacks
    let mut own_path = m.clone();
    own_path.physics_gain = 1.0;
    own_path.physics_path = own_path.path.clone();
    let mut faulty = m.clone();
    faulty.declared_fault = "inner".into();
    let mut other = m.clone();
    other.physics_gain = 1.0;
    other.model = "arx-laguerre".into();
    for (what, mm) in [
        ("own path", own_path),
        ("declared inner", faulty),
        ("arx-laguerre", other),
    ] {
        let src = BaselineSource::from_machine(std::path::Path::new("m.json"), mm);
        let p = src.at(FS, RPM).unwrap();
        assert!(p.0.residual.is_none(), "{what}: {}", p.1);
        assert!(
            p.1.contains("no healthy envelope lines") && p.1.contains("cannot be synthesised"),
            "{what}: {}",
            p.1
        );
        let o = diagnose_loaded(
            &loaded(rig(48_000, 2), FS, "g"),
            &Plan {
                channel: "DE".into(),
                fs: None,
                rpm: None,
                bearing: diagnosis::BearingSpec::parse("6205").unwrap(),
            },
            Some(&src),
        )
        .unwrap();
        assert_eq!(o.diagnosis.verdict, "normal", "{what}");
    }
}
