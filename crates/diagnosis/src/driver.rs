//! [`diagnose`]: the steps of the method (crate docs, "Method") on one recording.

use residual_features::order::{self, OrderTracked};
use residual_features::{Band, SpectralEngine};

use crate::bands::{envelope_spectra, healthy_spectra};
use crate::detect::{self, Detection};
use crate::options::{DiagnoseOptions, SpeedSource};
use crate::report::band_choice;
use crate::{
    ArWhitener, Baseline, BearingSpec, Diagnosis, DiagnosisError, EnvelopeSpectrum, HARMONICS,
    Hypothesis, HypothesisEvidence, MIN_TURNS, OperatingPointUsed, Reference, Result, Scores,
    SearchedLine, SecondaryRead, Signal, Statistics, Thresholds, candidate_bands, check_fs,
    min_band_width_hz, moments, speed, whiten,
};
use bearing_model::FaultOrders;

/// Diagnose one recording (its samples and sampling rate, a checked [`Signal`]), shaft declared at
/// `rpm`, on `bearing`, against an optional prepared healthy `baseline` (self-referenced
/// otherwise): the speed is searched
/// within ± [`crate::options::DEFAULT_SPEED_SEARCH`] of `rpm` and the false-alarm probability is
/// [`detect::DEFAULT_FALSE_ALARM`] ([`diagnose_with_options`] sets both).
///
/// # Errors
/// Typed, one-line [`DiagnosisError`]s for a sampling rate or speed out of range, a recording
/// shorter than [`MIN_TURNS`] shaft turns, a baseline at another sampling rate, a constant
/// signal. Never panics, never returns NaN. (No samples, a non-finite sample or a rate that is
/// not finite and > 0 cannot make a [`Signal`]: `DiagnosisError::from` a [`crate::SignalError`]
/// says so in this crate's words.)
pub fn diagnose(
    signal: &Signal<'_>,
    rpm: f64,
    bearing: &BearingSpec,
    baseline: Option<&Baseline>,
) -> Result<Diagnosis> {
    diagnose_with_options(signal, bearing, baseline, &DiagnoseOptions::declared(rpm))
}

/// [`diagnose`] with the speed given as a declared value and/or a range to search, and the
/// false-alarm probability chosen ([`DiagnoseOptions`]).
///
/// # Errors
/// As [`diagnose`], plus [`DiagnosisError::InvalidOptions`] for options that do not check and
/// [`DiagnosisError::SpeedNotFound`] when no speed is declared and the recording shows no shaft
/// comb in a range too wide to search the fault lines over.
pub fn diagnose_with_options(
    signal: &Signal<'_>,
    bearing: &BearingSpec,
    baseline: Option<&Baseline>,
    options: &DiagnoseOptions,
) -> Result<Diagnosis> {
    with_engine(|engine| diagnose_in(engine, signal, bearing, baseline, options, Look::Track))
}

/// A recording whose shaft speed spreads more than this (fastest over slowest, less one) through
/// it, read from its own shaft comb frame by frame, is order tracked before it is diagnosed: at
/// 4 % a line's 3rd harmonic smears over more than a slip window (2 %) and its windows.
pub const SPEED_VARIES: f64 = 0.04;

/// What the recording's whole spectrum and, where that holds no comb, its frames say about its
/// speed.
pub(crate) enum FirstLook {
    /// A steady speed (or none read): the whole recording's shaft comb, if any.
    Steady(Option<speed::SpeedEstimate>),
    /// A speed that changes: the recording resampled at equal shaft angles, the shaft comb its
    /// leading lines show at its mean speed (what tracked it right), and the whole recording's
    /// comb, for the reading at one speed should the tracked one fail.
    Varying(
        Box<OrderTracked>,
        speed::SpeedEstimate,
        Option<speed::SpeedEstimate>,
    ),
}

/// How step 0 ([`first_look`]) reads a recording's speed.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Look {
    /// Its whole comb and, where that is not clear and the options allow it, frame by frame:
    /// order tracked where the speed changes.
    Track,
    /// An order-tracked record: its speed is the tracking's, the shaft comb its leading lines
    /// show at the tracked mean (`speed::leading_lines_speed`, refined) — a measured speed, read
    /// as a refined comb is (`CheckedOptions::find_speed`), not searched again.
    Tracked(speed::SpeedEstimate),
}

/// Step 0 of a diagnosis: the length check, the whole recording's shaft comb over the range
/// searched (for a record already tracked, [`Look::Tracked`], the comb that tracking showed) and
/// — self-referenced, unless the options ask for one speed, and only where that comb is not accepted (a
/// comb the whole recording holds is a steady speed's) — the speed frame by frame
/// (`residual_features::order::speed_profile`); a spread over [`SPEED_VARIES`] has the
/// recording resampled at equal shaft angles along it. Against a baseline nothing is tracked
/// (the baseline would have to be resampled alike).
pub(crate) fn first_look(
    engine: &mut SpectralEngine,
    signal: &Signal<'_>,
    baseline: Option<&Baseline>,
    options: &crate::options::CheckedOptions,
    look: Look,
) -> Result<FirstLook> {
    let (x, fs_hz) = (signal.samples(), signal.fs_hz());
    let [rpm_low, rpm_high] = options.search_rpm();
    check_length(x, fs_hz, rpm_low)?;
    if let Look::Tracked(m) = look {
        return Ok(FirstLook::Steady(Some(m)));
    }
    let comb = speed::estimate_speed_in(engine, x, fs_hz, rpm_low, rpm_high)?;
    if options.steady_speed
        || baseline.is_some()
        || comb.is_some_and(|m| m.accepted || m.refined_rpm.is_some())
    {
        return Ok(FirstLook::Steady(comb));
    }
    let Some(p) = order::speed_profile(engine, x, fs_hz, rpm_low, rpm_high)? else {
        return Ok(FirstLook::Steady(comb));
    };
    if p.spread() <= SPEED_VARIES {
        return Ok(FirstLook::Steady(comb));
    }
    // tracking is a chance taken, not a step owed: where it cannot be made (a fastest frame
    // leaving too few samples a turn) the recording is read at one speed, as before
    let Ok(t) = order::order_track_profile(engine, x, fs_hz, &p) else {
        return Ok(FirstLook::Steady(comb));
    };
    // the speed the tracked angle itself shows (refined by a shaft line's phase) may be steady
    // where the frames' readings scattered: then the recording is one of a steady speed
    if t.max_rpm / t.min_rpm - 1.0 <= SPEED_VARIES {
        return Ok(FirstLook::Steady(comb));
    }
    // the profile is a speed only if tracking along it shows what the recording did not: a
    // shaft comb the whole tracked record holds, its leading lines sharp enough to refine the
    // mean speed (the first order standing and three orders agreeing within 2e-4; frames of a
    // short or faulty record can follow a fault's near-comb from frame to frame; tracked along
    // that, the true comb smears and its lines agree on no speed)
    // — and that comb must stand out more than the best the recording read at one speed shows
    // (the comb scores compare: a tracked record holds as many bins an order as turns, as the
    // recording does): tracking is worth taking only where it sharpens the shaft's comb. A
    // steady record tracked along a path its frames' lines led astray (2.5 s pieces of CWRU's
    // ball-fault records, their frames' spectra dense with the fault's lines) holds its comb
    // weaker tracked than not (score 9–17 against 21–24); every sweeping machine of the
    // corpus tracked right holds it stronger (1.1–6 times)
    let shown = speed::leading_lines_speed(engine, &t.samples, t.equivalent_fs_hz, t.mean_rpm, 0.0)
        .ok()
        .flatten()
        .filter(|m| {
            m.refined_rpm
                .is_some_and(|r| (r / t.mean_rpm - 1.0).abs() <= TRACKED_COMB_AGREEMENT)
                && comb.is_none_or(|c| m.comb_score > c.comb_score)
        });
    Ok(match shown {
        Some(m) => FirstLook::Varying(Box::new(t), m, comb),
        None => FirstLook::Steady(comb),
    })
}

/// A tracked record's refined comb must stand within this of the profile's mean speed.
pub const TRACKED_COMB_AGREEMENT: f64 = 0.005;

/// `run` on the order-tracked recording `t` (at its equivalent rate, at its mean speed, its
/// speed the comb `shown` of its leading lines, at the user's false-alarm probability), the
/// diagnosis then saying how it was tracked and, as its declared speed and range, the user's
/// (`user`): the tracked record's mean is a measured speed, not one declared. Until 2026-12-08
/// the tracked record was read as if its mean had been declared: its comb searched again by the
/// whole-record rule (ten orders, most of them refused) and, where that found none, the fault
/// lines read both at the mean and with templates widened ± 10 % around it, each at half the
/// false-alarm probability, the report saying "declared" the tracked mean and "no shaft comb".
pub(crate) fn diagnose_tracked(
    t: OrderTracked,
    shown: speed::SpeedEstimate,
    user: &crate::options::CheckedOptions,
    run: impl FnOnce(&Signal<'_>, &DiagnoseOptions, Look) -> Result<Diagnosis>,
) -> Result<Diagnosis> {
    let signal = Signal::new(&t.samples, t.equivalent_fs_hz)?;
    let options = DiagnoseOptions::declared(t.mean_rpm).with_false_alarm(user.false_alarm);
    let mut d = run(&signal, &options, Look::Tracked(shown))?;
    let declared = user.declared_rpm();
    if let Some(sp) = d.operating_point.speed.as_mut() {
        sp.declared_rpm = declared;
        sp.search_rpm = user.search_rpm();
        sp.offset_from_declared_percent = declared.map(|r| 100.0 * (sp.rpm_used / r - 1.0));
        if sp.source == crate::options::SpeedSource::SpectrumComb {
            sp.note = format!(
                "shaft comb of the order-tracked recording at its mean speed: {} of {} orders present, refined from its leading lines",
                shown.orders_present, shown.orders
            );
        }
    }
    d.operating_point.rpm = declared.unwrap_or(d.operating_point.rpm_used);
    d.order_tracking = Some(OrderTracked {
        samples: Vec::new(),
        ..t
    });
    Ok(d)
}

/// Run `f` with this thread's spectral engine: FFT plans and Hann windows kept between
/// recordings of one thread, each plan built on its own so that a recording's result does not
/// depend on which recordings the thread diagnosed before it (a batch runs them in parallel, in
/// no fixed order).
pub(crate) fn with_engine<R>(f: impl FnOnce(&mut SpectralEngine) -> R) -> R {
    thread_local! {
        static ENGINE: std::cell::RefCell<SpectralEngine> =
            std::cell::RefCell::new(SpectralEngine::order_independent());
    }
    // a thread already inside a diagnosis can start another one: a rayon task stolen while a
    // faer least-squares solve of the first waits on its join (the false-alarm corpus runs its
    // recordings on rayon). That one gets a fresh engine: the engine is order-independent, so
    // its bits are the same either way
    ENGINE.with(|cell| match cell.try_borrow_mut() {
        Ok(mut engine) => f(&mut engine),
        Err(_) => f(&mut SpectralEngine::order_independent()),
    })
}

/// The analysis plan at a speed: shaft rate, narrowest band, candidate bands.
struct Plan {
    fr: f64,
    min_width: f64,
    bands: Vec<Band>,
}

fn plan(fs_hz: f64, o: &FaultOrders, rpm: f64, widest_rpm: f64) -> Result<Plan> {
    let fr = rpm / 60.0;
    // bands wide enough for the template at the fastest speed it may read
    let min_width = min_band_width_hz(o, widest_rpm.max(rpm) / 60.0);
    if 2.0 * min_width > 0.5 * fs_hz {
        return Err(DiagnosisError::SampleRateTooLow {
            fs_hz,
            rpm: widest_rpm.max(rpm),
            needed_hz: min_width,
        });
    }
    Ok(Plan {
        fr,
        min_width,
        bands: candidate_bands(fs_hz, min_width),
    })
}

/// Steps 0–2 of a diagnosis: the speed, the residual, its statistics and the bands' squared
/// envelope spectra (the recording's and the healthy baseline's), planned for fault orders
/// `o`.
pub(crate) struct Analysis {
    pub finding: crate::SpeedFinding,
    pub spectrum_comb: Option<speed::SpeedEstimate>,
    pub envelope_comb: Option<speed::SpeedEstimate>,
    pub whitener: ArWhitener,
    pub reference: Reference,
    pub statistics: Statistics,
    pub fr: f64,
    pub spectra: Vec<EnvelopeSpectrum>,
    pub base_spectra: std::sync::Arc<Vec<Option<EnvelopeSpectrum>>>,
}

pub(crate) fn analyse(
    engine: &mut SpectralEngine,
    signal: &Signal<'_>,
    o: &FaultOrders,
    near_comb: f64,
    baseline: Option<&Baseline>,
    options: &crate::options::CheckedOptions,
    spectrum_comb: Option<speed::SpeedEstimate>,
) -> Result<Analysis> {
    // finite, non-empty, a positive rate: a `Signal` is checked when it is made; its length
    // and the whole recording's comb (step 0) were read by `first_look`
    let (x, fs_hz) = (signal.samples(), signal.fs_hz());
    let [rpm_low, rpm_high] = options.search_rpm();
    if let Some(b) = baseline
        && (b.whitener.fs_hz - fs_hz).abs() > 1e-9 * fs_hz
    {
        return Err(DiagnosisError::SampleRateMismatch {
            recording_hz: fs_hz,
            baseline_hz: b.whitener.fs_hz,
        });
    }

    // 1. residual
    let (whitener, reference) = match baseline {
        Some(b) => (b.whitener.clone(), Reference::Baseline),
        None => (
            ArWhitener::fit(signal, "recording")?,
            Reference::SelfReference,
        ),
    };
    let e = whitener.residual(x);

    // 0b. without a comb in the spectrum: the shaft comb of the residual's squared envelopes
    //     (a defect or a load that turns with the shaft modulates the impacts at fr), read in
    //     bands planned for the fastest speed searched
    let mut envelope_comb = None;
    let mut envs = None;
    let mut provisional = None;
    if !spectrum_comb.is_some_and(|m| m.accepted || m.refined_rpm.is_some()) {
        let p = plan(fs_hz, o, options.centre_rpm(), rpm_high)?;
        let all = engine.band_squared_envelopes(&e, fs_hz, &p.bands)?;
        envelope_comb = speed::estimate_envelope_speed_in(engine, &all, rpm_low, rpm_high)?;
        envs = Some(all);
        provisional = Some(p);
    }
    let finding = options.find_speed(spectrum_comb, envelope_comb, near_comb)?;
    let rpm_used = finding.rpm_used;
    let uncertain_fastest = rpm_used * (1.0 + finding.relative_uncertainty);
    let p = plan(fs_hz, o, rpm_used, uncertain_fastest)?;
    let envs = match (envs, provisional) {
        (Some(v), Some(q)) if q.bands == p.bands => v,
        _ => engine.band_squared_envelopes(&e, fs_hz, &p.bands)?,
    };
    let statistics = residual_statistics(engine, x, &e, fs_hz, baseline)?;

    // 2. bands: squared envelope spectra of the residual and of the healthy baseline
    let spectra = envelope_spectra(engine, &envs, e.len() as f64 / fs_hz, p.fr)?;
    if spectra.is_empty() {
        return Err(DiagnosisError::SampleRateTooLow {
            fs_hz,
            rpm: rpm_used,
            needed_hz: p.min_width,
        });
    }
    let resolutions: Vec<f64> = spectra.iter().map(|s| s.resolution_hz).collect();
    let base_spectra = healthy_spectra(
        engine,
        baseline,
        fs_hz,
        &p.bands,
        &resolutions,
        spectra.len(),
    )?;
    Ok(Analysis {
        finding,
        spectrum_comb,
        envelope_comb,
        whitener,
        reference,
        statistics,
        fr: p.fr,
        spectra,
        base_spectra,
    })
}

fn diagnose_in(
    engine: &mut SpectralEngine,
    signal: &Signal<'_>,
    bearing: &BearingSpec,
    baseline: Option<&Baseline>,
    options: &DiagnoseOptions,
    look: Look,
) -> Result<Diagnosis> {
    let fs_hz = signal.fs_hz();
    check_fs(fs_hz)?;
    let options = options.check()?;
    let spectrum_comb = match first_look(engine, signal, baseline, &options, look)? {
        FirstLook::Steady(c) => c,
        // a tracked record the diagnosis refuses (its equivalent rate too low for the bands,
        // say) is read at one speed instead
        FirstLook::Varying(t, m, c) => match diagnose_tracked(*t, m, &options, |s, o, l| {
            diagnose_in(engine, s, bearing, None, o, l)
        }) {
            Ok(d) => return Ok(d),
            Err(_) => c,
        },
    };
    let o = bearing.orders;
    let rate_uncertainty = options.rate_uncertainty(bearing);
    let near_comb = crate::options::near_comb_distance(&o, rate_uncertainty);
    let a = analyse(
        engine,
        signal,
        &o,
        near_comb,
        baseline,
        &options,
        spectrum_comb,
    )?;
    let fr = a.fr;

    // 3. the detector: each hypothesis's lines against the band's clear windows
    let unconfirmed = matches!(
        a.finding.source,
        SpeedSource::Declared | SpeedSource::RangeCentre
    );
    let detection = detect::detect(
        &a.spectra,
        &a.base_spectra,
        &o,
        fr,
        detect::Slack {
            speed: a.finding.relative_uncertainty,
            rate: rate_uncertainty,
        },
        unconfirmed,
        a.spectrum_comb
            .filter(speed::SpeedEstimate::is_complete)
            .map(|m| (m.rpm / 60.0, m.resolution)),
        options.false_alarm,
    );

    // 4. verdict and report
    let mut finding = a.finding;
    finding.read_at = Some(detection.stage);
    let rpm_used = finding.rpm_used;
    let operating_point = OperatingPointUsed {
        fs_hz,
        rpm: finding.declared_rpm.unwrap_or(rpm_used),
        shaft_hz: fr,
        rpm_used,
        measured_speed: a.spectrum_comb,
        envelope_speed: a.envelope_comb,
        bearing: bearing.name.clone(),
        bearing_spec: bearing.echo(),
        orders: o,
        frequencies_hz: o.at(fr),
        speed: Some(finding),
        rate_uncertainty,
    };
    Ok(report(
        &detection,
        &a.spectra,
        &a.base_spectra,
        &a.whitener,
        a.reference,
        operating_point,
        a.statistics,
        options.false_alarm,
    ))
}

/// A recording shorter than [`MIN_TURNS`] shaft turns at the slowest speed searched (plus the
/// longest whitening filter's start-up) is refused.
fn check_length(x: &[f64], fs_hz: f64, rpm_low: f64) -> Result<()> {
    let fr = rpm_low / 60.0;
    let turns = x.len() as f64 / fs_hz * fr;
    let needed =
        (MIN_TURNS / fr * fs_hz).ceil() as usize + whiten::ORDERS[whiten::ORDERS.len() - 1];
    if x.len() < needed {
        return Err(DiagnosisError::TooShort {
            samples: x.len(),
            needed,
            turns,
            min_turns: MIN_TURNS,
        });
    }
    Ok(())
}

/// Energy and kurtosis of the residual `e` against the baseline's (below its band limit when it
/// has one), or against a Gaussian when self-referenced.
fn residual_statistics(
    engine: &mut SpectralEngine,
    x: &[f64],
    e: &[f64],
    fs_hz: f64,
    baseline: Option<&Baseline>,
) -> Result<Statistics> {
    let (rms, kurt) = moments(e, "recording")?;
    let (_, signal_kurtosis) = moments(x, "recording")?;
    Ok(match baseline {
        Some(b) => {
            let (cmp_rms, cmp_kurt) = match b.band_limit_hz {
                Some(limit) => moments(
                    &engine.bandpass_fft(e, fs_hz, Band::new(0.0, limit)?)?,
                    "recording below the baseline's band limit",
                )?,
                None => (rms, kurt),
            };
            let ratio = (cmp_rms / b.residual_rms).powi(2);
            Statistics {
                residual_samples: e.len(),
                residual_rms: rms,
                residual_kurtosis: kurt,
                signal_kurtosis,
                energy_ratio: Some(ratio),
                energy_ratio_db: Some(10.0 * ratio.log10()),
                kurtosis_ratio: cmp_kurt / b.residual_kurtosis,
                kurtosis_reference: "baseline residual".into(),
                compared_below_hz: b.band_limit_hz,
            }
        }
        None => Statistics {
            residual_samples: e.len(),
            residual_rms: rms,
            residual_kurtosis: kurt,
            signal_kurtosis,
            energy_ratio: None,
            energy_ratio_db: None,
            kurtosis_ratio: kurt / 3.0,
            kurtosis_reference: "gaussian".into(),
            compared_below_hz: None,
        },
    })
}

/// The report of a detection: verdict, per-hypothesis evidence in each one's own band, the
/// primary band and the faults confirmed in other bands.
#[allow(clippy::too_many_arguments)]
fn report(
    det: &Detection,
    spectra: &[EnvelopeSpectrum],
    base_spectra: &[Option<EnvelopeSpectrum>],
    whitener: &ArWhitener,
    reference: Reference,
    operating_point: OperatingPointUsed,
    statistics: Statistics,
    alpha: f64,
) -> Diagnosis {
    let fr = operating_point.shaft_hz;
    let evidence: Vec<HypothesisEvidence> = det
        .templates
        .iter()
        .zip(&det.per_hypothesis)
        .zip(&det.readings)
        .map(|((t, sig), reading)| {
            crate::evidence::from_detection(
                t,
                sig,
                reading,
                &det.views[sig.band_index],
                &spectra[sig.band_index],
                det.confirmed.contains(&t.hypothesis),
            )
        })
        .collect();
    let verdict = verdict(det);
    let idx = hypothesis_index;
    let primary = primary_hypothesis(det);
    let bi = det.per_hypothesis[idx(primary)].band_index;
    let sk_best = (0..spectra.len())
        .max_by(|&a, &b| {
            spectra[a]
                .spectral_kurtosis
                .total_cmp(&spectra[b].spectral_kurtosis)
                .then(b.cmp(&a))
        })
        .unwrap_or(0);
    let secondary = secondary_reads(det, spectra, &evidence, bi);
    let sp = &spectra[bi];
    let shaft_harmonics = shaft_harmonics(sp, fr, base_spectra[bi].as_ref());
    let score = |h: Hypothesis| det.per_hypothesis[idx(h)].statistic_db;
    let p_min = det
        .per_hypothesis
        .iter()
        .map(|s| s.p_healthy)
        .fold(1.0, f64::min);
    let chosen_by = format!(
        "the band where {} reads strongest against its null (p under healthy {:.2e} after the search over {} bands)",
        primary.name(),
        det.per_hypothesis[idx(primary)].p_healthy,
        spectra.len()
    );
    let detected: Vec<Hypothesis> = if det.uncertain.is_empty() {
        det.confirmed.clone()
    } else {
        Vec::new()
    };
    Diagnosis {
        verdict,
        detected,
        scores: Scores {
            inner: score(Hypothesis::Inner),
            outer: score(Hypothesis::Outer),
            ball: score(Hypothesis::Ball),
        },
        reference,
        operating_point,
        whitening: whitener.clone(),
        band: band_choice(sp, chosen_by),
        kurtogram_band: band_choice(&spectra[sk_best], "maximum spectral kurtosis".into()),
        evidence,
        shaft_harmonics,
        statistics,
        thresholds: Thresholds::with_false_alarm(alpha),
        envelope: sp.clone(),
        secondary,
        candidates: det.uncertain.clone(),
        p_healthy: (Hypothesis::ALL.len() as f64 * p_min).min(1.0),
        false_alarm: alpha,
        bearing_guess: None,
        order_tracking: None,
    }
}

/// The index of `h` in [`Hypothesis::ALL`] (the order of a detection's per-hypothesis lists).
fn hypothesis_index(h: Hypothesis) -> usize {
    Hypothesis::ALL.iter().position(|x| *x == h).unwrap_or(0)
}

/// A detection's verdict: `uncertain`, `normal`, or the confirmed faults joined by `+`.
fn verdict(det: &Detection) -> String {
    if !det.uncertain.is_empty() {
        "uncertain".to_string()
    } else if det.confirmed.is_empty() {
        "normal".to_string()
    } else {
        det.confirmed
            .iter()
            .map(|h| h.name())
            .collect::<Vec<_>>()
            .join("+")
    }
}

/// The primary hypothesis: the most significant confirmed (or candidate) one, else the one
/// closest to significance.
fn primary_hypothesis(det: &Detection) -> Hypothesis {
    let idx = hypothesis_index;
    det.uncertain
        .first()
        .copied()
        .or_else(|| {
            det.confirmed.iter().copied().min_by(|&a, &b| {
                det.per_hypothesis[idx(a)]
                    .p_healthy
                    .total_cmp(&det.per_hypothesis[idx(b)].p_healthy)
            })
        })
        .unwrap_or_else(|| {
            (0..det.per_hypothesis.len())
                .min_by(|&a, &b| {
                    det.per_hypothesis[a]
                        .p_healthy
                        .total_cmp(&det.per_hypothesis[b].p_healthy)
                        .then(a.cmp(&b))
                })
                .map_or(Hypothesis::Inner, |i| Hypothesis::ALL[i])
        })
}

/// The confirmed faults that read strongest outside the primary band `bi`, each in its own band.
fn secondary_reads(
    det: &Detection,
    spectra: &[EnvelopeSpectrum],
    evidence: &[HypothesisEvidence],
    bi: usize,
) -> Vec<SecondaryRead> {
    let idx = hypothesis_index;
    det.confirmed
        .iter()
        .filter(|&&h| det.per_hypothesis[idx(h)].band_index != bi)
        .map(|&h| {
            let s = &det.per_hypothesis[idx(h)];
            SecondaryRead {
                hypothesis: h,
                band: band_choice(
                    &spectra[s.band_index],
                    format!(
                        "{} reads strongest in this band (p under healthy {:.2e} after the band search)",
                        h.name(),
                        s.p_healthy
                    ),
                ),
                evidence: evidence[idx(h)].clone(),
                envelope: spectra[s.band_index].clone(),
            }
        })
        .collect()
}

/// The shaft's first [`HARMONICS`] orders of `fr` in the primary band's spectrum `sp`, each
/// searched within `max(0.6 bin, 0.5 %)` and compared with the baseline's spectrum `base`.
fn shaft_harmonics(
    sp: &EnvelopeSpectrum,
    fr: f64,
    base: Option<&EnvelopeSpectrum>,
) -> Vec<SearchedLine> {
    (1..=HARMONICS)
        .map(|k| {
            let f = k as f64 * fr;
            let tol = (0.6 * sp.resolution_hz).max(0.005 * f);
            sp.line(format!("fr×{k}"), f, f - tol, f + tol, fr, false, base)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagnosis started on a thread already inside one (a rayon task stolen during a faer
    /// solve) gets its own engine instead of a `RefCell` double borrow, and the same bits.
    #[test]
    fn a_diagnosis_inside_a_diagnosis_gets_its_own_engine() {
        let fs = 12_000.0;
        let x: Vec<f64> = (0..24_000)
            .map(|i| ((i * 7919 % 1013) as f64 / 1013.0 - 0.5) + (0.01 * i as f64).sin())
            .collect();
        let signal = crate::Signal::new(&x, fs).unwrap();
        let bearing = crate::BearingSpec::parse("6205").unwrap();
        let alone = diagnose(&signal, 1800.0, &bearing, None).unwrap();
        let nested = with_engine(|_outer| diagnose(&signal, 1800.0, &bearing, None).unwrap());
        assert_eq!(
            serde_json::to_string(&alone).unwrap(),
            serde_json::to_string(&nested).unwrap()
        );
    }
}
