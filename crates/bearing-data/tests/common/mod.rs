//! Shared test helpers: locating the real data (skip when absent, fail under `CI=true`).

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use bearing_data::{DataLocation, ci_from_env};

/// Workspace root (two levels above this crate).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("..")
}

/// The data directory (holding `cwru/`), or `None` after printing a skip message.
/// Panics (fails the test) when the data is absent and `CI=true`.
pub fn data_dir() -> Option<PathBuf> {
    let loc = DataLocation::from_env(&workspace_root()).expect("HYBRID_FDD_DATA points nowhere");
    match loc.require(ci_from_env()) {
        Ok(Some(p)) => Some(p.to_path_buf()),
        Ok(None) => {
            eprintln!("SKIP: no CWRU data directory (set HYBRID_FDD_DATA); skipping");
            None
        }
        Err(e) => panic!("CI=true and the data is missing: {e}"),
    }
}

/// Data of one hand-built MAT variable.
pub enum MatData<'a> {
    /// miDOUBLE data of an mxDOUBLE_CLASS array.
    Double(&'a [f64]),
    /// One miUINT16 value in the small-data-element format, class mxDOUBLE (CWRU's `X###RPM`).
    SmallU16(u16),
}

/// A little-endian MAT v5 file holding the given `(name, data)` arrays (N×1 doubles or 1×1
/// small-element uint16 scalars), laid out the way the CWRU files are.
pub fn build_mat(vars: &[(&str, MatData<'_>)]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut text = b"MATLAB 5.0 MAT-file, Platform: PCWIN, Created on: test fixture".to_vec();
    text.resize(116, b' ');
    out.extend_from_slice(&text);
    out.extend_from_slice(&[0u8; 8]); // subsystem offset
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    for (name, data) in vars {
        let mut body = Vec::new();
        let u32le = |v: u32, b: &mut Vec<u8>| b.extend_from_slice(&v.to_le_bytes());
        // array flags: miUINT32, 8 bytes, class 6 (double)
        u32le(6, &mut body);
        u32le(8, &mut body);
        u32le(6, &mut body);
        u32le(0, &mut body);
        let rows = match data {
            MatData::Double(v) => v.len() as u32,
            MatData::SmallU16(_) => 1,
        };
        // dimensions: miINT32, 8 bytes
        u32le(5, &mut body);
        u32le(8, &mut body);
        u32le(rows, &mut body);
        u32le(1, &mut body);
        // name: miINT8, long format, padded to 8
        u32le(1, &mut body);
        u32le(name.len() as u32, &mut body);
        body.extend_from_slice(name.as_bytes());
        while body.len() % 8 != 0 {
            body.push(0);
        }
        match data {
            MatData::Double(v) => {
                u32le(9, &mut body);
                u32le((v.len() * 8) as u32, &mut body);
                for x in *v {
                    body.extend_from_slice(&x.to_le_bytes());
                }
            }
            MatData::SmallU16(r) => {
                // small element: size 2 in the high half, type 4 (miUINT16) in the low half
                u32le((2 << 16) | 4, &mut body);
                body.extend_from_slice(&r.to_le_bytes());
                body.extend_from_slice(&[0, 0]);
            }
        }
        u32le(14, &mut out);
        u32le(body.len() as u32, &mut out);
        out.extend_from_slice(&body);
    }
    out
}

/// A tiny CWRU-like file: `X{n}_DE_time`, `X{n}_FE_time` (8 samples each) and `X{n}RPM`.
pub fn tiny_cwru(n: u32, rpm: u16) -> Vec<u8> {
    let de: Vec<f64> = (0..8).map(|k| f64::from(k) * 0.5 - 1.0).collect();
    let fe: Vec<f64> = (0..8).map(|k| f64::from(k) * -0.25).collect();
    build_mat(&[
        (&format!("X{n:03}_DE_time"), MatData::Double(&de)),
        (&format!("X{n:03}_FE_time"), MatData::Double(&fe)),
        (&format!("X{n:03}RPM"), MatData::SmallU16(rpm)),
    ])
}
pub mod mat_fixtures;
