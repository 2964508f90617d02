//! Training-free, model-based diagnosis of one bearing recording.
//!
//! Given a vibration signal, its sampling rate, the shaft speed, the bearing (its fault orders
//! from `bearing-model`) and optionally a healthy baseline of the same machine, [`diagnose`]
//! returns a [`Diagnosis`]: `normal`, `inner`, `outer`, `ball` or a `+`-joined combination, with
//! every number that led to it. No training and no labels: the decision rests on fixed thresholds
//! with a stated physical meaning.
//!
//! # Method
//!
//! 0. **Speed** ([`speed`]): the recording's shaft-harmonic comb (orders 1–10 within ± 5 % of the
//!    declared speed) measures the speed; a clear, complete comb (first order and ≥ 80 % of the
//!    orders present, mains multiples not scored) replaces a declared speed more than ½
//!    [`SPEED_TOL`] off (`OperatingPoint::rpm_used`).
//! 1. **Residual** ([`whiten`]): an AR linear predictor fitted by least squares on the baseline
//!    (order by held-out prediction error) is applied as a prediction-error filter to the
//!    recording: the residual of the healthy model, which pre-whitens the structural path and
//!    removes the shaft and mains lines the baseline holds. Without a baseline the AR model is
//!    fitted on the recording itself (AR pre-whitening, Sawalhi & Randall 2007) and the report
//!    says `"reference": "self"`.
//! 2. **Bands**: a filter bank of the fast kurtogram's shape (widths `fs/2 / d`,
//!    `d ∈ {2, 3, 4, 6, 8, 12, 16, 24, 32}`, half-overlapping; only bands wide enough to hold
//!    three harmonics of the highest fault line and starting above them) gives each band's complex envelope `z` from one
//!    FFT (`residual_features::SpectralEngine::band_squared_envelopes`), its spectral kurtosis
//!    `⟨|z|⁴⟩/⟨|z|²⟩² − 2` (Antoni, MSSP 20, 2006; Antoni & Randall 2006) and its squared
//!    envelope spectrum (Welch average of `|z|²`; Randall & Antoni, MSSP 25, 2011).
//! 3. **Evidence** ([`evidence`]): for each hypothesis (BPFO, BPFI, ball-defect rate = CWRU's
//!    BSF, twice the ball spin) the largest line in a slip-tolerant window around harmonics 1..3,
//!    its prominence over the local median (dB), and the sidebands that tell faults apart (BPFI ±
//!    fr, BSF ± FTF). Only impulsive bands are eligible (spectral kurtosis above a Gaussian's by
//!    [`SK_SIGMAS`] standard deviations; with none, a band whose envelope holds [`MIN_LINES`]
//!    fault harmonics ≥ [`PERIODIC_LINE_DB`]); all hypotheses are read in the one such band where
//!    the best of them scores highest (an envelope-based band choice, as in the IESFOgram of
//!    Mauricio et al., MSSP 2020 — the same search for every hypothesis, so no label enters).
//!    A harmonic counts only at h × the fundamental its strongest harmonic implies (one impact
//!    train, one fault frequency), and lines of a weaker hypothesis that a stronger detected
//!    one's family explains (e.g. BPFO + fr near BSF) do not count for it — its window is then
//!    read again past them ([`Line::passed_over`]) — nor do harmonics found
//!    on an integer shaft order their kinematic rate is not on ([`Line::shaft_order`]).
//!    A fault not detected in that common band is read in each other impulsive band: where it
//!    is the strongest signature and has [`MIN_LINES`] harmonics at ≥ [`SECOND_BAND_LINE_DB`]
//!    that no common-band fault present in that band explains, it is added
//!    ([`Diagnosis::secondary`]) — a second fault ringing another resonance, or masked in the
//!    first's band.
//! 4. **Verdict**: a hypothesis is detected when at least [`MIN_LINES`] harmonics stand
//!    [`LINE_THRESHOLD_DB`] above the local median, or harmonic 1 does together with one of its
//!    sidebands. See `docs/equations/diagnosis.md` for the formulas and the reasoning behind the
//!    constants (chosen on simulated recordings and noise statistics, never on CWRU labels).
//!    Against a baseline recording, a line the healthy machine already holds counts only by what
//!    it has grown ([`Line::evidence_db`]).
//! 5. **Optional, with labels** ([`trained`]): a classifier trained on the evidence of labelled
//!    recordings' segments, beside the training-free verdict.
//!
//! # Dependencies and why
//! - `bearing-model`: the bearing's kinematics (`BearingSpec`, `FaultOrders`), one type for it.
//! - `laguerre-id`: the AR least squares of the whitening filter.
//! - `residual-features`: the FFT, band envelopes and Welch spectra.
//! - `classify`: the optional trained classifier (its Gini tree and linear SVM, and `Dataset`).
//! - `serde` / `serde_json`: reports and the trained classifier's file; `thiserror`: the one
//!   error enum.
//!
//! # Example
//! ```
//! use bearing_model::{FaultClass, Noise, Scenario};
//! use diagnosis::{Baseline, BearingSpec, diagnose};
//! let rpm = 1797.0;
//! let healthy = Scenario::cwru(FaultClass::None, 0.014, rpm)?
//!     .with_noise(Noise::SnrDb(20.0)).with_duration(1.0).with_seed(1).simulate()?;
//! let faulty = Scenario::cwru(FaultClass::Outer, 0.014, rpm)?
//!     .with_noise(Noise::SnrDb(20.0)).with_duration(1.0).with_seed(2).simulate()?;
//! let baseline = Baseline::prepare(&healthy.accel, healthy.fs_hz)?;
//! let d = diagnose(&faulty.accel, faulty.fs_hz, rpm, &BearingSpec::parse("6205")?, Some(&baseline))?;
//! assert_eq!(d.verdict, "outer");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod error;
pub mod evidence;
pub use residual_features::speed;
pub mod trained;
pub mod whiten;

use residual_features::{Band, SpectralEngine, WelchConfig};
use serde::{Deserialize, Serialize};

pub use bearing_model::BearingSpec;
pub use error::{DiagnosisError, Result};
pub use evidence::{EnvelopeSpectrum, HypothesisEvidence, Line, PassedOver};
pub use trained::{EVIDENCE_FEATURES, Labelled, TrainedDiagnoser};
pub use whiten::{ArWhitener, OrderScore};

use bearing_model::FaultOrders;

/// Slowest accepted shaft speed, rpm.
pub const MIN_RPM: f64 = 30.0;
/// Fastest accepted shaft speed, rpm.
pub const MAX_RPM: f64 = 30_000.0;
/// Lowest accepted sampling rate, Hz.
pub const MIN_FS_HZ: f64 = 1_000.0;
/// Highest accepted sampling rate, Hz.
pub const MAX_FS_HZ: f64 = 1.0e6;
/// Shortest accepted recording, in shaft turns: the envelope spectrum needs at least this many
/// turns to resolve the ± FTF sidebands of a ball fault (FTF ≈ 0.4 fr) in a few bins.
pub const MIN_TURNS: f64 = 10.0;
/// A line is present when its power in the squared envelope spectrum is at least this many dB
/// over the local median (6 dB = 4× the median power). In a Welch average of `K` segments a noise
/// bin exceeds 4× its median with probability below 1e-3 for K ≥ 8 (chi-square with ~2K degrees
/// of freedom), so requiring two such lines at harmonic positions makes a false detection in noise
/// rare even after the search over bands.
pub const LINE_THRESHOLD_DB: f64 = 6.0;
/// Harmonics (of 1..=[`HARMONICS`]) that must be present for a detection.
pub const MIN_LINES: usize = 2;
/// Without an impulsive band, a band is still read when one hypothesis has [`MIN_LINES`] of its
/// harmonics present at ≥ this evidence, dB (see `diagnose_with`, step 3).
pub const PERIODIC_LINE_DB: f64 = 10.0;
/// A fault not detected in the common band is added from a band of its own only when
/// [`MIN_LINES`] of its harmonics stand at ≥ this evidence, dB, there (10 dB = 10× the local
/// median): the search over the other bands is a second multiple comparison, so the single-band
/// rule's 6 dB is raised to the level of [`PERIODIC_LINE_DB`].
pub const SECOND_BAND_LINE_DB: f64 = 10.0;
/// Harmonics of each fault frequency searched.
pub const HARMONICS: usize = 3;
/// Largest rolling-element slip allowed for (1–2 % is usual).
pub const SLIP_MAX: f64 = 0.02;
/// Allowance above the kinematic rate: CWRU's outer-race lines sit ~0.33 % above the 6205's BPFO
/// at the logged speed. The closed loop reads the shaft at the logged speed on those records, so
/// the offset is the bearing's effective contact angle (a `defect_rate` effect, 7–14°), not the
/// speed; a rig-specific allowance, kept because the physical one (an angle up to 15°, lowering
/// BPFI too) cost verdicts (`docs/equations/diagnosis.md`, "Speed").
pub const SPEED_OFFSET: f64 = 0.0033;
/// Tolerance on the declared speed itself (± 0.3 %; a speed further off is measured from the
/// recording when it can be, see [`speed`]).
pub const SPEED_TOL: f64 = residual_features::speed::SPEED_TOL;
/// Local median of the envelope spectrum taken over ± this many shaft orders around a line.
pub const BACKGROUND_HALF_WIDTH_ORDERS: f64 = 2.0;
/// Welch segments of the squared envelope span at most this many shaft turns (resolution fr/32).
pub const SEGMENT_TURNS_MAX: f64 = 32.0;
/// … and at least this many (resolution fr/8), or the whole record when shorter.
pub const SEGMENT_TURNS_MIN: f64 = 8.0;
/// A band is impulsive (eligible for envelope analysis) when its spectral kurtosis exceeds a
/// Gaussian's (0) by this many standard deviations of the estimator, `σ = 2/√(B·T)` for a band of
/// width `B` over `T` seconds (delta method on `⟨|z|⁴⟩/⟨|z|²⟩²` with `B·T` independent samples).
pub const SK_SIGMAS: f64 = 5.0;

/// The spectral-kurtosis threshold of a band `width_hz` wide over `duration_s` seconds.
pub fn sk_threshold(width_hz: f64, duration_s: f64) -> f64 {
    SK_SIGMAS * 2.0 / (width_hz * duration_s).max(1.0).sqrt()
}

/// Rank CFAR: a line's prominence must also reach this quantile of the prominences of the local
/// maxima of the same envelope spectrum (up to [`analysis_top_hz`]) that no bearing kinematics
/// explains: in a spectrum of noise the quantile sits below [`LINE_THRESHOLD_DB`] and changes
/// nothing; in a spectrum crowded with unexplained lines (mains, interference, beats) a
/// candidate must be stronger than nine in ten of them.
pub const CFAR_QUANTILE: f64 = 0.9;

/// Highest envelope frequency examined: 3.4 × the highest fault line + fr.
pub fn analysis_top_hz(orders: &FaultOrders, fr: f64) -> f64 {
    (3.4 * orders.bpfo.max(orders.bpfi).max(orders.ball_defect) + 1.0) * fr
}

/// Band widths `fs/2 / d` of the filter bank.
pub const BAND_DIVISORS: [f64; 9] = [2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0];

/// A fault hypothesis: a fault location, `bearing-model`'s [`bearing_model::FaultLocation`]
/// (the workspace's one fault-location type; serialised `inner`, `outer`, `ball`).
pub use bearing_model::FaultLocation as Hypothesis;

/// What the residual's model was fitted on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Reference {
    /// A healthy baseline of the same machine.
    Baseline,
    /// The recording itself (AR pre-whitening).
    #[serde(rename = "self")]
    SelfReference,
}

/// A prepared healthy baseline: its AR whitening model and its residual statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Baseline {
    /// The AR prediction-error filter fitted on the baseline.
    pub whitener: ArWhitener,
    /// RMS of the baseline's own residual.
    pub residual_rms: f64,
    /// Kurtosis (not excess) of the baseline's own residual.
    pub residual_kurtosis: f64,
    /// Samples in the baseline.
    pub samples: usize,
    /// The baseline's own residual, kept to read the healthy machine's envelope lines in the
    /// same bands as the recording's (a line the baseline already holds is not fault
    /// evidence, see `Line::evidence_db`). `None` for a baseline from a model
    /// ([`Baseline::from_whitener`]); not serialised.
    #[serde(skip)]
    pub residual: Option<std::sync::Arc<[f64]>>,
    /// The residual's envelope spectra per band set and segment lengths, computed once.
    #[serde(skip)]
    spectra: SpectraCache,
}

/// Squared envelope spectra of a baseline's residual, keyed by the rate, band edges and Welch
/// segment lengths they were computed for (a batch run at a few speeds needs a few).
#[derive(Default)]
struct SpectraCache(std::sync::Mutex<Vec<SpectraEntry>>);

/// One key (rate, band edges, segment lengths as bits) and its spectra.
type SpectraEntry = (Vec<u64>, std::sync::Arc<Vec<Option<EnvelopeSpectrum>>>);

/// At most this many band sets are kept per baseline.
const SPECTRA_CACHE_LEN: usize = 16;

impl SpectraCache {
    fn get(&self, key: &[u64]) -> Option<std::sync::Arc<Vec<Option<EnvelopeSpectrum>>>> {
        let v = self.0.lock().ok()?;
        v.iter().find(|(k, _)| k == key).map(|(_, s)| s.clone())
    }

    fn put(&self, key: Vec<u64>, spectra: std::sync::Arc<Vec<Option<EnvelopeSpectrum>>>) {
        if let Ok(mut v) = self.0.lock() {
            if v.len() >= SPECTRA_CACHE_LEN {
                v.remove(0);
            }
            v.push((key, spectra));
        }
    }
}

impl Clone for SpectraCache {
    fn clone(&self) -> Self {
        Self(std::sync::Mutex::new(
            self.0.lock().map(|v| v.clone()).unwrap_or_default(),
        ))
    }
}

/// A cache: equal whatever it holds.
impl PartialEq for SpectraCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for SpectraCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SpectraCache")
    }
}

impl Baseline {
    /// Fit the AR model on a healthy recording sampled at `fs_hz`.
    ///
    /// # Errors
    /// Non-finite samples, a baseline shorter than [`whiten::MIN_FIT_SAMPLES`], a sampling rate
    /// out of range, a constant signal.
    pub fn prepare(x: &[f64], fs_hz: f64) -> Result<Self> {
        check_fs(fs_hz)?;
        let whitener = ArWhitener::fit(x, fs_hz, "baseline")?;
        let e = whitener.residual(x);
        let (residual_rms, residual_kurtosis) = moments(&e, "baseline")?;
        Ok(Self {
            whitener,
            residual_rms,
            residual_kurtosis,
            samples: x.len(),
            residual: Some(e.into()),
            spectra: SpectraCache::default(),
        })
    }

    /// A baseline from a healthy model prepared elsewhere — the structural path of a calibrated
    /// machine model — with the residual statistics measured when it was calibrated
    /// (`samples` = how many samples those statistics came from).
    ///
    /// # Errors
    /// A sampling rate out of range, or non-finite / non-positive statistics
    /// ([`DiagnosisError::Degenerate`]).
    pub fn from_whitener(
        whitener: ArWhitener,
        residual_rms: f64,
        residual_kurtosis: f64,
        samples: usize,
    ) -> Result<Self> {
        check_fs(whitener.fs_hz)?;
        if !(residual_rms.is_finite()
            && residual_rms > 0.0
            && residual_kurtosis.is_finite()
            && residual_kurtosis > 0.0)
        {
            return Err(DiagnosisError::Degenerate {
                what: "baseline model",
                reason: format!(
                    "residual RMS {residual_rms} and kurtosis {residual_kurtosis} must be finite and > 0"
                ),
            });
        }
        Ok(Self {
            whitener,
            residual_rms,
            residual_kurtosis,
            samples,
            residual: None,
            spectra: SpectraCache::default(),
        })
    }
}

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

/// The operating point the diagnosis used.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OperatingPoint {
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
}

/// The fixed decision constants, written into every report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Thresholds {
    /// [`LINE_THRESHOLD_DB`].
    pub line_db: f64,
    /// [`MIN_LINES`].
    pub min_harmonics: usize,
    /// [`HARMONICS`].
    pub harmonics_searched: usize,
    /// [`SLIP_MAX`].
    pub slip_max: f64,
    /// [`SPEED_OFFSET`].
    pub speed_offset: f64,
    /// [`SPEED_TOL`].
    pub speed_tolerance: f64,
    /// [`SK_SIGMAS`].
    pub sk_sigmas: f64,
    /// [`CFAR_QUANTILE`].
    pub cfar_quantile: f64,
    /// [`SECOND_BAND_LINE_DB`].
    #[serde(default)]
    pub second_band_line_db: f64,
    /// Plain-language rule.
    pub rule: String,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self {
            line_db: LINE_THRESHOLD_DB,
            min_harmonics: MIN_LINES,
            harmonics_searched: HARMONICS,
            slip_max: SLIP_MAX,
            speed_offset: SPEED_OFFSET,
            speed_tolerance: SPEED_TOL,
            sk_sigmas: SK_SIGMAS,
            cfar_quantile: CFAR_QUANTILE,
            second_band_line_db: SECOND_BAND_LINE_DB,
            rule: format!(
                "a fault is detected when >= {MIN_LINES} of its harmonics 1..{HARMONICS} (at one common fundamental), or harmonic 1 and one distinguishing sideband (BPFI±fr, BSF±FTF), stand >= {LINE_THRESHOLD_DB} dB over the local median (and among the top {:.0} % of the spectrum's local maxima) in the squared envelope spectrum of an impulsive band (SK > {SK_SIGMAS} sigma of a Gaussian's; when no band is impulsive, a band whose envelope holds {MIN_LINES} harmonics of one fault at >= {PERIODIC_LINE_DB} dB), not explained by a stronger detected fault; against a baseline recording, a line the healthy machine already holds (>= {LINE_THRESHOLD_DB} dB there) counts only by what it has grown; a fault not detected in that common band is added when, in another impulsive band, it scores highest and has {MIN_LINES} harmonics at >= {SECOND_BAND_LINE_DB} dB that no common-band fault present in that band explains",
                100.0 * (1.0 - CFAR_QUANTILE)
            ),
        }
    }
}

/// A fault found in a band of its own, not in the common band (see [`diagnose`], step 3b).
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

fn band_choice(sp: &EnvelopeSpectrum, chosen_by: String) -> BandChoice {
    BandChoice {
        low_hz: sp.band_hz[0],
        high_hz: sp.band_hz[1],
        spectral_kurtosis: sp.spectral_kurtosis,
        line_threshold_db: sp.line_threshold_db,
        chosen_by,
    }
}

/// The result of [`diagnose`].
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
    pub operating_point: OperatingPoint,
    /// The AR whitening model used.
    pub whitening: ArWhitener,
    /// The band all hypotheses were read in (see `chosen_by`).
    pub band: BandChoice,
    /// The band of maximal spectral kurtosis (fast-kurtogram choice), for reference.
    pub kurtogram_band: BandChoice,
    /// Evidence per hypothesis (inner, outer, ball).
    pub evidence: Vec<HypothesisEvidence>,
    /// Shaft harmonics 1..=3 in `band`'s envelope spectrum.
    pub shaft_harmonics: Vec<Line>,
    /// Energy and kurtosis against the reference.
    pub statistics: Statistics,
    /// The fixed decision constants.
    pub thresholds: Thresholds,
    /// Faults not detected in the common band but found in a band of their own (step 3b of
    /// [`diagnose`]); they are in `detected` and the verdict, and their scores and lines are
    /// here (`scores` and `evidence` are the common band's).
    #[serde(default)]
    pub secondary: Vec<SecondaryRead>,
    /// Squared envelope spectrum of `band` (for figures; not serialised).
    #[serde(skip)]
    pub envelope: EnvelopeSpectrum,
}

impl Diagnosis {
    /// Why the verdict differs from a known `label` (`normal`, `inner`, `outer`, `ball`), from
    /// the evidence: the labelled fault's lines when it was not detected (prominence in dB,
    /// `ₓ` explained by a stronger fault, `≠` off the common fundamental) against the band's
    /// line threshold, and the lines of every other fault detected. Empty when they agree.
    pub fn explain_against(&self, label: &str) -> String {
        use std::fmt::Write as _;
        // a fault found in a band of its own is explained by its lines there
        let lines = |h: &str| {
            self.secondary
                .iter()
                .map(|r| &r.evidence)
                .chain(&self.evidence)
                .find(|e| e.hypothesis.name() == h)
                .map_or(String::new(), |e| {
                    e.harmonics
                        .iter()
                        .chain(&e.sidebands)
                        .map(|l| {
                            format!(
                                "{} {:.1}{}{}{}",
                                l.label,
                                l.prominence_db,
                                if l.evidence_db == l.prominence_db {
                                    String::new()
                                } else {
                                    format!(" (baseline {:.1})", l.prominence_db - l.evidence_db)
                                },
                                if l.explained_by.is_some() { "ₓ" } else { "" },
                                if l.consistent { "" } else { "≠" }
                            )
                        })
                        .collect::<Vec<_>>()
                        .join(", ")
                })
        };
        let mut s = String::new();
        if label != "normal" && !self.detected.iter().any(|h| h.name() == label) {
            let _ = write!(
                s,
                "{label} lines short of the rule (line threshold in band {:.0}–{:.0} Hz: {:.1} dB): {}",
                self.band.low_hz,
                self.band.high_hz,
                self.band.line_threshold_db,
                lines(label)
            );
        }
        for h in &self.detected {
            if h.name() != label {
                if !s.is_empty() {
                    s += "; ";
                }
                let own =
                    self.secondary
                        .iter()
                        .find(|r| r.hypothesis == *h)
                        .map_or(String::new(), |r| {
                            format!(
                                " in its own band {:.0}–{:.0} Hz",
                                r.band.low_hz, r.band.high_hz
                            )
                        });
                let _ = write!(s, "{} detected{own}: {}", h.name(), lines(h.name()));
            }
        }
        s
    }
}

fn check_fs(fs_hz: f64) -> Result<()> {
    if !(fs_hz.is_finite() && (MIN_FS_HZ..=MAX_FS_HZ).contains(&fs_hz)) {
        return Err(DiagnosisError::SampleRateOutOfRange {
            fs_hz,
            min: MIN_FS_HZ,
            max: MAX_FS_HZ,
        });
    }
    Ok(())
}

/// (RMS, kurtosis) of a residual.
fn moments(e: &[f64], what: &'static str) -> Result<(f64, f64)> {
    let degenerate = |reason: String| DiagnosisError::Degenerate { what, reason };
    let rms = residual_features::rms(e).map_err(|e| degenerate(e.to_string()))?;
    let k = residual_features::kurtosis(e).map_err(|e| degenerate(e.to_string()))?;
    if !(rms.is_finite() && rms > 0.0 && k.is_finite()) {
        return Err(degenerate("zero or non-finite residual".into()));
    }
    Ok((rms, k))
}

/// The candidate demodulation bands at `fs_hz`: no narrower than `min_width_hz` and with a
/// lower edge at or above it.
pub fn candidate_bands(fs_hz: f64, min_width_hz: f64) -> Vec<Band> {
    let nyq = 0.5 * fs_hz;
    let mut out = Vec::new();
    for d in BAND_DIVISORS {
        let w = nyq / d;
        if w < min_width_hz {
            continue;
        }
        let step = 0.5 * w;
        let mut lo = 0.0;
        while lo + w <= nyq * (1.0 + 1e-12) {
            // the band must lie above the fault lines and their first harmonics, or its
            // envelope shows beats between discrete low-frequency components (e.g. the
            // varying-compliance vibration at BPFO of a healthy bearing), not modulation
            if lo >= min_width_hz
                && let Ok(b) = Band::new(lo, (lo + w).min(nyq))
            {
                out.push(b);
            }
            lo += step;
        }
    }
    out
}

/// Narrowest band that holds three harmonics of the highest fault line plus a shaft-order
/// sideband, with 20 % margin: `1.2 (3 max(BPFO, BPFI, BSF) + 1) fr`.
pub fn min_band_width_hz(orders: &FaultOrders, fr: f64) -> f64 {
    let top = orders.bpfo.max(orders.bpfi).max(orders.ball_defect);
    1.2 * (HARMONICS as f64 * top + 1.0) * fr
}

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
        // FFT plans and Hann windows kept between recordings of one thread
        static ENGINE: std::cell::RefCell<SpectralEngine> =
            std::cell::RefCell::new(SpectralEngine::new());
    }
    ENGINE.with_borrow_mut(|engine| diagnose_with(engine, x, fs_hz, rpm, bearing, baseline))
}

/// The healthy machine's squared envelope spectra in `bands`, one Welch segment length per band
/// (`None` where the baseline is shorter than the segment).
fn baseline_spectra(
    engine: &mut SpectralEngine,
    residual: &[f64],
    fs_hz: f64,
    bands: &[Band],
    segs: &[usize],
) -> Result<Vec<Option<EnvelopeSpectrum>>> {
    let benvs = engine.band_squared_envelopes(residual, fs_hz, bands)?;
    let mut out = Vec::with_capacity(benvs.len());
    for (be, &seg) in benvs.iter().zip(segs) {
        let s = &be.squared_envelope;
        out.push(if s.len() >= seg {
            let psd = engine.welch_psd(s, be.rate_hz, WelchConfig::half_overlap(seg))?;
            Some(EnvelopeSpectrum {
                band_hz: [be.band.low_hz(), be.band.high_hz()],
                resolution_hz: psd.resolution_hz,
                power: psd.values,
                ..EnvelopeSpectrum::default()
            })
        } else {
            None
        });
    }
    Ok(out)
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
    let rpm_used = match measured_speed {
        Some(m) if m.accepted && (m.rpm / rpm - 1.0).abs() > 0.5 * SPEED_TOL => m.rpm,
        _ => rpm,
    };
    let fr = rpm_used / 60.0;
    let o = bearing.orders;
    let min_width = min_band_width_hz(&o, fr);
    if 2.0 * min_width > 0.5 * fs_hz {
        return Err(DiagnosisError::SampleRateTooLow {
            fs_hz,
            rpm,
            needed_hz: min_width,
        });
    }
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
    let (rms, kurt) = moments(&e, "recording")?;
    let (_, signal_kurtosis) = moments(x, "recording")?;
    let statistics = match baseline {
        Some(b) => {
            let ratio = (rms / b.residual_rms).powi(2);
            Statistics {
                residual_samples: e.len(),
                residual_rms: rms,
                residual_kurtosis: kurt,
                signal_kurtosis,
                energy_ratio: Some(ratio),
                energy_ratio_db: Some(10.0 * ratio.log10()),
                kurtosis_ratio: kurt / b.residual_kurtosis,
                kurtosis_reference: "baseline residual".into(),
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
        },
    };

    // 2. bands: squared envelopes, spectral kurtosis, Welch squared envelope spectra
    let bands = candidate_bands(fs_hz, min_width);
    let envs = engine.band_squared_envelopes(&e, fs_hz, &bands)?;
    let duration_turns = e.len() as f64 / fs_hz * fr;
    let seg_turns = (duration_turns / 4.0)
        .clamp(SEGMENT_TURNS_MIN, SEGMENT_TURNS_MAX)
        .min(duration_turns);
    let mut spectra = Vec::with_capacity(envs.len());
    let mut segs = Vec::with_capacity(envs.len());
    for be in &envs {
        let s = &be.squared_envelope;
        let n = s.len() as f64;
        let m1 = s.iter().sum::<f64>() / n;
        let m2 = s.iter().map(|v| v * v).sum::<f64>() / n;
        let sk = if m1 > 0.0 { m2 / (m1 * m1) - 2.0 } else { 0.0 };
        // `seg_turns` shaft turns, shortened to the nearest even 7-smooth length (≤ 2 %
        // shorter): an odd or large-prime segment takes a real FFT several times slower
        let target = (seg_turns / fr * be.rate_hz).round() as usize;
        let seg = (2 * residual_features::smooth_floor(target / 2)).clamp(16, s.len());
        segs.push(seg);
        let cfg = WelchConfig::half_overlap(seg);
        let psd = engine.welch_psd(s, be.rate_hz, cfg)?;
        let segments = if s.len() >= seg {
            1 + (s.len() - seg) / (seg - cfg.overlap)
        } else {
            0
        };
        let mut sp = EnvelopeSpectrum {
            band_hz: [be.band.low_hz(), be.band.high_hz()],
            resolution_hz: psd.resolution_hz,
            power: psd.values,
            spectral_kurtosis: if sk.is_finite() { sk } else { 0.0 },
            segments,
            line_threshold_db: LINE_THRESHOLD_DB,
        };
        // clutter for the rank CFAR: local maxima no kinematic family explains
        let top_hz = analysis_top_hz(&o, fr);
        let mut kinematic: Vec<f64> = Hypothesis::ALL
            .iter()
            .flat_map(|&h| evidence::evaluate(h, &sp, None, &o, fr).family(fr, o.ftf * fr))
            .collect();
        let mut j = 1.0;
        while j * fr <= top_hz {
            kinematic.push(j * fr);
            j += 1.0;
        }
        sp.set_threshold(fr, top_hz, &kinematic);
        spectra.push(sp);
    }
    // the healthy machine's squared envelope spectra in the same bands, at the same resolution
    // (a baseline recording only; one too short for a band's Welch segment gives none there)
    let base_spectra: std::sync::Arc<Vec<Option<EnvelopeSpectrum>>> = match baseline
        .and_then(|b| b.residual.as_deref().map(|r| (b, r)))
    {
        Some((b, br)) => {
            let mut key = vec![fs_hz.to_bits()];
            for (band, &seg) in bands.iter().zip(&segs) {
                key.extend([
                    band.low_hz().to_bits(),
                    band.high_hz().to_bits(),
                    seg as u64,
                ]);
            }
            match b.spectra.get(&key) {
                Some(s) => s,
                None => {
                    let s =
                        std::sync::Arc::new(baseline_spectra(engine, br, fs_hz, &bands, &segs)?);
                    b.spectra.put(key, s.clone());
                    s
                }
            }
        }
        None => std::sync::Arc::new(vec![None; spectra.len()]),
    };
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

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
