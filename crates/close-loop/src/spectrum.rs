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

/// |Σ xw\[i\]·e^(−j2πf·i/fs)|²: the DFT power of an already windowed signal at any frequency f.
///
/// Four phasors, one per residue of `i` mod 4, each advanced by e^(−j4·2πf/fs): the four
/// multiply chains are independent, so they run in parallel instead of one chain waiting on
/// the previous product (≈ 3× faster on a 10 s, 12 kHz record; the phasors are renormalised
/// every 1024 samples against round-off drift).
pub fn zoom_power(xw: &[f64], fs: f64, f: f64) -> f64 {
    let w = 2.0 * PI * f / fs;
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

/// A shaft line must stand this far (dB) above the median of the periodogram around it (± 5 %
/// of its frequency or ± 10 resolution bins, its own main lobe left out) to count in
/// [`measure_shaft_speed`]. CWRU's 1× line stands 10–41 dB out on every record that has one
/// (the NTN-bearing ball records 3005, 3006, 3008 and five 48 kHz records show none: 2–8 dB).
pub const SHAFT_LINE_DB: f64 = 10.0;
/// Shaft orders read by [`measure_shaft_speed`].
pub const SHAFT_ORDERS: u32 = 8;
/// Half-width of the window in which a shaft order's line is sought once the 1× line has placed
/// the speed, as a fraction of its frequency.
pub const SHAFT_REFINE_WINDOW: f64 = 0.002;
/// An order within this fraction of a mains multiple or of a declared fault harmonic (1–4) is
/// not read: its line may be the other one (at 1797 rpm 2·fr is 0.12 % from 60 Hz).
pub const SHAFT_EXCLUSION: f64 = 0.005;
/// Read orders tell one speed ρ when each lies within this fraction of k·fr (plus a tenth of a
/// resolution bin) of k·fr·ρ. CWRU's shaft lines agree within 1e-4 at orders 3–7; the 1× line,
/// read to a fraction of a 0.2 Hz bin, within 6e-4. 161.mat decimated to 12 kHz shows lines at
/// 1.0148, 1.0128 and 1.0128 × orders 1, 2 and 3 of the logged speed, none a shaft line.
pub const SHAFT_CONSISTENCY: f64 = 2e-4;
/// Orders that must tell one speed ([`SHAFT_CONSISTENCY`]) for a shaft speed to be read.
pub const SHAFT_MIN_ORDERS: usize = 3;
/// The shaft has moved with a speed step when the measured shaft speed differs from the speed
/// of the model's lines by more than this fraction (the measurement's spread on CWRU's 12 kHz
/// records is ±0.06 % about the logged speed; their fault lines sit 0.2–0.7 % off it).
pub const SHAFT_AGREE: f64 = 1e-3;

/// The shaft speed the recording's own shaft lines show.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaftSpeed {
    /// Measured shaft speed / declared speed.
    pub ratio: f64,
    /// The shaft orders whose lines were read.
    pub orders: Vec<u32>,
}

/// The shaft speed from the shaft lines of `y` (the fitting segment of the raw recording), as a
/// ratio to the declared shaft rate `fr` Hz: the 1× line, sought within ± `max_offset`, must
/// stand [`SHAFT_LINE_DB`] above its neighbourhood; it places orders 1..=[`SHAFT_ORDERS`]
/// (below 0.45·fs), each sought within ± [`SHAFT_REFINE_WINDOW`] and read when it stands as
/// far out and lies clear ([`SHAFT_EXCLUSION`]) of the mains multiples and of the declared
/// fault's harmonics `fault_orders` (× fr). The ratio is the least-squares fit f_k = k·fr·ρ
/// over the largest set of read orders that tell one speed ([`SHAFT_CONSISTENCY`]); `None`
/// unless [`SHAFT_MIN_ORDERS`] do. Peaks are placed by the zoom DFT of the Hann-windowed
/// segment ([`PeakRefiner`]).
pub fn measure_shaft_speed(
    y: &[f64],
    fs: f64,
    fr: f64,
    fault_orders: &[f64],
    mains_hz: Option<f64>,
    max_offset: f64,
) -> Option<ShaftSpeed> {
    if y.len() < 64 || !(fr > 0.0 && fs > 0.0) || 1.05 * fr >= 0.45 * fs {
        return None;
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let xw = hann_windowed(&y.iter().map(|v| v - mean).collect::<Vec<_>>());
    let refiner = PeakRefiner::new(&xw, fs);
    // the line's power over the median of the zero-padded periodogram around it: within ± 5 %
    // or ± 10 resolution bins (fs / N) whichever is wider, outside the line's own main lobe
    // (± 3 bins; the Hann lobe is ± 2)
    let bin = fs / y.len() as f64;
    let excess_db = |f: f64| -> f64 {
        let p = refiner.power();
        let df = refiner.df();
        let w = (0.05 * f).max(10.0 * bin);
        let k = |x: f64| ((x.max(0.0) / df).round() as usize).min(p.len() - 1);
        let side: Vec<f64> = (k(f - w)..=k(f + w))
            .filter(|&j| (j as f64 * df - f).abs() > 3.0 * bin)
            .map(|j| p[j])
            .collect();
        if side.is_empty() {
            return f64::NEG_INFINITY;
        }
        10.0 * (zoom_power(&xw, fs, f) / median(&side).max(1e-300)).log10()
    };
    let f1 = refiner.refine(fr * (1.0 - max_offset), fr * (1.0 + max_offset));
    if excess_db(f1) < SHAFT_LINE_DB {
        return None;
    }
    let rho0 = f1 / fr;
    let near = |f: f64, g: f64| (f - g).abs() < SHAFT_EXCLUSION * f;
    let mut ratios = Vec::new();
    let mut orders = Vec::new();
    for k in 1..=SHAFT_ORDERS {
        let fc = f64::from(k) * fr * rho0;
        if fc >= 0.45 * fs {
            break;
        }
        let mains = mains_hz.is_some_and(|lf| {
            let m = (fc / lf).round();
            m >= 1.0 && near(fc, m * lf)
        });
        let fault = fault_orders
            .iter()
            .any(|o| (1..=4).any(|m| near(fc, f64::from(m) * o * fr * rho0)));
        if mains || fault {
            continue;
        }
        let f = refiner.refine(
            fc * (1.0 - SHAFT_REFINE_WINDOW),
            fc * (1.0 + SHAFT_REFINE_WINDOW),
        );
        if excess_db(f) >= SHAFT_LINE_DB {
            ratios.push(f / (f64::from(k) * fr));
            orders.push(k);
        }
    }
    // the orders must tell one speed: the largest set within SHAFT_CONSISTENCY·k·fr plus a tenth
    // of a resolution bin of k·fr·ρ, ρ taken from each read order in turn (a line's frequency is
    // read to a fraction of a bin, so a low order's ratio is the least precise); the speed is
    // then the least-squares fit f_k = k·fr·ρ over that set
    let agree = |rho: f64| -> Vec<usize> {
        (0..orders.len())
            .filter(|&i| {
                let fk = f64::from(orders[i]) * fr;
                (ratios[i] - rho).abs() * fk <= SHAFT_CONSISTENCY * fk + 0.1 * bin
            })
            .collect()
    };
    let best = ratios
        .iter()
        .map(|&rho| agree(rho))
        .max_by_key(Vec::len)
        .unwrap_or_default();
    if best.len() < SHAFT_MIN_ORDERS {
        return None;
    }
    let (num, den) = best.iter().fold((0.0, 0.0), |(a, b), &i| {
        let k = f64::from(orders[i]);
        (a + k * k * ratios[i], b + k * k)
    });
    Some(ShaftSpeed {
        ratio: num / den,
        orders: best.iter().map(|&i| orders[i]).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
    /// Shaft lines at orders 1–6 of a shaft turning 0.07 % faster than declared, in white
    /// noise, with a strong 60 Hz mains line and fault lines at BPFO (3.5848 × fr) and its
    /// harmonics: the speed comes back within 1e-4, order 2 (0.2 % from 60 Hz) is not read.
    /// White noise alone gives no speed, nor do lines near orders 1, 2 and 4 that tell no one
    /// speed.
    #[test]
    fn shaft_speed_is_read_from_the_shaft_lines() {
        let fs = 12_000.0;
        let fr = 1797.0 / 60.0;
        let truth = 1.0007;
        let n = 60_000;
        let mut g = crate::scenario::Gaussian::new(5);
        let noise: Vec<f64> = (0..n).map(|_| g.sample()).collect();
        let mut x = noise.clone();
        for (i, v) in x.iter_mut().enumerate() {
            let t = i as f64 / fs;
            for k in 1..=6 {
                let f = f64::from(k) * fr * truth;
                *v += 0.2 * (2.0 * PI * f * t + 0.3 * f64::from(k)).cos();
            }
            *v += 0.5 * (2.0 * PI * 60.0 * t).cos();
            for m in 1..=3 {
                *v += 0.3 * (2.0 * PI * f64::from(m) * 3.5848 * fr * t).cos();
            }
        }
        let s = measure_shaft_speed(&x, fs, fr, &[3.5848], Some(60.0), 0.05).expect("no speed");
        assert!((s.ratio / truth - 1.0).abs() < 1e-4, "{s:?}");
        assert!(s.orders.contains(&1) && !s.orders.contains(&2), "{s:?}");
        assert!(measure_shaft_speed(&noise, fs, fr, &[], Some(60.0), 0.05).is_none());
        let mut y = noise.clone();
        for (i, v) in y.iter_mut().enumerate() {
            let t = i as f64 / fs;
            for (k, r) in [(1.0, 1.015), (2.0, 1.012), (4.0, 1.012)] {
                *v += 0.2 * (2.0 * PI * k * fr * r * t).cos();
            }
        }
        assert!(measure_shaft_speed(&y, fs, fr, &[], None, 0.05).is_none());
    }
}
