//! The reports of one recording: JSON, Markdown and the PNG figure.

use std::path::Path;

use super::Outcome;

/// Write `<report>.json`, `.md` and `.png`.
///
/// # Errors
/// File system or drawing errors.
pub fn write_reports(o: &Outcome, report: &Path, title: &str) -> anyhow::Result<()> {
    if let Some(parent) = report.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)?;
    }
    let mut json = serde_json::to_value(&o.diagnosis)?;
    if let (Some(t), Some(obj)) = (&o.trained, json.as_object_mut()) {
        obj.insert(
            "classifier".into(),
            serde_json::json!({
                "class": t.class,
                "segments": t.segments,
                "classifier": t.classifier,
                "examples": t.examples,
                "recordings": t.recordings,
                "file": t.file,
            }),
        );
    }
    std::fs::write(
        report.with_extension("json"),
        serde_json::to_string_pretty(&json)? + "\n",
    )?;
    std::fs::write(report.with_extension("md"), markdown(o, title))?;
    crate::figure::envelope_figure(&o.diagnosis, &report.with_extension("png"), title)?;
    Ok(())
}

/// The Markdown report: the verdict, the trained classifier's class, the bearing guess, the
/// facts of the run, the rule, the evidence table and the shaft harmonics, in that order.
pub fn markdown(o: &Outcome, title: &str) -> String {
    let d = &o.diagnosis;
    let mut m = verdict_section(d, title);
    if let Some(t) = &o.trained {
        m += &trained_section(t);
    }
    if let Some(g) = &d.bearing_guess {
        m += &bearing_guess_section(g);
    }
    m += &speed_line(&d.operating_point);
    if let Some(t) = &d.order_tracking {
        m += &tracking_line(t);
    }
    if let Some((h, rpm)) = d.fault_read_at_rpm(&d.evidence) {
        m += &format!(
            "- fault lines read over the range: {} at {rpm:.1} rpm ({:+.1} % from the speed used), read there because the declared speed's own reading found no fault, or one a healthy machine shows at least 100 times as often; the figure's markers are drawn at it\n",
            h.name(),
            100.0 * (rpm / d.operating_point.rpm_used - 1.0)
        );
    }
    m += &facts_section(o);
    m += &format!("Rule: {}.\n\n", d.thresholds.rule);
    m += &evidence_table(d);
    m += &shaft_harmonics_line(d);
    m
}

/// The title, the verdict (with the candidates it could not tell apart) and its false-alarm
/// probability.
fn verdict_section(d: &diagnosis::Diagnosis, title: &str) -> String {
    let mut m = format!("# Diagnosis of {title}\n\n**Verdict: {}**", d.verdict);
    if !d.candidates.is_empty() {
        m += &format!(
            " (candidates: {}; their lines cannot be told apart)",
            d.candidates
                .iter()
                .map(|h| h.name())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    m += &format!(
        "\n\nA healthy machine shows evidence this strong for some fault with probability {:.1e} (the verdict names a fault at {} per recording or below, and only where its harmonics modulate the envelope like a defect's impacts).\n\n",
        d.p_healthy, d.false_alarm
    );
    m
}

/// The trained classifier's class, beside the training-free verdict.
fn trained_section(t: &super::TrainedClass) -> String {
    format!(
        "Trained classifier ({}, {} examples from {} labelled recordings, {}): **{}** (segments: {}) — learned from the user's labels, beside the training-free verdict above.\n\n",
        t.classifier,
        t.examples,
        t.recordings,
        t.file,
        t.class,
        t.segments.join(", ")
    )
}

/// The bearing guessed from the comb when none was given, and its interpretations.
fn bearing_guess_section(g: &diagnosis::BearingGuess) -> String {
    format!(
        "Bearing not given — **{}**. Comb found at {:.3} × fr ({:.2} Hz; p under healthy {:.1e} over {} independent orders {:.1}–{:.1} × fr, modulation depth {:.2}); {}. ± fr sidebands: p {:.1e}{}{}\n\n{}\n\n",
        g.note,
        g.fault_order,
        g.fault_hz,
        g.p_healthy,
        g.independent_orders,
        g.orders_searched[0],
        g.orders_searched[1],
        g.modulation_depth,
        g.basis,
        g.shaft_sidebands_p,
        g.cage_sidebands.map_or(String::new(), |[nu, p]| format!(
            "; best cage sidebands ± {nu:.3} × fr: p {p:.1e}"
        )),
        g.second_comb.map_or(String::new(), |[o, p]| format!(
            "; second comb {o:.3} × fr (p {p:.1e})"
        )),
        g.interpretations
            .iter()
            .map(|i| format!("- {i}"))
            .collect::<Vec<_>>()
            .join("\n")
    )
}

/// The facts of the run after the speed line: reference, operating point, fault frequencies,
/// samples, residual, its energy or kurtosis ratio, and the band.
fn facts_section(o: &Outcome) -> String {
    let d = &o.diagnosis;
    let op = &d.operating_point;
    let s = &d.statistics;
    let mut m = format!(
        "- reference: {} ({})\n- operating point: {:.1} rpm (fr = {:.3} Hz), fs = {} Hz, bearing {}{}\n\
         - fault frequencies (Hz): BPFO {:.2}, BPFI {:.2}, BSF (ball-defect rate, 2× spin) {:.2}, FTF {:.2}\n\
         - samples: {}; spectra are of the squared envelope, so line prominences are power ratios (dB) and do not depend on the unit\n\
         - residual: AR({}) prediction error; RMS {:.4e} {}; kurtosis {:.2} (signal {:.2})\n",
        match d.reference {
            diagnosis::Reference::Baseline => "baseline",
            diagnosis::Reference::SelfReference => "self",
        },
        o.baseline_note
            .as_deref()
            .unwrap_or("AR model fitted on the recording itself"),
        op.rpm_used,
        op.shaft_hz,
        op.fs_hz,
        if op.bearing_spec.is_empty() {
            &op.bearing
        } else {
            &op.bearing_spec
        },
        if op.rate_uncertainty > 0.0 {
            format!(
                " (a catalogue's typical geometry: fault-line windows widened by ± {:.0} %)",
                100.0 * op.rate_uncertainty
            )
        } else {
            String::new()
        },
        op.frequencies_hz.bpfo,
        op.frequencies_hz.bpfi,
        op.frequencies_hz.ball_defect,
        op.frequencies_hz.ftf,
        o.unit,
        d.whitening.order,
        s.residual_rms,
        o.unit.label(),
        s.residual_kurtosis,
        s.signal_kurtosis,
    );
    m += &match (s.energy_ratio_db, &d.reference) {
        (Some(db), _) => format!(
            "- against the baseline residual: energy {db:+.1} dB, kurtosis ×{:.2}\n",
            s.kurtosis_ratio
        ),
        _ => format!("- kurtosis / 3 (Gaussian): ×{:.2}\n", s.kurtosis_ratio),
    };
    m += &format!(
        "- band (Hz): {:.0}–{:.0}, {} (SK {:.2}); kurtogram band {:.0}–{:.0} (SK {:.2})\n\n",
        d.band.low_hz,
        d.band.high_hz,
        d.band.chosen_by,
        d.band.spectral_kurtosis,
        d.kurtogram_band.low_hz,
        d.kurtogram_band.high_hz,
        d.kurtogram_band.spectral_kurtosis
    );
    m
}

/// The evidence table: one row per line of every hypothesis (harmonics, then sidebands), the
/// hypothesis' columns on its first row only.
fn evidence_table(d: &diagnosis::Diagnosis) -> String {
    let mut m = "| hypothesis | p under healthy | modulation depth | reported | band (Hz) | line | expected (Hz) | found (Hz) | prominence (dB) | in baseline (dB) | evidence (dB) |\n|---|---:|---:|---|---|---|---:|---:|---:|---:|---:|\n".to_string();
    for e in &d.evidence {
        for (i, l) in e.harmonics.iter().chain(&e.sidebands).enumerate() {
            let head = if i == 0 {
                hypothesis_cells(e)
            } else {
                " | | | | ".to_string()
            };
            let base = l
                .baseline_prominence_db
                .map_or("—".to_string(), |b| format!("{b:.1}"));
            let found = if l.shaft_order.is_some() {
                "on a shaft order (masked)".to_string()
            } else {
                format!("{:.2}", l.found_hz)
            };
            m += &format!(
                "| {head} | {} | {:.2} | {found} | {:.1} | {base} | {:.1} |\n",
                l.label, l.expected_hz, l.prominence_db, l.evidence_db
            );
        }
    }
    m
}

/// A hypothesis' own cells of the evidence table: name, p under healthy, modulation depth,
/// whether it is reported (and why not), band.
fn hypothesis_cells(e: &diagnosis::HypothesisEvidence) -> String {
    let sig = e.significance.as_ref();
    let why = match sig {
        Some(g) if g.explained_by.is_some() => format!(
            "no, its lines belong to {}",
            g.explained_by.map_or("", |h| h.name())
        ),
        _ if e.detected => "**yes**".to_string(),
        _ => "no".to_string(),
    };
    format!(
        "{} | {} | {} | {why} | {:.0}–{:.0}",
        e.hypothesis.name(),
        sig.map_or("—".to_string(), |g| format!("{:.1e}", g.p_healthy)),
        sig.map_or("—".to_string(), |g| format!("{:.2}", g.modulation_depth)),
        e.band_hz[0],
        e.band_hz[1]
    )
}

/// The shaft harmonics of the band's envelope spectrum and their prominences.
fn shaft_harmonics_line(d: &diagnosis::Diagnosis) -> String {
    let mut m = "\nShaft harmonics in the band's envelope spectrum: ".to_string();
    m += &d
        .shaft_harmonics
        .iter()
        .map(|l| format!("{} {:.1} dB", l.label, l.prominence_db))
        .collect::<Vec<_>>()
        .join(", ");
    m += "\n";
    m
}

/// The speed as the report states it: declared, searched, found, how.
/// How the recording was order tracked (`--tach`).
fn tracking_line(t: &residual_features::OrderTracked) -> String {
    let source = match t.source {
        residual_features::order::AngleSource::Tachometer {
            pulses,
            pulses_per_rev,
        } => format!("the tachometer ({pulses} pulses, {pulses_per_rev} a turn)"),
        residual_features::order::AngleSource::ShaftComb {
            frames,
            frames_read,
            frame_s,
            phase_order,
        } => format!(
            "the recording's own shaft comb, read in {frames_read} of {frames} frames of {frame_s:.2} s{} (the speed changed through the recording; a tachometer, `--tach`, measures it better)",
            phase_order.map_or(String::new(), |k| format!(
                ", the angle then from the phase of its order {k}"
            ))
        ),
    };
    format!(
        "- order tracked from {source} over {:.1} turns: speed {:.1}–{:.1} rpm ({:.1} % apart), mean {:.1} rpm; resampled at {:.1} samples a turn (orders up to {:.1} kept: the band every turn holds) and diagnosed as a recording at the mean speed: every frequency below is an order × the mean shaft rate (equivalent rate {:.1} Hz)\n",
        t.turns,
        t.min_rpm,
        t.max_rpm,
        100.0 * (t.max_rpm / t.min_rpm - 1.0),
        t.mean_rpm,
        t.samples_per_rev,
        t.max_order,
        t.equivalent_fs_hz,
    )
}

fn speed_line(op: &diagnosis::OperatingPointUsed) -> String {
    let Some(f) = &op.speed else {
        return format!("- speed: {:.1} rpm\n", op.rpm_used);
    };
    let declared = f.declared_rpm.map_or("none declared".to_string(), |d| {
        format!("declared {d:.1} rpm")
    });
    let offset = f
        .offset_from_declared_percent
        .map_or(String::new(), |o| format!(" ({o:+.1} % from the declared)"));
    format!(
        "- speed: {declared}; searched {:.0}–{:.0} rpm; used {:.1} rpm ± {:.1}{offset}, from {}: {}\n",
        f.search_rpm[0],
        f.search_rpm[1],
        f.rpm_used,
        f.uncertainty_rpm,
        match f.source {
            diagnosis::SpeedSource::SpectrumComb => "the recording's shaft comb",
            diagnosis::SpeedSource::EnvelopeComb => "the shaft comb of the residual's envelope",
            diagnosis::SpeedSource::Declared => "the declared speed (no comb found)",
            diagnosis::SpeedSource::RangeCentre => "the middle of the range (no comb found)",
        },
        f.note
    )
}
