//! The machine model's file: versioned JSON (format, version), validated on reading and checked
//! against the recording it is used on.

use super::MachineModel;
use crate::CloseLoopError;

/// Parse one of the versioned JSON files of this crate and `calibrated-rig` (machine and rig
/// models) and check its `format` and `version`.
pub fn parse_versioned<T: serde::de::DeserializeOwned>(
    text: &str,
    format: &str,
    version: u32,
) -> Result<T, CloseLoopError> {
    // The header first: another kind of file (a rig model given where a machine model is
    // expected) or another version is named as such, not as the first field the body lacks.
    // A body that parses has a header that parses, so the header is checked only here.
    #[derive(serde::Deserialize)]
    struct Header {
        format: String,
        version: u32,
    }
    if let Ok(h) = serde_json::from_str::<Header>(text) {
        check_header(&h.format, h.version, format, version)?;
    }
    serde_json::from_str(text).map_err(|e| CloseLoopError::MachineModelFormat {
        reason: e.to_string(),
    })
}

fn check_header(f: &str, v: u32, format: &str, version: u32) -> Result<(), CloseLoopError> {
    if f != format {
        return Err(CloseLoopError::MachineModelMismatch {
            what: "format",
            expected: format.to_string(),
            found: f.to_string(),
        });
    }
    if v != version {
        return Err(CloseLoopError::MachineModelMismatch {
            what: "version",
            expected: version.to_string(),
            found: v.to_string(),
        });
    }
    Ok(())
}

/// The `format` string of a machine model file.
pub const FORMAT: &str = "hybrid-fdd/machine-model";
/// The current `version`.
pub const VERSION: u32 = 1;

impl MachineModel {
    /// The model as pretty JSON.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] if a value cannot be written (non-finite number).
    pub fn to_json(&self) -> Result<String, CloseLoopError> {
        serde_json::to_string_pretty(self).map_err(|e| CloseLoopError::MachineModelFormat {
            reason: e.to_string(),
        })
    }

    /// Parse and validate a machine model (format, version, finite positive rates and levels).
    /// The header is read first, so another kind of file (a rig model of `calibrate-rig`) or
    /// another version is named as such rather than by the first field its body lacks.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelFormat`] or [`CloseLoopError::MachineModelMismatch`].
    pub fn from_json(text: &str) -> Result<Self, CloseLoopError> {
        let m: Self = parse_versioned(text, FORMAT, VERSION)?;
        let positive = [
            ("fs_hz", m.fs_hz),
            ("speed_ratio", m.speed_ratio),
            ("defect_rate_ratio", m.defect_rate_ratio),
            ("declared_rpm", m.declared_rpm),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(CloseLoopError::MachineModelFormat {
                    reason: format!("`{name}` must be finite and > 0, got {v}"),
                });
            }
        }
        for (name, v) in [
            ("physics_gain", m.physics_gain),
            ("path_level", m.path_level),
            ("noise_floor_psd", m.noise_floor_psd),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(CloseLoopError::MachineModelFormat {
                    reason: format!("`{name}` must be finite and >= 0, got {v}"),
                });
            }
        }
        if let Some(p) = &m.path
            && ((p.fs_hz - m.fs_hz).abs() > 1e-9 * m.fs_hz
                || !p.ar.iter().all(|a| a.is_finite())
                || !(p.excitation_variance.is_finite() && p.excitation_variance > 0.0))
        {
            return Err(CloseLoopError::MachineModelFormat {
                reason: "`path` is not a finite AR model at the model's sampling rate".into(),
            });
        }
        Ok(m)
    }

    /// Check that the model fits a recording at `fs` Hz of bearing `bearing`.
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelMismatch`] naming what differs.
    pub fn check_compatible(&self, fs: f64, bearing: &str) -> Result<(), CloseLoopError> {
        if (self.fs_hz - fs).abs() > 1e-6 * fs.abs().max(1.0) {
            return Err(CloseLoopError::MachineModelMismatch {
                what: "sampling rate",
                expected: format!("{fs} Hz"),
                found: format!("{} Hz", self.fs_hz),
            });
        }
        if !self.bearing.eq_ignore_ascii_case(bearing) {
            return Err(CloseLoopError::MachineModelMismatch {
                what: "bearing",
                expected: bearing.to_string(),
                found: self.bearing.clone(),
            });
        }
        Ok(())
    }

    /// Check the units the model was calibrated in against the recording's (`"unknown"` on
    /// either side is accepted).
    ///
    /// # Errors
    /// [`CloseLoopError::MachineModelMismatch`] when both are known and differ.
    pub fn check_units(&self, units: &str) -> Result<(), CloseLoopError> {
        if self.units != "unknown" && units != "unknown" && self.units != units {
            return Err(CloseLoopError::MachineModelMismatch {
                what: "units",
                expected: units.to_string(),
                found: self.units.clone(),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn another_kind_or_version_is_named_before_the_fields_it_lacks() {
        // a rig model (`calibrate-rig`) given where a machine model is expected
        let rig = r#"{"format": "hybrid-fdd/rig-model", "version": 1, "fs_hz": 12000.0}"#;
        match MachineModel::from_json(rig) {
            Err(CloseLoopError::MachineModelMismatch {
                what: "format",
                found,
                ..
            }) => assert_eq!(found, "hybrid-fdd/rig-model"),
            other => panic!("{other:?}"),
        }
        // (and the other way round: `calibrated-rig`'s test of `RigModel::from_json`)
        let machine = r#"{"format": "hybrid-fdd/machine-model", "version": 1}"#;
        // a later version whose fields differ
        let later = r#"{"format": "hybrid-fdd/machine-model", "version": 2, "new": []}"#;
        assert!(matches!(
            MachineModel::from_json(later),
            Err(CloseLoopError::MachineModelMismatch {
                what: "version",
                ..
            })
        ));
        // the right header with a body that lacks fields: the field is named
        match MachineModel::from_json(machine) {
            Err(CloseLoopError::MachineModelFormat { reason }) => {
                assert!(reason.contains("missing field"), "{reason}")
            }
            other => panic!("{other:?}"),
        }
    }
}
