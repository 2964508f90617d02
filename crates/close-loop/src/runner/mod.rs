//! The loop: residual → candidate effects (detectors) → fit on the fitting segment → keep the best
//! one that lowers the held-out error by the margin → repeat; stop when none does.

use crate::effect::Effect;
use crate::engine::{Ctx, HeldOutScores, State};
use crate::machine::MachineModel;
use crate::report::{
    AcceptedOn, Declared, EffectEntry, HeldOutSplit, Ledger, PRIMARY_METRIC, RejectedCandidate,
    SECONDARY_METRIC, Spectra,
};
use crate::spectrum::Welch;
use crate::{CheckedConfig, CloseLoopError, DeclaredModel, OperatingPoint, Signal};
use bearing_model::FaultLocation;
use rayon::prelude::*;

/// Ledger plus the spectra behind it.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The report.
    pub ledger: Ledger,
    /// Held-out spectra.
    pub spectra: Spectra,
    /// The augmented model as a reloadable machine model (declared model + everything added).
    pub machine: MachineModel,
}

/// Smallest Welch segment the loop accepts.
pub const MIN_NPERSEG: usize = 256;

/// Samples a recording needs for `cfg`: both parts must hold `min_segments` Welch segments of
/// [`MIN_NPERSEG`] samples, and the fitting part the [`crate::path::MIN_PATH_SAMPLES`] a
/// structural path is identified from.
pub fn min_samples(cfg: &CheckedConfig) -> usize {
    let c = cfg.get();
    let part = MIN_NPERSEG * (c.min_segments + 1) / 2;
    let frac = c.fit_fraction.min(1.0 - c.fit_fraction);
    let welch = (part as f64 / frac).ceil() as usize + 1;
    let path = (crate::path::MIN_PATH_SAMPLES as f64 / c.fit_fraction).ceil() as usize + 1;
    welch.max(path)
}

/// Length of the fitting segment `[0, n_fit)` of an `n`-sample recording (the rest is held out).
/// A model identified from the recording (e.g. [`crate::observe::ArxLaguerreDeclared`]) must be
/// identified on `y[..fit_len(y.len(), cfg)]` only.
pub fn fit_len(n: usize, cfg: &CheckedConfig) -> usize {
    (n as f64 * cfg.get().fit_fraction).round() as usize
}

/// Run the loop on a recording (its samples and rate, a checked [`Signal`]), with the model told
/// `op`.
///
/// # Errors
/// Bad input ([`CloseLoopError::TooShort`], [`CloseLoopError::InvalidRpm`],
/// [`CloseLoopError::ZeroSignal`]) or a failing model. (A rate that is not finite and > 0, no
/// samples or a non-finite sample cannot make a [`Signal`]; `CloseLoopError::from` its
/// [`crate::SignalError`] gives [`CloseLoopError::InvalidSamplingRate`],
/// [`CloseLoopError::EmptyRecording`], [`CloseLoopError::NonFinite`].)
pub fn close_loop(
    model: &dyn DeclaredModel,
    signal: &Signal<'_>,
    op: &OperatingPoint,
    cfg: &CheckedConfig,
) -> Result<Outcome, CloseLoopError> {
    close_loop_from(model, None, signal, op, cfg)
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
    signal: &Signal<'_>,
    op: &OperatingPoint,
    cfg: &CheckedConfig,
) -> Result<Outcome, CloseLoopError> {
    // the rate is finite and > 0, the samples non-empty and finite (`Signal`)
    let (y, fs) = (signal.samples(), signal.fs_hz());
    let c = cfg.get();
    if let Some(m) = prior {
        m.check_compatible(fs, &op.bearing.name)?;
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
    // the shaft speed the segment's own comb shows, refined from its lines (a complete comb; only
    // a declared fault's rate can differ from it: speed_candidates)
    let shaft = if crate::impact_orders(op.fault, &op.bearing).is_empty() {
        None
    } else {
        residual_features::speed::estimate_speed(
            &mut residual_features::SpectralEngine::new(),
            &y[..n_fit],
            fs,
            op.rpm,
        )
        .ok()
        .flatten()
        .and_then(|m| m.refined_rpm)
        .map(|r| r / op.rpm)
    };
    // the faults the envelope shows on the fitting segment and again on the held-out one (only a
    // model with spalls can add one): a location one half alone shows is not offered
    let detected = if model.fault_size_in().is_some() {
        let fit = detected_faults(&y[..n_fit], fs, op);
        let held = if fit.is_empty() {
            Vec::new()
        } else {
            detected_faults(&y[n_fit..], fs, op)
        };
        fit.into_iter()
            .filter(|(l, _)| held.iter().any(|(h, _)| h == l))
            .collect()
    } else {
        Vec::new()
    };
    let ctx = Ctx {
        y,
        shaft,
        detected,
        fs,
        n_fit,
        eps,
        rejected_ratios: std::sync::Mutex::new(Vec::new()),
        bases: std::sync::Mutex::new(std::collections::HashMap::new()),
        residuals: crate::engine::ResidualMemo::default(),
        s_fit,
        s_held: welch.try_psd(&y[n_fit..])?,
        s_fit_hi: welch_hi.try_psd(&y[..n_fit])?,
        welch,
        welch_hi,
        bins: k_lo..k_hi + 1,
        bins_hi: kh_lo..kh_hi + 1,
        op: op.clone(),
        model,
        cfg,
    };
    run(&ctx, prior)
}

/// The fault locations the training-free diagnosis detects on `x` (self-referenced: AR
/// pre-whitening of `x` itself, kurtogram band, envelope lines at ≥ 2 harmonics or a harmonic
/// and a distinguishing sideband; `crates/diagnosis`), with their scores in dB; empty when it
/// cannot run (a segment too short for its bands).
fn detected_faults(x: &[f64], fs: f64, op: &OperatingPoint) -> Vec<(FaultLocation, f64)> {
    let Ok(d) = diagnosis::Signal::new(x, fs)
        .map_err(diagnosis::DiagnosisError::from)
        .and_then(|signal| diagnosis::diagnose(&signal, op.rpm, &op.bearing, None))
    else {
        return Vec::new();
    };
    // a location significant by itself is a candidate even when the diagnosis' verdict
    // explains it by a stronger fault's family (an inner race beside a declared outer one
    // puts BPFI near BPFO + 2 fr): the loop's spectral error judges it, not the verdict
    d.evidence
        .iter()
        .filter(|e| {
            d.detected.contains(&e.hypothesis)
                || e.significance.as_ref().is_some_and(|s| {
                    s.p_healthy <= d.false_alarm / 3.0
                        && s.modulation_depth >= diagnosis::detect::MIN_MODULATION_DEPTH
                })
        })
        .map(|e| (e.hypothesis, d.scores.of(e.hypothesis)))
        .collect()
}

/// A candidate accepted in a round: the candidate, its held-out scores, why it was accepted and
/// the held-out statistic that confirmed it (envelope step or modulation index), if any.
type Judged = (
    Evaluated,
    HeldOutScores,
    AcceptedOn,
    Option<(&'static str, f64)>,
);

/// A candidate evaluated on the fitting segment.
struct Evaluated {
    effect: Effect,
    state: State,
    fit_lsd: f64,
}

/// The loop's running state: the model as accepted so far, its fitting-segment and held-out
/// scores and observer residual, the ledger's effects, and the candidates the last round rejected.
struct Running {
    st: State,
    fit_lsd: f64,
    held: HeldOutScores,
    obs: Option<f64>,
    effects: Vec<EffectEntry>,
    rejected: Vec<RejectedCandidate>,
}

impl Running {
    /// An accepted effect goes into the ledger and its state becomes the loop's ([`take`]).
    fn take(
        &mut self,
        ctx: &Ctx<'_>,
        cand: Evaluated,
        h: HeldOutScores,
        on: AcceptedOn,
        extra: Option<(&'static str, f64)>,
    ) {
        take(
            ctx,
            Taken {
                effects: &mut self.effects,
                st: &mut self.st,
                obs: &mut self.obs,
                fit_lsd: &mut self.fit_lsd,
                held: &mut self.held,
            },
            cand,
            h,
            on,
            extra,
        );
    }

    /// `cand` was judged and not kept: the ledger lists it.
    fn reject(&mut self, cand: &Evaluated, h: &HeldOutScores) {
        self.rejected.push(RejectedCandidate {
            kind: cand.effect.kind(),
            frequency_hz: cand.effect.frequency_hz(),
            fit_error: cand.fit_lsd,
            held_out_error: Some(h.lsd),
        });
    }
}

/// The loop's steps: the start (the declared model, or a machine model's state), the spectral
/// phase (one effect a round, judged on the held-out spectral error), the envelope phase
/// (modulations judged on the held-out envelope), and the outcome.
fn run(ctx: &Ctx<'_>, prior: Option<&MachineModel>) -> Result<Outcome, CloseLoopError> {
    let st0 = match prior {
        None => declared_state(ctx)?,
        Some(m) => prior_state(ctx, m)?,
    };
    let (st, fit_lsd) = start_from(ctx, prior, st0);
    let first = st.clone();
    let held = ctx.held_scores(&st);
    let noise = crate::metric::estimation_lsd(
        segments(ctx.y.len() - ctx.n_fit, ctx.welch.nperseg()),
        Some(segments(ctx.n_fit, ctx.welch.nperseg())),
    );
    let obs = observer_rms(ctx, &st);
    let (before, obs_before) = (held, obs);
    let mut run = Running {
        st,
        fit_lsd,
        held,
        obs,
        effects: Vec::new(),
        rejected: Vec::new(),
    };
    let (stop_reason, modulations) = spectral_phase(ctx, &mut run, noise)?;
    envelope_phase(ctx, &mut run, modulations);
    let start = Start {
        first: &first,
        before,
        obs_before,
        noise,
    };
    Ok(outcome(ctx, &start, run, stop_reason))
}

/// The declared model as the loop starts from it: nothing added, the physics at the declared
/// speed.
fn declared_state(ctx: &Ctx<'_>) -> Result<State, CloseLoopError> {
    Ok(State {
        model: None,
        physics_lines: Vec::new(),
        shaft_lines: Vec::new(),
        base: ctx.make_base(1.0)?,
        defect_rate: 1.0,
        modes: Vec::new(),
        mods: Vec::new(),
        lines: Vec::new(),
        path: None,
        phys_shape: None,
        phys_path: None,
        phys_path_fitted: false,
        phys_highpass: None,
        log_gain: 0.0,
        log_floor: 0.0,
        log_bg: 0.0,
        assumed_shaft_step: 1.0,
    })
}

/// The spectral phase: each round, the candidates that lower the fitting error, judged in order
/// on the held-out segment; the first kept one (of a shaft line's two placements, the lower
/// held-out error) is taken. Returns why it stopped and how many modulations it took.
///
/// Modulations have their own budget, [`MAX_MODULATIONS`], in whichever phase they are found:
/// a modulation the spectral loop takes does not spend one of its `max_effects` rounds (it would
/// crowd out a channel mode the envelope phase cannot give back: 258, 259, 262 ended 0.2-0.4 dB
/// higher when it did), and leaves one modulation fewer for the envelope phase.
fn spectral_phase(
    ctx: &Ctx<'_>,
    run: &mut Running,
    noise: f64,
) -> Result<(String, usize), CloseLoopError> {
    let c = ctx.cfg.get();
    let (mut rounds, mut modulations) = (0usize, 0usize);
    while rounds < c.max_effects {
        // within the estimator's own scatter, only lines (a detection that stands on its own:
        // a narrow peak above the local floor that the model does not carry) are still tried;
        // broadband candidates would be fitting estimation noise
        let lines_only = run.held.lsd <= c.noise_stop_factor * noise;
        let cands = round_candidates(ctx, run, lines_only, modulations < MAX_MODULATIONS)?;
        run.rejected.clear();
        let Some((cand, h, accepted_on, envelope_step)) = judge(ctx, run, cands) else {
            return Ok((stop_reason(ctx, run, lines_only, noise), modulations));
        };
        if matches!(cand.effect, Effect::Modulation { .. }) {
            modulations += 1;
        } else {
            rounds += 1;
        }
        run.take(ctx, cand, h, accepted_on, envelope_step);
    }
    Ok((
        format!("reached the maximum of {} effects", c.max_effects),
        modulations,
    ))
}

/// A round's candidates, in the order they are judged: those that lower the fitting error (a
/// speed step also within the margin), only lines within the estimator's scatter, by fitting
/// error, then strong lines, the effects before slip, and the declared fault's first.
fn round_candidates(
    ctx: &Ctx<'_>,
    run: &Running,
    lines_only: bool,
    modulations_left: bool,
) -> Result<Vec<Evaluated>, CloseLoopError> {
    let c = ctx.cfg.get();
    let (st, fit_lsd) = (&run.st, run.fit_lsd);
    let mut cands = candidates(ctx, st, fit_lsd, modulations_left)?;
    // the physics' shaft forces turn with its simulated shaft, which runs at the impact rate
    // (`base.ratio`); a candidate that moves the impacts off the shaft (a defect rate, a
    // preload's rate step) would move the forces' lines off the measured ones, leaving the
    // model's record of them (`physics_lines`) wrong: once the physics holds a shaft force,
    // the defect rate stays (160 + a 2× line: the line into the physics, then a preload of
    // ×1.003 moved the simulated line by 0.17 Hz, and a second "2×" came back beside it)
    cands.retain(|e| {
        st.physics_lines.is_empty() || (e.state.defect_rate / st.defect_rate - 1.0).abs() < 1e-9
    });
    // a speed step is also judged when it leaves the fitting error within the margin: its
    // evidence may be in the envelope, which the spectral error barely sees (inner race)
    cands.retain(|e| {
        e.fit_lsd.is_finite()
            && (e.fit_lsd < fit_lsd
                || (e.effect.impact_rate_step().is_some()
                    && e.fit_lsd <= fit_lsd * (1.0 + c.margin)))
    });
    if lines_only {
        cands.retain(|e| e.effect.is_line());
    }
    cands.sort_by(|a, b| a.fit_lsd.total_cmp(&b.fit_lsd));
    Ok(declared_first(before_slip(strong_lines_first(
        ctx, st, cands,
    ))))
}

/// Judge a round's candidates on the held-out segment, in order; the first candidate kept (of a
/// shaft line's two placements, the one with the lower held-out error) ends the round. Every
/// candidate judged and not kept is recorded in `run.rejected`.
fn judge(ctx: &Ctx<'_>, run: &mut Running, cands: Vec<Evaluated>) -> Option<Judged> {
    let mut accepted: Option<Judged> = None;
    for cand in cands {
        // a shaft harmonic is scored as a sensor line in the search; the one about to be
        // judged goes into the physics first (3 simulations) and is judged as such; when the
        // model has no shaft, the simulations fail, or the physics placement does not lower
        // the held-out error (the force also changes the contact, hence the fault's
        // impacts), the sensor line is judged next, and when both pass, the lower held-out
        // error wins: the held-out data decides the placement
        let mut versions = Vec::with_capacity(2);
        if let Effect::ShaftHarmonic {
            order,
            line,
            shaft_hz,
            force: None,
        } = cand.effect
            && order.fract() == 0.0
            && let Some(ev) = shaft_force_candidate(ctx, &run.st, order as u32, line, shaft_hz)
        {
            versions.push(ev);
        }
        versions.push(cand);
        for cand in versions {
            let h = ctx.held_scores(&cand.state);
            match acceptance(ctx, run, &cand, &h) {
                Some((on, envelope)) => {
                    // both placements of a shaft line are judged: the one with the lower
                    // held-out error is kept (a 2× force on a simulated 6203 with an inner-race
                    // fault passed the test — 1.92 → 1.01 dB — but also modulated the impacts,
                    // which a broad patch then covered; the sensor line alone ends at 0.54)
                    let better = match &accepted {
                        Some((_, prev, ..)) => h.lsd < prev.lsd,
                        None => true,
                    };
                    if better {
                        accepted = Some((cand, h, on, envelope));
                    }
                }
                None => {
                    if let Some(ratio) = cand.effect.physics_ratio() {
                        ctx.rejected_ratios
                            .lock()
                            .unwrap_or_else(std::sync::PoisonError::into_inner)
                            .push(ratio);
                    }
                    run.reject(&cand, &h);
                }
            }
        }
        if accepted.is_some() {
            break;
        }
    }
    accepted
}

/// Why `cand` (held-out scores `h`) is kept, and the held-out envelope statistic that confirmed
/// it, if any; `None` when it is not kept.
fn acceptance(
    ctx: &Ctx<'_>,
    run: &Running,
    cand: &Evaluated,
    h: &HeldOutScores,
) -> Option<(AcceptedOn, Option<(&'static str, f64)>)> {
    let c = ctx.cfg.get();
    let (st, held) = (&run.st, &run.held);
    // a speed step beyond ± FAR_SPEED_STEP must explain much more (FAR_SPEED_MARGIN)
    let margin = match cand.effect.impact_rate_step() {
        Some(step) if (step - 1.0).abs() > FAR_SPEED_STEP => c.margin.max(FAR_SPEED_MARGIN),
        _ => c.margin,
    };
    // a speed step must not be contradicted by the fault's own lines in the held-out
    // envelope (`speed::envelope_contradicts_speed`)
    let spectral = h.lsd <= held.lsd * (1.0 - margin)
        && held.lsd - h.lsd >= c.min_improvement_db
        && cand
            .effect
            .impact_rate_step()
            .is_none_or(|step| !speed::envelope_contradicts_speed(ctx, st, step));
    // a strong coherent line covers a few bins of the spectral distance: it is also
    // kept when it removes ≥ min_line_power of the held-out signal's power from the
    // time-domain residual and does not raise the spectral error
    let coherent = cand.effect.is_coherent_line()
        && !is_declared_fault_line(ctx, st, &cand.effect)
        && h.lsd <= held.lsd
        && held.rms * held.rms - h.rms * h.rms >= c.min_line_power;
    // a speed step that the held-out envelope confirms on its own (the fault lines
    // of the held-out residual sit at the new speed) and that does not raise the
    // spectral error by more than an accepted effect must lower it (the margin, at
    // least the smallest improvement counted): a change the acceptance rule would
    // call noise in the other direction (171.mat played 1 % faster with a tone
    // added: +0.048 dB on 3.36 dB, the speed otherwise never named)
    let unchanged = h.lsd <= held.lsd + c.min_improvement_db.max(c.margin * held.lsd);
    let envelope = match cand.effect.impact_rate_step() {
        Some(step) if !spectral && unchanged => {
            speed::envelope_confirms_speed(ctx, st, step).map(|s| ("held_out_envelope_step", s))
        }
        _ => None,
    };
    if spectral {
        Some((AcceptedOn::SpectralError, envelope))
    } else if coherent {
        Some((AcceptedOn::CoherentLine, envelope))
    } else if envelope.is_some() {
        Some((AcceptedOn::HeldOutEnvelope, envelope))
    } else {
        None
    }
}

/// Why the spectral phase stopped with no candidate kept.
fn stop_reason(ctx: &Ctx<'_>, run: &Running, lines_only: bool, noise: f64) -> String {
    let c = ctx.cfg.get();
    if lines_only && run.rejected.is_empty() {
        format!(
            "the held-out error {:.3} dB is within {:.2} x the {:.3} dB a correct model \
             shows from estimation variance alone, and no line stands out",
            run.held.lsd, c.noise_stop_factor, noise
        )
    } else if run.rejected.is_empty() {
        "no candidate effect lowered the fitting-segment error".to_string()
    } else {
        format!(
            "no candidate lowered the held-out error by at least {:.1} % and {:.2} dB",
            100.0 * c.margin,
            c.min_improvement_db
        )
    }
}

/// The envelope phase: amplitude modulations, judged on the held-out envelope alone, while the
/// budget [`MAX_MODULATIONS`] lasts (`modulations` already taken by the spectral phase).
fn envelope_phase(ctx: &Ctx<'_>, run: &mut Running, modulations: usize) {
    let c = ctx.cfg.get();
    for _ in modulations..MAX_MODULATIONS {
        let mut accepted = None;
        for cand in modulation_candidates(ctx, &run.st) {
            let h = ctx.held_scores(&cand.state);
            let Effect::Modulation { modulation, .. } = &cand.effect else {
                continue;
            };
            let confirmed = if h.lsd <= run.held.lsd + c.min_improvement_db {
                modulation::held_out_confirms(ctx, &run.st, modulation)
            } else {
                None
            };
            match confirmed {
                Some(m) => {
                    accepted = Some((cand, h, m));
                    break;
                }
                None => run.reject(&cand, &h),
            }
        }
        let Some((cand, h, m_ho)) = accepted else {
            break;
        };
        run.take(
            ctx,
            cand,
            h,
            AcceptedOn::HeldOutEnvelope,
            Some(("held_out_modulation_index", m_ho)),
        );
    }
}

/// Where the loop started: its first state, the held-out scores and observer residual there,
/// and the estimator's own scatter.
struct Start<'a> {
    first: &'a State,
    before: HeldOutScores,
    obs_before: Option<f64>,
    noise: f64,
}

/// The loop's outcome: the ledger, the spectra before and after, the machine model.
fn outcome(ctx: &Ctx<'_>, start: &Start<'_>, run: Running, stop_reason: String) -> Outcome {
    let c = ctx.cfg.get();
    let Running {
        st,
        held,
        obs,
        effects,
        rejected,
        ..
    } = run;
    let spectra = spectra(ctx, start.first, &st);
    let machine = MachineModel::from_state(ctx, &st, &effects, start.before.lsd, held.lsd);
    let ledger = Ledger {
        error_metric: PRIMARY_METRIC.to_string(),
        error_before: start.before.lsd,
        error_after: held.lsd,
        secondary_metric: SECONDARY_METRIC.to_string(),
        secondary_before: start.before.rms,
        secondary_after: held.rms,
        observer: residual_observer(ctx, &st).describe(),
        residual_rms_before: start.obs_before,
        residual_rms_after: obs,
        held_out_signal_rms: crate::metric::rms(&ctx.y[ctx.n_fit..]),
        unit: bearing_data::SampleUnit::unknown(),
        effects,
        rejected,
        stop_reason,
        declared: Declared {
            model: ctx.model.name().to_string(),
            rpm: ctx.op.rpm,
            bearing: ctx.op.bearing.name.to_string(),
            bearing_spec: ctx.op.bearing.echo(),
            fault: ctx.op.fault.name().to_string(),
            fs: ctx.fs,
        },
        protocol: HeldOutSplit {
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
            estimation_lsd_db: start.noise,
        },
        structural_modes: st
            .path
            .as_ref()
            .map(|p| p.modes.clone())
            .unwrap_or_default(),
        verification: Vec::new(),
    };
    Outcome {
        ledger,
        spectra,
        machine,
    }
}

/// Most amplitude modulations a run adds — in the spectral loop (confirmed ones at a shaft or
/// cage rate, outside its `max_effects` rounds) and in the envelope phase after it, strongest
/// first (`docs/equations/close-loop.md`, "Modulation"): a fault record's envelope holds many
/// real lines (cage and shaft sidebands of the fault itself), and the largest excesses over the
/// model are the ones worth a name.
pub const MAX_MODULATIONS: usize = 2;

/// A speed step farther than this from the current speed (a fraction) is a far step.
pub const FAR_SPEED_STEP: f64 = 0.02;
/// Relative held-out improvement a far speed step must bring (the usual margin is 2 %). A speed
/// several percent off the declared one is an extraordinary claim: a true one moves every line
/// of the model and lowers the held-out error by about 20 % (130.mat played 1.5–4.5 % faster or
/// slower, from the rig's machine model), while on short or weakly periodic records a far step
/// can buy 2–3 % by moving some line onto a peak (174.mat, 1.33 s: ×0.952 for 2.2 %).
pub const FAR_SPEED_MARGIN: f64 = 0.10;

/// A grid search's best point `best` = (x, state, fitting LSD) at `grid[k]`, refined by
/// `iters` golden-section steps of `eval` between its grid neighbours; the best point tried is
/// kept (a failed evaluation, `None`, counts as infinitely bad).
fn refine_between(
    grid: &[f64],
    k: usize,
    best: (f64, State, f64),
    eval: impl Fn(f64) -> Option<(State, f64)>,
    iters: usize,
) -> (f64, State, f64) {
    let (mut x_best, mut s_best, mut lsd_best) = best;
    let lo = grid[k.saturating_sub(1)];
    let hi = grid[(k + 1).min(grid.len() - 1)];
    if hi > lo {
        let mut tried: Vec<(f64, State, f64)> = Vec::new();
        crate::optimize::golden_min(
            |x| match eval(x) {
                Some((s2, lsd)) => {
                    tried.push((x, s2, lsd));
                    lsd
                }
                None => f64::INFINITY,
            },
            lo,
            hi,
            iters,
        );
        for (x, s2, lsd) in tried {
            if lsd < lsd_best {
                (x_best, s_best, lsd_best) = (x, s2, lsd);
            }
        }
    }
    (x_best, s_best, lsd_best)
}

/// A grid search's best point `best` = (x, state, fitting LSD) at `grid[k]`, refined between
/// its grid neighbours for an objective that costs a simulation per point: at most `iters` new
/// evaluations — first the midpoints between the best point and its neighbours, then each at
/// the vertex of the parabola through the best point so far and the two points nearest it (at
/// an end of the grid the next points inward), on a lattice of step `lattice` so that later rounds re-trying the same model meet
/// the simulation memo. A vertex that is not a convex parabola's, falls outside the bracket
/// around the best point or within one lattice step of a point tried gives way to a
/// golden-section step into the bracket's larger side (Brent's safeguard: an objective with
/// fine-scale scatter, or a minimum just inside an end of the grid, does not stall the
/// parabola). The refinement stops when the next point was tried already; the best point tried
/// is kept (a failed evaluation, `None`, counts as infinitely bad). Used where
/// [`refine_between`]'s golden section (8 steps, each a simulation) was most of a run's time.
fn refine_parabolic<S>(
    grid: &[f64],
    k: usize,
    best: (f64, S, f64),
    eval: impl Fn(f64) -> Option<(S, f64)>,
    iters: usize,
    lattice: f64,
) -> (f64, S, f64) {
    /// 1 − 1/φ: the golden-section step into an interval.
    const GOLD: f64 = 1.0 - crate::optimize::INV_PHI;
    let n = grid.len();
    if n < 3 || k >= n {
        return best;
    }
    let (mut x_best, mut s_best, mut lsd_best) = best;
    // the refinement never leaves the best grid point's neighbours
    let (lo, hi) = (grid[k.saturating_sub(1)], grid[(k + 1).min(n - 1)]);
    let mut tried: Vec<(f64, f64)> = vec![(x_best, lsd_best)];
    let at = |x: f64, tried: &mut Vec<(f64, f64)>| -> (Option<S>, f64) {
        match tried.iter().find(|t| (t.0 - x).abs() < 1e-12) {
            Some(&(_, l)) => (None, l),
            None => {
                let (s, l) = eval(x).map_or((None, f64::INFINITY), |(s, l)| (Some(s), l));
                tried.push((x, l));
                (s, l)
            }
        }
    };
    let (ia, ic) = match k {
        0 => (1, 2),
        _ if k == n - 1 => (n - 3, n - 2),
        _ => (k - 1, k + 1),
    };
    let mut pts: Vec<(f64, f64)> = vec![
        (grid[ia], at(grid[ia], &mut tried).1),
        (grid[ic], at(grid[ic], &mut tried).1),
    ];
    pts.push((x_best, lsd_best));
    let snap = |x: f64| (x / lattice).round() * lattice;
    // first the midpoints between the best grid point and its neighbours: a parabola through
    // points half a grid step apart is not led astray by the objective's fine-scale scatter
    let mut left_budget = iters;
    let b0 = x_best;
    for side in [lo, hi] {
        let x = snap(0.5 * (b0 + side));
        if left_budget == 0 || (x - b0).abs() < lattice || (x - side).abs() < lattice {
            continue;
        }
        let (s, l) = at(x, &mut tried);
        left_budget -= 1;
        if let Some(s) = s
            && l < lsd_best
        {
            (x_best, s_best, lsd_best) = (x, s, l);
        }
        pts.push((x, l));
    }
    keep_best_three(&mut pts);
    for _ in 0..left_budget {
        pts.sort_by(|p, q| p.0.total_cmp(&q.0));
        let ib = (0..pts.len())
            .min_by(|&i, &j| pts[i].1.total_cmp(&pts[j].1))
            .unwrap_or(0);
        let b = pts[ib].0;
        let left = if ib > 0 { pts[ib - 1].0.max(lo) } else { lo };
        let right = if ib + 1 < pts.len() {
            pts[ib + 1].0.min(hi)
        } else {
            hi
        };
        let ((xa, fa), (xb, fb), (xc, fc)) = (pts[0], pts[1], pts[2]);
        let den = (xb - xa) * (fb - fc) - (xb - xc) * (fb - fa);
        let num = (xb - xa).powi(2) * (fb - fc) - (xb - xc).powi(2) * (fb - fa);
        let new = |x: f64| {
            x >= left + lattice - 1e-12
                && x <= right - lattice + 1e-12
                && (x - b).abs() >= lattice - 1e-12
                && !tried.iter().any(|t| (t.0 - x).abs() < 1e-12)
        };
        let vertex = (den < 0.0 && fa.is_finite() && fb.is_finite() && fc.is_finite())
            .then(|| snap(xb - 0.5 * num / den))
            .filter(|&x| new(x));
        let golden = snap(if right - b >= b - left {
            b + GOLD * (right - b)
        } else {
            b - GOLD * (b - left)
        });
        let Some(x) = vertex.or_else(|| new(golden).then_some(golden)) else {
            break;
        };
        let (s, l) = at(x, &mut tried);
        if let Some(s) = s
            && l < lsd_best
        {
            (x_best, s_best, lsd_best) = (x, s, l);
        }
        pts.push((x, l));
        keep_best_three(&mut pts);
    }
    (x_best, s_best, lsd_best)
}

/// `pts` (x, value) sorted by x and cut to the best point and the two nearest it (the three at
/// an end when the best is there); unchanged when it holds three or fewer.
fn keep_best_three(pts: &mut Vec<(f64, f64)>) {
    pts.sort_by(|p, q| p.0.total_cmp(&q.0));
    if pts.len() > 3 {
        let i = (0..pts.len())
            .min_by(|&i, &j| pts[i].1.total_cmp(&pts[j].1))
            .unwrap_or(1)
            .clamp(1, pts.len() - 2);
        *pts = pts[i - 1..=i + 1].to_vec();
    }
}

fn candidates(
    ctx: &Ctx<'_>,
    st: &State,
    fit_lsd: f64,
    modulations: bool,
) -> Result<Vec<Evaluated>, CloseLoopError> {
    let lr = log_ratio(ctx, st);
    // The families are independent (each reads the context and the state; the simulation memo
    // only saves work), so they run in parallel and are collected in this fixed order: the
    // candidates, and so the run, are the same as evaluated one after another.
    type Family<'f> = Box<dyn Fn() -> Result<Vec<Evaluated>, CloseLoopError> + Send + Sync + 'f>;
    let families: Vec<Family<'_>> = vec![
        Box::new(|| Ok(path_candidates(ctx, st))),
        Box::new(|| Ok(line_candidates(ctx, st, &lr))),
        Box::new(|| Ok(resonance_candidates(ctx, st, &lr))),
        Box::new(|| speed_candidates(ctx, st)),
        Box::new(|| Ok(Vec::from_iter(slip_candidate(ctx, st)))),
        Box::new(|| Ok(Vec::from_iter(highpass_candidate(ctx, st)))),
        Box::new(|| Ok(Vec::from_iter(fault_size_candidate(ctx, st, fit_lsd)))),
        Box::new(|| Ok(added_fault_candidates(ctx, st, fit_lsd))),
        Box::new(|| Ok(Vec::from_iter(preload_candidate(ctx, st)))),
        // a modulation at the shaft, twice-shaft or cage rate competes with the lines it
        // explains (the sidebands of the model's own lines, which tones would otherwise take one
        // by one), and only where the held-out envelope confirms it by itself, as in the envelope
        // phase: a spectral patch is no modulation. Other rates wait for the envelope phase (a
        // fault's own sideband 0.3 % off its geometric rate, BPFO − 2·fr, was taken at depth 1)
        Box::new(move || {
            if !modulations {
                return Ok(Vec::new());
            }
            Ok(modulation_candidates(ctx, st)
                .into_iter()
                .filter(|cand| match &cand.effect {
                    Effect::Modulation {
                        modulation, rate, ..
                    } => {
                        *rate != "other"
                            && modulation::held_out_confirms(ctx, st, modulation).is_some()
                    }
                    _ => false,
                })
                .collect())
        }),
    ];
    // rayon collects in the families' order; only the speed family can fail
    let found: Vec<Vec<Evaluated>> = families.par_iter().map(|f| f()).collect::<Result<_, _>>()?;
    Ok(found.into_iter().flatten().collect())
}

mod fault;
mod lines;
mod modulation;
mod naming;
mod path;
mod ranking;
mod resonance;
mod spectra;
mod speed;
mod start;

use lines::{fit_line, line_candidates, shaft_force_candidate};

use fault::added_fault_candidates;
use modulation::modulation_candidates;
use naming::{Taken, is_declared_fault_line, take};
use path::{has_impacts, highpass_candidate, path_candidates, with_impacts_path};
use ranking::{before_slip, declared_first, strong_lines_first};
use resonance::resonance_candidates;
use spectra::{log_ratio, observer_rms, residual_observer, segments, spectra};
use speed::{fault_size_candidate, preload_candidate, slip_candidate, speed_candidates};
use start::{prior_state, start_from};

#[cfg(test)]
mod tests {
    use super::refine_parabolic;
    use std::cell::Cell;

    /// The parabolic refinement finds a smooth minimum between grid points to the lattice's
    /// resolution in at most its few evaluations, counts new points only, holds an end point's
    /// refinement between the end and its neighbour, and keeps the grid's best when nothing
    /// tried is better.
    #[test]
    fn parabolic_refinement_finds_a_smooth_minimum_in_few_evaluations() {
        let grid: Vec<f64> = (-4..=4).map(|k| 0.5 * f64::from(k)).collect();
        let lattice = 1.0 / 32.0;
        for (x0, k) in [(0.3, 5), (-1.13, 2), (1.9, 8)] {
            let calls = Cell::new(0usize);
            let f = |x: f64| (x - x0).powi(2) + 0.3 * (x - x0).powi(4);
            let eval = |x: f64| {
                calls.set(calls.get() + 1);
                Some(((), f(x)))
            };
            let best = (grid[k], (), f(grid[k]));
            let (x, (), v) = refine_parabolic(&grid, k, best, eval, 3, lattice);
            // the two bracketing grid points are evaluated again (the memo makes them free in
            // the loop), then at most 3 new points
            assert!(calls.get() <= 2 + 3, "{} evaluations", calls.get());
            let want = if k == 8 { x0.min(2.0 - lattice) } else { x0 };
            assert!((x - want).abs() <= lattice, "min {x0}: found {x} ({v})");
        }
        // a minimum just inside an end of the grid, on an objective with fine-scale scatter
        // (a parabola through the end and the next two points extrapolates past the end; the
        // golden-section step reaches inside)
        let f = |x: f64| (x + 1.84).powi(2) + 0.002 * (97.0 * x).sin();
        let eval = |x: f64| Some(((), f(x)));
        let (x, (), _) = refine_parabolic(&grid, 0, (-2.0, (), f(-2.0)), eval, 3, lattice);
        assert!(
            (x + 1.84).abs() <= 2.0 * lattice,
            "min -1.84 near the end: found {x}"
        );
        // a grid point better than anything between its neighbours is kept
        let eval = |x: f64| Some(((), if x == 0.5 { -1.0 } else { x.abs() }));
        let (x, (), v) = refine_parabolic(&grid, 5, (0.5, (), -1.0), eval, 3, lattice);
        assert_eq!((x, v), (0.5, -1.0));
    }
}
