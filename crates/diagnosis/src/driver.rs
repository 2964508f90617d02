//! [`diagnose`]: the steps of the method (crate docs, "Method") on one recording.

use residual_features::SpectralEngine;

use crate::bands::{envelope_spectra, healthy_spectra};
use crate::report::band_choice;
use crate::{
    ArWhitener, Baseline, BearingSpec, Diagnosis, DiagnosisError, HARMONICS, Hypothesis,
    HypothesisEvidence, MAX_RPM, MIN_LINES, MIN_RPM, MIN_TURNS, OperatingPoint, PERIODIC_LINE_DB,
    Reference, Result, SECOND_BAND_LINE_DB, SPEED_TOL, Scores, SecondaryRead, Statistics,
    Thresholds, candidate_bands, check_fs, error, evidence, min_band_width_hz, moments,
    sk_threshold, speed, whiten,
};

/// Diagnose one recording `x` sampled at `fs_hz`, shaft at `rpm`, on `bearing`, against an
/// optional prepared healthy `baseline` (self-referenced otherwise).
///
/// # Errors
/// Typed, one-line [`DiagnosisError`]s for a bad sampling rate or speed, a recording shorter than
/// [`MIN_TURNS`] shaft turns, non-finite samples, a baseline at another sampling rate, a constant
/// signal. Never panics, never returns NaN.
pub fn diagnose(
    x: &[f64],
    fs_hz: f64,
    rpm: f64,
    bearing: &BearingSpec,
    baseline: Option<&Baseline>,
) -> Result<Diagnosis> {
    thread_local! {
        // FFT plans and Hann windows kept between recordings of one thread, each plan built
        // on its own so that a recording's result does not depend on which recordings the
        // thread diagnosed before it (a batch runs them in parallel, in no fixed order)
        static ENGINE: std::cell::RefCell<SpectralEngine> =
            std::cell::RefCell::new(SpectralEngine::order_independent());
    }
    ENGINE.with_borrow_mut(|engine| diagnose_with(engine, x, fs_hz, rpm, bearing, baseline))
}

fn diagnose_with(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm: f64,
    bearing: &BearingSpec,
    baseline: Option<&Baseline>,
) -> Result<Diagnosis> {
    check_fs(fs_hz)?;
    if !(rpm.is_finite() && (MIN_RPM..=MAX_RPM).contains(&rpm)) {
        return Err(DiagnosisError::RpmOutOfRange {
            rpm,
            min: MIN_RPM,
            max: MAX_RPM,
        });
    }
    error::check_finite("recording", x)?;
    // 0. the speed the recording shows (its shaft-harmonic comb, resolved to better than half
    //    the lines' speed tolerance) replaces the declared one when the comb stands out and the
    //    two differ by more than half that tolerance: a larger error would eat the windows' margin
    let measured_speed = speed::estimate_speed(engine, x, fs_hz, rpm)?;
    let replaces = |m: &speed::SpeedEstimate| (m.rpm / rpm - 1.0).abs() > 0.5 * SPEED_TOL;
    let rpm_used = match measured_speed {
        Some(m) if m.accepted && replaces(&m) => m.rpm,
        _ => rpm,
    };
    let o = bearing.orders;
    // the shaft rate and the narrowest band at a speed, if the sampling rate holds such a band
    let plan = |rpm_used: f64| {
        let fr = rpm_used / 60.0;
        let min_width = min_band_width_hz(&o, fr);
        if 2.0 * min_width > 0.5 * fs_hz {
            return Err(DiagnosisError::SampleRateTooLow {
                fs_hz,
                rpm,
                needed_hz: min_width,
            });
        }
        Ok((fr, min_width))
    };
    let (fr, min_width) = plan(rpm_used)?;
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
    if let Some(b) = baseline
        && (b.whitener.fs_hz - fs_hz).abs() > 1e-9 * fs_hz
    {
        return Err(DiagnosisError::SampleRateMismatch {
            recording_hz: fs_hz,
            baseline_hz: b.whitener.fs_hz,
        });
    }

    // 1. residual
    let self_fit;
    let (whitener, reference) = match baseline {
        Some(b) => (&b.whitener, Reference::Baseline),
        None => {
            self_fit = ArWhitener::fit(x, fs_hz, "recording")?;
            (&self_fit, Reference::SelfReference)
        }
    };
    let e = whitener.residual(x);
    // 0b. no comb in the recording's own spectrum: the shaft comb of the residual's squared
    //     envelopes (a defect or a load that turns with the shaft modulates the impacts at fr);
    //     the envelopes are kept for step 2 unless the speed found changes the band plan
    let mut bands = candidate_bands(fs_hz, min_width);
    let mut envs = None;
    let mut envelope_speed = None;
    if !measured_speed.is_some_and(|m| m.accepted) {
        let all = engine.band_squared_envelopes(&e, fs_hz, &bands)?;
        envelope_speed = speed::estimate_envelope_speed(engine, &all, rpm)?;
        envs = Some(all);
    }
    let (rpm_used, fr, min_width) = match envelope_speed {
        Some(m) if replaces(&m) => {
            let (fr, min_width) = plan(m.rpm)?;
            let moved = candidate_bands(fs_hz, min_width);
            if moved != bands {
                bands = moved;
                envs = None;
            }
            (m.rpm, fr, min_width)
        }
        _ => (rpm_used, fr, min_width),
    };
    let (rms, kurt) = moments(&e, "recording")?;
    let (_, signal_kurtosis) = moments(x, "recording")?;
    let statistics = match baseline {
        Some(b) => {
            // against a band-limited (decimated) baseline, both residuals below its limit
            let (cmp_rms, cmp_kurt) = match b.band_limit_hz {
                Some(limit) => moments(
                    &engine.bandpass_fft(&e, fs_hz, residual_features::Band::new(0.0, limit)?)?,
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
    };

    // 2. bands: squared envelopes, spectral kurtosis, Welch squared envelope spectra
    let envs = match envs {
        Some(v) => v,
        None => engine.band_squared_envelopes(&e, fs_hz, &bands)?,
    };
    let spectra = envelope_spectra(engine, &envs, e.len() as f64 / fs_hz, fr, &o)?;
    // the healthy machine's squared envelope spectra in the same bands, at the same resolution
    // (a baseline holding a residual only; one too short for a band's Welch segment gives none)
    let resolutions: Vec<f64> = spectra.iter().map(|s| s.resolution_hz).collect();
    let base_spectra =
        healthy_spectra(engine, baseline, fs_hz, &bands, &resolutions, spectra.len())?;
    let sk_best = (0..spectra.len())
        .max_by(|&a, &b| {
            spectra[a]
                .spectral_kurtosis
                .total_cmp(&spectra[b].spectral_kurtosis)
                .then(b.cmp(&a))
        })
        .ok_or(DiagnosisError::SampleRateTooLow {
            fs_hz,
            rpm,
            needed_hz: min_width,
        })?;

    // 3. evidence. Envelope analysis needs impulsive content: only bands whose spectral
    //    kurtosis exceeds a Gaussian's by SK_SIGMAS standard deviations (σ = 2/√(B·T)) are
    //    eligible; among them, the band where the best hypothesis scores highest is the one
    //    band all hypotheses are read in.
    let duration_s = e.len() as f64 / fs_hz;
    let eligible: Vec<usize> = (0..spectra.len())
        .filter(|&i| {
            let w = spectra[i].band_hz[1] - spectra[i].band_hz[0];
            spectra[i].spectral_kurtosis > sk_threshold(w, duration_s)
        })
        .collect();
    let eval_all = |i: usize| -> Vec<HypothesisEvidence> {
        Hypothesis::ALL
            .iter()
            .map(|&h| evidence::evaluate(h, &spectra[i], base_spectra[i].as_ref(), &o, fr))
            .collect()
    };
    let best_score = |v: &[HypothesisEvidence]| v.iter().map(|e| e.score_db).fold(0.0, f64::max);
    let mut chosen: Option<(usize, Vec<HypothesisEvidence>)> = None;
    let eligible_evidence: Vec<Vec<HypothesisEvidence>> =
        eligible.iter().map(|&i| eval_all(i)).collect();
    for (&i, ev) in eligible.iter().zip(&eligible_evidence) {
        let ev = ev.clone();
        let better = match &chosen {
            None => true,
            Some((j, b)) => {
                let (x, y) = (best_score(&ev), best_score(b));
                x > y || (x == y && spectra[i].spectral_kurtosis > spectra[*j].spectral_kurtosis)
            }
        };
        if better {
            chosen = Some((i, ev));
        }
    }
    // Dense impacts (a high fault rate against a long ring-down) overlap into a near-Gaussian
    // band — low spectral kurtosis — while their envelope is strongly periodic. When no band is
    // impulsive, a band still qualifies on periodicity alone if one hypothesis shows MIN_LINES
    // of its harmonics present at ≥ PERIODIC_LINE_DB (the detection rule's 6 dB raised to make
    // up for the missing impulsiveness): a pattern at the kinematic rate that a stationary band
    // does not produce.
    if chosen.is_none() {
        for i in 0..spectra.len() {
            let ev = eval_all(i);
            let periodic = ev.iter().any(|h| {
                h.harmonics
                    .iter()
                    .filter(|l| l.present && l.evidence_db >= PERIODIC_LINE_DB)
                    .count()
                    >= MIN_LINES
            });
            let better = chosen
                .as_ref()
                .is_none_or(|(_, b)| best_score(&ev) > best_score(b));
            if periodic && better {
                chosen = Some((i, ev));
            }
        }
    }
    let impulsive = chosen.is_some();
    let (bi, mut evidence) = chosen.unwrap_or_else(|| (sk_best, eval_all(sk_best)));
    evidence::cross_explain(
        &mut evidence,
        &spectra[bi],
        base_spectra[bi].as_ref(),
        fr,
        o.ftf * fr,
    );
    if !impulsive {
        for ev in &mut evidence {
            ev.detected = false;
        }
    }

    // 3b. a fault in a band of its own. The common band is the best one for the strongest
    //     signature; a second fault whose impacts ring a different resonance, or are masked
    //     there by the first, shows in another band. Each hypothesis not detected in the common
    //     band is read in every other eligible band; it is added when, in one of them, it is
    //     detected, scores highest of the three, has MIN_LINES harmonics at ≥ SECOND_BAND_LINE_DB
    //     (this second search over bands is a second multiple comparison), and none of its
    //     counting lines belongs to the family of a fault detected in the common band whose own
    //     lines show in this band.
    let mut secondary: Vec<SecondaryRead> = Vec::new();
    if impulsive && !eligible.is_empty() {
        let primary: Vec<(Hypothesis, Vec<(f64, f64)>)> = evidence
            .iter()
            .filter(|e| e.detected)
            .map(|e| (e.hypothesis, e.family_spans(fr, o.ftf * fr)))
            .collect();
        for (hi, &h) in Hypothesis::ALL.iter().enumerate() {
            if evidence[hi].detected {
                continue;
            }
            let mut best: Option<(usize, HypothesisEvidence)> = None;
            for (&i, ev) in eligible.iter().zip(&eligible_evidence) {
                if i == bi {
                    continue;
                }
                // the common band's faults whose own lines show in this band (detected here on
                // their own): only their families can explain lines here
                let here: Vec<(Hypothesis, Vec<(f64, f64)>)> = primary
                    .iter()
                    .filter(|(p, _)| ev.iter().any(|e| e.hypothesis == *p && e.detected))
                    .cloned()
                    .collect();
                let mut ev = ev.clone();
                evidence::cross_explain(
                    &mut ev,
                    &spectra[i],
                    base_spectra[i].as_ref(),
                    fr,
                    o.ftf * fr,
                );
                if ev.iter().any(|e| e.score_db > ev[hi].score_db) {
                    continue;
                }
                let mut e = ev.swap_remove(hi);
                evidence::explain_by(&mut e, &here, &spectra[i], base_spectra[i].as_ref(), fr);
                let strong = e
                    .harmonics
                    .iter()
                    .filter(|l| l.counts() && l.evidence_db >= SECOND_BAND_LINE_DB)
                    .count();
                if e.detected
                    && strong >= MIN_LINES
                    && best.as_ref().is_none_or(|(_, b)| e.score_db > b.score_db)
                {
                    best = Some((i, e));
                }
            }
            if let Some((i, e)) = best {
                secondary.push(SecondaryRead {
                    hypothesis: h,
                    band: band_choice(
                        &spectra[i],
                        format!(
                            "{} is the strongest signature in this band and has {MIN_LINES} harmonics at >= {SECOND_BAND_LINE_DB} dB no common-band fault present in this band explains",
                            h.name()
                        ),
                    ),
                    evidence: e,
                    envelope: spectra[i].clone(),
                });
            }
        }
    }

    // 4. verdict
    let detected: Vec<Hypothesis> = Hypothesis::ALL
        .iter()
        .copied()
        .filter(|&h| {
            evidence.iter().any(|e| e.hypothesis == h && e.detected)
                || secondary.iter().any(|r| r.hypothesis == h)
        })
        .collect();
    let verdict = if detected.is_empty() {
        "normal".to_string()
    } else {
        detected
            .iter()
            .map(|h| h.name())
            .collect::<Vec<_>>()
            .join("+")
    };
    let chosen_by = if impulsive && eligible.is_empty() {
        format!(
            "no band has significant spectral kurtosis; read on periodicity: the band of {} \
             where a hypothesis has {MIN_LINES} harmonics at >= {PERIODIC_LINE_DB} dB and scores highest",
            spectra.len()
        )
    } else if impulsive {
        format!(
            "largest hypothesis score among the {} of {} bands with significant spectral kurtosis",
            eligible.len(),
            spectra.len()
        )
    } else {
        "no band has significant spectral kurtosis (no impulsive content): evidence shown in the maximum-SK band, not used".to_string()
    };
    let sp = &spectra[bi];
    let choice = |i: usize, by: String| band_choice(&spectra[i], by);
    let shaft_harmonics = (1..=HARMONICS)
        .map(|k| {
            let f = k as f64 * fr;
            let tol = (0.6 * sp.resolution_hz).max(0.005 * f);
            sp.line(
                format!("fr×{k}"),
                f,
                f - tol,
                f + tol,
                fr,
                false,
                base_spectra[bi].as_ref(),
            )
        })
        .collect();
    let score = |h: Hypothesis| {
        evidence
            .iter()
            .find(|e| e.hypothesis == h)
            .map_or(0.0, |e| e.score_db)
    };
    Ok(Diagnosis {
        verdict,
        scores: Scores {
            inner: score(Hypothesis::Inner),
            outer: score(Hypothesis::Outer),
            ball: score(Hypothesis::Ball),
        },
        detected,
        reference,
        operating_point: OperatingPoint {
            fs_hz,
            rpm,
            shaft_hz: fr,
            rpm_used,
            measured_speed,
            envelope_speed,
            bearing: bearing.name.clone(),
            bearing_spec: bearing.echo(),
            orders: o,
            frequencies_hz: o.at(fr),
        },
        whitening: whitener.clone(),
        band: choice(bi, chosen_by),
        kurtogram_band: choice(sk_best, "maximum spectral kurtosis".into()),
        evidence,
        shaft_harmonics,
        statistics,
        thresholds: Thresholds::default(),
        envelope: sp.clone(),
        secondary,
    })
}
