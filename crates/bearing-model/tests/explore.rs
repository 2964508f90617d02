mod common;
use bearing_model::*;
use common::*;

#[test]
fn explore() {
    for set in [ParamSet::CwruRig, ParamSet::Table21] {
        let sc = Scenario::new(set, Bearing::Skf6205, 1797.0);
        let m = sc.model().unwrap();
        let x = m.static_equilibrium(0.0).unwrap();
        let mut q = vec![0.0; 9];
        m.ball_loads(0.0, &x, &mut q);
        println!("{set:?} eq {:?}\n loads {:?}\n omega_max {}", x.fixed_rows::<5>(0).transpose(), q, m.max_omega(0.0, &x));
    }
    let fr = 1797.0 / 60.0;
    let o = BearingGeometry::skf_6205().orders().at(fr);
    println!("{o:?}");
    for class in [FaultClass::None, FaultClass::Outer, FaultClass::Inner, FaultClass::Ball] {
        let t = std::time::Instant::now();
        let r = Scenario::cwru(class, 0.007, 1797.0).unwrap().with_slip(Slip::Off).with_duration(1.0).simulate().unwrap();
        let el = t.elapsed();
        let (df, e) = envelope_spectrum(&r.accel, r.fs_hz, 2000.0, 5000.0);
        println!("{class}: rms {:.4} max {:.4} t {:?} peak@{:.2} bpfo {:.3e} bpfi {:.3e} bdf {:.3e} ftf {:.3e} fr {:.3e} med {:.3e}",
          rms(&r.accel), r.accel.iter().cloned().fold(0.0f64, |a,b| a.max(b.abs())), el,
          argmax_in(df,&e,5.0,600.0), peak_near(df,&e,o.bpfo,1.0), peak_near(df,&e,o.bpfi,1.0), peak_near(df,&e,o.ball_defect,1.0), peak_near(df,&e,o.ftf,1.0), peak_near(df,&e,fr,1.0), median_in(df,&e,5.0,600.0));
    }
}
#[test]
fn explore_steps() {
    for step in [20e-6, 10e-6, 5e-6, 2.5e-6, 1.25e-6] {
        let mut sc = Scenario::cwru(FaultClass::InnerOuterBall, 0.014, 1797.0).unwrap().with_duration(0.15);
        sc.sim.max_step_s = step;
        let r = sc.simulate().unwrap();
        println!("step {:.3e} rms {:.6e} first {:?}", r.step_s, rms(&r.accel), &r.accel[1000..1003]);
    }
}
#[test]
fn explore_healthy() {
    let r = Scenario::cwru(FaultClass::None, 0.014, 1797.0).unwrap().simulate().unwrap();
    for (lo, hi) in [(0.0, 6000.0), (2000.0, 5000.0)] {
        let (df, e) = envelope_spectrum(&r.accel, r.fs_hz, lo, hi);
        let med = median_in(df, &e, 5.0, 600.0);
        let mut idx: Vec<usize> = (5..600).collect();
        idx.sort_by(|&a, &b| e[b].partial_cmp(&e[a]).unwrap());
        println!("band {lo}-{hi}: med {med:.3e} top: {:?}", idx[..12].iter().map(|&k| (k as f64 * df, e[k] / med)).collect::<Vec<_>>());
    }
}
