//! Test helpers: a small envelope-spectrum analyser (FFT band-pass, Hilbert envelope, FFT).

#![allow(dead_code)]

use rustfft::{FftPlanner, num_complex::Complex};

/// Envelope spectrum of `x` (sampled at `fs`) after an ideal FFT band-pass `[lo, hi]` Hz.
/// Returns (frequency resolution, magnitude per bin up to fs/2).
pub fn envelope_spectrum(x: &[f64], fs: f64, lo: f64, hi: f64) -> (f64, Vec<f64>) {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let mut planner = FftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v - mean, 0.0)).collect();
    fwd.process(&mut buf);
    // analytic signal restricted to the band: keep positive band bins doubled, zero the rest
    for (k, b) in buf.iter_mut().enumerate() {
        let f = k as f64 * fs / n as f64;
        let keep = k > 0 && k < n.div_ceil(2) && f >= lo && f <= hi;
        *b = if keep {
            *b * 2.0
        } else {
            Complex::new(0.0, 0.0)
        };
    }
    inv.process(&mut buf);
    let env: Vec<f64> = buf.iter().map(|c| c.norm() / n as f64).collect();
    let em = env.iter().sum::<f64>() / n as f64;
    let mut e: Vec<Complex<f64>> = env.iter().map(|&v| Complex::new(v - em, 0.0)).collect();
    fwd.process(&mut e);
    let mags: Vec<f64> = e[..n / 2].iter().map(|c| c.norm() / n as f64).collect();
    (fs / n as f64, mags)
}

/// Largest magnitude within ±`tol_hz` of `f`.
pub fn peak_near(df: f64, mags: &[f64], f: f64, tol_hz: f64) -> f64 {
    let lo = ((f - tol_hz) / df).floor().max(0.0) as usize;
    let hi = (((f + tol_hz) / df).ceil() as usize).min(mags.len() - 1);
    mags[lo..=hi].iter().cloned().fold(0.0, f64::max)
}

/// Median magnitude in `[a, b]` Hz (a background level).
pub fn median_in(df: f64, mags: &[f64], a: f64, b: f64) -> f64 {
    let lo = (a / df).floor().max(1.0) as usize;
    let hi = ((b / df).ceil() as usize).min(mags.len() - 1);
    let mut v: Vec<f64> = mags[lo..=hi].to_vec();
    v.sort_by(|x, y| x.partial_cmp(y).unwrap());
    v[v.len() / 2]
}

/// Frequency (Hz) of the largest bin in `[a, b]`.
pub fn argmax_in(df: f64, mags: &[f64], a: f64, b: f64) -> f64 {
    let lo = (a / df).floor().max(1.0) as usize;
    let hi = ((b / df).ceil() as usize).min(mags.len() - 1);
    let mut best = lo;
    for k in lo..=hi {
        if mags[k] > mags[best] {
            best = k;
        }
    }
    best as f64 * df
}

/// RMS of a slice.
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// Welch PSD (Hann, 50 % overlap, one-sided, unnormalised scale: ratios only) with `n` samples
/// per segment; bin k is at k·fs/n.
#[allow(dead_code)]
pub fn welch(x: &[f64], n: usize) -> Vec<f64> {
    let fft = FftPlanner::new().plan_fft_forward(n);
    let w: Vec<f64> = (0..n)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos())
        .collect();
    let mut acc = vec![0.0; n / 2 + 1];
    let mut start = 0;
    while start + n <= x.len() {
        let mut buf: Vec<Complex<f64>> = (0..n)
            .map(|i| Complex::new(x[start + i] * w[i], 0.0))
            .collect();
        fft.process(&mut buf);
        for (a, c) in acc.iter_mut().zip(&buf) {
            *a += c.norm_sqr();
        }
        start += n / 2;
    }
    acc
}
