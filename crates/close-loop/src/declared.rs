//! The declared model: operating point, bearing kinematics and the [`DeclaredModel`] trait the loop
//! runs against the measurement.

use crate::CloseLoopError;
use serde::Serialize;

/// A bearing as the loop is told it: `bearing-model`'s one bearing type (name, geometry when
/// known, defect orders as multiples of fr; [`BearingSpec::designated`] for the built-in
/// 6205 and 6203).
pub use bearing_model::BearingSpec;

/// The fault the model is told about: bearing-model's [`bearing_model::FaultClass`] (healthy,
/// inner, outer, ball or any combination) — one fault vocabulary for the workspace.
pub type DeclaredFault = bearing_model::FaultClass;

/// Impact rates of the declared fault(s) as multiples of fr (empty when healthy):
/// [`BearingSpec::impact_orders`].
pub fn impact_orders(fault: DeclaredFault, rates: &BearingSpec) -> Vec<f64> {
    rates.impact_orders(fault)
}

/// Parse "none|normal|healthy" or any `+`-joined set of "inner|ir", "outer|or", "ball|b", each
/// at most once: bearing-model's one fault-spec parser ([`DeclaredFault`]'s `FromStr`).
///
/// # Errors
/// [`CloseLoopError::RepeatedFault`] for a location named twice (`inner+inner`),
/// [`CloseLoopError::UnknownFault`] for anything else.
pub fn parse_fault(s: &str) -> Result<DeclaredFault, CloseLoopError> {
    s.parse::<DeclaredFault>().map_err(|e| match e {
        bearing_model::ModelError::RepeatedFaultLocation { spec, location } => {
            CloseLoopError::RepeatedFault {
                name: spec,
                location,
            }
        }
        _ => CloseLoopError::UnknownFault {
            name: s.to_string(),
        },
    })
}

/// What the model is told: speed, bearing and fault.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OperatingPoint {
    /// Shaft speed, rpm.
    pub rpm: f64,
    /// The bearing (its defect orders).
    pub bearing: BearingSpec,
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
        bearing: BearingSpec,
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
            ..self.clone()
        }
    }
}

/// A model of the measured channel that the loop can run at an operating point.
///
/// The loop treats the output as a realisation of the model's measured-channel signal: its
/// spectrum and envelope are compared with the measurement's (the phases of a free-running
/// simulation are not aligned with a recording). The 5-DOF physics model, an ARX-Laguerre model
/// driven by its own innovation, or [`crate::scenario::PhenomenologicalModel`] implement it.
///
/// `Send + Sync`: the loop evaluates its candidate families in parallel on one shared model.
pub trait DeclaredModel: Send + Sync {
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

    /// The linearised power response |T(f)|² of the model's output to a contact force at each
    /// of `freqs_hz`, at the operating point `op` and rate `fs`, with the housing mode as it is
    /// (`moved_to` = `None`) or moved to `(frequency_hz, damping_ratio)` — when the model can
    /// say without simulating (`None`, the default: the loop simulates the moved model).
    /// The ratio of two such responses ([`response_ratio`], moved / as is) is how the model's
    /// output PSD changes when the mode moves: the loop searches the housing frequency on that
    /// prediction and simulates only the frequency it settles on.
    fn housing_response(
        &self,
        _op: &OperatingPoint,
        _fs: f64,
        _moved_to: Option<(f64, f64)>,
        _freqs_hz: &[f64],
    ) -> Option<Vec<f64>> {
        None
    }

    /// The model's random slip fraction, if it has slip.
    fn slip_fraction(&self) -> Option<f64> {
        None
    }

    /// The declared fault's spall width, inches, if the model has one.
    fn fault_size_in(&self) -> Option<f64> {
        None
    }

    /// The model with another spall width, inches (`None` when it has none or `size_in` is not
    /// positive and finite).
    fn with_fault_size_in(&self, _size_in: f64) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// The largest slip fraction the model accepts, if it has slip and a limit.
    fn max_slip_fraction(&self) -> Option<f64> {
        None
    }

    /// The model with another slip fraction (`None` when it has no slip).
    fn with_slip_fraction(&self, _fraction: f64) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// The radial preload of every ball, m (a negative radial clearance; 0 = none), if the model
    /// has ball contacts.
    fn contact_preload_m(&self) -> Option<f64> {
        None
    }

    /// The model with every ball preloaded by `preload_m` (≥ 0; `None` when it has no contacts).
    fn with_contact_preload(&self, _preload_m: f64) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// Spalls the model carries beyond the declared fault ([`DeclaredModel::with_added_fault`]):
    /// location and width, inches.
    fn added_faults(&self) -> Vec<(bearing_model::FaultLocation, f64)> {
        Vec::new()
    }

    /// The model with a spall of width `size_in` (inches) at `location` besides the declared
    /// fault: a fault nobody declared (`None` when the model has no spalls, the location already
    /// has an added spall, or the width is not positive and finite). The declared fault's spall
    /// wins where both name one location: the caller offers only locations the declared fault
    /// leaves healthy.
    fn with_added_fault(
        &self,
        _location: bearing_model::FaultLocation,
        _size_in: f64,
    ) -> Option<Box<dyn DeclaredModel>> {
        None
    }

    /// The model's own measured-channel mode (frequency Hz, damping ratio), if it has one.
    fn housing_mode(&self) -> Option<(f64, f64)> {
        None
    }

    /// A key that is equal for two models exactly when their simulations are (every parameter
    /// and seed), so the loop simulates each (model, speed) once per run; `None` (the default)
    /// for a model that cannot say, which is then simulated every time it is asked.
    fn cache_key(&self) -> Option<String> {
        None
    }
}

/// The power ratio `to / from` of two [`DeclaredModel::housing_response`]s at `freqs_hz`
/// (moved / as is): `None` when a ratio is not finite or not
/// positive. An acceleration has no response at 0 Hz (both are round-off there); below the
/// modes the sprung mass moves with the pedestal, so the ratio's limit there is 1.
pub fn response_ratio(to: &[f64], from: &[f64], freqs_hz: &[f64]) -> Option<Vec<f64>> {
    to.iter()
        .zip(from)
        .zip(freqs_hz)
        .map(|((t, f), hz)| {
            if *hz == 0.0 {
                return Some(1.0);
            }
            let g = t / f;
            (g.is_finite() && g > 0.0).then_some(g)
        })
        .collect()
}
