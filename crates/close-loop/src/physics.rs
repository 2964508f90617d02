//! The 5-DOF physics model of `bearing-model` (Sawalhi & Randall 2008; dissertation eqs. 2.1–2.25)
//! as a [`DeclaredModel`]: the declared speed, bearing and fault go in, the housing acceleration
//! comes out (no measurement noise: the loop fits the channel's white floor itself).

use crate::{CloseLoopError, DeclaredModel, OperatingPoint};
use bearing_model::{
    Bearing, FaultClass, FaultLocation, FaultSet, Housing, Noise, ParamSet, Scenario,
    ShaftHarmonic, Slip, Spall,
};

/// Relative tolerance of the loop's 5-DOF simulations ([`bearing_model::Integrator::Adaptive`],
/// atol the default's), ten times the simulator's default (2e-6, which holds the output within
/// 1e-3 relative RMS of the 5 µs RK4 reference). The loop scores a model by a log-spectral
/// distance whose floor sits 30 dB below the mean PSD ([`crate::LoopConfig::floor_db`]) and
/// keeps an effect only when it lowers that distance by ≥ 0.03 dB and 2 %. At 2e-5 the output
/// differs from the default's by at most 1.5e-3 relative RMS and the two Welch PSDs by at most
/// 0.013 dB on that metric — healthy, inner, outer, ball and inner+outer+ball spalls, 300 and
/// 1797 rpm, 12 and 48 kHz, with and without slip and preload (`examples/loop_tolerance.rs`) —
/// for 1.1–1.6× fewer steps. 2e-4 would save 1.2–2.5× but moves a healthy model at 300 rpm by
/// 1.3 dB (its varying-compliance vibration is small beside the start-up transient the
/// tolerance is relative to).
pub const LOOP_RTOL: f64 = 2e-5;

/// Declared 5-DOF physics model.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsModel {
    /// Parameter set (default [`ParamSet::CwruRig`]).
    pub set: ParamSet,
    /// Bearing (geometry of the simulator; keep it consistent with the operating point's rates).
    pub bearing: Bearing,
    /// Spall width, inches (CWRU sizes 0.007 / 0.014 / 0.021).
    pub fault_size_in: f64,
    /// Random slip fraction (0 = off; default 0.01, as `cargo xtask simulate`: slip of 1–2 % is
    /// usual, references.md).
    pub slip_fraction: f64,
    /// Housing resonance override (`None` = the parameter set's).
    pub housing: Option<Housing>,
    /// Shaft forces the model already declares (unbalance, misalignment).
    pub harmonics: Vec<ShaftHarmonic>,
    /// Seed of slip draws.
    pub seed: u64,
    /// Radial clearance of every ball, m (negative: a preload, the load zone spanning the whole
    /// circumference); `None` = the parameter set's (0 for [`ParamSet::CwruRig`]).
    pub clearance_m: Option<f64>,
    /// Spalls beyond the declared fault (location, width in inches), each at a location the
    /// declared fault leaves healthy: faults the loop found that nobody declared
    /// ([`DeclaredModel::with_added_fault`]).
    pub added_faults: Vec<(FaultLocation, f64)>,
    /// A bearing given by its dimensions, simulated instead of `bearing`'s geometry (balls,
    /// cage and defect kinematics; the parameter set's structure, housing and contact stay, as
    /// for the 6203: `docs/equations/bearing-model.md`, "Other geometries"); `None`: `bearing`'s.
    pub geometry: Option<bearing_model::BearingGeometry>,
}

impl Default for PhysicsModel {
    fn default() -> Self {
        Self {
            set: ParamSet::CwruRig,
            bearing: Bearing::Skf6205,
            fault_size_in: 0.007,
            slip_fraction: 0.01,
            housing: None,
            harmonics: Vec::new(),
            seed: 1,
            clearance_m: None,
            added_faults: Vec::new(),
            geometry: None,
        }
    }
}

impl PhysicsModel {
    /// The default model for the bearing `spec` names: a built-in bearing by its designation,
    /// any other by its geometry; `None` for a bearing given by its four fault multiples only
    /// (they do not place balls).
    pub fn for_bearing(spec: &crate::BearingSpec) -> Option<Self> {
        let named = [spec.name.as_str(), spec.given.as_str()]
            .into_iter()
            .find_map(|s| s.parse::<Bearing>().ok());
        match (named, spec.geometry) {
            (Some(bearing), _) => Some(Self {
                bearing,
                ..Self::default()
            }),
            (None, Some(g)) => Some(Self {
                geometry: Some(g),
                ..Self::default()
            }),
            (None, None) => None,
        }
    }

    /// The scenario simulated for `op`, `n` samples at `fs`.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] with the simulator's message.
    pub fn scenario(
        &self,
        op: &OperatingPoint,
        n: usize,
        fs: f64,
    ) -> Result<Scenario, CloseLoopError> {
        let class = op.fault;
        let mut s = Scenario::new(self.set, self.bearing, op.rpm)
            .with_fs(fs)
            .with_duration(n as f64 / fs)
            .with_noise(Noise::Off)
            .with_seed(self.seed);
        if let Some(g) = self.geometry {
            s.spec.geometry = g;
        }
        let spall = |size_in: f64| {
            Spall::new(size_in * 0.0254).with_depth(bearing_model::scenario::CWRU_DEPTH_M)
        };
        if class != FaultClass::None {
            s.spec.faults = FaultSet::of_class(class, spall(self.fault_size_in));
        }
        for &(location, size_in) in &self.added_faults {
            let one = FaultSet::of_class(location.class(), spall(size_in));
            let f = &mut s.spec.faults;
            f.inner = f.inner.or(one.inner);
            f.outer = f.outer.or(one.outer);
            f.ball = f.ball.or(one.ball);
        }
        if self.slip_fraction > 0.0 {
            s = s.with_slip(Slip::Random {
                fraction: self.slip_fraction,
            });
        }
        if let Some(h) = self.housing {
            s = s.with_housing(h);
        }
        for h in &self.harmonics {
            s = s.with_harmonic(*h);
        }
        if let Some(c) = self.clearance_m {
            s.spec.contact.clearance_m = c;
        }
        s.sim.integrator = bearing_model::Integrator::adaptive(LOOP_RTOL);
        s.spec.validate().map_err(|e| CloseLoopError::Model {
            reason: e.to_string(),
        })?;
        Ok(s)
    }
}

impl PhysicsModel {
    /// The housing (measured-channel) mode the model uses: the override or the parameter set's.
    pub fn effective_housing(&self) -> Housing {
        self.housing
            .unwrap_or_else(|| Scenario::new(self.set, self.bearing, 1797.0).spec.housing)
    }
}

impl DeclaredModel for PhysicsModel {
    fn name(&self) -> &str {
        "physics-5dof"
    }

    /// Every field, floats at full (round-trip) precision: equal keys, equal simulations (the
    /// simulation is seeded by `seed`).
    fn cache_key(&self) -> Option<String> {
        Some(format!("{self:?}"))
    }

    fn residual_observer(&self, _fs: f64) -> crate::observe::ResidualObserver {
        let h = self.effective_housing();
        crate::observe::ResidualObserver::Physics {
            natural_frequency_hz: h.resonance_hz,
            damping_ratio: h.damping_ratio,
        }
    }

    fn with_shaft_force(
        &self,
        order: u32,
        amplitude_n: f64,
        phase_rad: f64,
    ) -> Option<Box<dyn DeclaredModel>> {
        let mut m = self.clone();
        m.harmonics.push(ShaftHarmonic {
            order,
            amplitude_n,
            phase_rad,
        });
        Some(Box::new(m))
    }

    fn with_housing_mode(
        &self,
        frequency_hz: f64,
        damping_ratio: f64,
    ) -> Option<Box<dyn DeclaredModel>> {
        let mut m = self.clone();
        m.housing = Some(Housing {
            resonance_hz: frequency_hz,
            damping_ratio,
            ..self.effective_housing()
        });
        Some(Box::new(m))
    }

    /// The ratio of the moved and the present model's linearised responses to a contact
    /// force (`bearing_model::BearingModel::contact_force_response`): the impacts drive the
    /// structure as a force source and the housing mode is a linear part of it, so the ratio is
    /// how the simulated PSD changes (0.01–0.03 dB RMS on the CWRU rig, the crate's test).
    fn housing_response(
        &self,
        op: &OperatingPoint,
        fs: f64,
        moved_to: Option<(f64, f64)>,
        freqs_hz: &[f64],
    ) -> Option<Vec<f64>> {
        let moved;
        let model = match moved_to {
            Some((resonance_hz, damping_ratio)) => {
                moved = Self {
                    housing: Some(Housing {
                        resonance_hz,
                        damping_ratio,
                        ..self.effective_housing()
                    }),
                    ..self.clone()
                };
                &moved
            }
            None => self,
        };
        model
            .scenario(op, 1, fs)
            .ok()?
            .model()
            .ok()?
            .contact_force_response(freqs_hz)
            .ok()
    }

    fn slip_fraction(&self) -> Option<f64> {
        Some(self.slip_fraction)
    }

    fn fault_size_in(&self) -> Option<f64> {
        Some(self.fault_size_in)
    }

    fn with_fault_size_in(&self, size_in: f64) -> Option<Box<dyn DeclaredModel>> {
        (size_in.is_finite() && size_in > 0.0).then(|| {
            let mut m = self.clone();
            m.fault_size_in = size_in;
            Box::new(m) as Box<dyn DeclaredModel>
        })
    }

    fn added_faults(&self) -> Vec<(FaultLocation, f64)> {
        self.added_faults.clone()
    }

    fn with_added_fault(
        &self,
        location: FaultLocation,
        size_in: f64,
    ) -> Option<Box<dyn DeclaredModel>> {
        let taken = self.added_faults.iter().any(|(l, _)| *l == location);
        (size_in.is_finite() && size_in > 0.0 && !taken).then(|| {
            let mut m = self.clone();
            m.added_faults.push((location, size_in));
            Box::new(m) as Box<dyn DeclaredModel>
        })
    }

    fn max_slip_fraction(&self) -> Option<f64> {
        Some(bearing_model::params::MAX_SLIP_FRACTION)
    }

    fn with_slip_fraction(&self, fraction: f64) -> Option<Box<dyn DeclaredModel>> {
        let mut m = self.clone();
        m.slip_fraction = fraction;
        Some(Box::new(m))
    }

    fn contact_preload_m(&self) -> Option<f64> {
        let c = self.clearance_m.unwrap_or_else(|| {
            Scenario::new(self.set, self.bearing, 1797.0)
                .spec
                .contact
                .clearance_m
        });
        Some((-c).max(0.0))
    }

    fn with_contact_preload(&self, preload_m: f64) -> Option<Box<dyn DeclaredModel>> {
        (preload_m.is_finite() && preload_m >= 0.0).then(|| {
            let mut m = self.clone();
            m.clearance_m = Some(-preload_m);
            Box::new(m) as Box<dyn DeclaredModel>
        })
    }

    fn housing_mode(&self) -> Option<(f64, f64)> {
        let h = self.effective_housing();
        Some((h.resonance_hz, h.damping_ratio))
    }

    fn simulate(&self, op: &OperatingPoint, n: usize, fs: f64) -> Result<Vec<f64>, CloseLoopError> {
        let rec = self
            .scenario(op, n, fs)?
            .simulate()
            .map_err(|e| CloseLoopError::Model {
                reason: e.to_string(),
            })?;
        let mut y = rec.accel;
        y.resize(n, 0.0);
        Ok(y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loop's simulation memo is keyed on `cache_key`: equal for equal models (and their
    /// simulations are equal), different whenever a parameter or the seed differs.
    #[test]
    fn cache_key_tells_models_apart_exactly() {
        let m = PhysicsModel::default();
        assert_eq!(m.cache_key(), m.clone().cache_key());
        let op = OperatingPoint::new(
            1797.0,
            crate::BearingSpec::designated(bearing_model::Bearing::Skf6205),
            crate::DeclaredFault::Inner,
        )
        .unwrap();
        let (a, b) = (
            m.simulate(&op, 2048, 12_000.0).unwrap(),
            m.clone().simulate(&op, 2048, 12_000.0).unwrap(),
        );
        assert_eq!(a, b);
        let slipped = m.with_slip_fraction(m.slip_fraction * 0.5).unwrap();
        assert_ne!(m.cache_key(), slipped.cache_key());
        let reseeded = PhysicsModel {
            seed: m.seed + 1,
            ..m.clone()
        };
        assert_ne!(m.cache_key(), reseeded.cache_key());
        let moved = m.with_housing_mode(3000.0, 0.05).unwrap();
        assert_ne!(m.cache_key(), moved.cache_key());
        let added = m.with_added_fault(FaultLocation::Outer, 0.014).unwrap();
        assert_ne!(m.cache_key(), added.cache_key());
    }

    /// A built-in bearing is simulated by its designation, another by its geometry (its balls
    /// in the scenario, its key apart), the four multiples alone not at all.
    #[test]
    fn a_bearing_is_simulated_by_its_designation_or_its_geometry() {
        let b6205 = PhysicsModel::for_bearing(&crate::BearingSpec::parse("6205").unwrap()).unwrap();
        assert_eq!((b6205.bearing, b6205.geometry), (Bearing::Skf6205, None));
        let b6203 = PhysicsModel::for_bearing(&crate::BearingSpec::designated(Bearing::Skf6203));
        assert_eq!(b6203.unwrap().bearing, Bearing::Skf6203);
        let spec = crate::BearingSpec::parse("n=8,d=0.235in,D=1.245in,angle=0deg").unwrap();
        let nice = PhysicsModel::for_bearing(&spec).unwrap();
        assert_ne!(nice.cache_key(), PhysicsModel::default().cache_key());
        let op = OperatingPoint::new(1500.0, spec, FaultClass::Outer).unwrap();
        let s = nice.scenario(&op, 2048, 12_000.0).unwrap();
        assert_eq!(s.spec.geometry.n_balls, 8);
        assert!((s.spec.geometry.orders().bpfo - op.bearing.orders.bpfo).abs() < 1e-12);
        let multiples = crate::BearingSpec::parse("bpfo=3.245,bpfi=4.755,ftf=0.4056,bsf=5.109");
        assert!(PhysicsModel::for_bearing(&multiples.unwrap()).is_none());
    }

    /// A fault nobody declared is a second spall in the simulated scenario (the declared one
    /// kept), once per location, with a positive finite width; the simulation is that of the
    /// two-fault class.
    #[test]
    fn an_added_fault_is_a_spall_beside_the_declared_one() {
        let m = PhysicsModel::default();
        assert!(m.with_added_fault(FaultLocation::Ball, 0.0).is_none());
        assert!(m.with_added_fault(FaultLocation::Ball, f64::NAN).is_none());
        let mut added = m.clone();
        added
            .added_faults
            .push((FaultLocation::Inner, m.fault_size_in));
        assert!(
            added
                .with_added_fault(FaultLocation::Inner, 0.014)
                .is_none()
        );
        let op = |fault| {
            OperatingPoint::new(
                1797.0,
                crate::BearingSpec::designated(bearing_model::Bearing::Skf6205),
                fault,
            )
            .unwrap()
        };
        let s = added
            .scenario(&op(FaultClass::Outer), 2048, 12_000.0)
            .unwrap();
        assert!(s.spec.faults.inner.is_some() && s.spec.faults.outer.is_some());
        assert!(s.spec.faults.ball.is_none());
        assert_eq!(
            added
                .simulate(&op(FaultClass::Outer), 2048, 12_000.0)
                .unwrap(),
            m.simulate(&op(FaultClass::InnerOuter), 2048, 12_000.0)
                .unwrap()
        );
    }
}
