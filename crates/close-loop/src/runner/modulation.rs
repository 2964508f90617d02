//! Modulation candidates: amplitude modulation of the physics at shaft or cage rate.

use super::*;
use crate::effect::{Effect, Modulation};
use crate::engine::{Ctx, State};
use crate::optimize::golden_min;
use crate::spectrum::{envelope, envelope_periodogram, hann_windowed, refine_peak, running_median};

pub(super) fn modulation_candidates(ctx: &Ctx<'_>, st: &State) -> Vec<Evaluated> {
    let c = ctx.cfg.get();
    let fr = ctx.op.shaft_hz() * st.base.ratio;
    let resid = ctx.fit_residual(st);
    // a residual without an envelope spectrum (cannot happen on checked, finite data) offers
    // no modulation candidate
    let Ok((ey, de)) = envelope_periodogram(&resid, ctx.fs) else {
        return Vec::new();
    };
    let mut msig = st.base.signal.clone();
    for m in &st.mods {
        msig = m.apply(&msig, 0, ctx.fs);
    }
    let Ok((em, _)) = envelope_periodogram(&msig, ctx.fs) else {
        return Vec::new();
    };
    let lo = ((0.5 * ctx.op.bearing.orders.ftf * fr / de).floor() as usize).max(2);
    let hi = ((2.5 * fr / de).ceil() as usize).min(ey.len() - 2);
    if hi <= lo + 4 {
        return Vec::new();
    }
    let half = ((0.25 * ctx.op.bearing.orders.ftf * fr / de).round() as usize).max(8);
    let ly: Vec<f64> = ey.iter().map(|v| 10.0 * v.max(1e-300).log10()).collect();
    let lm: Vec<f64> = em.iter().map(|v| 10.0 * v.max(1e-300).log10()).collect();
    let wlo = lo.saturating_sub(half);
    let whi = (hi + half).min(ey.len());
    let my = running_median(&ly[wlo..whi], half);
    let mm = running_median(&lm[wlo..whi], half);
    let mut peaks: Vec<(usize, f64)> = Vec::new();
    for k in lo..=hi {
        let xy = ly[k] - my[k - wlo];
        let xm = lm[k] - mm[k - wlo];
        if xy > c.envelope_threshold_db && ly[k] >= ly[k - 1] && ly[k] >= ly[k + 1] && xy > xm + 6.0
        {
            peaks.push((k, xy));
        }
    }
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    let Ok(env) = envelope(&resid) else {
        return Vec::new();
    };
    let envw = hann_windowed(&env);
    let mut out = Vec::new();
    let mut used: Vec<usize> = Vec::new();
    for (k, _) in peaks {
        if used.iter().any(|&j| j.abs_diff(k) <= 3) {
            continue;
        }
        used.push(k);
        if used.len() > 2 {
            break;
        }
        let f0 = k as f64 * de;
        let fm = refine_peak(&envw, ctx.fs, f0 - 1.5 * de, f0 + 1.5 * de);
        let eval = |mu: f64| -> (State, f64) {
            let mut s2 = st.clone();
            s2.mods.push(Modulation {
                frequency_hz: fm,
                depth: mu,
            });
            ctx.calibrate(s2, false)
        };
        let (mu, _) = golden_min(
            |mu| eval(mu).1,
            0.02,
            crate::effect::MODULATION_MAX_DEPTH,
            22,
        );
        let (s2, lsd) = eval(mu);
        let order = fm / fr;
        let ftf = ctx.op.bearing.orders.ftf;
        let rate = if (order - 1.0).abs() < 0.02 {
            "shaft"
        } else if (order - 2.0).abs() < 0.04 {
            "2x_shaft"
        } else if (order / ftf - 1.0).abs() < 0.02 {
            "cage"
        } else {
            "other"
        };
        out.push(Evaluated {
            effect: Effect::Modulation {
                modulation: Modulation {
                    frequency_hz: fm,
                    depth: mu,
                },
                shaft_order: order,
                rate,
            },
            state: s2,
            fit_lsd: lsd,
        });
    }
    out
}
