//! CWRU catalog records as the rig calibration sees them (`cargo xtask calibrate-rig`,
//! `calibrated_rig`): a record's fault location, outer-race spall position and size as a
//! training record or a synthesis request, and the simulated-versus-measured comparison of one
//! record. Decisions: `docs/equations/close-loop.md`, "Calibrated rig simulator".

use std::f64::consts::PI;

use bearing_data::{CatalogEntry, OuterPosition};
use calibrated_rig::{Comparison, Location, RigModel, Synthesis, TrainingRecord, signal_stats};

use crate::{PipelineError, Result};

/// The fault location of a catalog record (`None` for a normal record): its label's `From`.
pub fn location(e: &CatalogEntry) -> Option<Location> {
    e.fault.into()
}

/// The outer-race spall's angle in the load zone's frame, rad: 6 o'clock (centred in the load
/// zone) −π/2, 3 o'clock (orthogonal) 0, 12 o'clock (opposite) π/2.
pub fn outer_angle(e: &CatalogEntry) -> f64 {
    match e.outer_position {
        Some(OuterPosition::Orthogonal3) => 0.0,
        Some(OuterPosition::Opposite12) => PI / 2.0,
        _ => -PI / 2.0,
    }
}

/// The fault frequency of `loc` at `rpm` on the rig's bearing (× the rig's speed ratio), Hz.
pub fn fault_hz(m: &RigModel, loc: Location, rpm: f64) -> f64 {
    m.fault_rate_hz(loc, rpm)
}

/// A fault record as a calibration training record (`None` for a normal record or one without
/// a fault size).
pub fn training_record<'a>(
    e: &CatalogEntry,
    name: &'a str,
    y: &'a [f64],
    rpm: f64,
) -> Option<TrainingRecord<'a>> {
    Some(TrainingRecord {
        name,
        location: location(e)?,
        size_mm: e.fault_diameter_in()? * 25.4,
        outer_angle_rad: outer_angle(e),
        rpm,
        y,
    })
}

/// The rig's simulation of a fault record's conditions (`n` samples at `rpm`, seeded by the
/// record number), with the fault frequency it is judged at.
///
/// # Errors
/// [`PipelineError::Missing`] for a normal record or one without a fault size;
/// [`PipelineError::Rig`] when the synthesis fails.
pub fn simulate_record(
    m: &RigModel,
    e: &CatalogEntry,
    rpm: f64,
    n: usize,
) -> Result<(Vec<f64>, f64)> {
    let missing = |what: &str| PipelineError::Missing {
        what: format!("the {what} of record {}", e.number),
    };
    let loc = location(e).ok_or_else(|| missing("fault location"))?;
    let size_mm = e.fault_diameter_in().ok_or_else(|| missing("fault size"))? * 25.4;
    let mut s = Synthesis::new(loc.class(), size_mm, rpm, n, u64::from(e.number));
    s.outer_angle_rad = outer_angle(e);
    let rig = |source| PipelineError::Rig {
        record: e.number,
        source,
    };
    Ok((m.synthesize(&s).map_err(rig)?, m.fault_rate_hz(loc, rpm)))
}

/// Measured against simulated statistics of one fault record `y` (at `fs`, `rpm`), the fault
/// line judged at the rig's fault frequency.
///
/// # Errors
/// As [`simulate_record`]; [`PipelineError::Rig`] when the statistics fail.
pub fn compare_record(
    m: &RigModel,
    e: &CatalogEntry,
    y: &[f64],
    fs: f64,
    rpm: f64,
) -> Result<Comparison> {
    let (sim, f) = simulate_record(m, e, rpm, y.len())?;
    let rig = |source| PipelineError::Rig {
        record: e.number,
        source,
    };
    Ok(Comparison {
        measured: signal_stats(y, fs, Some(f)).map_err(rig)?,
        simulated: signal_stats(&sim, fs, Some(f)).map_err(rig)?,
    })
}
