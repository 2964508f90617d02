//! Bearing specifications: a designation from the catalogue (`6205`, `UC204`, `ZA-2115`;
//! [`crate::catalog`]), a geometry
//! (`n=8,d=0.235in,D=1.245in,angle=0deg`, lengths in mm, in or m) or the four fault multiples
//! directly (`bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135`, BSF in CWRU's convention: the
//! ball-defect rate, twice the ball spin).
//!
//! Multiples are checked against the kinematics: `bpfo + bpfi = n`, `ftf = bpfo / n` and
//! `d/D·cos α = 1 − 2·ftf` give the ball spin `(D/2d)(1 − (d/D·cos α)²)` (taking `cos α = 1`)
//! and the ball-defect rate, twice it. A `bsf` within 2 % of the spin is the textbook ball-spin
//! frequency given by mistake (an error); one within 5 % of neither is reported by
//! [`BearingSpec::warnings`] (catalogues round, and a contact angle lowers the rate).
//!
//! The kinematics are [`BearingGeometry::orders`] and [`FaultOrders`]; this module only parses
//! text into them. The one bearing type every crate names a bearing with (diagnosis,
//! close-loop, the command line).

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, Result};
use crate::geometry::{Bearing, BearingGeometry, FaultOrders};

/// A bearing as the diagnosis needs it: a name for reports, the geometry when known, and the
/// fault orders (multiples of the shaft frequency).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BearingSpec {
    /// Designation or the normalised spec (what machine models compare; `multiples bpfo=…`,
    /// `n=…,d=…m,D=…m,angle=…rad`).
    pub name: String,
    /// The spec as the user gave it (trimmed, case kept): what reports echo
    /// ([`BearingSpec::echo`]); the designation for a bearing built in code.
    #[serde(default)]
    pub given: String,
    /// Geometry, when the spec gives one (built-in or `n=…,d=…,D=…`).
    pub geometry: Option<BearingGeometry>,
    /// Fault orders (× shaft frequency); `ball_defect` is CWRU's "BSF".
    pub orders: FaultOrders,
}

impl BearingSpec {
    /// A built-in bearing.
    pub fn builtin(b: Bearing) -> Self {
        let g = b.geometry();
        Self {
            name: g.name.to_string(),
            given: b.designation().to_string(),
            geometry: Some(g),
            orders: g.orders(),
        }
    }

    /// A built-in bearing under its short designation ("6205", "6203"): the name machine models
    /// and the closed loop's reports use.
    pub fn designated(b: Bearing) -> Self {
        Self {
            name: b.designation().to_string(),
            ..Self::builtin(b)
        }
    }

    /// Shaft-rate multiples of the declared impacts of `fault` (BPFI for an inner-race spall,
    /// BPFO for an outer-race spall, the ball-defect rate for a ball spall; empty when healthy).
    pub fn impact_orders(&self, fault: crate::FaultClass) -> Vec<f64> {
        let mut v = Vec::new();
        if fault.has_inner() {
            v.push(self.orders.bpfi);
        }
        if fault.has_outer() {
            v.push(self.orders.bpfo);
        }
        if fault.has_ball() {
            v.push(self.orders.ball_defect);
        }
        v
    }

    /// A bearing from its geometry (validated).
    ///
    /// # Errors
    /// [`ModelError::InvalidBearingSpec`] when the geometry is not physical.
    pub fn from_geometry(g: BearingGeometry) -> Result<Self> {
        g.validate().map_err(|e| ModelError::InvalidBearingSpec {
            spec: g.name.to_string(),
            reason: e.to_string(),
        })?;
        Ok(Self {
            name: g.name.to_string(),
            given: g.name.to_string(),
            geometry: Some(g),
            orders: g.orders(),
        })
    }

    /// The spec as reports echo it: as the user gave it, with a built-in bearing's full
    /// designation after it when that differs (`6205 (SKF 6205-2RS JEM)`); the name for a spec
    /// read from a file written before the given text was kept.
    pub fn echo(&self) -> String {
        if self.given.is_empty() {
            return self.name.clone();
        }
        match self.geometry.map(|g| g.name) {
            Some(full) if !full.is_empty() && full != "custom" && full != self.given => {
                format!("{} ({full})", self.given)
            }
            _ => self.given.clone(),
        }
    }

    /// What looks wrong without being an error, one line each: multiples whose `bsf` is within
    /// 5 % of neither the ball-defect rate nor the spin that `ftf` implies
    /// ([`ball_rates_implied`]). Empty for a designation or a geometry (consistent by
    /// construction).
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.geometry.is_some() {
            return w;
        }
        let o = &self.orders;
        if let Some((spin, defect)) = ball_rates_implied(o.ftf)
            && !within(o.ball_defect, defect, BSF_TOLERANCE)
            && !within(o.ball_defect, spin, SPIN_TOLERANCE)
        {
            w.push(format!(
                "bearing `{}`: bsf={} is {:+.1} % from the ball-defect rate {defect:.4} that ftf implies (ball spin {spin:.4}; bsf is CWRU's ball-defect rate, twice the spin): check the value",
                self.echo(),
                o.ball_defect,
                100.0 * (o.ball_defect / defect - 1.0)
            ));
        }
        w
    }

    /// A bearing from the catalogue by its designation ([`crate::catalog::lookup`]: case,
    /// spaces, a maker's name and seal or clearance suffixes ignored), named by the catalogue's
    /// name, with its geometry, echoing `text` (trimmed). The CWRU 6205 and 6203 are
    /// [`BearingSpec::builtin`]'s.
    ///
    /// # Errors
    /// [`ModelError::UnknownBearing`] when the catalogue holds no such bearing (its message
    /// lists the nearest designations).
    pub fn designation(text: &str) -> Result<Self> {
        crate::catalog::lookup(text).map(|e| e.spec(text))
    }

    /// Parse a spec (see the module documentation): anything without `=` is a designation
    /// ([`BearingSpec::designation`]).
    ///
    /// # Errors
    /// [`ModelError::UnknownBearing`] for an unknown designation,
    /// [`ModelError::InvalidBearingSpec`] for a malformed or unphysical geometry/multiples.
    pub fn parse(spec: &str) -> Result<Self> {
        let s = spec.trim();
        if !s.contains('=') {
            return Self::designation(s);
        }
        let bad = |reason: String| ModelError::InvalidBearingSpec {
            spec: s.to_string(),
            reason,
        };
        let mut pairs: Vec<(String, String)> = Vec::new();
        for part in s.split([',', ';', ' ']).filter(|p| !p.trim().is_empty()) {
            let (k, v) = part
                .split_once('=')
                .ok_or_else(|| bad(format!("`{part}` is not key=value")))?;
            let (k, v) = (k.trim().to_string(), v.trim().to_string());
            if pairs.iter().any(|(q, _)| *q == k) {
                return Err(bad(format!("`{k}` given twice")));
            }
            pairs.push((k, v));
        }
        let get = |keys: &[&str]| {
            pairs
                .iter()
                .find(|(k, _)| keys.contains(&k.as_str()))
                .map(|(_, v)| v.as_str())
        };
        let multiples = ["bpfo", "bpfi", "ftf", "bsf"];
        if pairs
            .iter()
            .any(|(k, _)| multiples.contains(&k.to_ascii_lowercase().as_str()))
        {
            let mut vals = [0.0; 4];
            for (i, name) in multiples.iter().enumerate() {
                let (_, v) = pairs
                    .iter()
                    .find(|(k, _)| k.eq_ignore_ascii_case(name))
                    .ok_or_else(|| {
                        bad(format!(
                            "missing `{name}` (give all of bpfo, bpfi, ftf, bsf)"
                        ))
                    })?;
                vals[i] = v
                    .parse::<f64>()
                    .map_err(|_| bad(format!("`{name}={v}` is not a number")))?;
            }
            if let Some((k, _)) = pairs
                .iter()
                .find(|(k, _)| !multiples.contains(&k.to_ascii_lowercase().as_str()))
            {
                return Err(bad(format!("unexpected key `{k}` beside the multiples")));
            }
            let orders = FaultOrders::from_multiples(vals[0], vals[1], vals[2], vals[3])
                .map_err(|e| bad(e.to_string()))?;
            let [bpfo, bpfi, ftf, bsf] = vals;
            if let Some((spin, ball_defect)) = ball_rates_implied(ftf)
                && within(bsf, spin, SPIN_TOLERANCE)
            {
                return Err(ModelError::BallSpinGivenAsBsf {
                    spec: s.to_string(),
                    bsf,
                    spin,
                    ball_defect,
                    doubled: 2.0 * bsf,
                });
            }
            return Ok(Self {
                name: format!("multiples bpfo={bpfo} bpfi={bpfi} ftf={ftf} bsf={bsf}"),
                given: s.to_string(),
                geometry: None,
                orders,
            });
        }
        let known = ["n", "balls", "d", "ball", "D", "pitch", "angle", "alpha"];
        if let Some((k, _)) = pairs.iter().find(|(k, _)| !known.contains(&k.as_str())) {
            return Err(bad(format!(
                "unknown key `{k}` (n, d, D, angle; or bpfo, bpfi, ftf, bsf)"
            )));
        }
        let n_text =
            get(&["n", "balls"]).ok_or_else(|| bad("missing `n` (number of balls)".into()))?;
        let n: usize = n_text
            .parse()
            .map_err(|_| bad(format!("`n={n_text}` is not a whole number")))?;
        let d =
            length_m(get(&["d", "ball"]).ok_or_else(|| bad("missing `d` (ball diameter)".into()))?)
                .map_err(|r| bad(format!("d: {r}")))?;
        let pitch = length_m(
            get(&["D", "pitch"]).ok_or_else(|| bad("missing `D` (pitch diameter)".into()))?,
        )
        .map_err(|r| bad(format!("D: {r}")))?;
        let angle = match get(&["angle", "alpha"]) {
            Some(a) => angle_rad(a).map_err(|r| bad(format!("angle: {r}")))?,
            None => 0.0,
        };
        let g =
            BearingGeometry::from_dimensions(n, d, pitch, angle).map_err(|e| bad(e.to_string()))?;
        Ok(Self {
            name: format!("n={n},d={d:.6}m,D={pitch:.6}m,angle={angle:.4}rad"),
            given: s.to_string(),
            geometry: Some(g),
            orders: g.orders(),
        })
    }
}

impl std::str::FromStr for BearingSpec {
    type Err = ModelError;
    fn from_str(s: &str) -> Result<Self> {
        Self::parse(s)
    }
}

/// Relative distance within which a `bsf` is taken for the ball spin (an error).
const SPIN_TOLERANCE: f64 = 0.02;
/// Relative distance from the implied ball-defect rate beyond which a `bsf` is warned about.
const BSF_TOLERANCE: f64 = 0.05;

/// Whether `x` is within `rel` (relative) of `reference`.
fn within(x: f64, reference: f64, rel: f64) -> bool {
    (x - reference).abs() <= rel * reference.abs()
}

/// The ball spin and ball-defect rate (shaft orders) that a cage order `ftf` implies:
/// `r = d/D·cos α = 1 − 2·ftf` (with `bpfo + bpfi = n` and `ftf = bpfo / n`) and, taking
/// `cos α = 1` (a contact angle lowers both by `cos α`), the spin `(1 − r²) / (2r)`, the
/// ball-defect rate twice it. `None` when `ftf` does not give `0 < r < 1`.
pub fn ball_rates_implied(ftf: f64) -> Option<(f64, f64)> {
    let r = 1.0 - 2.0 * ftf;
    if !(r.is_finite() && r > 0.0 && r < 1.0) {
        return None;
    }
    let spin = (1.0 - r * r) / (2.0 * r);
    Some((spin, 2.0 * spin))
}

/// `0.235in`, `5.97mm`, `0.00597m` → metres (a unit is required).
fn length_m(v: &str) -> std::result::Result<f64, String> {
    let v = v.trim();
    let (num, scale) = if let Some(x) = v.strip_suffix("mm") {
        (x, 1e-3)
    } else if let Some(x) = v.strip_suffix("in") {
        (x, 0.0254)
    } else if let Some(x) = v.strip_suffix('m') {
        (x, 1.0)
    } else {
        return Err(format!("`{v}` needs a unit: mm, in or m"));
    };
    let x: f64 = num
        .trim()
        .parse()
        .map_err(|_| format!("`{v}` is not a number with a unit"))?;
    if !(x.is_finite() && x > 0.0) {
        return Err(format!("`{v}` must be positive"));
    }
    Ok(x * scale)
}

/// `0deg`, `0.1rad`, or a bare number in degrees → radians.
fn angle_rad(v: &str) -> std::result::Result<f64, String> {
    let v = v.trim();
    let (num, scale) = if let Some(x) = v.strip_suffix("deg") {
        (x, std::f64::consts::PI / 180.0)
    } else if let Some(x) = v.strip_suffix("rad") {
        (x, 1.0)
    } else {
        (v, std::f64::consts::PI / 180.0)
    };
    let x: f64 = num
        .trim()
        .parse()
        .map_err(|_| format!("`{v}` is not an angle (e.g. 0deg, 0.26rad)"))?;
    if !x.is_finite() {
        return Err(format!("`{v}` is not finite"));
    }
    Ok(x * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        ((a - b) / b).abs() < rel
    }

    #[test]
    fn builtins() {
        let s = BearingSpec::parse("6205").unwrap();
        assert!(close(s.orders.bpfo, 3.5848, 1e-4));
        assert!(close(s.orders.ball_defect, 4.7135, 1e-4));
        let s = BearingSpec::parse(" 6203 ").unwrap();
        assert!(close(s.orders.bpfi, 4.9469, 2e-4));
        assert!(matches!(
            BearingSpec::parse("6306"),
            Err(ModelError::UnknownBearing(_))
        ));
    }

    #[test]
    fn geometry_in_inches_and_mm() {
        let a = BearingSpec::parse("n=9,d=0.3126in,D=1.537in,angle=0deg").unwrap();
        assert!(close(a.orders.bpfi, 5.4152, 1e-4));
        let b = BearingSpec::parse("n=9, d=7.94004mm, D=39.0398mm").unwrap();
        assert!(close(b.orders.bpfo, a.orders.bpfo, 1e-5));
        let c = BearingSpec::parse("n=8,d=0.235in,D=1.245in,angle=0deg").unwrap();
        assert!(close(c.orders.bpfo, 4.0 * (1.0 - 0.235 / 1.245), 1e-9));
        let t = BearingSpec::parse("n=10,d=8mm,D=40mm,angle=15deg").unwrap();
        let r = 0.2 * (15f64).to_radians().cos();
        assert!(close(t.orders.bpfi, 5.0 * (1.0 + r), 1e-9));
    }

    #[test]
    fn multiples() {
        let s = BearingSpec::parse("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135").unwrap();
        assert_eq!(s.orders.ball_defect, 4.7135);
        assert!(s.geometry.is_none());
    }

    #[test]
    fn a_textbook_ball_spin_as_bsf_is_a_typed_error() {
        // the 6205's textbook BSF (ball spin), half of CWRU's ball-defect rate
        let e = BearingSpec::parse("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=2.3567").unwrap_err();
        let ModelError::BallSpinGivenAsBsf {
            bsf,
            spin,
            ball_defect,
            doubled,
            ..
        } = e
        else {
            panic!("{e}");
        };
        assert_eq!(bsf, 2.3567);
        assert_eq!(doubled, 4.7134);
        assert!(close(spin, 2.3567, 1e-3) && close(ball_defect, 4.7135, 1e-3));
        let msg = e.to_string();
        assert!(
            msg.contains("ball-spin") && msg.contains("bsf=4.7134"),
            "{msg}"
        );
        assert!(!msg.contains('\n'));
        // the 6203's, within 2 % of its spin
        assert!(matches!(
            BearingSpec::parse("bpfo=3.0530,bpfi=4.9469,ftf=0.3817,bsf=1.97"),
            Err(ModelError::BallSpinGivenAsBsf { .. })
        ));
    }

    #[test]
    fn a_bsf_far_from_the_kinematics_is_warned_about() {
        // CWRU's own table: consistent, no warning
        let ok = BearingSpec::parse("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135").unwrap();
        assert!(ok.warnings().is_empty());
        // a catalogue's rounding (1 %) passes silently
        let rounded = BearingSpec::parse("bpfo=3.58,bpfi=5.42,ftf=0.398,bsf=4.76").unwrap();
        assert!(rounded.warnings().is_empty());
        // 10 % off: accepted, with one warning naming the implied rate
        let off = BearingSpec::parse("bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=5.2").unwrap();
        let w = off.warnings();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("4.71") && !w[0].contains('\n'), "{}", w[0]);
        // designations and geometries are consistent by construction
        assert!(BearingSpec::parse("6205").unwrap().warnings().is_empty());
        assert!(
            BearingSpec::parse("n=10,d=8mm,D=40mm,angle=15deg")
                .unwrap()
                .warnings()
                .is_empty()
        );
    }

    #[test]
    fn the_spec_is_echoed_as_given() {
        let typed = "BPFO=3.5848,BPFI=5.4152,FTF=0.39828,BSF=4.7135";
        let s = BearingSpec::parse(&format!("  {typed} ")).unwrap();
        assert_eq!(s.given, typed);
        assert_eq!(s.echo(), typed);
        let g = BearingSpec::parse("n=9, d=7.94004mm, D=39.0398mm").unwrap();
        assert_eq!(g.echo(), "n=9, d=7.94004mm, D=39.0398mm");
        let b = BearingSpec::parse("SKF6205").unwrap();
        assert_eq!(b.echo(), "SKF6205 (SKF 6205-2RS JEM)");
        assert_eq!(
            BearingSpec::designated(Bearing::Skf6203).echo(),
            "6203 (SKF 6203-2RS JEM)"
        );
        // an unknown designation is named as typed
        let e = BearingSpec::parse("SKF6306").unwrap_err();
        assert_eq!(e, ModelError::UnknownBearing("SKF6306".into()));
        let e = "NU205".parse::<Bearing>().unwrap_err();
        assert_eq!(e, ModelError::UnknownBearing("NU205".into()));
        // a spec read from a file written without `given` echoes its name
        let old = BearingSpec {
            given: String::new(),
            ..BearingSpec::parse(typed).unwrap()
        };
        assert_eq!(old.echo(), old.name);
    }

    #[test]
    fn malformed_specs_are_typed_errors() {
        for bad in [
            "n=9,d=0.3126,D=1.537in",                // no unit
            "n=9,d=2in,D=1.537in",                   // ball larger than pitch
            "n=9,D=1.537in",                         // missing d
            "n=x,d=1mm,D=10mm",                      // not a number
            "n=9,d=1mm,D=10mm,w=3",                  // unknown key
            "bpfo=3.58,bpfi=5.41,ftf=0.398",         // missing bsf
            "bpfo=5.41,bpfi=3.58,ftf=0.398,bsf=4.7", // swapped
            "bpfo=3.58,bpfi=5.41,ftf=0.398,bsf=nan",
            "n=9,n=9,d=1mm,D=10mm",
        ] {
            let e = BearingSpec::parse(bad).unwrap_err();
            assert!(
                matches!(e, ModelError::InvalidBearingSpec { .. }),
                "{bad}: {e}"
            );
            assert!(!e.to_string().contains('\n'));
        }
    }
}
