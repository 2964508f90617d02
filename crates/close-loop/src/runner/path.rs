//! The structural path candidates: the broadband path of the machine and the path the fault's
//! impacts ring, identified on the fitting segment's line-free PSD.

use super::{Evaluated, refine_between};
use crate::effect::Effect;
use crate::engine::{Ctx, PathPsd, State};
use std::sync::Arc;

/// What a structural path's order is scored against ([`identify_path`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PathTarget {
    /// The fitting segment's PSD, lines included: the background path of a model without one.
    Measured,
    /// The line-free PSD the path is identified from, averaged onto the metric grid: the path
    /// the declared fault's impacts ring, whose lines the physics already carries, once the
    /// model has a background path of its own (a machine model's, or one taken earlier).
    LineFree,
}

/// Identify a structural path from the fitting segment's line-free PSD
/// ([`crate::path::identify`], the smallest order within 0.1 dB of the best by the regularised
/// LSD of the path alone against `target`).
///
/// The path the fault's impacts ring is scored against the line-free PSD: scored against the PSD
/// with its lines, strong lines the model lacks (a mains comb at 12 % of the RMS per line) add
/// the same large error to every order, the orders' differences shrink under the tolerance and
/// the smallest order wins (235.mat with a 50/100/150 Hz comb: AR 64 → 8, 3.9 dB against the
/// control's 2.4). The background path, and the fault's path while the model has no background
/// path, keep the measured PSD: on a fault recording without a machine model every path
/// candidate competes to explain the whole spectrum, and scored line-free an AR-128 path took a
/// channel mode that shapes the fault's lines too, which then came back as "tones" and a "shaft
/// comb" at the fault's harmonics (`undeclared::resonance_is_found`).
fn identify_path(
    ctx: &Ctx<'_>,
    st: &State,
    target: PathTarget,
) -> Option<crate::path::StructuralPath> {
    let c = ctx.cfg.get();
    let df = ctx.welch.df();
    let n_bins = ctx.welch.n_bins();
    let resid = ctx.fit_residual(st);
    let s_hi = ctx.welch_hi.try_psd(&resid).ok()?;
    let df_hi = ctx.welch_hi.df();
    let free_hi = crate::path::path_line_free(&s_hi, df_hi);
    let free;
    let score_against = match target {
        PathTarget::Measured => &ctx.s_fit,
        PathTarget::LineFree => {
            free = crate::spectrum::coarsen_psd(&free_hi, df_hi, df, n_bins);
            &free
        }
    };
    crate::path::identify_line_free(&free_hi, df_hi, ctx.fs, c.max_path_order, 0.1, |p| {
        let m = p.psd(n_bins, df);
        crate::metric::regularised_lsd(score_against, &m, ctx.bins.clone(), ctx.eps)
    })
    .ok()
}

/// The structural path as a candidate, in two places: when the model has no broadband path yet,
/// the path rung by broadband excitation; when a fault is declared and its physics is not yet
/// behind a path identified on this recording, the path the fault's impacts ring (the physics
/// keeps its lines, the data gives the resonances: [`Ctx::physics_shape`]).
pub(super) fn path_candidates(ctx: &Ctx<'_>, st: &State) -> Vec<Evaluated> {
    let n_bins = ctx.welch.n_bins();
    let df = ctx.welch.df();
    let want_broadband = st.path.is_none();
    // the path the impacts ring: of the declared fault, or of a fault the loop added
    let want_physics = !st.phys_path_fitted && has_impacts(ctx, st);
    if !(want_broadband || want_physics) {
        return Vec::new();
    }
    let mut out = Vec::new();
    if let Some(path) = want_broadband
        .then(|| identify_path(ctx, st, PathTarget::Measured))
        .flatten()
    {
        let order = path.order();
        let pp = Arc::new(PathPsd::new(path, n_bins, df));
        let mut s2 = st.clone();
        s2.path = Some(pp.clone());
        s2.log_bg = 0.0;
        let (s2, lsd) = ctx.calibrate(s2, true);
        out.push(Evaluated {
            effect: Effect::StructuralPath {
                order,
                modes: pp.modes.clone(),
                physics: false,
            },
            state: s2,
            fit_lsd: lsd,
        });
    }
    if let Some((s2, pp)) = want_physics.then(|| with_impacts_path(ctx, st)).flatten() {
        let order = pp.path.order();
        let (s2, lsd) = ctx.calibrate(s2, true);
        out.push(Evaluated {
            effect: Effect::StructuralPath {
                order,
                modes: pp.modes.clone(),
                physics: true,
            },
            state: s2,
            fit_lsd: lsd,
        });
    }
    out
}

/// Whether the physics of `st` has impacts: a declared fault, or a fault the loop added.
pub(super) fn has_impacts(ctx: &Ctx<'_>, st: &State) -> bool {
    !crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty()
        || !ctx.model_of(st).added_faults().is_empty()
}

/// `st` with the path its fault's impacts ring identified on its fitting residual
/// ([`identify_path`]) and the physics seen through it (not yet calibrated), and that path;
/// `None` when no path can be identified. While the model has no background path, the fault's
/// path competes to explain the whole spectrum, lines included; once it has one, the fault's
/// path is the shape under lines the physics already carries.
pub(super) fn with_impacts_path(ctx: &Ctx<'_>, st: &State) -> Option<(State, Arc<PathPsd>)> {
    let target = if st.path.is_some() {
        PathTarget::LineFree
    } else {
        PathTarget::Measured
    };
    let path = identify_path(ctx, st, target)?;
    let pp = Arc::new(PathPsd::new(path, ctx.welch.n_bins(), ctx.welch.df()));
    let mut s2 = st.clone();
    s2.phys_shape = Some(Arc::new(ctx.physics_shape(&st.base.psd, &pp)));
    s2.phys_path = Some(pp.clone());
    s2.phys_path_fitted = true;
    Some((s2, pp))
}

/// Corners the physics high-pass is tried at: log-spaced from [`HIGHPASS_MIN_HZ`] to
/// [`HIGHPASS_MAX_FS`]·fs, this many.
const HIGHPASS_GRID: usize = 12;
/// Lowest corner tried, Hz.
const HIGHPASS_MIN_HZ: f64 = 50.0;
/// Highest corner tried, as a fraction of the sampling rate.
const HIGHPASS_MAX_FS: f64 = 0.25;
/// Butterworth order of the physics high-pass.
const HIGHPASS_ORDER: u32 = 2;
/// Golden-section steps refining the best corner between its grid neighbours.
const HIGHPASS_REFINE: usize = 8;

/// A high-pass on the physics part ([`Effect::ImpactsHighPass`]): the fault's impacts reach the
/// sensor weaker below a corner than the path they are seen through gives. That path is
/// identified where the impacts dominate, near the resonance; below, its gain is an
/// extrapolation, and the physics' low BPFO harmonics (14–21 dB combs at 200–1100 Hz on 130.mat)
/// stand over a measured spectrum that shows none. Without this candidate a random slip at the
/// model's bound smeared them away, and the comb the measurement keeps at the resonance with it
/// (`docs/journal/close-loop.md`, "What the slip at the model's bound does not mean"). Only
/// with impacts behind a path; the corner on a log grid, each calibrated warm and cold, the best
/// refined by golden section between its neighbours. Nothing is re-simulated.
pub(super) fn highpass_candidate(ctx: &Ctx<'_>, st: &State) -> Option<Evaluated> {
    if !has_impacts(ctx, st) || st.phys_shape.is_none() {
        return None;
    }
    let (lo, hi) = (HIGHPASS_MIN_HZ.ln(), (HIGHPASS_MAX_FS * ctx.fs).ln());
    if hi <= lo {
        return None;
    }
    let eval = |log_corner: f64| -> Option<(State, f64)> {
        let mut s2 = st.clone();
        s2.phys_highpass = Some((log_corner.exp(), HIGHPASS_ORDER));
        Some(ctx.calibrate_warm_and_cold(s2))
    };
    let grid: Vec<f64> = (0..HIGHPASS_GRID)
        .map(|i| lo + (hi - lo) * i as f64 / (HIGHPASS_GRID - 1) as f64)
        .collect();
    let mut best: Option<(usize, f64, State, f64)> = None;
    for (i, &x) in grid.iter().enumerate() {
        let Some((s2, lsd)) = eval(x) else { continue };
        if lsd.is_finite() && best.as_ref().is_none_or(|b| lsd < b.3) {
            best = Some((i, x, s2, lsd));
        }
    }
    let (i, x, s2, lsd) = best?;
    let (x_best, s_best, lsd_best) = refine_between(&grid, i, (x, s2, lsd), eval, HIGHPASS_REFINE);
    if st
        .phys_highpass
        .is_some_and(|(c, _)| (c.ln() - x_best).abs() < 1e-9)
    {
        return None;
    }
    let at_bound = (x_best - lo).abs() < 1e-9 || (x_best - hi).abs() < 1e-9;
    Some(Evaluated {
        effect: Effect::ImpactsHighPass {
            corner_hz: x_best.exp(),
            order: HIGHPASS_ORDER,
            at_bound,
        },
        state: s_best,
        fit_lsd: lsd_best,
    })
}
