//! Anti-aliasing decimation: passband flatness, stopband attenuation, alignment, errors.

use bearing_data::{DataError, Decimator, DecimatorParams, decimate, integer_factor};
use proptest::prelude::*;

const FS: f64 = 48_000.0;

fn tone(f: f64, n: usize, phase: f64) -> Vec<f64> {
    (0..n)
        .map(|k| (2.0 * std::f64::consts::PI * f * k as f64 / FS + phase).sin())
        .collect()
}

/// Amplitude of the component at `f` (Hz, at rate `fs`) by least squares on sin/cos, skipping
/// `skip` samples at each end.
fn amplitude(y: &[f64], f: f64, fs: f64, skip: usize) -> f64 {
    let w = 2.0 * std::f64::consts::PI * f / fs;
    let (mut ss, mut cc, mut sc, mut ys, mut yc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, v) in y.iter().enumerate().skip(skip).take(y.len() - 2 * skip) {
        let (s, c) = (w * k as f64).sin_cos();
        ss += s * s;
        cc += c * c;
        sc += s * c;
        ys += v * s;
        yc += v * c;
    }
    let det = ss * cc - sc * sc;
    let a = (ys * cc - yc * sc) / det;
    let b = (yc * ss - ys * sc) / det;
    a.hypot(b)
}

fn rms(y: &[f64], skip: usize) -> f64 {
    let s = &y[skip..y.len() - skip];
    (s.iter().map(|v| v * v).sum::<f64>() / s.len() as f64).sqrt()
}

#[test]
fn passband_tones_keep_amplitude_within_0_1_db() {
    let dec = Decimator::new(DecimatorParams::new(4)).unwrap();
    // New Nyquist 6 kHz, passband edge 0.8 · 6 kHz = 4.8 kHz.
    for f in [50.0, 500.0, 1_000.0, 2_500.0, 3_700.0, 4_500.0, 4_800.0] {
        let y = dec.decimate(&tone(f, 48_000, 0.3)).unwrap();
        let a = amplitude(&y, f, FS / 4.0, 200);
        let db = 20.0 * a.log10();
        assert!(db.abs() < 0.1, "{f} Hz: {db:.4} dB");
    }
}

#[test]
fn tones_above_the_new_nyquist_are_attenuated_by_more_than_60_db() {
    let dec = Decimator::new(DecimatorParams::new(4)).unwrap();
    for f in [
        6_000.0, 6_500.0, 7_200.0, 9_000.0, 12_000.0, 17_000.0, 23_900.0,
    ] {
        let y = dec.decimate(&tone(f, 48_000, 0.7)).unwrap();
        // Whatever aliases into 0–6 kHz: total output power relative to the input's (1/√2).
        let db = 20.0 * (rms(&y, 200) / std::f64::consts::FRAC_1_SQRT_2).log10();
        assert!(db < -60.0, "{f} Hz: {db:.1} dB");
    }
}

#[test]
fn group_delay_is_compensated() {
    // Output m aligns with input 4m: a passband tone keeps its phase.
    let x = tone(1_000.0, 4_800, 0.0);
    let y = decimate(&x, 4).unwrap();
    for m in 100..1_000 {
        assert!(
            (y[m] - x[4 * m]).abs() < 1e-3,
            "m={m}: {} vs {}",
            y[m],
            x[4 * m]
        );
    }
}

#[test]
fn filter_is_symmetric_odd_and_unit_gain() {
    for factor in [2, 3, 4, 8] {
        let d = Decimator::new(DecimatorParams::new(factor)).unwrap();
        let h = d.taps();
        assert_eq!(h.len() % 2, 1);
        assert!((h.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        for k in 0..h.len() {
            assert!((h[k] - h[h.len() - 1 - k]).abs() < 1e-15);
        }
    }
}

#[test]
fn bad_parameters_and_inputs_are_typed_errors() {
    assert!(matches!(
        decimate(&[1.0, 2.0], 0),
        Err(DataError::InvalidParameter { name: "factor", .. })
    ));
    assert!(matches!(decimate(&[], 4), Err(DataError::Empty { .. })));
    assert!(matches!(
        decimate(&[1.0, f64::INFINITY], 4),
        Err(DataError::NonFinite { index: 1, .. })
    ));
    let p = DecimatorParams {
        passband_fraction: 1.2,
        ..DecimatorParams::new(4)
    };
    assert!(matches!(
        Decimator::new(p),
        Err(DataError::InvalidParameter {
            name: "passband_fraction",
            ..
        })
    ));
    let p = DecimatorParams {
        stopband_attenuation_db: f64::NAN,
        ..DecimatorParams::new(4)
    };
    assert!(Decimator::new(p).is_err());
    assert_eq!(integer_factor(48_000.0, 12_000.0).unwrap(), 4);
    assert!(integer_factor(48_000.0, 0.0).is_err());
    assert!(integer_factor(12_000.0, 48_000.0).is_err());
    assert!(integer_factor(48_000.0, 7_000.0).is_err());
    assert_eq!(decimate(&[3.0, 4.0], 1).unwrap(), vec![3.0, 4.0]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A constant is preserved exactly (unit DC gain, mirror extension) and the length is ⌈n/D⌉.
    #[test]
    fn constant_signals_are_preserved(c in -1e3f64..1e3, n in 1usize..400, factor in 1usize..9) {
        let y = decimate(&vec![c; n], factor).unwrap();
        prop_assert_eq!(y.len(), n.div_ceil(factor));
        for v in y {
            prop_assert!((v - c).abs() <= 1e-9 * c.abs().max(1.0));
        }
    }

    /// Decimation is linear: D(a·x + y) = a·D(x) + D(y).
    #[test]
    fn decimation_is_linear(x in prop::collection::vec(-1.0f64..1.0, 1..300), a in -3.0f64..3.0) {
        let y: Vec<f64> = x.iter().rev().copied().collect();
        let z: Vec<f64> = x.iter().zip(&y).map(|(p, q)| a * p + q).collect();
        let (dx, dy, dz) = (decimate(&x, 3).unwrap(), decimate(&y, 3).unwrap(), decimate(&z, 3).unwrap());
        for k in 0..dz.len() {
            prop_assert!((dz[k] - (a * dx[k] + dy[k])).abs() < 1e-9);
        }
    }
}
