//! The effect library: each candidate effect's parametric form and where it enters the model.

use crate::spectrum::{bandpass_coefficients, biquad_filter, biquad_response};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::f64::consts::PI;

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
        }
    }
}

/// A yes/no parameter of the report's numeric map: 1 or 0.
fn flag(b: bool) -> f64 {
    f64::from(u8::from(b))
}

/// Largest contact angle a deep-groove ball bearing's radial clearance lets it run at under
/// axial load, degrees (the free contact angle cos α₀ = 1 − P_d/(2(f_o + f_i − 1)·d): a 6205
/// with ISO 5753 normal clearance, P_d ≤ 20 µm, f ≈ 0.52, reaches about 14°). A defect rate
/// that asks for more is described as not the geometry alone.
pub const MAX_PLAUSIBLE_CONTACT_ANGLE_DEG: f64 = 15.0;

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

/// A phase-coherent line a·cos(2πft) + b·sin(2πft), t = sample index / fs from the recording start.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Line {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Cosine coefficient.
    pub a: f64,
    /// Sine coefficient.
    pub b: f64,
}

impl Line {
    /// Amplitude √(a² + b²).
    pub fn amplitude(&self) -> f64 {
        self.a.hypot(self.b)
    }

    /// Phase φ of amplitude·cos(2πft − φ), rad.
    pub fn phase(&self) -> f64 {
        self.b.atan2(self.a)
    }

    /// Add the line to `out`, whose first sample is sample `start` of the recording.
    pub fn add_to(&self, out: &mut [f64], start: usize, fs: f64) {
        let w = 2.0 * PI * self.frequency_hz / fs;
        // phasor recurrence e^{jω(k+1)} = e^{jωk}·e^{jω}, re-anchored exactly every 256 samples
        let (sw, cw) = w.sin_cos();
        for (j, chunk) in out.chunks_mut(256).enumerate() {
            let (mut s, mut c) = (w * (start + 256 * j) as f64).sin_cos();
            for o in chunk.iter_mut() {
                *o += self.a * c + self.b * s;
                (s, c) = (s * cw + c * sw, c * cw - s * sw);
            }
        }
    }
}

/// A mode added in parallel to the channel: y = x + c·BP(x), BP a unit-peak band-pass at f0, ζ.
/// Its power gain is G(f) = |1 + c·BP(e^{jω})|²; c > 0 adds a resonance, −1 < c < 0 cuts one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Centre frequency f0, Hz.
    pub frequency_hz: f64,
    /// Damping ratio ζ.
    pub damping_ratio: f64,
    /// Parallel gain c (peak power gain (1 + c)²).
    pub gain: f64,
}

impl Mode {
    /// Power gain G(f) at `f`.
    pub fn power_gain(&self, f: f64, fs: f64) -> f64 {
        let (b, a) = bandpass_coefficients(self.frequency_hz, self.damping_ratio, fs);
        (biquad_response(&b, &a, f, fs) * self.gain + 1.0).norm_sqr()
    }

    /// Multiply the PSD `psd` (bin k at k·`df`) by the power gains of `modes`.
    pub fn shape_psd(modes: &[Mode], psd: &mut [f64], df: f64, fs: f64) {
        if modes.is_empty() {
            return;
        }
        for (k, v) in psd.iter_mut().enumerate() {
            let f = k as f64 * df;
            for m in modes {
                *v *= m.power_gain(f, fs);
            }
        }
    }

    /// Apply the mode to a time signal.
    pub fn apply(&self, x: &[f64], fs: f64) -> Vec<f64> {
        let (b, a) = bandpass_coefficients(self.frequency_hz, self.damping_ratio, fs);
        let bp = biquad_filter(&b, &a, x);
        x.iter().zip(bp).map(|(v, p)| v + self.gain * p).collect()
    }
}

/// Amplitude modulation x·(1 + μ·cos(2π·fm·t)) of the modelled vibration.
/// Its PSD is S(f) + μ²/4·(S(f − fm) + S(f + fm)) (autocorrelation R_x(τ)·(1 + μ²/2·cos 2πf_mτ)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Modulation {
    /// Modulation rate fm, Hz.
    pub frequency_hz: f64,
    /// Depth μ (0 ≤ μ ≤ 1).
    pub depth: f64,
}

impl Modulation {
    /// Apply the modulation to a time signal whose first sample is sample `start`.
    pub fn apply(&self, x: &[f64], start: usize, fs: f64) -> Vec<f64> {
        let w = 2.0 * PI * self.frequency_hz / fs;
        x.iter()
            .enumerate()
            .map(|(i, v)| v * (1.0 + self.depth * (w * (start + i) as f64).cos()))
            .collect()
    }

    /// The modulated PSD on a uniform grid of step `df` (one-sided; S(−f) = S(f)).
    pub fn apply_psd(&self, s: &[f64], df: f64) -> Vec<f64> {
        let mu2 = self.depth * self.depth;
        let shift = self.frequency_hz / df;
        let at = |x: f64| -> f64 {
            let x = x.abs();
            let i = x.floor() as usize;
            if i + 1 >= s.len() {
                return 0.0;
            }
            let t = x - i as f64;
            s[i] * (1.0 - t) + s[i + 1] * t
        };
        (0..s.len())
            .map(|k| {
                let k = k as f64;
                s[k as usize] + mu2 / 4.0 * (at(k - shift) + at(k + shift))
            })
            .collect()
    }
}

/// One effect found by the loop, with its fitted parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Effect {
    /// A measurement-channel line not tied to the shaft.
    Tone {
        /// The fitted line.
        line: Line,
    },
    /// A line at k × fr, read as a shaft force (unbalance, misalignment) seen through the structure.
    ShaftHarmonic {
        /// Order k (a half order k + ½ for looseness).
        order: f64,
        /// The fitted line at the sensor.
        line: Line,
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
        lines: Vec<Line>,
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
        lines: Vec<Line>,
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

/// Largest damping ratio a fitted mode may take.
pub const MODE_MAX_DAMPING: f64 = 0.7;
/// Smallest damping ratio a fitted mode may take (the damping search's lower bound).
pub const MODE_MIN_DAMPING: f64 = 0.001;
/// Gain range of a fitted mode: a bump up to +200 (46 dB), a notch down to −0.97 (−30 dB).
pub const MODE_GAIN_RANGE: (f64, f64) = (-0.97, 200.0);

/// Largest modulation depth (a full modulation of the structural vibration).
pub const MODULATION_MAX_DEPTH: f64 = 1.0;

/// Whether a modulation's depth reached [`MODULATION_MAX_DEPTH`]: the envelope's modulation
/// index asked for more than a full modulation of the structural vibration gives, so the depth is
/// a lower bound. (Until 2026-11-26 the depth was fitted on the spectral distance and 30–50 %
/// modulations came back at 0.99999.)
pub fn depth_at_bound(m: &Modulation) -> bool {
    m.depth >= 0.99 * MODULATION_MAX_DEPTH
}

/// Whether a fitted mode's damping or gain sits at its search bound (within 1 %): the data did
/// not pin it, and the "mode" is a broad correction of the spectral shape, not a resonance.
pub fn mode_at_bound(mode: &Mode) -> bool {
    mode.damping_ratio >= 0.99 * MODE_MAX_DAMPING
        || mode.gain >= 0.99 * MODE_GAIN_RANGE.1
        || mode.gain <= 0.99 * MODE_GAIN_RANGE.0
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
            Self::Modulation { modulation, .. } => Some(modulation.frequency_hz),
            Self::StructuralPath { modes, .. } => dominant(modes).map(|m| m.frequency_hz),
            Self::ShaftComb { shaft_hz, .. } => Some(*shaft_hz),
            Self::LineComb { lines, .. } => strongest(lines).map(|l| l.frequency_hz),
        }
    }

    /// Its parameters by name, for the report.
    pub fn parameters(&self) -> BTreeMap<String, f64> {
        let mut m = BTreeMap::new();
        match self {
            Self::Tone { line } => {
                m.insert("amplitude".into(), line.amplitude());
                m.insert("phase_rad".into(), line.phase());
            }
            Self::ShaftHarmonic {
                order,
                line,
                shaft_hz,
                force,
            } => {
                m.insert("order".into(), *order);
                if let Some((a, p)) = force {
                    m.insert("force_amplitude_n".into(), *a);
                    m.insert("force_phase_rad".into(), *p);
                }
                m.insert("amplitude".into(), line.amplitude());
                m.insert("phase_rad".into(), line.phase());
                m.insert(
                    "implied_speed_ratio".into(),
                    line.frequency_hz / (order * shaft_hz),
                );
            }
            Self::Resonance { mode, housing } => {
                m.insert("housing_mode".into(), flag(*housing));
                m.insert("at_search_bound".into(), flag(mode_at_bound(mode)));
                m.insert("damping_ratio".into(), mode.damping_ratio);
                m.insert("gain".into(), mode.gain);
                m.insert(
                    "peak_gain_db".into(),
                    20.0 * (1.0 + mode.gain).abs().max(1e-12).log10(),
                );
            }
            Self::SpeedOffset {
                ratio,
                step,
                defect_rate,
                shaft_measured,
            } => {
                m.insert("ratio".into(), *ratio);
                m.insert("step".into(), *step);
                if *shaft_measured {
                    m.insert("defect_rate_ratio".into(), *defect_rate);
                }
                m.insert("shaft_measured".into(), flag(*shaft_measured));
            }
            Self::DefectRate {
                ratio,
                step,
                shaft_ratio,
                order,
                effective_pitch_ratio,
                contact_angle_deg,
                ..
            } => {
                m.insert("ratio".into(), *ratio);
                m.insert("step".into(), *step);
                m.insert("shaft_ratio".into(), *shaft_ratio);
                m.insert("order".into(), *order);
                m.insert("measured_order".into(), order * ratio);
                if let Some(g) = effective_pitch_ratio {
                    m.insert("effective_pitch_ratio".into(), *g);
                }
                if let Some(a) = contact_angle_deg {
                    m.insert("contact_angle_deg".into(), *a);
                }
            }
            Self::Modulation {
                modulation,
                shaft_order,
                ..
            } => {
                m.insert("depth".into(), modulation.depth);
                m.insert("shaft_order".into(), *shaft_order);
                m.insert("at_search_bound".into(), flag(depth_at_bound(modulation)));
            }
            Self::ShaftComb {
                shaft_hz,
                declared_shaft_hz,
                orders,
                lines,
            } => {
                m.insert("orders".into(), orders.len() as f64);
                m.insert(
                    "lowest_order".into(),
                    orders.first().copied().unwrap_or(0.0),
                );
                m.insert(
                    "highest_order".into(),
                    orders.last().copied().unwrap_or(0.0),
                );
                m.insert("implied_speed_ratio".into(), shaft_hz / declared_shaft_hz);
                m.insert(
                    "rms".into(),
                    (lines
                        .iter()
                        .map(|l| l.amplitude().powi(2) / 2.0)
                        .sum::<f64>())
                    .sqrt(),
                );
                if let Some(l) = strongest(lines) {
                    m.insert("strongest_order".into(), l.frequency_hz / shaft_hz);
                    m.insert("strongest_amplitude".into(), l.amplitude());
                }
            }
            Self::FaultSize {
                size_in,
                declared_in,
                at_bound,
            } => {
                m.insert("size_in".into(), *size_in);
                m.insert("size_mm".into(), size_in * 25.4);
                m.insert("declared_size_in".into(), *declared_in);
                m.insert("ratio".into(), size_in / declared_in);
                m.insert("at_search_bound".into(), flag(*at_bound));
            }
            Self::AddedFault {
                order,
                size_in,
                diagnosis_score_db,
                path_order,
                at_bound,
                ..
            } => {
                m.insert("order".into(), *order);
                m.insert("size_in".into(), *size_in);
                m.insert("size_mm".into(), size_in * 25.4);
                m.insert("diagnosis_score_db".into(), *diagnosis_score_db);
                if let Some(p) = path_order {
                    m.insert("path_ar_order".into(), *p as f64);
                }
                m.insert("at_search_bound".into(), flag(*at_bound));
            }
            Self::Slip {
                fraction,
                declared,
                at_bound,
            } => {
                m.insert("fraction".into(), *fraction);
                m.insert("declared_fraction".into(), *declared);
                m.insert("at_search_bound".into(), flag(*at_bound));
            }
            Self::ContactPreload {
                preload_m,
                declared_m,
                rate,
            } => {
                m.insert("preload_um".into(), preload_m * 1e6);
                m.insert("declared_preload_um".into(), declared_m * 1e6);
                if let Some((step, ratio)) = rate {
                    m.insert("defect_rate_step".into(), *step);
                    m.insert("defect_rate_ratio".into(), *ratio);
                }
            }
            Self::LineComb { spacing_hz, lines } => {
                m.insert("spacing_hz".into(), *spacing_hz);
                m.insert("lines".into(), lines.len() as f64);
                let lo = lines
                    .iter()
                    .map(|l| l.frequency_hz)
                    .fold(f64::INFINITY, f64::min);
                let hi = lines.iter().map(|l| l.frequency_hz).fold(0.0, f64::max);
                m.insert("lowest_hz".into(), lo);
                m.insert("highest_hz".into(), hi);
                if let Some(l) = strongest(lines) {
                    m.insert("amplitude".into(), l.amplitude());
                }
            }
            Self::StructuralPath {
                order,
                modes,
                physics,
            } => {
                m.insert("ar_order".into(), *order as f64);
                m.insert("physics_excitation".into(), f64::from(u8::from(*physics)));
                let resonant: Vec<_> = modes.iter().filter(|m| m.frequency_hz > 0.0).collect();
                m.insert("modes".into(), resonant.len() as f64);
                if let Some(d) = dominant(modes) {
                    m.insert("damping_ratio".into(), d.damping_ratio);
                    m.insert("gain".into(), d.gain);
                }
            }
        }
        m
    }

    /// One-line human description.
    pub fn describe(&self) -> String {
        match self {
            Self::Tone { line } => format!(
                "tone at {:.3} Hz, amplitude {:.4e}",
                line.frequency_hz,
                line.amplitude()
            ),
            Self::ShaftHarmonic {
                order, line, force, ..
            } => format!(
                "shaft harmonic {order}x at {:.3} Hz, amplitude {:.4e}{}",
                line.frequency_hz,
                line.amplitude(),
                force.map_or(String::new(), |(a, p)| format!(
                    " (shaft force {a:.4e} N, phase {p:+.3} rad)"
                ))
            ),
            Self::Resonance {
                mode,
                housing: true,
            } => format!(
                "housing mode moved to {:.1} Hz, zeta {:.4}",
                mode.frequency_hz, mode.damping_ratio
            ),
            Self::Resonance { mode, .. } => format!(
                "mode at {:.1} Hz, zeta {:.4}, parallel gain {:+.3}{}",
                mode.frequency_hz,
                mode.damping_ratio,
                mode.gain,
                if mode_at_bound(mode) {
                    " (damping or gain at its search bound: a broad spectral-shape correction, \
                     not a resolved resonance)"
                } else {
                    ""
                }
            ),
            Self::SpeedOffset {
                ratio,
                defect_rate,
                shaft_measured,
                ..
            } => {
                if *shaft_measured {
                    format!(
                        "speed ratio {ratio:.5} (true / declared, read from the shaft lines); \
                         the fault's impacts at {defect_rate:.5} x its geometry's rate"
                    )
                } else {
                    format!(
                        "speed ratio {ratio:.5} (true / declared; the shaft lines are too weak \
                         to tell a speed change from a defect-rate offset)"
                    )
                }
            }
            Self::DefectRate {
                ratio,
                shaft_ratio,
                order,
                frequency_hz,
                effective_pitch_ratio,
                contact_angle_deg,
                ..
            } => {
                let mut d = format!(
                    "defect rate {ratio:.5} x the geometry's: {:.4} x fr ({frequency_hz:.2} Hz) \
                     instead of {order:.4} x fr, the shaft lines at speed ratio {shaft_ratio:.5}",
                    order * ratio
                );
                if let Some(g) = effective_pitch_ratio {
                    d += &format!("; effective d cos(a) / D = {g:.4}");
                }
                if let Some(a) = contact_angle_deg {
                    d += &format!(" (contact angle {a:.1} deg)");
                    if *a > MAX_PLAUSIBLE_CONTACT_ANGLE_DEG {
                        d += &format!(
                            "; beyond the {MAX_PLAUSIBLE_CONTACT_ANGLE_DEG:.0} deg a deep-groove \
                             bearing's clearance allows: not the geometry alone"
                        );
                    }
                }
                d
            }
            Self::Modulation {
                modulation,
                rate,
                shaft_order,
            } => format!(
                "modulation at {:.3} Hz ({rate}, {shaft_order:.4} x fr), depth {:.3}{}",
                modulation.frequency_hz,
                modulation.depth,
                if depth_at_bound(modulation) {
                    " (depth at its bound: the envelope's modulation index asked for more than \
                     a full modulation of the structural vibration gives; the rate is measured, \
                     the depth is a lower bound)"
                } else {
                    ""
                }
            ),
            Self::ShaftComb {
                shaft_hz, orders, ..
            } => {
                let o: Vec<String> = orders.iter().map(|k| format!("{k}")).collect();
                format!(
                    "shaft-synchronous comb at fr = {shaft_hz:.4} Hz, orders {}",
                    o.join(", ")
                )
            }
            Self::AddedFault {
                location,
                order,
                frequency_hz,
                size_in,
                path_order,
                at_bound,
                ..
            } => format!(
                "{} fault nobody declared: impacts at {:.3} Hz ({:.4} x fr), spall width {:.4} in ({:.3} mm){}{}",
                location.name(),
                frequency_hz,
                order,
                size_in,
                size_in * 25.4,
                path_order
                    .map(|p| format!(
                        ", ringing a structural path identified with it (AR order {p})"
                    ))
                    .unwrap_or_default(),
                if *at_bound {
                    ", at an end of the width search"
                } else {
                    ""
                }
            ),
            Self::FaultSize {
                size_in,
                declared_in,
                at_bound,
            } => format!(
                "spall width {:.4} in ({:.3} mm; declared {:.4} in){}",
                size_in,
                size_in * 25.4,
                declared_in,
                if *at_bound {
                    ", at an end of the search: the data asks for at least this change"
                } else {
                    ""
                }
            ),
            Self::Slip {
                fraction,
                declared,
                at_bound,
            } => format!(
                "random slip {:.2} % of the ball spacing (declared {:.2} %){}",
                100.0 * fraction,
                100.0 * declared,
                if *at_bound {
                    ", the largest tried: the data asks for at least this much smear of the \
                     fault lines, a broad correction rather than a resolved slip"
                } else {
                    ""
                }
            ),
            Self::ContactPreload {
                preload_m,
                declared_m,
                rate,
            } => {
                let mut d = format!(
                    "radial preload of every ball {:.2} um (declared {:.2} um): the load zone \
                     {} the whole circumference",
                    preload_m * 1e6,
                    declared_m * 1e6,
                    if *preload_m > 0.0 {
                        "spans"
                    } else {
                        "need not span"
                    }
                );
                if let Some((step, ratio)) = rate {
                    d += &format!(
                        "; judged with the fault's rate moved by {step:.5} (defect rate \
                         {ratio:.5} x the geometry's)"
                    );
                }
                d
            }
            Self::LineComb { spacing_hz, lines } => {
                let f: Vec<String> = lines
                    .iter()
                    .map(|l| format!("{:.1}", l.frequency_hz))
                    .collect();
                format!("line comb, spacing {spacing_hz:.3} Hz: {} Hz", f.join(", "))
            }
            Self::StructuralPath {
                order,
                modes,
                physics,
            } => {
                let list: Vec<String> = modes
                    .iter()
                    .filter(|m| m.frequency_hz > 0.0)
                    .map(|m| format!("{:.0} Hz/{:.3}", m.frequency_hz, m.damping_ratio))
                    .collect();
                format!(
                    "structural path {}, AR order {order}, modes (Hz/zeta): {}",
                    if *physics {
                        "of the declared fault's impacts"
                    } else {
                        "of the broadband excitation"
                    },
                    list.join(", ")
                )
            }
        }
    }
}

/// The line with the largest amplitude.
fn strongest(lines: &[Line]) -> Option<&Line> {
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
