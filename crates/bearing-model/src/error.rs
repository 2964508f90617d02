//! The crate's single error type.

/// Everything that can go wrong when building or running the bearing model.
///
/// Every variant carries the offending numbers so a caller can print a useful message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// A parameter is NaN, infinite, or outside its documented range.
    #[error("parameter `{name}` = {value} is out of range (expected {expected})")]
    OutOfRange {
        /// Parameter name as written in the docs.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// A spall is wider than the surface it sits on allows.
    #[error(
        "{location} spall width {width_m} m exceeds the largest width the model supports ({max_m} m)"
    )]
    SpallTooWide {
        /// `"inner race"`, `"outer race"` or `"ball"`.
        location: &'static str,
        /// Requested width in metres.
        width_m: f64,
        /// Largest valid width in metres.
        max_m: f64,
    },
    /// The output sampling rate cannot represent the model's housing resonance.
    #[error(
        "sampling rate {fs_hz} Hz is too low for the model: the housing resonance at \
         {resonance_hz} Hz needs at least {required_hz} Hz"
    )]
    SamplingTooLow {
        /// Requested sampling rate.
        fs_hz: f64,
        /// Housing (sprung-mass) resonance of the model.
        resonance_hz: f64,
        /// Smallest accepted sampling rate.
        required_hz: f64,
    },
    /// The integrator step is too large for the stiffest linear mode of the model.
    #[error(
        "integration step {step_s} s is too large: the stiffest mode at {omega_rad_s} rad/s \
         needs a step below {max_step_s} s"
    )]
    StepTooLarge {
        /// Requested step.
        step_s: f64,
        /// Highest natural angular frequency found.
        omega_rad_s: f64,
        /// Largest accepted step.
        max_step_s: f64,
    },
    /// The Newton iteration for the static equilibrium did not converge.
    #[error("static equilibrium not found after {iterations} iterations (residual {residual_n} N)")]
    EquilibriumNotFound {
        /// Iterations performed.
        iterations: usize,
        /// Final force residual norm.
        residual_n: f64,
    },
    /// The linearised model's response cannot be computed at a frequency (a singular
    /// dynamic-stiffness matrix: an undamped mode exactly there, or a non-finite frequency).
    #[error("the linearised response at {frequency_hz} Hz is singular or not finite")]
    SingularResponse {
        /// The frequency asked for, Hz.
        frequency_hz: f64,
    },
    /// The simulated response became NaN or infinite.
    #[error("simulation diverged at t = {time_s} s")]
    Diverged {
        /// Simulation time at which a non-finite state appeared.
        time_s: f64,
    },
    /// The requested recording would be empty or absurdly long.
    #[error("recording of {samples} samples is not supported (1 ..= {max} samples)")]
    BadLength {
        /// Requested number of samples.
        samples: f64,
        /// Largest supported number.
        max: f64,
    },
    /// A fault-class name could not be parsed.
    #[error(
        "unknown fault class `{0}` (none|inner|outer|ball|inner+outer|inner+ball|outer+ball|inner+outer+ball)"
    )]
    UnknownFaultClass(String),
    /// A fault spec names one location twice (`inner+inner`, `ball+inner+ball`).
    #[error(
        "fault `{spec}` names {location} twice: give each of inner, outer, ball at most once (e.g. inner+outer)"
    )]
    RepeatedFaultLocation {
        /// The spec as given.
        spec: String,
        /// The location named more than once.
        location: crate::FaultLocation,
    },
    /// A fault onset that is negative or not finite.
    #[error(
        "fault onset {onset_s} s must be a finite time >= 0 s (omit it for a fault present from the start)"
    )]
    InvalidOnset {
        /// The onset given, s.
        onset_s: f64,
    },
    /// A fault onset at or after the end of the recording: the fault would never appear.
    #[error(
        "fault onset {onset_s} s is not before the end of the {duration_s} s recording: the fault would never appear"
    )]
    OnsetAfterEnd {
        /// The onset given, s.
        onset_s: f64,
        /// The recorded duration, s.
        duration_s: f64,
    },
    /// A parameter-set name could not be parsed.
    #[error("unknown parameter set `{0}` (table2.1|cwru)")]
    UnknownParamSet(String),
    /// A designation the bearing catalogue ([`crate::catalog`]) does not hold; the message
    /// lists the nearest catalogue rows ([`crate::catalog::nearest`]).
    #[error("unknown bearing \"{0}\": {hint}", hint = crate::catalog::unknown_hint(.0))]
    UnknownBearing(String),
    /// A catalogue bearing asked for as one of the model's built-in bearings
    /// ([`crate::Bearing`]: the 6205 and 6203), which it is not.
    #[error(
        "bearing `{given}` is the catalogue's {name}, not a built-in model bearing (6205, 6203): give it as a bearing spec, which carries its geometry"
    )]
    NotBuiltIn {
        /// The text as given.
        given: String,
        /// The catalogue row's name.
        name: &'static str,
    },
    /// Multiples whose `bsf` is the textbook ball-spin frequency, not CWRU's ball-defect rate.
    #[error(
        "invalid bearing spec `{spec}`: bsf={bsf} looks like the textbook ball-spin frequency (ftf implies a spin of {spin:.4} and a ball-defect rate of {ball_defect:.4}); bsf here is CWRU's ball-defect rate, twice the spin: give bsf={doubled}"
    )]
    BallSpinGivenAsBsf {
        /// The spec as given.
        spec: String,
        /// The `bsf` given.
        bsf: f64,
        /// The ball spin `ftf` implies (shaft orders).
        spin: f64,
        /// The ball-defect rate `ftf` implies (shaft orders).
        ball_defect: f64,
        /// `2 × bsf`: the value to give.
        doubled: f64,
    },
    /// A machine recipe or its drawn parameters are inconsistent ([`crate::machine`]).
    #[error("invalid machine recipe: {0}")]
    InvalidRecipe(String),
    /// A geometry or multiples spec that does not parse or is not physical.
    #[error("invalid bearing spec `{spec}`: {reason}")]
    InvalidBearingSpec {
        /// The spec as given.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, ModelError>;

/// Check that `value` is finite and within `[lo, hi]`.
pub(crate) fn check_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(ModelError::OutOfRange {
            name,
            value,
            expected,
        })
    }
}

/// Check that `value` is finite and strictly positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ModelError::OutOfRange {
            name,
            value,
            expected: "finite and > 0",
        })
    }
}
