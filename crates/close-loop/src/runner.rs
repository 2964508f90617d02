//! The loop: residual → candidate effects (detectors) → fit on the fitting segment → keep the best
//! one that lowers the held-out error by the margin → repeat; stop when none does.

use crate::effect::{Effect, Line, Mode, Modulation};
use crate::engine::{Base, Ctx, ModelRef, PathPsd, State};
use crate::machine::MachineModel;
use crate::optimize::golden_min;
use crate::report::{
    Declared, EffectEntry, Ledger, Outcome, PRIMARY_METRIC, Protocol, RejectedCandidate,
    SECONDARY_METRIC, Spectra,
};
use crate::spectrum::{
    PeakRefiner, Welch, envelope, envelope_periodogram, hann_windowed, refine_peak, running_median,
};
use crate::{CheckedConfig, CloseLoopError, DeclaredModel, OperatingPoint};
use std::sync::Arc;

/// Smallest Welch segment the loop accepts.
pub const MIN_NPERSEG: usize = 256;

/// Samples a recording needs for `cfg`: both parts must hold `min_segments` Welch segments of
/// [`MIN_NPERSEG`] samples.
pub fn min_samples(cfg: &CheckedConfig) -> usize {
    let c = cfg.get();
    let part = MIN_NPERSEG * (c.min_segments + 1) / 2;
    let frac = c.fit_fraction.min(1.0 - c.fit_fraction);
    (part as f64 / frac).ceil() as usize + 1
}

/// Length of the fitting segment `[0, n_fit)` of an `n`-sample recording (the rest is held out).
/// A model identified from the recording (e.g. [`crate::observe::ArxLaguerreDeclared`]) must be
/// identified on `y[..fit_len(y.len(), cfg)]` only.
pub fn fit_len(n: usize, cfg: &CheckedConfig) -> usize {
    (n as f64 * cfg.get().fit_fraction).round() as usize
}

/// Run the loop on a recording `y` sampled at `fs` Hz, with the model told `op`.
///
/// # Errors
/// Bad input ([`CloseLoopError::TooShort`], [`CloseLoopError::NonFinite`],
/// [`CloseLoopError::InvalidSamplingRate`], [`CloseLoopError::InvalidRpm`],
/// [`CloseLoopError::ZeroSignal`]) or a failing model.
pub fn close_loop(
    model: &dyn DeclaredModel,
    y: &[f64],
    fs: f64,
    op: &OperatingPoint,
    cfg: &CheckedConfig,
) -> Result<Outcome, CloseLoopError> {
    close_loop_from(model, None, y, fs, op, cfg)
}

/// [`close_loop`] starting from a calibrated machine model: its speed ratio, structural path,
/// channel modes and lines (re-fitted in amplitude and phase on this recording's fitting
/// segment) are part of the declared model, and the declared physics is seen through its path.
/// The machine model must match the recording's sampling rate (checked by
/// [`MachineModel::check_compatible`]).
///
/// # Errors
/// As [`close_loop`], plus [`CloseLoopError::MachineModelMismatch`].
pub fn close_loop_from(
    model: &dyn DeclaredModel,
    prior: Option<&MachineModel>,
    y: &[f64],
    fs: f64,
    op: &OperatingPoint,
    cfg: &CheckedConfig,
) -> Result<Outcome, CloseLoopError> {
    let c = cfg.get();
    if let Some(m) = prior {
        m.check_compatible(fs, op.bearing.name)?;
    }
    if !(fs.is_finite() && fs > 0.0) {
        return Err(CloseLoopError::InvalidSamplingRate { fs });
    }
    if !(op.rpm.is_finite() && op.rpm > 0.0) {
        return Err(CloseLoopError::InvalidRpm { rpm: op.rpm });
    }
    let needed = min_samples(cfg);
    if y.len() < needed {
        return Err(CloseLoopError::TooShort {
            needed,
            found: y.len(),
        });
    }
    if let Some(index) = y.iter().position(|v| !v.is_finite()) {
        return Err(CloseLoopError::NonFinite { index });
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    if y.iter().all(|v| (v - mean).abs() <= 1e-300) {
        return Err(CloseLoopError::ZeroSignal);
    }
    let n_fit = fit_len(y.len(), cfg);
    let shortest = n_fit.min(y.len() - n_fit);
    let mut nperseg = (fs / c.resolution_hz).log2().round().exp2() as usize;
    nperseg = nperseg.clamp(MIN_NPERSEG, 1 << 20);
    while nperseg > MIN_NPERSEG && (2 * shortest / nperseg).saturating_sub(1) < c.min_segments {
        nperseg /= 2;
    }
    let mut nperseg_hi = 8 * nperseg;
    while nperseg_hi > nperseg && 4 * nperseg_hi > n_fit {
        nperseg_hi /= 2;
    }
    let welch = Welch::new(fs, nperseg)?;
    let welch_hi = Welch::new(fs, nperseg_hi)?;
    let band_hi = c.band_high_fraction * fs;
    let k_lo = ((c.band_low_hz / welch.df()).ceil() as usize).max(1);
    let k_hi = ((band_hi / welch.df()).floor() as usize).min(welch.n_bins() - 1);
    let kh_lo = ((c.band_low_hz / welch_hi.df()).ceil() as usize).max(1);
    let kh_hi = ((band_hi / welch_hi.df()).floor() as usize).min(welch_hi.n_bins() - 1);
    if k_hi <= k_lo + 8 {
        return Err(CloseLoopError::ParameterOutOfRange {
            name: "band_low_hz",
            value: c.band_low_hz,
            min: 0.0,
            max: band_hi,
        });
    }
    let s_fit = welch.try_psd(&y[..n_fit])?;
    let eps = crate::metric::floor_of(&s_fit, k_lo..k_hi + 1, c.floor_db);
    let ctx = Ctx {
        y,
        fs,
        n_fit,
        eps,
        rejected_ratios: std::sync::Mutex::new(Vec::new()),
        s_fit,
        s_held: welch.try_psd(&y[n_fit..])?,
        s_fit_hi: welch_hi.try_psd(&y[..n_fit])?,
        welch,
        welch_hi,
        bins: k_lo..k_hi + 1,
        bins_hi: kh_lo..kh_hi + 1,
        op: *op,
        model,
        cfg,
    };
    run(&ctx, prior)
}

/// A candidate evaluated on the fitting segment.
struct Evaluated {
    effect: Effect,
    state: State,
    fit_lsd: f64,
}

fn run(ctx: &Ctx<'_>, prior: Option<&MachineModel>) -> Result<Outcome, CloseLoopError> {
    let c = ctx.cfg.get();
    let st0 = match prior {
        None => State {
            model: None,
            physics_lines: Vec::new(),
            base: ctx.make_base(1.0)?,
            modes: Vec::new(),
            mods: Vec::new(),
            lines: Vec::new(),
            path: None,
            phys_shape: None,
            phys_path: None,
            phys_path_fitted: false,
            log_gain: 0.0,
            log_floor: 0.0,
            log_bg: 0.0,
        },
        Some(m) => prior_state(ctx, m)?,
    };
    let (mut st, mut fit_lsd) = ctx.calibrate(st0, true);
    let first = st.clone();
    let mut held = ctx.held_scores(&st);
    let before = held;
    let noise = crate::metric::estimation_lsd(
        segments(ctx.y.len() - ctx.n_fit, ctx.welch.nperseg()),
        Some(segments(ctx.n_fit, ctx.welch.nperseg())),
    );
    let mut obs = observer_rms(ctx, &st);
    let obs_before = obs;
    let mut effects = Vec::new();
    let mut rejected = Vec::new();
    let mut stop_reason = format!("reached the maximum of {} effects", c.max_effects);
    for _round in 0..c.max_effects {
        // within the estimator's own scatter, only lines (a detection that stands on its own:
        // a narrow peak above the local floor that the model does not carry) are still tried;
        // broadband candidates would be fitting estimation noise
        let lines_only = held.lsd <= c.noise_stop_factor * noise;
        let mut cands = candidates(ctx, &st)?;
        cands.retain(|e| e.fit_lsd.is_finite() && e.fit_lsd < fit_lsd);
        if lines_only {
            cands.retain(|e| e.effect.is_line());
        }
        cands.sort_by(|a, b| a.fit_lsd.total_cmp(&b.fit_lsd));
        rejected.clear();
        let mut accepted = None;
        for mut cand in cands {
            // a shaft harmonic is scored as a sensor line in the search; the one about to be
            // judged goes into the physics (3 simulations) and is judged as such, falling back
            // to the sensor line if the model has no shaft or the simulations fail
            if let Effect::ShaftHarmonic {
                order,
                line,
                shaft_hz,
                force: None,
            } = cand.effect
                && order.fract() == 0.0
                && let Some(ev) = shaft_force_candidate(ctx, &st, order as u32, line, shaft_hz)
            {
                cand = ev;
            }
            let h = ctx.held_scores(&cand.state);
            if h.lsd <= held.lsd * (1.0 - c.margin) && held.lsd - h.lsd >= c.min_improvement_db {
                accepted = Some((cand, h));
                break;
            }
            if let Effect::SpeedOffset { ratio, .. } = cand.effect {
                ctx.rejected_ratios
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .push(ratio);
            }
            rejected.push(RejectedCandidate {
                kind: cand.effect.kind(),
                frequency_hz: cand.effect.frequency_hz(),
                fit_error: cand.fit_lsd,
                held_out_error: Some(h.lsd),
            });
        }
        let Some((cand, h)) = accepted else {
            stop_reason = if lines_only && rejected.is_empty() {
                format!(
                    "the held-out error {:.3} dB is within {:.2} x the {:.3} dB a correct model \
                     shows from estimation variance alone, and no line stands out",
                    held.lsd, c.noise_stop_factor, noise
                )
            } else if rejected.is_empty() {
                "no candidate effect lowered the fitting-segment error".to_string()
            } else {
                format!(
                    "no candidate lowered the held-out error by at least {:.1} % and {:.2} dB",
                    100.0 * c.margin,
                    c.min_improvement_db
                )
            };
            break;
        };
        effects.push(EffectEntry {
            kind: cand.effect.kind(),
            frequency_hz: cand.effect.frequency_hz(),
            parameters: cand.effect.parameters(),
            placement: cand.effect.placement(),
            description: cand.effect.describe(),
            error_before: held.lsd,
            error_after: h.lsd,
            secondary_before: held.rms,
            secondary_after: h.rms,
            fit_error_before: fit_lsd,
            fit_error_after: cand.fit_lsd,
            residual_rms_before: obs,
            residual_rms_after: None,
        });
        st = cand.state;
        obs = observer_rms(ctx, &st);
        if let Some(e) = effects.last_mut() {
            e.residual_rms_after = obs;
        }
        fit_lsd = cand.fit_lsd;
        held = h;
    }
    let spectra = spectra(ctx, &first, &st);
    let machine = MachineModel::from_state(ctx, &st, &effects, before.lsd, held.lsd);
    let ledger = Ledger {
        error_metric: PRIMARY_METRIC.to_string(),
        error_before: before.lsd,
        error_after: held.lsd,
        secondary_metric: SECONDARY_METRIC.to_string(),
        secondary_before: before.rms,
        secondary_after: held.rms,
        observer: ctx.model_of(&st).residual_observer(ctx.fs).describe(),
        residual_rms_before: obs_before,
        residual_rms_after: obs,
        held_out_signal_rms: crate::metric::rms(&ctx.y[ctx.n_fit..]),
        effects,
        rejected,
        stop_reason,
        declared: Declared {
            model: ctx.model.name().to_string(),
            rpm: ctx.op.rpm,
            bearing: ctx.op.bearing.name.to_string(),
            fault: ctx.op.fault.name().to_string(),
            fs: ctx.fs,
        },
        protocol: Protocol {
            fit_samples: [0, ctx.n_fit],
            held_out_samples: [ctx.n_fit, ctx.y.len()],
            nperseg: ctx.welch.nperseg(),
            df_hz: ctx.welch.df(),
            band_hz: [
                ctx.welch.frequency(ctx.bins.start),
                ctx.welch.frequency(ctx.bins.end - 1),
            ],
            margin: c.margin,
            floor_db: c.floor_db,
            floor_psd: ctx.eps,
            estimation_lsd_db: noise,
        },
        structural_modes: st
            .path
            .as_ref()
            .map(|p| p.modes.clone())
            .unwrap_or_default(),
    };
    Ok(Outcome {
        ledger,
        spectra,
        machine,
    })
}

/// Held-out RMS of the observer residual of y − (the state's phase-coherent lines), the observer
/// being the state's model's ([`crate::observe`]); `None` if the identification or the observer
/// fails on this signal.
fn observer_rms(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
    let all = 0..ctx.y.len();
    let d = ctx.lines_signal(&st.all_lines(), all);
    let sig: Vec<f64> = ctx.y.iter().zip(&d).map(|(a, b)| a - b).collect();
    ctx.model_of(st)
        .residual_observer(ctx.fs)
        .held_out_rms(&sig, ctx.n_fit, ctx.fs)
        .ok()
}

fn spectra(ctx: &Ctx<'_>, first: &State, last: &State) -> Spectra {
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
fn log_ratio(ctx: &Ctx<'_>, st: &State) -> Vec<f64> {
    let sh = ctx.shaped(st);
    let lp = ctx.lines_psd(&st.lines, 0..ctx.n_fit);
    let m = ctx.model_psd(st, &sh, &lp);
    ctx.bins
        .clone()
        .map(|k| 10.0 * (ctx.s_fit[k].max(1e-300) / m[k].max(1e-300)).log10())
        .collect()
}

/// Number of half-overlapped Welch segments of `nperseg` in `n` samples.
fn segments(n: usize, nperseg: usize) -> usize {
    (2 * n / nperseg.max(1)).saturating_sub(1).max(1)
}

/// The initial state of a run that starts from a calibrated machine model.
fn prior_state(ctx: &Ctx<'_>, m: &MachineModel) -> Result<State, CloseLoopError> {
    let ratio = m.speed_ratio;
    let base = ctx.make_base(ratio)?;
    let fr = ctx.op.shaft_hz() * ratio;
    let resid = &ctx.y[..ctx.n_fit];
    let mut lines: Vec<Line> = Vec::new();
    for f in m.line_frequencies(fr) {
        if f > 0.0 && f < 0.5 * ctx.fs {
            lines.push(fit_line(resid, ctx.fs, f));
        }
    }
    let df = ctx.welch.df();
    let n_bins = ctx.welch.n_bins();
    let path = m
        .path
        .as_ref()
        .map(|p| Arc::new(PathPsd::new(p.clone(), n_bins, df)));
    // the declared physics keeps its line structure (kinematics, modulation) and is seen
    // through the structural path identified from data: the machine's physics path if it has
    // one, else its broadband path
    let phys_path = m
        .physics_path
        .as_ref()
        .or(m.path.as_ref())
        .map(|p| Arc::new(PathPsd::new(p.clone(), n_bins, df)));
    let phys_path_fitted = false;
    let phys_shape = phys_path
        .as_ref()
        .map(|p| Arc::new(ctx.physics_shape(&base.psd, &p.path)));
    Ok(State {
        model: None,
        physics_lines: Vec::new(),
        base,
        modes: m.channel_modes.clone(),
        mods: m.modulations.clone(),
        lines,
        path,
        phys_shape,
        phys_path,
        phys_path_fitted,
        log_gain: m.physics_gain.max(1e-300).ln(),
        log_floor: m.noise_floor_psd.max(1e-300).ln(),
        log_bg: m.path_level.max(1e-300).ln(),
    })
}

/// Identify a structural path from the fitting segment's line-free PSD
/// ([`crate::path::identify`], order by the regularised LSD of the path alone).
fn identify_path(ctx: &Ctx<'_>, st: &State) -> Option<crate::path::StructuralPath> {
    let c = ctx.cfg.get();
    let df = ctx.welch.df();
    let n_bins = ctx.welch.n_bins();
    let resid = ctx.fit_residual(st);
    let s_hi = ctx.welch_hi.try_psd(&resid).ok()?;
    crate::path::identify(
        &s_hi,
        ctx.welch_hi.df(),
        ctx.fs,
        c.max_path_order,
        0.1,
        |p| {
            let m = p.psd(n_bins, df);
            crate::metric::regularised_lsd(&ctx.s_fit, &m, ctx.bins.clone(), ctx.eps)
        },
    )
    .ok()
}

/// The structural path as a candidate, in two places: when the model has no broadband path yet,
/// the path rung by broadband excitation; when a fault is declared and its physics is not yet
/// behind a path identified on this recording, the path the fault's impacts ring (the physics
/// keeps its lines, the data gives the resonances: [`Ctx::physics_shape`]).
fn path_candidates(ctx: &Ctx<'_>, st: &State) -> Vec<Evaluated> {
    let n_bins = ctx.welch.n_bins();
    let df = ctx.welch.df();
    let want_broadband = st.path.is_none();
    let want_physics =
        !st.phys_path_fitted && !crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty();
    if !(want_broadband || want_physics) {
        return Vec::new();
    }
    let Some(path) = identify_path(ctx, st) else {
        return Vec::new();
    };
    let order = path.order();
    let pp = Arc::new(PathPsd::new(path, n_bins, df));
    let mut out = Vec::new();
    if want_broadband {
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
    if want_physics {
        let mut s2 = st.clone();
        s2.phys_shape = Some(Arc::new(ctx.physics_shape(&st.base.psd, &pp.path)));
        s2.phys_path = Some(pp.clone());
        s2.phys_path_fitted = true;
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

fn candidates(ctx: &Ctx<'_>, st: &State) -> Result<Vec<Evaluated>, CloseLoopError> {
    let lr = log_ratio(ctx, st);
    let mut out = Vec::new();
    out.extend(path_candidates(ctx, st));
    out.extend(line_candidates(ctx, st, &lr));
    out.extend(resonance_candidates(ctx, st, &lr));
    out.extend(speed_candidates(ctx, st)?);
    out.extend(slip_candidate(ctx, st));
    out.extend(modulation_candidates(ctx, st));
    Ok(out)
}

/// Least-squares a·cos + b·sin at `f` on `x` (sample 0 of `x` is sample 0 of the recording).
fn fit_line(x: &[f64], fs: f64, f: f64) -> Line {
    let w = 2.0 * std::f64::consts::PI * f / fs;
    let (mut cc, mut cs, mut ss, mut xc, mut xs) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (sw, cw) = w.sin_cos();
    // phasor recurrence, re-anchored exactly every 256 samples
    for (j, chunk) in x.chunks(256).enumerate() {
        let (mut s, mut c) = (w * (256 * j) as f64).sin_cos();
        for v in chunk {
            cc += c * c;
            cs += c * s;
            ss += s * s;
            xc += v * c;
            xs += v * s;
            (s, c) = (s * cw + c * sw, c * cw - s * sw);
        }
    }
    let det = cc * ss - cs * cs;
    if det.abs() < 1e-12 {
        return Line {
            frequency_hz: f,
            a: 0.0,
            b: 0.0,
        };
    }
    Line {
        frequency_hz: f,
        a: (ss * xc - cs * xs) / det,
        b: (cc * xs - cs * xc) / det,
    }
}

/// Narrow lines of the fitting residual (y − the lines already in the model) that the model does
/// not carry: on the fine Welch grid, the residual's log PSD above its running median (±~25 Hz)
/// minus the same excess of the model's own simulated output (its fault lines), peaks above
/// `line_threshold_db`, ranked by the power they carry above the background — what they explain.
fn line_candidates(ctx: &Ctx<'_>, st: &State, lr: &[f64]) -> Vec<Evaluated> {
    let c = ctx.cfg.get();
    if c.max_line_candidates == 0 {
        return Vec::new();
    }
    let resid = ctx.fit_residual(st);
    let Ok(s) = ctx.welch_hi.try_psd(&resid) else {
        return Vec::new();
    };
    let dfh = ctx.welch_hi.df();
    let bins = ctx.bins_hi.clone();
    let half = ((25.0 / dfh).round() as usize).max(6);
    let ly: Vec<f64> = bins
        .clone()
        .map(|k| 10.0 * s[k].max(1e-300).log10())
        .collect();
    let my = running_median(&ly, half);
    let lm: Vec<f64> = bins
        .clone()
        .map(|k| {
            10.0 * st
                .base
                .psd_hi
                .get(k)
                .copied()
                .unwrap_or(0.0)
                .max(1e-300)
                .log10()
        })
        .collect();
    let mm = running_median(&lm, half);
    // the model's lines count only where the model carries power near the measurement's level
    let gain_db = 10.0 * st.log_gain / std::f64::consts::LN_10;
    let ex: Vec<f64> = (0..ly.len())
        .map(|i| {
            // the model's own line counts only where the model holds the measured power there
            // (log ratio on the metric grid under 3 dB)
            let f = ctx.welch_hi.frequency(bins.start + i);
            let km = ((f / ctx.welch.df()).round() as usize).saturating_sub(ctx.bins.start);
            let explained = lr.get(km).is_none_or(|v| *v < 3.0);
            let model_ex = if explained && lm[i] + gain_db > my[i] - 3.0 {
                (lm[i] - mm[i]).max(0.0)
            } else {
                0.0
            };
            ly[i] - my[i] - model_ex
        })
        .collect();
    let mut peaks: Vec<(usize, f64)> = (1..ex.len().saturating_sub(1))
        .filter(|&i| ex[i] > c.line_threshold_db && ly[i] >= ly[i - 1] && ly[i] >= ly[i + 1])
        .map(|i| {
            let k = bins.start + i;
            let above = s[k] - 10f64.powf(my[i] / 10.0);
            (i, above.max(0.0))
        })
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    let xw = hann_windowed(&resid);
    let refiner = PeakRefiner::new(&xw, ctx.fs);
    let fr = ctx.op.shaft_hz() * st.base.ratio;
    let mut out = Vec::new();
    // combs: every standing line refined once, then grouped
    let refined: Vec<(f64, f64)> = peaks
        .iter()
        .take(32)
        .map(|&(i, p)| {
            let f0 = ctx.welch_hi.frequency(bins.start + i);
            (
                refiner.refine((f0 - 1.5 * dfh).max(0.5 * dfh), f0 + 1.5 * dfh),
                p,
            )
        })
        .collect();
    out.extend(shaft_comb_candidate(ctx, st, &resid, &refined, fr));
    out.extend(line_comb_candidate(ctx, st, &resid, &refined, fr));
    let mut chosen: Vec<usize> = Vec::new();
    for (i, _) in peaks {
        if chosen.iter().all(|&j| j.abs_diff(i) > 2) {
            chosen.push(i);
        }
        if chosen.len() >= c.max_line_candidates {
            break;
        }
    }
    for i in chosen {
        let f0 = ctx.welch_hi.frequency(bins.start + i);
        let f = refiner.refine((f0 - 1.5 * dfh).max(0.5 * dfh), f0 + 1.5 * dfh);
        let line = fit_line(&resid, ctx.fs, f);
        let effect = classify_line(line, fr, c);
        let mut s2 = st.clone();
        s2.lines.push(line);
        let (s2, lsd) = ctx.calibrate(s2, false);
        out.push(Evaluated {
            effect,
            state: s2,
            fit_lsd: lsd,
        });
    }
    out
}

/// Largest distance of a comb member from its shaft order, in orders.
const COMB_ORDER_TOLERANCE: f64 = 0.05;

/// Fewest lines that make a comb.
const MIN_COMB_LINES: usize = 4;

/// A shaft-synchronous comb: the standing lines that sit at integer shaft orders (within
/// `harmonic_tolerance` and a quarter order), fr refined by weighted least squares of f_k = k·fr
/// over them, every order fitted as a phase-coherent line at k·fr̂ — what a time-synchronous
/// average of the shaft-synchronous part holds. Needs [`MIN_COMB_LINES`] orders.
fn shaft_comb_candidate(
    ctx: &Ctx<'_>,
    st: &State,
    resid: &[f64],
    refined: &[(f64, f64)],
    fr: f64,
) -> Option<Evaluated> {
    let c = ctx.cfg.get();
    let mut members: Vec<(f64, f64, f64)> = Vec::new(); // (order, f, power)
    for &(f, p) in refined {
        let k = (f / fr).round();
        // within 5 % of an order: at high orders a relative tolerance would take in the
        // fault's own lines (k·BPFI ± m·fr falls within 0.4 % of some shaft order)
        if k >= 1.0
            && (f - k * fr).abs() <= (c.harmonic_tolerance * f).min(COMB_ORDER_TOLERANCE * fr)
            && !line_near_mains(f, fr, c)
            && members.iter().all(|m| m.0 != k)
        {
            members.push((k, f, p));
        }
    }
    if members.len() < MIN_COMB_LINES {
        return None;
    }
    let (num, den) = members.iter().fold((0.0, 0.0), |(a, b), (k, f, p)| {
        let w = p.sqrt();
        (a + w * k * f, b + w * k * k)
    });
    let fr_hat = num / den;
    let mut s2 = st.clone();
    for (k, _, _) in &members {
        s2.lines.push(fit_line(resid, ctx.fs, k * fr_hat));
    }
    let (s2, lsd) = ctx.calibrate(s2, false);
    let mut orders: Vec<f64> = members.iter().map(|m| m.0).collect();
    orders.sort_by(f64::total_cmp);
    Some(Evaluated {
        effect: Effect::ShaftComb {
            shaft_hz: fr_hat,
            declared_shaft_hz: ctx.op.shaft_hz(),
            orders,
            lines: s2.lines[st.lines.len()..].to_vec(),
        },
        state: s2,
        fit_lsd: lsd,
    })
}

/// Is `f` nearer a multiple of the declared mains frequency than a shaft order?
fn line_near_mains(f: f64, fr: f64, c: &crate::LoopConfig) -> bool {
    c.line_frequency_hz.is_some_and(|lf| {
        let m = (f / lf).round();
        let k = (f / fr).round();
        m >= 1.0 && (f - m * lf).abs() < (f - k * fr).abs() && (f / (m * lf) - 1.0).abs() < 1e-3
    })
}

/// An equally spaced comb of lines not at shaft orders (an interference or mains comb): the
/// largest set of standing lines at f₀ + m·Δ (|m| ≤ 8, within 0.3 % of Δ), Δ from 10 Hz up,
/// over every pair of the strongest lines. Needs [`MIN_COMB_LINES`] lines.
fn line_comb_candidate(
    ctx: &Ctx<'_>,
    st: &State,
    resid: &[f64],
    refined: &[(f64, f64)],
    fr: f64,
) -> Option<Evaluated> {
    let c = ctx.cfg.get();
    let free: Vec<(f64, f64)> = refined
        .iter()
        .copied()
        .filter(|&(f, _)| {
            let k = (f / fr).round();
            k < 1.0
                || (f - k * fr).abs() > (c.harmonic_tolerance * f).min(0.25 * fr)
                || line_near_mains(f, fr, c)
        })
        .take(24)
        .collect();
    // a spacing at a kinematic fault rate (within the speed search range) is the fault's own
    // comb at another speed: the speed candidate's business, not an interference comb
    let kinematic: Vec<f64> = crate::impact_orders(ctx.op.fault, &ctx.op.bearing)
        .into_iter()
        .chain([ctx.op.bearing.ftf, 1.0])
        .map(|o| o * fr)
        .collect();
    let is_kinematic = |d: f64| {
        kinematic.iter().any(|&k| {
            let m = (d / k).round();
            m >= 1.0 && (d / (m * k) - 1.0).abs() <= c.max_speed_offset
        })
    };
    let mut best: Vec<(f64, f64)> = Vec::new();
    let mut best_spacing = 0.0;
    for i in 0..free.len() {
        for j in 0..free.len() {
            let (f0, f1) = (free[i].0, free[j].0);
            let d = f1 - f0;
            if d < 10.0 || is_kinematic(d) {
                continue;
            }
            let tol = 3e-3 * d;
            let set: Vec<(f64, f64)> = free
                .iter()
                .copied()
                .filter(|&(f, _)| {
                    let m = ((f - f0) / d).round();
                    m.abs() <= 8.0 && (f - f0 - m * d).abs() <= tol
                })
                .collect();
            let power = |v: &[(f64, f64)]| v.iter().map(|x| x.1).sum::<f64>();
            if set.len() > best.len() || (set.len() == best.len() && power(&set) > power(&best)) {
                best = set;
                best_spacing = d;
            }
        }
    }
    if best.len() < MIN_COMB_LINES {
        return None;
    }
    // spacing refined by least squares over the members' offsets
    best.sort_by(|a, b| a.0.total_cmp(&b.0));
    let f0 = best[0].0;
    let (num, den) = best.iter().fold((0.0, 0.0), |(a, b), &(f, _)| {
        let m = ((f - f0) / best_spacing).round();
        (a + m * (f - f0), b + m * m)
    });
    let spacing = if den > 0.0 { num / den } else { best_spacing };
    let mut s2 = st.clone();
    for &(f, _) in &best {
        s2.lines.push(fit_line(resid, ctx.fs, f));
    }
    let (s2, lsd) = ctx.calibrate(s2, false);
    Some(Evaluated {
        effect: Effect::LineComb {
            spacing_hz: spacing,
            lines: s2.lines[st.lines.len()..].to_vec(),
        },
        state: s2,
        fit_lsd: lsd,
    })
}

/// Complex amplitude C = a − j·b of a line (a·cos + b·sin = Re(C·e^{jωt})).
fn phasor(l: &Line) -> rustfft::num_complex::Complex<f64> {
    rustfft::num_complex::Complex::new(l.a, -l.b)
}

/// A shaft harmonic put into the physics: the model is re-simulated with a shaft force of order
/// k (bearing-model's `ShaftHarmonic`). The force follows from one unit-force run: the transfer
/// H = C₁ / (1 N) of the line the unit force adds at the sensor (fitted on the difference of the
/// two simulations), then F = C_measured / H (amplitude |F|, phase arg F), a run with F, one
/// secant correction F ← F·C_measured / C_response(F) and a run with that (3 simulations).
/// The response line of that run joins the phase-coherent prediction; its power is in the base.
/// `None` when the model has no shaft or a simulation fails (the line then stays a sensor term).
fn shaft_force_candidate(
    ctx: &Ctx<'_>,
    st: &State,
    order: u32,
    measured: Line,
    fr: f64,
) -> Option<Evaluated> {
    let model = ctx.model_of(st);
    let f_sim = f64::from(order) * ctx.op.shaft_hz() * st.base.ratio;
    let response = |m: &dyn DeclaredModel| -> Option<(Arc<Base>, Line)> {
        let b = ctx.make_base_with(m, st.base.ratio).ok()?;
        let d: Vec<f64> = b
            .signal
            .iter()
            .zip(&st.base.signal)
            .map(|(x, x0)| x - x0)
            .collect();
        Some((b.clone(), fit_line(&d, ctx.fs, f_sim)))
    };
    let unit = model.with_shaft_force(order, 1.0, 0.0)?;
    let (_, l1) = response(unit.as_ref())?;
    let h = phasor(&l1);
    if !(h.norm() > 0.0 && h.norm().is_finite()) {
        return None;
    }
    let target = phasor(&measured);
    let mut f = target / h;
    // the contact is Hertzian, so the transfer at 1 N is not the transfer at F: one secant step
    // F ← F·C_measured / C_response(F) corrects it (measured: 229 N → within 2 % of 200 N)
    let mut run = None;
    for step in 0..2 {
        let (amp, phase) = (f.norm(), f.arg());
        if !(amp.is_finite() && amp > 0.0 && amp <= 1e6) {
            return None;
        }
        let forced: Arc<dyn DeclaredModel> = Arc::from(model.with_shaft_force(order, amp, phase)?);
        let (base, resp) = response(forced.as_ref())?;
        let r = phasor(&resp);
        if step == 0 && r.norm() > 0.0 && r.norm().is_finite() {
            f = f * target / r;
            run = Some((forced, base, resp, amp, phase));
            continue;
        }
        run = Some((forced, base, resp, amp, phase));
        break;
    }
    let (forced, base, resp, amp, phase) = run?;
    let mut s2 = st.clone();
    s2.model = Some(ModelRef(forced));
    ctx.rebase(&mut s2, base);
    s2.physics_lines.push(resp);
    let (s2, lsd) = ctx.calibrate(s2, false);
    Some(Evaluated {
        effect: Effect::ShaftHarmonic {
            order: f64::from(order),
            line: measured,
            shaft_hz: fr,
            force: Some((amp, phase)),
        },
        state: s2,
        fit_lsd: lsd,
    })
}

/// Highest half order (k + ½) named a shaft harmonic (looseness shows half orders).
const MAX_HALF_ORDER: f64 = 5.5;

/// Name a line: a shaft harmonic when it sits within `harmonic_tolerance` of an order k·fr
/// (k = 1 … `max_harmonic_order`) or a half order (½ … 5½) and nearer to it than to a multiple of
/// the declared line frequency; a tone otherwise.
fn classify_line(line: Line, fr: f64, c: &crate::LoopConfig) -> Effect {
    let f = line.frequency_hz;
    let k2 = (2.0 * f / fr).round();
    let order = k2 / 2.0;
    let is_half = k2 % 2.0 != 0.0;
    let rel_h = if k2 >= 1.0 {
        (f / (order * fr) - 1.0).abs()
    } else {
        f64::INFINITY
    };
    let rel_l = c.line_frequency_hz.map_or(f64::INFINITY, |lf| {
        let m = (f / lf).round();
        if m >= 1.0 {
            (f / (m * lf) - 1.0).abs()
        } else {
            f64::INFINITY
        }
    });
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

fn resonance_candidates(ctx: &Ctx<'_>, st: &State, _lr: &[f64]) -> Vec<Evaluated> {
    let c = ctx.cfg.get();
    let df = ctx.welch.df();
    // Band-power ratio: 10·log10(Σ S_y / Σ S_m) over ±half bins. Power sums see a comb of fault
    // lines ringing a misplaced mode as well as a broadband bump (a running median would not).
    let half = ((120.0 / df).round() as usize).max(4);
    let sh = ctx.shaped(st);
    let lp = ctx.lines_psd(&st.lines, 0..ctx.n_fit);
    let m = ctx.model_psd(st, &sh, &lp);
    let (k0, k1) = (ctx.bins.start, ctx.bins.end);
    let mut cy = vec![0.0; k1 - k0 + 1];
    let mut cm = vec![0.0; k1 - k0 + 1];
    for k in k0..k1 {
        cy[k - k0 + 1] = cy[k - k0] + ctx.s_fit[k];
        cm[k - k0 + 1] = cm[k - k0] + m[k];
    }
    let nb = k1 - k0;
    let sm: Vec<f64> = (0..nb)
        .map(|i| {
            let lo = i.saturating_sub(half);
            let hi = (i + half + 1).min(nb);
            10.0 * ((cy[hi] - cy[lo]).max(1e-300) / (cm[hi] - cm[lo]).max(1e-300)).log10()
        })
        .collect();
    let mut out = Vec::new();
    let (imax, vmax) =
        sm.iter().enumerate().fold(
            (0, f64::NEG_INFINITY),
            |a, (i, &v)| if v > a.1 { (i, v) } else { a },
        );
    let (imin, vmin) =
        sm.iter().enumerate().fold(
            (0, f64::INFINITY),
            |a, (i, &v)| if v < a.1 { (i, v) } else { a },
        );
    for (i, v) in [(imax, vmax), (imin, vmin)] {
        if v.abs() < c.broadband_threshold_db {
            continue;
        }
        let f0 = ctx.welch.frequency(ctx.bins.start + i);
        // half-width where the smoothed ratio falls to half its extreme (in dB)
        let level = v / 2.0;
        let inside = |j: usize| {
            if v > 0.0 {
                sm[j] > level
            } else {
                sm[j] < level
            }
        };
        let mut lo = i;
        while lo > 0 && inside(lo - 1) {
            lo -= 1;
        }
        let mut hi = i;
        while hi + 1 < sm.len() && inside(hi + 1) {
            hi += 1;
        }
        let bw = ((hi - lo + 1) as f64 * df).max(2.0 * df);
        let zeta0 = (bw / (2.0 * f0)).clamp(0.003, 0.3);
        let (g_lo, g_hi) = if v > 0.0 { (0.0, 200.0) } else { (-0.97, 0.0) };
        let g0 = (10f64.powf(v / 20.0) - 1.0).clamp(g_lo, g_hi);
        let nyq = 0.499 * ctx.fs;
        let mut mode = Mode {
            frequency_hz: f0.min(nyq * 0.99),
            damping_ratio: zeta0,
            gain: g0,
        };
        let eval = |m: &Mode| -> (State, f64) {
            let mut s2 = st.clone();
            s2.modes.push(*m);
            ctx.calibrate(s2, false)
        };
        for _round in 0..3 {
            let (lf, _) = golden_min(
                |lf| {
                    eval(&Mode {
                        frequency_hz: lf.exp(),
                        ..mode
                    })
                    .1
                },
                (mode.frequency_hz * 0.85).ln(),
                (mode.frequency_hz * 1.15).min(nyq).ln(),
                18,
            );
            mode.frequency_hz = lf.exp();
            let (lz, _) = golden_min(
                |lz| {
                    eval(&Mode {
                        damping_ratio: lz.exp(),
                        ..mode
                    })
                    .1
                },
                (mode.damping_ratio / 8.0).max(0.001).ln(),
                (mode.damping_ratio * 8.0).min(0.7).ln(),
                16,
            );
            mode.damping_ratio = lz.exp();
            let (g, _) = if v > 0.0 {
                let (lg, val) = golden_min(
                    |lg| {
                        eval(&Mode {
                            gain: lg.exp(),
                            ..mode
                        })
                        .1
                    },
                    (0.01f64).ln(),
                    g_hi.ln(),
                    20,
                );
                (lg.exp(), val)
            } else {
                golden_min(|g| eval(&Mode { gain: g, ..mode }).1, g_lo, -0.01, 20)
            };
            mode.gain = g;
        }
        if let Some(ev) = housing_candidate(ctx, st, &mode) {
            out.push(ev);
        }
        let (s2, lsd) = eval(&mode);
        out.push(Evaluated {
            effect: Effect::Resonance {
                mode,
                housing: false,
            },
            state: s2,
            fit_lsd: lsd,
        });
    }
    out
}

/// Relative distance within which a fitted channel mode is read as the physics model's own
/// housing mode misplaced (and the housing mode is moved instead).
const HOUSING_MOVE_RANGE: f64 = 0.3;
/// Relative half-width of the housing-frequency search around the fitted channel mode.
const HOUSING_SEARCH: f64 = 0.08;

/// A misplaced housing mode put into the physics: when the fitted channel mode `fitted` (a bump)
/// lies within [`HOUSING_MOVE_RANGE`] of the model's housing mode, the model is re-simulated
/// with its housing mode at f (declared damping), f found by golden section on the
/// fitting-segment LSD over ±[`HOUSING_SEARCH`] around the fitted frequency (1 simulation, and 8
/// more only if the move at the fitted frequency already lowers the fitting error; the channel
/// mode's frequency is biased by the dip the misplaced mode leaves).
fn housing_candidate(ctx: &Ctx<'_>, st: &State, fitted: &Mode) -> Option<Evaluated> {
    // behind a path identified from data the model's own housing mode is divided out
    // ([`Ctx::physics_shape`]): moving it changes nothing that is seen
    if st.phys_shape.is_some() {
        return None;
    }
    let model = ctx.model_of(st);
    let (fh, zh) = model.housing_mode()?;
    if fitted.gain <= 0.0 || (fitted.frequency_hz / fh - 1.0).abs() > HOUSING_MOVE_RANGE {
        return None;
    }
    let nyq = 0.49 * ctx.fs;
    let eval = |f: f64| -> Option<(State, f64, Arc<dyn DeclaredModel>)> {
        let m: Arc<dyn DeclaredModel> = Arc::from(model.with_housing_mode(f, zh)?);
        let base = ctx.make_base_with(m.as_ref(), st.base.ratio).ok()?;
        let mut s2 = st.clone();
        s2.model = Some(ModelRef(m.clone()));
        ctx.rebase(&mut s2, base);
        let (s2, lsd) = ctx.calibrate(s2, false);
        Some((s2, lsd, m))
    };
    let f0 = fitted.frequency_hz.min(nyq);
    // one simulation first: refine only a move that already lowers the fitting error
    let (_, lsd0, _) = eval(f0)?;
    let current = ctx.calibrate(st.clone(), false).1;
    if lsd0.is_nan() || lsd0 >= current {
        return None;
    }
    let (lf, _) = golden_min(
        |lf| eval(lf.exp()).map_or(f64::INFINITY, |e| e.1),
        (f0 * (1.0 - HOUSING_SEARCH)).ln(),
        (f0 * (1.0 + HOUSING_SEARCH)).min(nyq).ln(),
        10,
    );
    let f = lf.exp();
    let (s2, lsd, _) = eval(f)?;
    Some(Evaluated {
        effect: Effect::Resonance {
            mode: Mode {
                frequency_hz: f,
                damping_ratio: zh,
                gain: 0.0,
            },
            housing: true,
        },
        state: s2,
        fit_lsd: lsd,
    })
}

/// Line-emphasised log spectrum: ln S minus its running median, clipped at 0.
fn line_excess(s: &[f64], bins: std::ops::Range<usize>) -> Vec<f64> {
    let l: Vec<f64> = bins.map(|k| s[k].max(1e-300).ln()).collect();
    let m = running_median(&l, 24);
    l.iter().zip(&m).map(|(a, b)| (a - b).max(0.0)).collect()
}

/// Kinematic speed estimate from the envelope spectrum: the ratio s that maximises the summed
/// line excess at k·f_fault·s (k = 1..4) of the fitting residual's envelope spectrum.
fn envelope_speed_step(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
    let c = ctx.cfg.get();
    let order = *crate::impact_orders(ctx.op.fault, &ctx.op.bearing).first()?;
    let f_fault = order * ctx.op.shaft_hz() * st.base.ratio;
    let resid = ctx.fit_residual(st);
    let (ey, de) = envelope_periodogram(&resid, ctx.fs);
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
    let (s, _) = crate::optimize::golden_max(score, best.0 - step, best.0 + step, 20);
    Some(s)
}

fn speed_candidates(ctx: &Ctx<'_>, st: &State) -> Result<Vec<Evaluated>, CloseLoopError> {
    let c = ctx.cfg.get();
    let mut steps: Vec<f64> = Vec::new();
    if let Some(s) = spectral_speed_step(ctx, st) {
        steps.push(s);
    }
    if let Some(s) = envelope_speed_step(ctx, st)
        && steps.iter().all(|p| (p - s).abs() > 1e-4)
    {
        steps.push(s);
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
        let base: Arc<Base> = ctx.make_base_with(ctx.model_of(st), ratio)?;
        let mut s2 = st.clone();
        ctx.rebase(&mut s2, base);
        for l in &mut s2.physics_lines {
            l.frequency_hz *= s;
        }
        let (s2, lsd) = ctx.calibrate(s2, true);
        out.push(Evaluated {
            effect: Effect::SpeedOffset { ratio, step: s },
            state: s2,
            fit_lsd: lsd,
        });
    }
    Ok(out)
}

/// Slip fractions tried, relative to the model's current one.
const SLIP_FACTORS: [f64; 4] = [0.0, 0.25, 0.5, 2.0];

/// Random ball slip (the spread of the impact times, which smears the fault lines): the declared
/// physics re-simulated at slip fractions [`SLIP_FACTORS`] × the current one, the best on the
/// fitting segment kept. Only with a declared fault and a model that has slip.
fn slip_candidate(ctx: &Ctx<'_>, st: &State) -> Option<Evaluated> {
    if crate::impact_orders(ctx.op.fault, &ctx.op.bearing).is_empty() {
        return None;
    }
    let model = ctx.model_of(st);
    let current = model.slip_fraction()?;
    let mut best: Option<(Evaluated, f64)> = None;
    for k in SLIP_FACTORS {
        let frac = current * k;
        let m: Arc<dyn DeclaredModel> = Arc::from(model.with_slip_fraction(frac)?);
        let Ok(base) = ctx.make_base_with(m.as_ref(), st.base.ratio) else {
            continue;
        };
        let mut s2 = st.clone();
        s2.model = Some(ModelRef(m));
        ctx.rebase(&mut s2, base);
        let (s2, lsd) = ctx.calibrate(s2, false);
        if best.as_ref().is_none_or(|b| lsd < b.0.fit_lsd) {
            best = Some((
                Evaluated {
                    effect: Effect::Slip {
                        fraction: frac,
                        declared: current,
                    },
                    state: s2,
                    fit_lsd: lsd,
                },
                frac,
            ));
        }
    }
    best.map(|b| b.0)
}

/// Speed step from the line pattern: the stretch s of the model's line-emphasised log spectrum
/// that best correlates with the measurement's.
fn spectral_speed_step(ctx: &Ctx<'_>, st: &State) -> Option<f64> {
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

fn modulation_candidates(ctx: &Ctx<'_>, st: &State) -> Vec<Evaluated> {
    let c = ctx.cfg.get();
    let fr = ctx.op.shaft_hz() * st.base.ratio;
    let resid = ctx.fit_residual(st);
    let (ey, de) = envelope_periodogram(&resid, ctx.fs);
    let mut msig = st.base.signal.clone();
    for m in &st.mods {
        msig = m.apply(&msig, 0, ctx.fs);
    }
    let (em, _) = envelope_periodogram(&msig, ctx.fs);
    let lo = ((0.5 * ctx.op.bearing.ftf * fr / de).floor() as usize).max(2);
    let hi = ((2.5 * fr / de).ceil() as usize).min(ey.len() - 2);
    if hi <= lo + 4 {
        return Vec::new();
    }
    let half = ((0.25 * ctx.op.bearing.ftf * fr / de).round() as usize).max(8);
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
    let env = envelope(&resid);
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
        let (mu, _) = golden_min(|mu| eval(mu).1, 0.02, 1.0, 22);
        let (s2, lsd) = eval(mu);
        let order = fm / fr;
        let ftf = ctx.op.bearing.ftf;
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
