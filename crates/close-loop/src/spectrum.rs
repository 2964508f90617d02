//! Spectral estimators the loop looks through. The Welch PSD, the Hilbert envelope and the
//! FFT behind the envelope periodogram are `residual-features`' (one implementation in the
//! workspace, conventions in `docs/equations/residual-features.md`); what that crate lacks lives
//! here: the zoom DFT that places a line between bins, the zero-padded envelope periodogram, the
//! digital band-pass mode used by the `resonance` effect and running medians.

use crate::CloseLoopError;
use residual_features::spectral::{SpectralEngine, Taper, WelchConfig};
use rustfft::num_complex::Complex;
use std::f64::consts::PI;
use std::sync::Mutex;

/// Welch power spectral density (Welch 1967) at a fixed segment length: a thin wrapper over
/// [`residual_features::spectral::SpectralEngine::welch_psd`] (periodic Hann, 50 % overlap,
/// per-segment mean removal, one-sided density scaling in units²/Hz so that Σ S·Δf ≈ variance;
/// segments that do not fit are left out). The engine caches the FFT plan.
pub struct Welch {
    fs: f64,
    nperseg: usize,
    engine: Mutex<SpectralEngine>,
}

impl std::fmt::Debug for Welch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Welch")
            .field("fs", &self.fs)
            .field("nperseg", &self.nperseg)
            .finish()
    }
}

impl Welch {
    /// An estimator with `nperseg`-sample segments at `fs` Hz.
    ///
    /// # Errors
    /// [`CloseLoopError::InvalidSamplingRate`] or [`CloseLoopError::ParameterOutOfRange`]
    /// (`nperseg` < 16).
    pub fn new(fs: f64, nperseg: usize) -> Result<Self, CloseLoopError> {
        if !(fs.is_finite() && fs > 0.0) {
            return Err(CloseLoopError::InvalidSamplingRate { fs });
        }
        if nperseg < 16 {
            return Err(CloseLoopError::ParameterOutOfRange {
                name: "nperseg",
                value: nperseg as f64,
                min: 16.0,
                max: f64::INFINITY,
            });
        }
        Ok(Self {
            fs,
            nperseg,
            engine: Mutex::new(SpectralEngine::new()),
        })
    }

    /// Segment length.
    pub fn nperseg(&self) -> usize {
        self.nperseg
    }

    /// Sampling frequency, Hz.
    pub fn fs(&self) -> f64 {
        self.fs
    }

    /// Bin width Δf = fs / nperseg, Hz.
    pub fn df(&self) -> f64 {
        self.fs / self.nperseg as f64
    }

    /// Number of one-sided bins, nperseg/2 + 1.
    pub fn n_bins(&self) -> usize {
        self.nperseg / 2 + 1
    }

    /// Frequency of bin `k`, Hz.
    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.df()
    }

    /// The PSD of `x`.
    ///
    /// # Errors
    /// [`CloseLoopError::TooShort`] when `x` holds less than one segment,
    /// [`CloseLoopError::Spectral`] for anything else `residual-features` rejects (non-finite
    /// samples).
    pub fn try_psd(&self, x: &[f64]) -> Result<Vec<f64>, CloseLoopError> {
        if x.len() < self.nperseg {
            return Err(CloseLoopError::TooShort {
                needed: self.nperseg,
                found: x.len(),
            });
        }
        let mut eng = self
            .engine
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        eng.welch_psd(x, self.fs, WelchConfig::half_overlap(self.nperseg))
            .map(|s| s.values)
            .map_err(|e| CloseLoopError::Spectral {
                reason: e.to_string(),
            })
    }
}

/// Hilbert envelope |x + j·H{x}| of the mean-removed signal
/// ([`residual_features::spectral::hilbert_envelope`] after removing the mean).
///
/// # Errors
/// [`CloseLoopError::Spectral`] for a signal `residual-features` rejects (empty, non-finite).
pub fn envelope(x: &[f64]) -> Result<Vec<f64>, CloseLoopError> {
    let mean = x.iter().sum::<f64>() / x.len().max(1) as f64;
    let c: Vec<f64> = x.iter().map(|v| v - mean).collect();
    residual_features::spectral::hilbert_envelope(&c).map_err(|e| CloseLoopError::Spectral {
        reason: e.to_string(),
    })
}

/// Normalised envelope periodogram of `x` and its bin width: the Hann-windowed Hilbert envelope
/// zero-padded to a power of two ≥ 2·len (a two-fold interpolated grid, which the speed search
/// needs), |E_k|² / (m²·len) with m the mean envelope, so a modulation of depth μ reads ≈ μ²/16·len.
/// The FFT is `residual-features`' amplitude spectrum with a rectangular taper on the padded,
/// already windowed block (|E_k| = A_k·N_pad / c_k, c_k its one-sided factor).
///
/// # Errors
/// [`CloseLoopError::Spectral`] when the envelope or its spectrum cannot be computed (an empty
/// or non-finite signal), or when the envelope is zero everywhere.
pub fn envelope_periodogram(x: &[f64], fs: f64) -> Result<(Vec<f64>, f64), CloseLoopError> {
    let env = envelope(x)?;
    let m = env.iter().sum::<f64>() / env.len().max(1) as f64;
    let xw = hann_windowed(&env);
    let nfft = (2 * xw.len()).next_power_of_two().max(2);
    let mut padded = vec![0.0; nfft];
    padded[..xw.len()].copy_from_slice(&xw);
    if !(m.is_finite() && m > 0.0) {
        return Err(CloseLoopError::Spectral {
            reason: "the envelope is zero everywhere".into(),
        });
    }
    let norm = m * m * xw.len() as f64;
    let de = fs / nfft as f64;
    let spec = residual_features::spectral::amplitude_spectrum(&padded, fs, Taper::Rectangular)
        .map_err(|e| CloseLoopError::Spectral {
            reason: e.to_string(),
        })?;
    let vals = spec
        .values
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let c = if k == 0 || k == nfft / 2 { 1.0 } else { 2.0 };
            let mag = a * nfft as f64 / c;
            mag * mag / norm
        })
        .collect();
    Ok((vals, de))
}

/// Hann-windowed copy of `x` (the window spans the whole signal), for [`zoom_power`].
pub fn hann_windowed(x: &[f64]) -> Vec<f64> {
    let n = x.len().max(2);
    let mean = x.iter().sum::<f64>() / x.len().max(1) as f64;
    x.iter()
        .enumerate()
        .map(|(i, v)| (v - mean) * (0.5 - 0.5 * (2.0 * PI * i as f64 / (n - 1) as f64).cos()))
        .collect()
}

/// Modulation index of `x` at `f`: the relative amplitude of the `f` component of its squared
/// Hilbert envelope E, m = 2·|Σ wᵢ(Eᵢ − Ē)·e^(−j2πf·i/fs)| / Σ wᵢEᵢ (w a Hann window). For a
/// stationary signal modulated as x·(1 + μ·cos 2πft), m = 2μ / (1 + μ²/2); for an unmodulated
/// one, m is the estimation scatter (≈ 1/√(effective envelope samples)).
///
/// # Errors
/// [`CloseLoopError::Spectral`] for an empty or all-zero signal.
pub fn modulation_index(x: &[f64], fs: f64, f: f64) -> Result<f64, CloseLoopError> {
    Ok(ModulationIndex::new(x, fs)?.at(f))
}

/// [`modulation_index`] of one signal at many frequencies: the envelope computed once.
pub struct ModulationIndex {
    ew: Vec<f64>,
    den: f64,
    fs: f64,
}

impl ModulationIndex {
    /// The squared envelope of `x`, windowed, and its weighted sum.
    ///
    /// # Errors
    /// [`CloseLoopError::Spectral`] for an empty or all-zero signal.
    pub fn new(x: &[f64], fs: f64) -> Result<Self, CloseLoopError> {
        let env = envelope(x)?;
        let e2: Vec<f64> = env.iter().map(|v| v * v).collect();
        let n = e2.len().max(2);
        let w = |i: usize| 0.5 - 0.5 * (2.0 * PI * i as f64 / (n - 1) as f64).cos();
        let den: f64 = e2.iter().enumerate().map(|(i, v)| w(i) * v).sum();
        if !(den.is_finite() && den > 0.0) {
            return Err(CloseLoopError::Spectral {
                reason: "the envelope is zero everywhere".into(),
            });
        }
        Ok(Self {
            ew: hann_windowed(&e2),
            den,
            fs,
        })
    }

    /// The index at `f`, Hz.
    pub fn at(&self, f: f64) -> f64 {
        2.0 * zoom_power(&self.ew, self.fs, f).sqrt() / self.den
    }
}

/// The zoom DFT power at any frequency: `residual-features`' (the workspace's one copy; it was
/// defined here until the shaft-speed reading of `residual_features::speed` needed it).
pub use residual_features::spectral::zoom_power;

/// The frequency in `[lo, hi]` where [`zoom_power`] is largest (one-off use of [`PeakRefiner`]).
pub fn refine_peak(xw: &[f64], fs: f64, lo: f64, hi: f64) -> f64 {
    PeakRefiner::new(xw, fs).refine(lo, hi)
}

/// Refines many peaks of one signal: a zero-padded (×4) FFT of the windowed signal computed
/// once locates each peak on a grid of a quarter of the full-length bin, then a golden-section
/// search of the zoom DFT ([`zoom_power`]) within ± one grid step places it (to ~1e-4 bin).
pub struct PeakRefiner<'a> {
    xw: &'a [f64],
    fs: f64,
    power: Vec<f64>,
    df: f64,
}

impl<'a> PeakRefiner<'a> {
    /// Transform `xw` (already windowed) once.
    pub fn new(xw: &'a [f64], fs: f64) -> Self {
        let n = (4 * xw.len().max(1)).next_power_of_two();
        let mut buf: Vec<Complex<f64>> = xw.iter().map(|&v| Complex::new(v, 0.0)).collect();
        buf.resize(n, Complex::new(0.0, 0.0));
        rustfft::FftPlanner::new()
            .plan_fft_forward(n)
            .process(&mut buf);
        let power = buf[..n / 2 + 1].iter().map(|c| c.norm_sqr()).collect();
        Self {
            xw,
            fs,
            power,
            df: fs / n as f64,
        }
    }

    /// The zero-padded periodogram |DFT|² on the grid k·[`PeakRefiner::df`].
    pub fn power(&self) -> &[f64] {
        &self.power
    }

    /// Bin width of [`PeakRefiner::power`], Hz.
    pub fn df(&self) -> f64 {
        self.df
    }

    /// The frequency of the largest peak in `[lo, hi]`, Hz.
    pub fn refine(&self, lo: f64, hi: f64) -> f64 {
        let last = self.power.len() - 1;
        let k0 = ((lo.max(0.0) / self.df).floor() as usize).min(last);
        let k1 = ((hi.max(lo) / self.df).ceil() as usize).clamp(k0, last);
        let kmax = (k0..=k1)
            .max_by(|&a, &b| self.power[a].total_cmp(&self.power[b]))
            .unwrap_or(k0);
        let f = kmax as f64 * self.df;
        let (a, b) = ((f - self.df).max(lo), (f + self.df).min(hi));
        if b <= a {
            return f.clamp(lo, hi);
        }
        crate::optimize::golden_max(|f| zoom_power(self.xw, self.fs, f), a, b, 16).0
    }
}

/// Digital second-order band-pass with unit peak gain (RBJ cookbook "constant 0 dB peak"),
/// centre `f0`, damping ratio `zeta` (Q = 1/(2ζ)). Returns `(b, a)` with `a[0] = 1`.
pub fn bandpass_coefficients(f0: f64, zeta: f64, fs: f64) -> ([f64; 3], [f64; 3]) {
    let w0 = 2.0 * PI * f0 / fs;
    let q = 1.0 / (2.0 * zeta);
    let alpha = w0.sin() / (2.0 * q);
    let a0 = 1.0 + alpha;
    (
        [alpha / a0, 0.0, -alpha / a0],
        [1.0, -2.0 * w0.cos() / a0, (1.0 - alpha) / a0],
    )
}

/// Complex response of the biquad `(b, a)` at frequency `f`.
pub fn biquad_response(b: &[f64; 3], a: &[f64; 3], f: f64, fs: f64) -> Complex<f64> {
    let w = 2.0 * PI * f / fs;
    let z1 = Complex::new(w.cos(), -w.sin());
    let z2 = z1 * z1;
    (b[0] + z1 * b[1] + z2 * b[2]) / (a[0] + z1 * a[1] + z2 * a[2])
}

/// Run the biquad `(b, a)` over `x` (direct form I, zero initial state).
pub fn biquad_filter(b: &[f64; 3], a: &[f64; 3], x: &[f64]) -> Vec<f64> {
    let (mut x1, mut x2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
    x.iter()
        .map(|&x0| {
            let y0 = b[0] * x0 + b[1] * x1 + b[2] * x2 - a[1] * y1 - a[2] * y2;
            x2 = x1;
            x1 = x0;
            y2 = y1;
            y1 = y0;
            y0
        })
        .collect()
}

/// Median of a slice (NaN-free input assumed; empty gives 0).
pub fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mut s = v.to_vec();
    let m = s.len() / 2;
    s.select_nth_unstable_by(m, |a, b| a.total_cmp(b));
    s[m]
}

/// Running median over a window of ±`half` samples (shrunk at the edges).
pub fn running_median(v: &[f64], half: usize) -> Vec<f64> {
    (0..v.len())
        .map(|i| {
            let lo = i.saturating_sub(half);
            let hi = (i + half + 1).min(v.len());
            median(&v[lo..hi])
        })
        .collect()
}

/// A one-sided PSD on the grid k·`df_hi` averaged onto the coarser grid k·`df`, `n_bins` bins:
/// coarse bin k is the mean of the fine bins within ±df/2 of k·df (the PSD's level is kept; a
/// Welch PSD with longer segments averaged this way estimates the shorter-segment one).
pub fn coarsen_psd(psd_hi: &[f64], df_hi: f64, df: f64, n_bins: usize) -> Vec<f64> {
    let r = df / df_hi;
    (0..n_bins)
        .map(|k| {
            let c = k as f64 * r;
            let lo = (c - 0.5 * r).ceil().max(0.0) as usize;
            let hi = ((c + 0.5 * r).floor() as usize).min(psd_hi.len().saturating_sub(1));
            if lo > hi {
                return psd_hi.get(c.round() as usize).copied().unwrap_or(0.0);
            }
            psd_hi[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Averaging onto a grid 8× coarser keeps a flat level and a ramp's mean per bin.
    #[test]
    fn coarsen_psd_keeps_the_level() {
        let flat = vec![2.0; 8 * 64 + 1];
        let c = coarsen_psd(&flat, 0.5, 4.0, 65);
        assert!(c.iter().all(|v| (v - 2.0).abs() < 1e-12), "{c:?}");
        let ramp: Vec<f64> = (0..=8 * 64).map(f64::from).collect();
        let c = coarsen_psd(&ramp, 0.5, 4.0, 65);
        // bin 10 averages fine bins 76..=84, mean 80
        assert!((c[10] - 80.0).abs() < 1e-12, "{}", c[10]);
        assert!((c[0] - 2.0).abs() < 1e-12, "{}", c[0]);
    }

    /// The four-lane phasor recurrence equals the DFT summed with an exact phase per sample,
    /// for lengths that are and are not multiples of four and across a renormalisation.
    #[test]
    fn zoom_power_is_the_dft_power_at_any_frequency() {
        let fs = 12_000.0;
        for n in [1usize, 3, 4, 7, 4099, 20_003] {
            let x: Vec<f64> = (0..n)
                .map(|i| {
                    let t = i as f64 / fs;
                    (2.0 * PI * 437.3 * t).sin() + 0.3 * (2.0 * PI * 1234.5 * t + 0.4).cos()
                })
                .collect();
            let xw = hann_windowed(&x);
            for f in [0.0, 101.7, 437.3, 1234.5, 5999.0] {
                let w = 2.0 * PI * f / fs;
                let exact = xw
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| Complex::from_polar(v, -w * i as f64))
                    .sum::<Complex<f64>>()
                    .norm_sqr();
                let got = zoom_power(&xw, fs, f);
                let scale = xw.iter().map(|v| v.abs()).sum::<f64>().powi(2).max(1e-300);
                assert!(
                    (got - exact).abs() <= 1e-9 * scale,
                    "n {n}, f {f}: {got} vs {exact}"
                );
            }
        }
    }
}
