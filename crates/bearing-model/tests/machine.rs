//! The phenomenological machine recordings put each component's lines where they belong:
//! gear-mesh sidebands at the second shaft's non-integer order, mains at k·50 Hz with pole-pass
//! sidebands, a fault's impacts at its rate with its modulation, once-per-rev impacts at every
//! shaft order of the envelope, another shaft's impacts at its non-integer order, the shaft comb
//! at integer and half orders.

mod common;

use bearing_model::machine::{LocalizedFault, MachineParams, MachineRecipe, Nuisances};
use bearing_model::{BearingGeometry, FaultLocation};
use common::{envelope_spectrum, median_in, peak_near};
use rustfft::{FftPlanner, num_complex::Complex};

/// One-sided Hann-windowed amplitude spectrum: (resolution, magnitudes).
fn spectrum(x: &[f64], fs: f64) -> (f64, Vec<f64>) {
    let n = x.len();
    let mut buf: Vec<Complex<f64>> = x
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let w = 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos();
            Complex::new(v * w, 0.0)
        })
        .collect();
    FftPlanner::<f64>::new()
        .plan_fft_forward(n)
        .process(&mut buf);
    (
        fs / n as f64,
        buf[..n / 2].iter().map(|c| c.norm() / n as f64).collect(),
    )
}

/// `params` with a still shaft speed (no wander), so lines are one bin wide.
fn steady(mut p: MachineParams) -> MachineParams {
    p.speed.rms_fraction = 0.0;
    for t in &mut p.speed.tones {
        t[1] = 0.0;
    }
    p
}

fn db(a: f64, b: f64) -> f64 {
    20.0 * (a / b).log10()
}

#[test]
fn gear_mesh_sidebands_sit_at_the_second_shaft_rate() {
    let r = MachineRecipe::healthy(BearingGeometry::skf_6205(), 1500.0, 12_000.0, 4.0, 21)
        .unwrap()
        .with_nuisances(Nuisances::GEAR_MESH)
        .with_snr_db(40.0);
    let mut p = steady(r.draw().unwrap());
    p.gear_mesh.z1 = 30;
    p.gear_mesh.z2 = 47;
    p.gear_mesh.level_db = 10.0;
    p.gear_mesh.am_depth = [0.3, 0.3];
    let rec = p.synthesize().unwrap();
    let fr = 25.0;
    let fr2 = fr * 30.0 / 47.0; // 15.96 Hz: order 0.638, not an integer
    let mesh = 30.0 * fr;
    let (df, s) = spectrum(&rec.accel, rec.fs_hz);
    let floor = median_in(df, &s, mesh - 100.0, mesh + 100.0);
    for f in [mesh, mesh - fr2, mesh + fr2, mesh - fr, mesh + fr, fr2] {
        let a = peak_near(df, &s, f, 0.5);
        assert!(db(a, floor) > 20.0, "{f:.2} Hz only {:.1} dB", db(a, floor));
    }
    // and nothing at a sideband spacing the gears do not have
    let off = peak_near(df, &s, mesh + 0.5 * (fr + fr2), 0.5);
    assert!(
        db(off, floor) < 10.0,
        "{:.1} dB between sidebands",
        db(off, floor)
    );
}

#[test]
fn mains_lines_at_multiples_of_50_hz_and_pole_pass_sidebands() {
    let r = MachineRecipe::healthy(BearingGeometry::skf_6203(), 1000.0, 20_000.0, 4.0, 8)
        .unwrap()
        .with_nuisances(Nuisances::ELECTRICAL)
        .with_snr_db(40.0);
    let mut p = r.draw().unwrap();
    p.electrical.line_hz = 50.0;
    p.electrical.level_db = 10.0;
    p.electrical.pole_pass_hz = Some(3.0);
    p.electrical.pole_pass_depth = 0.5;
    let rec = p.synthesize().unwrap();
    let (df, s) = spectrum(&rec.accel, rec.fs_hz);
    let floor = median_in(df, &s, 20.0, 400.0);
    for k in 1..=7 {
        let a = peak_near(df, &s, 50.0 * k as f64, 0.5);
        assert!(
            db(a, floor) > 20.0,
            "{}×50 Hz only {:.1} dB",
            k,
            db(a, floor)
        );
    }
    for f in [97.0, 103.0] {
        let a = peak_near(df, &s, f, 0.5);
        assert!(db(a, floor) > 20.0, "{f} Hz only {:.1} dB", db(a, floor));
    }
    let a = peak_near(df, &s, 75.0, 0.5);
    assert!(db(a, floor) < 10.0, "75 Hz {:.1} dB", db(a, floor));
}

/// Envelope spectrum in the band of the mode the fault (or impact) rings.
fn envelope_of(rec: &bearing_model::machine::MachineRecording, mode: usize) -> (f64, Vec<f64>) {
    let f = rec.params.structure.modes[mode].freq_hz;
    let lo = (0.7 * f).max(200.0);
    let hi = (1.3 * f).min(0.49 * rec.fs_hz);
    envelope_spectrum(&rec.accel, rec.fs_hz, lo, hi)
}

/// A 6205 at 1800 rpm, 25.6 kHz, 5 s, SNR 30 dB, with a fault at 0 dB, its speed steady.
fn faulty_params(location: FaultLocation, seed: u64) -> MachineParams {
    let r = MachineRecipe::healthy(BearingGeometry::skf_6205(), 1800.0, 25_600.0, 5.0, seed)
        .unwrap()
        .with_snr_db(30.0)
        .with_fault(LocalizedFault {
            location,
            severity_db: 0.0,
        });
    steady(r.draw().unwrap())
}

fn faulty(location: FaultLocation, seed: u64) -> bearing_model::machine::MachineRecording {
    faulty_params(location, seed).synthesize().unwrap()
}

#[test]
fn outer_race_impacts_come_at_bpfo_unmodulated() {
    let rec = faulty(FaultLocation::Outer, 31);
    let fr = 30.0;
    let bpfo = BearingGeometry::skf_6205().orders().bpfo * fr;
    // the count: one impact per 1/BPFO on average (slip is zero-mean jitter)
    let want = 5.0 * bpfo;
    let got = rec.fault_impacts as f64;
    assert!(
        (got / want - 1.0).abs() < 0.03,
        "{got} impacts, {want} expected"
    );
    let f = rec.params.fault.unwrap();
    assert!(f.slip >= 0.01 && f.slip <= 0.02);
    let (df, e) = envelope_of(&rec, f.mode);
    let floor = median_in(df, &e, 20.0, 400.0);
    for h in 1..=2 {
        let a = peak_near(df, &e, h as f64 * bpfo, 0.01 * h as f64 * bpfo);
        assert!(db(a, floor) > 15.0, "BPFO×{h} only {:.1} dB", db(a, floor));
    }
    // no load-zone modulation: nothing at BPFO ± fr
    let side = peak_near(df, &e, bpfo + fr, 0.5);
    assert!(db(side, floor) < 10.0, "BPFO+fr {:.1} dB", db(side, floor));
}

/// A race defect is struck by each rolling element in turn, each with its own gain: the impacts
/// repeat once per element cycle, which puts lines at the orders of FTF on an outer race
/// (BPFO = Z·FTF) and of fr − FTF on an inner race (BPFI = Z·(fr − FTF)); with equal elements
/// those lines are not there.
#[test]
fn unequal_elements_put_the_element_cycle_in_a_race_fault_s_envelope() {
    let fr = 30.0;
    let o = BearingGeometry::skf_6205().orders();
    for (location, cycle, seed) in [
        (FaultLocation::Outer, o.ftf * fr, 34),
        (FaultLocation::Inner, (1.0 - o.ftf) * fr, 35),
    ] {
        let mut p = faulty_params(location, seed);
        let f = p.fault.as_mut().unwrap();
        assert_eq!(f.elements, 9, "{location:?}: the 6205's nine balls");
        f.slip = 0.002;
        // the cycle's orders below the fault rate (Z − 1 of them), off the shaft's orders (the
        // inner race's load zone puts lines there): their mean level over the floor, dB
        let orders: Vec<f64> = (1..9)
            .map(|k| k as f64 * cycle)
            .filter(|f| {
                let m = (f / fr).round();
                (f - m * fr).abs() > 1.0
            })
            .collect();
        let level = |spread: f64| {
            let mut q = p.clone();
            q.fault.as_mut().unwrap().element_spread = spread;
            let rec = q.synthesize().unwrap();
            let (df, e) = envelope_of(&rec, rec.params.fault.unwrap().mode);
            let floor = median_in(df, &e, 5.0, 300.0);
            orders
                .iter()
                .map(|&f| db(peak_near(df, &e, f, 0.3), floor))
                .sum::<f64>()
                / orders.len() as f64
        };
        let (unequal, equal) = (level(0.3), level(0.0));
        assert!(
            orders.len() >= 6 && unequal > 10.0 && unequal > equal + 6.0,
            "{location:?}: the element cycle's orders {unequal:.1} dB with unequal elements, \
             {equal:.1} dB with equal ones"
        );
    }
}

#[test]
fn inner_race_impacts_are_modulated_once_per_turn() {
    let rec = faulty(FaultLocation::Inner, 32);
    let fr = 30.0;
    let bpfi = BearingGeometry::skf_6205().orders().bpfi * fr;
    let f = rec.params.fault.unwrap();
    let (df, e) = envelope_of(&rec, f.mode);
    let floor = median_in(df, &e, 20.0, 400.0);
    for line in [bpfi, bpfi - fr, bpfi + fr, fr] {
        let a = peak_near(df, &e, line, 0.01 * bpfi);
        assert!(
            db(a, floor) > 10.0,
            "{line:.1} Hz only {:.1} dB",
            db(a, floor)
        );
    }
}

#[test]
fn ball_impacts_are_modulated_at_the_cage_rate() {
    let rec = faulty(FaultLocation::Ball, 33);
    let fr = 30.0;
    let o = BearingGeometry::skf_6205().orders();
    let (bsf, ftf) = (o.ball_defect * fr, o.ftf * fr);
    let f = rec.params.fault.unwrap();
    let (df, e) = envelope_of(&rec, f.mode);
    let floor = median_in(df, &e, 20.0, 400.0);
    for line in [bsf, bsf - ftf, bsf + ftf, ftf] {
        let a = peak_near(df, &e, line, 0.3);
        assert!(
            db(a, floor) > 10.0,
            "{line:.1} Hz only {:.1} dB",
            db(a, floor)
        );
    }
}

#[test]
fn once_per_rev_impacts_put_every_shaft_order_in_the_envelope() {
    let r = MachineRecipe::healthy(BearingGeometry::skf_6205(), 1500.0, 12_000.0, 4.0, 41)
        .unwrap()
        .with_nuisances(Nuisances::ONCE_PER_REV)
        .with_snr_db(30.0);
    let mut p = steady(r.draw().unwrap());
    p.once_per_rev.level_db = 0.0;
    p.once_per_rev.jitter_fraction = 0.002;
    let rec = p.synthesize().unwrap();
    let (df, e) = envelope_of(&rec, rec.params.once_per_rev.mode);
    let floor = median_in(df, &e, 10.0, 200.0);
    for k in 1..=4 {
        let a = peak_near(df, &e, 25.0 * k as f64, 0.5);
        assert!(db(a, floor) > 15.0, "{k}× only {:.1} dB", db(a, floor));
    }
}

/// Another shaft's impacts put a comb at its non-integer order in the envelope, and nothing at
/// the measured shaft's orders; adding them leaves every other component's samples alone.
#[test]
fn other_shaft_impacts_put_a_comb_at_its_order_in_the_envelope() {
    let r = MachineRecipe::healthy(BearingGeometry::skf_6205(), 1500.0, 12_000.0, 4.0, 42)
        .unwrap()
        .with_snr_db(30.0);
    let base = steady(r.draw().unwrap());
    let mut p = steady(r.with_nuisances(Nuisances::OTHER_SHAFT).draw().unwrap());
    assert_eq!(p.structure, base.structure);
    let o = p.other_shaft.order;
    assert!(
        (0.3..=9.0).contains(&o) && (o - o.round()).abs() >= 0.1,
        "order {o}"
    );
    p.other_shaft.level_db = 0.0;
    p.other_shaft.order = 3.37;
    p.other_shaft.jitter_fraction = 0.002;
    let rec = p.synthesize().unwrap();
    assert!(rec.rms.other_shaft > 0.0 && rec.rms.once_per_rev == 0.0);
    let (df, e) = envelope_of(&rec, rec.params.other_shaft.mode);
    // against the envelope's own background around each line (a narrow mode's envelope rises
    // towards 0 Hz whatever it holds)
    let over = |f: f64| {
        db(
            peak_near(df, &e, f, 0.5),
            median_in(df, &e, f - 12.0, f + 12.0),
        )
    };
    for k in 1..=2 {
        let f = 25.0 * 3.37 * k as f64;
        assert!(over(f) > 15.0, "{k}× only {:.1} dB", over(f));
    }
    for k in 1..=3 {
        let f = 25.0 * k as f64;
        assert!(over(f) < 10.0, "shaft {k}× {:.1} dB", over(f));
    }
    assert_eq!(Nuisances::EVERY.label(), "all+other-shaft");
    assert_eq!(Nuisances::OTHER_SHAFT.label(), "other-shaft");
}

#[test]
fn shaft_comb_has_integer_and_half_orders() {
    let r = MachineRecipe::healthy(BearingGeometry::skf_6205(), 1200.0, 12_000.0, 4.0, 51)
        .unwrap()
        .with_nuisances(Nuisances::SHAFT_COMB)
        .with_snr_db(40.0);
    let mut p = steady(r.draw().unwrap());
    p.shaft_comb.level_db = 10.0;
    p.shaft_comb.lines.retain(|l| l.multiple.fract() == 0.0);
    for j in 0..3 {
        p.shaft_comb.lines.push(bearing_model::machine::OrderTone {
            multiple: j as f64 + 0.5,
            amplitude: 0.3,
            phase_rad: 0.0,
        });
    }
    let rec = p.synthesize().unwrap();
    let fr = 20.0;
    let (df, s) = spectrum(&rec.accel, rec.fs_hz);
    let floor = median_in(df, &s, 5.0, 200.0);
    for order in [0.5, 1.0, 1.5, 2.0, 2.5, 3.0] {
        let a = peak_near(df, &s, order * fr, 0.3);
        assert!(
            db(a, floor) > 20.0,
            "order {order} only {:.1} dB",
            db(a, floor)
        );
    }
}

#[test]
fn a_tiny_corpus_is_the_same_run_to_run() {
    // three recordings of different kinds, made twice
    let g = BearingGeometry::from_dimensions(8, 7.938e-3, 33.5e-3, 0.0).unwrap();
    let make = || {
        let a = MachineRecipe::healthy(g, 1000.0, 20_000.0, 1.0, 100)
            .unwrap()
            .with_nuisances(Nuisances::ALL)
            .with_snr_db(0.0)
            .synthesize()
            .unwrap();
        let b = MachineRecipe::noise_only(
            g,
            600.0,
            51_200.0,
            0.5,
            bearing_model::machine::Adc {
                bits: 24,
                full_scale_ms2: 500.0,
            },
            3.0,
            101,
        )
        .unwrap()
        .synthesize()
        .unwrap();
        let c = MachineRecipe::healthy(g, 3000.0, 48_000.0, 1.0, 102)
            .unwrap()
            .with_nuisances(Nuisances::GEAR_MESH)
            .with_fault(LocalizedFault {
                location: FaultLocation::Ball,
                severity_db: -20.0,
            })
            .synthesize()
            .unwrap();
        [a.accel, b.accel, c.accel]
    };
    let (x, y) = (make(), make());
    for (a, b) in x.iter().zip(&y) {
        assert_eq!(a.len(), b.len());
        assert!(a.iter().zip(b).all(|(u, v)| u.to_bits() == v.to_bits()));
    }
}
