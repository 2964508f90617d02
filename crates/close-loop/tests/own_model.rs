//! The loop checked against its own model: a recording simulated by the declared 5-DOF model
//! (another slip seed, with and without noise) is explained within the estimator's scatter
//! (held-out error ≤ 1 dB) and nothing is added — across fault combinations, speeds and sampling
//! rates. And the machine model: saved, reloaded, validated.

use close_loop::machine::MachineModel;
use close_loop::physics::PhysicsModel;
use close_loop::scenario::{add_noise, add_tone};
use close_loop::{
    BearingSpec, CloseLoopError, DeclaredFault, DeclaredModel, EffectKind, LoopConfig,
    OperatingPoint, close_loop, close_loop_from,
};

fn own(fault: DeclaredFault, rpm: f64, fs: f64, seconds: f64, noise: bool) {
    let op = OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        fault,
    )
    .unwrap();
    let truth = PhysicsModel {
        seed: 41,
        ..PhysicsModel::default()
    };
    let n = (seconds * fs) as usize;
    let mut y = truth.simulate(&op, n, fs).unwrap();
    if noise {
        let s = 0.2 * close_loop::metric::rms(&y);
        add_noise(&mut y, s, 3);
    }
    let cfg = LoopConfig::default().check().unwrap();
    let o = close_loop(&PhysicsModel::default(), &sig(&y, fs), &op, &cfg).unwrap();
    assert_explained(&o, &format!("{fault} {rpm} rpm {fs} Hz noise {noise}"));
}

/// The model's own recording explained: within the estimator's own scatter on these short
/// records (1–4 s; the 10 s records scatter less) and nothing added.
fn assert_explained(o: &close_loop::Outcome, what: &str) {
    let l = &o.ledger;
    let bound = 1.0f64.max(1.5 * l.protocol.estimation_lsd_db);
    assert!(
        l.error_before <= bound && l.effects.is_empty(),
        "{what}: {:.3} dB, effects {:?}",
        l.error_before,
        l.effects
            .iter()
            .map(|e| e.description.clone())
            .collect::<Vec<_>>()
    );
}

#[test]
fn own_model_every_fault_at_12k() {
    for fault in DeclaredFault::ALL {
        own(fault, 1772.0, 12_000.0, 3.0, false);
    }
}

#[test]
fn own_model_noisy_slow_and_48k() {
    own(DeclaredFault::Inner, 1797.0, 12_000.0, 3.0, true);
    own(DeclaredFault::OuterBall, 600.0, 12_000.0, 4.0, true);
    own(DeclaredFault::Outer, 1797.0, 48_000.0, 1.0, false);
}

/// The chain a user runs on a rig: a healthy recording calibrated into a machine model, then
/// the same rig's fault recordings started from it. On the declared model's own simulations
/// (healthy and faulty, other seeds) every fault is explained within the estimator's scatter and
/// nothing is added; the start behind the machine's path alone began at 7.6–11.5 dB here and
/// added a path and patches.
#[test]
fn own_model_faults_from_the_machine_model_calibrated_on_its_healthy_output() {
    let (fs, rpm) = (12_000.0, 1797.0);
    let bearing = bearing_model::Bearing::Skf6205;
    let cfg = LoopConfig::default().check().unwrap();
    let healthy =
        OperatingPoint::new(rpm, BearingSpec::designated(bearing), DeclaredFault::None).unwrap();
    let sim = |op: &OperatingPoint, seed: u64, seconds: f64| {
        PhysicsModel {
            seed,
            ..PhysicsModel::default()
        }
        .simulate(op, (seconds * fs) as usize, fs)
        .unwrap()
    };
    let machine =
        close_loop::machine::calibrate(&sig(&sim(&healthy, 5, 4.0), fs), rpm, bearing, &cfg)
            .unwrap();
    let machine = MachineModel::from_json(&machine.to_json().unwrap()).unwrap();
    for fault in [
        DeclaredFault::Outer,
        DeclaredFault::Inner,
        DeclaredFault::Ball,
        DeclaredFault::InnerOuter,
    ] {
        let op = OperatingPoint::new(rpm, BearingSpec::designated(bearing), fault).unwrap();
        let y = sim(&op, 43, 3.0);
        let o = close_loop_from(
            &PhysicsModel::default(),
            Some(&machine),
            &sig(&y, fs),
            &op,
            &cfg,
        )
        .unwrap();
        assert_explained(&o, &format!("{fault} from the machine model"));
    }
}

/// A tone and a 2× shaft line at 30–45 % of the RMS added to the model's own recording: both
/// named, frequency within 0.5 %, amplitude within 20 %.
#[test]
fn plain_tone_and_shaft_line_are_named() {
    let fs = 12_000.0;
    let rpm = 1772.0;
    let op = OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Inner,
    )
    .unwrap();
    let truth = PhysicsModel {
        seed: 41,
        ..PhysicsModel::default()
    };
    let mut y = truth.simulate(&op, 36_000, fs).unwrap();
    let a = close_loop::metric::rms(&y);
    add_tone(&mut y, fs, 251.3, 0.45 * a, 0.3);
    add_tone(&mut y, fs, 2.0 * rpm / 60.0, 0.35 * a, 1.1);
    let cfg = LoopConfig::default().check().unwrap();
    let o = close_loop(&PhysicsModel::default(), &sig(&y, fs), &op, &cfg).unwrap();
    let find = |f: f64| {
        o.ledger
            .effects
            .iter()
            .find(|e| e.frequency_hz.is_some_and(|g| (g / f - 1.0).abs() < 0.005))
            .unwrap_or_else(|| panic!("nothing at {f} Hz: {:#?}", o.ledger.effects))
    };
    let t = find(251.3);
    assert_eq!(t.kind, EffectKind::Tone);
    assert!((t.parameters["amplitude"] / (0.45 * a) - 1.0).abs() < 0.2);
    let h = find(2.0 * rpm / 60.0);
    assert_eq!(h.kind, EffectKind::ShaftHarmonic);
    assert_eq!(h.parameters["order"], 2.0);
    assert!((h.parameters["amplitude"] / (0.35 * a) - 1.0).abs() < 0.2);
    assert!(o.ledger.error_after < o.ledger.error_before);
}

/// A healthy "rig" (a resonant path rung by broadband excitation + a shaft line + a tone) is
/// calibrated into a machine model that explains its held-out half, round-trips through JSON,
/// and is refused by a recording at another rate or of another bearing.
#[test]
fn calibrated_machine_model_round_trips_and_is_validated() {
    let fs = 12_000.0;
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::None,
    )
    .unwrap();
    let n = 48_000;
    let mut e = vec![0.0; n];
    add_noise(&mut e, 1.0, 9);
    let path = close_loop::path::StructuralPath {
        fs_hz: fs,
        ar: {
            let (r, w) = (0.97f64, 2.0 * std::f64::consts::PI * 2800.0 / fs);
            vec![-2.0 * r * w.cos(), r * r]
        },
        excitation_variance: 1.0,
    };
    let mut y = path.filter(&e);
    let a = close_loop::metric::rms(&y);
    add_tone(&mut y, fs, 1797.0 / 60.0, 0.3 * a, 0.2);
    add_tone(&mut y, fs, 1234.5, 0.2 * a, 0.7);
    let cfg = LoopConfig::default().check().unwrap();
    let model = PhysicsModel::default();
    let o = close_loop(&model, &sig(&y, fs), &op, &cfg).unwrap();
    assert!(o.ledger.error_after <= 2.0, "{}", o.ledger.error_after);
    assert!(o.ledger.error_after < 0.5 * o.ledger.error_before);
    let m = &o.machine;
    let mode = m
        .structural_modes
        .iter()
        .max_by(|x, y| x.peak_psd.total_cmp(&y.peak_psd))
        .unwrap();
    assert!((mode.frequency_hz / 2800.0 - 1.0).abs() < 0.02, "{mode:?}");
    // the library call is the same calibration, verified from the saved model: the
    // verification pass adds nothing (its shaft force and line rebuilt), and the end error is
    // the saved model's own, within 1e-6 dB of the loop's
    let lib =
        close_loop::machine::calibrate(&sig(&y, fs), 1797.0, bearing_model::Bearing::Skf6205, &cfg)
            .unwrap();
    assert!((lib.provenance.error_after - m.provenance.error_after).abs() < 1e-6);
    let mut same = lib.clone();
    same.provenance.error_after = m.provenance.error_after;
    assert_eq!(&same, m);
    // the path's own residual on the held-out half: the unit-variance excitation plus the
    // whitened lines
    let r = m.path_residual_rms.unwrap();
    let k = m.path_residual_kurtosis.unwrap();
    assert!((0.9..1.6).contains(&r), "path residual RMS {r}");
    assert!((2.0..4.0).contains(&k), "path residual kurtosis {k}");
    // through the whole model's predictor the named tone is predicted too
    let rp = m.predictor_residual_rms.unwrap();
    assert!(rp < r, "predictor residual RMS {rp} against the path's {r}");
    assert!(m.predictor_residual_kurtosis.unwrap().is_finite());
    // as an observer model: the physics observers' one-step predictor removes the resonance
    let flo_ratio = |pm: observers::StateSpace| {
        assert!(pm.is_shift_form());
        let mut obs = observers::build_observer(
            observers::ObserverKind::Flo,
            &observers::ModelConfig::CalibratedPath(pm),
            &observers::ObserverSettings::new(1e-3),
        )
        .unwrap();
        let res = obs.run(&y).unwrap().residual;
        close_loop::metric::rms(&res[n / 2..]) / close_loop::metric::rms(&y[n / 2..])
    };
    let path_only = flo_ratio(m.observer_model().unwrap());
    assert!(
        path_only < 0.5,
        "FLO on the calibrated path: residual/signal {path_only}"
    );
    // on the whole machine model (path, floor and the line the loop named, the 1234.5 Hz tone)
    // that line is predicted too: the path alone leaves it, whitened, in the residual
    assert!(!m.lines.is_empty());
    let whole = flo_ratio(m.predictor_model().unwrap());
    assert!(
        whole < 0.98 * path_only,
        "FLO on the whole machine model: residual/signal {whole} against {path_only} on the path"
    );
    let text = m.to_json().unwrap();
    let back = MachineModel::from_json(&text).unwrap();
    assert_eq!(&back, m);
    // a second healthy recording of the same rig, started from the machine model: explained
    let mut e2 = vec![0.0; n];
    add_noise(&mut e2, 1.0, 10);
    let mut y2 = path.filter(&e2);
    add_tone(&mut y2, fs, 1797.0 / 60.0, 0.3 * a, 1.4);
    add_tone(&mut y2, fs, 1234.5, 0.2 * a, 2.0);
    let o2 = close_loop_from(&model, Some(&back), &sig(&y2, fs), &op, &cfg).unwrap();
    assert!(o2.ledger.error_before <= 2.0, "{}", o2.ledger.error_before);
    // validation
    assert!(matches!(
        close_loop_from(&model, Some(&back), &sig(&y2, 48_000.0), &op, &cfg),
        Err(CloseLoopError::MachineModelMismatch {
            what: "sampling rate",
            ..
        })
    ));
    let op3 = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6203),
        DeclaredFault::None,
    )
    .unwrap();
    assert!(matches!(
        close_loop_from(&model, Some(&back), &sig(&y2, fs), &op3, &cfg),
        Err(CloseLoopError::MachineModelMismatch {
            what: "bearing",
            ..
        })
    ));
    let mut g = back.clone();
    g.units = "g".into();
    assert!(matches!(
        g.check_units("m/s^2"),
        Err(CloseLoopError::MachineModelMismatch { what: "units", .. })
    ));
    assert!(matches!(
        MachineModel::from_json(&text.replace("\"version\": 1", "\"version\": 7")),
        Err(CloseLoopError::MachineModelMismatch {
            what: "version",
            ..
        })
    ));
    assert!(matches!(
        MachineModel::from_json("{\"format\": 3}"),
        Err(CloseLoopError::MachineModelFormat { .. })
    ));
}

/// `y` at `fs` Hz as a checked signal (the recordings here are finite and non-empty).
fn sig(y: &[f64], fs: f64) -> close_loop::Signal<'_> {
    close_loop::Signal::new(y, fs).unwrap()
}
