//! Synthesis of a rig recording ([`Synthesis`], [`RigModel::synthesize`]): the healthy
//! machine's background, the fault signal behind the strike gate, the random part and the impact
//! path, and the filters and lines they are made with.

use super::{
    Bearing, CloseLoopError, FaultClass, Gaussian, Location, MachineLine, MachineModel, PI,
    RigModel, bad, excitation,
};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Mean length of a burst of the strike gate, in fault periods (1 / fault rate): a few impacts
/// strike in a row, then the defect is off the track for a while; the gate's on/off switching
/// spreads the fault line's power over a few hertz around it, where the envelope spectrum's
/// neighbours of the line are judged.
pub const BURST_PERIODS: f64 = 4.0;

/// Settling samples discarded before a synthesized recording (path start-up).
pub(super) const WARMUP: usize = 4096;

/// What to synthesize.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Synthesis {
    /// Fault class (any combination: the spalls superpose in the 5-DOF model).
    pub class: FaultClass,
    /// Spall width, mm (ignored for [`FaultClass::None`]).
    pub size_mm: f64,
    /// Nominal shaft speed, rpm (the rig's calibrated speed ratio is applied).
    pub rpm: f64,
    /// Outer-race spall position, rad from +x towards +y (6 o'clock = −π/2).
    pub outer_angle_rad: f64,
    /// Samples to produce.
    pub n: usize,
    /// Seed of every random draw (excitation noise, line phases, slip).
    pub seed: u64,
    /// Seed of the spalls' 5-DOF excitations (their slip draws) when it differs from `seed`
    /// (`None`: `seed`). Recordings of several fault classes at one operating point that give
    /// the same value here share each spall's excitation — a combined fault is then the
    /// superposition of the very spalls of the single-fault recordings — while their
    /// background, strike gate and random part stay independent (their own `seed`); with an
    /// [`ExcitationCache`] each excitation is simulated once.
    pub excitation_seed: Option<u64>,
}

impl Synthesis {
    /// `class` with a spall of `size_mm` at `rpm`, outer race at 6 o'clock.
    pub fn new(class: FaultClass, size_mm: f64, rpm: f64, n: usize, seed: u64) -> Self {
        Self {
            class,
            size_mm,
            rpm,
            outer_angle_rad: -PI / 2.0,
            n,
            seed,
            excitation_seed: None,
        }
    }

    /// The same synthesis with its spalls' excitations drawn from `seed`
    /// ([`Synthesis::excitation_seed`]).
    pub fn with_excitation_seed(mut self, seed: u64) -> Self {
        self.excitation_seed = Some(seed);
        self
    }
}

/// What decides one spall's excitation: its location and the operating point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct ExcitationKey {
    location: Location,
    size_bits: u64,
    rpm_bits: u64,
    angle_bits: u64,
    n: usize,
    seed: u64,
}

type SharedExcitation = Arc<OnceLock<Result<Arc<Vec<f64>>, CloseLoopError>>>;

/// The spalls' excitations, as the sensor sees them, simulated so far
/// ([`RigModel::synthesize_cached`]): keyed by location, spall size, speed, outer-race position,
/// length and excitation seed, each simulated once even when threads ask for it at the same
/// time. The key does not hold the rig: a cache serves the syntheses of one [`RigModel`] (its
/// preload, load, sensor and sampling rate shape the excitation). Holds about 2 MB per
/// excitation of 10 s at 12 kHz; drop it when the syntheses are done.
#[derive(Debug, Default)]
pub struct ExcitationCache {
    map: Mutex<HashMap<ExcitationKey, SharedExcitation>>,
}

impl ExcitationCache {
    /// Excitations held.
    pub fn len(&self) -> usize {
        self.map.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    /// No excitation held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn get_or_simulate(
        &self,
        key: ExcitationKey,
        simulate: impl FnOnce() -> Result<Vec<f64>, CloseLoopError>,
    ) -> Result<Arc<Vec<f64>>, CloseLoopError> {
        let slot = Arc::clone(
            self.map
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .entry(key)
                .or_default(),
        );
        slot.get_or_init(|| simulate().map(Arc::new)).clone()
    }
}

impl RigModel {
    /// The healthy machine's signal: path noise, floor and lines (seeded), `n` samples at rig
    /// speed `rpm` (nominal; the calibrated speed ratio is applied).
    pub fn background(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        let lines = if self.chain_lines.is_empty() {
            &self.healthy.lines
        } else {
            &self.chain_lines
        };
        background_of(
            &self.healthy,
            lines,
            &self.background_fir,
            &self.background_chain_fir,
            self.fs_hz,
            rpm,
            n,
            seed,
        )
    }

    /// The healthy machine as its calibration recording holds it (lines at that recording's
    /// levels): what the healthy recording is compared with.
    pub fn background_as_calibrated(&self, rpm: f64, n: usize, seed: u64) -> Vec<f64> {
        background_of(
            &self.healthy,
            &self.healthy.lines,
            &self.background_fir,
            &[],
            self.fs_hz,
            rpm,
            n,
            seed,
        )
    }

    /// The fault's contribution: for each location of the class, the 5-DOF excitation of its
    /// spall (simulated alone) scaled by the calibrated gain and seen through the location's
    /// impact path; combined faults superpose these responses.
    ///
    /// # Errors
    /// As [`excitation`] and [`RigModel::severity`].
    pub fn fault_signal(&self, s: &Synthesis) -> Result<Vec<f64>, CloseLoopError> {
        self.fault_signal_with(s, None)
    }

    /// [`RigModel::fault_signal`] with the spalls' excitations looked up in, or added to,
    /// `cache` when one is given.
    fn fault_signal_with(
        &self,
        s: &Synthesis,
        cache: Option<&ExcitationCache>,
    ) -> Result<Vec<f64>, CloseLoopError> {
        let bearing: Bearing =
            self.bearing
                .parse()
                .map_err(|_| CloseLoopError::UnknownBearing {
                    name: self.bearing.clone(),
                })?;
        let mut y = vec![0.0; s.n];
        for loc in Location::ALL.into_iter().filter(|l| l.in_class(s.class)) {
            let (g, q) = self.severity_at(loc, s.size_mm, s.outer_angle_rad)?;
            // each spall simulated alone (same seed, same slip draws) and seen through its own
            // path: combined faults are the superposition of the spalls' responses
            let seed = s.excitation_seed.unwrap_or(s.seed);
            let simulate = || {
                excitation(
                    bearing,
                    self.preload_m,
                    self.radial_load_n,
                    loc.class(),
                    s.size_mm,
                    s.rpm * self.healthy.speed_ratio,
                    s.outer_angle_rad,
                    self.fs_hz,
                    s.n + WARMUP,
                    seed,
                    self.excitation_housing_hz,
                )
                .map(|e| e.seen(self.sensor_horizontal))
            };
            let e = match cache {
                Some(c) => c.get_or_simulate(
                    ExcitationKey {
                        location: loc,
                        size_bits: s.size_mm.to_bits(),
                        rpm_bits: s.rpm.to_bits(),
                        angle_bits: s.outer_angle_rad.to_bits(),
                        n: s.n,
                        seed,
                    },
                    simulate,
                )?,
                None => Arc::new(simulate()?),
            };
            let tau = BURST_PERIODS * self.fs_hz / self.fault_rate_hz(loc, s.rpm).max(1e-9);
            let e = gated(
                &e,
                self.strike_fraction_at(loc, s.size_mm, s.outer_angle_rad)?,
                tau,
                s.seed ^ 0xB0B5_7000,
            );
            let x: Vec<f64> = mix(&e, q, s.seed ^ 0x5EED_0FF1)
                .iter()
                .map(|v| g * v)
                .collect();
            let f = self
                .impact_path_for_at(loc, s.size_mm, s.outer_angle_rad)?
                .path
                .filter(&x);
            for (a, b) in y.iter_mut().zip(&f[WARMUP..]) {
                *a += b;
            }
        }
        Ok(y)
    }

    /// A simulated recording of the rig (rig units, [`RigModel::units`]).
    ///
    /// # Errors
    /// [`CloseLoopError::InvalidRpm`], [`CloseLoopError::ParameterOutOfRange`] for a speed above
    /// 100 000 rpm or `n` below 1024, and the errors of [`RigModel::fault_signal`].
    pub fn synthesize(&self, s: &Synthesis) -> Result<Vec<f64>, CloseLoopError> {
        self.synthesize_with(s, None)
    }

    /// [`RigModel::synthesize`] with the spalls' excitations taken from `cache` when it holds
    /// them (simulated and added otherwise): the output is bit-identical to
    /// [`RigModel::synthesize`]'s; only the work is shared between syntheses with the same
    /// [`Synthesis::excitation_seed`].
    ///
    /// # Errors
    /// As [`RigModel::synthesize`].
    pub fn synthesize_cached(
        &self,
        s: &Synthesis,
        cache: &ExcitationCache,
    ) -> Result<Vec<f64>, CloseLoopError> {
        self.synthesize_with(s, Some(cache))
    }

    /// [`RigModel::synthesize`] in its two parts, each through the measurement chain: the
    /// healthy machine (bit-identical to the synthesis of [`FaultClass::None`] with the same
    /// seed) and the fault's contribution (zeros for [`FaultClass::None`]). The chain is
    /// linear, so their sum is [`RigModel::synthesize`]'s recording up to rounding. What a
    /// degradation run needs to scale and report the two apart.
    ///
    /// # Errors
    /// As [`RigModel::synthesize`].
    pub fn synthesize_parts(&self, s: &Synthesis) -> Result<(Vec<f64>, Vec<f64>), CloseLoopError> {
        let none = Synthesis {
            class: FaultClass::None,
            ..*s
        };
        let healthy = self.synthesize_with(&none, None)?;
        let fault = if s.class == FaultClass::None {
            vec![0.0; healthy.len()]
        } else {
            let f = apply_fir(&self.chain_fir, &self.fault_signal_with(s, None)?);
            if let Some(i) = f.iter().position(|v| !v.is_finite()) {
                return Err(CloseLoopError::NonFinite { index: i });
            }
            f
        };
        Ok((healthy, fault))
    }

    fn synthesize_with(
        &self,
        s: &Synthesis,
        cache: Option<&ExcitationCache>,
    ) -> Result<Vec<f64>, CloseLoopError> {
        if !(s.rpm.is_finite() && s.rpm > 0.0) {
            return Err(CloseLoopError::InvalidRpm { rpm: s.rpm });
        }
        if s.rpm > 100_000.0 {
            return Err(bad("rpm", s.rpm, 0.0, 100_000.0));
        }
        if s.n < 1024 {
            return Err(bad("samples", s.n as f64, 1024.0, f64::INFINITY));
        }
        let mut y = self.background(s.rpm, s.n, s.seed);
        if s.class != FaultClass::None {
            let f = self.fault_signal_with(s, cache)?;
            for (a, b) in y.iter_mut().zip(&f) {
                *a += b;
            }
        }
        let y = apply_fir(&self.chain_fir, &y);
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            return Err(CloseLoopError::NonFinite { index: i });
        }
        Ok(y)
    }
}

/// The strike gate: `n` samples of a two-state Markov chain (seeded, started in its stationary
/// law) that is on a fraction `p` of the time, in bursts of `burst_samples` on average, and
/// off in between; on = 1/√p, off = 0, so the gate's mean square is 1 and its mean √p (the
/// periodic part of the impacts keeps a fraction p of their power). `p` ≥ 1 gives ones.
pub fn strike_gate(n: usize, p: f64, burst_samples: f64, seed: u64) -> Vec<f64> {
    if !(p.is_finite() && p > 0.0 && p < 1.0) {
        return vec![1.0; n];
    }
    let on_len = burst_samples.max(1.0);
    let off_len = (on_len * (1.0 - p) / p).max(1.0);
    let (leave_on, leave_off) = (1.0 / on_len, 1.0 / off_len);
    let level = 1.0 / p.sqrt();
    let mut g = Gaussian::new(seed);
    let mut on = g.uniform() < p;
    (0..n)
        .map(|_| {
            let v = if on { level } else { 0.0 };
            let u = g.uniform();
            on = if on { u >= leave_on } else { u < leave_off };
            v
        })
        .collect()
}

/// `x` times the strike gate of fraction `p` ([`strike_gate`]); `x` itself for p ≥ 1.
pub(super) fn gated(x: &[f64], p: f64, burst_samples: f64, seed: u64) -> Vec<f64> {
    if !(p.is_finite() && p > 0.0 && p < 1.0) {
        return x.to_vec();
    }
    strike_gate(x.len(), p, burst_samples, seed)
        .iter()
        .zip(x)
        .map(|(g, v)| g * v)
        .collect()
}

/// `x` plus a random part carrying the fraction `q` of the sum's power:
/// `x + √(q/(1−q))·r`, `r` a phase-randomised copy of `x` (every DFT bin keeps its magnitude,
/// its phase is drawn uniformly, seeded): the same power spectrum as the 5-DOF impacts, Gaussian
/// in distribution, so the random part lowers the kurtosis without changing the spectral shape
/// the impact path was fitted to (white noise would: the path divides the excess PSD by the
/// impacts' PSD, and white noise through it is over-weighted wherever the impacts are weak).
pub(super) fn mix(x: &[f64], q: f64, seed: u64) -> Vec<f64> {
    let q = q.clamp(0.0, 0.99);
    if q == 0.0 || x.is_empty() {
        return x.to_vec();
    }
    let r = phase_randomised(x, seed);
    let c = (q / (1.0 - q)).sqrt();
    x.iter().zip(&r).map(|(v, w)| v + c * w).collect()
}

/// A phase-randomised surrogate of `x`: the DFT magnitudes of `x` with seeded uniform phases
/// (Hermitian, so real; DC and, for even lengths, the Nyquist bin keep their values), hence the
/// same periodogram and mean square.
pub(super) fn phase_randomised(x: &[f64], seed: u64) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let n = x.len();
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    let mut planner = rustfft::FftPlanner::new();
    planner.plan_fft_forward(n).process(&mut buf);
    let mut g = Gaussian::new(seed);
    for k in 1..n.div_ceil(2) {
        let phase = 2.0 * PI * g.uniform();
        let m = buf[k].norm();
        buf[k] = Complex::from_polar(m, phase);
        buf[n - k] = buf[k].conj();
    }
    planner.plan_fft_inverse(n).process(&mut buf);
    buf.iter().map(|c| c.re / n as f64).collect()
}

/// The healthy machine's signal (see [`RigModel::background`]).
#[allow(clippy::too_many_arguments)] // the background's parts, spelled out
pub(super) fn background_of(
    machine: &MachineModel,
    lines: &[MachineLine],
    remainder: &[f64],
    broadband_chain: &[f64],
    fs: f64,
    rpm: f64,
    n: usize,
    seed: u64,
) -> Vec<f64> {
    let h = &machine;
    let mut y = if remainder.is_empty() {
        vec![0.0; n]
    } else {
        let mut g = Gaussian::new(seed ^ 0x2E3A_1DE4);
        let w: Vec<f64> = (0..n).map(|_| g.sample()).collect();
        apply_fir(remainder, &w)
    };
    let mut g = Gaussian::new(seed ^ 0xB6C0_5EED);
    if let Some(p) = &h.path {
        let sd = (p.excitation_variance * h.path_level).max(0.0).sqrt();
        let e: Vec<f64> = (0..n + WARMUP).map(|_| sd * g.sample()).collect();
        let f = p.filter(&e);
        for (a, b) in y.iter_mut().zip(&f[WARMUP..]) {
            *a += b;
        }
    }
    let floor_sd = (h.noise_floor_psd * fs / 2.0).max(0.0).sqrt();
    if floor_sd > 0.0 {
        y.iter_mut().for_each(|v| *v += floor_sd * g.sample());
    }
    let mut y = apply_fir(broadband_chain, &y);
    let fr = rpm / 60.0 * h.speed_ratio;
    for l in lines {
        let (f, a) = match *l {
            MachineLine::ShaftHarmonic {
                order, amplitude, ..
            } => (order * fr, amplitude),
            MachineLine::Tone {
                frequency_hz,
                amplitude,
            } => (frequency_hz, amplitude),
        };
        let ph = 2.0 * PI * g.uniform();
        if f > 0.0 && f < 0.5 * fs {
            add_cosine(&mut y, 2.0 * PI * f / fs, a, ph);
        }
    }
    y
}

/// Zero-phase FIR (odd length, symmetric `h`), zero padding at the edges; `x` itself when `h`
/// is empty.
pub(super) fn apply_fir(h: &[f64], x: &[f64]) -> Vec<f64> {
    if h.is_empty() {
        return x.to_vec();
    }
    let m = h.len() / 2;
    let n = x.len();
    if h.len() < FFT_FIR_MIN_TAPS || n < 8 * h.len() {
        return (0..n)
            .map(|i| {
                let lo = i.saturating_sub(m);
                let hi = (i + m).min(n - 1);
                (lo..=hi).map(|j| h[j + m - i] * x[j]).sum()
            })
            .collect();
    }
    // overlap-add: blocks of `b` samples convolved with h by FFTs of `nfft` ≥ b + len(h) − 1
    // points; the full convolution's samples m … m + n − 1 are the zero-phase output (the
    // same sums as above, the edges zero-padded, rounding aside)
    use rustfft::num_complex::Complex;
    let nfft = (4 * h.len()).next_power_of_two();
    let b = nfft - h.len() + 1;
    let mut planner = rustfft::FftPlanner::<f64>::new();
    let (fwd, inv) = (
        planner.plan_fft_forward(nfft),
        planner.plan_fft_inverse(nfft),
    );
    let mut hf: Vec<Complex<f64>> = (0..nfft)
        .map(|k| Complex::new(h.get(k).copied().unwrap_or(0.0), 0.0))
        .collect();
    fwd.process(&mut hf);
    let mut full = vec![0.0; n + h.len() - 1];
    let mut buf = vec![Complex::new(0.0, 0.0); nfft];
    for start in (0..n).step_by(b) {
        let len = b.min(n - start);
        buf.iter_mut().for_each(|v| *v = Complex::new(0.0, 0.0));
        for (v, xv) in buf.iter_mut().zip(&x[start..start + len]) {
            v.re = *xv;
        }
        fwd.process(&mut buf);
        for (v, hv) in buf.iter_mut().zip(&hf) {
            *v *= hv;
        }
        inv.process(&mut buf);
        for (o, v) in full[start..].iter_mut().zip(&buf[..len + h.len() - 1]) {
            *o += v.re / nfft as f64;
        }
    }
    full[m..m + n].to_vec()
}

/// Add `a·cos(w·k + φ)` to `y[k]` by a rotating phasor, re-anchored every 4096 samples to the
/// exact phase (within a few 1e-12 of the amplitude over 50 000 samples, test): one complex
/// multiplication per sample instead of a cosine.
fn add_cosine(y: &mut [f64], w: f64, a: f64, ph: f64) {
    let (sw, cw) = w.sin_cos();
    for (c, chunk) in y.chunks_mut(4096).enumerate() {
        let (mut s0, mut c0) = (w * (4096 * c) as f64 + ph).sin_cos();
        for v in chunk {
            *v += a * c0;
            (c0, s0) = (c0 * cw - s0 * sw, s0 * cw + c0 * sw);
        }
    }
}

/// Taps from which [`apply_fir`] convolves by FFT (overlap-add) rather than directly.
const FFT_FIR_MIN_TAPS: usize = 33;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mean_square;

    fn kurt(x: &[f64]) -> f64 {
        let n = x.len() as f64;
        let m = x.iter().sum::<f64>() / n;
        let v = x.iter().map(|a| (a - m).powi(2)).sum::<f64>() / n;
        x.iter().map(|a| (a - m).powi(4)).sum::<f64>() / n / (v * v)
    }

    /// The random part keeps the impacts' spectrum (and so the mix keeps the shape the impact
    /// path was fitted to) while the mix loses impulsiveness; odd and even lengths.
    #[test]
    fn the_random_part_has_the_spectrum_of_the_impacts() {
        for n in [4095usize, 4096] {
            // a decaying ringing every 100 samples: impulsive, strongly coloured
            let x: Vec<f64> = (0..n)
                .map(|i| {
                    let t = (i % 100) as f64;
                    (-t / 6.0).exp() * (0.9 * t).sin()
                })
                .collect();
            let r = phase_randomised(&x, 7);
            let spec = |y: &[f64]| {
                let mut b: Vec<rustfft::num_complex::Complex<f64>> = y
                    .iter()
                    .map(|&v| rustfft::num_complex::Complex::new(v, 0.0))
                    .collect();
                rustfft::FftPlanner::new()
                    .plan_fft_forward(n)
                    .process(&mut b);
                b.iter().map(|c| c.norm()).collect::<Vec<f64>>()
            };
            let (sx, sr) = (spec(&x), spec(&r));
            let peak = sx.iter().cloned().fold(0.0, f64::max);
            for (a, b) in sx.iter().zip(&sr) {
                assert!((a - b).abs() <= 1e-9 * peak, "{a} vs {b}");
            }
            assert!((mean_square(&r) / mean_square(&x) - 1.0).abs() < 1e-9);
            assert!(kurt(&x) > 4.0, "input kurtosis {}", kurt(&x));
            assert!(kurt(&r) < 3.5, "surrogate kurtosis {}", kurt(&r));
            let m = mix(&x, 0.5, 3);
            assert!(kurt(&m) < kurt(&x));
            assert_eq!(mix(&x, 0.0, 3), x);
        }
    }

    /// The FFT (overlap-add) convolution of a long input agrees with the direct sums, edges
    /// included, and a line synthesized by the rotating phasor with the cosine it stands for.
    #[test]
    fn fft_fir_and_phasor_lines_match_their_direct_forms() {
        let mut g = Gaussian::new(5);
        let x: Vec<f64> = (0..20_011).map(|_| g.sample()).collect();
        let h: Vec<f64> = (0..129)
            .map(|k| {
                let t = (k as f64 - 64.0) / 64.0;
                (1.0 - t * t) * (3.0 * t).cos()
            })
            .collect();
        let fast = apply_fir(&h, &x);
        let m = h.len() / 2;
        let direct: Vec<f64> = (0..x.len())
            .map(|i| {
                let lo = i.saturating_sub(m);
                let hi = (i + m).min(x.len() - 1);
                (lo..=hi).map(|j| h[j + m - i] * x[j]).sum()
            })
            .collect();
        assert_eq!(fast.len(), direct.len());
        let worst = fast
            .iter()
            .zip(&direct)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{worst}");
        let mut y = vec![0.25; 50_000];
        let (w, a, ph) = (2.0 * PI * 1234.567 / 12_000.0, 0.5, 2.1);
        add_cosine(&mut y, w, a, ph);
        let worst = y
            .iter()
            .enumerate()
            .map(|(k, v)| (v - 0.25 - a * (w * k as f64 + ph).cos()).abs())
            .fold(0.0, f64::max);
        // the reference itself rounds its argument (w·k up to 3e4 rad): a few 1e-12
        assert!(worst < 1e-10 * a, "{worst}");
    }
}
