//! Named scenarios: one-liners for CWRU-like recordings and the SHSE multi-fault substitute.
//!
//! ```
//! use bearing_model::{FaultClass, Scenario};
//! // 6205 at 1797 rpm, 0.007 in inner-race spall, 12 kHz, 0.05 s:
//! let rec = Scenario::cwru(FaultClass::Inner, 0.007, 1797.0)?.with_duration(0.05).simulate()?;
//! // SHSE substitute: inner+outer+ball, 3 mm cracks, 500 rpm:
//! let shse = Scenario::shse(FaultClass::InnerOuterBall, 3.0, 500.0)?.with_duration(0.05);
//! assert!(shse.spec.faults.inner.is_some() && shse.spec.faults.ball.is_some());
//! # Ok::<(), bearing_model::ModelError>(())
//! ```

use crate::error::{Result, check_positive};
use crate::fault::{FaultClass, FaultSet, Spall};
use crate::geometry::Bearing;
use crate::params::{Housing, ModelSpec, ParamSet, ShaftHarmonic, Slip, Uncertainty};
use crate::simulate::{Noise, SimConfig, SimulatedRecording, simulate};
use crate::state_space::BearingModel;

/// CWRU EDM spall depth: 0.011 in.
pub const CWRU_DEPTH_M: f64 = 0.011 * 0.0254;
/// Depth assumed for the SHSE cracks (not given in the dissertation): 0.5 mm.
pub const SHSE_DEPTH_M: f64 = 0.5e-3;

/// A model spec plus how to sample it.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The bearing model.
    pub spec: ModelSpec,
    /// Sampling, duration, noise.
    pub sim: SimConfig,
}

impl Scenario {
    /// A healthy bearing from a parameter set at `rpm`: 12 kHz, 1 s, no slip, no noise.
    pub fn new(set: ParamSet, bearing: Bearing, rpm: f64) -> Self {
        Self {
            spec: ModelSpec::from_set(set, bearing.geometry(), rpm),
            sim: SimConfig::new(12_000.0, 1.0),
        }
    }

    /// CWRU-like drive-end recording: SKF 6205, [`ParamSet::CwruRig`], spall width
    /// `fault_size_in` inches (0.007 / 0.014 / 0.021) at depth 0.011 in on every location the
    /// class names (outer race at 6 o'clock), 12 kHz, 1 s, 1 % slip, no noise.
    pub fn cwru(class: FaultClass, fault_size_in: f64, rpm: f64) -> Result<Self> {
        check_positive("fault_size_in", fault_size_in)?;
        check_positive("rpm", rpm)?;
        let mut s = Self::new(ParamSet::CwruRig, Bearing::Skf6205, rpm);
        s.spec.faults = FaultSet::of_class(
            class,
            Spall::new(fault_size_in * 0.0254).with_depth(CWRU_DEPTH_M),
        );
        s.spec.slip = Slip::Random { fraction: 0.01 };
        s.spec.validate()?;
        Ok(s)
    }

    /// Substitute for the private SHSE multi-fault data (Table 4.1): 8 classes, 300–500 rpm,
    /// 3 or 6 mm cracks. Table 4.1 gives no bearing geometry, so the SKF 6205 is used;
    /// [`ParamSet::CwruRig`], crack depth [`SHSE_DEPTH_M`], 12 kHz, 1 s, 1.5 % slip, noise at
    /// 20 dB SNR.
    pub fn shse(class: FaultClass, crack_mm: f64, rpm: f64) -> Result<Self> {
        check_positive("crack_mm", crack_mm)?;
        check_positive("rpm", rpm)?;
        let mut s = Self::new(ParamSet::CwruRig, Bearing::Skf6205, rpm);
        s.spec.faults =
            FaultSet::of_class(class, Spall::new(crack_mm * 1e-3).with_depth(SHSE_DEPTH_M));
        s.spec.slip = Slip::Random { fraction: 0.015 };
        s.sim.noise = Noise::SnrDb(20.0);
        s.spec.validate()?;
        Ok(s)
    }

    /// Output sampling rate, Hz.
    pub fn with_fs(mut self, fs_hz: f64) -> Self {
        self.sim.fs_hz = fs_hz;
        self
    }
    /// Recorded duration, s.
    pub fn with_duration(mut self, duration_s: f64) -> Self {
        self.sim.duration_s = duration_s;
        self
    }
    /// Seed of slip, uncertainty and noise.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.spec.seed = seed;
        self.sim.seed = seed;
        self
    }
    /// Measurement noise.
    pub fn with_noise(mut self, noise: Noise) -> Self {
        self.sim.noise = noise;
        self
    }
    /// Slip of the rolling elements.
    pub fn with_slip(mut self, slip: Slip) -> Self {
        self.spec.slip = slip;
        self
    }
    /// Seeded ΔM, ΔC, ΔK.
    pub fn with_uncertainty(mut self, u: Uncertainty) -> Self {
        self.spec.uncertainty = u;
        self
    }
    /// Radial load on the shaft (down), N.
    pub fn with_radial_load(mut self, n: f64) -> Self {
        self.spec.radial_load_n = n;
        self
    }
    /// Add a rotating shaft force (unbalance order 1, misalignment order 2).
    pub fn with_harmonic(mut self, h: ShaftHarmonic) -> Self {
        self.spec.harmonics.push(h);
        self
    }
    /// Constant speed ratio (e.g. 1.0033).
    pub fn with_speed_ratio(mut self, ratio: f64) -> Self {
        self.spec.speed.ratio = ratio;
        self
    }
    /// Housing resonance (sprung mass).
    pub fn with_housing(mut self, h: Housing) -> Self {
        self.spec.housing = h;
        self
    }
    /// Fault onset time `T_f` for every spall, s; [`Scenario::simulate`] refuses one outside
    /// `[0, duration)` ([`crate::fault::check_onset`]).
    pub fn with_fault_onset(mut self, onset_s: f64) -> Self {
        for s in [
            &mut self.spec.faults.inner,
            &mut self.spec.faults.outer,
            &mut self.spec.faults.ball,
        ]
        .into_iter()
        .flatten()
        {
            s.onset_s = onset_s;
        }
        self
    }
    /// Record all ten states too.
    pub fn with_states(mut self, on: bool) -> Self {
        self.sim.record_states = on;
        self
    }
    /// Build the model.
    pub fn model(&self) -> Result<BearingModel> {
        BearingModel::new(&self.spec)
    }
    /// Build and simulate.
    pub fn simulate(&self) -> Result<SimulatedRecording> {
        simulate(&self.model()?, &self.sim)
    }
}
