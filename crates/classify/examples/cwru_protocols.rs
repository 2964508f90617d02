//! The five protocols on raw CWRU drive-end windows (no observer): energy only (the dissertation's
//! feature) and the time-domain set, with the one-vs-one linear SVM and the Gini tree.
//!
//! Classes: normal (97, 48 kHz decimated to 12 kHz), ball / inner / outer@6 at 0.007, 0.014 and
//! 0.021 in, loads 0–3 hp, 12 kHz. Windows of 300 samples (= 120k samples / 400, the
//! dissertation's 400 windows per recording), the first `PER_RECORDING` windows of each record.
//!
//! `cargo run --release -p classify --example cwru_protocols`

use std::path::Path;

use bearing_data::{DataLocation, LoadOptions, load_record};
use classify::*;
use residual_features::{FeatureConfig, FeatureExtractor, TailPolicy, WindowPlan, Windowing};

const PER_RECORDING: usize = 50;

fn main() -> std::result::Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let loc = DataLocation::resolve(None, &root)?;
    let dir = loc.required()?;
    let classes = ["normal", "ball", "inner", "outer"]
        .map(String::from)
        .to_vec();
    let mut recs: Vec<(usize, u32, u32, Option<u32>)> = vec![(0, 97, 0, None)];
    let groups: [(usize, [[u32; 4]; 3]); 3] = [
        (
            1,
            [
                [118, 119, 120, 121],
                [185, 186, 187, 188],
                [222, 223, 224, 225],
            ],
        ),
        (
            2,
            [
                [105, 106, 107, 108],
                [169, 170, 171, 172],
                [209, 210, 211, 212],
            ],
        ),
        (
            3,
            [
                [130, 131, 132, 133],
                [197, 198, 199, 200],
                [234, 235, 236, 237],
            ],
        ),
    ];
    for (class, sizes) in groups {
        for (s, numbers) in sizes.iter().enumerate() {
            for (load, &n) in numbers.iter().enumerate() {
                recs.push((class, n, load as u32, Some(7 * (s as u32 + 1))));
            }
        }
    }
    let plan = WindowPlan::new(Windowing::FixedLength { length: 300 }, TailPolicy::Discard)?;
    for (label, config) in [
        ("energy", FeatureConfig::energy_only()),
        ("time-domain set", FeatureConfig::time_domain()),
    ] {
        let mut fx = FeatureExtractor::new(config)?;
        let mut b = Dataset::builder(classes.clone(), fx.names());
        for &(class, n, load_hp, fault_size_mils) in &recs {
            let rec = load_record(dir, n, &LoadOptions::default())?;
            let de = rec.de_at(12_000.0)?;
            let mut rows = fx.extract_windows(&de, &plan)?.rows;
            rows.truncate(PER_RECORDING);
            let info = RecordingInfo {
                class,
                recording: n.to_string(),
                load_hp,
                fault_size_mils,
                speed_rpm: None,
            };
            b.add_recording(&info, rows);
        }
        let data = b.build()?;
        println!(
            "\n## Raw DE signal, features: {label} ({} windows)\n",
            data.n_samples()
        );
        let plans = [
            random_window_split(&data, &RandomSplitConfig::default())?,
            time_blocked(&data, 0.25)?,
            grouped_by_recording(&data, &GroupedConfig::default())?,
            leave_one_load_out(&data, DegenerateClassPolicy::default())?,
            leave_one_fault_size_out(&data, DegenerateClassPolicy::default())?,
        ];
        for p in &plans {
            for spec in [ClassifierSpec::svm(), ClassifierSpec::tree()] {
                let eval = evaluate(&data, p, &spec)?;
                let aca = eval.average_accuracy().map_or(f64::NAN, |a| a.mean);
                let sd = eval.average_accuracy().map_or(f64::NAN, |a| a.std);
                let per: Vec<String> = eval
                    .per_class_accuracy()
                    .iter()
                    .map(|a| a.map_or("-".into(), |a| format!("{:.1}", a.mean)))
                    .collect();
                println!(
                    "| {} | {} | ACA {aca:.1} ± {sd:.1} | per class (N/B/I/O) {} |",
                    p.protocol,
                    spec.name(),
                    per.join(" / ")
                );
            }
        }
    }
    Ok(())
}
