//! The chapter-2 cell where the SVM used to give Normal 0 %: CWRU 0 hp, 0.007 in, raw DE signal,
//! 1-D window energy, windows of 300 samples (normal 97 decimated to 12 kHz: 163 windows; ball
//! 118, inner 105, outer@6 130: the first 400 windows each), random 75/25 split over 10 seeds.
//! Prints per-class accuracy for the default SVM, the log10 variant, scikit-learn's settings and
//! the tree.
//!
//! `cargo run -p classify --example cwru_chapter2_cell`

use std::path::Path;

use bearing_data::{DataLocation, LoadOptions, load_record};
use classify::*;
use residual_features::{FeatureConfig, FeatureExtractor, TailPolicy, WindowPlan, Windowing};

fn main() -> std::result::Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let loc = DataLocation::resolve(None, &root)?;
    let dir = loc.required()?;
    let classes = ["normal", "ball", "inner", "outer"]
        .map(String::from)
        .to_vec();
    let plan = WindowPlan::new(Windowing::FixedLength { length: 300 }, TailPolicy::Discard)?;
    let mut fx = FeatureExtractor::new(FeatureConfig::energy_only())?;
    let mut b = Dataset::builder(classes, fx.names());
    for (class, n) in [(0usize, 97u32), (1, 118), (2, 105), (3, 130)] {
        let rec = load_record(dir, n, &LoadOptions::default())?;
        let de = rec.de_at(12_000.0)?;
        let mut rows = fx.extract_windows(&de, &plan)?.rows;
        rows.truncate(400);
        let med = {
            let mut e: Vec<f64> = rows.iter().map(|r| r[0]).collect();
            e.sort_by(f64::total_cmp);
            e[e.len() / 2]
        };
        println!(
            "record {n}: {} windows, median energy {med:.4e}",
            rows.len()
        );
        let info = RecordingInfo {
            class,
            recording: n.to_string(),
            load_hp: 0,
            fault_size_mils: (class > 0).then_some(7),
            speed_rpm: None,
        };
        b.add_recording(&info, rows);
    }
    let data = b.build()?;
    let split = random_window_split(&data, &RandomSplitConfig::default())?;
    let specs = [
        ("default SVM", ClassifierSpec::svm()),
        (
            "SVM + log10",
            ClassifierSpec::svm_with(
                LinearSvmParams::default().with_transform(FeatureTransform::Log10),
            ),
        ),
        ("SVM sklearn settings", ClassifierSpec::svm_sklearn()),
        ("tree", ClassifierSpec::tree()),
    ];
    for (name, spec) in specs {
        let eval = evaluate(&data, &split, &spec)?;
        let per: Vec<String> = eval
            .per_class_accuracy()
            .iter()
            .map(|a| a.map_or("-".into(), |a| format!("{:.1}", a.mean)))
            .collect();
        println!("| {name} | per class (N/B/I/O) {} |", per.join(" / "));
    }
    Ok(())
}
