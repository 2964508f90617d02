//! The optional trained classifier (`train-classifier`'s JSON) applied beside the
//! training-free verdict.

use std::path::Path;

use anyhow::Context as _;

use super::{BaselineSource, Loaded, Outcome, Plan, decimated_to};

/// What an optional trained classifier says about a recording.
#[derive(Debug, Clone)]
pub struct TrainedClass {
    /// Its class (the majority over the segments).
    pub class: String,
    /// The class of each segment.
    pub segments: Vec<String>,
    /// The classifier's name.
    pub classifier: String,
    /// Examples and recordings it was trained on.
    pub examples: usize,
    /// Distinct recordings among them.
    pub recordings: usize,
    /// Where it was read from.
    pub file: String,
}

/// Read a trained classifier saved by `train-classifier`.
///
/// # Errors
/// Unreadable file, or the library's format error.
pub fn load_classifier(path: &Path) -> anyhow::Result<diagnosis::TrainedDiagnoser> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("classifier {}", path.display()))?;
    diagnosis::TrainedDiagnoser::from_json(&text)
        .with_context(|| format!("classifier {}", path.display()))
}

/// Apply a trained classifier to a recording the way it was trained: its segments diagnosed
/// against the same reference, classified, and the majority class kept.
///
/// # Errors
/// Missing speed, the library's errors (another reference than the training diagnoses).
pub fn apply_classifier(
    o: &mut Outcome,
    t: &diagnosis::TrainedDiagnoser,
    file: &Path,
    l: &Loaded,
    plan: &Plan,
    baseline: Option<&BaselineSource>,
) -> anyhow::Result<()> {
    let rpm = plan
        .rpm
        .or(l.rpm)
        .context("--rpm is required (the file stores no speed)")?;
    // at the classifier's rate (decimated when the recording's is an integer multiple of it)
    let (x, fs) = match decimated_to(&l.samples, l.fs_hz, t.fs_hz)? {
        Some((x, _)) => (x, t.fs_hz),
        None => (l.samples.clone(), l.fs_hz),
    };
    let b = baseline.map(|src| src.at(fs, rpm)).transpose()?;
    let signal = diagnosis::Signal::new(x, fs).map_err(diagnosis::DiagnosisError::from)?;
    let (class, segments) =
        t.classify_recording(&signal, rpm, &plan.bearing, b.as_ref().map(|b| &b.0))?;
    o.trained = Some(TrainedClass {
        class,
        segments,
        classifier: t.classifier.clone(),
        examples: t.examples,
        recordings: t.recordings,
        file: file.display().to_string(),
    });
    Ok(())
}
