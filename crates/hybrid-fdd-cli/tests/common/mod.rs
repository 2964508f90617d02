//! Shared helpers of the command tests: synthetic vibration of a 12-ball bearing rig, text and
//! CWRU-style `.mat` files written into a per-test temporary directory, and the subcommands'
//! clap parsers.

#![allow(dead_code)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use clap::Parser;

/// The 12-ball bearing of QA's second rig (not a built-in one).
pub const BEARING: &str = "n=12,d=7.94mm,D=38.5mm,angle=0deg";

/// `diagnose`'s flags.
#[derive(Parser, Debug)]
pub struct Diagnose {
    #[command(flatten)]
    pub a: hybrid_fdd_cli::diagnose::Args,
}

/// `calibrate`'s flags.
#[derive(Parser, Debug)]
pub struct Calibrate {
    #[command(flatten)]
    pub a: hybrid_fdd_cli::close_loop::CalibrateArgs,
}

/// `close-loop`'s flags.
#[derive(Parser, Debug)]
pub struct CloseLoop {
    #[command(flatten)]
    pub a: hybrid_fdd_cli::close_loop::Args,
}

/// `simulate`'s flags.
#[derive(Parser, Debug)]
pub struct Simulate {
    #[command(flatten)]
    pub a: hybrid_fdd_cli::simulate::Args,
}

/// A fresh directory for one test (removed first if a previous run left it).
pub fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hybrid-fdd-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// `p` as a `&str` argument.
pub fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

/// Uniform noise in [-0.5, 0.5) (xorshift64, reproducible).
pub fn noise(n: usize, seed: u64) -> Vec<f64> {
    let mut st = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            st ^= st << 13;
            st ^= st >> 7;
            st ^= st << 17;
            (st >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

/// What a synthetic recording holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// Healthy: a 1× line and broadband noise.
    None,
    /// Outer-race impacts at BPFO of [`BEARING`], each ringing a 3 kHz resonance.
    Outer,
}

/// `secs` seconds at `fs` Hz of the [`BEARING`] rig at `rpm` (as QA's generator: 1× line,
/// optional impacts ringing a 3 kHz resonance with 0.8 ms decay and 1 % period jitter, noise of
/// RMS 0.5).
pub fn machine(fault: Fault, fs: f64, rpm: f64, secs: f64, seed: u64) -> Vec<f64> {
    let n = (fs * secs) as usize;
    let fr = rpm / 60.0;
    let w = noise(n + 64, seed);
    let mut x: Vec<f64> = (0..n)
        .map(|k| 0.2 * (2.0 * PI * fr * k as f64 / fs + 0.3).sin() + 1.73 * w[k])
        .collect();
    if fault == Fault::Outer {
        let r = 7.94 / 38.5;
        let period = 1.0 / (6.0 * (1.0 - r) * fr);
        let kernel: Vec<f64> = (0..(0.0064 * fs) as usize)
            .map(|k| {
                let t = k as f64 / fs;
                (-t / 0.0008).exp() * (2.0 * PI * 3000.0 * t).sin()
            })
            .collect();
        let mut t = 0.0;
        let mut j = 0;
        while t < secs {
            let at = ((t + 0.01 * period * 2.0 * w[n + (j % 64)]) * fs)
                .round()
                .max(0.0) as usize;
            for (i, v) in kernel.iter().enumerate() {
                if let Some(y) = x.get_mut(at + i) {
                    *y += v;
                }
            }
            t += period;
            j += 1;
        }
    }
    x
}

/// A one-column text file of `x`.
pub fn write_one_column(path: &Path, x: &[f64]) {
    let body: String = x.iter().map(|v| format!("{v:.6}\n")).collect();
    std::fs::write(path, body).expect("write");
}

/// A `time,<name>` text file of `x` at `fs` (stamps to 1 ns), joined by `sep`.
pub fn write_time_signal(path: &Path, name: &str, x: &[f64], fs: f64, sep: &str) {
    let mut body = format!("time{sep}{name}\n");
    for (k, v) in x.iter().enumerate() {
        body += &format!("{:.9}{sep}{v:.6}\n", k as f64 / fs);
    }
    std::fs::write(path, body).expect("write");
}

/// The 128-byte header of a little-endian MAT v5 file.
fn mat_header() -> Vec<u8> {
    let mut out = b"MATLAB 5.0 MAT-file, Platform: PCWIN, Created on: test fixture".to_vec();
    out.resize(116, b' ');
    out.extend_from_slice(&[0u8; 8]);
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    out
}

/// A little-endian MAT v5 file laid out as the CWRU files are: `X{n:03}_DE_time` (N×1 double)
/// and `X{n:03}RPM` (a 1×1 uint16 small element).
pub fn write_cwru_mat(path: &Path, number: u32, de: &[f64], rpm: u16) {
    let mut out = mat_header();
    let u32le = |v: u32, b: &mut Vec<u8>| b.extend_from_slice(&v.to_le_bytes());
    for (name, data) in [
        (format!("X{number:03}_DE_time"), Some(de)),
        (format!("X{number:03}RPM"), None),
    ] {
        let mut body = Vec::new();
        // array flags (class double), dimensions, name
        for v in [6, 8, 6, 0, 5, 8] {
            u32le(v, &mut body);
        }
        u32le(data.map_or(1, |d| d.len() as u32), &mut body);
        u32le(1, &mut body);
        u32le(1, &mut body);
        u32le(name.len() as u32, &mut body);
        body.extend_from_slice(name.as_bytes());
        while body.len() % 8 != 0 {
            body.push(0);
        }
        match data {
            Some(d) => {
                u32le(9, &mut body);
                u32le((d.len() * 8) as u32, &mut body);
                for v in d {
                    body.extend_from_slice(&v.to_le_bytes());
                }
            }
            None => {
                u32le((2 << 16) | 4, &mut body);
                body.extend_from_slice(&rpm.to_le_bytes());
                body.extend_from_slice(&[0, 0]);
            }
        }
        u32le(14, &mut out);
        u32le(body.len() as u32, &mut out);
        out.extend_from_slice(&body);
    }
    std::fs::write(path, out).expect("write");
}

/// A JSON report's field.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("report")).expect("JSON")
}
