//! The start from a calibrated machine model: its final state rebuilt on this recording, and
//! the calibrated start the run keeps.

use super::fit_line;
use crate::effect::CoherentLine;
use crate::engine::{Ctx, PathPsd, State};
use crate::machine::MachineModel;
use crate::{CloseLoopError, DeclaredModel};
use std::sync::Arc;

/// Largest factor by which a machine model's line may exceed its calibrated amplitude on
/// another recording before the excess counts as an undeclared line (6 dB).
pub const LINE_GROWTH_LIMIT: f64 = 2.0;

/// The initial state of a run that starts from a calibrated machine model: the calibration's
/// final state rebuilt on this recording, so that on the calibration recording itself it is that
/// state (test `idempotence::calibration_recording_from_its_own_model_12k`):
/// - the declared physics with the calibration's slip, housing mode and shaft forces (their
///   response lines part of the phase-coherent prediction), at the calibrated speed ratio;
/// - the lines at their calibrated frequencies (shaft lines moved with the speed), re-fitted in
///   amplitude and phase one after the other in the order the loop added them, each on what the
///   physics lines and the lines before it leave — as the loop fitted them. Fitted each on the
///   raw recording instead (before 2026-12), a line the loop had added twice (two shaft combs
///   share orders; the second holds the correction) counted twice at full amplitude;
/// - the physics behind the machine's physics path when it has one; behind its broadband path
///   when this run declares a fault whose impacts the path rings; otherwise as the calibration
///   saw it, unshaped. Put behind the broadband path on a healthy run (before 2026-12), the
///   physics became a second copy of the path with a gain of its own, which a channel mode at its
///   search bound and a speed step then bent into a broad correction: 97 from its own model
///   gained a resonance and a speed offset (2.716 → 2.454 dB) that its calibration never had.
///
/// Gains, floor and path level are fitted afresh by the caller ([`Ctx::calibrate`]).
pub(super) fn prior_state(ctx: &Ctx<'_>, m: &MachineModel) -> Result<State, CloseLoopError> {
    // the physics runs at the fault's impact rate, the lines at the shaft's
    let ratio = m.speed_ratio * m.defect_rate_ratio;
    let mut model: Option<Arc<dyn DeclaredModel>> = None;
    fn current<'m>(
        model: &'m Option<Arc<dyn DeclaredModel>>,
        declared: &'m dyn DeclaredModel,
    ) -> &'m dyn DeclaredModel {
        match model {
            Some(x) => x.as_ref(),
            None => declared,
        }
    }
    if let Some(frac) = m.slip_fraction
        && let Some(x) = current(&model, ctx.model).with_slip_fraction(frac)
    {
        model = Some(Arc::from(x));
    }
    if let Some(p) = m.contact_preload_m
        && let Some(x) = current(&model, ctx.model).with_contact_preload(p)
    {
        model = Some(Arc::from(x));
    }
    if let Some([f, z]) = m.housing_mode
        && let Some(x) = current(&model, ctx.model).with_housing_mode(f, z)
    {
        model = Some(Arc::from(x));
    }
    let unforced = match &model {
        Some(x) => ctx.make_base_with(x.as_ref(), ratio)?,
        None => ctx.make_base(ratio)?,
    };
    let mut forced_orders = Vec::new();
    for &[order, amp, phase] in &m.shaft_forces {
        if order >= 1.0
            && order.fract() == 0.0
            && let Some(x) = current(&model, ctx.model).with_shaft_force(order as u32, amp, phase)
        {
            model = Some(Arc::from(x));
            forced_orders.push(order);
        }
    }
    let (base, physics_lines) = match (&model, forced_orders.is_empty()) {
        (Some(x), false) => {
            let b = ctx.make_base_with(x.as_ref(), ratio)?;
            let d: Vec<f64> = b
                .signal
                .iter()
                .zip(&unforced.signal)
                .map(|(p, q)| p - q)
                .collect();
            let f_sim = ctx.op.shaft_hz() * ratio;
            let lines = forced_orders
                .iter()
                .map(|o| fit_line(&d, ctx.fs, o * f_sim))
                .collect();
            (b, lines)
        }
        _ => (unforced, Vec::new()),
    };
    let fr = ctx.op.shaft_hz() * m.speed_ratio;
    let mut resid = ctx.y[..ctx.n_fit].to_vec();
    for l in &physics_lines {
        negated(l).add_to(&mut resid, 0, ctx.fs);
    }
    let mut lines: Vec<CoherentLine> = Vec::new();
    for (f, ml) in m.line_frequencies(fr).into_iter().zip(&m.lines) {
        if f > 0.0 && f < 0.5 * ctx.fs {
            let mut l = fit_line(&resid, ctx.fs, f);
            // a machine line takes its phase and level from this recording, but no more than
            // LINE_GROWTH_LIMIT times its calibrated level: what a line grew beyond that stays
            // in the residual, where the loop names it (a 4× order thirty times the healthy
            // machine's is looseness, not the machine)
            let cap = LINE_GROWTH_LIMIT * ml.amplitude();
            let amp = l.amplitude();
            if amp > cap && amp > 0.0 {
                l.a *= cap / amp;
                l.b *= cap / amp;
            }
            negated(&l).add_to(&mut resid, 0, ctx.fs);
            lines.push(l);
        }
    }
    let df = ctx.welch.df();
    let n_bins = ctx.welch.n_bins();
    let path = m
        .path
        .as_ref()
        .map(|p| Arc::new(PathPsd::new(p.clone(), n_bins, df)));
    let impacts = !crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty();
    let phys_path = m
        .physics_path
        .as_ref()
        .or(m.path.as_ref().filter(|_| impacts))
        .map(|p| Arc::new(PathPsd::new(p.clone(), n_bins, df)));
    let phys_path_fitted = false;
    let phys_shape = phys_path
        .as_ref()
        .map(|p| Arc::new(ctx.physics_shape(&base.psd, p)));
    Ok(State {
        model: model.map(crate::engine::ModelRef),
        physics_lines,
        shaft_lines: Vec::new(),
        base,
        defect_rate: m.defect_rate_ratio,
        modes: m.channel_modes.clone(),
        mods: m.modulations.clone(),
        lines,
        path,
        phys_shape,
        phys_path,
        phys_path_fitted,
        phys_highpass: None,
        log_gain: m.physics_gain.max(1e-300).ln(),
        log_floor: m.noise_floor_psd.max(1e-300).ln(),
        log_bg: m.path_level.max(1e-300).ln(),
        assumed_shaft_step: 1.0,
    })
}

/// The run's calibrated start. From a machine model that holds no path of the declared physics
/// and a run that declares a fault, [`prior_state`] puts the fault's impacts behind the machine's
/// broadband path (on a real rig the declared 5-DOF's own response is far from the rig's); the
/// declared physics as it is, unshaped beside that path, is calibrated too, and the start with
/// the lower fitting-segment error is kept. Without it a recording simulated by the declared
/// model itself, started from the machine model calibrated on the same model's healthy output,
/// began at 7.6–11.5 dB (against 0.09–0.61 dB from the bare model) and the loop identified a
/// path and patches for what the declared physics already held (docs/equations/close-loop.md,
/// "The start from a machine model").
pub(super) fn start_from(ctx: &Ctx<'_>, prior: Option<&MachineModel>, st0: State) -> (State, f64) {
    let behind_broadband = prior.is_some_and(|m| m.physics_path.is_none())
        && st0.phys_path.is_some()
        && !st0.phys_path_fitted;
    if !behind_broadband {
        return ctx.calibrate(st0, true);
    }
    let mut unshaped = st0.clone();
    unshaped.phys_shape = None;
    unshaped.phys_path = None;
    let a = ctx.calibrate(st0, true);
    let b = ctx.calibrate(unshaped, true);
    if b.1 < a.1 { b } else { a }
}

/// The line with the opposite sign (to subtract it with [`CoherentLine::add_to`]).
fn negated(l: &CoherentLine) -> CoherentLine {
    CoherentLine {
        a: -l.a,
        b: -l.b,
        ..*l
    }
}
