//! Speed candidates: a speed offset (envelope and spectral steps) and slip.

use super::{Evaluated, refine_parabolic};
use crate::effect::Effect;
use crate::engine::{Base, Ctx, ModelRef, State};
use crate::spectrum::{envelope_periodogram, running_median};
use crate::{CloseLoopError, DeclaredModel};
use std::sync::Arc;

/// Line-emphasised log spectrum: ln S minus its running median, clipped at 0.
pub(super) fn line_excess(s: &[f64], bins: std::ops::Range<usize>) -> Vec<f64> {
    let l: Vec<f64> = bins.map(|k| s[k].max(1e-300).ln()).collect();
    let m = running_median(&l, 24);
    l.iter().zip(&m).map(|(a, b)| (a - b).max(0.0)).collect()
}

/// Kinematic speed estimate from the envelope spectrum: the ratio s that maximises the summed
/// line excess at k·f_fault·s (k = 1..4) of the fitting residual's envelope spectrum.
pub(super) fn envelope_speed_step(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
    envelope_speed_of(ctx, st, &ctx.fit_residual(st)).map(|(s, ..)| s)
}

/// Summed line excess (ln units over 4 harmonics) the held-out envelope must show to confirm a
/// speed step by itself ([`envelope_confirms_speed`]): twice the detection threshold. The best of
/// the ± 5 % search over pure noise sums to about 5 (each harmonic's excess over the running
/// median of a periodogram averages 0.36 with a spread of about 0.6, maximised over ~300
/// independent positions); the CWRU inner and outer races show 20–36.
pub const ENVELOPE_CONFIRM_SCORE: f64 = 8.0;

/// Whether the held-out segment confirms the speed step `step` by itself: the envelope speed
/// estimate of the held-out residual alone (lines of `st` removed; nothing fitted on it) finds
/// lines summing to at least [`ENVELOPE_CONFIRM_SCORE`] at a step within two steps of its own
/// search grid of `step` (half an envelope bin at the 4th harmonic: 1.5e-4 for BPFI on 5 s at
/// 12 kHz; the two halves of one record differ by up to one grid step, 8e-5 on 170.mat, as the
/// motor's speed wanders). An inner-race or ball fault's lines sit in the envelope, not in the
/// spectrum, so a speed error barely moves the spectral distance there while it moves every
/// envelope line; this is the held-out test that sees it. Returns the held-out estimate.
pub(super) fn envelope_confirms_speed(ctx: &Ctx<'_>, st: &State, step: f64) -> Option<f64> {
    let (s, score, grid) = envelope_speed_of(ctx, st, &ctx.held_residual(st))?;
    ((s - step).abs() <= 2.0 * grid && score >= ENVELOPE_CONFIRM_SCORE).then_some(s)
}

/// Whether the held-out residual's envelope contradicts the speed step `step`: its fault lines
/// stand clear (summed excess at least [`ENVELOPE_CONFIRM_SCORE`]) at a step farther from it than
/// the smallest step the loop proposes (`min_speed_step`, 0.1 %; the spectral estimate of a true
/// step lands within 0.02 % of the envelope's: 130 played 3 % faster) or two steps of the
/// envelope's search grid, whichever is larger. A step the spectral error favours but the fault's own lines do not
/// follow is a fit of something else: with a random slip of 6–10 % (the fault's upper harmonics
/// smeared, its first ones still sharp at the declared rate) a step of ×0.988 moved the model's
/// sharp upper harmonics off the measured floor and was taken before the slip, then a broadband
/// path and three "tones" at the fault's own first harmonics (the truth: slip alone). A weak or
/// absent envelope line vetoes nothing.
pub(super) fn envelope_contradicts_speed(ctx: &Ctx<'_>, st: &State, step: f64) -> bool {
    let tol = ctx.cfg.get().min_speed_step;
    envelope_speed_of(ctx, st, &ctx.held_residual(st)).is_some_and(|(s, score, grid)| {
        score >= ENVELOPE_CONFIRM_SCORE && (s - step).abs() > tol.max(2.0 * grid)
    })
}

/// The envelope speed step of `resid`, its summed line excess and the step of its search grid
/// (`None` without a declared fault or without a clear line).
fn envelope_speed_of(ctx: &Ctx<'_>, st: &State, resid: &[f64]) -> Option<(f64, f64, f64)> {
    let c = ctx.cfg.get();
    let order = *crate::impact_orders(ctx.op.fault, &ctx.op.bearing).first()?;
    let f_fault = order * ctx.op.shaft_hz() * st.base.ratio;
    let (ey, de) = envelope_periodogram(resid, ctx.fs).ok()?;
    let kmax = ((4.5 * f_fault * (1.0 + c.max_speed_offset) / de).ceil() as usize).min(ey.len());
    let l: Vec<f64> = ey[..kmax].iter().map(|v| v.max(1e-300).ln()).collect();
    let half = ((0.1 * f_fault / de).round() as usize).max(8);
    let med = running_median(&l, half);
    let ex: Vec<f64> = l.iter().zip(&med).map(|(a, b)| (a - b).max(0.0)).collect();
    let score = |s: f64| -> f64 {
        (1..=4)
            .map(|k| {
                let x = k as f64 * f_fault * s / de;
                let j = x.floor() as usize;
                if j + 1 >= ex.len() {
                    return 0.0;
                }
                let t = x - j as f64;
                ex[j] * (1.0 - t) + ex[j + 1] * t
            })
            .sum()
    };
    let step = 0.25 * de / (4.0 * f_fault);
    let n = (c.max_speed_offset / step).ceil() as i64;
    let mut best = (1.0, f64::NEG_INFINITY);
    for i in -n..=n {
        let s = 1.0 + i as f64 * step;
        let v = score(s);
        if v > best.1 {
            best = (s, v);
        }
    }
    // require a clear line: the summed excess must be large (ln units; 4 lines × ~2.3 = 10 dB each)
    if best.1 < 4.0 {
        return None;
    }
    let (s, v) = crate::optimize::golden_max(score, best.0 - step, best.0 + step, 20);
    Some((s, v, step))
}

/// The shaft has moved with a speed step when the measured shaft speed differs from the speed
/// of the model's lines by more than this fraction (the comb reads CWRU's 12 kHz records within
/// ±0.06 % of the logged speed; their fault lines sit 0.2–0.7 % off it).
pub const SHAFT_AGREE: f64 = 1e-3;

/// Speed steps from the line pattern ([`spectral_speed_step`]) and from the envelope
/// ([`envelope_speed_step`]): the declared model re-simulated with its fault's impacts moved by
/// the step. Whether the step is the shaft's speed or the fault's own rate is read from the
/// recording's shaft-harmonic comb (`Ctx::shaft`, `residual_features::speed`): with a
/// declared fault and shaft lines that stay within [`SHAFT_AGREE`] of the
/// model's shaft speed, the step is a [`Effect::DefectRate`] and the model's shaft lines stay;
/// when they moved, it is a [`Effect::SpeedOffset`] to the measured speed (the lines move with
/// it) with the rest of the step as the fault's rate; without readable shaft lines (or without
/// a declared fault) the whole step is taken as the speed, as before.
pub(super) fn speed_candidates(
    ctx: &Ctx<'_>,
    st: &State,
) -> Result<Vec<Evaluated>, CloseLoopError> {
    let c = ctx.cfg.get();
    let orders = crate::impact_orders(ctx.op.fault, &ctx.op.bearing);
    // the shaft's speed: its comb, or, when the comb cannot be read, the strongest shaft
    // harmonic this recording showed and the model took (a line fitted at k·fr is evidence of
    // where the shaft turns: 213.mat at 48 kHz with a 2× line added took the line, then a speed
    // step that moved it, and named the line again as a sensor line)
    let measured = ctx
        .shaft
        .or_else(|| shaft_from_lines(ctx, st))
        .filter(|_| !orders.is_empty());
    // the spectral and envelope estimates, and the shaft comb's own speed, which moves the
    // impacts with the shaft (the defect rate kept); each distinct step once
    let shaft_step = measured
        .map(|m| m / st.shaft_ratio())
        .filter(|s| (s - 1.0).abs() > SHAFT_AGREE);
    let mut steps: Vec<f64> = Vec::new();
    for s in [
        spectral_speed_step(ctx, st),
        envelope_speed_step(ctx, st),
        shaft_step,
    ]
    .into_iter()
    .flatten()
    {
        if steps.iter().all(|p| (p - s).abs() > 1e-4) {
            steps.push(s);
        }
    }
    let mut out = Vec::new();
    for s in steps {
        if (s - 1.0).abs() < c.min_speed_step || (s - 1.0).abs() > c.max_speed_offset {
            continue;
        }
        let ratio = st.base.ratio * s;
        // a ratio judged and rejected in an earlier round is not simulated again
        if ctx
            .rejected_ratios
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .iter()
            .any(|r| (r / ratio - 1.0).abs() < 0.25 * c.min_speed_step)
        {
            continue;
        }
        let shaft_now = st.shaft_ratio();
        let shaft_new = match measured {
            Some(m) if (m / shaft_now - 1.0).abs() > SHAFT_AGREE => m,
            Some(_) => shaft_now,
            None => shaft_now * s,
        };
        let defect_rate = ratio / shaft_new;
        let effect = if measured.is_some() && shaft_new == shaft_now {
            let order = orders[0];
            let (effective_pitch_ratio, contact_angle_deg) =
                effective_geometry(ctx, order, defect_rate);
            Effect::DefectRate {
                ratio: defect_rate,
                step: s,
                shaft_ratio: shaft_now,
                order,
                frequency_hz: order * defect_rate * ctx.op.shaft_hz() * shaft_now,
                effective_pitch_ratio,
                contact_angle_deg,
            }
        } else {
            Effect::SpeedOffset {
                ratio: shaft_new,
                step: s,
                defect_rate,
                shaft_measured: measured.is_some(),
            }
        };
        let base: Arc<Base> = ctx.make_base_with(ctx.model_of(st), ratio)?;
        let mut s2 = st.clone();
        ctx.rebase(&mut s2, base);
        s2.defect_rate = defect_rate;
        s2.assumed_shaft_step = match measured {
            // the shaft's speed read on its own lines
            Some(_) if shaft_new != shaft_now => 1.0,
            Some(_) => st.assumed_shaft_step,
            None => st.assumed_shaft_step * s,
        };
        for l in &mut s2.physics_lines {
            l.frequency_hz *= shaft_new / shaft_now;
        }
        let (s2, lsd) = ctx.calibrate(s2, true);
        out.push(Evaluated {
            effect,
            state: s2,
            fit_lsd: lsd,
        });
    }
    Ok(out)
}

/// The shaft's speed over the declared one that the strongest shaft harmonic of `st.shaft_lines`
/// shows (its refined frequency over its order × the declared shaft rate), when that line can be
/// read to half of [`SHAFT_AGREE`]: a line strong enough to be taken into the model is refined
/// (zoom DFT) to a small fraction of the fitting segment's 1/T, counted here as 1/(20 T).
fn shaft_from_lines(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
    let (order, f, _) = st
        .shaft_lines
        .iter()
        .copied()
        .max_by(|a, b| a.2.total_cmp(&b.2))?;
    let precision = ctx.fs / ctx.n_fit as f64 / 20.0;
    (order >= 1.0 && precision <= 0.5 * SHAFT_AGREE * f).then(|| f / (order * ctx.op.shaft_hz()))
}

/// The pitch ratio γ = d·cos α / D that makes the declared fault's rate `order` × `q` (the
/// kinematic formulas with the shaft turning and the outer race still: BPFO = n/2·(1 − γ),
/// BPFI = n/2·(1 + γ), CWRU's ball-defect rate = D/d·(1 − γ²)), and the contact angle that gives
/// it with the catalogue's d and D. `(None, None)` without a geometry or for an order the
/// geometry does not give (a bearing given by its four multiples).
fn effective_geometry(ctx: &Ctx<'_>, order: f64, q: f64) -> (Option<f64>, Option<f64>) {
    let Some(g) = ctx.op.bearing.geometry else {
        return (None, None);
    };
    let d_over_pd = g.ball_diameter_m / g.pitch_diameter_m;
    let gamma = d_over_pd * g.contact_angle_rad.cos();
    let o = ctx.op.bearing.orders;
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-9;
    let gamma_new = if close(order, o.bpfo) {
        Some(1.0 - q * (1.0 - gamma))
    } else if close(order, o.bpfi) {
        Some(q * (1.0 + gamma) - 1.0)
    } else if close(order, o.ball_defect) {
        let v = 1.0 - q * (1.0 - gamma * gamma);
        (v >= 0.0).then(|| v.sqrt())
    } else {
        None
    };
    let Some(gn) = gamma_new.filter(|v| v.is_finite() && *v > 0.0) else {
        return (None, None);
    };
    let cos_a = gn / d_over_pd;
    let angle = (cos_a <= 1.0).then(|| cos_a.acos().to_degrees());
    (Some(gn), angle)
}

/// `st` with its physics replaced by `m` simulated at speed ratio `ratio` (its fault's impacts
/// at `defect_rate` × the geometry's rate at the shaft's speed), gains and floor refitted without
/// a new path: the state a re-simulated physics candidate (slip, preload) is judged in, and its
/// fitting error; `None` when the simulation fails.
fn resimulated(
    ctx: &Ctx<'_>,
    st: &State,
    m: &Arc<dyn DeclaredModel>,
    ratio: f64,
    defect_rate: f64,
) -> Option<(State, f64)> {
    Some(ctx.calibrate(rebased(ctx, st, m, ratio, defect_rate)?, false))
}

/// `st` with its physics replaced by `m` simulated at speed ratio `ratio` (impacts at
/// `defect_rate`), not yet calibrated; `None` when the simulation fails.
pub(super) fn rebased(
    ctx: &Ctx<'_>,
    st: &State,
    m: &Arc<dyn DeclaredModel>,
    ratio: f64,
    defect_rate: f64,
) -> Option<State> {
    let base = ctx.make_base_with(m.as_ref(), ratio).ok()?;
    let mut s2 = st.clone();
    s2.model = Some(ModelRef(m.clone()));
    ctx.rebase(&mut s2, base);
    s2.defect_rate = defect_rate;
    Some(s2)
}

/// Slip fractions tried, relative to the declared model's: the whole range at every step, so
/// that the loop takes the best slip at once (each candidate sets the slip, it does not scale the
/// one already taken) and a second acceptance can only correct the first.
pub(super) const SLIP_FACTORS: [f64; 6] = [0.0, 0.25, 0.5, 2.0, 4.0, 8.0];

/// Random ball slip (the spread of the impact times, which smears the fault lines): the model
/// re-simulated at slip fractions [`SLIP_FACTORS`] × the declared one up to the model's largest
/// ([`DeclaredModel::max_slip_fraction`]; the 5-DOF model takes at most 0.1), and at that largest
/// one, the best on the fitting segment kept. Only with a declared fault and a model that has
/// slip; the slip already in the model is not tried again. The largest fraction tried is
/// flagged (`at_bound`): the grid stopped at 8 × the declared 1 % until 2026-11-27, and a slip of
/// 9 % was named as a speed step of −1.3 % and a broadband path.
pub(super) fn slip_candidate(ctx: &Ctx<'_>, st: &State) -> Option<Evaluated> {
    if crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty() {
        return None;
    }
    let declared = ctx.model.slip_fraction()?;
    let model = ctx.model_of(st);
    let current = model.slip_fraction()?;
    let mut best: Option<Evaluated> = None;
    let limit = model.max_slip_fraction().unwrap_or(f64::INFINITY);
    let mut fractions: Vec<f64> = SLIP_FACTORS
        .iter()
        .map(|k| declared * k)
        .filter(|f| *f <= limit)
        .collect();
    if limit.is_finite() && fractions.last().is_none_or(|f| *f < limit) {
        fractions.push(limit);
    }
    // the top of the search (the slip already in the model, skipped below, may be it)
    let top = fractions.last().map_or(current, |f| f.max(current));
    for frac in fractions {
        if (frac - current).abs() <= 1e-12 * declared.max(1e-300) {
            continue;
        }
        let Some(m) = model.with_slip_fraction(frac) else {
            continue;
        };
        let m: Arc<dyn DeclaredModel> = Arc::from(m);
        let Some((s2, lsd)) = resimulated(ctx, st, &m, st.base.ratio, st.defect_rate) else {
            continue;
        };
        if best.as_ref().is_none_or(|b| lsd < b.fit_lsd) {
            best = Some(Evaluated {
                effect: Effect::Slip {
                    fraction: frac,
                    declared,
                    at_bound: frac >= top,
                },
                state: s2,
                fit_lsd: lsd,
            });
        }
    }
    best
}

/// Speed step from the line pattern: the stretch s of the model's line-emphasised log spectrum
/// that best correlates with the measurement's.
pub(super) fn spectral_speed_step(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
    let c = ctx.cfg.get();
    let ey = line_excess(&ctx.s_fit_hi, ctx.bins_hi.clone());
    let em_full = line_excess(&st.base.psd_hi, 0..st.base.psd_hi.len());
    let k0 = ctx.bins_hi.start as f64;
    let corr = |s: f64| -> f64 {
        // model stretched by s: S'(f) = S(f / s)
        ey.iter()
            .enumerate()
            .map(|(i, &e)| {
                if e == 0.0 {
                    return 0.0;
                }
                let x = (k0 + i as f64) / s;
                let j = x.floor() as usize;
                if j + 1 >= em_full.len() {
                    return 0.0;
                }
                let t = x - j as f64;
                e * (em_full[j] * (1.0 - t) + em_full[j + 1] * t)
            })
            .sum()
    };
    let step = 1e-4;
    let n = (c.max_speed_offset / step).round() as i64;
    let mut best = (1.0, f64::NEG_INFINITY);
    for i in -n..=n {
        let s = 1.0 + i as f64 * step;
        let v = corr(s);
        if v > best.1 {
            best = (s, v);
        }
    }
    let c1 = corr(1.0);
    if best.1.is_nan() || best.1 <= 0.0 || best.1 <= c1 * 1.02 {
        return None;
    }
    let (s, _) = crate::optimize::golden_max(corr, best.0 - step, best.0 + step, 20);
    Some(s)
}

/// The balls' radial preload (a negative clearance: every ball loaded, the load zone spanning
/// the whole circumference): the model re-simulated at each of the calibrated rig's preloads
/// ([`crate::PRELOADS_M`]) but its current
/// one, the best on the fitting segment kept. It sets how strongly the shaft (inner race) or
/// the cage (ball) modulates the fault's impacts — a 5-DOF model without preload modulates an
/// inner-race fault by the load zone far more than CWRU's records show (107: the BPFI ± fr
/// envelope lines at −1/−2 dB of BPFI simulated, −19/−18 dB measured). Only with a declared
/// fault and a model with contacts.
pub(super) fn preload_candidate(ctx: &Ctx<'_>, st: &State) -> Option<Evaluated> {
    let c = ctx.cfg.get();
    if crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty() {
        return None;
    }
    let declared = ctx.model.contact_preload_m()?;
    let model = ctx.model_of(st);
    let current = model.contact_preload_m()?;
    // the fault's rate the envelope asks for, when the shaft lines say it is a defect rate
    let rate_step = envelope_speed_step(ctx, st).filter(|s| {
        (s - 1.0).abs() >= c.min_speed_step
            && (s - 1.0).abs() <= c.max_speed_offset
            && ctx
                .shaft
                .is_some_and(|m| (m / st.shaft_ratio() - 1.0).abs() <= SHAFT_AGREE)
    });
    let mut best: Option<Evaluated> = None;
    for &p in crate::PRELOADS_M {
        if (p - current).abs() <= 1e-12 {
            continue;
        }
        let Some(m) = model.with_contact_preload(p) else {
            continue;
        };
        let m: Arc<dyn DeclaredModel> = Arc::from(m);
        for step in std::iter::once(None).chain(rate_step.map(Some)) {
            let ratio = st.base.ratio * step.unwrap_or(1.0);
            let defect_rate = ratio / st.shaft_ratio();
            let Some((s2, lsd)) = resimulated(ctx, st, &m, ratio, defect_rate) else {
                continue;
            };
            if best.as_ref().is_none_or(|b| lsd < b.fit_lsd) {
                best = Some(Evaluated {
                    effect: Effect::ContactPreload {
                        preload_m: p,
                        declared_m: declared,
                        rate: step.map(|s| (s, s2.defect_rate)),
                    },
                    state: s2,
                    fit_lsd: lsd,
                });
            }
        }
    }
    best
}

/// Points of the spall-width grid ([`fault_size_candidate`]): ratios 2^(k/2) to the declared
/// width, k = −4 … 4 (¼ … 4 ×; CWRU's sizes span 0.007–0.028 in, a factor 4).
const FAULT_SIZE_GRID: i32 = 4;

/// Simulations of the spall width's refinement between the best grid point's neighbours (the
/// midpoints, then successive parabolic interpolation, [`refine_parabolic`]; 8 golden-section
/// steps, 10 simulations, until 2026-11-28).
const FAULT_SIZE_REFINE: usize = 4;

/// The refinement's lattice in log₂ width (1/32: 2.2 % steps), on which re-tried widths meet
/// the simulation memo.
const FAULT_SIZE_LATTICE: f64 = 1.0 / 32.0;

/// The declared fault's spall width: the model re-simulated at widths 2^(k/2) × the declared one
/// (k = −4 … 4), the best on the fitting segment refined between its neighbours (in log width)
/// by at most [`FAULT_SIZE_REFINE`] more simulations. The width sets how long each impact
/// lasts, hence the shape and level of the impacts' spectrum: a wider spall than declared was named a housing mode moved
/// from 3300 to 1948 Hz and two channel modes (inner race, 0.021 in against the declared
/// 0.007), or a path and patches (outer, 0.014 in). Only with a declared fault and a model
/// that has a spall width, and only while the width is still the declared one. The loop keeps
/// only candidates that lower the current fitting error `fit_lsd`, so when no grid point does,
/// the refinement is skipped and nothing is offered: the grid's spacing (×√2) is fine enough
/// that a width between two points that both lose to the declared one is within the loop's
/// margin of it (`--all-real`: the same effects and final errors on every record, 3006 taking
/// its width one round later; about half the width's simulations saved on records that keep
/// the declared width).
pub(super) fn fault_size_candidate(ctx: &Ctx<'_>, st: &State, fit_lsd: f64) -> Option<Evaluated> {
    if crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty() {
        return None;
    }
    let declared = ctx.model.fault_size_in()?;
    let model = ctx.model_of(st);
    let current = model.fault_size_in()?;
    if (current / declared - 1.0).abs() > 1e-12 {
        return None;
    }
    let eval = |log_ratio: f64| -> Option<(State, f64)> {
        let m: Arc<dyn DeclaredModel> =
            Arc::from(model.with_fault_size_in(declared * log_ratio.exp2())?);
        let s2 = rebased(ctx, st, &m, st.base.ratio, st.defect_rate)?;
        Some(ctx.calibrate_warm_and_cold(s2))
    };
    let grid: Vec<f64> = (-FAULT_SIZE_GRID..=FAULT_SIZE_GRID)
        .map(|k| 0.5 * f64::from(k))
        .collect();
    let mut best: Option<(f64, State, f64)> = None;
    let mut best_k = 0usize;
    for (i, &x) in grid.iter().enumerate() {
        if x == 0.0 {
            continue;
        }
        if let Some((s2, lsd)) = eval(x)
            && best.as_ref().is_none_or(|b| lsd < b.2)
        {
            best = Some((x, s2, lsd));
            best_k = i;
        }
    }
    let best = best.filter(|b| b.2 < fit_lsd)?;
    let (x_best, s_best, lsd_best) = refine_parabolic(
        &grid,
        best_k,
        best,
        eval,
        FAULT_SIZE_REFINE,
        FAULT_SIZE_LATTICE,
    );
    let end = 0.5 * f64::from(FAULT_SIZE_GRID);
    Some(Evaluated {
        effect: Effect::FaultSize {
            size_in: declared * x_best.exp2(),
            declared_in: declared,
            at_bound: (x_best.abs() - end).abs() < 1e-9,
        },
        state: s_best,
        fit_lsd: lsd_best,
    })
}
