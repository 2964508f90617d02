//! Training-free, model-based diagnosis of one bearing recording.
//!
//! Given a vibration signal, its sampling rate, the shaft speed (declared, a range to search, or
//! both), the bearing (its fault orders from `bearing-model`) and optionally a healthy baseline of
//! the same machine, [`diagnose`] returns a [`Diagnosis`]: `normal`, `inner`, `outer`, `ball`, a
//! `+`-joined combination, or `uncertain` (two faults that explain the same lines, both named in
//! [`Diagnosis::candidates`]), with every number that led to it. No training and no labels: a
//! fault is reported only when its evidence would be this strong on a healthy machine with a
//! probability at most `α/3` ([`detect`]; `α` = [`DEFAULT_FALSE_ALARM`] = 1 % per recording by
//! default, [`DiagnoseOptions::with_false_alarm`]).
//!
//! # Method
//!
//! 0. **Speed** ([`options`], [`speed`]): the recording's shaft-harmonic comb is searched over the
//!    range given (by default ± 10 % of a declared speed: a set point or nameplate is often
//!    several per cent off), in its spectrum and, when that shows none, in the residual's squared
//!    envelopes (a defect or load that turns with the shaft modulates the impacts at fr). A comb
//!    found gives the speed (refined from its lines); without one, the declared speed is used and
//!    the fault templates' windows are widened by the range, their null read with the same
//!    windows ([`SpeedFinding`] says which). A self-referenced recording whose whole spectrum
//!    holds no comb but whose frames do, spreading more than [`SPEED_VARIES`] (a run-up, a
//!    coast-down), is resampled at equal shaft angles along them (`residual_features::order`)
//!    and diagnosed at its mean speed, where the tracked record then shows the shaft comb
//!    ([`Diagnosis::order_tracking`] says how).
//! 1. **Residual** ([`whiten`]): an AR linear predictor fitted by least squares on the baseline
//!    (order by held-out prediction error) is applied as a prediction-error filter to the
//!    recording: the residual of the healthy model, which pre-whitens the structural path and
//!    removes the shaft and mains lines the baseline holds. Without a baseline the AR model is
//!    fitted on the recording itself (AR pre-whitening, Sawalhi & Randall 2007) and the report
//!    says `"reference": "self"`.
//! 2. **Bands**: a filter bank of the fast kurtogram's shape (widths `fs/2 / d`,
//!    `d ∈ {2, 3, 4, 6, 8, 12, 16, 24, 32}`, half-overlapping; only bands wide enough to hold
//!    three harmonics of the highest fault line and starting above them) gives each band's
//!    complex envelope from one FFT (`residual_features::SpectralEngine::band_squared_envelopes`),
//!    its spectral kurtosis (Antoni, MSSP 20, 2006) and its squared envelope spectrum (Welch
//!    average of `|z|²`; Randall & Antoni, MSSP 25, 2011).
//! 3. **Detector** ([`detect`]): each band's spectrum as the prominence of its local maxima over
//!    the local median (dB), less what the healthy baseline holds there, with shaft orders, half
//!    orders and mains multiples masked where the band shows their comb. For each hypothesis
//!    (BPFO, BPFI, the ball-defect rate = CWRU's BSF) a template — harmonics 1..3 of one
//!    fundamental searched in the slip window, plus half its distinguishing sidebands (BPFI ± fr,
//!    BSF ± FTF) — is read at the kinematic rate and, as the null, at every bin-spaced
//!    fundamental where no kinematics puts a line; the hypothesis's rank among its nulls (with a
//!    generalised Pareto tail) is its probability per band, and the same rank over the band
//!    search gives `p_healthy`.
//! 4. **Verdict**: the hypotheses with `p_healthy ≤ α/3`, each re-tested with the line families
//!    of the stronger ones masked (a second fault stays significant; a fault's lines that another
//!    fault's family explains do not); `uncertain` when two explain each other's lines equally
//!    well. Against a baseline recording, a line the healthy machine already holds counts only
//!    by what it has grown ([`SearchedLine::evidence_db`]). See `docs/equations/diagnosis.md`.
//! 5. **Optional, with labels** (`trained`, cargo feature `trained`): a classifier trained on the
//!    evidence of labelled recordings' segments, beside the training-free verdict.
//!
//! # Dependencies and why
//! - `bearing-model`: the bearing's kinematics (`BearingSpec`, `FaultOrders`, its catalogue of
//!   designations), one type for it.
//! - `laguerre-id`: the AR least squares of the whitening filter.
//! - `residual-features`: the FFT, band envelopes and Welch spectra, the shaft-speed estimator
//!   and the order tracking.
//! - `classify` (only with the feature `trained`, which brings linfa with it): the optional
//!   trained classifier (its Gini tree and linear SVM, and `Dataset`).
//! - `sampled-signal`: [`Signal`], the checked recording (samples and rate) every entry point
//!   takes, and the one finite check of a slice.
//! - `serde` / `serde_json`: reports and the trained classifier's file; `thiserror`: the one
//!   error enum.
//!
//! # Example
//! ```
//! use bearing_model::{FaultClass, Noise, Scenario};
//! use diagnosis::{Baseline, BearingSpec, Signal, diagnose};
//! let rpm = 1797.0;
//! let healthy = Scenario::cwru(FaultClass::None, 0.014, rpm)?
//!     .with_noise(Noise::SnrDb(20.0)).with_duration(1.0).with_seed(1).simulate()?;
//! let faulty = Scenario::cwru(FaultClass::Outer, 0.014, rpm)?
//!     .with_noise(Noise::SnrDb(20.0)).with_duration(1.0).with_seed(2).simulate()?;
//! let baseline = Baseline::prepare(&Signal::new(&healthy.accel, healthy.fs_hz)?)?;
//! let recording = Signal::new(&faulty.accel, faulty.fs_hz)?;
//! let d = diagnose(&recording, rpm, &BearingSpec::parse("6205")?, Some(&baseline))?;
//! assert_eq!(d.verdict, "outer");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod detect;
pub mod error;
pub mod evidence;
mod lines;
pub mod options;
pub use residual_features::speed;
/// A recording's samples at their rate, checked (`sampled-signal`, the workspace's one type).
pub use sampled_signal::{Signal, SignalError};
#[cfg(feature = "trained")]
pub mod trained;
pub mod unknown;
pub mod whiten;

mod bands;
mod driver;
mod report;

use serde::{Deserialize, Serialize};

pub use bands::{candidate_bands, min_band_width_hz};
pub use bearing_model::BearingSpec;
pub use detect::{DEFAULT_FALSE_ALARM, Masks, Significance};
pub use driver::{SPEED_VARIES, TRACKED_COMB_AGREEMENT, diagnose, diagnose_with_options};
pub use error::{DiagnosisError, Result};
#[allow(deprecated)]
pub use evidence::Line;
pub use evidence::{EnvelopeSpectrum, HypothesisEvidence, PassedOver, SearchedLine};
pub use options::{DiagnoseOptions, SpeedFinding, SpeedSource};
pub use report::{
    BandChoice, Diagnosis, OperatingPointUsed, Scores, SecondaryRead, Statistics, Thresholds,
};

/// The former name of [`OperatingPointUsed`], kept so that code written against it still
/// compiles.
#[deprecated(
    note = "renamed to `OperatingPointUsed`: a report of what the diagnosis used (the declared \
            input of a close-loop run is `close_loop::OperatingPoint`)"
)]
pub type OperatingPoint = OperatingPointUsed;
#[cfg(feature = "trained")]
pub use trained::{EVIDENCE_FEATURES, Labelled, TrainedDiagnoser};
pub use unknown::{BearingGuess, diagnose_unknown_bearing};
pub use whiten::{ArWhitener, OrderScore};

/// Slowest accepted shaft speed, rpm.
pub const MIN_RPM: f64 = 30.0;
/// Fastest accepted shaft speed, rpm.
pub const MAX_RPM: f64 = 30_000.0;
/// Lowest accepted sampling rate, Hz.
pub const MIN_FS_HZ: f64 = 1_000.0;
/// Highest accepted sampling rate, Hz.
pub const MAX_FS_HZ: f64 = 1.0e6;
/// Shortest accepted recording, in shaft turns at the slowest speed searched: the envelope
/// spectrum needs at least this many turns to resolve the ± FTF sidebands of a ball fault
/// (FTF ≈ 0.4 fr) in a few bins and to hold a few Welch segments.
pub const MIN_TURNS: f64 = 20.0;
/// A line is *present* (reports mark it, and a band's comb of shaft orders or mains multiples
/// is recognised by such lines) when its power in the squared envelope spectrum is at least this
/// many dB over the local median (6 dB = 4× the median power). The verdict does not rest on it:
/// it rests on the detector's probability under "healthy" ([`detect`]).
pub const LINE_THRESHOLD_DB: f64 = 6.0;
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
    /// RMS of the baseline's own residual (below [`Self::band_limit_hz`] when set).
    pub residual_rms: f64,
    /// Kurtosis (not excess) of the baseline's own residual (below [`Self::band_limit_hz`] when
    /// set).
    pub residual_kurtosis: f64,
    /// Highest frequency, Hz, up to which the baseline holds the machine's signal; `None`: up to
    /// its Nyquist frequency. A baseline decimated from a higher rate holds only the
    /// anti-aliasing filter's stopband residue between the filter's passband edge and the new
    /// Nyquist, and a whitener fitted on it has a gain there as deep as that stopband: a
    /// recording's residual in that range is the whitener's amplification, not a change of the
    /// machine (a healthy bearing read +25 dB in energy against 97.mat decimated to 12 kHz). The
    /// energy and kurtosis ratios then compare both residuals below this frequency
    /// ([`Baseline::band_limited`]; `docs/journal/diagnosis.md`, "A decimated baseline").
    #[serde(default)]
    pub band_limit_hz: Option<f64>,
    /// Samples in the baseline.
    pub samples: usize,
    /// The baseline's own residual, kept to read the healthy machine's envelope lines in the
    /// same bands as the recording's (a line the baseline already holds is not fault
    /// evidence, see `SearchedLine::evidence_db`). For a baseline from a model
    /// ([`Baseline::from_whitener`]) `None` until a residual of a recording synthesised from
    /// the model is attached ([`Baseline::with_residual`]); not serialised.
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
    /// Fit the AR model on a healthy recording (its samples and rate; build its [`Signal`] with
    /// `DiagnosisError::signal("baseline", e)` as the error, so it is named the baseline).
    ///
    /// # Errors
    /// A baseline shorter than [`whiten::MIN_FIT_SAMPLES`], a sampling rate out of range, a
    /// constant signal.
    pub fn prepare(signal: &Signal<'_>) -> Result<Self> {
        let (x, fs_hz) = (signal.samples(), signal.fs_hz());
        check_fs(fs_hz)?;
        let whitener = ArWhitener::fit(signal, "baseline")?;
        let e = whitener.residual(x);
        let (residual_rms, residual_kurtosis) = moments(&e, "baseline")?;
        Ok(Self {
            whitener,
            residual_rms,
            residual_kurtosis,
            samples: x.len(),
            band_limit_hz: None,
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
            band_limit_hz: None,
            residual: None,
            spectra: SpectraCache::default(),
        })
    }

    /// This baseline with `residual` as the healthy machine's own residual, whose envelope lines
    /// are discounted as a baseline recording's are: for a model baseline
    /// ([`Baseline::from_whitener`]), the residual of a recording synthesised from the model,
    /// through the same whitener. The residual statistics stay those given (a synthesis is
    /// the model's idea of the machine; the statistics were measured on the machine itself).
    ///
    /// # Errors
    /// [`DiagnosisError::Degenerate`] for a residual with non-finite samples, zero RMS, or too
    /// short for moments — an envelope reference of zeros would discount nothing and say it did.
    pub fn with_residual(mut self, residual: Vec<f64>) -> Result<Self> {
        // a non-finite sample makes the RMS non-finite: `moments` refuses both
        moments(&residual, "baseline envelope reference")?;
        self.residual = Some(residual.into());
        self.spectra = SpectraCache::default();
        Ok(self)
    }

    /// This baseline compared with recordings only below `limit_hz`: its residual statistics
    /// are recomputed on its residual band-limited to `[0, limit_hz]` (an FFT brick-wall, as
    /// the recording's residual will be), and [`Self::band_limit_hz`] is set. For a baseline
    /// decimated from a higher rate, `limit_hz` is the anti-aliasing filter's passband edge
    /// (`bearing_data::DecimatorParams::passband_edge_hz`). A limit at or above the Nyquist
    /// frequency compares the whole band (a baseline never limited is returned as it is).
    ///
    /// # Errors
    /// [`DiagnosisError::Degenerate`] for a limit that is not finite and positive, a baseline
    /// that keeps no residual ([`Baseline::from_whitener`] without
    /// [`Baseline::with_residual`]), or a band-limited residual without energy.
    pub fn band_limited(mut self, limit_hz: f64) -> Result<Self> {
        if !(limit_hz.is_finite() && limit_hz > 0.0) {
            return Err(DiagnosisError::Degenerate {
                what: "baseline band limit",
                reason: format!("{limit_hz} Hz must be finite and > 0"),
            });
        }
        let whole = limit_hz >= 0.5 * self.whitener.fs_hz;
        if whole && self.band_limit_hz.is_none() {
            return Ok(self);
        }
        let Some(e) = self.residual.clone() else {
            return Err(DiagnosisError::Degenerate {
                what: "baseline",
                reason: "a band limit needs the baseline's own residual".into(),
            });
        };
        // from the whole residual each time, so a second call replaces the first
        let low = if whole {
            e.to_vec()
        } else {
            residual_features::bandpass_fft(
                &e,
                self.whitener.fs_hz,
                residual_features::Band::new(0.0, limit_hz)?,
            )?
        };
        let (rms, kurtosis) = moments(&low, "baseline below its band limit")?;
        self.residual_rms = rms;
        self.residual_kurtosis = kurtosis;
        self.band_limit_hz = (!whole).then_some(limit_hz);
        Ok(self)
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

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
