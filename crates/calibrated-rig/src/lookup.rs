//! The rig's lookups: the calibrated severity, strike fraction and impact path for a fault
//! location, spall size and outer-race position, and the fault rates.

use super::{
    CloseLoopError, ImpactPath, Location, MachineModel, RigModel, Severity, StructuralPath,
    same_position,
};

/// The path of `location` for a spall of `size_mm` among `paths`: the one fitted on the nearest
/// size (in log size; a pooled path matches every size) among the reference paths, else the
/// first path of any location.
pub(super) fn nearest_path(
    paths: &[ImpactPath],
    location: Location,
    size_mm: f64,
) -> Option<&ImpactPath> {
    nearest_path_at(paths, location, size_mm, None)
}

/// [`nearest_path`] for an outer-race spall at `outer_angle_rad`: among the paths fitted at that
/// position when `paths` holds any, else among the reference paths.
pub(super) fn nearest_path_at(
    paths: &[ImpactPath],
    location: Location,
    size_mm: f64,
    outer_angle_rad: Option<f64>,
) -> Option<&ImpactPath> {
    let distance = |p: &ImpactPath| match p.size_mm {
        Some(s) if s > 0.0 && size_mm > 0.0 => (s.ln() - size_mm.ln()).abs(),
        Some(s) => (s - size_mm).abs(),
        None => 0.0,
    };
    let at = |p: &ImpactPath| match (p.outer_angle_rad, outer_angle_rad) {
        (Some(a), Some(b)) => location == Location::Outer && same_position(a, b),
        _ => false,
    };
    let positioned = paths.iter().any(|p| p.location == location && at(p));
    paths
        .iter()
        .filter(|p| p.location == location)
        .filter(|p| {
            if positioned {
                at(p)
            } else {
                p.outer_angle_rad.is_none()
            }
        })
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .or(paths.first())
}

impl RigModel {
    /// The calibrated severity at `location` for a spall of `size_mm`: gain and random
    /// fraction, interpolated between calibrated sizes (log gain and fraction linear in log
    /// size; equal sizes averaged), the nearest calibrated size's values outside them.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no severity for `location`.
    pub fn severity(&self, location: Location, size_mm: f64) -> Result<(f64, f64), CloseLoopError> {
        let [log_gain, fraction, _] = self.severity_point(location, size_mm, None)?;
        Ok((log_gain.exp(), fraction))
    }

    /// [`RigModel::severity`] for an outer-race spall at `outer_angle_rad`: the severities
    /// calibrated at that position ([`Severity::outer_angle_rad`]) where the rig holds any, the
    /// reference ones otherwise (and for inner-race and ball spalls).
    ///
    /// # Errors
    /// As [`RigModel::severity`].
    pub fn severity_at(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: f64,
    ) -> Result<(f64, f64), CloseLoopError> {
        let [log_gain, fraction, _] =
            self.severity_point(location, size_mm, Some(outer_angle_rad))?;
        Ok((log_gain.exp(), fraction))
    }

    /// [`RigModel::strike_fraction`] at an outer-race position, as [`RigModel::severity_at`].
    ///
    /// # Errors
    /// As [`RigModel::severity`].
    pub fn strike_fraction_at(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: f64,
    ) -> Result<f64, CloseLoopError> {
        Ok(self.severity_point(location, size_mm, Some(outer_angle_rad))?[2])
    }

    /// The calibrated strike fraction ([`Severity::strike_fraction`]) at `location` for a spall
    /// of `size_mm`, interpolated as [`RigModel::severity`] is (linear in log size; the nearest
    /// calibrated size's value outside them).
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no severity for `location`.
    pub fn strike_fraction(&self, location: Location, size_mm: f64) -> Result<f64, CloseLoopError> {
        Ok(self.severity_point(location, size_mm, None)?[2])
    }

    /// The severities that serve `location` at the outer-race position `outer_angle_rad`: those
    /// calibrated at that position when the rig holds any (`true`), else the reference ones.
    fn severity_set(
        &self,
        location: Location,
        outer_angle_rad: Option<f64>,
    ) -> (Vec<&Severity>, bool) {
        let at = |s: &Severity| match (s.outer_angle_rad, outer_angle_rad) {
            (Some(a), Some(b)) => location == Location::Outer && same_position(a, b),
            _ => false,
        };
        let of_location = || self.severities.iter().filter(|s| s.location == location);
        let positioned = of_location().any(at);
        let set = of_location()
            .filter(|s| {
                if positioned {
                    at(s)
                } else {
                    s.outer_angle_rad.is_none()
                }
            })
            .collect();
        (set, positioned)
    }

    /// [`RigModel::calibrated_range_mm`] of the severities that serve `location` at the
    /// outer-race position `outer_angle_rad` ([`RigModel::severity_at`]), and whether they were
    /// calibrated at that position.
    pub fn calibrated_range_mm_at(
        &self,
        location: Location,
        outer_angle_rad: f64,
    ) -> Option<((f64, f64), bool)> {
        let (set, positioned) = self.severity_set(location, Some(outer_angle_rad));
        set.iter()
            .map(|s| (s.size_mm, s.size_mm))
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
            .map(|r| (r, positioned))
    }

    /// The smallest and largest calibrated spall width of `location`'s reference severities,
    /// mm (`None` without any): outside them the nearest calibrated severity is held.
    pub fn calibrated_range_mm(&self, location: Location) -> Option<(f64, f64)> {
        self.severities
            .iter()
            .filter(|s| s.location == location && s.outer_angle_rad.is_none())
            .map(|s| (s.size_mm, s.size_mm))
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    }

    /// Fault rate of `location` at nominal speed `rpm`, Hz: BPFI, BPFO or the ball-defect rate
    /// (CWRU's "BSF") times the shaft rate at the calibrated speed ratio.
    pub fn fault_rate_hz(&self, location: Location, rpm: f64) -> f64 {
        fault_rate_of(&self.healthy, location, rpm)
    }

    /// (log gain, random fraction, strike fraction) at `location` for `size_mm`: per calibrated size
    /// the mean over its records, linear in log size between sizes, held beyond them. Among the
    /// severities calibrated at the outer-race position `outer_angle_rad` when the rig holds
    /// any, else among the reference ones.
    fn severity_point(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: Option<f64>,
    ) -> Result<[f64; 3], CloseLoopError> {
        let (set, _) = self.severity_set(location, outer_angle_rad);
        let mut pts: Vec<(f64, [f64; 3])> = Vec::new();
        for s in &set {
            if pts.iter().any(|p| (p.0 - s.size_mm).abs() < 1e-9) {
                continue;
            }
            let same: Vec<&Severity> = set
                .iter()
                .copied()
                .filter(|t| (t.size_mm - s.size_mm).abs() < 1e-9)
                .collect();
            let n = same.len() as f64;
            let mean = |f: &dyn Fn(&Severity) -> f64| same.iter().map(|t| f(t)).sum::<f64>() / n;
            pts.push((
                s.size_mm,
                [
                    mean(&|t| t.gain.max(1e-300).ln()),
                    mean(&|t| t.random_fraction),
                    mean(&|t| t.strike_fraction),
                ],
            ));
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (first, last) = match (pts.first(), pts.last()) {
            (Some(f), Some(l)) => (*f, *l),
            _ => {
                return Err(CloseLoopError::Model {
                    reason: format!("the rig model holds no {} fault severity", location.name()),
                });
            }
        };
        if size_mm <= first.0 {
            return Ok(first.1);
        }
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            if size_mm <= b.0 {
                let t = (size_mm.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
                return Ok(std::array::from_fn(|i| a.1[i] + t * (b.1[i] - a.1[i])));
            }
        }
        Ok(last.1)
    }

    /// The first impact path of `location` (the first path of any location when the rig holds
    /// none for it). A rig fitted per size holds one path per calibrated size:
    /// [`RigModel::impact_path_for`] picks the one for a spall.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no impact path at all.
    pub fn impact_path(&self, location: Location) -> Result<&StructuralPath, CloseLoopError> {
        self.impact_paths
            .iter()
            .find(|p| p.location == location)
            .or(self.impact_paths.first())
            .map(|p| &p.path)
            .ok_or_else(|| CloseLoopError::Model {
                reason: "the rig model holds no impact path".into(),
            })
    }

    /// The impact path of `location` for a spall of `size_mm`: the path fitted on the nearest
    /// calibrated size of that location (in log size; beyond the calibrated sizes the nearest
    /// one is held, as the severity is), a pooled path where the rig holds one, else the first
    /// path of any location.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no impact path at all.
    pub fn impact_path_for(
        &self,
        location: Location,
        size_mm: f64,
    ) -> Result<&ImpactPath, CloseLoopError> {
        nearest_path(&self.impact_paths, location, size_mm).ok_or_else(|| CloseLoopError::Model {
            reason: "the rig model holds no impact path".into(),
        })
    }

    /// [`RigModel::impact_path_for`] for an outer-race spall at `outer_angle_rad`: the path fitted
    /// at that position ([`ImpactPath::outer_angle_rad`]) where the rig holds one, the
    /// reference path otherwise (and for inner-race and ball spalls).
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the rig holds no impact path at all.
    pub fn impact_path_for_at(
        &self,
        location: Location,
        size_mm: f64,
        outer_angle_rad: f64,
    ) -> Result<&ImpactPath, CloseLoopError> {
        nearest_path_at(&self.impact_paths, location, size_mm, Some(outer_angle_rad)).ok_or_else(
            || CloseLoopError::Model {
                reason: "the rig model holds no impact path".into(),
            },
        )
    }
}

/// Fault rate of `location` on `machine` at nominal speed `rpm`, Hz ([`RigModel::fault_rate_hz`]).
pub(super) fn fault_rate_of(machine: &MachineModel, location: Location, rpm: f64) -> f64 {
    let [bpfo, bpfi, _ftf, bsf] = machine.bearing_orders;
    let fr = rpm / 60.0 * machine.speed_ratio;
    fr * match location {
        Location::Inner => bpfi,
        Location::Outer => bpfo,
        Location::Ball => bsf,
    }
}
