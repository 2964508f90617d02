//! Shared helpers for the integration tests: reference plants with known truth.
#![allow(dead_code)]

use observers::named::{per_sample_bound_levant, per_sample_bound_super_twisting};
use observers::scenarios::{ArxPlant, OscillatorPlant, reference_arx_model};
use observers::*;
use std::f64::consts::PI;

/// Test mode: 500 Hz, ζ = 0.05, sampled at 12 kHz (ωT = 0.26).
pub fn mode() -> ModalParams {
    ModalParams {
        natural_frequency_hz: 500.0,
        damping_ratio: 0.05,
        input_gain: 0.0,
        sample_rate_hz: 12_000.0,
    }
}

/// Disturbance scale: ω², so that |X₁| ~ |d|/ω² ~ 1.
pub fn amp() -> f64 {
    let w = mode().omega();
    w * w
}

/// A smooth bounded disturbance d(k) = A (c0 + a1 sin(2π f1 k T + φ)).
#[derive(Debug, Clone, Copy)]
pub struct Smooth {
    pub c0: f64,
    pub a1: f64,
    pub f1: f64,
    pub phase: f64,
}

impl Smooth {
    pub fn at(&self, k: usize) -> f64 {
        let t = k as f64 * mode().dt();
        amp() * (self.c0 + self.a1 * (2.0 * PI * self.f1 * t + self.phase).sin())
    }
    pub fn max_abs(&self) -> f64 {
        amp() * (self.c0.abs() + self.a1)
    }
    pub fn max_rate(&self) -> f64 {
        amp() * self.a1 * 2.0 * PI * self.f1
    }
}

/// The per-sample bound Γ each law family is designed for on the physics chain
/// (Levant: |ḋ| T³, and at least |d| T²/300 so that the initial fault-estimate error is
/// reached in ~300 samples; others: |d| T²), with a 20 % margin; a floor keeps it positive.
pub fn physics_bound(kind: ObserverKind, d: &Smooth) -> f64 {
    let t = mode().dt();
    let g = match kind.family() {
        LawFamily::Levant => per_sample_bound_levant(d.max_rate(), t)
            .max(per_sample_bound_super_twisting(d.max_abs(), t) / 300.0),
        _ => per_sample_bound_super_twisting(d.max_abs(), t),
    };
    1.2 * g.max(1e-6)
}

/// Simulate the oscillator from (x1, x2) with disturbance `d`; returns y.
pub fn oscillator_record(x1: f64, x2: f64, n: usize, d: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut p = OscillatorPlant::new(&mode()).unwrap();
    p.set_state(x1, x2);
    p.simulate(n, d)
}

/// Reference ARX-Laguerre plant with input u(k) = sin(0.05k) + 0.5 sin(0.31k), fault δ along
/// b_u, initial state `x0`.
pub fn arx_record(x0: &[f64], n: usize, delta: impl Fn(usize) -> f64) -> (Vec<f64>, Vec<f64>) {
    let model = reference_arx_model();
    let f = FaultDirection::Input.vector(&model);
    let mut p = ArxPlant::new(&model, &f).unwrap();
    p.set_state(x0);
    p.simulate(
        n,
        |k| (k as f64 * 0.05).sin() + 0.5 * (k as f64 * 0.31).sin(),
        delta,
    )
}

pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}
