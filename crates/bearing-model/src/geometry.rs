//! Bearing geometry and kinematics: eq. (2.8) and the classical defect frequencies.
//!
//! All defect frequencies are returned as *orders* (multiples of the shaft frequency `fr`),
//! so they can be scaled by any speed. Two ball frequencies are given and named apart:
//! [`FaultOrders::ball_spin`] is the classical ball spin frequency (BSF, one ball revolution
//! relative to the cage), [`FaultOrders::ball_defect`] is twice that: the rate at which a
//! single ball defect strikes the races (the value CWRU's table calls "BSF").

use crate::error::{ModelError, Result, check_positive, check_range};
use std::f64::consts::PI;

/// Largest number of balls a geometry may have: the 5-DOF model keeps fixed-size per-ball
/// buffers of this length (`state_space`).
pub const MAX_BALLS: usize = 32;

const INCH: f64 = 0.0254;

/// Geometry of a deep-groove ball bearing (the quantities of eq. (2.8)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BearingGeometry {
    /// Designation, for reports (for example `"SKF 6205-2RS JEM"`); not serialized.
    #[serde(skip, default)]
    pub name: &'static str,
    /// Number of rolling elements `n_b`.
    pub n_balls: usize,
    /// Ball diameter `d` in metres.
    pub ball_diameter_m: f64,
    /// Pitch diameter `D` in metres.
    pub pitch_diameter_m: f64,
    /// Contact angle in radians (0 for a radially loaded deep-groove bearing).
    pub contact_angle_rad: f64,
}

/// Built-in bearings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum Bearing {
    /// SKF 6205-2RS JEM, CWRU drive end: 9 balls, d = 0.3126 in, D = 1.537 in.
    Skf6205,
    /// SKF 6203-2RS JEM, CWRU fan end: 8 balls, d = 0.2656 in, D = 1.122 in.
    Skf6203,
}

impl Bearing {
    /// The short designation machine models and close-loop reports name it by ("6205", "6203").
    pub fn designation(self) -> &'static str {
        match self {
            Bearing::Skf6205 => "6205",
            Bearing::Skf6203 => "6203",
        }
    }

    /// The geometry of this bearing.
    pub fn geometry(self) -> BearingGeometry {
        match self {
            Bearing::Skf6205 => BearingGeometry::skf_6205(),
            Bearing::Skf6203 => BearingGeometry::skf_6203(),
        }
    }
}

/// A built-in bearing by any name the catalogue finds it by ([`crate::catalog::lookup`]: `6205`,
/// `SKF 6205-2RS`, `de`, `drive-end`; `6203`, `fe`, `fan-end`).
///
/// # Errors
/// [`ModelError::UnknownBearing`] for a name the catalogue does not hold,
/// [`ModelError::NotBuiltIn`] for a catalogue bearing that is not built in (`UC204`).
impl std::str::FromStr for Bearing {
    type Err = ModelError;
    fn from_str(s: &str) -> Result<Self> {
        let e = crate::catalog::lookup(s)?;
        e.builtin.ok_or_else(|| ModelError::NotBuiltIn {
            given: s.trim().to_string(),
            name: e.name,
        })
    }
}

impl BearingGeometry {
    /// SKF 6205-2RS JEM (CWRU drive end; also used for the SHSE substitute, whose geometry
    /// the dissertation does not give in Table 4.1).
    pub fn skf_6205() -> Self {
        Self {
            name: "SKF 6205-2RS JEM",
            n_balls: 9,
            ball_diameter_m: 0.3126 * INCH,
            pitch_diameter_m: 1.537 * INCH,
            contact_angle_rad: 0.0,
        }
    }

    /// SKF 6203-2RS JEM (CWRU fan end).
    pub fn skf_6203() -> Self {
        Self {
            name: "SKF 6203-2RS JEM",
            n_balls: 8,
            ball_diameter_m: 0.2656 * INCH,
            pitch_diameter_m: 1.122 * INCH,
            contact_angle_rad: 0.0,
        }
    }

    /// A bearing of the given dimensions (named `"custom"`), validated with
    /// [`BearingGeometry::validate`]: `n_balls` rolling elements of diameter `ball_diameter_m` on
    /// a pitch circle of diameter `pitch_diameter_m`, contact angle `contact_angle_rad`.
    ///
    /// # Errors
    /// [`ModelError`] when the geometry is not physical (see [`BearingGeometry::validate`]) or a
    /// value is not finite.
    pub fn from_dimensions(
        n_balls: usize,
        ball_diameter_m: f64,
        pitch_diameter_m: f64,
        contact_angle_rad: f64,
    ) -> Result<Self> {
        let g = Self {
            name: "custom",
            n_balls,
            ball_diameter_m,
            pitch_diameter_m,
            contact_angle_rad,
        };
        g.validate()?;
        Ok(g)
    }

    /// Check that the geometry is physical: at least 3 balls, `0 < d < D`, balls fit on the
    /// pitch circle, contact angle in `[0, π/2)`.
    pub fn validate(&self) -> Result<()> {
        check_range(
            "n_balls",
            self.n_balls as f64,
            3.0,
            MAX_BALLS as f64,
            "3 ..= 32",
        )?;
        check_positive("ball_diameter_m", self.ball_diameter_m)?;
        check_positive("pitch_diameter_m", self.pitch_diameter_m)?;
        check_range(
            "contact_angle_rad",
            self.contact_angle_rad,
            0.0,
            PI / 2.0 - 1e-6,
            "0 ..< π/2",
        )?;
        // Neighbouring balls must not overlap: chord between centres > d.
        let chord = self.pitch_diameter_m * (PI / self.n_balls as f64).sin();
        if self.ball_diameter_m >= chord {
            return Err(ModelError::OutOfRange {
                name: "ball_diameter_m",
                value: self.ball_diameter_m,
                expected: "smaller than the chord between neighbouring ball centres",
            });
        }
        Ok(())
    }

    /// `r = (d/D)·cos α`, the ratio all kinematic formulas use.
    pub fn ratio(&self) -> f64 {
        self.ball_diameter_m / self.pitch_diameter_m * self.contact_angle_rad.cos()
    }

    /// Contact radius on the inner race, `(D − d)/2`, in metres.
    pub fn inner_race_radius_m(&self) -> f64 {
        0.5 * (self.pitch_diameter_m - self.ball_diameter_m)
    }

    /// Contact radius on the outer race, `(D + d)/2`, in metres.
    pub fn outer_race_radius_m(&self) -> f64 {
        0.5 * (self.pitch_diameter_m + self.ball_diameter_m)
    }

    /// Defect frequencies as multiples of the shaft frequency (outer race fixed, inner race
    /// turning with the shaft). Eq. (2.8) gives the cage order `½(1 − d/D)`.
    pub fn orders(&self) -> FaultOrders {
        let r = self.ratio();
        let n = self.n_balls as f64;
        let spin = 0.5 * self.pitch_diameter_m / self.ball_diameter_m * (1.0 - r * r);
        FaultOrders {
            ftf: 0.5 * (1.0 - r),
            bpfo: 0.5 * n * (1.0 - r),
            bpfi: 0.5 * n * (1.0 + r),
            ball_spin: spin,
            ball_defect: 2.0 * spin,
        }
    }
}

/// Defect frequencies as orders of the shaft frequency `fr`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FaultOrders {
    /// Fundamental train (cage) frequency, eq. (2.8): `½(1 − r)`.
    pub ftf: f64,
    /// Ball pass frequency, outer race: `n/2 (1 − r)`.
    pub bpfo: f64,
    /// Ball pass frequency, inner race: `n/2 (1 + r)`.
    pub bpfi: f64,
    /// Classical ball spin frequency (one ball revolution relative to the cage):
    /// `D/(2d) (1 − r²)`. For the 6205 this is 2.3567.
    pub ball_spin: f64,
    /// Ball-defect rate: a spall on one ball strikes a race twice per spin, `2 × ball_spin`.
    /// This is the value CWRU's table calls "BSF" (4.7135 for the 6205).
    pub ball_defect: f64,
}

impl FaultOrders {
    /// Orders given directly as multiples of the shaft frequency (a manufacturer's table),
    /// with `ball_defect` in CWRU's convention (twice the ball spin; `ball_spin` is set to half
    /// of it). Every value must be finite and positive, `ftf < 1` (the cage turns slower than the
    /// shaft) and `bpfo < bpfi`.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] (or the positivity error) naming the offending multiple.
    pub fn from_multiples(bpfo: f64, bpfi: f64, ftf: f64, ball_defect: f64) -> Result<Self> {
        check_positive("bpfo", bpfo)?;
        check_positive("bpfi", bpfi)?;
        check_positive("ftf", ftf)?;
        check_positive("bsf", ball_defect)?;
        check_range("ftf", ftf, 0.0, 1.0 - 1e-9, "0 < ftf < 1")?;
        if bpfo >= bpfi {
            return Err(ModelError::OutOfRange {
                name: "bpfo",
                value: bpfo,
                expected: "smaller than bpfi",
            });
        }
        Ok(Self {
            ftf,
            bpfo,
            bpfi,
            ball_spin: 0.5 * ball_defect,
            ball_defect,
        })
    }

    /// The impact rate of a spall at `location`: BPFI (inner race), BPFO (outer race) or the
    /// ball-defect rate (ball), in the units of `self` (orders, or Hz after [`FaultOrders::at`]).
    pub fn of(&self, location: crate::FaultLocation) -> f64 {
        match location {
            crate::FaultLocation::Inner => self.bpfi,
            crate::FaultLocation::Outer => self.bpfo,
            crate::FaultLocation::Ball => self.ball_defect,
        }
    }

    /// The same frequencies in Hz at shaft frequency `fr_hz`.
    pub fn at(&self, fr_hz: f64) -> FaultOrders {
        FaultOrders {
            ftf: self.ftf * fr_hz,
            bpfo: self.bpfo * fr_hz,
            bpfi: self.bpfi * fr_hz,
            ball_spin: self.ball_spin * fr_hz,
            ball_defect: self.ball_defect * fr_hz,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cwru_6205_orders_within_0_01_percent() {
        // CWRU Bearing Data Center table for the 6205-2RS JEM.
        let o = BearingGeometry::skf_6205().orders();
        for (got, want) in [
            (o.bpfi, 5.4152),
            (o.bpfo, 3.5848),
            (o.ftf, 0.39828),
            (o.ball_defect, 4.7135),
        ] {
            assert!(((got - want) / want).abs() < 1e-4, "{got} vs {want}");
        }
        assert!((o.ball_spin - 2.3567).abs() / 2.3567 < 1e-4);
    }

    #[test]
    fn cwru_6203_orders() {
        // CWRU fan-end table: BPFI 4.9469, BPFO 3.0530, FTF 0.3817, BSF(x2) 3.9874.
        let o = BearingGeometry::skf_6203().orders();
        for (got, want) in [
            (o.bpfi, 4.9469),
            (o.bpfo, 3.0530),
            (o.ftf, 0.3817),
            (o.ball_defect, 3.9874),
        ] {
            assert!(((got - want) / want).abs() < 2e-4, "{got} vs {want}");
        }
    }

    #[test]
    fn bpfo_plus_bpfi_is_n() {
        let g = BearingGeometry::skf_6205();
        let o = g.orders();
        assert!((o.bpfo + o.bpfi - 9.0).abs() < 1e-12);
        assert!((o.bpfo - 9.0 * o.ftf).abs() < 1e-12);
    }

    #[test]
    fn from_dimensions_and_multiples() {
        let g = BearingGeometry::from_dimensions(9, 0.3126 * INCH, 1.537 * INCH, 0.0).unwrap();
        assert_eq!(g.orders(), BearingGeometry::skf_6205().orders());
        assert!(BearingGeometry::from_dimensions(9, 0.05, 0.04, 0.0).is_err());
        assert!(BearingGeometry::from_dimensions(2, 0.005, 0.04, 0.0).is_err());
        assert!(BearingGeometry::from_dimensions(9, f64::NAN, 0.04, 0.0).is_err());
        let o = FaultOrders::from_multiples(3.5848, 5.4152, 0.39828, 4.7135).unwrap();
        assert!((o.ball_spin - 2.35675).abs() < 1e-9);
        assert!(FaultOrders::from_multiples(5.4, 3.5, 0.4, 4.7).is_err());
        assert!(FaultOrders::from_multiples(3.5, 5.4, 1.4, 4.7).is_err());
        assert!(FaultOrders::from_multiples(3.5, 5.4, 0.4, -1.0).is_err());
    }

    #[test]
    fn invalid_geometry_rejected() {
        let mut g = BearingGeometry::skf_6205();
        g.ball_diameter_m = 0.05;
        assert!(g.validate().is_err());
        let mut g = BearingGeometry::skf_6205();
        g.n_balls = 1;
        assert!(g.validate().is_err());
        assert!(BearingGeometry::skf_6205().validate().is_ok());
    }
}
