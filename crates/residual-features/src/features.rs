//! Window feature extraction: a validated list of features applied to every window of a series.
//!
//! The dissertation uses one feature, the window energy (eq. 2.46 / 3.26 / 4.31 / 5.33). This
//! module adds the usual time-domain statistics and, given the shaft speed and the bearing's
//! characteristic multiples of it ([`FaultOrders`]), envelope-spectrum line amplitudes at
//! BPFO, BPFI, the ball-defect rate and the cage rate and their harmonics, plus band energies.
//! It knows nothing about where the series came from: the same extractor runs on a residual
//! `r = y − ŷ` or on the raw signal `y`, so the two can be compared.

use serde::{Deserialize, Serialize};

use crate::error::{FeatureError, Result, check_finite, check_positive};
use crate::spectral::{Band, SpectralEngine, Taper};
use crate::stats;
use crate::window::WindowPlan;

/// Characteristic fault frequencies as multiples of the shaft frequency `fr`: `bearing-model`'s
/// one kinematics type (from a geometry, [`bearing_model::BearingGeometry::orders`], or a
/// manufacturer's table, [`FaultOrders::from_multiples`]); the ball line is its ball-defect rate
/// (CWRU's "BSF").
pub use bearing_model::FaultOrders;

/// Every multiple the envelope features read must be finite and positive.
fn validate_orders(m: &FaultOrders) -> Result<()> {
    check_positive("bpfo", m.bpfo)?;
    check_positive("bpfi", m.bpfi)?;
    check_positive("ball", m.ball_defect)?;
    check_positive("ftf", m.ftf)
}

/// A characteristic line of the envelope spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FaultLine {
    /// Shaft rate `fr`.
    Shaft,
    /// Outer-race ball pass frequency.
    Bpfo,
    /// Inner-race ball pass frequency.
    Bpfi,
    /// Ball-defect rate.
    Ball,
    /// Cage rate.
    Ftf,
}

impl FaultLine {
    fn name(self) -> &'static str {
        match self {
            FaultLine::Shaft => "fr",
            FaultLine::Bpfo => "bpfo",
            FaultLine::Bpfi => "bpfi",
            FaultLine::Ball => "ball",
            FaultLine::Ftf => "ftf",
        }
    }

    fn multiple(self, m: &FaultOrders) -> f64 {
        match self {
            FaultLine::Shaft => 1.0,
            FaultLine::Bpfo => m.bpfo,
            FaultLine::Bpfi => m.bpfi,
            FaultLine::Ball => m.ball_defect,
            FaultLine::Ftf => m.ftf,
        }
    }
}

/// One scalar feature of a window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Feature {
    /// Energy `Σ r²`, eq. (2.46) / (5.33).
    Energy,
    /// Root mean square.
    Rms,
    /// Peak absolute value.
    Peak,
    /// Peak / RMS.
    CrestFactor,
    /// Kurtosis `m4/m2²` (3 for Gaussian noise).
    Kurtosis,
    /// Skewness `m3/m2^{3/2}`.
    Skewness,
    /// Energy inside a band (one-sided Parseval); needs a sample rate.
    BandEnergy(Band),
    /// Largest envelope-spectrum amplitude within ±tolerance of `harmonic × line × fr`; needs
    /// [`EnvelopeSettings`].
    EnvelopeLine {
        /// Which characteristic line.
        line: FaultLine,
        /// 1 for the fundamental, 2 for the first harmonic, …
        harmonic: u32,
    },
}

impl Feature {
    /// Stable column name, e.g. `energy`, `band_2000_4000`, `env_bpfi_x2`.
    pub fn name(&self) -> String {
        match self {
            Feature::Energy => "energy".into(),
            Feature::Rms => "rms".into(),
            Feature::Peak => "peak".into(),
            Feature::CrestFactor => "crest_factor".into(),
            Feature::Kurtosis => "kurtosis".into(),
            Feature::Skewness => "skewness".into(),
            Feature::BandEnergy(b) => format!("band_{}_{}", b.low_hz(), b.high_hz()),
            Feature::EnvelopeLine { line, harmonic } => {
                format!("env_{}_x{}", line.name(), harmonic)
            }
        }
    }
}

/// Operating point and demodulation settings for envelope features.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EnvelopeSettings {
    /// Shaft frequency `fr` in Hz (stored rpm / 60).
    pub shaft_hz: f64,
    /// Characteristic multiples of `fr`.
    pub multiples: FaultOrders,
    /// Band-pass applied before the Hilbert envelope (e.g. 2–4 kHz for 12 kHz CWRU); `None` uses
    /// the full band.
    pub demodulation_band: Option<Band>,
    /// Relative search half-width around each line (e.g. 0.02 for ±2 %, to absorb slip).
    pub tolerance: f64,
}

/// Which features to compute and the context they need.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeatureConfig {
    /// Features, in column order.
    pub features: Vec<Feature>,
    /// Sample rate in Hz; required by band and envelope features.
    pub sample_rate_hz: Option<f64>,
    /// Envelope settings; required by envelope features.
    pub envelope: Option<EnvelopeSettings>,
}

impl FeatureConfig {
    /// The dissertation's feature set: energy only.
    pub fn energy_only() -> Self {
        Self {
            features: vec![Feature::Energy],
            sample_rate_hz: None,
            envelope: None,
        }
    }

    /// Energy, RMS, peak, crest factor, kurtosis and skewness.
    pub fn time_domain() -> Self {
        Self {
            features: vec![
                Feature::Energy,
                Feature::Rms,
                Feature::Peak,
                Feature::CrestFactor,
                Feature::Kurtosis,
                Feature::Skewness,
            ],
            sample_rate_hz: None,
            envelope: None,
        }
    }

    /// Time-domain set + envelope lines (fr, BPFO, BPFI, ball, FTF; fundamental and first
    /// harmonic) + the given band energies.
    pub fn full(sample_rate_hz: f64, envelope: EnvelopeSettings, bands: &[Band]) -> Self {
        let mut cfg = Self::time_domain();
        for line in [
            FaultLine::Shaft,
            FaultLine::Bpfo,
            FaultLine::Bpfi,
            FaultLine::Ball,
            FaultLine::Ftf,
        ] {
            for harmonic in 1..=2 {
                cfg.features.push(Feature::EnvelopeLine { line, harmonic });
            }
        }
        cfg.features
            .extend(bands.iter().map(|b| Feature::BandEnergy(*b)));
        cfg.sample_rate_hz = Some(sample_rate_hz);
        cfg.envelope = Some(envelope);
        cfg
    }
}

/// Rows of features, one per window, with column names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeatureTable {
    /// Column names ([`Feature::name`]).
    pub names: Vec<String>,
    /// One row per window, in time order.
    pub rows: Vec<Vec<f64>>,
}

/// A validated feature configuration that computes feature rows.
#[derive(Debug)]
pub struct FeatureExtractor {
    config: FeatureConfig,
    engine: SpectralEngine,
    needs_envelope: bool,
}

impl FeatureExtractor {
    /// Validate the configuration once.
    ///
    /// # Errors
    /// [`FeatureError::InvalidParameter`] for an empty feature list, a missing or invalid sample
    /// rate where band/envelope features need one, missing envelope settings, a zero harmonic,
    /// a non-positive shaft rate or tolerance outside (0, 0.5).
    pub fn new(config: FeatureConfig) -> Result<Self> {
        if config.features.is_empty() {
            return Err(FeatureError::InvalidParameter {
                name: "features",
                value: 0.0,
                reason: "at least one feature is required",
            });
        }
        let needs_rate = config
            .features
            .iter()
            .any(|f| matches!(f, Feature::BandEnergy(_) | Feature::EnvelopeLine { .. }));
        let needs_envelope = config
            .features
            .iter()
            .any(|f| matches!(f, Feature::EnvelopeLine { .. }));
        if needs_rate {
            match config.sample_rate_hz {
                Some(fs) => check_positive("sample_rate_hz", fs)?,
                None => {
                    return Err(FeatureError::InvalidParameter {
                        name: "sample_rate_hz",
                        value: f64::NAN,
                        reason: "band and envelope features need a sample rate",
                    });
                }
            }
        }
        if needs_envelope {
            let Some(env) = config.envelope else {
                return Err(FeatureError::InvalidParameter {
                    name: "envelope",
                    value: f64::NAN,
                    reason: "envelope features need EnvelopeSettings",
                });
            };
            check_positive("shaft_hz", env.shaft_hz)?;
            validate_orders(&env.multiples)?;
            if !(env.tolerance > 0.0 && env.tolerance < 0.5) {
                return Err(FeatureError::InvalidParameter {
                    name: "tolerance",
                    value: env.tolerance,
                    reason: "must lie in (0, 0.5)",
                });
            }
        }
        for f in &config.features {
            if let Feature::EnvelopeLine { harmonic: 0, .. } = f {
                return Err(FeatureError::InvalidParameter {
                    name: "harmonic",
                    value: 0.0,
                    reason: "must be >= 1",
                });
            }
        }
        Ok(Self {
            config,
            engine: SpectralEngine::new(),
            needs_envelope,
        })
    }

    /// The validated configuration.
    pub fn config(&self) -> &FeatureConfig {
        &self.config
    }

    /// Column names, in order.
    pub fn names(&self) -> Vec<String> {
        self.config.features.iter().map(Feature::name).collect()
    }

    /// Features of one window, in column order.
    ///
    /// # Errors
    /// Input errors (empty, non-finite), [`FeatureError::ZeroSpread`] for normalised statistics
    /// of a constant window.
    pub fn extract(&mut self, window: &[f64]) -> Result<Vec<f64>> {
        check_finite(window)?;
        let fs = self.config.sample_rate_hz.unwrap_or(1.0);
        let env_spec = if self.needs_envelope {
            let env = self.config.envelope.as_ref().ok_or(FeatureError::Empty)?;
            Some(
                self.engine
                    .envelope_spectrum(window, fs, env.demodulation_band, Taper::Hann)?,
            )
        } else {
            None
        };
        let mut row = Vec::with_capacity(self.config.features.len());
        for f in &self.config.features {
            let v = match *f {
                Feature::Energy => stats::energy(window)?,
                Feature::Rms => stats::rms(window)?,
                Feature::Peak => stats::peak(window)?,
                Feature::CrestFactor => stats::crest_factor(window)?,
                Feature::Kurtosis => stats::kurtosis(window)?,
                Feature::Skewness => stats::skewness(window)?,
                Feature::BandEnergy(b) => self.engine.band_energy(window, fs, b)?,
                Feature::EnvelopeLine { line, harmonic } => {
                    // Both Options were checked in `new`.
                    let (Some(env), Some(spec)) = (self.config.envelope.as_ref(), &env_spec) else {
                        return Err(FeatureError::Empty);
                    };
                    let f0 = env.shaft_hz * line.multiple(&env.multiples) * f64::from(harmonic);
                    let band = Band::new(f0 * (1.0 - env.tolerance), f0 * (1.0 + env.tolerance))?;
                    spec.peak_in_band(band).map_or(0.0, |p| p.value)
                }
            };
            row.push(v);
        }
        Ok(row)
    }

    /// Cut `signal` with `plan` and extract features of every window.
    ///
    /// # Errors
    /// Windowing errors and per-window feature errors.
    pub fn extract_windows(&mut self, signal: &[f64], plan: &WindowPlan) -> Result<FeatureTable> {
        let windows = plan.windows(signal)?;
        let rows = windows
            .into_iter()
            .map(|w| self.extract(w))
            .collect::<Result<Vec<_>>>()?;
        Ok(FeatureTable {
            names: self.names(),
            rows,
        })
    }
}
