//! A fault nobody declared: a spall at a location the declared model leaves healthy.

use super::{Evaluated, has_impacts, speed, with_impacts_path};
use crate::DeclaredModel;
use crate::effect::Effect;
use crate::engine::{Ctx, State};
use bearing_model::FaultLocation;
use std::sync::Arc;

/// Spall widths tried for a fault nobody declared, as multiples of the model's reference width
/// (the declared spall's): ¼ … 4 ×, a factor 2 apart. The width sets the added impacts' level and
/// spectral shape beside the declared fault's (the physics has one calibrated gain); the loop's
/// width candidate refines the declared spall, not this one.
pub const ADDED_FAULT_WIDTHS: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];

/// Every location the training-free diagnosis detects on the fitting segment and on the held-out
/// segment alike ([`Ctx::detected`]: kinematic lines in the envelope of the impulsive band; a
/// healthy 97 modulated 30 % at the cage rate showed BPFI lines on one half only) that the model —
/// its declared fault and the faults already added — leaves healthy, as a spall simulated beside
/// the declared one at the widths [`ADDED_FAULT_WIDTHS`] × the declared width, each calibrated
/// warm and cold, seen through the model's present shaping and — while the model has not
/// identified the path its own impacts ring — through a path identified with it
/// ([`with_impacts_path`]); the best that lowers the fitting error `fit_lsd` is the candidate,
/// judged on the held-out segment as any other. The envelope names the location, the spectral
/// error judges whether the fault's physics explains the recording: the spectral error alone
/// prefers an inner race on any record, healthy 97 included (docs/equations/close-loop.md, "A
/// fault nobody declared"). Only for a model with spalls (the 5-DOF physics).
pub(super) fn added_fault_candidates(ctx: &Ctx<'_>, st: &State, fit_lsd: f64) -> Vec<Evaluated> {
    let model = ctx.model_of(st);
    let Some(width) = model.fault_size_in() else {
        return Vec::new();
    };
    let added = model.added_faults();
    let open: Vec<(FaultLocation, f64)> = ctx
        .detected
        .iter()
        .copied()
        .filter(|(l, _)| !l.in_class(ctx.op.fault) && !added.iter().any(|(a, _)| a == l))
        .collect();
    if open.is_empty() {
        return Vec::new();
    }
    // the fitting error with a path of the model's present impacts alone (when it has impacts
    // and no such path yet), computed when a spall with a path of its own is first weighed: such
    // a spall must explain more than that path does without it (the loop's margin), or the
    // path's improvement would be credited to the spall (160, an outer race at 12 o'clock, took
    // a "ball fault" with a path 5.97 → 3.59 dB where the path alone of its declared fault's
    // impacts gave nearly as much)
    let path_alone = std::cell::OnceCell::new();
    let path_alone = || {
        *path_alone.get_or_init(|| {
            (has_impacts(ctx, st) && !st.phys_path_fitted)
                .then(|| with_impacts_path(ctx, st))
                .flatten()
                .map(|(s, _)| ctx.calibrate_warm_and_cold(s).1)
        })
    };
    let margin = ctx.cfg.get().margin;
    let mut out = Vec::new();
    for (location, score_db) in open {
        let Some(&order) = ctx.op.bearing.impact_orders(location.class()).first() else {
            continue;
        };
        let mut best: Option<(f64, State, f64, Option<usize>)> = None;
        for &k in &ADDED_FAULT_WIDTHS {
            let Some(m) = model.with_added_fault(location, k * width) else {
                continue;
            };
            let m: Arc<dyn DeclaredModel> = Arc::from(m);
            let Some(s2) = speed::rebased(ctx, st, &m, st.base.ratio, st.defect_rate) else {
                continue;
            };
            // the new impacts seen through the model's present shaping, and, while the model
            // has not identified a path of its own impacts, through one identified now on the
            // residual the spall leaves (added alone, the spall rings the declared housing mode
            // or the healthy background's path: from the rig's machine model the outer race of
            // 235 declared healthy was eight channel modes)
            let pathed = (!s2.phys_path_fitted)
                .then(|| with_impacts_path(ctx, &s2))
                .flatten();
            let versions =
                std::iter::once((s2, None)).chain(pathed.map(|(s, pp)| (s, Some(pp.path.order()))));
            for (s2, path_order) in versions {
                let (s2, lsd) = ctx.calibrate_warm_and_cold(s2);
                let beats_path =
                    path_order.is_none() || path_alone().is_none_or(|p| lsd < p * (1.0 - margin));
                if lsd < fit_lsd && beats_path && best.as_ref().is_none_or(|b| lsd < b.2) {
                    best = Some((k, s2, lsd, path_order));
                }
            }
        }
        if let Some((k, state, lsd, path_order)) = best {
            out.push(Evaluated {
                effect: Effect::AddedFault {
                    location,
                    order,
                    frequency_hz: order * ctx.op.shaft_hz() * st.base.ratio,
                    size_in: k * width,
                    diagnosis_score_db: score_db,
                    path_order,
                    at_bound: k == ADDED_FAULT_WIDTHS[0]
                        || k == ADDED_FAULT_WIDTHS[ADDED_FAULT_WIDTHS.len() - 1],
                },
                state,
                fit_lsd: lsd,
            });
        }
    }
    out
}
