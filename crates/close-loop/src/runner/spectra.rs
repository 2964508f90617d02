//! What the ledger and the loop measure of a state: the observer residual's held-out RMS, the
//! report's spectra, the fitting segment's log ratio and the Welch segment count.

use crate::engine::{Ctx, State};
use crate::report::Spectra;

/// Held-out RMS of the observer residual of y − (the state's phase-coherent lines), the observer
/// being the state's model's ([`crate::observe`]); `None` if the identification or the observer
/// fails on this signal.
pub(super) fn observer_rms(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
    let all = 0..ctx.y.len();
    let d = ctx.lines_signal(&st.all_lines(), all);
    let sig: Vec<f64> = ctx.y.iter().zip(&d).map(|(a, b)| a - b).collect();
    residual_observer(ctx, st)
        .held_out_rms(&sig, ctx.n_fit, ctx.fs)
        .ok()
}

/// The observer of the state's model: a physics model with a structural path (the broadband
/// path of the machine, else the path the physics is seen through) is observed on that path —
/// the calibrated model, whose residual then carries what the healthy machine does not explain
/// — and otherwise on what the declared model names (its housing mode, or the ARX-Laguerre
/// model identified on the fitting segment).
pub(super) fn residual_observer(ctx: &Ctx<'_>, st: &State) -> crate::observe::ResidualObserver {
    let own = ctx.model_of(st).residual_observer(ctx.fs);
    match (&own, st.path.as_ref().or(st.phys_path.as_ref())) {
        (crate::observe::ResidualObserver::Physics { .. }, Some(p)) => {
            crate::observe::ResidualObserver::CalibratedPath {
                ar: p.path.ar.clone(),
            }
        }
        _ => own,
    }
}

pub(super) fn spectra(ctx: &Ctx<'_>, first: &State, last: &State) -> Spectra {
    let held = ctx.held();
    let model = |st: &State| {
        let sh = ctx.shaped(st);
        let lp = ctx.lines_psd(&st.lines, held.clone());
        ctx.model_psd(st, &sh, &lp)
    };
    Spectra {
        frequency_hz: (0..ctx.welch.n_bins())
            .map(|k| ctx.welch.frequency(k))
            .collect(),
        measured: ctx.s_held.clone(),
        model_before: model(first),
        model_after: model(last),
    }
}

/// The log ratio 10·log10(S_y/S_m) on the fitting segment over the scored band.
pub(super) fn log_ratio(ctx: &Ctx<'_>, st: &State) -> Vec<f64> {
    let sh = ctx.shaped(st);
    let lp = ctx.lines_psd(&st.lines, 0..ctx.n_fit);
    let m = ctx.model_psd(st, &sh, &lp);
    ctx.bins
        .clone()
        .map(|k| 10.0 * (ctx.s_fit[k].max(1e-300) / m[k].max(1e-300)).log10())
        .collect()
}

/// Number of half-overlapped Welch segments of `nperseg` in `n` samples.
pub(super) fn segments(n: usize, nperseg: usize) -> usize {
    (2 * n / nperseg.max(1)).saturating_sub(1).max(1)
}
