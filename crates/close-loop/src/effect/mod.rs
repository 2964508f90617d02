//! The effect library: each candidate effect's parametric form and where it enters the model.
//!
//! This file holds the vocabulary: the [`EffectKind`]s, the [`Placement`]s and the [`Effect`]
//! enum with its kind, placement and characteristic frequency. `signal` holds the parametric
//! forms a fitted effect applies ([`CoherentLine`], [`Mode`], [`Modulation`], to a time signal or a PSD)
//! and their search bounds; `report` the effect's report form ([`Effect::parameters`],
//! [`Effect::describe`]).

use serde::{Deserialize, Serialize};

mod report;
mod signal;

pub use report::MAX_PLAUSIBLE_CONTACT_ANGLE_DEG;
#[allow(deprecated)]
pub use signal::Line;
pub use signal::{
    CoherentLine, MODE_GAIN_RANGE, MODE_MAX_DAMPING, MODE_MIN_DAMPING, MODULATION_MAX_DEPTH, Mode,
    Modulation, depth_at_bound, mode_at_bound,
};

/// The kinds of effect the loop can trace a residual to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EffectKind {
    /// A line not tied to the shaft (electrical pick-up, interference).
    Tone,
    /// A line at k × fr (unbalance at 1×, misalignment at 2×, looseness at higher orders).
    ShaftHarmonic,
    /// A structural mode the model lacks (gain > 0) or over-states / misplaces (gain < 0).
    Resonance,
    /// The true speed differs from the declared one: every kinematic line moves by one ratio.
    SpeedOffset,
    /// The impact train is amplitude-modulated at a rate such as fr or the cage rate.
    Modulation,
    /// The structural path from bearing to sensor (its modes), identified from the data: the
    /// broadband response the declared model lacked.
    StructuralPath,
    /// Many shaft orders at once: the shaft-synchronous vibration (coupling, gears, looseness).
    ShaftComb,
    /// An equally spaced comb of lines not tied to the shaft (electrical interference, mains).
    LineComb,
    /// Random ball slip other than declared: the spread of the impact times.
    Slip,
    /// The declared fault's impacts run at another rate than its geometry gives at the shaft's
    /// measured speed (the effective contact angle or pitch ratio differs from the catalogue's).
    DefectRate,
    /// The balls' radial preload other than declared: how much of the circumference the load
    /// zone spans, hence how strongly the shaft (inner race) or the cage (ball) modulates the
    /// fault's impacts.
    ContactPreload,
    /// The declared fault's spall width other than declared: the impacts' duration, hence the
    /// shape and level of their spectrum.
    FaultSize,
    /// A spall at a location nobody declared (a second fault beside the declared one, or a fault
    /// on a bearing declared healthy): its kinematic lines stand in the residual's envelope.
    BearingFault,
    /// The declared fault's impacts reach the sensor weaker below a corner frequency than the
    /// physics' path gives: a high-pass on the physics part. The impacts' path is identified
    /// where the impacts dominate (near the resonance); below, its gain is an extrapolation.
    ImpactsHighPass,
}

impl EffectKind {
    /// A setting of the model (the speed ratio, the slip, the structural path): taking it again
    /// replaces its value rather than adding a term.
    pub fn is_setting(self) -> bool {
        matches!(
            self,
            Self::SpeedOffset
                | Self::Slip
                | Self::StructuralPath
                | Self::DefectRate
                | Self::ContactPreload
                | Self::FaultSize
                | Self::ImpactsHighPass
        )
    }

    /// The JSON spelling ("tone", "shaft_harmonic", …).
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Tone => "tone",
            Self::ShaftHarmonic => "shaft_harmonic",
            Self::Resonance => "resonance",
            Self::SpeedOffset => "speed_offset",
            Self::Modulation => "modulation",
            Self::StructuralPath => "structural_path",
            Self::ShaftComb => "shaft_comb",
            Self::LineComb => "line_comb",
            Self::Slip => "slip",
            Self::DefectRate => "defect_rate",
            Self::ContactPreload => "contact_preload",
            Self::FaultSize => "fault_size",
            Self::BearingFault => "bearing_fault",
            Self::ImpactsHighPass => "impacts_high_pass",
        }
    }
}

/// Where an effect is put: into the physics (the declared model is re-simulated with it) or into
/// the measurement channel (a term applied to the model's output).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// Re-simulated in the declared model: a shaft force, a moved housing mode, a corrected speed.
    Physics,
    /// Applied to the model output: a pick-up line, a channel mode, a modulation of the output,
    /// or a shaft line when the declared model has no shaft (ARX-Laguerre).
    Measurement,
}

/// One effect found by the loop, with its fitted parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Effect {
    /// A measurement-channel line not tied to the shaft.
    Tone {
        /// The fitted line.
        line: CoherentLine,
    },
    /// A line at k × fr, read as a shaft force (unbalance, misalignment) seen through the structure.
    ShaftHarmonic {
        /// Order k (a half order k + ½ for looseness).
        order: f64,
        /// The fitted line at the sensor.
        line: CoherentLine,
        /// fr used to name the order, Hz.
        shaft_hz: f64,
        /// The shaft force (amplitude N, phase rad) re-simulated in the physics model that
        /// reproduces the line; `None` when the model has no shaft (the line stays a sensor term).
        force: Option<(f64, f64)>,
    },
    /// A structural mode.
    Resonance {
        /// The fitted mode. For a moved housing mode, `gain` is 0 and the mode is in the
        /// simulation.
        mode: Mode,
        /// `true`: the physics model's housing mode was moved to `mode.frequency_hz` and
        /// re-simulated; `false`: a parallel mode on the model output.
        housing: bool,
    },
    /// A corrected speed.
    SpeedOffset {
        /// True speed / declared speed (cumulative).
        ratio: f64,
        /// Change of the fault's impact rate relative to the model before this effect.
        step: f64,
        /// The fault's impact rate over its geometry's at this speed: 1 unless the recording's
        /// shaft lines measured the speed apart from the fault lines
        /// (`residual_features::speed::estimate_speed`).
        defect_rate: f64,
        /// The speed was read from the recording's shaft lines (`false`: the whole step of the
        /// fault lines is taken as the speed; the shaft lines were too weak to tell).
        shaft_measured: bool,
    },
    /// The declared fault's impact rate differs from the one its geometry gives at the shaft's
    /// measured speed: the fault lines move, the shaft lines stay.
    DefectRate {
        /// Impact rate / the geometry's at the shaft's speed (cumulative).
        ratio: f64,
        /// Change of the impact rate relative to the model before this effect.
        step: f64,
        /// Shaft speed / declared speed, as the model's lines have it (the recording's shaft
        /// comb agrees with it within 0.1 %, `SHAFT_AGREE`).
        shaft_ratio: f64,
        /// The fault's rate as a multiple of the shaft rate: the geometry's (declared) order.
        order: f64,
        /// The fault's fundamental at the true speed, Hz (order × ratio × true fr).
        frequency_hz: f64,
        /// The pitch ratio γ = d·cos α / D that gives this rate (the geometry's γ when the
        /// bearing gives none).
        effective_pitch_ratio: Option<f64>,
        /// The contact angle that gives `effective_pitch_ratio` with the catalogue's d and D
        /// (`None` when no angle does: γ above d / D, or no geometry).
        contact_angle_deg: Option<f64>,
    },
    /// Amplitude modulation of the modelled vibration.
    Modulation {
        /// The fitted modulation.
        modulation: Modulation,
        /// fm / fr.
        shaft_order: f64,
        /// Named rate: "shaft", "2x_shaft", "cage" or "other".
        rate: &'static str,
    },
    /// Shaft-synchronous lines at several orders of the refined shaft rate.
    ShaftComb {
        /// Refined shaft rate, Hz.
        shaft_hz: f64,
        /// Declared shaft rate, Hz.
        declared_shaft_hz: f64,
        /// The orders present.
        orders: Vec<f64>,
        /// The fitted lines.
        lines: Vec<CoherentLine>,
    },
    /// A re-simulated radial preload of the balls.
    ContactPreload {
        /// Fitted preload, m (every ball compressed by it at the centred position).
        preload_m: f64,
        /// Declared preload, m.
        declared_m: f64,
        /// The fault's rate moved with it by this step (a defect rate judged jointly: the
        /// preload's clean fault comb and the rate that lines it up are one change of the
        /// spectrum, neither of which lowers the error alone), and the resulting defect rate.
        rate: Option<(f64, f64)>,
    },
    /// A spall at a location the declared model leaves healthy, simulated with the declared one.
    AddedFault {
        /// Where.
        location: bearing_model::FaultLocation,
        /// Its impact rate as a multiple of the shaft rate (BPFI, BPFO or the ball-defect order).
        order: f64,
        /// Its impact rate at the model's speed, Hz.
        frequency_hz: f64,
        /// Fitted spall width, inches.
        size_in: f64,
        /// The training-free diagnosis's score of the location on the fitting segment, dB (the
        /// evidence that offered it: its lines in the envelope of the impulsive band).
        diagnosis_score_db: f64,
        /// The AR order of the structural path identified with it for its impacts (`None`: the
        /// impacts seen through the model's present shaping).
        path_order: Option<usize>,
        /// Whether `size_in` is at an end of the width search.
        at_bound: bool,
    },
    /// A re-simulated spall width of the declared fault.
    FaultSize {
        /// Fitted width, inches.
        size_in: f64,
        /// Declared width, inches.
        declared_in: f64,
        /// Whether `size_in` is at an end of the search (¼ or 4 × the declared width).
        at_bound: bool,
    },
    /// A high-pass on the physics part (see [`EffectKind::ImpactsHighPass`]).
    ImpactsHighPass {
        /// Corner frequency, Hz.
        corner_hz: f64,
        /// Butterworth order.
        order: u32,
        /// Whether `corner_hz` is at an end of the search.
        at_bound: bool,
    },
    /// A re-simulated slip fraction.
    Slip {
        /// Fitted slip fraction (of the ball spacing).
        fraction: f64,
        /// Declared slip fraction.
        declared: f64,
        /// Whether `fraction` is the largest the search tried: the data asks for at least this
        /// much smear of the fault lines, a broad correction rather than a resolved slip.
        at_bound: bool,
    },
    /// Equally spaced lines not tied to the shaft.
    LineComb {
        /// Spacing, Hz.
        spacing_hz: f64,
        /// The fitted lines.
        lines: Vec<CoherentLine>,
    },
    /// The structural path (AR model of the broadband response) identified from the data.
    StructuralPath {
        /// AR order chosen.
        order: usize,
        /// Its modes.
        modes: Vec<crate::path::PathMode>,
        /// `true`: the path the declared physics (the fault's impacts) is seen through;
        /// `false`: the path rung by broadband excitation.
        physics: bool,
    },
}

impl Effect {
    /// An effect on narrow lines (tone, shaft harmonic, comb, or a speed offset that moves the
    /// kinematic lines), detected by a test of its own that does not rest on the broadband level.
    pub fn is_line(&self) -> bool {
        matches!(
            self,
            Self::Tone { .. }
                | Self::ShaftHarmonic { .. }
                | Self::ShaftComb { .. }
                | Self::LineComb { .. }
                | Self::SpeedOffset { .. }
                | Self::DefectRate { .. }
        )
    }

    /// The step a speed or defect-rate effect makes in the rate the fault's impacts run at
    /// (`None` for every other effect).
    pub fn impact_rate_step(&self) -> Option<f64> {
        match self {
            Self::SpeedOffset { step, .. } | Self::DefectRate { step, .. } => Some(*step),
            _ => None,
        }
    }

    /// The speed ratio the declared physics is simulated at after a speed or defect-rate effect
    /// (true shaft speed × defect rate, over the declared speed).
    pub fn physics_ratio(&self) -> Option<f64> {
        match self {
            Self::SpeedOffset {
                ratio, defect_rate, ..
            } => Some(ratio * defect_rate),
            Self::DefectRate {
                ratio, shaft_ratio, ..
            } => Some(ratio * shaft_ratio),
            _ => None,
        }
    }

    /// A line subtracted phase-coherently in the measurement channel (a tone, a shaft harmonic
    /// kept as a sensor line, a shaft or line-frequency comb): what it explains shows directly
    /// in the held-out time-domain residual.
    pub fn is_coherent_line(&self) -> bool {
        matches!(
            self,
            Self::Tone { .. }
                | Self::ShaftHarmonic { force: None, .. }
                | Self::ShaftComb { .. }
                | Self::LineComb { .. }
        )
    }

    /// Its kind.
    pub fn kind(&self) -> EffectKind {
        match self {
            Self::Tone { .. } => EffectKind::Tone,
            Self::ShaftHarmonic { .. } => EffectKind::ShaftHarmonic,
            Self::Resonance { .. } => EffectKind::Resonance,
            Self::SpeedOffset { .. } => EffectKind::SpeedOffset,
            Self::Modulation { .. } => EffectKind::Modulation,
            Self::StructuralPath { .. } => EffectKind::StructuralPath,
            Self::ShaftComb { .. } => EffectKind::ShaftComb,
            Self::LineComb { .. } => EffectKind::LineComb,
            Self::Slip { .. } => EffectKind::Slip,
            Self::DefectRate { .. } => EffectKind::DefectRate,
            Self::ContactPreload { .. } => EffectKind::ContactPreload,
            Self::FaultSize { .. } => EffectKind::FaultSize,
            Self::AddedFault { .. } => EffectKind::BearingFault,
            Self::ImpactsHighPass { .. } => EffectKind::ImpactsHighPass,
        }
    }

    /// Where it goes in the model.
    pub fn placement(&self) -> Placement {
        match self {
            Self::SpeedOffset { .. }
            | Self::DefectRate { .. }
            | Self::ShaftHarmonic { force: Some(_), .. }
            | Self::Resonance { housing: true, .. }
            | Self::StructuralPath { .. }
            | Self::Slip { .. }
            | Self::FaultSize { .. }
            | Self::AddedFault { .. }
            | Self::ImpactsHighPass { .. }
            | Self::ContactPreload { .. } => Placement::Physics,
            _ => Placement::Measurement,
        }
    }

    /// The characteristic frequency (tone, harmonic, resonance or modulation rate); `None` for a
    /// speed offset.
    pub fn frequency_hz(&self) -> Option<f64> {
        match self {
            Self::Tone { line } | Self::ShaftHarmonic { line, .. } => Some(line.frequency_hz),
            Self::Resonance { mode, .. } => Some(mode.frequency_hz),
            Self::SpeedOffset { .. }
            | Self::Slip { .. }
            | Self::FaultSize { .. }
            | Self::ContactPreload { .. } => None,
            Self::DefectRate { frequency_hz, .. } | Self::AddedFault { frequency_hz, .. } => {
                Some(*frequency_hz)
            }
            Self::ImpactsHighPass { corner_hz, .. } => Some(*corner_hz),
            Self::Modulation { modulation, .. } => Some(modulation.frequency_hz),
            Self::StructuralPath { modes, .. } => dominant(modes).map(|m| m.frequency_hz),
            Self::ShaftComb { shaft_hz, .. } => Some(*shaft_hz),
            Self::LineComb { lines, .. } => strongest(lines).map(|l| l.frequency_hz),
        }
    }
}

/// The line with the largest amplitude.
fn strongest(lines: &[CoherentLine]) -> Option<&CoherentLine> {
    lines
        .iter()
        .max_by(|a, b| a.amplitude().total_cmp(&b.amplitude()))
}

/// The resonant mode with the highest PSD peak.
fn dominant(modes: &[crate::path::PathMode]) -> Option<&crate::path::PathMode> {
    modes
        .iter()
        .filter(|m| m.frequency_hz > 0.0)
        .max_by(|a, b| a.peak_psd.total_cmp(&b.peak_psd))
}

/// The multiple m·lf (m ≥ 1) of the declared mains frequency nearest `f`; `None` without a
/// declared mains frequency or when `f` is below half of it.
pub(crate) fn nearest_mains(f: f64, c: &crate::LoopConfig) -> Option<f64> {
    c.line_frequency_hz.and_then(|lf| {
        let m = (f / lf).round();
        (m >= 1.0).then_some(m * lf)
    })
}

/// Highest half order (k + ½) named a shaft harmonic (looseness shows half orders).
pub(crate) const MAX_HALF_ORDER: f64 = 5.5;

/// Name a line: a shaft harmonic when it sits within `harmonic_tolerance` of an order k·fr
/// (k = 1 … `max_harmonic_order`) or a half order (½ … 5½) and nearer to it than to a multiple of
/// the declared line frequency; a tone otherwise.
pub(crate) fn classify_line(line: CoherentLine, fr: f64, c: &crate::LoopConfig) -> Effect {
    let f = line.frequency_hz;
    let k2 = (2.0 * f / fr).round();
    let order = k2 / 2.0;
    let is_half = k2 % 2.0 != 0.0;
    let rel_h = if k2 >= 1.0 {
        (f / (order * fr) - 1.0).abs()
    } else {
        f64::INFINITY
    };
    let rel_l = nearest_mains(f, c).map_or(f64::INFINITY, |g| (f / g - 1.0).abs());
    let in_range = if is_half {
        order <= MAX_HALF_ORDER
    } else {
        order >= 1.0 && order <= f64::from(c.max_harmonic_order)
    };
    if in_range && rel_h <= c.harmonic_tolerance && rel_h <= rel_l {
        Effect::ShaftHarmonic {
            order,
            line,
            shaft_hz: fr,
            force: None,
        }
    } else {
        Effect::Tone { line }
    }
}
