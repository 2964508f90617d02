//! The structural path from the bearing to the sensor, identified from a recording: an all-pole
//! (autoregressive) model `y = e / A(z)`, `A(z) = 1 + a₁z⁻¹ + … + a_p z⁻ᵖ`, driven by white
//! excitation of variance σ². Its pole pairs are the structural modes (frequency, damping ratio,
//! modal gain); its one-sided PSD is `2σ²/fs / |A(e^{jω})|²`.
//!
//! The model is estimated from a *line-free* PSD: narrow lines (shaft harmonics, tones) are
//! replaced by the local median first, so that the modes describe the broadband structure and
//! the lines stay for the loop to name (a high-order AR fitted to the raw signal would spend
//! poles on them). The autocorrelation follows from the PSD by the Wiener–Khinchin cosine sum and
//! the AR coefficients from the Yule–Walker equations by Levinson–Durbin recursion. The order is
//! the smallest whose fit is within a tolerance of the best order tried ("as many modes as the
//! data supports"). See `docs/equations/close-loop.md`, "Structural path".

use crate::CloseLoopError;
use crate::spectrum::running_median;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Orders tried when the path is identified.
pub const ORDERS: [usize; 12] = [2, 4, 8, 12, 16, 24, 32, 40, 48, 64, 96, 128];

/// One structural mode of the path (a complex pole pair of `1/A(z)`, or a real pole).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathMode {
    /// Damped natural frequency, Hz (0 for a real pole).
    pub frequency_hz: f64,
    /// Damping ratio ζ (from the continuous-time pole s = fs·ln z).
    pub damping_ratio: f64,
    /// Modal gain: σ·|residue| (×2 for a pair), in the recording's units — the amplitude with
    /// which unit-variance excitation rings this mode.
    pub gain: f64,
    /// Peak of this mode's own PSD contribution, units²/Hz.
    pub peak_psd: f64,
}

/// An identified structural path.
///
/// The workspace's other AR model is the diagnosis' whitener (`diagnosis::ArWhitener`). Both
/// filter through the one prediction-error loop ([`diagnosis::whiten::prediction_error`], which
/// [`StructuralPath::prediction_error`] runs with [`StructuralPath::prediction_coefficients`]),
/// and a path becomes a whitener at the edge (`ArWhitener::from_coefficients` of its prediction
/// coefficients, as a machine-model baseline does). They stay two types because what they hold
/// and how they are fitted differ: a path is fitted by Yule–Walker (Levinson–Durbin,
/// [`levinson`]) on a line-free PSD with its order chosen by a spectral score ([`identify`]),
/// keeps `A(z)` coefficients and an excitation variance, and is also a spectrum, a set of modes
/// and a synthesis filter `1/A(z)`; the whitener is fitted by least squares on time samples with
/// its order chosen by held-out one-step error, keeps prediction coefficients `−α_i` and its
/// fit's record. Either fit on the other's data gives other numbers, and both are serialised
/// (machine models, diagnosis reports).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StructuralPath {
    /// Sampling rate the path was identified at, Hz.
    pub fs_hz: f64,
    /// `a₁ … a_p` of `A(z) = 1 + Σ a_k z⁻ᵏ`.
    pub ar: Vec<f64>,
    /// Excitation (innovation) variance σ², units².
    pub excitation_variance: f64,
}

/// The line-free PSD a path is identified from: [`line_free`] of the hi-resolution PSD (grid
/// k·`df_hi`) against its running median over ±40 Hz (at least 8 bins), lines 4 dB above it.
pub fn path_line_free(psd_hi: &[f64], df_hi: f64) -> Vec<f64> {
    line_free(psd_hi, ((40.0 / df_hi).round() as usize).max(8), 4.0)
}

/// Replace narrow lines of a one-sided PSD by the running median of its logarithm (half-width
/// `half` bins) wherever the PSD stands more than `threshold_db` above it.
pub fn line_free(psd: &[f64], half: usize, threshold_db: f64) -> Vec<f64> {
    let l: Vec<f64> = psd.iter().map(|v| v.max(1e-300).ln()).collect();
    let m = running_median(&l, half);
    let t = threshold_db / 10.0 * std::f64::consts::LN_10;
    l.iter()
        .zip(&m)
        .map(|(a, b)| if a - b > t { b.exp() } else { a.exp() })
        .collect()
}

/// Autocorrelation R(0..=p) of a process with one-sided PSD `psd` on the grid k·df
/// (R(m) = Σ_k w_k S(f_k) Δf cos(2π f_k m / fs), half weight at DC and Nyquist).
pub fn autocorrelation(psd: &[f64], df: f64, fs: f64, p: usize) -> Vec<f64> {
    let n = psd.len();
    (0..=p)
        .map(|m| {
            psd.iter()
                .enumerate()
                .map(|(k, s)| {
                    let w = if k == 0 || k + 1 == n { 0.5 } else { 1.0 };
                    w * s * df * (2.0 * PI * k as f64 * df * m as f64 / fs).cos()
                })
                .sum()
        })
        .collect()
}

/// Levinson–Durbin: AR coefficients `a₁…a_p` and the prediction-error variance from R(0..=p).
///
/// # Errors
/// [`CloseLoopError::Model`] if R(0) ≤ 0 or the recursion loses positive definiteness.
pub fn levinson(r: &[f64]) -> Result<(Vec<f64>, f64), CloseLoopError> {
    let p = r.len().saturating_sub(1);
    if !(r.first().is_some_and(|v| *v > 0.0 && v.is_finite())) {
        return Err(CloseLoopError::Model {
            reason: "structural path: the autocorrelation at lag 0 is not positive".into(),
        });
    }
    let mut a = vec![0.0; p];
    let mut e = r[0];
    for i in 0..p {
        let mut acc = r[i + 1];
        for j in 0..i {
            acc += a[j] * r[i - j];
        }
        let k = -acc / e;
        if !k.is_finite() || k.abs() >= 1.0 {
            return Err(CloseLoopError::Model {
                reason: format!(
                    "structural path: reflection coefficient {k} at order {}",
                    i + 1
                ),
            });
        }
        let prev = a.clone();
        a[i] = k;
        for j in 0..i {
            a[j] = prev[j] + k * prev[i - 1 - j];
        }
        e *= 1.0 - k * k;
    }
    Ok((a, e))
}

impl StructuralPath {
    /// Identify an order-`p` path from a one-sided PSD (grid k·df, k = 0..), lines removed first.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the PSD carries no power or the recursion fails.
    pub fn from_psd(psd: &[f64], df: f64, fs: f64, p: usize) -> Result<Self, CloseLoopError> {
        let r = autocorrelation(psd, df, fs, p);
        let (ar, e) = levinson(&r)?;
        Ok(Self {
            fs_hz: fs,
            ar,
            excitation_variance: e,
        })
    }

    /// Model order p.
    pub fn order(&self) -> usize {
        self.ar.len()
    }

    /// |A(e^{j2πf/fs})|².
    pub fn a_power(&self, f: f64) -> f64 {
        let w = 2.0 * PI * f / self.fs_hz;
        let (mut re, mut im) = (1.0, 0.0);
        for (k, a) in self.ar.iter().enumerate() {
            let ph = w * (k + 1) as f64;
            re += a * ph.cos();
            im -= a * ph.sin();
        }
        re * re + im * im
    }

    /// One-sided PSD at `f`, units²/Hz.
    pub fn psd_at(&self, f: f64) -> f64 {
        2.0 * self.excitation_variance / self.fs_hz / self.a_power(f).max(1e-300)
    }

    /// One-sided PSD on the grid k·df, k = 0..n_bins.
    pub fn psd(&self, n_bins: usize, df: f64) -> Vec<f64> {
        (0..n_bins).map(|k| self.psd_at(k as f64 * df)).collect()
    }

    /// The path's power response normalised to its excitation: |1/A|² (dimensionless).
    pub fn power_gain(&self, f: f64) -> f64 {
        1.0 / self.a_power(f).max(1e-300)
    }

    /// Filter `x` through `1/A(z)` (zero initial state).
    pub fn filter(&self, x: &[f64]) -> Vec<f64> {
        let p = self.ar.len();
        let mut y = vec![0.0; x.len()];
        for n in 0..x.len() {
            let mut v = x[n];
            for k in 1..=p.min(n) {
                v -= self.ar[k - 1] * y[n - k];
            }
            y[n] = v;
        }
        y
    }

    /// The prediction coefficients `a_i = −α_i` of the path's one-step predictor
    /// `ŷ(n) = Σ a_i y(n−i)` (the convention of `diagnosis::ArWhitener`).
    pub fn prediction_coefficients(&self) -> Vec<f64> {
        self.ar.iter().map(|a| -a).collect()
    }

    /// The one-step prediction error `A(z)·y` (the path's innovation; the first p samples use
    /// the available past only). From sample p on it is [`diagnosis::whiten::prediction_error`]
    /// of [`StructuralPath::prediction_coefficients`]: `y(n) − Σ (−α_k) y(n−k)` is the bits of
    /// `y(n) + Σ α_k y(n−k)` (negation is exact), summed in the same order.
    pub fn prediction_error(&self, y: &[f64]) -> Vec<f64> {
        let p = self.ar.len();
        let mut e: Vec<f64> = (0..p.min(y.len()))
            .map(|n| {
                let mut v = y[n];
                for k in 1..=n {
                    v += self.ar[k - 1] * y[n - k];
                }
                v
            })
            .collect();
        e.extend(diagnosis::whiten::prediction_error(
            &self.prediction_coefficients(),
            y,
        ));
        e
    }

    /// The structural modes: the poles of `1/A(z)` (roots of A), one entry per complex pair
    /// (positive frequency) or real pole, sorted by frequency.
    pub fn modes(&self) -> Vec<PathMode> {
        let p = self.ar.len();
        if p == 0 {
            return Vec::new();
        }
        // companion matrix of z^p + a1 z^{p-1} + … + a_p
        let mut c = nalgebra::DMatrix::<f64>::zeros(p, p);
        for k in 0..p {
            c[(0, k)] = -self.ar[k];
        }
        for i in 1..p {
            c[(i, i - 1)] = 1.0;
        }
        let poles: Vec<nalgebra::Complex<f64>> = c.complex_eigenvalues().iter().copied().collect();
        let sigma = self.excitation_variance.max(0.0).sqrt();
        let mut out = Vec::new();
        for (i, z) in poles.iter().enumerate() {
            if z.im < -1e-12 {
                continue;
            }
            // residue of Π 1/(1 − p_j z⁻¹) at p_i
            let mut r = nalgebra::Complex::new(1.0, 0.0);
            for (j, q) in poles.iter().enumerate() {
                if j != i {
                    r /= nalgebra::Complex::new(1.0, 0.0) - q / z;
                }
            }
            let pair = z.im > 1e-12;
            let s = z.ln() * self.fs_hz;
            let wn = s.norm();
            let f = (s.im / (2.0 * PI)).abs();
            let zeta = if wn > 0.0 {
                (-s.re / wn).clamp(-1.0, 1.0)
            } else {
                1.0
            };
            let gain = sigma * r.norm() * if pair { 2.0 } else { 1.0 };
            out.push(PathMode {
                frequency_hz: if pair { f } else { 0.0 },
                damping_ratio: zeta,
                gain,
                peak_psd: self.psd_at(if pair { f } else { 0.0 }),
            });
        }
        out.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        out
    }
}

/// Identify the path from a hi-resolution one-sided PSD (grid k·df), choosing the order: the
/// smallest of [`ORDERS`] (up to `max_order`) whose `score` (lower is better; the loop's metric of
/// the path PSD on its own grid) is within `tolerance` of the best order's.
///
/// # Errors
/// [`CloseLoopError::Model`] if no order can be identified.
pub fn identify(
    psd_hi: &[f64],
    df_hi: f64,
    fs: f64,
    max_order: usize,
    tolerance: f64,
    score: impl FnMut(&StructuralPath) -> f64,
) -> Result<StructuralPath, CloseLoopError> {
    identify_line_free(
        &path_line_free(psd_hi, df_hi),
        df_hi,
        fs,
        max_order,
        tolerance,
        score,
    )
}

/// [`identify`] from a PSD already made line-free by [`path_line_free`].
///
/// # Errors
/// [`CloseLoopError::Model`] if no order can be identified.
pub fn identify_line_free(
    free: &[f64],
    df_hi: f64,
    fs: f64,
    max_order: usize,
    tolerance: f64,
    mut score: impl FnMut(&StructuralPath) -> f64,
) -> Result<StructuralPath, CloseLoopError> {
    let mut fits: Vec<(StructuralPath, f64)> = Vec::new();
    for &p in ORDERS.iter().filter(|&&p| p <= max_order) {
        if let Ok(path) = StructuralPath::from_psd(free, df_hi, fs, p) {
            let s = score(&path);
            if s.is_finite() {
                fits.push((path, s));
            }
        }
    }
    let best = fits.iter().map(|f| f.1).fold(f64::INFINITY, f64::min);
    fits.into_iter()
        .find(|f| f.1 <= best + tolerance)
        .map(|f| f.0)
        .ok_or_else(|| CloseLoopError::Model {
            reason: "structural path: no AR order could be identified".into(),
        })
}

/// Fewest samples a structural path is identified from ([`identify_from_signal`]); the loop
/// identifies it on the fitting part, so a recording needs this many there
/// ([`crate::min_samples`]).
pub const MIN_PATH_SAMPLES: usize = 2048;

/// Identify the structural path of a recording directly, without the loop: Welch PSDs of `y`
/// (segments of about 12 Hz resolution for the score, eight times finer for the AR fit, both
/// shrunk until at least eight segments fit), lines removed, and the order chosen by
/// [`identify`] with the loop's own score (the floor-regularised log-spectral distance of the
/// path PSD against the measured PSD, floor 30 dB under its mean). This is the path a machine
/// model falls back to when the loop added none because the declared model already explained
/// the recording's spectrum.
///
/// # Errors
/// [`CloseLoopError::TooShort`] below [`MIN_PATH_SAMPLES`] samples,
/// [`CloseLoopError::InvalidSamplingRate`], and the errors of the Welch PSD and of [`identify`].
pub fn identify_from_signal(
    y: &[f64],
    fs: f64,
    max_order: usize,
) -> Result<StructuralPath, CloseLoopError> {
    if !(fs.is_finite() && fs > 0.0) {
        return Err(CloseLoopError::InvalidSamplingRate { fs });
    }
    if y.len() < MIN_PATH_SAMPLES {
        return Err(CloseLoopError::TooShort {
            needed: MIN_PATH_SAMPLES,
            found: y.len(),
        });
    }
    let pow2 = |x: f64| (x.max(1.0).log2().round().exp2() as usize).max(crate::MIN_NPERSEG);
    let mut nperseg = pow2(fs / 12.0);
    while nperseg > crate::MIN_NPERSEG && y.len() / nperseg < 8 {
        nperseg /= 2;
    }
    let mut nperseg_hi = 8 * nperseg;
    while nperseg_hi > nperseg && y.len() / nperseg_hi < 4 {
        nperseg_hi /= 2;
    }
    let welch = crate::spectrum::Welch::new(fs, nperseg)?;
    let welch_hi = crate::spectrum::Welch::new(fs, nperseg_hi)?;
    let s = welch.try_psd(y)?;
    let s_hi = welch_hi.try_psd(y)?;
    let n_bins = welch.n_bins();
    let bins = 1..n_bins;
    let eps = crate::metric::floor_of(&s, bins.clone(), -30.0);
    identify(&s_hi, welch_hi.df(), fs, max_order, 0.1, |p| {
        crate::metric::regularised_lsd(&s, &p.psd(n_bins, welch.df()), bins.clone(), eps)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A known AR(2) (one mode at 1 kHz, r = 0.98, fs = 10 kHz): the PSD it implies gives back
    /// its coefficients, its mode frequency and its damping (closed form: ζ = −ln r / |ln z|).
    #[test]
    fn recovers_a_known_mode() {
        let fs = 10_000.0;
        let (r, th) = (0.98f64, 2.0 * PI * 1000.0 / fs);
        let truth = StructuralPath {
            fs_hz: fs,
            ar: vec![-2.0 * r * th.cos(), r * r],
            excitation_variance: 0.5,
        };
        let n = 4097;
        let df = fs / 8192.0;
        let psd = truth.psd(n, df);
        let est = StructuralPath::from_psd(&psd, df, fs, 2).unwrap();
        for (a, b) in est.ar.iter().zip(&truth.ar) {
            assert!((a - b).abs() < 1e-3, "{:?} vs {:?}", est.ar, truth.ar);
        }
        assert!((est.excitation_variance / 0.5 - 1.0).abs() < 1e-2);
        let m = est.modes();
        assert_eq!(m.len(), 1);
        assert!((m[0].frequency_hz - 1000.0).abs() < 1.0, "{m:?}");
        let s = nalgebra::Complex::new(r * th.cos(), r * th.sin()).ln();
        let zeta = -s.re / s.norm();
        assert!((m[0].damping_ratio - zeta).abs() < 1e-3, "{m:?} vs {zeta}");
        // prediction error inverts the filter
        let x: Vec<f64> = (0..200).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let y = truth.filter(&x);
        let e = truth.prediction_error(&y);
        for (a, b) in e.iter().zip(&x) {
            assert!((a - b).abs() < 1e-9);
        }
    }

    #[test]
    fn line_free_removes_a_line_and_keeps_a_broad_bump() {
        let mut s: Vec<f64> = (0..1000)
            .map(|k| 1.0 + 9.0 * (-((k as f64 - 500.0) / 60.0).powi(2)).exp())
            .collect();
        s[200] = 1000.0;
        let f = line_free(&s, 20, 4.0);
        assert!(f[200] < 2.0);
        assert!((f[500] - s[500]).abs() < 1e-9);
    }

    /// A simulated AR(4) (two modes) read back from its own samples: both mode frequencies
    /// within 3 %, and a short record is a typed error.
    #[test]
    fn identifies_modes_from_a_signal() {
        let fs = 12_000.0;
        let pairs = [(0.97f64, 1500.0f64), (0.95, 3500.0)];
        let mut a = vec![1.0];
        for (r, f) in pairs {
            let th = 2.0 * PI * f / fs;
            let q = [1.0, -2.0 * r * th.cos(), r * r];
            let mut n = vec![0.0; a.len() + 2];
            for (i, ai) in a.iter().enumerate() {
                for (j, qj) in q.iter().enumerate() {
                    n[i + j] += ai * qj;
                }
            }
            a = n;
        }
        let truth = StructuralPath {
            fs_hz: fs,
            ar: a[1..].to_vec(),
            excitation_variance: 1.0,
        };
        // deterministic white-ish excitation (xorshift)
        let mut st = 0x9E37_79B9_7F4A_7C15u64;
        let x: Vec<f64> = (0..48_000)
            .map(|_| {
                st ^= st << 13;
                st ^= st >> 7;
                st ^= st << 17;
                (st >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let y = truth.filter(&x);
        let est = identify_from_signal(&y, fs, 64).unwrap();
        let modes: Vec<f64> = est
            .modes()
            .iter()
            .filter(|m| m.frequency_hz > 0.0 && m.damping_ratio < 0.05)
            .map(|m| m.frequency_hz)
            .collect();
        for (_, f) in pairs {
            assert!(
                modes.iter().any(|m| (m / f - 1.0).abs() < 0.03),
                "{f} Hz not among {modes:?}"
            );
        }
        assert!(matches!(
            identify_from_signal(&y[..1000], fs, 64),
            Err(CloseLoopError::TooShort { .. })
        ));
    }

    /// The prediction error through the shared loop gives the bits of its definition
    /// `y(n) + Σ_{k ≤ min(n, p)} α_k y(n−k)`, for every length around the loop's block size.
    #[test]
    fn prediction_error_is_the_definition_bit_for_bit() {
        let path = StructuralPath {
            fs_hz: 1000.0,
            ar: (0..7).map(|i| 0.3 / (i as f64 + 1.0) - 0.05).collect(),
            excitation_variance: 1.0,
        };
        for n in 0..60 {
            let y: Vec<f64> = (0..n)
                .map(|k| (0.7 * k as f64).sin() + 0.01 * k as f64)
                .collect();
            let definition: Vec<u64> = (0..n)
                .map(|i| {
                    let mut v = y[i];
                    for k in 1..=path.order().min(i) {
                        v += path.ar[k - 1] * y[i - k];
                    }
                    v.to_bits()
                })
                .collect();
            let shared: Vec<u64> = path
                .prediction_error(&y)
                .iter()
                .map(|v| v.to_bits())
                .collect();
            assert_eq!(shared, definition, "length {n}");
        }
    }

    #[test]
    fn levinson_rejects_zero_power() {
        assert!(levinson(&[0.0, 0.0]).is_err());
    }
}
