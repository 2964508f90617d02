//! End-to-end with the 5-DOF physics model of `bearing-model` as both the declared model and the
//! simulator of the "measured" recording, which carries an effect nobody declared.

use bearing_model::{Housing, ShaftHarmonic};
use close_loop::physics::PhysicsModel;
use close_loop::scenario::{add_mode, add_noise, add_tone, modulate};
use close_loop::{
    BearingSpec, DeclaredFault, DeclaredModel, EffectKind, LoopConfig, OperatingPoint, Outcome,
    close_loop,
};

const FS: f64 = 12_000.0;
const RPM: f64 = 1797.0;
const N: usize = 24_000;

fn op_fault(rpm: f64, fault: DeclaredFault) -> OperatingPoint {
    OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        fault,
    )
    .unwrap()
}

fn recording(truth: &PhysicsModel, rpm: f64, effect: impl Fn(Vec<f64>) -> Vec<f64>) -> Vec<f64> {
    recording_fault(truth, rpm, DeclaredFault::Outer, effect)
}

fn recording_fault(
    truth: &PhysicsModel,
    rpm: f64,
    fault: DeclaredFault,
    effect: impl Fn(Vec<f64>) -> Vec<f64>,
) -> Vec<f64> {
    let x = truth.simulate(&op_fault(rpm, fault), N, FS).unwrap();
    let sigma = 0.1 * close_loop::metric::rms(&x);
    let mut y = effect(x);
    add_noise(&mut y, sigma, 99);
    y
}

fn run(y: &[f64]) -> Outcome {
    run_fault(y, DeclaredFault::Outer)
}

fn run_fault(y: &[f64], fault: DeclaredFault) -> Outcome {
    let cfg = LoopConfig::default().check().unwrap();
    let out = close_loop(
        &PhysicsModel::default(),
        &sig(y, FS),
        &op_fault(RPM, fault),
        &cfg,
    )
    .unwrap();
    eprintln!("{}", out.ledger.to_markdown("physics"));
    // a setting (speed ratio, slip, structural path) taken again names the step it replaces
    let e = &out.ledger.effects;
    for (i, x) in e.iter().enumerate() {
        let earlier = e[..i].iter().rposition(|p| p.kind == x.kind).map(|j| j + 1);
        let want = if x.kind.is_setting() { earlier } else { None };
        assert_eq!(x.replaces_step, want, "step {}: {}", i + 1, x.description);
    }
    out
}

fn first(o: &Outcome, kind: EffectKind) -> &close_loop::EffectEntry {
    o.ledger
        .effects
        .iter()
        .find(|e| e.kind == kind)
        .unwrap_or_else(|| panic!("no {kind:?}"))
}

#[test]
fn physics_clean_reports_nothing() {
    let y = recording(&PhysicsModel::default(), RPM, |x| x);
    let o = run(&y);
    assert!(o.ledger.effects.is_empty());
}

#[test]
fn physics_tone() {
    let y = recording(&PhysicsModel::default(), RPM, |mut x| {
        let a = close_loop::metric::rms(&x);
        add_tone(&mut x, FS, 1234.5, 0.5 * a, 0.4);
        x
    });
    let o = run(&y);
    let e = first(&o, EffectKind::Tone);
    assert!((e.frequency_hz.unwrap() / 1234.5 - 1.0).abs() < 0.01);
    assert!(o.ledger.error_after < o.ledger.error_before);
    // a pick-up: measurement channel; the observer residual of y − tone falls
    assert_eq!(e.placement, close_loop::Placement::Measurement);
    assert!(e.residual_rms_after.unwrap() < e.residual_rms_before.unwrap());
}

/// On a healthy bearing the unbalance force shows as its 1× line. (With a spall, the same force
/// also modulates the impacts at fr, and the loop then names `modulation` at fr first: see the
/// equations notes.)
#[test]
fn physics_unbalance() {
    let truth = PhysicsModel {
        harmonics: vec![ShaftHarmonic {
            order: 1,
            amplitude_n: 200.0,
            phase_rad: 0.3,
        }],
        ..PhysicsModel::default()
    };
    let y = recording_fault(&truth, RPM, DeclaredFault::None, |x| x);
    let o = run_fault(&y, DeclaredFault::None);
    // (the structural path of the noise-dominated healthy spectrum may come first)
    let e = first(&o, EffectKind::ShaftHarmonic);
    assert_eq!(e.parameters["order"], 1.0);
    assert!((e.frequency_hz.unwrap() / (RPM / 60.0) - 1.0).abs() < 0.01);
    assert!(o.ledger.error_after < o.ledger.error_before);
    // put into the physics: the re-simulated shaft force is the one in the truth
    assert_eq!(e.placement, close_loop::Placement::Physics);
    let (amp, ph) = (
        e.parameters["force_amplitude_n"],
        e.parameters["force_phase_rad"],
    );
    eprintln!("fitted force {amp} N, phase {ph} rad");
    assert!((amp / 200.0 - 1.0).abs() < 0.1, "{amp}");
    let dph =
        (ph - 0.3 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    assert!(dph.abs() < 0.2, "{ph}");
    assert!(e.residual_rms_after.unwrap() < e.residual_rms_before.unwrap());
}

/// A mode the model lacks, added to the simulated housing acceleration.
#[test]
fn physics_missing_mode() {
    let y = recording(&PhysicsModel::default(), RPM, |x| {
        add_mode(&x, FS, 1800.0, 0.03, 3.0)
    });
    let o = run(&y);
    let e = &o.ledger.effects[0];
    assert_eq!(e.kind, EffectKind::Resonance);
    assert!(
        (e.frequency_hz.unwrap() / 1800.0 - 1.0).abs() < 0.01,
        "{:?}",
        e.frequency_hz
    );
    assert!(o.ledger.error_after < o.ledger.error_before);
}

/// The housing resonance placed wrongly (2.6 kHz true, 3.3 kHz declared). The loop reads the
/// bump as the model's own housing mode misplaced and re-simulates the physics model with the
/// housing mode moved (placement physics); measured 2599.3 Hz. The observer (ASMO on the
/// housing mode) then runs on the moved mode, and its held-out residual falls.
#[test]
fn physics_misplaced_housing_resonance() {
    let truth = PhysicsModel {
        housing: Some(Housing {
            mass_kg: 1.0,
            resonance_hz: 2600.0,
            damping_ratio: 0.05,
        }),
        ..PhysicsModel::default()
    };
    let y = recording(&truth, RPM, |x| x);
    let o = run(&y);
    let e = &o.ledger.effects[0];
    assert_eq!(e.kind, EffectKind::Resonance);
    assert_eq!(e.placement, close_loop::Placement::Physics);
    assert_eq!(e.parameters["housing_mode"], 1.0);
    assert!(
        (e.frequency_hz.unwrap() / 2600.0 - 1.0).abs() < 0.02,
        "{:?}",
        e.frequency_hz
    );
    assert!(o.ledger.error_after < 0.6 * o.ledger.error_before);
    assert!(e.residual_rms_after.unwrap() < e.residual_rms_before.unwrap());
}

/// A housing mode far from the declared one, above and below (4400, 2250 and 1800 Hz against
/// 3300 Hz; 12 kHz, outer race). Its bump is not where the loop's symmetric channel mode puts
/// it (a 4200 Hz housing on a simulated 6203 was fitted at 4989 Hz and only a data-identified
/// structural path followed, 5.01 → 1.41 dB with three effects), but the dip at the declared
/// mode starts a search of the housing frequency itself (1800 Hz lies below the grid's
/// f_h / 1.6, which then extends; there the physics gain had collapsed, and only a cold
/// calibration of each grid point sees the housing move): one effect, in the physics, within
/// 0.5 %. Measured 4399.7, 2249.2 and 1799.6 Hz.
#[test]
fn physics_housing_far_from_the_declared_one_is_found() {
    let declared = PhysicsModel::default().effective_housing();
    for f in [4400.0, 2250.0, 1800.0] {
        let truth = PhysicsModel {
            housing: Some(Housing {
                resonance_hz: f,
                ..declared
            }),
            ..PhysicsModel::default()
        };
        let y = recording(&truth, RPM, |x| x);
        let o = run(&y);
        let e = &o.ledger.effects[0];
        assert_eq!(e.kind, EffectKind::Resonance, "{f} Hz");
        assert_eq!(e.placement, close_loop::Placement::Physics, "{f} Hz");
        assert_eq!(e.parameters["housing_mode"], 1.0, "{f} Hz");
        let got = e.frequency_hz.unwrap();
        assert!((got / f - 1.0).abs() < 0.005, "{f} Hz: {got}");
        assert_eq!(o.ledger.effects.len(), 1, "{f} Hz");
        assert!(o.ledger.error_after < 0.5 * o.ledger.error_before, "{f} Hz");
    }
}

#[test]
fn physics_speed_offset() {
    let y = recording(&PhysicsModel::default(), RPM * 1.0033, |x| x);
    let o = run(&y);
    let e = first(&o, EffectKind::SpeedOffset);
    assert!((e.parameters["ratio"] / 1.0033 - 1.0).abs() < 0.002);
    assert!(o.ledger.error_after < o.ledger.error_before);
}

#[test]
fn physics_modulation() {
    let fr = RPM / 60.0;
    let y = recording(&PhysicsModel::default(), RPM, |x| modulate(&x, FS, fr, 0.6));
    let o = run(&y);
    let e = first(&o, EffectKind::Modulation);
    assert!((e.frequency_hz.unwrap() / fr - 1.0).abs() < 0.01);
    assert!(o.ledger.error_after < o.ledger.error_before);
}

/// A healthy 6203 (another geometry, another rate: 1100 rpm, 20 kHz, 8 s) whose vibration — the
/// model's varying-compliance lines at k·BPFO — is modulated 50 % at the shaft rate: one
/// `modulation` at fr, not tones at the sidebands k·BPFO ± fr. Before the modulation competed in
/// the spectral loop (2026-11-29) the loop spent all eight effects on such tones (37.6, 74.3,
/// 261.5 … Hz, 1.22 → 0.65 dB) and the modulation came too late to explain anything.
#[test]
fn physics_modulation_at_the_shaft_rate_is_not_split_into_sideband_tones() {
    let (rpm, fs, n) = (1100.0, 20_000.0, 160_000);
    let truth = PhysicsModel {
        bearing: bearing_model::Bearing::Skf6203,
        ..PhysicsModel::default()
    };
    let op = OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6203),
        DeclaredFault::None,
    )
    .unwrap();
    let x = truth.simulate(&op, n, fs).unwrap();
    let sigma = 0.1 * close_loop::metric::rms(&x);
    let fr = rpm / 60.0;
    let mut y = modulate(&x, fs, fr, 0.5);
    add_noise(&mut y, sigma, 99);
    let cfg = LoopConfig::default().check().unwrap();
    let o = close_loop(&truth, &sig(&y, fs), &op, &cfg).unwrap();
    eprintln!("{}", o.ledger.to_markdown("physics"));
    let e = first(&o, EffectKind::Modulation);
    assert!((e.frequency_hz.unwrap() / fr - 1.0).abs() < 0.005);
    let tones = o
        .ledger
        .effects
        .iter()
        .filter(|e| e.kind == EffectKind::Tone)
        .count();
    assert_eq!(tones, 0, "the sidebands are the modulation's");
    assert!(o.ledger.error_after < 0.5 * o.ledger.error_before);
}

/// Slip four times the declared one: the loop sets the slip once, from the whole range of
/// fractions, instead of doubling it step after step (one slip effect, the true fraction).
#[test]
fn physics_slip_is_set_once() {
    let truth = PhysicsModel {
        slip_fraction: 4.0 * PhysicsModel::default().slip_fraction,
        ..PhysicsModel::default()
    };
    let y = recording(&truth, RPM, |x| x);
    let o = run(&y);
    let slips: Vec<&close_loop::EffectEntry> = o
        .ledger
        .effects
        .iter()
        .filter(|e| e.kind == EffectKind::Slip)
        .collect();
    assert_eq!(
        slips.len(),
        1,
        "{:?}",
        o.ledger.effects.iter().map(|e| e.kind).collect::<Vec<_>>()
    );
    let f = slips[0].parameters["fraction"];
    assert!((f / truth.slip_fraction - 1.0).abs() < 1e-9, "slip {f}");
    assert_eq!(
        slips[0].parameters["declared_fraction"],
        PhysicsModel::default().slip_fraction
    );
    // inside the grid: a resolved slip, not a bound
    assert_eq!(slips[0].parameters["at_search_bound"], 0.0);
}

/// A slip past the grid's ladder (9 % and 10 %, against its top step of 8 × the declared 1 %):
/// named as slip, not as a speed step and a path (as it was while the grid stopped at 8 %); at
/// the 5-DOF model's largest slip (10 %) the effect says that it sits at the bound of the search.
#[test]
fn physics_slip_past_the_ladder_is_slip_and_flagged_at_the_models_bound() {
    for truth_slip in [0.09, 0.1] {
        let truth = PhysicsModel {
            slip_fraction: truth_slip,
            ..PhysicsModel::default()
        };
        let y = recording(&truth, RPM, |x| x);
        let o = run(&y);
        let kinds: Vec<EffectKind> = o.ledger.effects.iter().map(|e| e.kind).collect();
        assert!(
            !kinds.contains(&EffectKind::SpeedOffset),
            "slip {truth_slip}: {kinds:?}"
        );
        let slip = o
            .ledger
            .effects
            .iter()
            .find(|e| e.kind == EffectKind::Slip)
            .unwrap_or_else(|| panic!("slip {truth_slip}: no slip in {kinds:?}"));
        let f = slip.parameters["fraction"];
        assert!((0.08..=0.1).contains(&f), "slip {truth_slip}: {f}");
        let at_bound = slip.parameters["at_search_bound"] == 1.0;
        assert_eq!(at_bound, f >= 0.1, "slip {truth_slip}: {slip:?}");
        assert_eq!(at_bound, slip.description.contains("the largest tried"));
    }
}

/// An inner-race fault whose balls are all preloaded by 2 µm (the load zone spans the whole
/// circumference, so the shaft barely modulates the impacts), declared without preload: the
/// loop names the contact preload (placement physics) from the rig's grid, near the truth.
#[test]
fn physics_contact_preload() {
    let truth = PhysicsModel {
        clearance_m: Some(-2e-6),
        ..PhysicsModel::default()
    };
    let y = recording_fault(&truth, RPM, DeclaredFault::Inner, |x| x);
    let o = run_fault(&y, DeclaredFault::Inner);
    let e = first(&o, EffectKind::ContactPreload);
    assert_eq!(e.placement, close_loop::Placement::Physics);
    let p = e.parameters["preload_um"];
    assert!((1.0..=4.0).contains(&p), "{:?}", e.parameters);
    assert!(e.error_after < e.error_before);
    // the machine model carries the preload through its JSON, and the loop run from it on the
    // same recording starts with it: it starts near where the first run ended and does not
    // name the preload again
    let text = o.machine.to_json().unwrap();
    let m = close_loop::machine::MachineModel::from_json(&text).unwrap();
    assert_eq!(m.contact_preload_m, Some(p * 1e-6));
    let cfg = LoopConfig::default().check().unwrap();
    let again = close_loop::close_loop_from(
        &PhysicsModel::default(),
        Some(&m),
        &sig(&y, FS),
        &op_fault(RPM, DeclaredFault::Inner),
        &cfg,
    )
    .unwrap();
    assert!(
        again.ledger.error_before < 0.5 * o.ledger.error_before,
        "{} vs {}",
        again.ledger.error_before,
        o.ledger.error_before
    );
    assert!(
        again
            .ledger
            .effects
            .iter()
            .all(|e| e.kind != EffectKind::ContactPreload),
        "{:?}",
        again.ledger.effects
    );
}

/// A spall wider or narrower than declared (the declared model's own recording at 2 × and 3 ×
/// the declared 0.007 in, outer and inner race, and at ½ ×, ball): named as the fault's width,
/// within 2 %, the one effect. Before the width was a candidate, the 3 × inner race was named a
/// housing mode moved to 1948 Hz and two channel modes, the 2 × outer race a path and patches.
#[test]
fn physics_fault_size_other_than_declared_is_named() {
    let declared = PhysicsModel::default().fault_size_in;
    for (fault, ratio) in [
        (DeclaredFault::Outer, 2.0),
        (DeclaredFault::Inner, 3.0),
        (DeclaredFault::Ball, 0.5),
    ] {
        let truth = PhysicsModel {
            fault_size_in: ratio * declared,
            ..PhysicsModel::default()
        };
        let y = recording_fault(&truth, RPM, fault, |x| x);
        let o = run_fault(&y, fault);
        let kinds: Vec<EffectKind> = o.ledger.effects.iter().map(|e| e.kind).collect();
        assert_eq!(kinds, [EffectKind::FaultSize], "{fault} x{ratio}");
        let p = &o.ledger.effects[0].parameters;
        assert!(
            (p["ratio"] / ratio - 1.0).abs() < 0.02,
            "{fault} x{ratio}: {p:?}"
        );
        assert_eq!(p["at_search_bound"], 0.0);
    }
}

/// A fault nobody declared: the declared model's own recording with an inner-race spall beside
/// the declared outer-race one (same width), and with an outer-race spall on a bearing declared
/// healthy. Each is named as the only effect, a `bearing_fault` at its kinematic rate within
/// 0.5 %, its width the truth's (the declared one), in the physics, at least halving the held-out
/// error. Before the candidate the loop had no way to add a fault: the inner race beside the
/// outer was a broadband path, a broad resonance, three tones and a modulation (held-out 1.96 →
/// 1.27 dB; with the fault 0.93 dB).
#[test]
fn physics_fault_nobody_declared_is_named() {
    let truth = PhysicsModel::default();
    let orders = BearingSpec::designated(bearing_model::Bearing::Skf6205).orders;
    for (recorded, declared, rate, order) in [
        (
            DeclaredFault::InnerOuter,
            DeclaredFault::Outer,
            "BPFI",
            orders.bpfi,
        ),
        (
            DeclaredFault::Outer,
            DeclaredFault::None,
            "BPFO",
            orders.bpfo,
        ),
    ] {
        let y = recording_fault(&truth, RPM, recorded, |x| x);
        let o = run_fault(&y, declared);
        let kinds: Vec<EffectKind> = o.ledger.effects.iter().map(|e| e.kind).collect();
        assert_eq!(
            kinds,
            [EffectKind::BearingFault],
            "{recorded} declared {declared}"
        );
        let e = &o.ledger.effects[0];
        assert_eq!(e.kinematic_rate.as_deref(), Some(rate));
        assert!((e.frequency_hz.unwrap() / (order * RPM / 60.0) - 1.0).abs() < 0.005);
        assert_eq!(e.parameters["size_in"], truth.fault_size_in);
        assert_eq!(e.placement, close_loop::Placement::Physics);
        assert!(e.error_after < 0.5 * e.error_before, "{}", e.description);
    }
}

/// `y` at `fs` Hz as a checked signal (the recordings here are finite and non-empty).
fn sig(y: &[f64], fs: f64) -> close_loop::Signal<'_> {
    close_loop::Signal::new(y, fs).unwrap()
}
