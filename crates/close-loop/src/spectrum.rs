//! Spectral estimators the loop looks through: Welch PSD, analytic-signal envelope, zoom DFT, and
//! the digital band-pass mode used by the `resonance` effect.

use crate::CloseLoopError;
use realfft::{RealFftPlanner, RealToComplex};
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use std::f64::consts::PI;
use std::sync::Arc;

/// Welch power spectral density (Welch 1967): periodic Hann window, 50 % overlap, per-segment
/// mean removal, one-sided density scaling (units²/Hz), so that Σ S·Δf ≈ variance.
#[derive(Clone)]
pub struct Welch {
    fs: f64,
    nperseg: usize,
    window: Vec<f64>,
    scale: f64,
    fft: Arc<dyn RealToComplex<f64>>,
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
        let window: Vec<f64> = (0..nperseg)
            .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / nperseg as f64).cos())
            .collect();
        let s2: f64 = window.iter().map(|w| w * w).sum();
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(nperseg);
        Ok(Self {
            fs,
            nperseg,
            window,
            scale: 1.0 / (fs * s2),
            fft,
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

    /// The PSD of `x`. A signal shorter than one segment is zero-padded into a single segment.
    pub fn psd(&self, x: &[f64]) -> Vec<f64> {
        let n = self.nperseg;
        let hop = n / 2;
        let mut acc = vec![0.0; n / 2 + 1];
        let mut input = self.fft.make_input_vec();
        let mut out = self.fft.make_output_vec();
        let mut scratch = self.fft.make_scratch_vec();
        let mut count = 0usize;
        let mut start = 0usize;
        loop {
            let end = (start + n).min(x.len());
            let seg = &x[start.min(x.len())..end];
            let mean = if seg.is_empty() {
                0.0
            } else {
                seg.iter().sum::<f64>() / seg.len() as f64
            };
            for (i, v) in input.iter_mut().enumerate() {
                *v = seg.get(i).map_or(0.0, |s| (s - mean) * self.window[i]);
            }
            let _ = self
                .fft
                .process_with_scratch(&mut input, &mut out, &mut scratch);
            for (a, c) in acc.iter_mut().zip(&out) {
                *a += c.norm_sqr();
            }
            count += 1;
            start += hop;
            if start + n > x.len() {
                break;
            }
        }
        let last = n / 2;
        for (k, a) in acc.iter_mut().enumerate() {
            let two = if k == 0 || k == last { 1.0 } else { 2.0 };
            *a *= two * self.scale / count as f64;
        }
        acc
    }
}

/// Hilbert envelope |x + j·H{x}| of the mean-removed signal (analytic signal by FFT).
pub fn envelope(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n == 0 {
        return Vec::new();
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let mut planner = FftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v - mean, 0.0)).collect();
    fwd.process(&mut buf);
    for (k, c) in buf.iter_mut().enumerate().skip(1) {
        let h = match (2 * k).cmp(&n) {
            std::cmp::Ordering::Less => 2.0,
            std::cmp::Ordering::Equal => 1.0,
            std::cmp::Ordering::Greater => 0.0,
        };
        *c *= h;
    }
    inv.process(&mut buf);
    buf.iter().map(|c| c.norm() / n as f64).collect()
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

/// |Σ xw[i]·e^(−j2πf·i/fs)|²: the DFT power of an already windowed signal at any frequency f.
pub fn zoom_power(xw: &[f64], fs: f64, f: f64) -> f64 {
    let w = 2.0 * PI * f / fs;
    let step = Complex::new(w.cos(), -w.sin());
    let mut ph = Complex::new(1.0, 0.0);
    let mut acc = Complex::new(0.0, 0.0);
    for (i, &v) in xw.iter().enumerate() {
        acc += ph * v;
        ph *= step;
        if i % 1024 == 1023 {
            // renormalise the phasor against round-off drift
            ph /= ph.norm();
        }
    }
    acc.norm_sqr()
}

/// The frequency in `[lo, hi]` where [`zoom_power`] is largest: a grid of step `fs/(4·len)`
/// (a quarter of the DFT bin, finer than the Hann main lobe) then golden-section refinement.
pub fn refine_peak(xw: &[f64], fs: f64, lo: f64, hi: f64) -> f64 {
    let step = fs / (4.0 * xw.len().max(1) as f64);
    let n_grid = (((hi - lo) / step).ceil() as usize).clamp(2, 4000);
    let step = (hi - lo) / n_grid as f64;
    let mut best = (lo, f64::NEG_INFINITY);
    for i in 0..=n_grid {
        let f = lo + step * i as f64;
        let p = zoom_power(xw, fs, f);
        if p > best.1 {
            best = (f, p);
        }
    }
    let (f, _) = crate::optimize::golden_max(
        |f| zoom_power(xw, fs, f),
        (best.0 - step).max(lo),
        (best.0 + step).min(hi),
        30,
    );
    f
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
