//! Spectral tools shared with other crates: one-sided amplitude spectrum, Welch PSD (Hann),
//! Hilbert envelope, envelope spectrum, band-pass by FFT masking and band energy.
//!
//! These are the tools a vibration analyst uses to read a residual (see the closed-loop part of
//! the architecture brief); the `close-loop` crate reuses them. FFTs come from `realfft`/`rustfft`.
//! Each free function plans its own transform; for many windows of the same length hold a
//! [`SpectralEngine`], which caches FFT plans.
//!
//! Conventions (documented in `docs/equations/residual-features.md`):
//! - amplitude spectrum: `A_k = c_k |X_k| / Σ w_n`, `c_k = 2` except at DC and Nyquist (`c_k = 1`),
//!   so a bin-centred sine of amplitude `a` reads `a` with any taper (coherent-gain corrected);
//! - Welch PSD: periodic Hann segments, constant detrend, density scaling `|X_k|² / (fs Σ w²)`,
//!   doubled off DC/Nyquist (the `scipy.signal.welch` defaults); segments that do not fit are left out;
//! - Hilbert envelope: `|x + j H{x}|` from the one-sided analytic spectrum;
//! - band energy: one-sided Parseval, so the bands covering `[0, fs/2]` sum to `Σ x²`.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};
use rustfft::FftPlanner;
use serde::{Deserialize, Serialize};

use crate::error::{FeatureError, Result, check_finite, check_positive};

/// A frequency band `[low_hz, high_hz]`, inclusive, validated on construction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Band {
    low_hz: f64,
    high_hz: f64,
}

impl Band {
    /// A band with `0 <= low_hz < high_hz`, both finite.
    ///
    /// # Errors
    /// [`FeatureError::InvalidParameter`] otherwise.
    pub fn new(low_hz: f64, high_hz: f64) -> Result<Self> {
        if !(low_hz.is_finite() && low_hz >= 0.0) {
            return Err(FeatureError::InvalidParameter {
                name: "low_hz",
                value: low_hz,
                reason: "must be finite and >= 0",
            });
        }
        if !(high_hz.is_finite() && high_hz > low_hz) {
            return Err(FeatureError::InvalidParameter {
                name: "high_hz",
                value: high_hz,
                reason: "must be finite and > low_hz",
            });
        }
        Ok(Self { low_hz, high_hz })
    }

    /// Lower edge in Hz.
    pub fn low_hz(&self) -> f64 {
        self.low_hz
    }

    /// Upper edge in Hz.
    pub fn high_hz(&self) -> f64 {
        self.high_hz
    }

    /// Bin indices `k` with `k·df` inside the band (edges inclusive, with a relative slack of
    /// 1e-9 bins so that e.g. the Nyquist bin is not lost to rounding), clipped to `nbins`.
    fn bins(&self, df: f64, nbins: usize) -> std::ops::Range<usize> {
        let lo = (self.low_hz / df - 1e-9).ceil().max(0.0) as usize;
        let hi = ((self.high_hz / df + 1e-9).floor() as usize).saturating_add(1);
        lo.min(nbins)..hi.min(nbins)
    }
}

/// Taper applied to a block before its FFT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Taper {
    /// No taper (boxcar).
    Rectangular,
    /// Periodic Hann `0.5 − 0.5 cos(2πn/N)`.
    Hann,
}

impl Taper {
    /// The taper's `n` weights.
    pub(crate) fn weights(self, n: usize) -> Vec<f64> {
        match self {
            Taper::Rectangular => vec![1.0; n],
            Taper::Hann => (0..n)
                .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
                .collect(),
        }
    }
}

/// A one-sided spectrum on the grid `f_k = k · resolution_hz`, `k = 0..values.len()`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Spectrum {
    /// Bin spacing `fs / N` in Hz.
    pub resolution_hz: f64,
    /// One value per bin (amplitude, or power density, depending on the producing function).
    pub values: Vec<f64>,
}

/// The largest value of a spectrum inside a band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpectralPeak {
    /// Frequency of the peak bin in Hz.
    pub frequency_hz: f64,
    /// Value at the peak bin.
    pub value: f64,
}

impl Spectrum {
    /// Frequency of bin `k` in Hz.
    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.resolution_hz
    }

    /// All bin frequencies in Hz.
    pub fn frequencies(&self) -> Vec<f64> {
        (0..self.values.len()).map(|k| self.frequency(k)).collect()
    }

    /// The largest bin whose frequency lies in `band`; if the band falls between two bins, the
    /// bin nearest to the band centre. `None` only if the band lies above the last bin.
    pub fn peak_in_band(&self, band: Band) -> Option<SpectralPeak> {
        let best = band
            .bins(self.resolution_hz, self.values.len())
            .max_by(|&a, &b| self.values[a].total_cmp(&self.values[b]).then(b.cmp(&a)));
        let k = match best {
            Some(k) => k,
            None => {
                let centre = 0.5 * (band.low_hz + band.high_hz);
                let k = (centre / self.resolution_hz).round() as usize;
                if k >= self.values.len() {
                    return None;
                }
                k
            }
        };
        Some(SpectralPeak {
            frequency_hz: self.frequency(k),
            value: self.values[k],
        })
    }
}

/// The squared envelope of a signal in one band, sampled at a reduced rate (see
/// [`SpectralEngine::band_squared_envelopes`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BandEnvelope {
    /// The demodulation band.
    pub band: Band,
    /// Sampling rate of `squared_envelope`, Hz (at least twice the band width, so the squared
    /// envelope, whose spectrum lies within ± the band width, is not aliased).
    pub rate_hz: f64,
    /// `|x_a(t)|²` of the band's analytic signal at `t_m = m / rate_hz`, covering the whole
    /// record (same duration as the input).
    pub squared_envelope: Vec<f64>,
}

impl BandEnvelope {
    /// Spectral kurtosis of the band, `⟨|z|⁴⟩/⟨|z|²⟩² − 2` (Antoni 2006; 0 for a Gaussian
    /// complex envelope), from the squared envelope's two first moments; 0 for an empty or
    /// all-zero envelope.
    pub fn spectral_kurtosis(&self) -> f64 {
        let s = &self.squared_envelope;
        let n = s.len() as f64;
        let m1 = s.iter().sum::<f64>() / n;
        let m2 = s.iter().map(|v| v * v).sum::<f64>() / n;
        if m1 > 0.0 { m2 / (m1 * m1) - 2.0 } else { 0.0 }
    }
}

/// Only prime factors in `primes`.
fn is_smooth(m: usize, primes: &[usize]) -> bool {
    let mut r = m;
    for &p in primes {
        while r % p == 0 && r > 0 {
            r /= p;
        }
    }
    r == 1
}

/// Smallest `m ≥ n` whose only prime factors are 2, 3 and 5 (fast FFT sizes).
fn smooth_size(n: usize) -> usize {
    let mut m = n.max(1);
    while !is_smooth(m, &[2, 3, 5]) {
        m += 1;
    }
    m
}

/// `x`'s length after the checks of a transform at `fs_hz`: finite samples, at least two, a
/// finite positive rate.
fn checked_pair(x: &[f64], fs_hz: f64) -> Result<usize> {
    check_finite(x)?;
    check_positive("fs_hz", fs_hz)?;
    if x.len() < 2 {
        return Err(FeatureError::TooShort {
            needed: 2,
            found: x.len(),
        });
    }
    Ok(x.len())
}

/// Largest `m ≤ n` (`n ≥ 1`) whose only prime factors are 2, 3 and 5: a count of bins
/// [`SpectralEngine::low_pass_resample`] keeps without a zero band above it (it transforms back
/// on twice the smallest 5-smooth count ≥ the bins kept).
pub(crate) fn smooth5_floor(n: usize) -> usize {
    let mut m = n.max(1);
    while !is_smooth(m, &[2, 3, 5]) {
        m -= 1;
    }
    m
}

/// Largest `m ≤ n` (`n ≥ 1`) whose only prime factors are 2, 3, 5 and 7: how many samples of
/// a record of `n` to transform so that its FFT is fast. A length with a large prime factor (a
/// 10 s, 12 kHz record less an AR filter's warm-up, 119 992 = 2³·53·283) takes a Bluestein FFT
/// several times slower; the largest 7-smooth length keeps at least 98 % of a record of 10⁴
/// samples or more (unit test).
pub fn smooth_floor(n: usize) -> usize {
    let mut m = n.max(1);
    while !is_smooth(m, &[2, 3, 5, 7]) {
        m -= 1;
    }
    m
}

/// Welch PSD settings: segment length and overlap in samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct WelchConfig {
    /// Samples per segment (≥ 2).
    pub segment_len: usize,
    /// Samples shared by consecutive segments (< `segment_len`; half is usual).
    pub overlap: usize,
}

impl WelchConfig {
    /// Half-overlapping segments of `segment_len` samples (scipy's default overlap).
    pub fn half_overlap(segment_len: usize) -> Self {
        Self {
            segment_len,
            overlap: segment_len / 2,
        }
    }
}

/// FFT plan cache for the spectral functions; reuse one per thread when processing many windows.
///
/// An engine's results can differ in the last bits with what it transformed before: rustfft
/// builds a length's plan from the sub-plans its planner already holds. For results that do not
/// depend on call order, use [`SpectralEngine::order_independent`] (the free functions' per-thread
/// engine is one).
pub struct SpectralEngine {
    real: RealFftPlanner<f64>,
    complex: FftPlanner<f64>,
    /// Plans built each by a planner of its own and kept by length (the free functions'
    /// engine): a shared planner builds a length's plan from the sub-plans it already holds, so
    /// its result can differ in the last bits with what was planned before; these plans do not.
    independent: Option<IndependentPlans>,
    /// Hann weights by length, for repeated Welch estimates at the same segment length.
    hann: Vec<(usize, Arc<[f64]>)>,
    /// A reusable segment buffer.
    scratch: Vec<f64>,
}

impl Default for SpectralEngine {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for SpectralEngine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SpectralEngine")
    }
}

thread_local! {
    /// The free functions' plan cache, one per thread: a plan for a length that is not a power
    /// of two costs as much as several transforms to build (its twiddles), and callers such as
    /// the closed loop take the envelope of same-length signals hundreds of times.
    static ENGINE: std::cell::RefCell<SpectralEngine> =
        std::cell::RefCell::new(SpectralEngine::order_independent());
}

/// Lengths kept by [`IndependentPlans`] before it starts afresh (a batch over files of many
/// lengths does not grow it without bound).
const INDEPENDENT_PLANS_KEPT: usize = 32;

/// FFT plans by length, each built by a planner of its own ([`SpectralEngine::order_independent`]).
#[derive(Default)]
struct IndependentPlans {
    real_forward: Vec<(usize, Arc<dyn RealToComplex<f64>>)>,
    real_inverse: Vec<(usize, Arc<dyn realfft::ComplexToReal<f64>>)>,
    complex_inverse: Vec<(usize, Arc<dyn rustfft::Fft<f64>>)>,
}

/// The plan for `n` in `cache`, built by `build` when missing.
fn kept_plan<P: ?Sized>(
    cache: &mut Vec<(usize, Arc<P>)>,
    n: usize,
    build: impl FnOnce() -> Arc<P>,
) -> Arc<P> {
    if let Some((_, p)) = cache.iter().find(|(m, _)| *m == n) {
        return p.clone();
    }
    if cache.len() >= INDEPENDENT_PLANS_KEPT {
        cache.clear();
    }
    let p = build();
    cache.push((n, p.clone()));
    p
}

impl IndependentPlans {
    fn real_forward(&mut self, n: usize) -> Arc<dyn RealToComplex<f64>> {
        kept_plan(&mut self.real_forward, n, || {
            RealFftPlanner::new().plan_fft_forward(n)
        })
    }

    fn real_inverse(&mut self, n: usize) -> Arc<dyn realfft::ComplexToReal<f64>> {
        kept_plan(&mut self.real_inverse, n, || {
            RealFftPlanner::new().plan_fft_inverse(n)
        })
    }

    fn complex_inverse(&mut self, n: usize) -> Arc<dyn rustfft::Fft<f64>> {
        kept_plan(&mut self.complex_inverse, n, || {
            FftPlanner::new().plan_fft_inverse(n)
        })
    }
}

/// Run `f` on this thread's [`SpectralEngine`] (a fresh one if it is already in use); its plans
/// are independent of one another ([`SpectralEngine::order_independent`]), so every free function
/// gives the bits a fresh engine gives.
fn with_engine<T>(f: impl FnOnce(&mut SpectralEngine) -> T) -> T {
    ENGINE.with(|cell| match cell.try_borrow_mut() {
        Ok(mut engine) => f(&mut engine),
        Err(_) => f(&mut SpectralEngine::new()),
    })
}

/// One-sided scale factor for bin `k` of an `n`-point transform.
fn one_sided(k: usize, n: usize) -> f64 {
    if k == 0 || (n % 2 == 0 && k == n / 2) {
        1.0
    } else {
        2.0
    }
}

impl SpectralEngine {
    /// An empty plan cache.
    pub fn new() -> Self {
        Self {
            real: RealFftPlanner::new(),
            complex: FftPlanner::new(),
            independent: None,
            hann: Vec::new(),
            scratch: Vec::new(),
        }
    }

    /// An engine whose every plan is built as a fresh engine would build it (and then kept):
    /// its results never depend on what it transformed before, so a cache shared by unrelated
    /// callers (the free functions' per-thread engine, a batch's per-thread engine) gives the
    /// same bits in any order. It keeps at most 32 lengths per kind of transform.
    pub fn order_independent() -> Self {
        Self {
            independent: Some(IndependentPlans::default()),
            ..Self::new()
        }
    }

    fn complex_inverse(&mut self, n: usize) -> Arc<dyn rustfft::Fft<f64>> {
        match &mut self.independent {
            Some(p) => p.complex_inverse(n),
            None => self.complex.plan_fft_inverse(n),
        }
    }

    fn real_inverse(&mut self, n: usize) -> Arc<dyn realfft::ComplexToReal<f64>> {
        match &mut self.independent {
            Some(p) => p.real_inverse(n),
            None => self.real.plan_fft_inverse(n),
        }
    }

    /// Hann weights of length `m`, computed once per length (the last few lengths are kept).
    fn hann(&mut self, m: usize) -> Arc<[f64]> {
        if let Some((_, w)) = self.hann.iter().find(|(n, _)| *n == m) {
            return w.clone();
        }
        let w: Arc<[f64]> = Taper::Hann.weights(m).into();
        if self.hann.len() >= 64 {
            self.hann.remove(0);
        }
        self.hann.push((m, w.clone()));
        w
    }

    fn forward(&mut self, n: usize) -> Arc<dyn RealToComplex<f64>> {
        match &mut self.independent {
            Some(p) => p.real_forward(n),
            None => self.real.plan_fft_forward(n),
        }
    }

    fn rfft(&mut self, mut buf: Vec<f64>) -> Result<Vec<Complex<f64>>> {
        let n = buf.len();
        let plan = self.forward(n);
        let mut out = plan.make_output_vec();
        plan.process(&mut buf, &mut out)
            .map_err(|_| FeatureError::Fft { len: n })?;
        Ok(out)
    }

    /// One-sided amplitude spectrum of `x` sampled at `fs_hz`, with the given taper
    /// (coherent-gain corrected: a bin-centred sine of amplitude `a` reads `a`).
    ///
    /// # Errors
    /// Input errors, [`FeatureError::TooShort`] below 2 samples, invalid `fs_hz`.
    pub fn amplitude_spectrum(&mut self, x: &[f64], fs_hz: f64, taper: Taper) -> Result<Spectrum> {
        check_finite(x)?;
        check_positive("fs_hz", fs_hz)?;
        let n = x.len();
        if n < 2 {
            return Err(FeatureError::TooShort {
                needed: 2,
                found: n,
            });
        }
        // the engine's Hann cache: the speed search takes the spectrum of same-length blocks
        let w: Arc<[f64]> = match taper {
            Taper::Hann => self.hann(n),
            other => other.weights(n).into(),
        };
        let gain: f64 = w.iter().sum();
        let buf: Vec<f64> = x.iter().zip(w.iter()).map(|(a, b)| a * b).collect();
        let spec = self.rfft(buf)?;
        let values = spec
            .iter()
            .enumerate()
            .map(|(k, c)| one_sided(k, n) * c.norm() / gain)
            .collect();
        Ok(Spectrum {
            resolution_hz: fs_hz / n as f64,
            values,
        })
    }

    /// Welch power spectral density (units²/Hz), periodic Hann segments, constant detrend.
    ///
    /// # Errors
    /// Input errors; [`FeatureError::InvalidParameter`] if `segment_len < 2` or
    /// `overlap >= segment_len`; [`FeatureError::TooShort`] if `x` is shorter than one segment.
    pub fn welch_psd(&mut self, x: &[f64], fs_hz: f64, config: WelchConfig) -> Result<Spectrum> {
        check_finite(x)?;
        check_positive("fs_hz", fs_hz)?;
        let WelchConfig {
            segment_len: m,
            overlap,
        } = config;
        if m < 2 {
            return Err(FeatureError::InvalidParameter {
                name: "segment_len",
                value: m as f64,
                reason: "must be >= 2",
            });
        }
        if overlap >= m {
            return Err(FeatureError::InvalidParameter {
                name: "overlap",
                value: overlap as f64,
                reason: "must be < segment_len",
            });
        }
        if x.len() < m {
            return Err(FeatureError::TooShort {
                needed: m,
                found: x.len(),
            });
        }
        let step = m - overlap;
        let w = self.hann(m);
        let s2: f64 = w.iter().map(|v| v * v).sum();
        let plan = self.forward(m);
        let mut acc = vec![0.0; m / 2 + 1];
        let mut out = plan.make_output_vec();
        let mut buf = std::mem::take(&mut self.scratch);
        buf.resize(m, 0.0);
        let mut segments = 0usize;
        let mut start = 0;
        while start + m <= x.len() {
            let seg = &x[start..start + m];
            let mean = seg.iter().sum::<f64>() / m as f64;
            for ((b, v), wi) in buf.iter_mut().zip(seg).zip(w.iter()) {
                *b = (v - mean) * wi;
            }
            plan.process(&mut buf, &mut out)
                .map_err(|_| FeatureError::Fft { len: m })?;
            for (k, (a, c)) in acc.iter_mut().zip(&out).enumerate() {
                *a += one_sided(k, m) * c.norm_sqr() / (fs_hz * s2);
            }
            segments += 1;
            start += step;
        }
        self.scratch = buf;
        for a in &mut acc {
            *a /= segments as f64;
        }
        Ok(Spectrum {
            resolution_hz: fs_hz / m as f64,
            values: acc,
        })
    }

    /// Hilbert envelope `|x + j·H{x}|` via the one-sided analytic spectrum.
    ///
    /// # Errors
    /// Input errors, [`FeatureError::TooShort`] below 2 samples.
    pub fn hilbert_envelope(&mut self, x: &[f64]) -> Result<Vec<f64>> {
        check_finite(x)?;
        let n = x.len();
        if n < 2 {
            return Err(FeatureError::TooShort {
                needed: 2,
                found: n,
            });
        }
        let spec = self.rfft(x.to_vec())?;
        let mut z = vec![Complex::new(0.0, 0.0); n];
        for (k, c) in spec.iter().enumerate() {
            z[k] = c * one_sided(k, n);
        }
        let inv = self.complex_inverse(n);
        inv.process(&mut z);
        let scale = 1.0 / n as f64;
        Ok(z.iter().map(|c| c.norm() * scale).collect())
    }

    /// Unwrapped phase (rad) of the analytic signal of `x` band-limited to `band`: the zero-phase
    /// brick wall of [`SpectralEngine::bandpass_fft`] and the one-sided spectrum of
    /// [`SpectralEngine::hilbert_envelope`] in one transform. A band holding one line gives that
    /// line's phase sample by sample (`residual_features::order` reads a shaft order's).
    ///
    /// # Errors
    /// Input errors, invalid `fs_hz`, [`FeatureError::TooShort`] below 2 samples.
    pub fn band_phase(&mut self, x: &[f64], fs_hz: f64, band: Band) -> Result<Vec<f64>> {
        let n = checked_pair(x, fs_hz)?;
        let df = fs_hz / n as f64;
        let spec = self.rfft(x.to_vec())?;
        let keep = band.bins(df, spec.len());
        let mut z = vec![Complex::new(0.0, 0.0); n];
        for k in keep {
            z[k] = spec[k] * one_sided(k, n);
        }
        let inv = self.complex_inverse(n);
        inv.process(&mut z);
        let mut out = Vec::with_capacity(n);
        let mut offset = 0.0;
        let mut prev = 0.0;
        for (i, c) in z.iter().enumerate() {
            let a = c.im.atan2(c.re);
            if i > 0 {
                let d = a - prev;
                if d > std::f64::consts::PI {
                    offset -= 2.0 * std::f64::consts::PI;
                } else if d < -std::f64::consts::PI {
                    offset += 2.0 * std::f64::consts::PI;
                }
            }
            prev = a;
            out.push(a + offset);
        }
        Ok(out)
    }

    /// Envelope spectrum: the amplitude spectrum of the mean-removed Hilbert envelope of `x`,
    /// optionally band-passed first (the demodulation band).
    ///
    /// # Errors
    /// As [`SpectralEngine::amplitude_spectrum`] and [`SpectralEngine::bandpass_fft`].
    pub fn envelope_spectrum(
        &mut self,
        x: &[f64],
        fs_hz: f64,
        demodulation_band: Option<Band>,
        taper: Taper,
    ) -> Result<Spectrum> {
        let filtered;
        let src = match demodulation_band {
            Some(b) => {
                filtered = self.bandpass_fft(x, fs_hz, b)?;
                &filtered[..]
            }
            None => x,
        };
        let mut env = self.hilbert_envelope(src)?;
        let mean = env.iter().sum::<f64>() / env.len() as f64;
        for e in &mut env {
            *e -= mean;
        }
        self.amplitude_spectrum(&env, fs_hz, taper)
    }

    /// Squared envelopes of `x` in several demodulation bands from one forward FFT.
    ///
    /// For each band the bins inside it are shifted to base band and transformed back with a
    /// short inverse FFT (size ≥ 2 × the band's bin count, 2-3-5-smooth), which gives the band's
    /// complex envelope `z(t)` (the analytic signal without its carrier) at a reduced rate;
    /// `|z|²` equals `|x_bp + j H{x_bp}|²` of [`SpectralEngine::bandpass_fft`] followed by
    /// [`SpectralEngine::hilbert_envelope`], squared, at the reduced sample times. This is the
    /// filter bank of a (fast) kurtogram: the spectral kurtosis of a band is
    /// `⟨|z|⁴⟩ / ⟨|z|²⟩² − 2` (Antoni 2006), and the spectrum of `|z|²` is the squared envelope
    /// spectrum of the band (Randall & Antoni 2011).
    ///
    /// # Errors
    /// Input errors, invalid `fs_hz`, [`FeatureError::TooShort`] below 4 samples,
    /// [`FeatureError::InvalidParameter`] for a band with no bin below Nyquist.
    pub fn band_squared_envelopes(
        &mut self,
        x: &[f64],
        fs_hz: f64,
        bands: &[Band],
    ) -> Result<Vec<BandEnvelope>> {
        check_finite(x)?;
        check_positive("fs_hz", fs_hz)?;
        let n = x.len();
        if n < 4 {
            return Err(FeatureError::TooShort {
                needed: 4,
                found: n,
            });
        }
        let df = fs_hz / n as f64;
        let spec = self.rfft(x.to_vec())?;
        let mut out = Vec::with_capacity(bands.len());
        for &band in bands {
            let keep = band.bins(df, spec.len());
            if keep.is_empty() {
                return Err(FeatureError::InvalidParameter {
                    name: "band.low_hz",
                    value: band.low_hz,
                    reason: "the band holds no frequency bin below Nyquist",
                });
            }
            let m = smooth_size(2 * keep.len()).max(4);
            let mut z = vec![Complex::new(0.0, 0.0); m];
            for (j, k) in keep.enumerate() {
                z[j] = spec[k] * one_sided(k, n);
            }
            let inv = self.complex_inverse(m);
            inv.process(&mut z);
            let scale = 1.0 / n as f64;
            out.push(BandEnvelope {
                band,
                rate_hz: m as f64 / (n as f64 / fs_hz),
                squared_envelope: z.iter().map(|c| c.norm_sqr() * scale * scale).collect(),
            });
        }
        Ok(out)
    }

    /// Band-pass by FFT masking: zero every bin outside `band` and transform back (zero phase,
    /// brick-wall; edges ring, which is acceptable for envelope demodulation).
    ///
    /// # Errors
    /// Input errors, invalid `fs_hz`, [`FeatureError::TooShort`] below 2 samples.
    pub fn bandpass_fft(&mut self, x: &[f64], fs_hz: f64, band: Band) -> Result<Vec<f64>> {
        let n = checked_pair(x, fs_hz)?;
        let df = fs_hz / n as f64;
        let mut spec = self.rfft(x.to_vec())?;
        let keep = band.bins(df, spec.len());
        for (k, c) in spec.iter_mut().enumerate() {
            if !keep.contains(&k) {
                *c = Complex::new(0.0, 0.0);
            }
        }
        // realfft requires real DC and Nyquist bins.
        spec[0].im = 0.0;
        if n % 2 == 0 {
            spec[n / 2].im = 0.0;
        }
        let inv = self.real_inverse(n);
        let mut out = inv.make_output_vec();
        inv.process(&mut spec, &mut out)
            .map_err(|_| FeatureError::Fft { len: n })?;
        let scale = 1.0 / n as f64;
        Ok(out.into_iter().map(|v| v * scale).collect())
    }

    /// `x` (sampled at `fs_hz`) band-limited to `[0, max_hz]` and resampled at the lowest fast
    /// rate that holds that band, by truncating its spectrum: the record is cut to its largest
    /// even 7-smooth length (≤ 2 % shorter, [`smooth_floor`]), transformed, its bins above
    /// `max_hz` and its mean dropped, and the rest transformed back on `m` points (`m/2` the
    /// smallest 5-smooth count ≥ the bins kept), so the duration is kept and the rate is `m`
    /// per duration. Returns the samples and their rate, Hz. The low-frequency lines of a long,
    /// high-rate signal (a squared envelope's shaft comb) are then searched at a fraction of
    /// the cost; below `max_hz` its spectrum is the original's.
    ///
    /// # Errors
    /// Input errors, invalid `fs_hz` or `max_hz`, [`FeatureError::TooShort`] below 4 samples.
    pub fn low_pass_resample(
        &mut self,
        x: &[f64],
        fs_hz: f64,
        max_hz: f64,
    ) -> Result<(Vec<f64>, f64)> {
        check_finite(x)?;
        check_positive("fs_hz", fs_hz)?;
        check_positive("max_hz", max_hz)?;
        if x.len() < 4 {
            return Err(FeatureError::TooShort {
                needed: 4,
                found: x.len(),
            });
        }
        let n = 2 * smooth_floor(x.len() / 2);
        let duration = n as f64 / fs_hz;
        let mut spec = self.rfft(x[..n].to_vec())?;
        // bins 0..keep, never the original Nyquist bin (it would count twice off Nyquist)
        let keep = ((max_hz * duration).ceil() as usize + 1).min(spec.len() - 1);
        let half = smooth_size(keep);
        let m = 2 * half;
        let mut z = vec![Complex::new(0.0, 0.0); half + 1];
        z[1..keep.min(half + 1)].copy_from_slice(&spec[1..keep.min(half + 1)]);
        // realfft requires a real Nyquist bin
        z[half].im = 0.0;
        spec.clear();
        let inv = self.real_inverse(m);
        let mut out = inv.make_output_vec();
        inv.process(&mut z, &mut out)
            .map_err(|_| FeatureError::Fft { len: m })?;
        let scale = 1.0 / n as f64;
        Ok((
            out.into_iter().map(|v| v * scale).collect(),
            m as f64 / duration,
        ))
    }

    /// Energy of `x` inside `band` by one-sided Parseval: `(1/N) Σ_{k∈band} c_k |X_k|²`, so bands
    /// tiling `[0, fs/2]` add up to `Σ x²` (eq. 2.46 restricted to a band).
    ///
    /// # Errors
    /// Input errors, invalid `fs_hz`.
    pub fn band_energy(&mut self, x: &[f64], fs_hz: f64, band: Band) -> Result<f64> {
        check_finite(x)?;
        check_positive("fs_hz", fs_hz)?;
        let n = x.len();
        let df = fs_hz / n as f64;
        let spec = self.rfft(x.to_vec())?;
        let keep = band.bins(df, spec.len());
        Ok(spec[keep.clone()]
            .iter()
            .zip(keep)
            .map(|(c, k)| one_sided(k, n) * c.norm_sqr())
            .sum::<f64>()
            / n as f64)
    }
}

/// One-sided amplitude spectrum (see [`SpectralEngine::amplitude_spectrum`]).
///
/// # Errors
/// As the engine method.
pub fn amplitude_spectrum(x: &[f64], fs_hz: f64, taper: Taper) -> Result<Spectrum> {
    with_engine(|e| e.amplitude_spectrum(x, fs_hz, taper))
}

/// Welch PSD with Hann segments (see [`SpectralEngine::welch_psd`]).
///
/// # Errors
/// As the engine method.
pub fn welch_psd(x: &[f64], fs_hz: f64, config: WelchConfig) -> Result<Spectrum> {
    with_engine(|e| e.welch_psd(x, fs_hz, config))
}

/// Hilbert envelope (see [`SpectralEngine::hilbert_envelope`]).
///
/// # Errors
/// As the engine method.
pub fn hilbert_envelope(x: &[f64]) -> Result<Vec<f64>> {
    with_engine(|e| e.hilbert_envelope(x))
}

/// Envelope spectrum (see [`SpectralEngine::envelope_spectrum`]).
///
/// # Errors
/// As the engine method.
pub fn envelope_spectrum(
    x: &[f64],
    fs_hz: f64,
    demodulation_band: Option<Band>,
    taper: Taper,
) -> Result<Spectrum> {
    with_engine(|e| e.envelope_spectrum(x, fs_hz, demodulation_band, taper))
}

/// Band-pass by FFT masking (see [`SpectralEngine::bandpass_fft`]).
///
/// # Errors
/// As the engine method.
pub fn bandpass_fft(x: &[f64], fs_hz: f64, band: Band) -> Result<Vec<f64>> {
    with_engine(|e| e.bandpass_fft(x, fs_hz, band))
}

/// Squared envelopes in several bands (see [`SpectralEngine::band_squared_envelopes`]).
///
/// # Errors
/// As the engine method.
pub fn band_squared_envelopes(x: &[f64], fs_hz: f64, bands: &[Band]) -> Result<Vec<BandEnvelope>> {
    with_engine(|e| e.band_squared_envelopes(x, fs_hz, bands))
}

/// Band energy by Parseval (see [`SpectralEngine::band_energy`]).
///
/// # Errors
/// As the engine method.
pub fn band_energy(x: &[f64], fs_hz: f64, band: Band) -> Result<f64> {
    with_engine(|e| e.band_energy(x, fs_hz, band))
}

/// |Σ xw\[i\]·e^(−j2πf·i/fs)|²: the DFT power of an already windowed signal at any frequency f.
///
/// Four phasors, one per residue of `i` mod 4, each advanced by e^(−j4·2πf/fs): the four
/// multiply chains are independent, so they run in parallel instead of one chain waiting on
/// the previous product (≈ 3× faster on a 10 s, 12 kHz record; the phasors are renormalised
/// every 1024 samples against round-off drift).
pub fn zoom_power(xw: &[f64], fs: f64, f: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI * f / fs;
    let step = Complex::new(w.cos(), -w.sin());
    let step4 = Complex::new((4.0 * w).cos(), -(4.0 * w).sin());
    let mut ph = [
        Complex::new(1.0, 0.0),
        step,
        Complex::new((2.0 * w).cos(), -(2.0 * w).sin()),
        Complex::new((3.0 * w).cos(), -(3.0 * w).sin()),
    ];
    let mut acc = [Complex::new(0.0, 0.0); 4];
    let mut chunks = xw.chunks_exact(4);
    for (c, quad) in chunks.by_ref().enumerate() {
        for l in 0..4 {
            acc[l] += ph[l] * quad[l];
            ph[l] *= step4;
        }
        if c % 256 == 255 {
            for p in &mut ph {
                *p /= p.norm();
            }
        }
    }
    let mut total = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (l, &v) in chunks.remainder().iter().enumerate() {
        total += ph[l] * v;
    }
    total.norm_sqr()
}

/// The DFT power of one windowed signal at many frequencies within ± `half_width` Hz of one
/// centre: [`zoom_power`] at each of them to the last few bits, at the cost of about four
/// [`zoom_power`] calls however many frequencies are asked for.
///
/// The signal is shifted down by the centre, y_i = xw_i·e^(−j2π f_c i/fs), and cut into blocks
/// short enough that the remaining offset δ turns a block's samples by at most
/// [`LocalZoom::TURN`] radians from its middle: X(f_c + δ) = Σ_b e^(−jφ t_b) Σ_p (−jφ M/2)^p/p!
/// · S_(b,p), with φ = 2πδ/fs, t_b the block's middle, M its length and S_(b,p) = Σ v^p y over
/// the block (v the offset from the middle in half-blocks, |v| ≤ 1). The series stops at
/// [`LocalZoom::TERMS`], where the next term is below 3e-16 of the block's magnitude sum.
#[derive(Debug, Clone)]
pub struct LocalZoom {
    fs: f64,
    centre: f64,
    half_width: f64,
    /// Per block: its middle (in samples), its half-length M/2 and its moments S_(b,0..TERMS).
    blocks: Vec<(f64, f64, [Complex<f64>; LocalZoom::TERMS])>,
}

impl LocalZoom {
    /// Largest turn, in radians, of the offset's phase across half a block.
    pub const TURN: f64 = 0.125;
    /// Moments kept per block (0.125¹⁰/10! < 3e-16).
    pub const TERMS: usize = 10;

    /// Moments of `xw` (already windowed, sampled at `fs`) for frequencies within
    /// ± `half_width` Hz of `centre`.
    pub fn new(xw: &[f64], fs: f64, centre: f64, half_width: f64) -> Self {
        let n = xw.len();
        let hw = half_width.abs().max(1e-12 * fs);
        // half a block turns φ_max·M/2 ≤ TURN  ⇒  M ≤ TURN·fs/(π·hw)
        let m =
            ((Self::TURN * fs / (std::f64::consts::PI * hw)).floor() as usize).clamp(1, n.max(1));
        let w = 2.0 * std::f64::consts::PI * centre / fs;
        let step = Complex::new(w.cos(), -w.sin());
        let mut blocks = Vec::with_capacity(n.div_ceil(m));
        for (b, chunk) in xw.chunks(m).enumerate() {
            let start = b * m;
            let half = 0.5 * (chunk.len() as f64 - 1.0);
            let scale = if half > 0.0 { 1.0 / half } else { 0.0 };
            // the block's first phasor exactly, then advanced sample by sample (≤ a few
            // thousand products: drift far below the series' truncation)
            let turns = (centre * start as f64 / fs).fract();
            let a = -2.0 * std::f64::consts::PI * turns;
            let mut ph = Complex::new(a.cos(), a.sin());
            let mut s = [Complex::new(0.0, 0.0); Self::TERMS];
            for (i, &v) in chunk.iter().enumerate() {
                let y = ph * v;
                let u = (i as f64 - half) * scale;
                let mut up = 1.0;
                for sp in &mut s {
                    *sp += y * up;
                    up *= u;
                }
                ph *= step;
            }
            blocks.push((start as f64 + half, half, s));
        }
        LocalZoom {
            fs,
            centre,
            half_width: hw,
            blocks,
        }
    }

    /// The centre frequency the moments were taken about.
    pub fn centre(&self) -> f64 {
        self.centre
    }

    /// |Σ xw\[i\]·e^(−j2πf·i/fs)|² at `f`, which must lie within the half-width given to
    /// [`LocalZoom::new`] (beyond it the series is cut too early; debug builds assert).
    pub fn power(&self, f: f64) -> f64 {
        let d = f - self.centre;
        debug_assert!(
            d.abs() <= self.half_width * (1.0 + 1e-9),
            "{f} Hz lies outside the zoom's ± {} Hz of {} Hz",
            self.half_width,
            self.centre
        );
        let phi = 2.0 * std::f64::consts::PI * d / self.fs;
        let mut total = Complex::new(0.0, 0.0);
        for (mid, half, s) in &self.blocks {
            // Σ_p (−jφ·half)^p / p! · S_p, by Horner from the highest term
            let z = Complex::new(0.0, -phi * half);
            let mut acc = Complex::new(0.0, 0.0);
            for p in (0..Self::TERMS).rev() {
                acc = acc * z / (p + 1) as f64 + s[p];
            }
            let a = -phi * mid;
            total += Complex::new(a.cos(), a.sin()) * acc;
        }
        total.norm_sqr()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The local zoom gives the DFT power anywhere within its half-width, for records shorter
    /// than a block, a few blocks and many, centres at DC, mid-band and near Nyquist.
    #[test]
    fn local_zoom_is_the_dft_power_near_its_centre() {
        let fs = 12_000.0;
        for n in [1usize, 5, 4099, 120_001] {
            let x: Vec<f64> = (0..n)
                .map(|i| {
                    let t = i as f64 / fs;
                    (2.0 * PI * 437.3 * t).sin()
                        + 0.3 * (2.0 * PI * 1234.5 * t + 0.4).cos()
                        + ((i * 7919 % 1000) as f64) * 1e-3
                })
                .collect();
            let w = Taper::Hann.weights(n);
            let xw: Vec<f64> = x.iter().zip(&w).map(|(a, b)| a * b).collect();
            let scale = xw.iter().map(|v| v.abs()).sum::<f64>().powi(2).max(1e-300);
            for (centre, hw) in [(0.0, 0.3), (437.0, 1.0), (1234.0, 2.5), (5990.0, 9.0)] {
                let zoom = LocalZoom::new(&xw, fs, centre, hw);
                for k in -10..=10 {
                    let f = centre + hw * k as f64 / 10.0;
                    let (got, exact) = (zoom.power(f), zoom_power(&xw, fs, f));
                    assert!(
                        (got - exact).abs() <= 1e-12 * scale,
                        "n {n}, f {f}: {got} vs {exact}"
                    );
                }
            }
        }
    }

    /// A shared planner builds a length's plan from the sub-plans it already holds: after a
    /// 32 639-point spectrum, the 121 702-point Hilbert envelope of a planner that made it
    /// differs from a fresh engine's in most samples (last bits). The free functions' engine
    /// keeps its plans independent, so their result does not depend on what ran before them.
    #[test]
    fn free_functions_give_a_fresh_engines_bits_whatever_ran_before() {
        let sig = |n: usize| -> Vec<f64> {
            (0..n)
                .map(|i| (i as f64 * 0.123).sin() + ((i * 7919 % 1000) as f64) * 1e-3)
                .collect()
        };
        let (before, x) = (sig(32_639), sig(121_702));
        let fresh = SpectralEngine::new().hilbert_envelope(&x).unwrap();
        let mut shared = SpectralEngine::new();
        shared
            .amplitude_spectrum(&before, 12_000.0, Taper::Rectangular)
            .unwrap();
        let after_shared = shared.hilbert_envelope(&x).unwrap();
        let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
        // the premise: with a shared planner the order matters
        assert_ne!(bits(&after_shared), bits(&fresh));
        amplitude_spectrum(&before, 12_000.0, Taper::Rectangular).unwrap();
        let free = hilbert_envelope(&x).unwrap();
        assert_eq!(bits(&free), bits(&fresh));
    }

    /// 2 + 0.7 cos 2π·25t + cos 2π·2000t at 10 kHz, 4 s, band-limited to 100 Hz: the mean and
    /// the 2 kHz tone go, the 25 Hz line is kept sample for sample at the new rate, and the
    /// duration is the record's.
    #[test]
    fn low_pass_resample_keeps_the_low_lines_and_the_duration() {
        let fs = 10_000.0;
        let n = 40_000;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                2.0 + 0.7 * (2.0 * PI * 25.0 * t).cos() + (2.0 * PI * 2000.0 * t).cos()
            })
            .collect();
        let (y, rate) = SpectralEngine::new()
            .low_pass_resample(&x, fs, 100.0)
            .unwrap();
        assert!((200.0..260.0).contains(&rate), "{rate}");
        assert!(
            (y.len() as f64 / rate - 4.0).abs() < 1e-9,
            "{} {rate}",
            y.len()
        );
        for (m, v) in y.iter().enumerate() {
            let want = 0.7 * (2.0 * PI * 25.0 * m as f64 / rate).cos();
            assert!((v - want).abs() < 1e-9, "{m}: {v} vs {want}");
        }
        let mut e = SpectralEngine::new();
        assert!(e.low_pass_resample(&x, fs, 0.0).is_err());
        assert!(e.low_pass_resample(&x[..3], fs, 100.0).is_err());
        assert!(
            e.low_pass_resample(&[1.0, f64::NAN, 0.0, 1.0], fs, 100.0)
                .is_err()
        );
    }

    #[test]
    fn band_squared_envelope_of_am_tone() {
        // (1 + 0.5 cos 2π·10t) cos 2π·1000t: squared envelope (1 + 0.5 cos 2π·10t)².
        let fs = 8000.0;
        let n = 8000;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                (1.0 + 0.5 * (2.0 * PI * 10.0 * t).cos()) * (2.0 * PI * 1000.0 * t).cos()
            })
            .collect();
        let band = Band::new(800.0, 1200.0).unwrap();
        let e = band_squared_envelopes(&x, fs, &[band]).unwrap();
        let e = &e[0];
        assert!(e.rate_hz >= 800.0 && e.rate_hz < 1000.0, "{}", e.rate_hz);
        for (m, v) in e.squared_envelope.iter().enumerate() {
            let t = m as f64 / e.rate_hz;
            let want = (1.0 + 0.5 * (2.0 * PI * 10.0 * t).cos()).powi(2);
            assert!((v - want).abs() < 1e-9, "{m}: {v} vs {want}");
        }
        // the same as band-pass + Hilbert envelope, squared, at full rate
        let full = hilbert_envelope(&bandpass_fft(&x, fs, band).unwrap()).unwrap();
        assert!((full[0] * full[0] - e.squared_envelope[0]).abs() < 1e-9);
        assert!(smooth_size(7) == 8 && smooth_size(31) == 32 && smooth_size(121) == 125);
        assert!(smooth_floor(11) == 10 && smooth_floor(31) == 30 && smooth_floor(1) == 1);
        assert_eq!(smooth_floor(119_992), 119_070);
        for n in (10_000usize..1_100_000).step_by(997) {
            let m = smooth_floor(n);
            assert!(
                m <= n && 50 * (n - m) <= n && is_smooth(m, &[2, 3, 5, 7]),
                "{n} -> {m}"
            );
        }
        assert!(band_squared_envelopes(&x, fs, &[Band::new(5000.0, 6000.0).unwrap()]).is_err());
    }
}
