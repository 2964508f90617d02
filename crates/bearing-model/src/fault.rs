//! Localized faults (spalls), eqs. (2.15)–(2.24), and the eight fault classes.
//!
//! A spall is extra clearance `β(·)` subtracted from a ball's contact deflection while the ball
//! (or, for a ball fault, the spall on the ball) crosses it. Its *entry/exit profile* follows
//! eqs. (2.22)–(2.23) read as chord depths: a ball of radius `r` whose contact point is `u` from
//! the nearest spall edge can drop by `c_r(u) = r − √(r² − u²)`; the race's own curvature adds
//! `c_R(u)` on the convex inner race and subtracts it on the concave outer race. The drop is
//! capped by the spall depth. `u` runs from 0 at the entry edge to `w/2` mid-spall and back to
//! 0 at the exit edge, so the profile is continuous (no jump in the contact force), which is
//! what lets a fixed-step integrator converge.

use crate::error::{ModelError, Result, check_positive, check_range};
use crate::geometry::BearingGeometry;
use std::f64::consts::PI;

/// One spall: its circumferential width, depth, angular position and onset time.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spall {
    /// Width along the rolling direction, metres (CWRU's "fault diameter").
    pub width_m: f64,
    /// Depth in metres (CWRU EDM faults: 0.011 in = 0.2794 mm).
    pub depth_m: f64,
    /// Angular position of the spall's entry edge, radians, at `t = 0`. Angles are measured
    /// from +x towards +y; y points up, so 6 o'clock is `−π/2`. For the outer race the
    /// position is fixed, for the inner race it turns with the shaft (eq. 2.18), for a ball
    /// it is the spin angle of the spall relative to the outer-race contact.
    pub angle_rad: f64,
    /// Fault onset time `T_f` of eqs. (2.5)–(2.6) and (2.25): the spall is absent before it.
    pub onset_s: f64,
}

impl Spall {
    /// A spall of `width_m` at the CWRU EDM depth (0.2794 mm), at 6 o'clock, present from
    /// the start.
    pub fn new(width_m: f64) -> Self {
        Self {
            width_m,
            depth_m: 0.011 * 0.0254,
            angle_rad: -PI / 2.0,
            onset_s: f64::NEG_INFINITY,
        }
    }

    /// Same spall with another depth.
    pub fn with_depth(mut self, depth_m: f64) -> Self {
        self.depth_m = depth_m;
        self
    }

    /// Same spall at another angle.
    pub fn with_angle(mut self, angle_rad: f64) -> Self {
        self.angle_rad = angle_rad;
        self
    }

    /// Same spall with an onset time `T_f`.
    pub fn with_onset(mut self, onset_s: f64) -> Self {
        self.onset_s = onset_s;
        self
    }

    fn validate(&self, location: &'static str, max_width_m: f64) -> Result<()> {
        check_positive("spall width_m", self.width_m)?;
        check_positive("spall depth_m", self.depth_m)?;
        check_range(
            "spall angle_rad",
            self.angle_rad,
            -1e3,
            1e3,
            "finite, |angle| <= 1000 rad",
        )?;
        if self.onset_s.is_nan() {
            return Err(ModelError::OutOfRange {
                name: "spall onset_s",
                value: self.onset_s,
                expected: "a number (−∞ allowed)",
            });
        }
        if self.width_m >= max_width_m {
            return Err(ModelError::SpallTooWide {
                location,
                width_m: self.width_m,
                max_m: max_width_m,
            });
        }
        Ok(())
    }
}

/// Which spalls the bearing has. Any combination is allowed (eq. 2.25 sums them).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FaultSet {
    /// Spall on the inner race (turns with the shaft).
    pub inner: Option<Spall>,
    /// Spall on the outer race (fixed).
    pub outer: Option<Spall>,
    /// Spall on ball 0 (turns with the cage and spins).
    pub ball: Option<Spall>,
}

impl FaultSet {
    /// No fault.
    pub fn healthy() -> Self {
        Self::default()
    }

    /// The same spall size on every location the class names (positions: outer at 6 o'clock,
    /// inner and ball starting at 0).
    pub fn of_class(class: FaultClass, spall: Spall) -> Self {
        let mut f = Self::default();
        if class.has_inner() {
            f.inner = Some(spall.with_angle(0.0));
        }
        if class.has_outer() {
            f.outer = Some(spall);
        }
        if class.has_ball() {
            f.ball = Some(spall.with_angle(0.0));
        }
        f
    }

    /// Whether any spall is present.
    pub fn any(&self) -> bool {
        self.inner.is_some() || self.outer.is_some() || self.ball.is_some()
    }

    /// Check every spall's onset against a recording of `duration_s` seconds
    /// ([`check_onset`]; an onset of `−∞`, present from the start, always passes).
    ///
    /// # Errors
    /// [`ModelError::InvalidOnset`], [`ModelError::OnsetAfterEnd`].
    pub fn check_onsets(&self, duration_s: f64) -> Result<()> {
        for s in [&self.inner, &self.outer, &self.ball].into_iter().flatten() {
            if s.onset_s != f64::NEG_INFINITY {
                check_onset(s.onset_s, duration_s)?;
            }
        }
        Ok(())
    }

    /// Validate every spall against the bearing: a race spall must be narrower than the ball
    /// spacing on that race (one ball in it at a time) and than the ball diameter; a ball spall
    /// must be narrower than the ball diameter.
    pub fn validate(&self, g: &BearingGeometry) -> Result<()> {
        let n = g.n_balls as f64;
        let d = g.ball_diameter_m;
        if let Some(s) = &self.inner {
            s.validate(
                "inner race",
                (2.0 * PI * g.inner_race_radius_m() / n).min(d),
            )?;
        }
        if let Some(s) = &self.outer {
            s.validate(
                "outer race",
                (2.0 * PI * g.outer_race_radius_m() / n).min(d),
            )?;
        }
        if let Some(s) = &self.ball {
            s.validate("ball", d)?;
        }
        Ok(())
    }
}

/// Check a fault onset `T_f` given for a recording of `duration_s` seconds (sample `k` at
/// `k / fs`, so the recording covers `[0, duration_s)`): a finite time `>= 0` before the end,
/// or the fault would never appear.
///
/// # Errors
/// [`ModelError::InvalidOnset`] for a negative or non-finite onset,
/// [`ModelError::OnsetAfterEnd`] for an onset at or after `duration_s`.
pub fn check_onset(onset_s: f64, duration_s: f64) -> Result<()> {
    if !(onset_s.is_finite() && onset_s >= 0.0) {
        return Err(ModelError::InvalidOnset { onset_s });
    }
    if onset_s >= duration_s {
        return Err(ModelError::OnsetAfterEnd {
            onset_s,
            duration_s,
        });
    }
    Ok(())
}

/// Where one spall sits: the three locations a [`FaultClass`] combines. The workspace's one
/// fault-location type (the rig's calibrated paths and severities, the diagnosis' hypotheses).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum FaultLocation {
    /// Inner race (impacts at BPFI).
    Inner,
    /// Outer race (impacts at BPFO).
    Outer,
    /// Rolling element (impacts at the ball-defect rate, CWRU's BSF).
    Ball,
}

impl FaultLocation {
    /// All three, in verdict order.
    pub const ALL: [FaultLocation; 3] = [Self::Inner, Self::Outer, Self::Ball];

    /// `inner`, `outer`, `ball` (as [`FaultClass::name`] spells the single-location classes).
    pub fn name(self) -> &'static str {
        match self {
            Self::Inner => "inner",
            Self::Outer => "outer",
            Self::Ball => "ball",
        }
    }

    /// The single-location class.
    pub fn class(self) -> FaultClass {
        match self {
            Self::Inner => FaultClass::Inner,
            Self::Outer => FaultClass::Outer,
            Self::Ball => FaultClass::Ball,
        }
    }

    /// Whether `class` has a spall here.
    pub fn in_class(self, class: FaultClass) -> bool {
        match self {
            Self::Inner => class.has_inner(),
            Self::Outer => class.has_outer(),
            Self::Ball => class.has_ball(),
        }
    }
}

impl std::fmt::Display for FaultLocation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The eight classes of the SHSE multi-fault data (Table 4.1) and of `cargo xtask simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum FaultClass {
    /// Healthy.
    None,
    /// Inner race.
    Inner,
    /// Outer race.
    Outer,
    /// Ball.
    Ball,
    /// Inner + outer race.
    InnerOuter,
    /// Inner race + ball.
    InnerBall,
    /// Outer race + ball.
    OuterBall,
    /// Inner + outer race + ball.
    InnerOuterBall,
}

impl FaultClass {
    /// All eight classes, in the dissertation's order.
    pub const ALL: [FaultClass; 8] = [
        FaultClass::None,
        FaultClass::Inner,
        FaultClass::Outer,
        FaultClass::Ball,
        FaultClass::InnerOuter,
        FaultClass::InnerBall,
        FaultClass::OuterBall,
        FaultClass::InnerOuterBall,
    ];

    /// Has an inner-race spall.
    pub fn has_inner(self) -> bool {
        matches!(
            self,
            Self::Inner | Self::InnerOuter | Self::InnerBall | Self::InnerOuterBall
        )
    }

    /// Has an outer-race spall.
    pub fn has_outer(self) -> bool {
        matches!(
            self,
            Self::Outer | Self::InnerOuter | Self::OuterBall | Self::InnerOuterBall
        )
    }

    /// Has a ball spall.
    pub fn has_ball(self) -> bool {
        matches!(
            self,
            Self::Ball | Self::InnerBall | Self::OuterBall | Self::InnerOuterBall
        )
    }

    /// The locations with a spall, in [`FaultLocation::ALL`] order (empty when healthy).
    pub fn locations(self) -> Vec<FaultLocation> {
        FaultLocation::ALL
            .into_iter()
            .filter(|l| l.in_class(self))
            .collect()
    }

    /// The class with spalls at exactly `locations` (duplicates ignored; empty = healthy).
    pub fn from_locations(locations: &[FaultLocation]) -> Self {
        let has = |l| locations.contains(&l);
        match (
            has(FaultLocation::Inner),
            has(FaultLocation::Outer),
            has(FaultLocation::Ball),
        ) {
            (false, false, false) => Self::None,
            (true, false, false) => Self::Inner,
            (false, true, false) => Self::Outer,
            (false, false, true) => Self::Ball,
            (true, true, false) => Self::InnerOuter,
            (true, false, true) => Self::InnerBall,
            (false, true, true) => Self::OuterBall,
            (true, true, true) => Self::InnerOuterBall,
        }
    }

    /// Name as the CLI spells it (`"inner+outer"`).
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Inner => "inner",
            Self::Outer => "outer",
            Self::Ball => "ball",
            Self::InnerOuter => "inner+outer",
            Self::InnerBall => "inner+ball",
            Self::OuterBall => "outer+ball",
            Self::InnerOuterBall => "inner+outer+ball",
        }
    }
}

impl std::fmt::Display for FaultClass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FaultClass {
    type Err = ModelError;
    /// Parses `none|normal|healthy`, and any `+`/`-`/`,`-joined set of `inner|ir`, `outer|or`,
    /// `ball|b` in any order, each location at most once. The workspace's one fault-spec parser
    /// (`simulate --fault`, close-loop's `parse_fault`).
    ///
    /// # Errors
    /// [`ModelError::UnknownFaultClass`] for an unknown part, [`ModelError::RepeatedFaultLocation`]
    /// for a location named twice (`inner+inner`, `ball+ir+b`).
    fn from_str(s: &str) -> Result<Self> {
        let low = s.trim().to_ascii_lowercase();
        if matches!(low.as_str(), "none" | "normal" | "healthy") {
            return Ok(Self::None);
        }
        let mut locations = Vec::new();
        for part in low.split(['+', '-', ',']) {
            let location = match part.trim() {
                "inner" | "ir" => FaultLocation::Inner,
                "outer" | "or" => FaultLocation::Outer,
                "ball" | "b" => FaultLocation::Ball,
                _ => return Err(ModelError::UnknownFaultClass(s.to_string())),
            };
            if locations.contains(&location) {
                return Err(ModelError::RepeatedFaultLocation {
                    spec: s.trim().to_string(),
                    location,
                });
            }
            locations.push(location);
        }
        Ok(Self::from_locations(&locations))
    }
}

/// Precomputed spall profile for the inner loop.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SpallProfile {
    /// Angular width on the surface it is measured on (rad).
    pub width_rad: f64,
    /// Radius converting angle to arc length (race contact radius or ball radius).
    pub arc_radius: f64,
    /// Half width (m): `u` never exceeds it.
    pub half_width: f64,
    /// Ball radius.
    pub r_ball: f64,
    /// Race radius whose curvature adds (+1) or subtracts (−1).
    pub r_race: f64,
    /// +1 for the convex inner race, −1 for the concave outer race.
    pub sign: f64,
    /// Depth cap.
    pub depth: f64,
    /// Entry angle at t = 0.
    pub angle0: f64,
    /// Onset time.
    pub onset: f64,
}

impl SpallProfile {
    pub(crate) fn new(s: &Spall, arc_radius: f64, r_ball: f64, r_race: f64, sign: f64) -> Self {
        Self {
            width_rad: s.width_m / arc_radius,
            arc_radius,
            half_width: 0.5 * s.width_m,
            r_ball,
            r_race,
            sign,
            depth: s.depth_m,
            angle0: s.angle_rad,
            onset: s.onset_s,
        }
    }

    /// Extra clearance when the contact point is `rel` radians past the entry edge
    /// (`rel` already wrapped to `[0, 2π)`).
    #[inline(always)]
    pub(crate) fn drop(&self, rel: f64) -> f64 {
        if rel >= self.width_rad {
            return 0.0;
        }
        let s = rel * self.arc_radius;
        let u = s.min(2.0 * self.half_width - s).clamp(0.0, self.half_width);
        let cr = chord_depth(self.r_ball, u);
        let c_race = chord_depth(self.r_race, u);
        (cr + self.sign * c_race).clamp(0.0, self.depth)
    }
}

/// `R − √(R² − u²)` (eqs. 2.22–2.23 read as chord depths), with `u` clamped to `R`.
#[inline(always)]
fn chord_depth(r: f64, u: f64) -> f64 {
    let u = u.min(r);
    // u² / (R + √(R² − u²)) is the same quantity without cancellation.
    u * u / (r + (r * r - u * u).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_classes() {
        for c in FaultClass::ALL {
            assert_eq!(c.name().parse::<FaultClass>().unwrap(), c);
        }
        assert_eq!(
            "OR+IR".parse::<FaultClass>().unwrap(),
            FaultClass::InnerOuter
        );
        assert!("cage".parse::<FaultClass>().is_err());
        assert!("".parse::<FaultClass>().is_err());
    }

    #[test]
    fn a_location_named_twice_is_a_typed_error() {
        for (spec, location) in [
            ("inner+inner", FaultLocation::Inner),
            ("outer+outer", FaultLocation::Outer),
            ("ball+inner+ball", FaultLocation::Ball),
            ("IR+inner", FaultLocation::Inner),
            ("outer-ball-or", FaultLocation::Outer),
        ] {
            let e = spec.parse::<FaultClass>().unwrap_err();
            assert_eq!(
                e,
                ModelError::RepeatedFaultLocation {
                    spec: spec.to_string(),
                    location
                },
                "{spec}"
            );
            let msg = e.to_string();
            assert!(!msg.contains('\n'), "{msg}");
            assert!(msg.contains(&format!("{location} twice")), "{msg}");
        }
        // every location once, in any order, is still a class
        assert_eq!(
            "ball+outer+inner".parse::<FaultClass>().unwrap(),
            FaultClass::InnerOuterBall
        );
    }

    #[test]
    fn profile_is_continuous_and_capped() {
        let g = BearingGeometry::skf_6205();
        let s = Spall::new(0.5e-3);
        let p = SpallProfile::new(
            &s,
            g.outer_race_radius_m(),
            g.ball_diameter_m / 2.0,
            g.outer_race_radius_m(),
            -1.0,
        );
        assert_eq!(p.drop(0.0), 0.0);
        assert_eq!(p.drop(p.width_rad), 0.0);
        let mid = p.drop(0.5 * p.width_rad);
        // hand value: c_r(0.25 mm) − c_R(0.25 mm), r = 3.97 mm, R = 23.5 mm
        let r = g.ball_diameter_m / 2.0;
        let big_r = g.outer_race_radius_m();
        let u: f64 = 0.25e-3;
        let want = (r - (r * r - u * u).sqrt()) - (big_r - (big_r * big_r - u * u).sqrt());
        assert!((mid - want).abs() < 1e-15);
        // continuity near the edges
        assert!(p.drop(1e-9) < 1e-12);
        assert!(p.drop(p.width_rad - 1e-9) < 1e-12);
        let deep = SpallProfile::new(&Spall::new(6e-3).with_depth(1e-4), r, r, big_r, -1.0);
        assert!((deep.drop(0.5 * deep.width_rad) - 1e-4).abs() < 1e-15);
    }

    #[test]
    fn onsets_must_fall_inside_the_recording() {
        assert!(check_onset(0.0, 1.0).is_ok());
        assert!(check_onset(0.999, 1.0).is_ok());
        for bad in [-0.1, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(
                matches!(check_onset(bad, 1.0), Err(ModelError::InvalidOnset { .. })),
                "{bad}"
            );
        }
        for late in [1.0, 5.0] {
            let e = check_onset(late, 1.0).unwrap_err();
            assert_eq!(
                e,
                ModelError::OnsetAfterEnd {
                    onset_s: late,
                    duration_s: 1.0
                }
            );
            let msg = e.to_string();
            assert!(!msg.contains('\n') && msg.contains("onset") && msg.contains("1 s"));
        }
        // a spall present from the start (onset −∞) always passes; a late one does not
        let f = FaultSet::of_class(FaultClass::Outer, Spall::new(1e-3));
        assert!(f.check_onsets(0.5).is_ok());
        let late = FaultSet::of_class(FaultClass::Outer, Spall::new(1e-3).with_onset(0.5));
        assert!(late.check_onsets(0.5).is_err());
        assert!(late.check_onsets(0.6).is_ok());
    }

    #[test]
    fn spall_validation() {
        let g = BearingGeometry::skf_6205();
        let f = FaultSet {
            outer: Some(Spall::new(-1.0)),
            ..FaultSet::default()
        };
        assert!(f.validate(&g).is_err());
        let f = FaultSet {
            inner: Some(Spall::new(9e-3)),
            ..FaultSet::default()
        };
        assert!(matches!(
            f.validate(&g),
            Err(ModelError::SpallTooWide { .. })
        ));
        let f = FaultSet::of_class(FaultClass::InnerOuterBall, Spall::new(6e-3));
        assert!(f.validate(&g).is_ok());
    }
}
