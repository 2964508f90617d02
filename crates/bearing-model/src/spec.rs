//! Bearing specifications: a designation (`6205`, `6203`), a geometry
//! (`n=8,d=0.235in,D=1.245in,angle=0deg`, lengths in mm, in or m) or the four fault multiples
//! directly (`bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135`, BSF in CWRU's convention: the
//! ball-defect rate, twice the ball spin).
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
    /// Designation or the spec text (for reports).
    pub name: String,
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
            geometry: Some(g),
            orders: g.orders(),
        })
    }

    /// Parse a spec (see the module documentation).
    ///
    /// # Errors
    /// [`ModelError::UnknownBearing`] for an unknown designation,
    /// [`ModelError::InvalidBearingSpec`] for a malformed or unphysical geometry/multiples.
    pub fn parse(spec: &str) -> Result<Self> {
        let s = spec.trim();
        if !s.contains('=') {
            return s
                .parse::<Bearing>()
                .map(Self::builtin)
                .map_err(|_| ModelError::UnknownBearing(s.to_string()));
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
            return Ok(Self {
                name: format!(
                    "multiples bpfo={} bpfi={} ftf={} bsf={}",
                    vals[0], vals[1], vals[2], vals[3]
                ),
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
