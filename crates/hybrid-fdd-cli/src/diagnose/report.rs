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

/// The Markdown report.
pub fn markdown(o: &Outcome, title: &str) -> String {
    let d = &o.diagnosis;
    let op = &d.operating_point;
    let s = &d.statistics;
    let mut m = format!("# Diagnosis of {title}\n\n**Verdict: {}**\n\n", d.verdict);
    if let Some(t) = &o.trained {
        m += &format!(
            "Trained classifier ({}, {} examples from {} labelled recordings, {}): **{}** (segments: {}) — learned from the user's labels, beside the training-free verdict above.\n\n",
            t.classifier,
            t.examples,
            t.recordings,
            t.file,
            t.class,
            t.segments.join(", ")
        );
    }
    let envelope = op.envelope_speed.map_or(String::new(), |es| {
        let band = es
            .envelope_band_hz
            .map_or(String::new(), |[lo, hi]| format!(" in {lo:.0}–{hi:.0} Hz"));
        format!(
            "; the shaft comb of the residual's squared envelope{band} says {:.1} rpm (score {:.1}, contrast {:.1}, refined from its lines)",
            es.rpm, es.comb_score, es.contrast
        )
    });
    m += &match op.measured_speed {
        Some(ms) => format!(
            "- speed: declared {:.1} rpm; the recording's shaft-harmonic comb (orders 1–{}) says {:.1} rpm (score {:.1}, contrast {:.1}: {}){envelope}; analysed at {:.1} rpm\n",
            op.rpm,
            ms.orders,
            ms.rpm,
            ms.comb_score,
            ms.contrast,
            if ms.accepted {
                "clear"
            } else {
                "not clear enough to use"
            },
            op.rpm_used
        ),
        None => format!(
            "- speed: declared {:.1} rpm (the recording is too short to measure it from its shaft-harmonic comb)\n",
            op.rpm
        ),
    };
    m += &format!(
        "- reference: {} ({})\n- operating point: {:.1} rpm (fr = {:.3} Hz), fs = {} Hz, bearing {}\n\
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
        "- band (Hz): {:.0}–{:.0}, {} (SK {:.2}, line threshold {:.1} dB); kurtogram band {:.0}–{:.0} (SK {:.2})\n\n",
        d.band.low_hz,
        d.band.high_hz,
        d.band.chosen_by,
        d.band.spectral_kurtosis,
        d.band.line_threshold_db,
        d.kurtogram_band.low_hz,
        d.kurtogram_band.high_hz,
        d.kurtogram_band.spectral_kurtosis
    );
    for r in &d.secondary {
        m += &format!(
            "- {} found in a band of its own (Hz): {:.0}–{:.0} (SK {:.2}, line threshold {:.1} dB, score {:.1} dB): {}\n",
            r.hypothesis.name(),
            r.band.low_hz,
            r.band.high_hz,
            r.band.spectral_kurtosis,
            r.band.line_threshold_db,
            r.evidence.score_db,
            r.band.chosen_by
        );
    }
    if !d.secondary.is_empty() {
        m += "\n";
    }
    m += &format!("Rule: {}.\n\n", d.thresholds.rule);
    m += "| hypothesis | score (dB) | detected | band (Hz) | line | expected (Hz) | found (Hz) | prominence (dB) | in baseline (dB) | evidence (dB) | counts |\n|---|---:|---|---|---|---:|---:|---:|---:|---:|---|\n";
    let own_band = d.secondary.iter().map(|r| (&r.evidence, " (own band)"));
    for (e, tag) in d.evidence.iter().map(|e| (e, "")).chain(own_band) {
        for (i, l) in e.harmonics.iter().chain(&e.sidebands).enumerate() {
            let head = if i == 0 {
                format!(
                    "{}{tag} | {:.1} | {} | {:.0}–{:.0}",
                    e.hypothesis.name(),
                    e.score_db,
                    if e.detected { "**yes**" } else { "no" },
                    e.band_hz[0],
                    e.band_hz[1]
                )
            } else {
                " | | | ".to_string()
            };
            let counts = match (l.present, l.explained_by, l.consistent) {
                (true, None, true) => "yes".to_string(),
                (true, Some(h), _) => format!("no, explained by {}", h.name()),
                (true, None, false) => "no, off the common fundamental".to_string(),
                _ => "no".to_string(),
            };
            let base = l
                .baseline_prominence_db
                .map_or("—".to_string(), |b| format!("{b:.1}"));
            m += &format!(
                "| {head} | {} | {:.2} | {:.2} | {:.1} | {base} | {:.1} | {counts} |\n",
                l.label, l.expected_hz, l.found_hz, l.prominence_db, l.evidence_db
            );
        }
    }
    m += "\nShaft harmonics in the band's envelope spectrum: ";
    m += &d
        .shaft_harmonics
        .iter()
        .map(|l| format!("{} {:.1} dB", l.label, l.prominence_db))
        .collect::<Vec<_>>()
        .join(", ");
    m += "\n";
    m
}
