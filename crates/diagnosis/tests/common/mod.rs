//! Helpers shared by the integration tests: synthetic signal parts (white noise, impact trains
//! ringing a resonance, line combs) and a one-glance print of a diagnosis.
#![allow(dead_code)]

use diagnosis::Diagnosis;

/// `x` at `fs` Hz as a checked signal (the tests' recordings are finite and non-empty).
pub fn sig(x: &[f64], fs: f64) -> diagnosis::Signal<'_> {
    diagnosis::Signal::new(x, fs).unwrap()
}

/// Prints what a diagnosis rests on (stderr, shown for a failing test): the verdict, the
/// speed used and how it was found, and per hypothesis its probability under "healthy", the
/// modulation depth of its harmonics, its band, and whether a stronger fault explains it.
pub fn show(what: &str, d: &Diagnosis) {
    let sp = d.operating_point.speed.as_ref();
    eprintln!(
        "{what}: {} (p_healthy {:.1e}; candidates {:?}) at {:.1} rpm ({:?}, ± {:.2} %, read {:?})",
        d.verdict,
        d.p_healthy,
        d.candidates,
        d.operating_point.rpm_used,
        sp.map(|s| s.source),
        sp.map_or(0.0, |s| 100.0 * s.relative_uncertainty),
        sp.and_then(|s| s.read_at),
    );
    for e in &d.evidence {
        let Some(s) = e.significance.as_ref() else {
            continue;
        };
        eprintln!(
            "   {:<5} p {:.1e} (band {:.1e}) depth {:.2} band {:.0}-{:.0} f1/F {:.4} ρ {:.4} lines {} null {} masks [{}{}{}] {}{}{}: {}",
            e.hypothesis.name(),
            s.p_healthy,
            s.p_band,
            s.modulation_depth,
            s.band_hz[0],
            s.band_hz[1],
            s.fundamental_hz / e.fault_hz,
            s.speed_ratio,
            s.lines_read,
            s.null_size,
            if s.masks.shaft_orders { "k·fr " } else { "" },
            if s.masks.half_orders {
                "(k+½)·fr "
            } else {
                ""
            },
            s.masks
                .mains_hz
                .map_or(String::new(), |m| format!("mains {m} Hz")),
            if s.significant { "significant" } else { "-" },
            s.p_given_stronger
                .map_or(String::new(), |p| format!(" p|stronger {p:.1e}")),
            s.explained_by
                .map_or(String::new(), |h| format!(" explained by {}", h.name())),
            e.harmonics
                .iter()
                .chain(&e.sidebands)
                .map(|l| format!("{} {:.1}", l.label, l.evidence_db))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
}

/// The reading of hypothesis `name` (`inner`, `outer`, `ball`).
pub fn significance<'a>(d: &'a Diagnosis, name: &str) -> &'a diagnosis::Significance {
    d.evidence
        .iter()
        .find(|e| e.hypothesis.name() == name)
        .and_then(|e| e.significance.as_ref())
        .expect("every hypothesis has a reading")
}

/// Adds a train of decaying ring-downs to `x` (one fault's impacts seen through a resonance):
/// impacts at `rate_hz`, each interval scaled by (1 + `jitter`·z), z standard normal from `rng`
/// (no draw when `jitter` is 0), each impact a `resonance_hz` sine decaying with damping `zeta`
/// over `ring_s` seconds, of amplitude `amplitude(t0)` at impact time t0.
#[allow(clippy::too_many_arguments)]
pub fn ring_downs(
    x: &mut [f64],
    fs: f64,
    rate_hz: f64,
    resonance_hz: f64,
    zeta: f64,
    ring_s: f64,
    jitter: f64,
    rng: &mut rand_chacha::ChaCha8Rng,
    amplitude: impl Fn(f64) -> f64,
) {
    use rand::Rng;
    use rand_distr::StandardNormal;
    let w = 2.0 * std::f64::consts::PI * resonance_hz;
    let mut t0 = 0.0;
    while t0 < x.len() as f64 / fs {
        let k0 = (t0 * fs).ceil() as usize;
        let a = amplitude(t0);
        for (k, v) in x
            .iter_mut()
            .enumerate()
            .skip(k0)
            .take((ring_s * fs) as usize)
        {
            let t = k as f64 / fs - t0;
            *v += a * (-zeta * w * t).exp() * (w * t).sin();
        }
        t0 += if jitter == 0.0 {
            1.0 / rate_hz
        } else {
            (1.0 + jitter * rng.sample::<f64, _>(StandardNormal)) / rate_hz
        };
    }
}

/// `n` samples of white Gaussian noise of standard deviation `sigma`, drawn from `rng`.
pub fn white(n: usize, sigma: f64, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
    use rand::Rng;
    use rand_distr::StandardNormal;
    (0..n)
        .map(|_| sigma * rng.sample::<f64, _>(StandardNormal))
        .collect()
}

/// Adds harmonics h = 1..=`count` of `f0` to `x`, of amplitude `amp(h)` and phase `phase(h)`.
pub fn add_comb(
    x: &mut [f64],
    fs: f64,
    f0: f64,
    count: usize,
    amp: impl Fn(f64) -> f64,
    phase: impl Fn(f64) -> f64,
) {
    for (k, v) in x.iter_mut().enumerate() {
        let t = k as f64 / fs;
        for h in 1..=count {
            let h = h as f64;
            *v += amp(h) * (2.0 * std::f64::consts::PI * h * f0 * t + phase(h)).cos();
        }
    }
}
