//! An optional trained classifier on top of the training-free diagnosis, for users who have
//! labelled recordings of their machine.
//!
//! The training-free verdict ([`crate::diagnose`]) decides with fixed rules. A user with labelled
//! recordings can instead learn the decision from the same evidence: every [`Diagnosis`] gives a
//! fixed vector of [`EVIDENCE_FEATURES`] (the three hypothesis scores, their counting harmonics and
//! sidebands, the residual's kurtosis and energy against the reference, the chosen band's spectral
//! kurtosis and position), and [`TrainedDiagnoser`] fits one of `classify`'s classifiers (Gini
//! tree by default: it reads as rules and is indifferent to the features' scales) to labelled
//! examples, saves as JSON and classifies new diagnoses of the same reference kind. Cutting each
//! recording into a few [`segments`] gives more examples per recording; evaluate with `classify`'s
//! grouped protocols (no recording on both sides), never a random split of segments.

use serde::{Deserialize, Serialize};

use crate::{
    Baseline, BearingSpec, Diagnosis, DiagnosisError, Hypothesis, MIN_TURNS, Reference, Result,
    Signal, diagnose,
};
use classify::{ClassifierSpec, Dataset, RecordingInfo, TrainedClassifier};

/// Names of [`Diagnosis::evidence_features`], in order.
pub const EVIDENCE_FEATURES: [&str; 12] = [
    "score_inner_db",
    "score_outer_db",
    "score_ball_db",
    "harmonics_inner",
    "harmonics_outer",
    "harmonics_ball",
    "sidebands_inner",
    "sidebands_ball",
    "log10_kurtosis_ratio",
    "energy_ratio_db",
    "log10_band_spectral_kurtosis",
    "band_centre_over_nyquist",
];

/// The `format` field of a saved [`TrainedDiagnoser`].
pub const FORMAT: &str = "hybrid-fdd trained diagnoser";
/// The `version` this code writes and reads.
pub const VERSION: u32 = 1;

impl Diagnosis {
    /// The evidence as a fixed feature vector ([`EVIDENCE_FEATURES`]); every entry finite
    /// (`energy_ratio_db` is 0 when self-referenced, the spectral kurtosis is floored at 10⁻³).
    pub fn evidence_features(&self) -> Vec<f64> {
        let ev = |h: Hypothesis| self.evidence.iter().find(|e| e.hypothesis == h);
        let harm = |h| ev(h).map_or(0.0, |e| e.harmonics_present as f64);
        let side = |h| ev(h).map_or(0.0, |e| e.sidebands_present as f64);
        let s = &self.statistics;
        let nyq = 0.5 * self.operating_point.fs_hz;
        let v = vec![
            self.scores.inner,
            self.scores.outer,
            self.scores.ball,
            harm(Hypothesis::Inner),
            harm(Hypothesis::Outer),
            harm(Hypothesis::Ball),
            side(Hypothesis::Inner),
            side(Hypothesis::Ball),
            s.kurtosis_ratio.max(1e-6).log10(),
            s.energy_ratio_db.unwrap_or(0.0),
            self.band.spectral_kurtosis.max(1e-3).log10(),
            0.5 * (self.band.low_hz + self.band.high_hz) / nyq,
        ];
        v.into_iter()
            .map(|x| if x.is_finite() { x } else { 0.0 })
            .collect()
    }
}

/// Consecutive pieces of `seconds` each (the last partial one dropped), every piece at least
/// [`MIN_TURNS`] shaft turns long at the slowest speed a diagnosis searches around `rpm` (and
/// the longest whitening filter's start-up); the whole recording when it holds less than two
/// pieces. Each piece borrows the recording's samples.
pub fn segments<'s>(signal: &'s Signal<'_>, rpm: f64, seconds: f64) -> Vec<Signal<'s>> {
    let fs_hz = signal.fs_hz();
    let slowest = rpm * (1.0 - crate::options::DEFAULT_SPEED_SEARCH);
    let len = (seconds * fs_hz).round() as usize;
    let turns = len.saturating_sub(crate::whiten::ORDERS[crate::whiten::ORDERS.len() - 1]) as f64
        / fs_hz
        * slowest
        / 60.0;
    if !(turns >= MIN_TURNS && len > 0) || signal.len() < 2 * len {
        return vec![signal.borrowed()];
    }
    signal.chunks_exact(len).collect()
}

/// One labelled example: a diagnosis's evidence and what the recording is known to be.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Labelled {
    /// [`Diagnosis::evidence_features`].
    pub features: Vec<f64>,
    /// The known class, e.g. `normal`, `inner`, `outer`, `ball`.
    pub label: String,
    /// The recording the example comes from (examples of one recording are never split
    /// between training and test by the grouped protocols).
    pub recording: String,
    /// Motor load in hp (0 when unknown).
    pub load_hp: u32,
    /// Fault size in mils, `None` for a healthy recording or when unknown.
    pub fault_size_mils: Option<u32>,
    /// Shaft speed in rpm, when known.
    pub speed_rpm: Option<u32>,
}

/// `classify`'s dataset of labelled examples (classes sorted by name, features
/// [`EVIDENCE_FEATURES`], one "window" per example in recording order).
///
/// # Errors
/// [`DiagnosisError::Classifier`]: no examples, a feature vector of the wrong length or with a
/// non-finite entry.
pub fn labelled_dataset(examples: &[Labelled]) -> Result<Dataset> {
    let mut classes: Vec<String> = examples.iter().map(|e| e.label.clone()).collect();
    classes.sort();
    classes.dedup();
    let features: Vec<String> = EVIDENCE_FEATURES.iter().map(|s| s.to_string()).collect();
    let mut b = Dataset::builder(classes.clone(), features);
    for e in examples {
        let class = classes.iter().position(|c| *c == e.label).unwrap_or(0);
        let info = RecordingInfo {
            class,
            recording: e.recording.clone(),
            load_hp: e.load_hp,
            fault_size_mils: e.fault_size_mils,
            speed_rpm: e.speed_rpm,
        };
        b.add_recording(&info, vec![e.features.clone()]);
    }
    Ok(b.build()?)
}

/// A classifier trained on labelled diagnoses, saved and reloaded as JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainedDiagnoser {
    /// [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The reference of the diagnoses it was trained on; it classifies only such diagnoses.
    pub reference: Reference,
    /// Class names (the labels seen in training, sorted).
    pub classes: Vec<String>,
    /// [`EVIDENCE_FEATURES`] at training time.
    pub features: Vec<String>,
    /// Examples and distinct recordings it was trained on.
    pub examples: usize,
    /// Distinct recordings among them.
    pub recordings: usize,
    /// The classifier's name.
    pub classifier: String,
    /// Sampling rate of the training recordings, Hz; it classifies only diagnoses at this rate
    /// (the evidence — band positions, resolutions — depends on it).
    pub fs_hz: f64,
    /// Length of the segments the examples were diagnosed on, s; a recording is classified the
    /// same way ([`TrainedDiagnoser::classify_recording`]).
    pub segment_seconds: f64,
    /// The trained model.
    pub model: TrainedClassifier,
}

impl TrainedDiagnoser {
    /// Train `spec` on every example (all diagnosed with `reference`, at `fs_hz`, on segments
    /// of `segment_seconds`).
    ///
    /// # Errors
    /// As [`labelled_dataset`], the classifier's training errors (e.g. a single class), and
    /// [`DiagnosisError::ClassifierFormat`] for a rate or segment length that is not > 0.
    pub fn train(
        examples: &[Labelled],
        reference: Reference,
        fs_hz: f64,
        segment_seconds: f64,
        spec: &ClassifierSpec,
    ) -> Result<Self> {
        for (what, v) in [
            ("sampling rate (Hz)", fs_hz),
            ("segment length (s)", segment_seconds),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(DiagnosisError::ClassifierFormat {
                    reason: format!("{what} {v} must be > 0"),
                });
            }
        }
        let data = labelled_dataset(examples)?;
        let all: Vec<usize> = (0..data.n_samples()).collect();
        let model = spec.fit(&data, &all)?;
        let mut recs: Vec<&str> = examples.iter().map(|e| e.recording.as_str()).collect();
        recs.sort_unstable();
        recs.dedup();
        Ok(Self {
            format: FORMAT.into(),
            version: VERSION,
            reference,
            classes: data.class_names().to_vec(),
            features: data.feature_names().to_vec(),
            examples: examples.len(),
            recordings: recs.len(),
            classifier: spec.name().into(),
            fs_hz,
            segment_seconds,
            model,
        })
    }

    /// Classify a whole recording as the examples were made: cut into segments of
    /// `segment_seconds` ([`segments`]), each diagnosed (against `baseline` when given) and
    /// classified; the class most segments get wins (ties: the class named first). Returns the
    /// class and the per-segment classes.
    ///
    /// # Errors
    /// The diagnosis's errors on a segment, and as [`TrainedDiagnoser::classify`].
    pub fn classify_recording(
        &self,
        signal: &Signal<'_>,
        rpm: f64,
        bearing: &BearingSpec,
        baseline: Option<&Baseline>,
    ) -> Result<(String, Vec<String>)> {
        let per: Vec<String> = segments(signal, rpm, self.segment_seconds)
            .into_iter()
            .map(|seg| self.classify(&diagnose(&seg, rpm, bearing, baseline)?))
            .collect::<Result<_>>()?;
        let best = self
            .classes
            .iter()
            .max_by_key(|c| {
                let n = per.iter().filter(|p| p == c).count();
                // more votes wins; among equals the class named first
                (
                    n,
                    std::cmp::Reverse(self.classes.iter().position(|x| x == *c)),
                )
            })
            .cloned()
            .unwrap_or_default();
        Ok((best, per))
    }

    /// The class of a diagnosis.
    ///
    /// # Errors
    /// [`DiagnosisError::ClassifierRate`] for a diagnosis at another sampling rate,
    /// [`DiagnosisError::ReferenceMismatch`] when `d` was diagnosed with another reference than
    /// the training examples; the classifier's errors.
    pub fn classify(&self, d: &Diagnosis) -> Result<String> {
        let fs = d.operating_point.fs_hz;
        if (fs - self.fs_hz).abs() > 1e-9 * self.fs_hz {
            return Err(DiagnosisError::ClassifierRate {
                recording_hz: fs,
                trained_hz: self.fs_hz,
            });
        }
        if d.reference != self.reference {
            let name = |r: Reference| match r {
                Reference::Baseline => "baseline".to_string(),
                Reference::SelfReference => "self".to_string(),
            };
            return Err(DiagnosisError::ReferenceMismatch {
                trained: name(self.reference),
                got: name(d.reference),
            });
        }
        let k = self.model.predict_row(&d.evidence_features())?;
        self.classes
            .get(k)
            .cloned()
            .ok_or_else(|| DiagnosisError::ClassifierFormat {
                reason: format!("class index {k} beyond the {} classes", self.classes.len()),
            })
    }

    /// Read a saved classifier, checking its format, version and features.
    ///
    /// # Errors
    /// [`DiagnosisError::ClassifierFormat`] naming what is wrong.
    pub fn from_json(text: &str) -> Result<Self> {
        let bad = |reason: String| DiagnosisError::ClassifierFormat { reason };
        let t: Self = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        if t.format != FORMAT {
            return Err(bad(format!("format {:?}, expected {FORMAT:?}", t.format)));
        }
        if t.version != VERSION {
            return Err(bad(format!(
                "version {}, this build reads {VERSION}",
                t.version
            )));
        }
        if t.features.iter().map(String::as_str).ne(EVIDENCE_FEATURES) {
            return Err(bad(format!(
                "features {:?} differ from this build's {:?}",
                t.features, EVIDENCE_FEATURES
            )));
        }
        if t.classes.is_empty() {
            return Err(bad("no classes".into()));
        }
        for (what, v) in [("segment_seconds", t.segment_seconds), ("fs_hz", t.fs_hz)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(format!("{what} {v} must be > 0")));
            }
        }
        Ok(t)
    }

    /// As JSON (pretty-printed).
    ///
    /// # Errors
    /// [`DiagnosisError::ClassifierFormat`] if serialisation fails.
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(self).map_err(|e| DiagnosisError::ClassifierFormat {
            reason: e.to_string(),
        })
    }
}
