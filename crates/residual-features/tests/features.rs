//! Reference-value and property tests for windowing, statistics, spectra and window features.
//!
//! Provenance: closed forms only. Kurtosis of a sine over whole periods is 3/2 (E[sin⁴]/E[sin²]² =
//! (3/8)/(1/4)); of Gaussian noise 3. A bin-centred sine of amplitude a has one-sided amplitude a.
//! The envelope of (1 + m cos 2πf_m t) cos 2πf_c t is 1 + m cos 2πf_m t, so its envelope spectrum
//! peaks at f_m with amplitude m. One-sided Parseval: bands tiling [0, fs/2] sum to Σx².

use std::f64::consts::PI;

use approx::assert_relative_eq;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

/// The committed regression seeds, replayed before new cases (path relative to the crate root,
/// where `cargo test` runs integration tests).
const REGRESSIONS: &str = "tests/features.proptest-regressions";

#[test]
fn regression_seed_file_is_the_one_committed() {
    let text = std::fs::read_to_string(REGRESSIONS).expect("committed proptest seeds");
    assert!(
        text.lines().any(|l| l.starts_with("cc ")),
        "no seed in {REGRESSIONS}"
    );
}
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use residual_features::*;

fn sine(n: usize, fs: f64, f: f64, a: f64) -> Vec<f64> {
    (0..n)
        .map(|k| a * (2.0 * PI * f * k as f64 / fs).sin())
        .collect()
}

fn gaussian(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n).map(|_| StandardNormal.sample(&mut rng)).collect()
}

#[test]
fn energy_matches_closed_form() {
    // Σ_{k=1}^{n} k² = n(n+1)(2n+1)/6
    let x: Vec<f64> = (1..=10).map(f64::from).collect();
    assert_eq!(energy(&x).unwrap(), 385.0);
    assert_relative_eq!(rms(&x).unwrap(), (38.5f64).sqrt());
    assert_eq!(peak(&[-3.0, 2.0]).unwrap(), 3.0);
}

#[test]
fn kurtosis_of_sine_is_one_and_a_half() {
    let x = sine(1200, 1200.0, 10.0, 2.0); // 10 whole periods
    assert_relative_eq!(kurtosis(&x).unwrap(), 1.5, epsilon = 1e-9);
    assert_relative_eq!(skewness(&x).unwrap(), 0.0, epsilon = 1e-9);
    assert_relative_eq!(crest_factor(&x).unwrap(), 2f64.sqrt(), epsilon = 1e-3);
}

#[test]
fn kurtosis_of_gaussian_noise_is_three() {
    let x = gaussian(200_000, 7);
    // standard error of sample kurtosis ≈ sqrt(24/n) ≈ 0.011
    assert!((kurtosis(&x).unwrap() - 3.0).abs() < 0.05);
    assert!(skewness(&x).unwrap().abs() < 0.03);
}

#[test]
fn bad_input_gets_typed_errors() {
    assert_eq!(energy(&[]), Err(FeatureError::Empty));
    assert!(matches!(
        energy(&[1.0, f64::NAN]),
        Err(FeatureError::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        kurtosis(&[1.0; 8]),
        Err(FeatureError::ZeroSpread { .. })
    ));
    assert!(matches!(
        crest_factor(&[0.0; 8]),
        Err(FeatureError::ZeroSpread { .. })
    ));
    assert!(Band::new(10.0, 5.0).is_err());
    assert!(Band::new(f64::NAN, 5.0).is_err());
    assert!(matches!(
        amplitude_spectrum(&[1.0, 2.0], 0.0, Taper::Hann),
        Err(FeatureError::InvalidParameter { name: "fs_hz", .. })
    ));
    assert!(
        welch_psd(
            &[1.0; 10],
            1.0,
            WelchConfig {
                segment_len: 16,
                overlap: 8
            }
        )
        .is_err()
    );
    assert!(
        welch_psd(
            &[1.0; 10],
            1.0,
            WelchConfig {
                segment_len: 4,
                overlap: 4
            }
        )
        .is_err()
    );
    assert!(
        FeatureExtractor::new(FeatureConfig {
            features: vec![],
            sample_rate_hz: None,
            envelope: None
        })
        .is_err()
    );
    let needs_rate = FeatureConfig {
        features: vec![Feature::BandEnergy(Band::new(1.0, 2.0).unwrap())],
        sample_rate_hz: None,
        envelope: None,
    };
    assert!(FeatureExtractor::new(needs_rate).is_err());
    let needs_env = FeatureConfig {
        features: vec![Feature::EnvelopeLine {
            line: FaultLine::Bpfi,
            harmonic: 1,
        }],
        sample_rate_hz: Some(12_000.0),
        envelope: None,
    };
    assert!(FeatureExtractor::new(needs_env).is_err());
}

#[test]
fn window_counts_and_tail_policy() {
    let n = 1003;
    let plan = WindowPlan::new(Windowing::FixedCount { count: 10 }, TailPolicy::Discard).unwrap();
    let set = plan.split(n).unwrap();
    assert_eq!(set.len(), 10);
    assert!(set.ranges().iter().all(|r| r.len() == 100));
    assert_eq!(set.discarded_tail(), Some(1000..1003));

    let reject =
        WindowPlan::new(Windowing::FixedLength { length: 100 }, TailPolicy::Reject).unwrap();
    assert_eq!(
        reject.split(n),
        Err(FeatureError::TailRejected { len: 1003, tail: 3 })
    );
    assert_eq!(reject.split(1000).unwrap().len(), 10);

    let keep = WindowPlan::new(
        Windowing::FixedLength { length: 100 },
        TailPolicy::KeepShort,
    )
    .unwrap();
    let set = keep.split(n).unwrap();
    assert_eq!(set.len(), 11);
    assert_eq!(set.ranges()[10], 1000..1003);
    assert_eq!(set.discarded_tail(), None);

    let slide = WindowPlan::new(
        Windowing::Sliding {
            length: 100,
            hop: 50,
        },
        TailPolicy::Discard,
    )
    .unwrap();
    let set = slide.split(n).unwrap();
    assert_eq!(set.len(), 19); // starts 0..=900 step 50
    assert_eq!(set.ranges()[18], 900..1000);
    assert_eq!(set.discarded_tail(), Some(1000..1003));

    assert!(WindowPlan::new(Windowing::FixedCount { count: 4 }, TailPolicy::KeepShort).is_err());
    assert!(
        WindowPlan::new(
            Windowing::Sliding { length: 4, hop: 0 },
            TailPolicy::Discard
        )
        .is_err()
    );
    assert!(WindowPlan::new(Windowing::FixedLength { length: 0 }, TailPolicy::Discard).is_err());
    assert!(matches!(
        plan.split(5),
        Err(FeatureError::TooShort {
            needed: 10,
            found: 5
        })
    ));
}

#[test]
fn amplitude_spectrum_reads_sine_amplitude() {
    let fs = 1000.0;
    let x = sine(1000, fs, 50.0, 3.0);
    for taper in [Taper::Rectangular, Taper::Hann] {
        let s = amplitude_spectrum(&x, fs, taper).unwrap();
        assert_relative_eq!(s.resolution_hz, 1.0);
        let p = s.peak_in_band(Band::new(40.0, 60.0).unwrap()).unwrap();
        assert_relative_eq!(p.frequency_hz, 50.0);
        assert_relative_eq!(p.value, 3.0, epsilon = 1e-9);
    }
}

#[test]
fn welch_psd_integrates_to_variance() {
    let fs = 2000.0;
    let x = gaussian(64_000, 3);
    let var = x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64;
    let psd = welch_psd(&x, fs, WelchConfig::half_overlap(256)).unwrap();
    let total: f64 = psd.values.iter().sum::<f64>() * psd.resolution_hz;
    assert!((total / var - 1.0).abs() < 0.02, "{total} vs {var}");
    // white noise: flat at 2σ²/fs one-sided
    let mid = psd.values[64];
    assert!((mid / (2.0 * var / fs) - 1.0).abs() < 0.3);
    // a sine of amplitude a carries a²/2 in its peak area
    let s = sine(64_000, fs, 250.0, 2.0);
    let psd = welch_psd(&s, fs, WelchConfig::half_overlap(256)).unwrap();
    let area: f64 = psd.values[28..37].iter().sum::<f64>() * psd.resolution_hz;
    assert_relative_eq!(area, 2.0, epsilon = 1e-3);
}

#[test]
fn envelope_spectrum_of_am_carrier_peaks_at_modulation_rate() {
    let fs = 12_000.0;
    let (fc, fm, m) = (3000.0, 105.0, 0.5);
    let n = 12_000;
    let x: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 / fs;
            (1.0 + m * (2.0 * PI * fm * t).cos()) * (2.0 * PI * fc * t).cos()
        })
        .collect();
    let env = hilbert_envelope(&x).unwrap();
    // interior samples follow 1 + m cos
    for k in (1000..11_000).step_by(997) {
        let t = k as f64 / fs;
        assert_relative_eq!(env[k], 1.0 + m * (2.0 * PI * fm * t).cos(), epsilon = 1e-6);
    }
    let spec = envelope_spectrum(
        &x,
        fs,
        Some(Band::new(2000.0, 4000.0).unwrap()),
        Taper::Rectangular,
    )
    .unwrap();
    let p = spec.peak_in_band(Band::new(5.0, 1000.0).unwrap()).unwrap();
    assert_relative_eq!(p.frequency_hz, fm);
    assert_relative_eq!(p.value, m, epsilon = 1e-6);
}

#[test]
fn bandpass_keeps_in_band_tone_only() {
    let fs = 1000.0;
    let a = sine(1000, fs, 50.0, 1.0);
    let b = sine(1000, fs, 200.0, 1.0);
    let x: Vec<f64> = a.iter().zip(&b).map(|(p, q)| p + q).collect();
    let y = bandpass_fft(&x, fs, Band::new(150.0, 250.0).unwrap()).unwrap();
    for (yi, bi) in y.iter().zip(&b) {
        assert_relative_eq!(yi, bi, epsilon = 1e-9);
    }
}

#[test]
fn envelope_features_name_the_right_line() {
    // Impacts at BPFI of a 1797 rpm shaft, each ringing a 3 kHz resonance.
    let fs = 12_000.0;
    let fr = 1797.0 / 60.0;
    let m = bearing_model::BearingGeometry::skf_6205().orders();
    let fi = m.bpfi * fr;
    let n = 12_000;
    let mut x = gaussian(n, 11)
        .into_iter()
        .map(|v| 0.05 * v)
        .collect::<Vec<_>>();
    let mut t_hit = 0.0;
    while t_hit < n as f64 / fs {
        let k0 = (t_hit * fs) as usize;
        for j in 0..200.min(n - k0) {
            let t = j as f64 / fs;
            x[k0 + j] += (-t * 800.0).exp() * (2.0 * PI * 3000.0 * t).sin();
        }
        t_hit += 1.0 / fi;
    }
    let env = EnvelopeSettings {
        shaft_hz: fr,
        multiples: m,
        demodulation_band: Some(Band::new(2000.0, 4000.0).unwrap()),
        tolerance: 0.02,
    };
    let mut fx = FeatureExtractor::new(FeatureConfig::full(
        fs,
        env,
        &[Band::new(2000.0, 4000.0).unwrap()],
    ))
    .unwrap();
    let names = fx.names();
    let row = fx.extract(&x).unwrap();
    let get = |name: &str| row[names.iter().position(|s| s == name).unwrap()];
    let bpfi = get("env_bpfi_x1");
    for other in ["env_bpfo_x1", "env_ball_x1", "env_ftf_x1", "env_fr_x1"] {
        assert!(
            bpfi > 3.0 * get(other),
            "bpfi {bpfi} vs {other} {}",
            get(other)
        );
    }
    assert!(get("env_bpfi_x2") > 2.0 * get("env_bpfo_x2"));
    assert!(get("kurtosis") > 3.0);
    assert_eq!(names.len(), row.len());
}

#[test]
fn same_extractor_runs_on_raw_and_residual() {
    let x = gaussian(4000, 5);
    let plan = WindowPlan::new(Windowing::FixedCount { count: 8 }, TailPolicy::Reject).unwrap();
    let mut fx = FeatureExtractor::new(FeatureConfig::time_domain()).unwrap();
    let t = fx.extract_windows(&x, &plan).unwrap();
    assert_eq!(t.rows.len(), 8);
    assert_eq!(t.names.len(), 6);
    let t2 = fx.extract_windows(&x, &plan).unwrap();
    assert_eq!(t, t2, "deterministic");
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(REGRESSIONS))),
        ..ProptestConfig::default()
    })]

    #[test]
    fn energy_is_sum_of_squares(x in prop::collection::vec(-1e3f64..1e3, 1..300)) {
        let e = energy(&x).unwrap();
        let mut s = 0.0;
        for v in &x { s += v * v; }
        prop_assert!((e - s).abs() <= 1e-12 * s.max(1.0));
        // and the Parseval band energy over [0, fs/2] agrees
        let fs = 100.0;
        if x.len() >= 2 {
            let b = band_energy(&x, fs, Band::new(0.0, fs / 2.0).unwrap()).unwrap();
            prop_assert!((b - s).abs() <= 1e-9 * s.max(1.0));
            // two tiling bands add up
            let df = fs / x.len() as f64;
            let cut = (x.len() / 4) as f64 * df;
            let lo = band_energy(&x, fs, Band::new(0.0, cut + 0.5 * df).unwrap()).unwrap();
            let hi = band_energy(&x, fs, Band::new(cut + 0.5 * df, fs / 2.0).unwrap()).unwrap();
            prop_assert!((lo + hi - s).abs() <= 1e-9 * s.max(1.0));
        }
    }

    #[test]
    fn windows_never_overlap_and_account_for_every_sample(
        n in 1usize..5000, len in 1usize..400, count in 1usize..50
    ) {
        for windowing in [Windowing::FixedLength { length: len }, Windowing::FixedCount { count }] {
            let plan = WindowPlan::new(windowing, TailPolicy::Discard).unwrap();
            match plan.split(n) {
                Ok(set) => {
                    let mut next = 0;
                    for r in set.ranges() {
                        prop_assert_eq!(r.start, next);
                        next = r.end;
                    }
                    let tail = set.discarded_tail().map_or(0, |t| t.len());
                    prop_assert_eq!(next + tail, n);
                    if let Windowing::FixedCount { count } = windowing {
                        prop_assert_eq!(set.len(), count);
                        prop_assert!(tail < count);
                    } else {
                        prop_assert!(tail < len);
                    }
                }
                Err(FeatureError::TooShort { .. }) => {
                    let need = match windowing { Windowing::FixedLength { length } => length, _ => count };
                    prop_assert!(n < need);
                }
                Err(e) => prop_assert!(false, "unexpected {e}"),
            }
        }
    }

    #[test]
    fn sliding_windows_have_equal_length_and_hop(n in 1usize..3000, len in 1usize..300, hop in 1usize..300) {
        let plan = WindowPlan::new(Windowing::Sliding { length: len, hop }, TailPolicy::Discard).unwrap();
        if let Ok(set) = plan.split(n) {
            for (i, r) in set.ranges().iter().enumerate() {
                prop_assert_eq!(r.start, i * hop);
                prop_assert_eq!(r.len(), len);
            }
            let end = set.ranges().last().unwrap().end;
            prop_assert!(end <= n);
            prop_assert!(end + hop > n || set.ranges().last().unwrap().start + hop + len > n);
        } else {
            prop_assert!(n < len);
        }
    }
}

#[test]
fn random_windows_are_finite() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let x: Vec<f64> = (0..2048).map(|_| rng.random_range(-1.0..1.0)).collect();
    let mut fx = FeatureExtractor::new(FeatureConfig::time_domain()).unwrap();
    assert!(fx.extract(&x).unwrap().iter().all(|v| v.is_finite()));
}
