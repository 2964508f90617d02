//! Windowing and window features of residual signals (energy, statistics, envelope spectrum).
//!
//! Implements the residual characterisation step of Piltan (2020): cut the residual
//! `r(k) = y(k) − ŷ(k)` into windows and compute the window energy `E = Σ r²`
//! (eqs. 2.46, 3.26, 4.31, 5.33). Beyond the dissertation it offers RMS, peak, crest factor,
//! kurtosis, skewness, band energies and envelope-spectrum line amplitudes at the bearing's
//! characteristic frequencies, and it exposes the spectral tools (amplitude spectrum, Welch PSD,
//! Hilbert envelope, envelope spectrum, FFT band-pass) for reuse by `close-loop`.
//!
//! [`order`] resamples a recording whose shaft speed changes at equal shaft angles (computed order
//! tracking, from a tachometer or from the recording's own shaft comb).
//!
//! Works equally on a residual or on the raw signal. Knows nothing about classifiers or
//! observers.
//!
//! # Dependencies and why
//! - `realfft` / `rustfft`: mature pure-Rust FFTs with plan caching (real-input FFT halves the work;
//!   the complex FFT is needed for the analytic signal).
//! - `serde`: configurations and feature tables are saved with results.
//! - `thiserror`: the crate's one error enum.
//! - `sampled-signal`: the workspace's one finite check of a slice (`first_non_finite`).
//!
//! # Example
//! ```
//! use residual_features::{FeatureConfig, FeatureExtractor, TailPolicy, WindowPlan, Windowing};
//! let residual: Vec<f64> = (0..1000).map(|k| (0.3 * k as f64).sin()).collect();
//! let plan = WindowPlan::new(Windowing::FixedCount { count: 4 }, TailPolicy::Discard)?;
//! let mut fx = FeatureExtractor::new(FeatureConfig::energy_only())?;
//! let table = fx.extract_windows(&residual, &plan)?;
//! assert_eq!(table.rows.len(), 4);
//! assert_eq!(table.names, vec!["energy"]);
//! # Ok::<(), residual_features::FeatureError>(())
//! ```

mod error;
mod features;
pub mod order;
pub mod spectral;
pub mod speed;
pub mod stats;
mod window;

pub use error::{FeatureError, Result};
pub use features::{
    EnvelopeSettings, FaultLine, FaultOrders, Feature, FeatureConfig, FeatureExtractor,
    FeatureTable,
};
pub use order::{OrderTracked, order_track, tach_pulse_times};
pub use spectral::{
    Band, BandEnvelope, SpectralEngine, SpectralPeak, Spectrum, Taper, WelchConfig,
    amplitude_spectrum, band_energy, band_squared_envelopes, bandpass_fft, envelope_spectrum,
    hilbert_envelope, smooth_floor, welch_psd,
};
pub use stats::{crest_factor, energy, kurtosis, peak, rms, skewness};
pub use window::{TailPolicy, WindowPlan, WindowSet, Windowing};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
