//! The rig model: its types ([`RigModel`], [`ImpactPath`], [`Severity`], [`RigProvenance`]),
//! their (de)serialisation and validation, and the committed CWRU rig.

use super::{
    CloseLoopError, Deserialize, LEGACY_EXCITATION_HOUSING_HZ, Location, MachineLine, MachineModel,
    PI, Serialize, StructuralPath,
};

/// The `format` string of a rig model file.
pub const FORMAT: &str = "hybrid-fdd/rig-model";
/// The current `version`.
pub const VERSION: u32 = 1;

fn legacy_housing_hz() -> f64 {
    LEGACY_EXCITATION_HOUSING_HZ
}

/// The committed calibration of the CWRU rig (`cargo xtask calibrate-rig`): 6205 drive end,
/// 12 kHz, units g.
pub const CWRU_RIG_JSON: &str = include_str!("../rig/cwru-12k.json");

/// The calibrated CWRU rig ([`CWRU_RIG_JSON`], validated).
///
/// # Errors
/// [`CloseLoopError::MachineModelFormat`] if the committed file is not a valid rig model.
pub fn cwru_rig() -> Result<RigModel, CloseLoopError> {
    RigModel::from_json(CWRU_RIG_JSON)
}

/// One calibrated severity: the gain that puts the 5-DOF excitation of a spall of `size_mm` at
/// `location` at the level measured on `record`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Severity {
    /// Fault location.
    pub location: Location,
    /// Spall width, mm.
    pub size_mm: f64,
    /// Gain from the excitation (m/s²) to the impact path's input (rig units).
    pub gain: f64,
    /// Fraction of the fault excitation's power that is random (white, seeded) rather than the
    /// 5-DOF impacts: the rough contact in and around the spall the 5-DOF model does not hold.
    /// Fitted so the record's kurtosis is matched (0 when the impacts alone are not impulsive
    /// enough).
    #[serde(default)]
    pub random_fraction: f64,
    /// Fraction of the time the defect strikes ([`crate::strike_gate`]; 1 = every impact, the rig files
    /// written before the gate existed). Chosen from [`crate::STRIKE_FRACTIONS`] so that the record's
    /// fault-line prominence in the envelope spectrum is matched.
    #[serde(default = "every_impact")]
    pub strike_fraction: f64,
    /// The training record it was fitted on.
    pub record: String,
    /// `Some(angle)` (rad, 6 o'clock = −π/2) for an outer-race severity fitted on a record
    /// with the spall at that position off the load zone's centre: spalls at that position
    /// ([`POSITION_TOLERANCE_RAD`]) use these severities; `None` (the rig files written before,
    /// and every 6 o'clock, inner-race and ball severity) for the location's reference severity,
    /// which serves every other position through the 5-DOF model's load zone and the
    /// sensor's horizontal sensitivity. Each CWRU position is a separate bearing, seeded and
    /// mounted on its own (as each size is); the model's load zone and sensor direction alone
    /// left the 0.007 in records at 12 o'clock 2× too loud and those at 3 o'clock too
    /// impulsive (results/calibration/).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_angle_rad: Option<f64>,
}

/// Two outer-race positions within this angle (rad, about 6°; CWRU's are 90° apart) are the
/// same position for [`Severity::outer_angle_rad`].
pub const POSITION_TOLERANCE_RAD: f64 = 0.1;

pub(super) fn same_position(a: f64, b: f64) -> bool {
    let d = (a - b).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d) <= POSITION_TOLERANCE_RAD
}

/// The path from one fault location — and, since each CWRU fault size is a separate bearing,
/// one spall size — to the sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImpactPath {
    /// Fault location.
    pub location: Location,
    /// Spall width of the training records it was fitted on, mm; `None` for a path pooled over
    /// every size of the location (rig files written before paths were fitted per size).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size_mm: Option<f64>,
    /// AR path `1/A_i(z)`.
    pub path: StructuralPath,
    /// `Some(angle)` for an outer-race path fitted on records with the spall at that position
    /// (as [`Severity::outer_angle_rad`]): the path from a defect at 3 or 12 o'clock to the
    /// sensor is not the one from 6 o'clock; `None` for the location's reference path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_angle_rad: Option<f64>,
}

/// Where a rig model came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct RigProvenance {
    /// The healthy recording the machine model was calibrated on.
    pub healthy_record: String,
    /// The fault records the impact path and the severities were fitted on.
    pub training_records: Vec<String>,
    /// How the training records were chosen (a sentence).
    pub training_rule: String,
}

/// A calibrated rig (JSON, `format` = [`FORMAT`], `version` = [`VERSION`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RigModel {
    /// Always [`FORMAT`].
    pub format: String,
    /// Schema version ([`VERSION`]).
    pub version: u32,
    /// Sampling rate of the calibration, Hz (the paths are discrete-time at this rate).
    pub fs_hz: f64,
    /// Units of the synthesized signal (those of the calibration records: "g", "m/s^2",
    /// "unknown").
    pub units: String,
    /// Bearing designation of the 5-DOF model.
    pub bearing: String,
    /// The healthy machine, as calibrated on the healthy recording (its lines at that
    /// recording's levels).
    pub healthy: MachineModel,
    /// The healthy machine's lines as the fault records' measurement chain sees them (tones —
    /// the chain's interference — rescaled to the training records; shaft orders unchanged):
    /// what [`RigModel::synthesize`] uses.
    #[serde(default)]
    pub chain_lines: Vec<MachineLine>,
    /// The paths the 5-DOF excitation of each fault location is seen through (unit excitation
    /// variance: the severity gains carry the level).
    pub impact_paths: Vec<ImpactPath>,
    /// Radial preload of every ball in the excitation model, m (the calibrated contact load:
    /// it sets how far round the bearing the balls stay loaded, hence the load-zone
    /// modulation of the impacts).
    pub preload_m: f64,
    /// Constant radial load on the shaft in the excitation model, N, downwards (beside the
    /// shaft's weight): it concentrates the contact load in the 6 o'clock load zone, so a
    /// spall at 12 o'clock strikes lighter than one at 6. Calibrated on outer-race records with
    /// the spall opposite the load zone against the 6 o'clock record of the same size (0
    /// without any, and in rig files written before it).
    #[serde(default)]
    pub radial_load_n: f64,
    /// Horizontal sensitivity of the sensor relative to vertical: the fault excitation is the
    /// vertical housing acceleration plus this times the horizontal pedestal acceleration
    /// (fitted on outer-race records with the spall off the sensor axis; 0 without any).
    #[serde(default)]
    pub sensor_horizontal: f64,
    /// The fault records' measurement chain (their anti-alias roll-off): a zero-phase FIR
    /// applied to every synthesized recording (empty = none). Identified from the training
    /// records (see [`crate::calibrate_rig`]).
    #[serde(default)]
    pub chain_fir: Vec<f64>,
    /// The healthy recording's broadband remainder — the power of the healthy PSD (smoothed
    /// ±150 Hz) that the machine model's named effects do not carry — as a zero-phase FIR
    /// shaping unit-variance white noise; added to every background (empty = none; rig files
    /// written before it have none).
    #[serde(default)]
    pub background_fir: Vec<f64>,
    /// The fault records' chain seen on the healthy machine's broadband part (its path noise,
    /// floor and remainder; not its lines, which `chain_lines` already holds at the fault
    /// records' levels): a zero-phase FIR applied to that part of every background but the
    /// healthy recording's own (empty = none; rig files written before it have none). The
    /// healthy recording (97, 48 kHz decimated) carries 20–30 times the 4–6 kHz power of the
    /// 12 kHz fault records whose faults are weak; see [`crate::calibrate_rig`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub background_chain_fir: Vec<f64>,
    /// Sprung-mass resonance of the excitation model, Hz (ζ 0.7; [`crate::EXCITATION_HOUSING_HZ`] when
    /// calibrated now, [`LEGACY_EXCITATION_HOUSING_HZ`] in rig files written before it was
    /// stored): the paths and severities were fitted behind it, so a rig keeps its own.
    #[serde(default = "legacy_housing_hz")]
    pub excitation_housing_hz: f64,
    /// Spall depth used in the excitation model, m.
    pub depth_m: f64,
    /// Slip fraction used in the excitation model.
    pub slip_fraction: f64,
    /// Calibrated severities, one per training record.
    pub severities: Vec<Severity>,
    /// Where it came from.
    pub provenance: RigProvenance,
}

impl RigModel {
    /// Serialise (pretty JSON).
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] if serialisation fails.
    pub fn to_json(&self) -> Result<String, CloseLoopError> {
        serde_json::to_string_pretty(self).map_err(|e| CloseLoopError::MachineModelFormat {
            reason: e.to_string(),
        })
    }

    /// Parse and validate a rig model.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] for malformed JSON or values,
    /// [`CloseLoopError::MachineModelMismatch`] for another format or version.
    pub fn from_json(text: &str) -> Result<Self, CloseLoopError> {
        let m: Self = close_loop::machine::parse_versioned(text, FORMAT, VERSION)?;
        let fmt = |reason: String| CloseLoopError::MachineModelFormat { reason };
        if !(m.fs_hz.is_finite() && m.fs_hz > 0.0) {
            return Err(fmt(format!("`fs_hz` must be > 0, got {}", m.fs_hz)));
        }
        // the healthy part goes through the machine model's own validation
        MachineModel::from_json(&m.healthy.to_json()?)?;
        if m.impact_paths.is_empty()
            || m.impact_paths.iter().any(|p| {
                p.path.ar.iter().any(|a| !a.is_finite())
                    || !(p.path.excitation_variance.is_finite() && p.path.excitation_variance > 0.0)
                    || p.size_mm.is_some_and(|s| !(s.is_finite() && s > 0.0))
            })
        {
            return Err(fmt(
                "`impact_paths` is empty or holds a non-finite coefficient or a size that is not > 0"
                    .into(),
            ));
        }
        if m.chain_fir
            .iter()
            .chain(&m.background_fir)
            .chain(&m.background_chain_fir)
            .any(|v| !v.is_finite())
        {
            return Err(fmt(
                "`chain_fir`, `background_fir` or `background_chain_fir` holds a non-finite tap"
                    .into(),
            ));
        }
        if !(m.preload_m.is_finite() && (0.0..=1e-4).contains(&m.preload_m)) {
            return Err(fmt(format!(
                "`preload_m` must be in [0, 1e-4], got {}",
                m.preload_m
            )));
        }
        if !(m.radial_load_n.is_finite() && (0.0..=1e5).contains(&m.radial_load_n)) {
            return Err(fmt(format!(
                "`radial_load_n` must be in [0, 1e5], got {}",
                m.radial_load_n
            )));
        }
        if !(m.excitation_housing_hz.is_finite()
            && (0.5 * m.fs_hz..=1e6).contains(&m.excitation_housing_hz))
        {
            return Err(fmt(format!(
                "`excitation_housing_hz` must be in [fs/2, 1e6] (above the output band), got {}",
                m.excitation_housing_hz
            )));
        }
        if m.impact_paths.iter().any(|p| {
            p.outer_angle_rad.is_some_and(|a| !a.is_finite())
                || (p.outer_angle_rad.is_some() && p.location != Location::Outer)
        }) {
            return Err(fmt(
                "an impact path's position must be finite and on the outer race".into(),
            ));
        }
        for s in &m.severities {
            if !(s.gain.is_finite() && s.gain >= 0.0 && s.size_mm.is_finite() && s.size_mm > 0.0)
                || s.outer_angle_rad.is_some_and(|a| !a.is_finite())
                || (s.outer_angle_rad.is_some() && s.location != Location::Outer)
            {
                return Err(fmt(format!(
                    "severity of {} must have size > 0, gain >= 0 and a finite position on the outer race only",
                    s.record
                )));
            }
        }
        Ok(m)
    }

    /// Check that the rig can produce a recording at `fs` for `bearing`.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelMismatch`] for another sampling rate or bearing.
    pub fn check_compatible(&self, fs: f64, bearing: &str) -> Result<(), CloseLoopError> {
        self.healthy.check_compatible(fs, bearing)
    }
}

/// Serde default of [`Severity::strike_fraction`]: every impact strikes.
fn every_impact() -> f64 {
    1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_machine_model_file_is_refused_as_a_rig_model() {
        let machine = r#"{"format": "hybrid-fdd/machine-model", "version": 1}"#;
        assert!(matches!(
            RigModel::from_json(machine),
            Err(CloseLoopError::MachineModelMismatch { what: "format", .. })
        ));
    }
}
