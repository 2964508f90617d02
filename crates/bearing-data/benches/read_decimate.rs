//! Reading (SHA-256 + MAT parse) and 4× decimating a 48 kHz record: 97.mat when the data is
//! present, else a synthetic 48 kHz buffer of the same length written as a MAT file.

// `criterion_group!` expands to an undocumented public function.
#![allow(missing_docs)]

use std::hint::black_box;
use std::path::Path;

use bearing_data::{DataLocation, Decimator, DecimatorParams, Verify, parse_record, verify_bytes};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn synthetic_mat(n: usize) -> Vec<u8> {
    // Minimal little-endian MAT v5 with one N×1 double `X097_DE_time`.
    let mut out = b"MATLAB 5.0 MAT-file, synthetic".to_vec();
    out.resize(124, b' ');
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    let mut body = Vec::new();
    for w in [6u32, 8, 6, 0, 5, 8, n as u32, 1, 1, 12] {
        body.extend_from_slice(&w.to_le_bytes());
    }
    body.extend_from_slice(b"X097_DE_time\0\0\0\0");
    body.extend_from_slice(&9u32.to_le_bytes());
    body.extend_from_slice(&((n * 8) as u32).to_le_bytes());
    for k in 0..n {
        body.extend_from_slice(&((k as f64 * 0.37).sin() * 0.1).to_le_bytes());
    }
    out.extend_from_slice(&14u32.to_le_bytes());
    out.extend_from_slice(&(body.len() as u32).to_le_bytes());
    out.extend_from_slice(&body);
    out
}

fn bench(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let real = DataLocation::from_env(&root)
        .ok()
        .and_then(|l| l.path().map(|p| p.join("cwru/normal/97.mat")))
        .and_then(|p| std::fs::read(p).ok());
    let (bytes, label) = match real {
        Some(b) => (b, "97.mat"),
        None => (synthetic_mat(243_938), "synthetic"),
    };
    let entry = bearing_data::entry(97).expect("97 is catalogued");
    let dec = Decimator::new(DecimatorParams::new(4)).expect("design");
    let mut g = c.benchmark_group(format!("read_decimate/{label}"));
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    let verify = if label == "97.mat" {
        Verify::Required
    } else {
        Verify::Skip
    };
    g.bench_function("sha256_verify", |b| {
        b.iter(|| verify_bytes(entry, black_box(&bytes), verify))
    });
    g.bench_function("parse", |b| {
        b.iter(|| parse_record(black_box(&bytes), 97).expect("parse"))
    });
    let rec = parse_record(&bytes, 97).expect("parse");
    g.bench_function("decimate_de_x4", |b| {
        b.iter(|| dec.decimate(black_box(rec.de())).expect("decimate"))
    });
    g.bench_function("parse_and_decimate", |b| {
        b.iter(|| {
            let r = parse_record(black_box(&bytes), 97).expect("parse");
            dec.decimate(r.de()).expect("decimate")
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
