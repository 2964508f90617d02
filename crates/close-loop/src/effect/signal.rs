//! The parametric forms a fitted effect applies — a phase-coherent line, a parallel mode, an
//! amplitude modulation — to a time signal or a PSD, and the search bounds of their parameters.

use crate::spectrum::{bandpass_coefficients, biquad_filter, biquad_response};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A phase-coherent line a·cos(2πft) + b·sin(2πft), t = sample index / fs from the recording start.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoherentLine {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Cosine coefficient.
    pub a: f64,
    /// Sine coefficient.
    pub b: f64,
}

/// The former name of [`CoherentLine`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed to `CoherentLine`: a phase-coherent line a·cos + b·sin at a frequency in Hz \
            (other crates' lines are `diagnosis::SearchedLine` and \
            `bearing_model::machine::OrderTone`)"
)]
pub type Line = CoherentLine;

impl CoherentLine {
    /// Amplitude √(a² + b²).
    pub fn amplitude(&self) -> f64 {
        self.a.hypot(self.b)
    }

    /// Phase φ of amplitude·cos(2πft − φ), rad.
    pub fn phase(&self) -> f64 {
        self.b.atan2(self.a)
    }

    /// Add the line to `out`, whose first sample is sample `start` of the recording.
    pub fn add_to(&self, out: &mut [f64], start: usize, fs: f64) {
        let w = 2.0 * PI * self.frequency_hz / fs;
        // phasor recurrence e^{jω(k+1)} = e^{jωk}·e^{jω}, re-anchored exactly every 256 samples
        let (sw, cw) = w.sin_cos();
        for (j, chunk) in out.chunks_mut(256).enumerate() {
            let (mut s, mut c) = (w * (start + 256 * j) as f64).sin_cos();
            for o in chunk.iter_mut() {
                *o += self.a * c + self.b * s;
                (s, c) = (s * cw + c * sw, c * cw - s * sw);
            }
        }
    }
}

/// A mode added in parallel to the channel: y = x + c·BP(x), BP a unit-peak band-pass at f0, ζ.
/// Its power gain is G(f) = |1 + c·BP(e^{jω})|²; c > 0 adds a resonance, −1 < c < 0 cuts one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Centre frequency f0, Hz.
    pub frequency_hz: f64,
    /// Damping ratio ζ.
    pub damping_ratio: f64,
    /// Parallel gain c (peak power gain (1 + c)²).
    pub gain: f64,
}

impl Mode {
    /// Power gain G(f) at `f`.
    pub fn power_gain(&self, f: f64, fs: f64) -> f64 {
        let (b, a) = bandpass_coefficients(self.frequency_hz, self.damping_ratio, fs);
        (biquad_response(&b, &a, f, fs) * self.gain + 1.0).norm_sqr()
    }

    /// Multiply the PSD `psd` (bin k at k·`df`) by the power gains of `modes`.
    pub fn shape_psd(modes: &[Mode], psd: &mut [f64], df: f64, fs: f64) {
        if modes.is_empty() {
            return;
        }
        for (k, v) in psd.iter_mut().enumerate() {
            let f = k as f64 * df;
            for m in modes {
                *v *= m.power_gain(f, fs);
            }
        }
    }

    /// Apply the mode to a time signal.
    pub fn apply(&self, x: &[f64], fs: f64) -> Vec<f64> {
        let (b, a) = bandpass_coefficients(self.frequency_hz, self.damping_ratio, fs);
        let bp = biquad_filter(&b, &a, x);
        x.iter().zip(bp).map(|(v, p)| v + self.gain * p).collect()
    }
}

/// Amplitude modulation x·(1 + μ·cos(2π·fm·t)) of the modelled vibration.
/// Its PSD is S(f) + μ²/4·(S(f − fm) + S(f + fm)) (autocorrelation R_x(τ)·(1 + μ²/2·cos 2πf_mτ)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Modulation {
    /// Modulation rate fm, Hz.
    pub frequency_hz: f64,
    /// Depth μ (0 ≤ μ ≤ 1).
    pub depth: f64,
}

impl Modulation {
    /// Apply the modulation to a time signal whose first sample is sample `start`.
    pub fn apply(&self, x: &[f64], start: usize, fs: f64) -> Vec<f64> {
        let w = 2.0 * PI * self.frequency_hz / fs;
        x.iter()
            .enumerate()
            .map(|(i, v)| v * (1.0 + self.depth * (w * (start + i) as f64).cos()))
            .collect()
    }

    /// The modulated PSD on a uniform grid of step `df` (one-sided; S(−f) = S(f)).
    pub fn apply_psd(&self, s: &[f64], df: f64) -> Vec<f64> {
        let mu2 = self.depth * self.depth;
        let shift = self.frequency_hz / df;
        let at = |x: f64| -> f64 {
            let x = x.abs();
            let i = x.floor() as usize;
            if i + 1 >= s.len() {
                return 0.0;
            }
            let t = x - i as f64;
            s[i] * (1.0 - t) + s[i + 1] * t
        };
        (0..s.len())
            .map(|k| {
                let k = k as f64;
                s[k as usize] + mu2 / 4.0 * (at(k - shift) + at(k + shift))
            })
            .collect()
    }
}

/// Largest damping ratio a fitted mode may take.
pub const MODE_MAX_DAMPING: f64 = 0.7;
/// Smallest damping ratio a fitted mode may take (the damping search's lower bound).
pub const MODE_MIN_DAMPING: f64 = 0.001;
/// Gain range of a fitted mode: a bump up to +200 (46 dB), a notch down to −0.97 (−30 dB).
pub const MODE_GAIN_RANGE: (f64, f64) = (-0.97, 200.0);

/// Largest modulation depth (a full modulation of the structural vibration).
pub const MODULATION_MAX_DEPTH: f64 = 1.0;

/// Whether a modulation's depth reached [`MODULATION_MAX_DEPTH`]: the envelope's modulation
/// index asked for more than a full modulation of the structural vibration gives, so the depth is
/// a lower bound. (Until 2026-11-26 the depth was fitted on the spectral distance and 30–50 %
/// modulations came back at 0.99999.)
pub fn depth_at_bound(m: &Modulation) -> bool {
    m.depth >= 0.99 * MODULATION_MAX_DEPTH
}

/// Whether a fitted mode's damping or gain sits at its search bound (within 1 %): the data did
/// not pin it, and the "mode" is a broad correction of the spectral shape, not a resonance.
pub fn mode_at_bound(mode: &Mode) -> bool {
    mode.damping_ratio >= 0.99 * MODE_MAX_DAMPING
        || mode.gain >= 0.99 * MODE_GAIN_RANGE.1
        || mode.gain <= 0.99 * MODE_GAIN_RANGE.0
}
