//! The declared model: operating point, bearing kinematics and the [`DeclaredModel`] trait the loop
//! runs against the measurement.

use crate::CloseLoopError;
use serde::Serialize;

/// Characteristic defect frequencies of a rolling bearing as multiples of the shaft rate fr
/// (eqs. for BPFO = n/2·(1 − r), BPFI = n/2·(1 + r), FTF = ½(1 − r), BSF = (D/d)(1 − r²),
/// r = d/D·cos α; the BSF is the twice-per-spin ball-defect rate, as in the CWRU table).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BearingRates {
    /// Designation, e.g. "6205".
    pub name: &'static str,
    /// Ball-pass frequency, outer race, × fr.
    pub bpfo: f64,
    /// Ball-pass frequency, inner race, × fr.
    pub bpfi: f64,
    /// Fundamental train (cage) frequency, × fr.
    pub ftf: f64,
    /// Ball-defect rate (2 × ball spin), × fr.
    pub bsf: f64,
}

impl BearingRates {
    /// From geometry: `n` balls, ball diameter `d`, pitch diameter `pitch` (any one length
    /// unit), contact angle (rad). The kinematics are `bearing-model`'s
    /// ([`bearing_model::BearingGeometry::orders`]), so there is one copy of the formulas.
    ///
    /// # Errors
    /// [`CloseLoopError::ParameterOutOfRange`] when the geometry is not physical (at least 3
    /// balls, 0 < d < D, balls fit on the pitch circle, angle in [0, π/2)).
    pub fn from_geometry(
        name: &'static str,
        n: u32,
        d: f64,
        pitch: f64,
        contact_angle: f64,
    ) -> Result<Self, CloseLoopError> {
        let g =
            bearing_model::BearingGeometry::from_dimensions(n as usize, d, pitch, contact_angle)
                .map_err(|_| CloseLoopError::ParameterOutOfRange {
                    name: "bearing geometry (ball diameter)",
                    value: d,
                    min: 0.0,
                    max: pitch,
                })?;
        Ok(Self::from_orders(name, g.orders()))
    }

    /// From `bearing-model`'s defect orders (the BSF here is its ball-defect rate).
    pub fn from_orders(name: &'static str, o: bearing_model::FaultOrders) -> Self {
        Self {
            name,
            bpfo: o.bpfo,
            bpfi: o.bpfi,
            ftf: o.ftf,
            bsf: o.ball_defect,
        }
    }

    /// The rates of one of `bearing-model`'s built-in bearings, under the designation the
    /// machine model and `from_name` use ("6205", "6203").
    ///
    /// # Errors
    /// [`CloseLoopError::UnknownBearing`] for a bearing this table does not name.
    pub fn of(bearing: bearing_model::Bearing) -> Result<Self, CloseLoopError> {
        let name = match bearing {
            bearing_model::Bearing::Skf6205 => "6205",
            bearing_model::Bearing::Skf6203 => "6203",
            other => {
                return Err(CloseLoopError::UnknownBearing {
                    name: format!("{other:?}"),
                });
            }
        };
        Ok(Self::from_orders(name, bearing.geometry().orders()))
    }

    /// SKF 6205-2RS JEM (CWRU drive end): 9 balls, d = 0.3126 in, D = 1.537 in.
    pub fn skf6205() -> Self {
        Self::from_orders("6205", bearing_model::Bearing::Skf6205.geometry().orders())
    }

    /// SKF 6203-2RS JEM (CWRU fan end): 8 balls, d = 0.2656 in, D = 1.122 in.
    pub fn skf6203() -> Self {
        Self::from_orders("6203", bearing_model::Bearing::Skf6203.geometry().orders())
    }

    /// Look a designation up in the built-in table ("6205", "6203"; an "skf" prefix is accepted).
    ///
    /// # Errors
    /// [`CloseLoopError::UnknownBearing`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, CloseLoopError> {
        let key = name.trim().to_ascii_lowercase();
        let key = key.trim_start_matches("skf").trim_start_matches('-');
        match key {
            "6205" | "6205-2rs" => Ok(Self::skf6205()),
            "6203" | "6203-2rs" => Ok(Self::skf6203()),
            _ => Err(CloseLoopError::UnknownBearing {
                name: name.to_string(),
            }),
        }
    }
}

/// The fault the model is told about: bearing-model's [`bearing_model::FaultClass`] (healthy,
/// inner, outer, ball or any combination) — one fault vocabulary for the workspace.
pub type DeclaredFault = bearing_model::FaultClass;

/// Impact rates of the declared fault(s) as multiples of fr (empty when healthy): BPFI for an
/// inner-race spall, BPFO for an outer-race spall, the ball-defect rate for a ball spall.
pub fn impact_orders(fault: DeclaredFault, rates: &BearingRates) -> Vec<f64> {
    let mut v = Vec::new();
    if fault.has_inner() {
        v.push(rates.bpfi);
    }
    if fault.has_outer() {
        v.push(rates.bpfo);
    }
    if fault.has_ball() {
        v.push(rates.bsf);
    }
    v
}

/// Parse "none|normal|healthy" or any `+`-joined set of "inner|ir", "outer|or", "ball|b".
///
/// # Errors
/// [`CloseLoopError::UnknownFault`] for anything else.
pub fn parse_fault(s: &str) -> Result<DeclaredFault, CloseLoopError> {
    s.parse::<DeclaredFault>()
        .map_err(|_| CloseLoopError::UnknownFault {
            name: s.to_string(),
        })
}

/// What the model is told: speed, bearing and fault.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OperatingPoint {
    /// Shaft speed, rpm.
    pub rpm: f64,
    /// Bearing defect rates.
    pub bearing: BearingRates,
    /// Declared fault.
    pub fault: DeclaredFault,
}

impl OperatingPoint {
    /// A checked operating point.
    ///
    /// # Errors
    /// [`CloseLoopError::InvalidRpm`] unless `rpm` is finite and positive.
    pub fn new(
        rpm: f64,
        bearing: BearingRates,
        fault: DeclaredFault,
    ) -> Result<Self, CloseLoopError> {
        if !(rpm.is_finite() && rpm > 0.0) {
            return Err(CloseLoopError::InvalidRpm { rpm });
        }
        Ok(Self {
            rpm,
            bearing,
            fault,
        })
    }

    /// Shaft rate fr = rpm / 60, Hz.
    pub fn shaft_hz(&self) -> f64 {
        self.rpm / 60.0
    }

    /// The same operating point with the speed scaled by `ratio`.
    pub fn with_speed_ratio(&self, ratio: f64) -> Self {
        Self {
            rpm: self.rpm * ratio,
            ..*self
        }
    }
}

/// A model of the measured channel that the loop can run at an operating point.
///
/// The loop treats the output as a realisation of the model's measured-channel signal: its
/// spectrum and envelope are compared with the measurement's (the phases of a free-running
/// simulation are not aligned with a recording). The 5-DOF physics model, an ARX-Laguerre model
/// driven by its own innovation, or [`crate::scenario::PhenomenologicalModel`] implement it.
pub trait DeclaredModel {
    /// Short name for reports ("physics", "arx-laguerre", …).
    fn name(&self) -> &str;
    /// Simulate `n` samples at `fs` Hz at the operating point `op`.
    ///
    /// # Errors
    /// Whatever the model cannot do, as [`CloseLoopError::Model`].
    fn simulate(&self, op: &OperatingPoint, n: usize, fs: f64) -> Result<Vec<f64>, CloseLoopError>;

    /// The model's expected one-sided PSD (units²/Hz) on the grid k·fs/`nperseg`,
    /// k = 0..=nperseg/2, when it is known in closed form (`None`: the loop takes the Welch PSD of
    /// [`DeclaredModel::simulate`]'s output, which carries the estimate's own variance).
    fn expected_psd(&self, _op: &OperatingPoint, _nperseg: usize, _fs: f64) -> Option<Vec<f64>> {
        None
    }

    /// The observer that runs this model against the measurement for the residual-RMS metric
    /// (default: ALPIO on an ARX-Laguerre model identified on the fitting segment).
    fn residual_observer(&self, _fs: f64) -> crate::observe::ResidualObserver {
        crate::observe::ResidualObserver::ArxLaguerre
    }

    /// The model with an added shaft-harmonic force of order `order`, amplitude `amplitude_n`
    /// (N) and phase `phase_rad`, when the model has a shaft (`None` otherwise: the effect then
    /// stays a sensor line).
    fn with_shaft_force(
        &self,
        _order: u32,
        _amplitude_n: f64,
        _phase_rad: f64,
    ) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// The model with its measured-channel (housing) mode moved to `frequency_hz`, damping
    /// `damping_ratio`, when it has one (`None` otherwise: a mode is then a channel filter).
    fn with_housing_mode(
        &self,
        _frequency_hz: f64,
        _damping_ratio: f64,
    ) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// The model's random slip fraction, if it has slip.
    fn slip_fraction(&self) -> Option<f64> {
        None
    }

    /// The model with another slip fraction (`None` when it has no slip).
    fn with_slip_fraction(&self, _fraction: f64) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// The model's own measured-channel mode (frequency Hz, damping ratio), if it has one.
    fn housing_mode(&self) -> Option<(f64, f64)> {
        None
    }
}
