//! Decimation by an integer factor with a linear-phase Kaiser-windowed-sinc anti-aliasing FIR.
//!
//! Design (see `docs/equations/bearing-data.md`): for factor `D` the new Nyquist frequency is
//! `fs/(2D)`. The passband edge is `fp = ρ·fs/(2D)` (ρ = `passband_fraction`, default 0.8) and the
//! stopband starts at the new Nyquist `fs/(2D)`, so every tone that would alias is attenuated by
//! at least `A` dB (default 80). Kaiser's formulas give the window shape
//! `β = 0.1102 (A − 8.7)` (A > 50) and the length `N = ⌈(A − 7.95) / (2.285 · Δω)⌉ + 1`, with
//! `Δω = 2π (fs/(2D) − fp)/fs`, rounded up to odd so the filter is type I with an integer group
//! delay `(N − 1)/2`. Taps are the ideal low-pass `2fc·sinc(2fc(n − M))` at
//! `fc = (fp + fs/(2D))/2`, times the window, normalised to unit DC gain.
//!
//! Only the kept samples are computed (output `m` is the filter centred on input `mD`, so the
//! group delay is compensated and output `m` is time-aligned with input `mD`). Beyond both ends
//! the signal is extended by mirror reflection about the end samples, which avoids the step
//! transient that zero padding would put at the edges.

use std::f64::consts::PI;

use crate::error::{DataError, Result};

/// Parameters of a [`Decimator`], validated by [`Decimator::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecimatorParams {
    /// Integer decimation factor `D ≥ 1` (at most 256); 1 is the identity.
    pub factor: usize,
    /// Passband edge as a fraction of the new Nyquist frequency, in [0.5, 0.95]; default 0.8.
    pub passband_fraction: f64,
    /// Minimum stopband attenuation `A` in dB, in [40, 150]; default 80.
    pub stopband_attenuation_db: f64,
}

impl DecimatorParams {
    /// Default design (passband 0.8 of the new Nyquist, 80 dB stopband) for `factor`.
    pub fn new(factor: usize) -> Self {
        Self {
            factor,
            passband_fraction: 0.8,
            stopband_attenuation_db: 80.0,
        }
    }

    /// The passband edge, Hz, for an input sampled at `input_fs_hz`:
    /// `passband_fraction · input_fs_hz / (2D)`. Above it, up to the new Nyquist frequency, the
    /// output holds the filter's transition band, not the input's signal.
    pub fn passband_edge_hz(&self, input_fs_hz: f64) -> f64 {
        self.passband_fraction * input_fs_hz / (2.0 * self.factor as f64)
    }
}

/// A designed decimation filter; reuse it across signals.
#[derive(Debug, Clone, PartialEq)]
pub struct Decimator {
    params: DecimatorParams,
    taps: Vec<f64>,
}

/// Zeroth-order modified Bessel function of the first kind, by its power series.
fn bessel_i0(x: f64) -> f64 {
    let q = x * x / 4.0;
    let (mut sum, mut term, mut k) = (1.0, 1.0, 1.0);
    while term > 1e-17 * sum {
        term *= q / (k * k);
        sum += term;
        k += 1.0;
    }
    sum
}

impl Decimator {
    /// Design the filter. Errors: factor 0 or > 256, passband fraction outside [0.5, 0.95],
    /// attenuation outside [40, 150] dB (all [`DataError::InvalidParameter`]).
    pub fn new(params: DecimatorParams) -> Result<Self> {
        let DecimatorParams {
            factor,
            passband_fraction: rho,
            stopband_attenuation_db: a,
        } = params;
        if factor == 0 || factor > 256 {
            return Err(DataError::InvalidParameter {
                name: "factor",
                value: factor as f64,
                reason: "decimation factor must be an integer in 1..=256",
            });
        }
        if !(0.5..=0.95).contains(&rho) {
            return Err(DataError::InvalidParameter {
                name: "passband_fraction",
                value: rho,
                reason: "must be in [0.5, 0.95]",
            });
        }
        if !(40.0..=150.0).contains(&a) {
            return Err(DataError::InvalidParameter {
                name: "stopband_attenuation_db",
                value: a,
                reason: "must be in [40, 150] dB",
            });
        }
        if factor == 1 {
            return Ok(Self {
                params,
                taps: vec![1.0],
            });
        }
        let d = factor as f64;
        // Frequencies normalised to the input rate (cycles/sample).
        let f_stop = 0.5 / d;
        let f_pass = rho * f_stop;
        let fc = 0.5 * (f_pass + f_stop);
        let dw = 2.0 * PI * (f_stop - f_pass);
        let beta = if a > 50.0 {
            0.1102 * (a - 8.7)
        } else {
            0.5842 * (a - 21.0).powf(0.4) + 0.07886 * (a - 21.0)
        };
        let mut n = ((a - 7.95) / (2.285 * dw)).ceil() as usize + 1;
        if n % 2 == 0 {
            n += 1;
        }
        let m = (n - 1) / 2;
        let i0b = bessel_i0(beta);
        let mut taps: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 - m as f64;
                let x = 2.0 * fc * t;
                let sinc = if t == 0.0 {
                    1.0
                } else {
                    (PI * x).sin() / (PI * x)
                };
                let r = t / m as f64;
                let w = bessel_i0(beta * (1.0 - r * r).max(0.0).sqrt()) / i0b;
                2.0 * fc * sinc * w
            })
            .collect();
        let sum: f64 = taps.iter().sum();
        taps.iter_mut().for_each(|h| *h /= sum);
        Ok(Self { params, taps })
    }

    /// The design parameters.
    pub fn params(&self) -> DecimatorParams {
        self.params
    }

    /// The decimation factor.
    pub fn factor(&self) -> usize {
        self.params.factor
    }

    /// The FIR taps (odd length, symmetric, unit sum).
    pub fn taps(&self) -> &[f64] {
        &self.taps
    }

    /// Group delay in input samples, `(N − 1)/2` (compensated by [`decimate`](Self::decimate)).
    pub fn group_delay(&self) -> usize {
        (self.taps.len() - 1) / 2
    }

    /// Filter and keep every `D`-th sample: `y[m] = Σ_j h[j] · x[mD − M + j]`, with mirror
    /// extension beyond the ends. Output length `⌈len/D⌉`; output `m` aligns with input `mD`.
    ///
    /// Errors: empty input ([`DataError::Empty`]); a NaN/∞ sample ([`DataError::NonFinite`]);
    /// a sample of magnitude ≥ [`crate::MAX_SAMPLE_MAGNITUDE`] ([`DataError::SampleTooLarge`]).
    pub fn decimate(&self, x: &[f64]) -> Result<Vec<f64>> {
        if x.is_empty() {
            return Err(DataError::Empty {
                what: "signal to decimate",
            });
        }
        crate::error::check_samples(|| "signal to decimate".into(), x, 0)?;
        let d = self.params.factor;
        if d == 1 {
            return Ok(x.to_vec());
        }
        let n = x.len();
        let m_half = self.group_delay();
        let h = &self.taps;
        let out_len = n.div_ceil(d);
        let mut y = Vec::with_capacity(out_len);
        for m in 0..out_len {
            let c = m * d;
            let v = if c >= m_half && c + m_half < n {
                dot(&x[c - m_half..=c + m_half], h)
            } else {
                h.iter()
                    .enumerate()
                    .map(|(j, hj)| hj * x[reflect(c as isize - m_half as isize + j as isize, n)])
                    .sum()
            };
            y.push(v);
        }
        Ok(y)
    }
}

/// Dot product with four independent accumulators (lets the compiler vectorise; the summation
/// order differs from a plain left fold only by rounding).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (p, q) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += p[k] * q[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(p, q)| p * q).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Mirror index `i` into `0..n` (whole-sample symmetric extension, repeated as needed).
fn reflect(i: isize, n: usize) -> usize {
    if n == 1 {
        return 0;
    }
    let period = 2 * (n as isize - 1);
    let r = i.rem_euclid(period);
    (if r >= n as isize { period - r } else { r }) as usize
}

/// Decimate `x` by `factor` with the default design ([`DecimatorParams::new`]).
pub fn decimate(x: &[f64], factor: usize) -> Result<Vec<f64>> {
    Decimator::new(DecimatorParams::new(factor))?.decimate(x)
}

/// The integer factor taking `from_hz` to `to_hz`, or [`DataError::NotIntegerFactor`].
pub fn integer_factor(from_hz: f64, to_hz: f64) -> Result<usize> {
    let bad = || DataError::NotIntegerFactor { from_hz, to_hz };
    if !(from_hz.is_finite() && to_hz.is_finite() && from_hz > 0.0 && to_hz > 0.0)
        || to_hz > from_hz
    {
        return Err(bad());
    }
    let r = from_hz / to_hz;
    let k = r.round();
    if (r - k).abs() > 1e-9 * r || k > 256.0 {
        return Err(bad());
    }
    Ok(k as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflect_mirrors_about_end_samples() {
        let n = 5;
        let got: Vec<usize> = (-3..9).map(|i| reflect(i, n)).collect();
        assert_eq!(got, vec![3, 2, 1, 0, 1, 2, 3, 4, 3, 2, 1, 0]);
    }

    #[test]
    fn bessel_i0_reference_values() {
        // Abramowitz & Stegun Table 9.8: I0(1) = 1.266065878, I0(5) = 27.23987182.
        assert!((bessel_i0(1.0) - 1.266_065_878).abs() < 1e-8);
        assert!((bessel_i0(5.0) - 27.239_871_82).abs() < 1e-6);
    }
}
