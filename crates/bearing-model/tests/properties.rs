//! Property tests: for random valid parameters the simulation stays finite and every ball's
//! contact force is non-negative (eq. 2.9 with the Heaviside gate of eq. 2.10).

use bearing_model::*;
use proptest::prelude::*;

fn class_strategy() -> impl Strategy<Value = FaultClass> {
    (0usize..8).prop_map(|i| FaultClass::ALL[i])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn simulation_is_finite_and_contact_forces_non_negative(
        set in prop_oneof![Just(ParamSet::CwruRig), Just(ParamSet::Table21)],
        class in class_strategy(),
        rpm in 100.0f64..3600.0,
        width_mm in 0.05f64..3.0,
        depth_mm in 0.01f64..2.0,
        slip in prop_oneof![Just(Slip::Off), (0.005f64..0.03).prop_map(|f| Slip::Random { fraction: f })],
        mass_scale in 0.5f64..2.0,
        stiff_scale in 0.5f64..2.0,
        load in 0.0f64..2000.0,
        clearance_um in 0.0f64..10.0,
        res_hz in 1000.0f64..5000.0,
        seed in 0u64..1000,
    ) {
        let mut sc = Scenario::new(set, Bearing::Skf6205, rpm)
            .with_slip(slip)
            .with_radial_load(load)
            .with_duration(0.02)
            .with_states(true)
            .with_seed(seed)
            .with_uncertainty(Uncertainty { mass: 0.1, damping: 0.1, stiffness: 0.1 });
        sc.spec.faults = FaultSet::of_class(class, Spall::new(width_mm * 1e-3).with_depth(depth_mm * 1e-3));
        sc.spec.structure.shaft_mass_kg *= mass_scale;
        sc.spec.structure.pedestal_mass_kg *= mass_scale;
        sc.spec.structure.shaft_stiffness_n_m *= stiff_scale;
        sc.spec.contact.clearance_m = clearance_um * 1e-6;
        sc.spec.housing.resonance_hz = res_hz;
        sc.sim.settle_s = 0.01;
        let m = sc.model().unwrap();
        let r = simulate(&m, &sc.sim).unwrap();
        prop_assert!(r.accel.iter().all(|a| a.is_finite()));
        let mut q = vec![0.0; m.n_balls()];
        for (k, x) in r.states.as_ref().unwrap().iter().enumerate() {
            prop_assert!(x.iter().all(|v| v.is_finite()));
            m.ball_loads(r.time(k), x, &mut q);
            prop_assert!(q.iter().all(|&f| f >= 0.0 && f.is_finite()));
        }
    }
}

/// A class is the set of its locations: `locations` and `from_locations` are inverse, the name
/// parses back to the class, and single locations name their single-location class.
#[test]
fn a_fault_class_is_the_set_of_its_locations() {
    for class in FaultClass::ALL {
        let locs = class.locations();
        assert_eq!(FaultClass::from_locations(&locs), class);
        if class != FaultClass::None {
            assert_eq!(class.name().parse::<FaultClass>().unwrap(), class);
        }
        let mut reversed = locs.clone();
        reversed.reverse();
        reversed.extend(locs.iter().copied());
        assert_eq!(
            FaultClass::from_locations(&reversed),
            class,
            "order and repeats ignored"
        );
    }
    for l in FaultLocation::ALL {
        assert_eq!(l.class().locations(), vec![l]);
        assert_eq!(l.name(), l.class().name());
    }
    assert!("inner+cage".parse::<FaultClass>().is_err());
    assert!("".parse::<FaultClass>().is_err());
}
