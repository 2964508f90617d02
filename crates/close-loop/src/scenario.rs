//! Reference scenarios for tests, benches and examples: a phenomenological bearing-vibration model
//! (McFadden & Smith 1984; Randall & Antoni 2011, MSSP 25: an impact train at the defect rate,
//! load-zone or cage modulated, ringing a structural resonance, plus a 1× shaft line, ball-pass
//! lines and a broadband background), and helpers that add an undeclared effect to a signal.

use crate::effect::{CoherentLine, Mode, Modulation};
use crate::{CloseLoopError, DeclaredFault, DeclaredModel, OperatingPoint};
use std::f64::consts::PI;

use rand::{RngCore, SeedableRng};
/// SplitMix64 (Steele, Lea & Flood 2014), the workspace's seeded generator of noise and splits
/// (the loop's noise, the rig's synthesis; `classify`'s window splits use the same), from
/// `rand_xoshiro` (rust-random): 64-bit state, a stream specified bit for bit, identical output
/// on every platform. `SplitMix64::seed_from_u64(s)` starts the state at `s`.
pub use rand_xoshiro::SplitMix64;

/// Deterministic normal generator ([`SplitMix64`] + Box–Muller).
#[derive(Debug, Clone)]
pub struct Gaussian {
    bits: SplitMix64,
    spare: Option<f64>,
}

impl Gaussian {
    /// Seeded generator.
    pub fn new(seed: u64) -> Self {
        Self {
            bits: SplitMix64::seed_from_u64(seed ^ 0x9E37_79B9_7F4A_7C15),
            spare: None,
        }
    }

    fn next_u64(&mut self) -> u64 {
        self.bits.next_u64()
    }

    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal sample.
    pub fn sample(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u1, u2) = (self.uniform(), self.uniform());
        let r = (-2.0 * u1.ln()).sqrt();
        self.spare = Some(r * (2.0 * PI * u2).sin());
        r * (2.0 * PI * u2).cos()
    }
}

/// The phenomenological model's parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct PhenomenologicalModel {
    /// Structural resonance rung by the impacts, Hz.
    pub resonance_hz: f64,
    /// Its damping ratio.
    pub damping_ratio: f64,
    /// Impact amplitude (force units; the output is the resonator response).
    pub impact_amplitude: f64,
    /// Load-zone (inner: at fr) or cage (ball: at FTF) modulation depth of the impacts.
    pub modulation_depth: f64,
    /// Relative random jitter of the impact spacing (slip), e.g. 0.002.
    pub jitter: f64,
    /// Amplitude of the 1× shaft line at the sensor.
    pub shaft_amplitude: f64,
    /// Amplitude of the ball-pass (BPFO) line at the sensor; harmonic k has amplitude/k (k ≤ 3).
    pub ball_pass_amplitude: f64,
    /// Standard deviation of the broadband force that rings the resonance.
    pub background: f64,
    /// Seed of the random parts.
    pub seed: u64,
}

impl Default for PhenomenologicalModel {
    fn default() -> Self {
        Self {
            resonance_hz: 2600.0,
            damping_ratio: 0.04,
            impact_amplitude: 1.0,
            modulation_depth: 0.5,
            jitter: 0.001,
            shaft_amplitude: 0.02,
            ball_pass_amplitude: 0.01,
            background: 0.02,
            seed: 1,
        }
    }
}

impl PhenomenologicalModel {
    /// The same model with another seed (an independent realisation).
    pub fn with_seed(&self, seed: u64) -> Self {
        Self {
            seed,
            ..self.clone()
        }
    }

    fn resonator(&self, fs: f64) -> (f64, f64) {
        let wn = 2.0 * PI * self.resonance_hz / fs;
        let r = (-self.damping_ratio * wn).exp();
        let wd = wn * (1.0 - self.damping_ratio * self.damping_ratio).sqrt();
        (2.0 * r * wd.cos(), -r * r)
    }
}

impl DeclaredModel for PhenomenologicalModel {
    fn name(&self) -> &str {
        "phenomenological"
    }

    fn simulate(&self, op: &OperatingPoint, n: usize, fs: f64) -> Result<Vec<f64>, CloseLoopError> {
        if !(fs.is_finite() && fs > 0.0) {
            return Err(CloseLoopError::InvalidSamplingRate { fs });
        }
        if !(op.rpm.is_finite() && op.rpm > 0.0) {
            return Err(CloseLoopError::InvalidRpm { rpm: op.rpm });
        }
        if !(self.resonance_hz > 0.0 && self.resonance_hz < 0.5 * fs) {
            return Err(CloseLoopError::ParameterOutOfRange {
                name: "resonance_hz",
                value: self.resonance_hz,
                min: 0.0,
                max: 0.5 * fs,
            });
        }
        let mut rng = Gaussian::new(self.seed);
        let fr = op.shaft_hz();
        let mut force: Vec<f64> = (0..n).map(|_| self.background * rng.sample()).collect();
        if let Some(&order) = crate::impact_orders(op.fault, &op.bearing).first() {
            let rate = order * fr;
            let fm = match op.fault {
                DeclaredFault::Inner => fr,
                DeclaredFault::Ball => op.bearing.orders.ftf * fr,
                _ => 0.0,
            };
            let depth = if fm > 0.0 { self.modulation_depth } else { 0.0 };
            let mut k = 0u64;
            loop {
                let t = (k as f64 + self.jitter * rng.sample()) / rate;
                let pos = t * fs;
                if pos >= (n - 1) as f64 {
                    break;
                }
                if pos >= 0.0 {
                    let amp = self.impact_amplitude * (1.0 + depth * (2.0 * PI * fm * t).cos());
                    let i = pos.floor() as usize;
                    let frac = pos - i as f64;
                    force[i] += amp * (1.0 - frac);
                    force[i + 1] += amp * frac;
                }
                k += 1;
            }
        }
        let (a1, a2) = self.resonator(fs);
        let (mut y1, mut y2) = (0.0, 0.0);
        let mut out: Vec<f64> = force
            .iter()
            .map(|&f| {
                let y = f + a1 * y1 + a2 * y2;
                y2 = y1;
                y1 = y;
                y
            })
            .collect();
        let w = 2.0 * PI / fs;
        let bpfo = op.bearing.orders.bpfo * fr;
        for (i, o) in out.iter_mut().enumerate() {
            let t = i as f64;
            *o += self.shaft_amplitude * (w * fr * t + 0.3).cos();
            for h in 1..=3 {
                *o += self.ball_pass_amplitude / h as f64
                    * (w * bpfo * h as f64 * t + 0.7 * h as f64).cos();
            }
        }
        Ok(out)
    }
}

/// Add white sensor noise of standard deviation `sigma`.
pub fn add_noise(x: &mut [f64], sigma: f64, seed: u64) {
    let mut g = Gaussian::new(seed);
    for v in x.iter_mut() {
        *v += sigma * g.sample();
    }
}

/// Add a line amplitude·cos(2πft + phase).
pub fn add_tone(x: &mut [f64], fs: f64, frequency_hz: f64, amplitude: f64, phase: f64) {
    let line = CoherentLine {
        frequency_hz,
        a: amplitude * phase.cos(),
        b: -amplitude * phase.sin(),
    };
    line.add_to(x, 0, fs);
}

/// Add a parallel mode (see [`Mode`]).
pub fn add_mode(x: &[f64], fs: f64, frequency_hz: f64, damping_ratio: f64, gain: f64) -> Vec<f64> {
    Mode {
        frequency_hz,
        damping_ratio,
        gain,
    }
    .apply(x, fs)
}

/// Amplitude-modulate at `frequency_hz` with depth `depth`.
pub fn modulate(x: &[f64], fs: f64, frequency_hz: f64, depth: f64) -> Vec<f64> {
    Modulation {
        frequency_hz,
        depth,
    }
    .apply(x, 0, fs)
}
