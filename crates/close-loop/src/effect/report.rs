//! The report form of an effect: its parameters by name and its one-line description.
//!
//! [`Effect::parameters`] and [`Effect::describe`] dispatch on the variant; each variant's
//! parameters and description are a function of its own below, in the order of the dispatch.

use super::{
    CoherentLine, Effect, Mode, Modulation, depth_at_bound, dominant, mode_at_bound, strongest,
};
use crate::path::PathMode;
use std::collections::BTreeMap;

/// The report's numeric map: parameter name → value.
type Parameters = BTreeMap<String, f64>;

/// A yes/no parameter of the report's numeric map: 1 or 0.
fn flag(b: bool) -> f64 {
    f64::from(u8::from(b))
}

/// Largest contact angle a deep-groove ball bearing's radial clearance lets it run at under
/// axial load, degrees (the free contact angle cos α₀ = 1 − P_d/(2(f_o + f_i − 1)·d): a 6205
/// with ISO 5753 normal clearance, P_d ≤ 20 µm, f ≈ 0.52, reaches about 14°). A defect rate
/// that asks for more is described as not the geometry alone.
pub const MAX_PLAUSIBLE_CONTACT_ANGLE_DEG: f64 = 15.0;

impl Effect {
    /// Its parameters by name, for the report.
    pub fn parameters(&self) -> BTreeMap<String, f64> {
        let mut m = Parameters::new();
        match self {
            Self::Tone { line } => line_parameters(&mut m, line),
            Self::ShaftHarmonic {
                order,
                line,
                shaft_hz,
                force,
            } => shaft_harmonic_parameters(&mut m, *order, line, *shaft_hz, *force),
            Self::Resonance { mode, housing } => resonance_parameters(&mut m, mode, *housing),
            Self::SpeedOffset {
                ratio,
                step,
                defect_rate,
                shaft_measured,
            } => speed_offset_parameters(&mut m, *ratio, *step, *defect_rate, *shaft_measured),
            Self::DefectRate {
                ratio,
                step,
                shaft_ratio,
                order,
                effective_pitch_ratio,
                contact_angle_deg,
                ..
            } => defect_rate_parameters(
                &mut m,
                *ratio,
                *step,
                *shaft_ratio,
                *order,
                *effective_pitch_ratio,
                *contact_angle_deg,
            ),
            Self::Modulation {
                modulation,
                shaft_order,
                ..
            } => modulation_parameters(&mut m, modulation, *shaft_order),
            Self::ShaftComb {
                shaft_hz,
                declared_shaft_hz,
                orders,
                lines,
            } => shaft_comb_parameters(&mut m, *shaft_hz, *declared_shaft_hz, orders, lines),
            Self::FaultSize {
                size_in,
                declared_in,
                at_bound,
            } => fault_size_parameters(&mut m, *size_in, *declared_in, *at_bound),
            Self::AddedFault {
                order,
                size_in,
                diagnosis_score_db,
                path_order,
                at_bound,
                ..
            } => added_fault_parameters(
                &mut m,
                *order,
                *size_in,
                *diagnosis_score_db,
                *path_order,
                *at_bound,
            ),
            Self::ImpactsHighPass {
                corner_hz,
                order,
                at_bound,
            } => impacts_high_pass_parameters(&mut m, *corner_hz, *order, *at_bound),
            Self::Slip {
                fraction,
                declared,
                at_bound,
            } => slip_parameters(&mut m, *fraction, *declared, *at_bound),
            Self::ContactPreload {
                preload_m,
                declared_m,
                rate,
            } => contact_preload_parameters(&mut m, *preload_m, *declared_m, *rate),
            Self::LineComb { spacing_hz, lines } => {
                line_comb_parameters(&mut m, *spacing_hz, lines);
            }
            Self::StructuralPath {
                order,
                modes,
                physics,
            } => structural_path_parameters(&mut m, *order, modes, *physics),
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
            } => describe_shaft_harmonic(*order, line, *force),
            Self::Resonance { mode, housing } => describe_resonance(mode, *housing),
            Self::SpeedOffset {
                ratio,
                defect_rate,
                shaft_measured,
                ..
            } => describe_speed_offset(*ratio, *defect_rate, *shaft_measured),
            Self::DefectRate {
                ratio,
                shaft_ratio,
                order,
                frequency_hz,
                effective_pitch_ratio,
                contact_angle_deg,
                ..
            } => describe_defect_rate(
                *ratio,
                *shaft_ratio,
                *order,
                *frequency_hz,
                *effective_pitch_ratio,
                *contact_angle_deg,
            ),
            Self::Modulation {
                modulation,
                rate,
                shaft_order,
            } => describe_modulation(modulation, rate, *shaft_order),
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
            } => describe_added_fault(
                *location,
                *order,
                *frequency_hz,
                *size_in,
                *path_order,
                *at_bound,
            ),
            Self::FaultSize {
                size_in,
                declared_in,
                at_bound,
            } => describe_fault_size(*size_in, *declared_in, *at_bound),
            Self::ImpactsHighPass {
                corner_hz,
                order,
                at_bound,
            } => describe_impacts_high_pass(*corner_hz, *order, *at_bound),
            Self::Slip {
                fraction,
                declared,
                at_bound,
            } => describe_slip(*fraction, *declared, *at_bound),
            Self::ContactPreload {
                preload_m,
                declared_m,
                rate,
            } => describe_contact_preload(*preload_m, *declared_m, *rate),
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
            } => describe_structural_path(*order, modes, *physics),
        }
    }
}

// ---- parameters, one function per variant ----

/// A line's amplitude and phase (a tone's, a shaft harmonic's).
fn line_parameters(m: &mut Parameters, line: &CoherentLine) {
    m.insert("amplitude".into(), line.amplitude());
    m.insert("phase_rad".into(), line.phase());
}

/// A shaft harmonic: its order, the shaft force behind it if one was fitted, its line and the
/// speed ratio its frequency implies.
fn shaft_harmonic_parameters(
    m: &mut Parameters,
    order: f64,
    line: &CoherentLine,
    shaft_hz: f64,
    force: Option<(f64, f64)>,
) {
    m.insert("order".into(), order);
    if let Some((a, p)) = force {
        m.insert("force_amplitude_n".into(), a);
        m.insert("force_phase_rad".into(), p);
    }
    line_parameters(m, line);
    m.insert(
        "implied_speed_ratio".into(),
        line.frequency_hz / (order * shaft_hz),
    );
}

/// A resonance: housing mode or not, at a search bound or not, damping, gain and peak gain.
fn resonance_parameters(m: &mut Parameters, mode: &Mode, housing: bool) {
    m.insert("housing_mode".into(), flag(housing));
    m.insert("at_search_bound".into(), flag(mode_at_bound(mode)));
    m.insert("damping_ratio".into(), mode.damping_ratio);
    m.insert("gain".into(), mode.gain);
    m.insert(
        "peak_gain_db".into(),
        20.0 * (1.0 + mode.gain).abs().max(1e-12).log10(),
    );
}

/// A speed offset: its ratio and step, and the fault's defect rate when the shaft lines
/// measured the speed.
fn speed_offset_parameters(
    m: &mut Parameters,
    ratio: f64,
    step: f64,
    defect_rate: f64,
    shaft_measured: bool,
) {
    m.insert("ratio".into(), ratio);
    m.insert("step".into(), step);
    if shaft_measured {
        m.insert("defect_rate_ratio".into(), defect_rate);
    }
    m.insert("shaft_measured".into(), flag(shaft_measured));
}

/// A defect rate: its ratio and step, the shaft's speed
/// ratio, the geometry's and the measured order, and the pitch ratio and contact angle it
/// implies where known.
fn defect_rate_parameters(
    m: &mut Parameters,
    ratio: f64,
    step: f64,
    shaft_ratio: f64,
    order: f64,
    effective_pitch_ratio: Option<f64>,
    contact_angle_deg: Option<f64>,
) {
    m.insert("ratio".into(), ratio);
    m.insert("step".into(), step);
    m.insert("shaft_ratio".into(), shaft_ratio);
    m.insert("order".into(), order);
    m.insert("measured_order".into(), order * ratio);
    if let Some(g) = effective_pitch_ratio {
        m.insert("effective_pitch_ratio".into(), g);
    }
    if let Some(a) = contact_angle_deg {
        m.insert("contact_angle_deg".into(), a);
    }
}

/// A modulation: its depth, its rate as a shaft order, and whether the depth is at its bound.
fn modulation_parameters(m: &mut Parameters, modulation: &Modulation, shaft_order: f64) {
    m.insert("depth".into(), modulation.depth);
    m.insert("shaft_order".into(), shaft_order);
    m.insert("at_search_bound".into(), flag(depth_at_bound(modulation)));
}

/// A shaft comb: how many orders and which, the speed ratio it implies, its RMS and its
/// strongest line.
fn shaft_comb_parameters(
    m: &mut Parameters,
    shaft_hz: f64,
    declared_shaft_hz: f64,
    orders: &[f64],
    lines: &[CoherentLine],
) {
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

/// A fault size: the width in inches and mm, the declared width and their ratio, at a bound or
/// not.
fn fault_size_parameters(m: &mut Parameters, size_in: f64, declared_in: f64, at_bound: bool) {
    m.insert("size_in".into(), size_in);
    m.insert("size_mm".into(), size_in * 25.4);
    m.insert("declared_size_in".into(), declared_in);
    m.insert("ratio".into(), size_in / declared_in);
    m.insert("at_search_bound".into(), flag(at_bound));
}

/// An added fault: its order, width, diagnosis score, the
/// AR order of the path identified with it, at a bound or not.
fn added_fault_parameters(
    m: &mut Parameters,
    order: f64,
    size_in: f64,
    diagnosis_score_db: f64,
    path_order: Option<usize>,
    at_bound: bool,
) {
    m.insert("order".into(), order);
    m.insert("size_in".into(), size_in);
    m.insert("size_mm".into(), size_in * 25.4);
    m.insert("diagnosis_score_db".into(), diagnosis_score_db);
    if let Some(p) = path_order {
        m.insert("path_ar_order".into(), p as f64);
    }
    m.insert("at_search_bound".into(), flag(at_bound));
}

/// A high-pass on the fault's impacts: its corner, its order, at a search bound or not.
fn impacts_high_pass_parameters(m: &mut Parameters, corner_hz: f64, order: u32, at_bound: bool) {
    m.insert("corner_hz".into(), corner_hz);
    // not `order`: that key is a shaft or impact order everywhere else
    m.insert("filter_order".into(), f64::from(order));
    m.insert("at_search_bound".into(), flag(at_bound));
}

/// A slip fraction beside the declared one, at a search bound or not.
fn slip_parameters(m: &mut Parameters, fraction: f64, declared: f64, at_bound: bool) {
    m.insert("fraction".into(), fraction);
    m.insert("declared_fraction".into(), declared);
    m.insert("at_search_bound".into(), flag(at_bound));
}

/// A contact preload in µm beside the declared one, and the defect rate it was judged with.
fn contact_preload_parameters(
    m: &mut Parameters,
    preload_m: f64,
    declared_m: f64,
    rate: Option<(f64, f64)>,
) {
    m.insert("preload_um".into(), preload_m * 1e6);
    m.insert("declared_preload_um".into(), declared_m * 1e6);
    if let Some((step, ratio)) = rate {
        m.insert("defect_rate_step".into(), step);
        m.insert("defect_rate_ratio".into(), ratio);
    }
}

/// A line comb: its spacing, how many lines, the lowest and highest, the strongest's amplitude.
fn line_comb_parameters(m: &mut Parameters, spacing_hz: f64, lines: &[CoherentLine]) {
    m.insert("spacing_hz".into(), spacing_hz);
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

/// A structural path: its AR order, physics excitation or not, how many resonant modes, the
/// dominant one's damping and gain.
fn structural_path_parameters(m: &mut Parameters, order: usize, modes: &[PathMode], physics: bool) {
    m.insert("ar_order".into(), order as f64);
    m.insert("physics_excitation".into(), f64::from(u8::from(physics)));
    let resonant: Vec<_> = modes.iter().filter(|m| m.frequency_hz > 0.0).collect();
    m.insert("modes".into(), resonant.len() as f64);
    if let Some(d) = dominant(modes) {
        m.insert("damping_ratio".into(), d.damping_ratio);
        m.insert("gain".into(), d.gain);
    }
}

// ---- descriptions, one function per variant ----

/// "shaft harmonic 2x at … Hz, amplitude …", with the shaft force behind it if one was fitted.
fn describe_shaft_harmonic(order: f64, line: &CoherentLine, force: Option<(f64, f64)>) -> String {
    format!(
        "shaft harmonic {order}x at {:.3} Hz, amplitude {:.4e}{}",
        line.frequency_hz,
        line.amplitude(),
        force.map_or(String::new(), |(a, p)| format!(
            " (shaft force {a:.4e} N, phase {p:+.3} rad)"
        ))
    )
}

/// A housing mode moved, or a mode with its parallel gain (and a note when its damping or gain
/// sits at a search bound).
fn describe_resonance(mode: &Mode, housing: bool) -> String {
    if housing {
        return format!(
            "housing mode moved to {:.1} Hz, zeta {:.4}",
            mode.frequency_hz, mode.damping_ratio
        );
    }
    format!(
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
    )
}

/// The speed ratio, read from the shaft lines (with the fault's defect rate) or not.
fn describe_speed_offset(ratio: f64, defect_rate: f64, shaft_measured: bool) -> String {
    if shaft_measured {
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

/// The defect rate against the geometry's, with the pitch
/// ratio and contact angle it implies, and a note when the angle is beyond what a deep-groove
/// bearing allows.
fn describe_defect_rate(
    ratio: f64,
    shaft_ratio: f64,
    order: f64,
    frequency_hz: f64,
    effective_pitch_ratio: Option<f64>,
    contact_angle_deg: Option<f64>,
) -> String {
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
        if a > MAX_PLAUSIBLE_CONTACT_ANGLE_DEG {
            d += &format!(
                "; beyond the {MAX_PLAUSIBLE_CONTACT_ANGLE_DEG:.0} deg a deep-groove \
                 bearing's clearance allows: not the geometry alone"
            );
        }
    }
    d
}

/// A modulation's rate and depth (and a note when the depth is at its bound).
fn describe_modulation(modulation: &Modulation, rate: &str, shaft_order: f64) -> String {
    format!(
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
    )
}

/// A fault nobody declared: its location, impact rate and
/// width, the path identified with it, at an end of the width search or not.
fn describe_added_fault(
    location: bearing_model::FaultLocation,
    order: f64,
    frequency_hz: f64,
    size_in: f64,
    path_order: Option<usize>,
    at_bound: bool,
) -> String {
    format!(
        "{} fault nobody declared: impacts at {:.3} Hz ({:.4} x fr), spall width {:.4} in ({:.3} mm){}{}",
        location.name(),
        frequency_hz,
        order,
        size_in,
        size_in * 25.4,
        path_order
            .map(|p| format!(", ringing a structural path identified with it (AR order {p})"))
            .unwrap_or_default(),
        if at_bound {
            ", at an end of the width search"
        } else {
            ""
        }
    )
}

/// The spall width against the declared one, at an end of the search or not.
fn describe_fault_size(size_in: f64, declared_in: f64, at_bound: bool) -> String {
    format!(
        "spall width {:.4} in ({:.3} mm; declared {:.4} in){}",
        size_in,
        size_in * 25.4,
        declared_in,
        if at_bound {
            ", at an end of the search: the data asks for at least this change"
        } else {
            ""
        }
    )
}

/// The high-pass on the fault's impacts: its corner and order, at an end of the search or not.
fn describe_impacts_high_pass(corner_hz: f64, order: u32, at_bound: bool) -> String {
    format!(
        "the fault's impacts reach the sensor weaker below {corner_hz:.0} Hz than their \
         path gives (order-{order} high-pass on the physics part): the path is identified \
         where the impacts dominate, below it its gain was an extrapolation{}",
        if at_bound {
            "; at an end of the search"
        } else {
            ""
        }
    )
}

/// The random slip against the declared one, the largest tried or not.
fn describe_slip(fraction: f64, declared: f64, at_bound: bool) -> String {
    format!(
        "random slip {:.2} % of the ball spacing (declared {:.2} %){}",
        100.0 * fraction,
        100.0 * declared,
        if at_bound {
            ", the largest tried: the data asks for at least this much smear of the \
             fault lines, a broad correction rather than a resolved slip"
        } else {
            ""
        }
    )
}

/// The balls' radial preload against the declared one, whether the load zone spans the whole
/// circumference, and the defect rate it was judged with.
fn describe_contact_preload(preload_m: f64, declared_m: f64, rate: Option<(f64, f64)>) -> String {
    let mut d = format!(
        "radial preload of every ball {:.2} um (declared {:.2} um): the load zone \
         {} the whole circumference",
        preload_m * 1e6,
        declared_m * 1e6,
        if preload_m > 0.0 {
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

/// The structural path: what excites it, its AR order and its resonant modes.
fn describe_structural_path(order: usize, modes: &[PathMode], physics: bool) -> String {
    let list: Vec<String> = modes
        .iter()
        .filter(|m| m.frequency_hz > 0.0)
        .map(|m| format!("{:.0} Hz/{:.3}", m.frequency_hz, m.damping_ratio))
        .collect();
    format!(
        "structural path {}, AR order {order}, modes (Hz/zeta): {}",
        if physics {
            "of the declared fault's impacts"
        } else {
            "of the broadband excitation"
        },
        list.join(", ")
    )
}
