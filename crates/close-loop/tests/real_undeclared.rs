//! Measured data with undeclared effects: real CWRU recordings with known effects added — a
//! tone, a shaft order, a speed change by resampling — each to be named with its parameters, and
//! the untouched recording as the control. Skipped with a message when the data is absent; a
//! failure under `CI=true`.

use std::path::{Path, PathBuf};

use bearing_data::{LoadOptions, load_record};
use close_loop::physics::PhysicsModel;
use close_loop::scenario::add_tone;
use close_loop::{
    BearingSpec, DeclaredFault, EffectKind, LoopConfig, OperatingPoint, Outcome, close_loop,
};

mod common;

fn data_dir() -> Option<PathBuf> {
    common::data_dir("real-data close-loop test")
}

fn run(y: &[f64], rpm: f64, fault: DeclaredFault) -> Outcome {
    run_at(y, 12_000.0, rpm, fault, Some(60.0))
}

fn run_at(y: &[f64], fs: f64, rpm: f64, fault: DeclaredFault, mains: Option<f64>) -> Outcome {
    let op = OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        fault,
    )
    .unwrap();
    let cfg = LoopConfig {
        line_frequency_hz: mains,
        ..LoopConfig::default()
    }
    .check()
    .unwrap();
    close_loop(&PhysicsModel::default(), &sig(y, fs), &op, &cfg).unwrap()
}

fn near(o: &Outcome, f: f64) -> Option<&close_loop::EffectEntry> {
    o.ledger
        .effects
        .iter()
        .find(|e| e.frequency_hz.is_some_and(|g| (g / f - 1.0).abs() < 0.005))
}

/// 209 (inner race 0.021 in, 0 hp, 12 kHz, grade Y): a 287.3 Hz tone at 40 % of the record's RMS
/// and a 3× shaft line at 35 % are named (kind, frequency within 0.5 %, amplitude within 20 %);
/// the untouched record names neither.
#[test]
fn tone_and_shaft_order_added_to_209() {
    let Some(dir) = data_dir() else { return };
    let r = load_record(&dir, 209, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    let y0 = r.de().to_vec();
    let a = close_loop::metric::rms(&y0);
    let f3 = 3.0 * rpm / 60.0;
    let control = run(&y0, rpm, DeclaredFault::Inner);
    assert!(near(&control, 287.3).is_none());
    assert!(
        control
            .ledger
            .effects
            .iter()
            .all(|e| e.parameters.get("order") != Some(&3.0)),
        "{:#?}",
        control.ledger.effects
    );
    let mut y = y0.clone();
    add_tone(&mut y, 12_000.0, 287.3, 0.4 * a, 0.5);
    add_tone(&mut y, 12_000.0, f3, 0.35 * a, 2.0);
    let o = run(&y, rpm, DeclaredFault::Inner);
    let t = near(&o, 287.3).expect("tone not named");
    assert_eq!(t.kind, EffectKind::Tone);
    assert!((t.parameters["amplitude"] / (0.4 * a) - 1.0).abs() < 0.2);
    // the 3× shaft line at 35 % RMS: named a shaft harmonic of order 3 (within 0.5 % and 20 %).
    // In the physics (a shaft force) it also changes the contact and raises the held-out error,
    // so the held-out data places it in the measurement channel.
    let h = near(&o, f3).expect("3x shaft line not named");
    assert_eq!(h.kind, EffectKind::ShaftHarmonic, "{h:#?}");
    assert_eq!(h.parameters.get("order"), Some(&3.0));
    assert!(
        (h.parameters["amplitude"] / (0.35 * a) - 1.0).abs() < 0.2,
        "{h:#?}"
    );
    assert!(h.error_after < h.error_before);
}

/// 130 (outer race 0.007 in @6, 0 hp, grade Y) from the rig's machine model, untouched and
/// resampled so that it plays 1.5 % faster. Untouched, its shaft lines sit at the logged speed
/// (within 0.02 %) while its BPFO lines sit 0.32 % above the 6205's 3.5848 × fr: the loop names
/// a defect rate (an effective contact angle of about 9°, or the rate step of a contact
/// preload), not a speed offset. Played faster,
/// the shaft lines move too: it names a speed offset of 1.5 %, read from the shaft lines, with
/// the same defect rate beside it.
#[test]
fn defect_rate_and_speed_change_by_resampling_130() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let r = load_record(&dir, 130, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    let x = r.de();
    let control = run_from(machine, x, rpm, &cfg);
    let kinds: Vec<EffectKind> = control.ledger.effects.iter().map(|e| e.kind).collect();
    assert!(!kinds.contains(&EffectKind::SpeedOffset), "{kinds:?}");
    // the rate is named as a `defect_rate` (with its contact angle), or — since the physics
    // high-pass (2026-11-27) leaves the low band to it — as the rate step a `contact_preload`
    // is judged with
    let (d, q0) = control
        .ledger
        .effects
        .iter()
        .find_map(|e| match e.kind {
            EffectKind::DefectRate => Some((e, e.parameters["ratio"])),
            EffectKind::ContactPreload => e.parameters.get("defect_rate_ratio").map(|&q| (e, q)),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no defect rate named: {kinds:?}"));
    assert!((1.002..1.0045).contains(&q0), "{:?}", d.parameters);
    if d.kind == EffectKind::DefectRate {
        assert!((d.parameters["shaft_ratio"] - 1.0).abs() < 1e-3);
        let angle = d.parameters["contact_angle_deg"];
        assert!((6.0..13.0).contains(&angle), "{angle}");
    }
    let s = 1.015;
    let y = played_faster(x, s);
    let o = run_from(machine, &y, rpm, &cfg);
    let e = o
        .ledger
        .effects
        .iter()
        .rfind(|e| e.kind == EffectKind::SpeedOffset)
        .expect("no speed offset named");
    let ratio = e.parameters["ratio"];
    assert_eq!(e.parameters["shaft_measured"], 1.0, "{:?}", e.parameters);
    assert!((ratio / s - 1.0).abs() < 1e-3, "ratio {ratio}");
    let q = e.parameters["defect_rate_ratio"];
    assert!((q / q0 - 1.0).abs() < 1e-3, "defect rate {q}, control {q0}");
}

/// `x` played `s` times faster: y(k) = x(s·k), linear interpolation (the band of interest is
/// far below Nyquist).
fn played_faster(x: &[f64], s: f64) -> Vec<f64> {
    let n = ((x.len() - 2) as f64 / s) as usize;
    (0..n)
        .map(|k| {
            let t = k as f64 * s;
            let i = t.floor() as usize;
            let f = t - i as f64;
            x[i] * (1.0 - f) + x[i + 1] * f
        })
        .collect()
}

/// The rig's machine model as committed (`results/close-loop/<name>.json`, written by `cargo
/// xtask close-loop --all-real` with the CLI's 60 Hz mains): what users pass with `--machine`.
fn committed_rig(name: &str) -> close_loop::machine::MachineModel {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../results/close-loop/{name}.json"));
    close_loop::machine::MachineModel::from_json(
        &std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    )
    .unwrap()
}

/// [`run_from_at`] with the declared spall width (inches), as `--fault-size-in` gives it.
fn run_sized(
    machine: &close_loop::machine::MachineModel,
    y: &[f64],
    fs: f64,
    rpm: f64,
    fault: DeclaredFault,
    size_in: f64,
    cfg: &close_loop::CheckedConfig,
) -> Outcome {
    let model = PhysicsModel {
        fault_size_in: size_in,
        ..PhysicsModel::default()
    };
    let op = OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        fault,
    )
    .unwrap();
    close_loop::close_loop_from(&model, Some(machine), &sig(y, fs), &op, cfg).unwrap()
}

/// The default settings with the CLI's 60 Hz mains declared.
fn mains_60() -> close_loop::CheckedConfig {
    LoopConfig {
        line_frequency_hz: Some(60.0),
        ..LoopConfig::default()
    }
    .check()
    .unwrap()
}

/// The rig's machine model: 97 (healthy, 48 kHz) decimated to 12 kHz and calibrated by the loop
/// with the default settings; once per test binary.
fn rig_12k(dir: &Path) -> &'static close_loop::machine::MachineModel {
    static RIG: std::sync::OnceLock<close_loop::machine::MachineModel> = std::sync::OnceLock::new();
    RIG.get_or_init(|| calibrate_97(dir, 12_000.0))
}

/// 97 (healthy, 48 kHz), at `fs` (decimated when below 48 kHz), calibrated by the loop with the
/// default settings.
fn calibrate_97(dir: &Path, fs: f64) -> close_loop::machine::MachineModel {
    let cfg = LoopConfig::default().check().unwrap();
    let h = load_record(dir, 97, &LoadOptions::default()).unwrap();
    let x = h.de_at(fs).unwrap();
    close_loop::machine::calibrate(
        &sig(&x, fs),
        h.rpm().value,
        bearing_model::Bearing::Skf6205,
        &cfg,
    )
    .unwrap()
}

/// The loop on `y` (12 kHz, 6205, outer race declared at `rpm`) started from `machine`.
fn run_from(
    machine: &close_loop::machine::MachineModel,
    y: &[f64],
    rpm: f64,
    cfg: &close_loop::CheckedConfig,
) -> Outcome {
    run_from_with(machine, y, rpm, DeclaredFault::Outer, cfg)
}

/// [`run_from`] with `fault` declared.
fn run_from_with(
    machine: &close_loop::machine::MachineModel,
    y: &[f64],
    rpm: f64,
    fault: DeclaredFault,
    cfg: &close_loop::CheckedConfig,
) -> Outcome {
    run_from_at(machine, y, 12_000.0, rpm, fault, cfg)
}

/// [`run_from_with`] at the sampling rate `fs`.
fn run_from_at(
    machine: &close_loop::machine::MachineModel,
    y: &[f64],
    fs: f64,
    rpm: f64,
    fault: DeclaredFault,
    cfg: &close_loop::CheckedConfig,
) -> Outcome {
    let op = OperatingPoint::new(
        rpm,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        fault,
    )
    .unwrap();
    close_loop::close_loop_from(
        &PhysicsModel::default(),
        Some(machine),
        &sig(y, fs),
        &op,
        cfg,
    )
    .unwrap()
}

/// The shaft harmonics of `order` that `o` names.
fn shaft_order_named(o: &Outcome, order: f64) -> Vec<close_loop::EffectEntry> {
    o.ledger
        .effects
        .iter()
        .filter(|e| {
            e.kind == EffectKind::ShaftHarmonic && e.parameters.get("order") == Some(&order)
        })
        .cloned()
        .collect()
}

/// The line comb `o` names, if any.
fn line_comb(o: &Outcome) -> Option<&close_loop::EffectEntry> {
    o.ledger
        .effects
        .iter()
        .find(|e| e.kind == EffectKind::LineComb)
}

/// The line comb `o` names, checked to have a 50 Hz spacing (within 0.5 %).
fn mains_comb_50(o: &Outcome) -> &close_loop::EffectEntry {
    let comb = line_comb(o).unwrap_or_else(|| {
        let k: Vec<EffectKind> = o.ledger.effects.iter().map(|e| e.kind).collect();
        panic!("no line comb named: {k:?}")
    });
    assert!(
        (comb.parameters["spacing_hz"] / 50.0 - 1.0).abs() < 0.005,
        "{comb:?}"
    );
    comb
}

/// Starting from the rig's machine model, 130 with a 50 Hz mains comb added (50…300 Hz, each
/// line at 28 % of the record's RMS; mains declared 50 Hz): the comb is named with its spacing,
/// its six lines and their amplitude. 50 Hz is 4.19 × the 6205's cage rate at 1796 rpm; when
/// comb spacings within the whole ± 5 % speed search of a rate's *multiples* counted as the
/// fault's own comb, it was never named (black-box check).
#[test]
fn mains_comb_from_the_machine_model_130() {
    let Some(dir) = data_dir() else { return };
    let machine = rig_12k(&dir);
    let r = load_record(&dir, 130, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    let x = r.de();
    let a = 0.28 * close_loop::metric::rms(x);
    let w = 2.0 * std::f64::consts::PI * 50.0 / 12_000.0;
    let y: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v + (1..=6)
                .map(|k| a * (w * (k * i) as f64 + 0.7 * k as f64).cos())
                .sum::<f64>()
        })
        .collect();
    let cfg = LoopConfig {
        line_frequency_hz: Some(50.0),
        ..LoopConfig::default()
    }
    .check()
    .unwrap();
    let o = run_from(machine, &y, rpm, &cfg);
    let comb = mains_comb_50(&o);
    assert!(comb.parameters["lines"] >= 5.0, "{comb:?}");
    assert!(
        (comb.parameters["amplitude"] / a - 1.0).abs() < 0.2,
        "{comb:?}"
    );
}

/// Starting from the rig's machine model (97 calibrated at 12 kHz), 130 played 3 % faster and
/// 3 % slower: the loop names the speed offset (beyond the former ± 2 % search), and does so
/// before random slip, which otherwise smears the model's lines over the moved ones (slip 8 %
/// was taken at 1.5 % and the speed never named).
#[test]
fn speed_change_by_resampling_from_the_machine_model_130() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let r = load_record(&dir, 130, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    for s in [1.03, 1.0 / 1.03] {
        let y = played_faster(r.de(), s);
        let o = run_from(machine, &y, rpm, &cfg);
        let speed = speed_named_before_slip(&o, s);
        // the speed is read from the shaft lines: the rig's BPFO, 0.32 % above the 6205's
        // order, is the defect rate beside it, not part of the speed
        let e = &o.ledger.effects[speed];
        let ratio = e.parameters["ratio"];
        let rel = ratio / s - 1.0;
        assert!((-0.001..0.001).contains(&rel), "{s}: {:?}", e.parameters);
        let q = e.parameters["defect_rate_ratio"];
        assert!((1.002..1.0045).contains(&q), "{s}: {:?}", e.parameters);
        assert!(o.ledger.error_after < o.ledger.error_before);
    }
}

/// The ledger position of the speed offset `o` names for a record played `s` times faster;
/// panics when none is named or a slip comes before it.
fn speed_named_before_slip(o: &Outcome, s: f64) -> usize {
    let kinds: Vec<EffectKind> = o.ledger.effects.iter().map(|e| e.kind).collect();
    let speed = kinds
        .iter()
        .position(|k| *k == EffectKind::SpeedOffset)
        .unwrap_or_else(|| panic!("{s}: no speed offset named: {kinds:?}"));
    if let Some(slip) = kinds.iter().position(|k| *k == EffectKind::Slip) {
        assert!(speed < slip, "{s}: slip before the speed: {kinds:?}");
    }
    speed
}

/// 170 (inner race 0.014 in, 1 hp, grade Y) played 2.5 % faster and 2 % slower, from the rig's
/// machine model with the inner race declared: the speed offset is named. An inner-race fault's
/// lines sit in the envelope (BPFI with shaft-rate sidebands), not in the spectrum, so the
/// spectral error barely moves with the speed; the held-out envelope's own speed estimate
/// confirms it (before, random slip of 8 % was taken instead and the speed never named).
#[test]
fn inner_race_speed_change_is_named_from_the_envelope_170() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let r = load_record(&dir, 170, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    for s in [1.025, 1.0 / 1.02] {
        let y = played_faster(r.de(), s);
        let o = run_from_with(machine, &y, rpm, DeclaredFault::Inner, &cfg);
        let speed = speed_named_before_slip(&o, s);
        // the speed is read from the shaft lines; CWRU's inner-race lines, 0.05–0.3 % below
        // the 6205's BPFI (169, 209, 105: 0.9996, 0.998, 0.997), are the defect rate beside it
        let e = &o.ledger.effects[speed];
        let rel = e.parameters["ratio"] / s - 1.0;
        assert!((-0.001..0.001).contains(&rel), "{s}: {:?}", e.parameters);
        assert_eq!(
            e.parameters["shaft_measured"], 1.0,
            "{s}: {:?}",
            e.parameters
        );
        assert!(e.accepted_on.is_some());
        assert!(o.ledger.error_after < o.ledger.error_before);
    }
}

/// 97 (healthy, 0 hp, 48 kHz, at its own rate, default settings: no mains frequency declared): a
/// 517 Hz tone at 25 % of the record's RMS, in a band where the healthy rig's own lines and
/// structural response sit, is named with its frequency and amplitude (a narrow line covers a
/// few bins of the spectral distance; its time-domain share decides), and the untouched record
/// names no line there.
#[test]
fn tone_among_the_healthy_rigs_lines_is_named_97() {
    let Some(dir) = data_dir() else { return };
    let r = load_record(&dir, 97, &LoadOptions::default()).unwrap();
    let (rpm, fs) = (r.rpm().value, r.fs_hz());
    let y0 = r.de().to_vec();
    let a = close_loop::metric::rms(&y0);
    let control = run_at(&y0, fs, rpm, DeclaredFault::None, None);
    assert!(
        near(&control, 517.0).is_none(),
        "{:#?}",
        control.ledger.effects
    );
    let mut y = y0.clone();
    add_tone(&mut y, fs, 517.0, 0.25 * a * std::f64::consts::SQRT_2, 1.0);
    let o = run_at(&y, fs, rpm, DeclaredFault::None, None);
    let t = near(&o, 517.0).expect("tone not named");
    assert_eq!(t.kind, EffectKind::Tone);
    let amp = t.parameters["amplitude"];
    assert!(
        (amp / (0.25 * a * std::f64::consts::SQRT_2) - 1.0).abs() < 0.2,
        "amplitude {amp}"
    );
    assert!(o.ledger.error_after < o.ledger.error_before);
}

/// `x` amplitude-modulated: x·(1 + μ·cos(2π·fm·t)).
fn modulated(x: &[f64], fs: f64, fm: f64, mu: f64) -> Vec<f64> {
    let w = 2.0 * std::f64::consts::PI * fm / fs;
    x.iter()
        .enumerate()
        .map(|(k, v)| v * (1.0 + mu * (w * k as f64).cos()))
        .collect()
}

/// The modulations `o` names near `fm` (within 1 %).
fn modulation_near(o: &Outcome, fm: f64) -> Option<&close_loop::EffectEntry> {
    o.ledger.effects.iter().find(|e| {
        e.kind == EffectKind::Modulation
            && e.frequency_hz.is_some_and(|f| (f / fm - 1.0).abs() < 0.01)
    })
}

/// 131 (outer race 0.007 in @6, 1 hp, grade Y) modulated 35 % at the cage rate, and 97 (healthy,
/// decimated to 12 kHz) modulated 30 % at the shaft and at the cage rate, each from the rig's
/// machine model: the modulation is named at its rate with its depth within 20 %, accepted on the
/// held-out envelope; the untouched records name no modulation there; the modulated healthy
/// record gets no bearing fault (a modulated band's spectral kurtosis makes it eligible for the
/// envelope search, whose lines one half of 97 at 48 kHz modulated at the cage rate passed at
/// BPFI: a fault is offered only when both halves show it). A modulation's sidebands barely move
/// the spectral distance of a broadband signal (before, such modulations were missed or came
/// back at the depth bound).
#[test]
fn amplitude_modulation_is_named_with_its_depth_131_97() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let r = load_record(&dir, 131, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    let cage = 0.39828 * rpm / 60.0 * 1.0032;
    let h = load_record(&dir, 97, &LoadOptions::default()).unwrap();
    let h12 = h.de_at(12_000.0).unwrap();
    let hrpm = h.rpm().value;
    let hcage = 0.39828 * hrpm / 60.0 * 1.0032;
    // each untouched record once, checked at every rate it is modulated at below
    let (x131, x97) = (r.de().to_vec(), h12.to_vec());
    let c131 = run_from_with(machine, &x131, rpm, DeclaredFault::Outer, &cfg);
    let c97 = run_from_with(machine, &x97, hrpm, DeclaredFault::None, &cfg);
    for (x, control, rpm, fault, fm, mu) in [
        (&x131, &c131, rpm, DeclaredFault::Outer, cage, 0.35),
        (&x97, &c97, hrpm, DeclaredFault::None, hrpm / 60.0, 0.30),
        (&x97, &c97, hrpm, DeclaredFault::None, hcage, 0.30),
    ] {
        assert!(
            modulation_near(control, fm).is_none(),
            "control: {:#?}",
            control.ledger.effects
        );
        let y = modulated(x, 12_000.0, fm, mu);
        let o = run_from_with(machine, &y, rpm, fault, &cfg);
        let e = modulation_near(&o, fm)
            .unwrap_or_else(|| panic!("{fm} Hz not named: {:#?}", o.ledger.effects));
        let depth = e.parameters["depth"];
        assert!(
            (depth / mu - 1.0).abs() < 0.2,
            "{fm} Hz: depth {depth} for {mu}"
        );
        assert_eq!(e.accepted_on, Some(close_loop::AcceptedOn::HeldOutEnvelope));
        if fault == DeclaredFault::None {
            assert!(
                o.ledger
                    .effects
                    .iter()
                    .all(|e| e.kind != EffectKind::BearingFault),
                "{fm} Hz: {:#?}",
                o.ledger.effects
            );
        }
    }
}

/// Does an effect of `o` name shaft order `k` (a shaft harmonic, or a member of a shaft comb)?
fn names_order(o: &Outcome, k: f64) -> bool {
    o.ledger.effects.iter().any(|e| match e.kind {
        EffectKind::ShaftHarmonic => e.parameters.get("order") == Some(&k),
        EffectKind::ShaftComb => e
            .description
            .split("orders ")
            .nth(1)
            .is_some_and(|l| l.split(", ").any(|v| v.trim().parse::<f64>() == Ok(k))),
        _ => false,
    })
}

/// Starting from the rig's machine model, which holds the healthy rig's 11th shaft order at a
/// few mg: the same order grown to a fifth of 130's RMS is named (the machine's lines take
/// their level from the recording only up to twice the calibrated one; before, the machine's
/// line absorbed any growth and nothing was named), the untouched record names no order 11.
#[test]
fn shaft_order_grown_beyond_the_machine_models_is_named_130() {
    let Some(dir) = data_dir() else { return };
    let machine = rig_12k(&dir);
    assert!(machine.lines.iter().any(|l| matches!(
        l,
        close_loop::machine::MachineLine::ShaftHarmonic { order, .. } if *order == 11.0
    )));
    let r = load_record(&dir, 130, &LoadOptions::default()).unwrap();
    let rpm = r.rpm().value;
    let x = r.de();
    let cfg = LoopConfig::default().check().unwrap();
    let control = run_from(machine, x, rpm, &cfg);
    assert!(
        !names_order(&control, 11.0),
        "{:#?}",
        control.ledger.effects
    );
    let fr = rpm / 60.0 * machine.speed_ratio;
    let a = 0.2 * close_loop::metric::rms(x) * std::f64::consts::SQRT_2;
    let w = 2.0 * std::f64::consts::PI * 11.0 * fr / 12_000.0;
    let y: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| v + a * (w * i as f64 + 0.4).cos())
        .collect();
    let o = run_from(machine, &y, rpm, &cfg);
    assert!(
        names_order(&o, 11.0),
        "{:#?}",
        o.ledger
            .effects
            .iter()
            .map(|e| &e.description)
            .collect::<Vec<_>>()
    );
}

/// `x` through a mode added in parallel: x + c·BP(x), BP the unit-peak band-pass biquad at `f0`
/// with damping `zeta` (RBJ cookbook, constant 0 dB peak gain), written out here rather than
/// taken from the crate so that the loop is checked against an independent resonator.
fn with_mode(x: &[f64], fs: f64, f0: f64, zeta: f64, c: f64) -> Vec<f64> {
    let w0 = 2.0 * std::f64::consts::PI * f0 / fs;
    let alpha = w0.sin() * zeta; // sin(w0) / (2Q), Q = 1 / (2ζ)
    let a0 = 1.0 + alpha;
    let (b0, b2) = (alpha / a0, -alpha / a0);
    let (a1, a2) = (-2.0 * w0.cos() / a0, (1.0 - alpha) / a0);
    let (mut x1, mut x2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
    x.iter()
        .map(|&v| {
            let y = b0 * v + b2 * x2 - a1 * y1 - a2 * y2;
            (x2, x1, y2, y1) = (x1, v, y1, y);
            v + c * y
        })
        .collect()
}

/// Starting from the rig's machine model, 97 (healthy, decimated to 12 kHz) seen through a mode
/// the model lacks — 1730 Hz, ζ 0.02, peak amplitude gain 2.5 (+8 dB), and in a second case
/// 4700 Hz, ζ 0.02, peak gain 2 (+6 dB) above the rig's 4.0–4.4 kHz interference comb — is
/// named as a resonance in the measurement channel with the mode's frequency within 0.5 % and
/// its peak gain within 20 %; the untouched record names no resonance within 3 % of either.
/// (A mode of the channel shapes the healthy machine's background as it shapes a fault's
/// impacts; before, channel modes acted on the physics alone and a healthy machine's missing
/// mode could not be named.) On a fault record a mode near where the impacts ring is taken into
/// the impacts' structural path identified on that record — the data cannot tell the two apart.
/// Not every mode is found: at ζ 0.02 and +6 dB, 600, 900, 3500 and 5200 Hz were not named (a
/// mode a few bins wide moves the held-out spectral distance by less than the 2 % a candidate
/// must explain; `docs/equations/close-loop.md`, "Resonance").
#[test]
fn resonance_added_to_97_is_named() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let h = load_record(&dir, 97, &LoadOptions::default()).unwrap();
    let x = h.de_at(12_000.0).unwrap().to_vec();
    let rpm = h.rpm().value;
    let fault = DeclaredFault::None;
    let cases = [(1730.0, 0.02, 1.5), (4700.0, 0.02, 1.0)];
    let resonance_near = |o: &Outcome, f0: f64, tol: f64| {
        o.ledger
            .effects
            .iter()
            .find(|e| {
                e.kind == EffectKind::Resonance
                    && e.frequency_hz.is_some_and(|f| (f / f0 - 1.0).abs() < tol)
            })
            .cloned()
    };
    let control = run_from_with(machine, &x, rpm, fault, &cfg);
    for (f0, zeta, c) in cases {
        assert!(
            resonance_near(&control, f0, 0.03).is_none(),
            "control {f0} Hz: {:#?}",
            control.ledger.effects
        );
        let y = with_mode(&x, 12_000.0, f0, zeta, c);
        let o = run_from_with(machine, &y, rpm, fault, &cfg);
        let e = resonance_near(&o, f0, 0.005).unwrap_or_else(|| {
            panic!(
                "{f0} Hz not named: {:#?}\nrejected: {:#?}",
                o.ledger.effects, o.ledger.rejected
            )
        });
        assert_eq!(e.placement, close_loop::Placement::Measurement, "{e:#?}");
        let peak = 1.0 + e.parameters["gain"];
        assert!(
            (peak / (1.0 + c) - 1.0).abs() < 0.2,
            "{f0} Hz: peak amplitude gain {peak} for {}; {e:#?}",
            1.0 + c
        );
        assert!(e.error_after < e.error_before, "{e:#?}");
        eprintln!("{f0} Hz: {}", e.description);
    }
}

/// The effect of `kind` that `o` names within 0.5 % of `f`.
fn named(o: &Outcome, kind: EffectKind, f: f64) -> Option<&close_loop::EffectEntry> {
    o.ledger
        .effects
        .iter()
        .find(|e| e.kind == kind && e.frequency_hz.is_some_and(|g| (g / f - 1.0).abs() < 0.005))
}

/// A 48 kHz record's sampling rate (checked), stored speed (rpm) and drive-end signal.
fn drive_end_48k(dir: &Path, number: u32) -> (f64, f64, Vec<f64>) {
    let r = load_record(dir, number, &LoadOptions::default()).unwrap();
    let fs = r.fs_hz();
    assert_eq!(fs, 48_000.0, "{number}.mat");
    (fs, r.rpm().value, r.de().to_vec())
}

/// A record's stored speed (rpm) and its drive-end signal.
fn drive_end(dir: &Path, number: u32) -> (f64, Vec<f64>) {
    let r = load_record(dir, number, &LoadOptions::default()).unwrap();
    (r.rpm().value, r.de().to_vec())
}

/// 235 (outer race 0.021 in @6, 1 hp, 12 kHz), from the rig's machine model, with a mains comb
/// of only three lines added (50, 100, 150 Hz, each at 12 % of the record's RMS; the rig's
/// declared mains stays 60 Hz): the three are named as one line comb (spacing within 0.5 % of
/// 50 Hz, amplitude within 20 %), and the rest of the model is left as on the untouched record
/// (final held-out error within 0.5 dB of the control's). Before, a comb needed four lines, so
/// the three came one by one behind the resonances and were cut off by the effect budget; and
/// the strong lines had made the fault's structural path fall from AR order 64 to 8 (its order
/// was scored against the PSD with the lines in it), leaving the record at 3.9 dB against the
/// control's 2.4.
#[test]
fn three_line_mains_comb_is_one_comb_and_leaves_the_path_235() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let (rpm, x) = drive_end(&dir, 235);
    let a = 0.12 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    for k in 1..=3 {
        add_tone(&mut y, 12_000.0, 50.0 * k as f64, a, k as f64);
    }
    let control = run_from(machine, &x, rpm, &cfg);
    assert!(
        !control
            .ledger
            .effects
            .iter()
            .any(|e| e.kind == EffectKind::LineComb),
        "control: {:#?}",
        control.ledger.effects
    );
    let o = run_from(machine, &y, rpm, &cfg);
    let comb = mains_comb_50(&o);
    assert_eq!(comb.parameters["lines"], 3.0, "{comb:?}");
    assert!(
        (comb.parameters["amplitude"] / a - 1.0).abs() < 0.2,
        "{comb:?}"
    );
    assert!(
        o.ledger.error_after <= control.ledger.error_after + 0.5,
        "with the comb {:.3} dB, control {:.3} dB",
        o.ledger.error_after,
        control.ledger.error_after
    );
}

/// 235 from the rig's machine model, modulated 35 % at the cage rate. The record's envelope holds
/// its fault's own sidebands, BPFO − 2·fr (47.0 Hz) and BPFO − 3·fr (17.5 Hz), which the loop
/// named as modulations of their own ("1.59 × fr") and which took both modulation slots, so the
/// cage modulation was never judged. Now the control names no modulation at a sideband of the
/// impact rate, and the modulated record names the cage modulation (rate within 0.5 %, `cage`).
/// Its depth comes out above the 35 % added (the record's own cage-rate modulation adds to it,
/// 13 % on the control), within ×1.5.
#[test]
fn cage_modulation_is_not_crowded_out_by_the_faults_sidebands_235() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let (rpm, x) = drive_end(&dir, 235);
    let fr = rpm / 60.0;
    let bpfo = 3.5848 * fr;
    let control = run_from(machine, &x, rpm, &cfg);
    for e in control
        .ledger
        .effects
        .iter()
        .filter(|e| e.kind == EffectKind::Modulation)
    {
        let f = e.frequency_hz.unwrap();
        assert!(
            (1..=3).all(|k| (f - (bpfo - k as f64 * fr)).abs() > 0.005 * f),
            "control names a modulation at a sideband of BPFO: {e:?}"
        );
    }
    let cage = 0.39828 * fr * 1.0032;
    let y = modulated(&x, 12_000.0, cage, 0.35);
    let o = run_from(machine, &y, rpm, &cfg);
    let e = named(&o, EffectKind::Modulation, cage)
        .unwrap_or_else(|| panic!("cage modulation not named: {:#?}", o.ledger.effects));
    assert!(e.description.contains("cage"), "{e:?}");
    let depth = e.parameters["depth"];
    assert!((0.35..=0.525).contains(&depth), "depth {depth}");
}

/// The rig's machine model at 48 kHz: 97 (healthy, 48 kHz) calibrated by the loop with the
/// default settings; once per test binary.
fn rig_48k(dir: &Path) -> &'static close_loop::machine::MachineModel {
    static RIG: std::sync::OnceLock<close_loop::machine::MachineModel> = std::sync::OnceLock::new();
    RIG.get_or_init(|| calibrate_97(dir, 48_000.0))
}

/// 213 (inner race 0.021 in, 0 hp, 48 kHz), from the 48 kHz rig, with a 2× shaft line at 30 % of
/// the record's RMS. The record's shaft comb cannot be read, and its fault lines sit 0.19 % below
/// the declared speed's. The line went into the physics, then a speed step of ×0.9981 moved it
/// and the leftover at the true 2·fr was named a second time, as a sensor line. The fitted line
/// now reads the shaft's speed: the step is a defect rate, and order 2 is named once, with its
/// amplitude within 20 %. The untouched record names no 2× line.
#[test]
fn a_fitted_shaft_line_keeps_the_shaft_speed_213_48k() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_48k(&dir);
    let (fs, rpm, x) = drive_end_48k(&dir, 213);
    let a = 0.3 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    add_tone(&mut y, fs, 2.0 * rpm / 60.0, a, 0.4);
    let run = |z: &[f64]| run_from_at(machine, z, fs, rpm, DeclaredFault::Inner, &cfg);
    let second = |o: &Outcome| shaft_order_named(o, 2.0);
    let control = run(&x);
    assert!(second(&control).is_empty(), "{:#?}", control.ledger.effects);
    let o = run(&y);
    let named = second(&o);
    assert_eq!(named.len(), 1, "{named:#?}");
    assert!(
        (named[0].parameters["amplitude"] / a - 1.0).abs() < 0.2,
        "{named:#?}"
    );
    assert!(
        !o.ledger
            .effects
            .iter()
            .any(|e| e.kind == EffectKind::SpeedOffset),
        "{:#?}",
        o.ledger.effects
    );
}

/// 235 from the rig's machine model with a 733 Hz tone at 25 % of the record's RMS, 11 Hz below
/// the record's own 744 Hz resonance, and a 3× shaft line as strong: the tone is named (frequency
/// within 0.5 %, amplitude within 20 %). Before, a 735 Hz mode of ζ 0.011 (+16 dB), ranked ahead
/// of it by the fitting error, took the tone and the resonance together; the untouched record
/// names no tone there.
#[test]
fn tone_beside_the_records_resonance_is_a_tone_235() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let (rpm, x) = drive_end(&dir, 235);
    let a = 0.25 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    let h = std::f64::consts::FRAC_PI_2;
    add_tone(&mut y, 12_000.0, 733.0, a, -h);
    add_tone(&mut y, 12_000.0, 3.0 * rpm / 60.0, a, 0.7 - h);
    let control = run_from(machine, &x, rpm, &cfg);
    assert!(
        named(&control, EffectKind::Tone, 733.0).is_none(),
        "{:#?}",
        control.ledger.effects
    );
    let o = run_from(machine, &y, rpm, &cfg);
    let e = named(&o, EffectKind::Tone, 733.0)
        .unwrap_or_else(|| panic!("733 Hz tone not named: {:#?}", o.ledger.effects));
    assert!((e.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{e:#?}");
}

/// 171 (inner race 0.014 in, 2 hp, 12 kHz), from the rig's machine model with the inner race
/// declared, played 1 % faster with a 1234 Hz tone at 25 % of the record's RMS in it: the speed
/// (read from the shaft lines, within 0.1 %) and the tone (at 1246.3 Hz after the resampling,
/// frequency within 0.5 %, amplitude within 20 %) are both named. The tone was named first;
/// a correct speed step then raised the held-out spectral error by 0.048 dB of 3.36 dB, over the
/// 0.03 dB a speed step confirmed by the held-out envelope alone was allowed, and the speed was
/// never named. The allowance is now the acceptance margin (2 % of the error, at least 0.03 dB).
#[test]
fn speed_change_beside_a_tone_is_named_171() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_12k(&dir);
    let (rpm, x) = drive_end(&dir, 171);
    let a = 0.25 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    add_tone(&mut y, 12_000.0, 1234.0, a, 0.3);
    let s = 1.01;
    let y = played_faster(&y, s);
    let o = run_from_with(machine, &y, rpm, DeclaredFault::Inner, &cfg);
    let speed = speed_named_before_slip(&o, s);
    let e = &o.ledger.effects[speed];
    let rel = e.parameters["ratio"] / s - 1.0;
    assert!((-0.001..0.001).contains(&rel), "{:?}", e.parameters);
    let t = named(&o, EffectKind::Tone, 1234.0 * s)
        .unwrap_or_else(|| panic!("tone not named: {:#?}", o.ledger.effects));
    assert!((t.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{t:#?}");
}

/// 246 (outer race 0.021 in @3, 0 hp, 1796 rpm, 12 kHz), from the rig's machine model with the
/// rig's 60 Hz mains declared, with a 60 Hz comb added (60, 120, 180, 240 Hz, each at 12 % of the
/// record's RMS): one line comb is named (spacing within 0.5 % of 60 Hz, at least three lines,
/// amplitude within 20 %); the untouched record names none. 60 Hz is 0.2 % from 2 × fr here, so
/// the comb's spacing counted as a multiple of the shaft rate (the fault's own comb at another
/// speed) and only 180 and 240 Hz were named, as two tones.
#[test]
fn sixty_hz_comb_beside_the_shaft_harmonics_246() {
    let Some(dir) = data_dir() else { return };
    let cfg = mains_60();
    let machine = rig_12k(&dir);
    let (rpm, x) = drive_end(&dir, 246);
    let a = 0.12 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    for k in 1..=4 {
        add_tone(&mut y, 12_000.0, 60.0 * k as f64, a, 0.7 * k as f64);
    }
    let control = run_from(machine, &x, rpm, &cfg);
    assert!(
        line_comb(&control).is_none(),
        "{:#?}",
        control.ledger.effects
    );
    let o = run_from(machine, &y, rpm, &cfg);
    let c = line_comb(&o).unwrap_or_else(|| panic!("no line comb: {:#?}", o.ledger.effects));
    assert!(
        (c.parameters["spacing_hz"] / 60.0 - 1.0).abs() < 0.005,
        "{c:?}"
    );
    assert!(c.parameters["lines"] >= 3.0, "{c:?}");
    assert!((c.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{c:?}");
}

/// 160 (outer race 0.007 in @12, 3 hp, 12 kHz), from the rig's machine model with 60 Hz mains:
///
/// - with a 2× shaft line at 20 % of the record's RMS, the order is named once (amplitude within
///   20 %), and once it is a physics shaft force no later effect moves the fault's rate off the
///   shaft (the physics' shaft runs at the impact rate, so a preload's ×1.003 rate step moved the
///   simulated line 0.17 Hz off the measured one);
/// - with the same line and a 30 % modulation at the cage rate, the order is still named once
///   (before, after a ×1.003 preload the line was put into the physics at 57.64 Hz against
///   57.467 Hz measured, and a second "2×" came back at 57.567 Hz), and the cage modulation is
///   named (rate within 0.5 %; the record's own cage modulation drifts in phase against the
///   added one, 0.71 and 0.47 on the two halves, which the former held-out rule — the modulated
///   model predicting the held-out index twice as well as the plain one — rejected).
#[test]
fn one_line_per_shaft_order_and_the_cage_modulation_160() {
    let Some(dir) = data_dir() else { return };
    let cfg = mains_60();
    let machine = rig_12k(&dir);
    let (rpm, x) = drive_end(&dir, 160);
    let fr = rpm / 60.0;
    let a = 0.2 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    add_tone(&mut y, 12_000.0, 2.0 * fr, a, 0.3);
    let second = |o: &Outcome| shaft_order_named(o, 2.0);
    let o = run_from(machine, &y, rpm, &cfg);
    let named2 = second(&o);
    assert_eq!(named2.len(), 1, "{:#?}", o.ledger.effects);
    assert!(
        (named2[0].parameters["amplitude"] / a - 1.0).abs() < 0.2,
        "{named2:#?}"
    );
    if named2[0].parameters.contains_key("force_amplitude_n") {
        let at = o
            .ledger
            .effects
            .iter()
            .position(|e| e.kind == EffectKind::ShaftHarmonic)
            .unwrap();
        assert!(
            !o.ledger.effects[at..].iter().any(|e| {
                e.kind == EffectKind::DefectRate
                    || (e.kind == EffectKind::ContactPreload
                        && e.parameters.contains_key("defect_rate_step"))
            }),
            "{:#?}",
            o.ledger.effects
        );
    }
    let cage = 0.39828 * fr;
    let h = std::f64::consts::FRAC_PI_2;
    let mut z: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let t = i as f64 / 12_000.0;
            v * (1.0 + 0.3 * (2.0 * std::f64::consts::PI * cage * t + h).cos())
        })
        .collect();
    add_tone(&mut z, 12_000.0, 2.0 * fr, a, 0.3);
    let o = run_from(machine, &z, rpm, &cfg);
    assert_eq!(second(&o).len(), 1, "{:#?}", o.ledger.effects);
    named(&o, EffectKind::Modulation, cage)
        .unwrap_or_else(|| panic!("cage modulation not named: {:#?}", o.ledger.effects));
}

/// 109 (inner race 0.007 in, 0 hp, 48 kHz), from the 48 kHz rig, with a 21 kHz tone (0.44·fs)
/// at 25 % of the record's RMS: the tone is named (frequency within 0.5 %, amplitude within
/// 20 %). At 21 kHz the windows that make a line "the declared fault's" (k·BPFI + m·fr, |m| ≤
/// 3, each ± 0.03 %) cover 55 % of the axis, so the tone was taken for a fault line, lost its
/// standing as a coherent line behind the record's own fault lines and was never named.
#[test]
fn tone_near_the_top_of_the_band_is_named_109_48k() {
    let Some(dir) = data_dir() else { return };
    let cfg = LoopConfig::default().check().unwrap();
    let machine = rig_48k(&dir);
    let (fs, rpm, x) = drive_end_48k(&dir, 109);
    let a = 0.25 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    add_tone(&mut y, fs, 21_000.0, a, 0.3);
    let o = run_from_at(machine, &y, fs, rpm, DeclaredFault::Inner, &cfg);
    let e = named(&o, EffectKind::Tone, 21_000.0)
        .unwrap_or_else(|| panic!("21 kHz tone not named: {:#?}", o.ledger.effects));
    assert!((e.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{e:#?}");
}

/// 135 (outer race 0.007 in @6, 0 hp, 48 kHz), from the 48 kHz rig, with a 2.5 × shaft line at
/// 20 % and a 9 kHz tone at 15 % of the record's RMS, the tone 54 dB over its neighbourhood in
/// the residual's spectrum. The record's BPFO
/// harmonics around its 3.4 kHz resonance, 0.3 % off the declared speed until the speed is
/// taken, each held more power than the tone and filled the eight line candidates taken by
/// power; a 9 kHz mode at the narrowest damping the search allows took the tone, and a −24 dB
/// mode beside it undid the rest. A line standing ≥ 30 dB over its neighbourhood is now tried
/// whatever its power: the tone is named, amplitude within 20 %, and no mode sits on it.
#[test]
fn plain_tone_beside_stronger_fault_lines_is_named_135_48k() {
    let Some(dir) = data_dir() else { return };
    let cfg = mains_60();
    // the rig's model as users pass it (`--machine results/close-loop/rig-48k.json`: calibrated
    // with the CLI's 60 Hz mains); the defaults' model (no mains) happens to keep the tone in
    // the slots taken by power
    let machine = &committed_rig("rig-48k");
    let (fs, rpm, x) = drive_end_48k(&dir, 135);
    let a = 0.15 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let a_half = 0.2 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let mut y = x.clone();
    // sin(2π·f·t + 0.3), as `docs/crosschecks/close_loop_blackbox.py` case b adds them
    let ph = 0.3 - std::f64::consts::FRAC_PI_2;
    add_tone(&mut y, fs, 2.5 * rpm / 60.0, a_half, ph);
    add_tone(&mut y, fs, 9_000.0, a, ph);
    let o = run_from_at(machine, &y, fs, rpm, DeclaredFault::Outer, &cfg);
    let h = named(&o, EffectKind::ShaftHarmonic, 2.5 * rpm / 60.0)
        .unwrap_or_else(|| panic!("2.5× not named: {:#?}", o.ledger.effects));
    assert!(
        (h.parameters["amplitude"] / a_half - 1.0).abs() < 0.2,
        "{h:#?}"
    );
    let e = named(&o, EffectKind::Tone, 9_000.0)
        .unwrap_or_else(|| panic!("9 kHz tone not named: {:#?}", o.ledger.effects));
    assert!((e.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{e:#?}");
    assert!(
        !o.ledger
            .effects
            .iter()
            .any(|e| e.kind == EffectKind::Resonance
                && e.frequency_hz
                    .is_some_and(|f| (f / 9_000.0 - 1.0).abs() < 0.01)),
        "a mode on the tone: {:#?}",
        o.ledger.effects
    );
}

/// 226 (ball 0.021 in, 0 hp, 48 kHz), from the 48 kHz rig, with a tone at 0.45·fs (21.6 kHz, the
/// band's upper edge) at 20 % of the record's RMS. Two defects had it: four of the record's lines
/// at 2557–2620 Hz, all within 0.3 % of "position 0" of a 19 kHz spacing, made a five-line
/// `line_comb` with the tone (now one member per comb position); and, without that, a mode at
/// the narrowest damping the search allows (ζ 0.001, 43 Hz wide, more than two bins) took the
/// tone before it was judged, and a second mode beside it the rest (a strong line now goes
/// before a mode that narrow on it). The tone is named, amplitude within 20 %, alone.
#[test]
fn tone_at_the_band_edge_is_neither_a_comb_nor_a_mode_226_48k() {
    let Some(dir) = data_dir() else { return };
    let cfg = mains_60();
    let machine = &committed_rig("rig-48k");
    let (fs, rpm, x) = drive_end_48k(&dir, 226);
    let a = 0.2 * std::f64::consts::SQRT_2 * close_loop::metric::rms(&x);
    let f = 0.45 * fs;
    let mut y = x.clone();
    add_tone(&mut y, fs, f, a, 0.3 - std::f64::consts::FRAC_PI_2);
    // the record's own size declared, as `hybrid-fdd close-loop --fault-size-in 0.021` does
    let o = run_sized(machine, &y, fs, rpm, DeclaredFault::Ball, 0.021, &cfg);
    let e = named(&o, EffectKind::Tone, f)
        .unwrap_or_else(|| panic!("{f} Hz tone not named: {:#?}", o.ledger.effects));
    assert!((e.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{e:#?}");
    assert!(
        !o.ledger
            .effects
            .iter()
            .any(|e| (e.kind == EffectKind::Resonance
                && e.frequency_hz.is_some_and(|g| (g / f - 1.0).abs() < 0.01))
                || (e.kind == EffectKind::LineComb && e.parameters["highest_hz"] > 0.4 * fs)),
        "a mode or a comb on the tone: {:#?}",
        o.ledger.effects
    );
}

/// 3001 (inner race 0.028 in, 0 hp, 12 kHz), from the rig's machine model as users pass it, with
/// a 5 kHz tone at 10 % and a 4 × shaft line at 15 % of the record's RMS. The tone was a
/// candidate (44 dB over its neighbourhood) and strong, but a 5002 Hz mode of ζ 0.0038 (38 Hz
/// wide, six bins, +25 dB) on it fitted better and took it. A strong line now also goes before a
/// mode centred on it when the line holds at least half the power the mode adds: the tone is
/// named, amplitude within 20 %, and no mode sits on it.
#[test]
fn tone_before_the_mode_it_would_dress_3001() {
    let Some(dir) = data_dir() else { return };
    let cfg = mains_60();
    let machine = &committed_rig("rig-12k");
    let (rpm, x) = drive_end(&dir, 3001);
    let fs = 12_000.0;
    let rms = close_loop::metric::rms(&x);
    let (a, a4) = (
        0.10 * std::f64::consts::SQRT_2 * rms,
        0.15 * std::f64::consts::SQRT_2 * rms,
    );
    let ph = 0.3 - std::f64::consts::FRAC_PI_2;
    let mut y = x.clone();
    add_tone(&mut y, fs, 5_000.0, a, ph);
    add_tone(&mut y, fs, 4.0 * rpm / 60.0, a4, ph);
    let o = run_sized(machine, &y, fs, rpm, DeclaredFault::Inner, 0.028, &cfg);
    let e = named(&o, EffectKind::Tone, 5_000.0)
        .unwrap_or_else(|| panic!("5 kHz tone not named: {:#?}", o.ledger.effects));
    assert!((e.parameters["amplitude"] / a - 1.0).abs() < 0.2, "{e:#?}");
    assert!(
        !o.ledger
            .effects
            .iter()
            .any(|e| e.kind == EffectKind::Resonance
                && e.frequency_hz
                    .is_some_and(|g| (g / 5_000.0 - 1.0).abs() < 0.01)),
        "a mode on the tone: {:#?}",
        o.ledger.effects
    );
}

/// 148 (outer race 0.007 in @3, 3 hp, 48 kHz), from the committed 48 kHz rig, with a 12 kHz
/// tone at 10 % and a 1.5 × shaft line at 15 % of the record's RMS, at the stored speed. A speed
/// step of ×1.005 read from the fault's lines alone (the shaft's own lines too weak to read) came
/// first and put the model's 1.5 × 0.5 % away, past the 0.4 % a shaft order allows: the line was
/// named a `tone`. After a step the shaft's lines did not confirm, a line at an order of the
/// speed before it is a shaft line too: named a `shaft_harmonic` of order 1.5, amplitude within
/// 20 %, and the tone beside it. Since the held-out envelope may veto a speed step its fault
/// lines contradict (2026-11-27), the ×1.0048 step is refused (the envelope reads the fault's
/// lines at ×1.0037) and ×1.0039 is taken: the step stays unconfirmed by the shaft but no longer
/// passes 0.4 %, and the half order must still be named a shaft line. Since the impacts'
/// high-pass is judged before slip (2026-11-27, later) no speed step is taken on this record at
/// all (the high-pass, the comb, the 1.5 × and the tone come first): the guarded path is no
/// longer reached here, and the test keeps what a user sees — the half order a shaft line with
/// its amplitude, the tone a tone — with or without a step before them.
#[test]
fn half_order_beside_a_tone_is_a_shaft_line_with_or_without_a_speed_step_148_48k() {
    let Some(dir) = data_dir() else { return };
    let cfg = mains_60();
    let machine = &committed_rig("rig-48k");
    let (fs, rpm, x) = drive_end_48k(&dir, 148);
    let rms = close_loop::metric::rms(&x);
    let (a_tone, a_half) = (0.1 * 2f64.sqrt() * rms, 0.15 * 2f64.sqrt() * rms);
    let f_half = 1.5 * rpm / 60.0;
    let mut y = x.clone();
    add_tone(&mut y, fs, 12_000.0, a_tone, 0.3);
    add_tone(&mut y, fs, f_half, a_half, 0.3);
    let o = run_sized(machine, &y, fs, rpm, DeclaredFault::Outer, 0.007, &cfg);
    let e = named(&o, EffectKind::ShaftHarmonic, f_half)
        .unwrap_or_else(|| panic!("1.5 x not named a shaft line: {:#?}", o.ledger.effects));
    assert_eq!(e.parameters["order"], 1.5, "{e:#?}");
    assert!(
        (e.parameters["amplitude"] / a_half - 1.0).abs() < 0.2,
        "{e:#?}"
    );
    assert!(
        named(&o, EffectKind::Tone, 12_000.0).is_some(),
        "{:#?}",
        o.ledger.effects
    );
}

/// Real fault records declared healthy, from the rig's machine model (calibrated on 97): the
/// fault nobody declared is named first, as what it is — 106 (IR007, 1 hp) an inner race at
/// BPFI, 235 (OR021 @6, 1 hp) an outer race at BPFO — and halves the error or nearly so; the
/// healthy rig itself (97 at 12 kHz) declared healthy gets no fault. Before the candidate
/// (`hybrid-fdd close-loop --fault none --machine rig.json`) 235 was eight channel modes
/// (8.75 → 3.51 dB) and 106 a resonance and patches; with the spall but without a path of its
/// own impacts the outer race lost to those modes every round.
#[test]
fn a_fault_nobody_declared_is_named_from_the_machine_model_106_235() {
    let Some(dir) = data_dir() else { return };
    let rig = rig_12k(&dir);
    let cfg = mains_60();
    for (number, rate) in [(106, "BPFI"), (235, "BPFO")] {
        let (rpm, y) = drive_end(&dir, number);
        let o = run_from_with(rig, &y, rpm, DeclaredFault::None, &cfg);
        let faults: Vec<_> = o
            .ledger
            .effects
            .iter()
            .filter(|e| e.kind == EffectKind::BearingFault)
            .collect();
        assert_eq!(faults.len(), 1, "{number}: {:#?}", o.ledger.effects);
        let e = &o.ledger.effects[0];
        assert_eq!(
            e.kind,
            EffectKind::BearingFault,
            "{number}: {}",
            e.description
        );
        assert_eq!(e.kinematic_rate.as_deref(), Some(rate), "{number}");
        assert!(
            e.error_after < 0.6 * e.error_before,
            "{number}: {}",
            e.description
        );
    }
    let h = load_record(&dir, 97, &LoadOptions::default()).unwrap();
    let x = h.de_at(12_000.0).unwrap();
    let o = run_from_with(rig, &x, h.rpm().value, DeclaredFault::None, &cfg);
    assert!(
        o.ledger
            .effects
            .iter()
            .all(|e| e.kind != EffectKind::BearingFault),
        "{:#?}",
        o.ledger.effects
    );
}

/// 146 (OR007 at 3 o'clock, 2 hp), untouched, from the rig's machine model as users pass it.
/// From the rig, the physics of the outer-race spall is seen through the path its impacts ring.
/// That path is identified near the resonance, where the impacts dominate, and below it the
/// physics puts BPFO combs that the record does not show. Until 2026-11-27 only a random slip at
/// the model's 10 % bound could smear them, and the comb the record keeps at the resonance went
/// with them (`docs/journal/close-loop.md`, "What the slip at the model's bound does not
/// mean"). The loop now names `impacts_high_pass`: a physics placement, a corner inside its
/// search range, and a held-out error lowered by at least 10 %. No slip is then taken at the
/// model's bound.
#[test]
fn the_impacts_weaker_below_a_corner_is_a_high_pass_not_slip_146() {
    let Some(dir) = data_dir() else { return };
    let o = outer_race_from_rig_12k(&dir, 146, 0.007);
    let hp = o
        .ledger
        .effects
        .iter()
        .find(|e| e.kind == EffectKind::ImpactsHighPass)
        .unwrap_or_else(|| panic!("no impacts_high_pass: {:#?}", o.ledger.effects));
    assert_eq!(hp.placement, close_loop::Placement::Physics);
    let corner = hp.parameters["corner_hz"];
    assert!(
        (100.0..3_000.0).contains(&corner) && hp.parameters["at_search_bound"] == 0.0,
        "{hp:#?}"
    );
    assert!(hp.error_after < 0.9 * hp.error_before, "{hp:#?}");
    assert!(
        !o.ledger.effects.iter().any(
            |e| e.kind == EffectKind::Slip && e.parameters.get("at_search_bound") == Some(&1.0)
        ),
        "{:#?}",
        o.ledger.effects
    );
}

/// 259 (OR021 at 12 o'clock, 1 hp), untouched, from the rig's machine model. Judged by the
/// fitting error alone, a random slip ranked ahead of the impacts' high-pass there, was taken at
/// the model's 10 % bound, and once it had smeared the low BPFO comb no corner helped: the
/// high-pass was never named (as on 28 other measured records). A slip can stand in for the
/// high-pass, which cannot stand in for slip (it leaves the comb at the resonance), so the
/// high-pass is judged first (`runner::ranking::before_slip`). The loop names it, ahead of any
/// slip, a physics placement with a corner inside its search range, and takes no slip at the
/// model's bound. A different family from 146's (OR021, not OR007) and a larger spall.
#[test]
fn the_high_pass_is_judged_before_slip_259() {
    let Some(dir) = data_dir() else { return };
    let o = outer_race_from_rig_12k(&dir, 259, 0.021);
    let fx = &o.ledger.effects;
    let hp = fx
        .iter()
        .position(|e| e.kind == EffectKind::ImpactsHighPass)
        .unwrap_or_else(|| panic!("no impacts_high_pass: {fx:#?}"));
    assert_eq!(fx[hp].placement, close_loop::Placement::Physics);
    assert!(fx[hp].parameters["at_search_bound"] == 0.0, "{:#?}", fx[hp]);
    assert!(
        fx[..hp].iter().all(|e| e.kind != EffectKind::Slip),
        "a slip before the high-pass: {fx:#?}"
    );
    assert!(
        !fx.iter().any(
            |e| e.kind == EffectKind::Slip && e.parameters.get("at_search_bound") == Some(&1.0)
        ),
        "{fx:#?}"
    );
}

/// A 12 kHz outer-race record `number`, untouched, run from the committed 12 kHz rig with its
/// catalogued spall width declared and the 60 Hz mains.
fn outer_race_from_rig_12k(dir: &std::path::Path, number: u32, size_in: f64) -> Outcome {
    let (rpm, x) = drive_end(dir, number);
    run_sized(
        &committed_rig("rig-12k"),
        &x,
        12_000.0,
        rpm,
        DeclaredFault::Outer,
        size_in,
        &mains_60(),
    )
}

/// `y` at `fs` Hz as a checked signal (the recordings here are finite and non-empty).
fn sig(y: &[f64], fs: f64) -> close_loop::Signal<'_> {
    close_loop::Signal::new(y, fs).unwrap()
}
