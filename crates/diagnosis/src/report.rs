//! The result of [`diagnose`](crate::diagnose) and its parts, as written into every report,
//! and the explanation of a verdict against a known label ([`Diagnosis::explain_against`]).

use serde::{Deserialize, Serialize};

use crate::{
    ArWhitener, EnvelopeSpectrum, HARMONICS, Hypothesis, HypothesisEvidence, LINE_THRESHOLD_DB,
    Reference, SLIP_MAX, SPEED_OFFSET, SPEED_TOL, SearchedLine, SpeedFinding, detect, speed,
};
use bearing_model::FaultOrders;

/// Per-hypothesis scores (dB; see [`HypothesisEvidence::score_db`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Inner race.
    pub inner: f64,
    /// Outer race.
    pub outer: f64,
    /// Ball.
    pub ball: f64,
}

impl Scores {
    /// The score of hypothesis `h`.
    pub fn of(&self, h: Hypothesis) -> f64 {
        match h {
            Hypothesis::Inner => self.inner,
            Hypothesis::Outer => self.outer,
            Hypothesis::Ball => self.ball,
        }
    }
}

/// The operating point the diagnosis used: a report of the sampling rate, the declared and the
/// used speed, the measured speed and the bearing (the declared input of a close-loop run is
/// `close_loop::OperatingPoint`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OperatingPointUsed {
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Declared shaft speed, rpm.
    pub rpm: f64,
    /// Shaft frequency fr the analysis used, Hz (`rpm_used` / 60).
    pub shaft_hz: f64,
    /// Shaft speed the analysis used, rpm: the declared one, or the measured one when the
    /// recording's shaft-harmonic comb stands out and differs from it by more than half of
    /// [`SPEED_TOL`] ([`speed`]).
    #[serde(default)]
    pub rpm_used: f64,
    /// The speed measured from the recording's shaft-harmonic comb (`None` when the recording
    /// is too short to resolve the search).
    #[serde(default)]
    pub measured_speed: Option<speed::SpeedEstimate>,
    /// When the recording's own comb is not clear: the speed read from the shaft comb of its
    /// residual's squared envelopes (`speed::estimate_envelope_speed`; absent when not looked
    /// for or not found). It is used like a clear comb: when it differs from the declared speed
    /// by more than half of [`SPEED_TOL`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub envelope_speed: Option<speed::SpeedEstimate>,
    /// Bearing name or normalised spec.
    pub bearing: String,
    /// The bearing spec as the user gave it, case kept (`BearingSpec::echo`): what reports echo
    /// (empty in a report written before it was kept).
    #[serde(default)]
    pub bearing_spec: String,
    /// Fault orders (× fr).
    pub orders: FaultOrders,
    /// Fault frequencies at fr, Hz.
    pub frequencies_hz: FaultOrders,
    /// How the speed used was found: declared, range searched, source, uncertainty.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<SpeedFinding>,
    /// Relative uncertainty of the bearing's fault rates every line window was widened by (a
    /// catalogue's typical geometry, `options::TYPICAL_GEOMETRY_UNCERTAINTY`; 0 for a maker's
    /// or a data set's own geometry).
    #[serde(default)]
    pub rate_uncertainty: f64,
}

/// A demodulation band.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BandChoice {
    /// Lower edge, Hz.
    pub low_hz: f64,
    /// Upper edge, Hz.
    pub high_hz: f64,
    /// Spectral kurtosis of the band's complex envelope.
    pub spectral_kurtosis: f64,
    /// Prominence a line needs in this band's envelope spectrum, dB (6 dB or the rank-CFAR level).
    pub line_threshold_db: f64,
    /// How it was chosen.
    pub chosen_by: String,
}

/// Energy and kurtosis of the residual against the reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Statistics {
    /// Residual samples analysed.
    pub residual_samples: usize,
    /// Residual RMS (units of the input).
    pub residual_rms: f64,
    /// Residual kurtosis (3 for Gaussian).
    pub residual_kurtosis: f64,
    /// Kurtosis of the input signal.
    pub signal_kurtosis: f64,
    /// Residual energy (mean square) / the baseline residual's; `null` when self-referenced.
    pub energy_ratio: Option<f64>,
    /// The same in dB.
    pub energy_ratio_db: Option<f64>,
    /// Residual kurtosis / the baseline residual's kurtosis, or / 3 (Gaussian) when self-referenced.
    pub kurtosis_ratio: f64,
    /// `"baseline residual"` or `"gaussian"`.
    pub kurtosis_reference: String,
    /// The energy and kurtosis ratios compare both residuals below this frequency, Hz: the band
    /// a decimated baseline holds ([`crate::Baseline::band_limit_hz`]); `null` when they
    /// compare the whole band (or when self-referenced).
    #[serde(default)]
    pub compared_below_hz: Option<f64>,
}

/// The fixed decision constants, written into every report. Keys of the line rule this
/// detector replaced (2026-12) are kept for scripts that read them, `null` where they no longer
/// apply.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Thresholds {
    /// A line is marked present at this prominence over the local median, dB ([`LINE_THRESHOLD_DB`]).
    pub line_db: f64,
    /// No longer used (the former rule's harmonics needed); `null`.
    pub min_harmonics: Option<usize>,
    /// [`HARMONICS`]: harmonics of each fault frequency in the template.
    pub harmonics_searched: usize,
    /// [`SLIP_MAX`].
    pub slip_max: f64,
    /// [`SPEED_OFFSET`].
    pub speed_offset: f64,
    /// [`SPEED_TOL`].
    pub speed_tolerance: f64,
    /// No longer used (impulsive-band gate of the former rule); `null`.
    pub sk_sigmas: Option<f64>,
    /// No longer used (rank CFAR of the former rule); `null`.
    pub cfar_quantile: Option<f64>,
    /// No longer used (second-band rule of the former rule); `null`.
    #[serde(default)]
    pub second_band_line_db: Option<f64>,
    /// False-alarm probability per recording, α.
    #[serde(default)]
    pub false_alarm: f64,
    /// Each hypothesis is significant at `α / 3`.
    #[serde(default)]
    pub per_hypothesis_level: f64,
    /// Plain-language rule.
    pub rule: String,
}

impl Thresholds {
    /// The constants at false-alarm probability `alpha`.
    pub fn with_false_alarm(alpha: f64) -> Self {
        let level = alpha / Hypothesis::ALL.len() as f64;
        Self {
            line_db: LINE_THRESHOLD_DB,
            min_harmonics: None,
            harmonics_searched: HARMONICS,
            slip_max: SLIP_MAX,
            speed_offset: SPEED_OFFSET,
            speed_tolerance: SPEED_TOL,
            sk_sigmas: None,
            cfar_quantile: None,
            second_band_line_db: None,
            false_alarm: alpha,
            per_hypothesis_level: level,
            rule: format!(
                "a fault is detected when its template (harmonics 1..{HARMONICS} of one fundamental in the slip window, plus half its distinguishing sidebands BPFI±fr / BSF±FTF, each line's prominence over the local median less the baseline's) reads so strong that a healthy machine would show it with probability <= {level:.2e} after the search over bands (alpha = {alpha} per recording over 3 hypotheses; the null is the same template read at fundamentals no bearing kinematics explains, shaft orders and mains multiples masked where the band shows their comb); a fault whose lines a stronger detected fault's family explains is dropped, and two that explain each other equally well give `uncertain`"
            ),
        }
    }
}

impl Default for Thresholds {
    fn default() -> Self {
        Self::with_false_alarm(detect::DEFAULT_FALSE_ALARM)
    }
}

/// A fault found in a band of its own, not in the common band (see [`diagnose`], step 3b).
///
/// [`diagnose`]: crate::diagnose
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SecondaryRead {
    /// The fault.
    pub hypothesis: Hypothesis,
    /// The band it was read in.
    pub band: BandChoice,
    /// Its evidence in that band.
    pub evidence: HypothesisEvidence,
    /// Squared envelope spectrum of that band (for figures; not serialised).
    #[serde(skip)]
    pub envelope: EnvelopeSpectrum,
}

pub(crate) fn band_choice(sp: &EnvelopeSpectrum, chosen_by: String) -> BandChoice {
    BandChoice {
        low_hz: sp.band_hz[0],
        high_hz: sp.band_hz[1],
        spectral_kurtosis: sp.spectral_kurtosis,
        line_threshold_db: sp.line_threshold_db,
        chosen_by,
    }
}

/// The result of [`diagnose`].
///
/// [`diagnose`]: crate::diagnose
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// `normal`, `inner`, `outer`, `ball`, or detected faults joined by `+` (in that order).
    pub verdict: String,
    /// Detected hypotheses.
    pub detected: Vec<Hypothesis>,
    /// Score per hypothesis, dB.
    pub scores: Scores,
    /// Baseline or self.
    pub reference: Reference,
    /// Speed, rate, bearing, fault frequencies.
    pub operating_point: OperatingPointUsed,
    /// The AR whitening model used.
    pub whitening: ArWhitener,
    /// The band all hypotheses were read in (see `chosen_by`).
    pub band: BandChoice,
    /// The band of maximal spectral kurtosis (fast-kurtogram choice), for reference.
    pub kurtogram_band: BandChoice,
    /// Evidence per hypothesis (inner, outer, ball).
    pub evidence: Vec<HypothesisEvidence>,
    /// Shaft harmonics 1..=3 in `band`'s envelope spectrum.
    pub shaft_harmonics: Vec<SearchedLine>,
    /// Energy and kurtosis against the reference.
    pub statistics: Statistics,
    /// The fixed decision constants.
    pub thresholds: Thresholds,
    /// Faults not detected in the common band but found in a band of their own (step 3b of
    /// [`diagnose`]); they are in `detected` and the verdict, and their scores and lines are
    /// here (`scores` and `evidence` are the common band's).
    ///
    /// [`diagnose`]: crate::diagnose
    #[serde(default)]
    pub secondary: Vec<SecondaryRead>,
    /// Squared envelope spectrum of `band` (for figures; not serialised).
    #[serde(skip)]
    pub envelope: EnvelopeSpectrum,
    /// With the verdict `uncertain`: the two faults that explain the same lines, strongest
    /// first (empty otherwise).
    #[serde(default)]
    pub candidates: Vec<Hypothesis>,
    /// The probability that a healthy machine gives evidence at least this strong for some
    /// fault: `3 × min_h p_healthy` (capped at 1); the recording is called faulty when it is at
    /// most `false_alarm`.
    #[serde(default = "one")]
    pub p_healthy: f64,
    /// The false-alarm probability per recording the verdict was taken at (α).
    #[serde(default)]
    pub false_alarm: f64,
    /// With an unknown bearing ([`crate::diagnose_unknown_bearing`]): the comb found, the fault
    /// named from it and on what basis — a guess, and the report says so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bearing_guess: Option<crate::BearingGuess>,
    /// A recording whose speed changed through it: how it was resampled at equal shaft angles
    /// before it was diagnosed (from its own shaft comb frame by frame, or from a tachometer the
    /// caller tracked it with); every frequency of the diagnosis is then an order × the mean
    /// shaft rate. Absent for a steady speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub order_tracking: Option<residual_features::OrderTracked>,
}

fn one() -> f64 {
    1.0
}

impl Diagnosis {
    /// Where a reported fault's lines were read off the speed used (a declared speed no comb
    /// confirmed, the templates searching its range): of `evidence`, the reported hypothesis
    /// (detected, or an `uncertain` candidate) with the smallest `p_healthy`, and the shaft speed
    /// (rpm) its lines imply: the speed used times its [`crate::Significance::speed_ratio`] (a
    /// step of the searched grid) times its fundamental found over the one expected there
    /// (`fault_hz`, at that ratio; the fault's slip, 1–2 % for a bearing, included). `None`
    /// when that hypothesis was read at the speed used, or none is reported.
    pub fn fault_read_at_rpm(&self, evidence: &[HypothesisEvidence]) -> Option<(Hypothesis, f64)> {
        let rpm = self.operating_point.rpm_used;
        evidence
            .iter()
            .filter(|e| e.detected || self.candidates.contains(&e.hypothesis))
            .filter_map(|e| e.significance.as_ref().map(|s| (e, s)))
            .min_by(|a, b| a.1.p_healthy.total_cmp(&b.1.p_healthy))
            .filter(|(_, s)| (s.speed_ratio - 1.0).abs() > 1e-9)
            .map(|(e, s)| {
                let ratio = if s.fundamental_hz > 0.0 && e.fault_hz > 0.0 {
                    s.speed_ratio * s.fundamental_hz / e.fault_hz
                } else {
                    s.speed_ratio
                };
                (e.hypothesis, rpm * ratio)
            })
    }

    /// Why the verdict differs from a known `label` (`normal`, `inner`, `outer`, `ball`), from
    /// the evidence: the labelled fault's probability under healthy against `α/3`, its
    /// modulation depth against the depth a defect needs, and its lines (evidence in dB); and
    /// every other fault reported or candidate. Empty when they agree.
    pub fn explain_against(&self, label: &str) -> String {
        use std::fmt::Write as _;
        let level = self.false_alarm / 3.0;
        let describe = |h: &str| {
            self.evidence
                .iter()
                .find(|e| e.hypothesis.name() == h)
                .map_or(String::new(), |e| {
                    let lines = e
                        .harmonics
                        .iter()
                        .chain(&e.sidebands)
                        .map(|l| format!("{} {:.1}", l.label, l.evidence_db))
                        .collect::<Vec<_>>()
                        .join(", ");
                    match &e.significance {
                        Some(s) => format!(
                            "p {:.1e} (level {level:.1e}), depth {:.2} (needs {}){}; lines {lines}",
                            s.p_healthy,
                            s.modulation_depth,
                            crate::detect::MIN_MODULATION_DEPTH,
                            s.explained_by
                                .map_or(String::new(), |b| format!(", explained by {}", b.name()))
                        ),
                        None => format!("lines {lines}"),
                    }
                })
        };
        let mut s = String::new();
        if label != "normal" && !self.detected.iter().any(|h| h.name() == label) {
            let _ = write!(s, "{label} not reported: {}", describe(label));
        }
        for h in self.detected.iter().chain(&self.candidates) {
            if h.name() != label {
                if !s.is_empty() {
                    s += "; ";
                }
                let _ = write!(
                    s,
                    "{} {}: {}",
                    h.name(),
                    if self.detected.contains(h) {
                        "reported"
                    } else {
                        "a candidate"
                    },
                    describe(h.name())
                );
            }
        }
        s
    }
}
