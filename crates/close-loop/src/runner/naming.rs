//! What is taken and how it is named: an accepted candidate recorded in the ledger, the
//! kinematic rate a line sits on, and whether a tone is a line of the declared fault.

use super::{Evaluated, observer_rms};
use crate::effect::Effect;
use crate::engine::{Ctx, HeldOutScores, State};
use crate::report::{AcceptedOn, EffectEntry};
use bearing_model::FaultLocation;

/// The loop's running state that an accepted effect updates.
pub(super) struct Taken<'a> {
    pub(super) effects: &'a mut Vec<EffectEntry>,
    pub(super) st: &'a mut State,
    pub(super) obs: &'a mut Option<f64>,
    pub(super) fit_lsd: &'a mut f64,
    pub(super) held: &'a mut HeldOutScores,
}

/// Record `cand` (held-out scores `h`, kept by `accepted_on`, with the held-out evidence `extra`
/// among its parameters) in the ledger and make its state the loop's.
pub(super) fn take(
    ctx: &Ctx<'_>,
    t: Taken<'_>,
    cand: Evaluated,
    h: HeldOutScores,
    accepted_on: AcceptedOn,
    extra: Option<(&'static str, f64)>,
) {
    // a speed ratio, a slip or a structural path is a setting of the model, not an added
    // term: taken again, it corrects the earlier value, and the ledger says which step
    let kind = cand.effect.kind();
    let replaces_step = kind
        .is_setting()
        .then(|| t.effects.iter().rposition(|e: &EffectEntry| e.kind == kind))
        .flatten()
        .map(|i| i + 1);
    let mut description = cand.effect.describe();
    if let Some(k) = replaces_step {
        description += &format!("; replaces step {k}'s value (a setting, not an added term)");
    }
    let mut parameters = cand.effect.parameters();
    if let Some((key, v)) = extra {
        parameters.insert(key.into(), v);
    }
    // a fault nobody declared is named by its rate
    let fault_rate = match &cand.effect {
        Effect::AddedFault { location, .. } => Some(rate_name(*location).to_string()),
        _ => None,
    };
    let kinematic_rate = match &cand.effect {
        Effect::Tone { line } => kinematic_rate_of(ctx, &cand.state, line.frequency_hz),
        _ => None,
    }
    .map(|(name, order, ratio)| {
        parameters.insert("kinematic_order".into(), order);
        parameters.insert("kinematic_ratio".into(), ratio);
        description += &format!(
            "; at {ratio:.4} × {name} ({order:.4} × fr at the measured shaft speed): a kinematic \
             rate of the bearing"
        );
        name
    })
    .or(fault_rate);
    *t.st = cand.state;
    let obs_after = observer_rms(ctx, t.st);
    t.effects.push(EffectEntry {
        kind,
        frequency_hz: cand.effect.frequency_hz(),
        parameters,
        placement: cand.effect.placement(),
        description,
        replaces_step,
        error_before: t.held.lsd,
        error_after: h.lsd,
        secondary_before: t.held.rms,
        secondary_after: h.rms,
        fit_error_before: *t.fit_lsd,
        fit_error_after: cand.fit_lsd,
        residual_rms_before: *t.obs,
        residual_rms_after: obs_after,
        accepted_on: Some(accepted_on),
        kinematic_rate,
    });
    *t.obs = obs_after;
    *t.fit_lsd = cand.fit_lsd;
    *t.held = h;
}

/// The name of the impact rate of a spall at `location` as the report spells kinematic rates
/// (`EffectEntry::kinematic_rate`): BPFI, BPFO, ball-defect.
fn rate_name(location: FaultLocation) -> &'static str {
    match location {
        FaultLocation::Inner => "BPFI",
        FaultLocation::Outer => "BPFO",
        FaultLocation::Ball => "ball-defect",
    }
}

/// The bearing's kinematic rate (harmonic 1–3 of FTF, BPFO, BPFI or the ball-defect rate, at the
/// shaft speed of `st`) within [`crate::KINEMATIC_LINE_TOLERANCE`] of `f_hz`, nearest first:
/// (name, order × fr, f / rate).
fn kinematic_rate_of(ctx: &Ctx<'_>, st: &State, f_hz: f64) -> Option<(String, f64, f64)> {
    let fr = ctx.op.shaft_hz() * st.shaft_ratio();
    let o = &ctx.op.bearing.orders;
    let rates = [
        ("FTF", o.ftf),
        (rate_name(FaultLocation::Outer), o.bpfo),
        (rate_name(FaultLocation::Inner), o.bpfi),
        (rate_name(FaultLocation::Ball), o.ball_defect),
    ];
    rates
        .iter()
        .flat_map(|&(name, order)| (1..=3).map(move |h| (name, h, h as f64 * order)))
        .filter(|&(.., order)| order > 0.0 && fr > 0.0)
        .map(|(name, h, order)| (name, h, order, f_hz / (order * fr)))
        .filter(|&(.., r)| (r - 1.0).abs() <= crate::KINEMATIC_LINE_TOLERANCE)
        .min_by(|a, b| (a.3 - 1.0).abs().total_cmp(&(b.3 - 1.0).abs()))
        .map(|(name, h, order, r)| {
            let name = if h == 1 {
                name.to_string()
            } else {
                format!("{h}x{name}")
            };
            (name, order, r)
        })
}

/// Largest share of the frequency axis the windows of [`is_declared_fault_line`] may cover for a
/// line in them to count as the declared fault's: 20 % (below about 33 × the impact rate; at
/// 12 kHz every fault line of the 6205 up to 5.1 kHz).
pub const DECLARED_LINE_MAX_COVERAGE: f64 = 0.2;

/// Whether `effect` is a tone on a line of the declared fault's own family at the state's speed
/// — k·BPFO ± m·fr (outer), k·BPFI ± m·fr (inner), k·(ball-defect rate) ± m·FTF (ball),
/// k ≥ 1, |m| ≤ 3, within 0.03 % — i.e. a line the declared physics makes but with another
/// amplitude or phase, not an undeclared tone. Such a line gets no coherent-line privilege
/// (it is judged by the spectral error alone, as any patch of the declared fault's spectrum).
pub(super) fn is_declared_fault_line(ctx: &Ctx<'_>, st: &State, effect: &Effect) -> bool {
    let Effect::Tone { line } = effect else {
        return false;
    };
    let f = line.frequency_hz;
    let fr = ctx.op.rpm / 60.0 * st.base.ratio;
    let o = ctx.op.bearing.orders;
    let fault = ctx.op.fault;
    let mut families: Vec<(f64, f64)> = Vec::new();
    if fault.has_outer() {
        families.push((o.bpfo * fr, fr));
    }
    if fault.has_inner() {
        families.push((o.bpfi * fr, fr));
    }
    if fault.has_ball() {
        families.push((o.ball_defect * fr, o.ftf * fr));
    }
    let tol = 3e-4 * f;
    // the seven windows k·f_d + m·side (|m| ≤ 3) per period f_d cover a share of the axis that
    // grows with f; where they cover more than DECLARED_LINE_MAX_COVERAGE of it, a line falling
    // into one is no evidence that the physics makes it (at 21 kHz, 48 kHz, BPFI 162 Hz: 6.3 Hz
    // windows cover 55 %, and a 21 kHz tone at 25 % RMS added to 109 was taken for a fault line,
    // lost its coherent-line standing and was never named)
    families.retain(|&(base, _)| 7.0 * 2.0 * tol <= DECLARED_LINE_MAX_COVERAGE * base);
    families.iter().any(|&(base, side)| {
        (-3..=3).any(|m: i32| {
            let rest = f - f64::from(m) * side;
            let k = (rest / base).round();
            k >= 1.0 && (rest - k * base).abs() <= tol
        })
    })
}
