//! Model parameters: Table 2.1 as printed, a physically consistent CWRU set, and the optional
//! effects other crates add (shaft harmonics, speed offset, uncertainty ΔM/ΔC/ΔK, slip).
//!
//! Everything is a plain documented struct; [`ModelSpec::validate`] checks it once, and
//! [`crate::BearingModel::new`] refuses an invalid spec.

use crate::error::{ModelError, Result, check_positive, check_range};
use crate::fault::FaultSet;
use crate::geometry::BearingGeometry;
use std::f64::consts::PI;

/// Standard gravity, m/s².
pub const G: f64 = 9.80665;

/// Shaft/inner race and pedestal/outer race masses, stiffnesses and dampings (eqs. 2.12–2.13).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Structure {
    /// Shaft + inner race mass `M_S`, kg.
    pub shaft_mass_kg: f64,
    /// Shaft support stiffness `K_S` (per direction), N/m.
    pub shaft_stiffness_n_m: f64,
    /// Shaft damping `C_S`, N·s/m.
    pub shaft_damping_ns_m: f64,
    /// Pedestal + outer race mass `M_P`, kg.
    pub pedestal_mass_kg: f64,
    /// Pedestal stiffness to ground `K_P`, N/m.
    pub pedestal_stiffness_n_m: f64,
    /// Pedestal damping `C_P`, N·s/m.
    pub pedestal_damping_ns_m: f64,
}

/// The sprung mass of eq. (2.14): a housing resonance on the pedestal, vertical only.
/// Its acceleration is what the accelerometer measures.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Housing {
    /// Sprung mass `M_R`, kg.
    pub mass_kg: f64,
    /// Resonance frequency `√(K_R/M_R)/2π`, Hz.
    pub resonance_hz: f64,
    /// Damping ratio `C_R / (2 √(K_R M_R))`.
    pub damping_ratio: f64,
}

impl Housing {
    /// `K_R = M_R (2π f)²`.
    pub fn stiffness(&self) -> f64 {
        let w = 2.0 * PI * self.resonance_hz;
        self.mass_kg * w * w
    }
    /// `C_R = 2 ζ M_R (2π f)`.
    pub fn damping(&self) -> f64 {
        2.0 * self.damping_ratio * self.mass_kg * 2.0 * PI * self.resonance_hz
    }
}

/// Hertzian ball contact, eqs. (2.9)–(2.11): `Q = k_b · max(δ, 0)^1.5` per ball.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Contact {
    /// Load–deflection constant `k_b` (the dissertation's `C_P`), N/m^1.5.
    pub hertz_constant: f64,
    /// Radial clearance subtracted from every ball's deflection, m. Negative values are a
    /// radial preload (interference fit): every ball is compressed by `|clearance_m|` at the
    /// centred position, so the load zone spans the whole circumference.
    pub clearance_m: f64,
}

/// Which weights the model applies (see `docs/equations/bearing-model.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Gravity {
    /// No gravity.
    Off,
    /// Gravity on the shaft only: the pedestal and sprung mass hang on mounts assembled
    /// concentric, so their weights are carried by the mounts (the CWRU rig: load zone at
    /// 6 o'clock).
    ShaftOnly,
    /// Gravity on every mass, as eqs. (2.12)–(2.14) print it. With a soft pedestal (Table 2.1)
    /// the pedestal sinks onto the top balls: load zone at 12 o'clock.
    AllMasses,
}

/// A force on the shaft rotating at an order of the shaft speed: unbalance (order 1),
/// misalignment (order 2). `F = A (cos(kΩt + φ), sin(kΩt + φ))`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShaftHarmonic {
    /// Order `k` (≥ 1).
    pub order: u32,
    /// Amplitude `A`, N.
    pub amplitude_n: f64,
    /// Phase `φ`, rad.
    pub phase_rad: f64,
}

/// Shaft speed.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShaftSpeed {
    /// Nominal speed, rpm (≥ 0; 0 = shaft at rest, used for the energy check).
    pub rpm: f64,
    /// Constant ratio applied to the nominal speed (1.0 = none; CWRU fault lines sit about
    /// 0.33 % above the kinematic prediction, i.e. 1.0033).
    pub ratio: f64,
}

impl ShaftSpeed {
    /// `rpm` with no offset.
    pub fn rpm(rpm: f64) -> Self {
        Self { rpm, ratio: 1.0 }
    }
    /// Effective shaft frequency, Hz.
    pub fn hz(&self) -> f64 {
        self.rpm * self.ratio / 60.0
    }
}

/// Relative bounds of the seeded parameter uncertainties ΔM, ΔC, ΔK of eq. (2.3): every mass
/// (stiffness, damping) is multiplied by `1 + u`, `u ~ U(−bound, bound)`, drawn once.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Uncertainty {
    /// Bound on ΔM/M (0 ..< 0.5).
    pub mass: f64,
    /// Bound on ΔC/C (0 ..< 0.5).
    pub damping: f64,
    /// Bound on ΔK/K (0 ..< 0.5), contact constant included.
    pub stiffness: f64,
}

/// Largest random slip fraction the model accepts ([`Slip::Random`]): ±10 % of the ball spacing.
pub const MAX_SLIP_FRACTION: f64 = 0.1;

/// Random slip of the rolling elements.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Slip {
    /// Balls keep their nominal kinematic positions.
    Off,
    /// Each ball's angle is offset by `ε ~ U(−f, f) · 2π/n_b`, redrawn once per cage
    /// revolution while the ball crosses the unloaded side (`f` = `fraction`, typically
    /// 0.01–0.02). Fault impacts then jitter by ±f of the ball-pass period.
    Random {
        /// `f` in (0, 0.1].
        fraction: f64,
    },
}

/// Named parameter sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ParamSet {
    /// Dissertation Table 2.1 as printed (see the crate docs for what is odd about it).
    Table21,
    /// Physically consistent set for the CWRU rig (Sawalhi–Randall stiffness/damping family,
    /// Hertz constant of a 6205, housing resonance at 3.3 kHz).
    CwruRig,
}

impl std::str::FromStr for ParamSet {
    type Err = ModelError;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "table2.1" | "table21" | "table-2.1" | "dissertation" => Ok(ParamSet::Table21),
            "cwru" | "cwru-rig" | "consistent" => Ok(ParamSet::CwruRig),
            other => Err(ModelError::UnknownParamSet(other.to_string())),
        }
    }
}

/// Everything needed to build a [`crate::BearingModel`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModelSpec {
    /// Bearing geometry.
    pub geometry: BearingGeometry,
    /// Masses, stiffnesses, dampings of shaft and pedestal.
    pub structure: Structure,
    /// Sprung mass / housing resonance (the measured point).
    pub housing: Housing,
    /// Ball contact law.
    pub contact: Contact,
    /// Which weights act.
    pub gravity: Gravity,
    /// Constant radial load on the shaft, pointing down (−y), N (≥ 0).
    pub radial_load_n: f64,
    /// Shaft speed.
    pub speed: ShaftSpeed,
    /// Rotating forces on the shaft (unbalance, misalignment).
    pub harmonics: Vec<ShaftHarmonic>,
    /// Spalls.
    pub faults: FaultSet,
    /// Random slip.
    pub slip: Slip,
    /// Seeded ΔM, ΔC, ΔK (all zero = nominal model).
    pub uncertainty: Uncertainty,
    /// Cage angle of ball 0 at `t = 0` (θ₀ of eq. 2.8), rad.
    pub cage_angle0_rad: f64,
    /// Seed of slip and uncertainty draws.
    pub seed: u64,
}

impl ModelSpec {
    /// A spec from a named parameter set, for `geometry`, at `rpm`, healthy, no slip,
    /// no uncertainty.
    pub fn from_set(set: ParamSet, geometry: BearingGeometry, rpm: f64) -> Self {
        let (structure, housing, contact, gravity) = match set {
            ParamSet::Table21 => (
                Structure {
                    shaft_mass_kg: 1.36,
                    shaft_stiffness_n_m: 23.3e6,
                    shaft_damping_ns_m: 654.0,
                    pedestal_mass_kg: 2.7,
                    pedestal_stiffness_n_m: 1.31e5,
                    pedestal_damping_ns_m: 654.0,
                },
                // Table 2.1 gives no sprung mass: borrowed from the CWRU set.
                Housing {
                    mass_kg: 1.0,
                    resonance_hz: 3300.0,
                    damping_ratio: 0.05,
                },
                Contact {
                    hertz_constant: 5.96e7,
                    clearance_m: 0.0,
                },
                Gravity::AllMasses,
            ),
            ParamSet::CwruRig => (
                Structure {
                    shaft_mass_kg: 3.2638,
                    shaft_stiffness_n_m: 7.42e7,
                    shaft_damping_ns_m: 1376.8,
                    pedestal_mass_kg: 6.638,
                    pedestal_stiffness_n_m: 1.51e7,
                    pedestal_damping_ns_m: 2210.7,
                },
                Housing {
                    mass_kg: 1.0,
                    resonance_hz: 3300.0,
                    damping_ratio: 0.05,
                },
                Contact {
                    hertz_constant: 9.3e9,
                    clearance_m: 0.0,
                },
                Gravity::ShaftOnly,
            ),
        };
        Self {
            geometry,
            structure,
            housing,
            contact,
            gravity,
            radial_load_n: 0.0,
            speed: ShaftSpeed::rpm(rpm),
            harmonics: Vec::new(),
            faults: FaultSet::healthy(),
            slip: Slip::Off,
            uncertainty: Uncertainty::default(),
            cage_angle0_rad: -PI / 2.0,
            seed: 0,
        }
    }

    /// Check every field once.
    pub fn validate(&self) -> Result<()> {
        self.geometry.validate()?;
        let s = &self.structure;
        check_positive("shaft_mass_kg", s.shaft_mass_kg)?;
        check_positive("shaft_stiffness_n_m", s.shaft_stiffness_n_m)?;
        check_range(
            "shaft_damping_ns_m",
            s.shaft_damping_ns_m,
            0.0,
            1e9,
            "0 ..= 1e9",
        )?;
        check_positive("pedestal_mass_kg", s.pedestal_mass_kg)?;
        check_positive("pedestal_stiffness_n_m", s.pedestal_stiffness_n_m)?;
        check_range(
            "pedestal_damping_ns_m",
            s.pedestal_damping_ns_m,
            0.0,
            1e9,
            "0 ..= 1e9",
        )?;
        check_positive("housing mass_kg", self.housing.mass_kg)?;
        check_range(
            "housing resonance_hz",
            self.housing.resonance_hz,
            1.0,
            1e6,
            "1 ..= 1e6 Hz",
        )?;
        check_range(
            "housing damping_ratio",
            self.housing.damping_ratio,
            0.0,
            2.0,
            "0 ..= 2",
        )?;
        check_positive("hertz_constant", self.contact.hertz_constant)?;
        check_range(
            "clearance_m",
            self.contact.clearance_m,
            -1e-4,
            1e-3,
            "-0.1 mm (preload) ..= 1 mm",
        )?;
        check_range("radial_load_n", self.radial_load_n, 0.0, 1e6, "0 ..= 1e6 N")?;
        check_range("rpm", self.speed.rpm, 0.0, 1e5, "0 ..= 100000")?;
        check_range("speed ratio", self.speed.ratio, 0.5, 2.0, "0.5 ..= 2")?;
        for h in &self.harmonics {
            check_range("harmonic order", h.order as f64, 1.0, 100.0, "1 ..= 100")?;
            check_range(
                "harmonic amplitude_n",
                h.amplitude_n,
                0.0,
                1e6,
                "0 ..= 1e6 N",
            )?;
            check_range("harmonic phase_rad", h.phase_rad, -1e3, 1e3, "finite")?;
        }
        self.faults.validate(&self.geometry)?;
        if let Slip::Random { fraction } = self.slip {
            check_range(
                "slip fraction",
                fraction,
                1e-9,
                MAX_SLIP_FRACTION,
                "0 < f <= 0.1",
            )?;
        }
        let u = &self.uncertainty;
        check_range("uncertainty mass", u.mass, 0.0, 0.49, "0 ..< 0.5")?;
        check_range("uncertainty damping", u.damping, 0.0, 0.49, "0 ..< 0.5")?;
        check_range("uncertainty stiffness", u.stiffness, 0.0, 0.49, "0 ..< 0.5")?;
        check_range("cage_angle0_rad", self.cage_angle0_rad, -1e3, 1e3, "finite")?;
        Ok(())
    }
}
