//! MATLAB level-5 MAT-file reading on top of the `matfile` crate, hardened for untrusted bytes.
//!
//! `matfile` 0.5 parses the CWRU files correctly, including the `X###RPM` scalars whose
//! `mxDOUBLE_CLASS` data is stored as miUINT16 in the small-data-element format (it widens
//! UInt16 to Double; `tests/mat_reader.rs` checks this on a hand-built fixture). It can panic on
//! malformed input, though: an element length near `u32::MAX` overflows its padding arithmetic,
//! and the product of hostile dimensions overflows `i32` (both are debug-mode overflow panics).
//! So [`validate_structure`] walks the element tree first and rejects anything whose lengths do
//! not fit in the buffer, whose dimensions overflow, or that uses features the CWRU files do not
//! (compression, sparse arrays). Only then are the bytes handed to `matfile`, inside
//! `std::panic::catch_unwind` as a last resort that turns any remaining panic into
//! [`DataError::MatParse`].

use std::collections::BTreeMap;

use crate::catalog::SensorEnd;
use crate::error::{DataError, Result};
use crate::mat_tree::{Endian, Tag as SubTag, tag_at, type_size as numeric_size};

/// Length of the MAT v5 header.
const HEADER_LEN: usize = 128;
/// miINT8
const MI_INT8: u32 = 1;
/// miINT32
const MI_INT32: u32 = 5;
/// miUINT32
const MI_UINT32: u32 = 6;
/// miMATRIX
const MI_MATRIX: u32 = 14;
/// miCOMPRESSED
const MI_COMPRESSED: u32 = 15;

fn malformed(offset: usize, reason: &'static str) -> DataError {
    DataError::MalformedMat { offset, reason }
}

/// A sub-element tag inside a matrix: the generic reader's tag, padded to 8 bytes.
fn sub_tag(b: &[u8], e: Endian, off: usize, end: usize) -> Result<SubTag> {
    tag_at(b, e, off, end, true)
}

/// Check the structure of a MAT v5 file without allocating: header, every top-level element
/// length, and each numeric matrix's flags, dimensions, name and data sub-elements.
///
/// Rejects (typed errors): files shorter than the header, a bad version or endian indicator,
/// truncated or overlong elements, compressed elements, sparse arrays, dimension products
/// that overflow `i32`, and data lengths that do not match the dimensions.
pub fn validate_structure(b: &[u8]) -> Result<()> {
    if b.len() < HEADER_LEN {
        return Err(malformed(
            b.len(),
            "shorter than the 128-byte MAT v5 header",
        ));
    }
    if b[..4].contains(&0) {
        return Err(malformed(
            0,
            "not a level-5 MAT-file (header text starts with a NUL byte)",
        ));
    }
    let e = match &b[126..128] {
        b"IM" => Endian { little: true },
        b"MI" => Endian { little: false },
        _ => {
            return Err(malformed(
                126,
                "not a level-5 MAT-file (no IM/MI endian indicator)",
            ));
        }
    };
    let version = if e.little {
        u16::from_le_bytes([b[124], b[125]])
    } else {
        u16::from_be_bytes([b[124], b[125]])
    };
    if version != 0x0100 {
        return Err(malformed(
            124,
            "unsupported MAT-file version (expected 0x0100)",
        ));
    }
    let mut off = HEADER_LEN;
    while off < b.len() {
        if b.len() - off < 8 {
            return Err(malformed(off, "truncated element tag"));
        }
        let ty = e
            .u32_at(b, off)
            .ok_or_else(|| malformed(off, "truncated tag"))?;
        if ty >> 16 != 0 {
            return Err(DataError::UnsupportedMat {
                offset: off,
                feature: "small data element at top level",
            });
        }
        let len = e
            .u32_at(b, off + 4)
            .ok_or_else(|| malformed(off, "truncated tag"))? as usize;
        let data = off + 8;
        if len > b.len() - data {
            return Err(malformed(
                off,
                "element extends past the end of the file (truncated?)",
            ));
        }
        match ty {
            MI_MATRIX => validate_matrix(b, e, data, data + len)?,
            MI_COMPRESSED => {
                return Err(DataError::UnsupportedMat {
                    offset: off,
                    feature: "compressed elements (miCOMPRESSED, MAT v7)",
                });
            }
            _ => {
                return Err(DataError::UnsupportedMat {
                    offset: off,
                    feature: "top-level element that is not miMATRIX",
                });
            }
        }
        off = data + len.div_ceil(8) * 8;
    }
    Ok(())
}

fn validate_matrix(b: &[u8], e: Endian, start: usize, end: usize) -> Result<()> {
    // Array flags: miUINT32, length 8, then flags/class and nzmax.
    if end - start < 16 {
        return Err(malformed(
            start,
            "matrix shorter than its array-flags sub-element",
        ));
    }
    let fty = e
        .u32_at(b, start)
        .ok_or_else(|| malformed(start, "truncated flags"))?;
    let flen = e
        .u32_at(b, start + 4)
        .ok_or_else(|| malformed(start, "truncated flags"))?;
    if fty != MI_UINT32 || flen != 8 {
        return Err(malformed(start, "bad array-flags sub-element"));
    }
    let flags = e
        .u32_at(b, start + 8)
        .ok_or_else(|| malformed(start, "truncated flags"))?;
    let class = flags & 0xFF;
    let complex = flags & 0x0800 != 0;
    match class {
        1..=4 => return Ok(()), // cell, struct, object, char: skipped by matfile, never read
        5 => {
            return Err(DataError::UnsupportedMat {
                offset: start,
                feature: "sparse arrays",
            });
        }
        6..=15 => {}
        _ => return Err(malformed(start + 8, "unknown array class")),
    }
    // Dimensions: miINT32, at least two, product fits i32.
    let dims = sub_tag(b, e, start + 16, end)?;
    if dims.ty != MI_INT32 || dims.len < 8 || dims.len % 4 != 0 {
        return Err(malformed(start + 16, "bad dimensions sub-element"));
    }
    let mut count: i32 = 1;
    for k in 0..dims.len / 4 {
        let d = e
            .i32_at(b, dims.data + 4 * k)
            .ok_or_else(|| malformed(dims.data, "truncated"))?;
        if d < 0 {
            return Err(malformed(dims.data + 4 * k, "negative dimension"));
        }
        count = count
            .checked_mul(d)
            .ok_or_else(|| malformed(dims.data, "dimensions overflow"))?;
    }
    // Name: miINT8, non-empty.
    let name = sub_tag(b, e, dims.next, end)?;
    if name.ty != MI_INT8 || name.len == 0 {
        return Err(malformed(dims.next, "bad array-name sub-element"));
    }
    // Real (and imaginary) parts.
    let mut at = name.next;
    for _part in 0..if complex { 2 } else { 1 } {
        let p = sub_tag(b, e, at, end)?;
        let size =
            numeric_size(p.ty).ok_or_else(|| malformed(at, "non-numeric data sub-element"))?;
        if p.len % size != 0 || p.len / size != count as usize {
            return Err(malformed(at, "data length does not match the dimensions"));
        }
        at = p.next;
    }
    Ok(())
}

/// One `X###` variable set of a CWRU-style file: the channels and rpm stored under one number.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VariableSet {
    /// The `###` of the variable names.
    pub number: u32,
    /// `X###_DE_time`.
    pub de: Option<Vec<f64>>,
    /// `X###_FE_time`.
    pub fe: Option<Vec<f64>>,
    /// `X###_BA_time`.
    pub ba: Option<Vec<f64>>,
    /// `X###RPM`, when stored (any real numeric class, widened to `f64`).
    pub rpm: Option<f64>,
}

impl VariableSet {
    /// The channel of `end`, if present.
    pub fn channel(&self, end: SensorEnd) -> Option<&[f64]> {
        match end {
            SensorEnd::DriveEnd => self.de.as_deref(),
            SensorEnd::FanEnd => self.fe.as_deref(),
            SensorEnd::Base => self.ba.as_deref(),
        }
    }
}

/// What a CWRU variable name denotes.
enum VarKind {
    Channel(SensorEnd),
    Rpm,
}

/// Split `X097_DE_time` into (97, DE) and `X097RPM` into (97, Rpm); other names give `None`.
fn classify_name(name: &str) -> Option<(u32, VarKind)> {
    let rest = name.strip_prefix('X')?;
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    if digits == 0 || digits > 6 {
        return None;
    }
    let number: u32 = rest[..digits].parse().ok()?;
    let kind = match &rest[digits..] {
        "_DE_time" => VarKind::Channel(SensorEnd::DriveEnd),
        "_FE_time" => VarKind::Channel(SensorEnd::FanEnd),
        "_BA_time" => VarKind::Channel(SensorEnd::Base),
        "RPM" => VarKind::Rpm,
        _ => return None,
    };
    Some((number, kind))
}

fn real_as_f64(data: &matfile::NumericData) -> Option<Vec<f64>> {
    use matfile::NumericData as N;
    Some(match data {
        N::Double { real, imag: None } => real.clone(),
        N::Single { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::Int8 { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::UInt8 { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::Int16 { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::UInt16 { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::Int32 { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::UInt32 { real, imag: None } => real.iter().map(|&v| f64::from(v)).collect(),
        N::Int64 { real, imag: None } => real.iter().map(|&v| v as f64).collect(),
        N::UInt64 { real, imag: None } => real.iter().map(|&v| v as f64).collect(),
        _ => return None,
    })
}

/// Parse validated bytes with `matfile`, converting any panic into a typed error.
fn parse_with_matfile(bytes: &[u8]) -> Result<matfile::MatFile> {
    validate_structure(bytes)?;
    match std::panic::catch_unwind(|| matfile::MatFile::parse(bytes)) {
        Ok(Ok(m)) => Ok(m),
        Ok(Err(err)) => Err(DataError::MatParse {
            message: format!("{err} ({err:?})"),
        }),
        Err(_) => Err(DataError::MatParse {
            message: "matfile panicked on this input".into(),
        }),
    }
}

/// Read every `X###_{DE,FE,BA}_time` / `X###RPM` variable of a MAT v5 file, grouped by number.
///
/// Variables with other names are ignored. Signal variables must be real vectors (N×1 or 1×N).
pub fn read_variable_sets(bytes: &[u8]) -> Result<Vec<VariableSet>> {
    let mat = parse_with_matfile(bytes)?;
    let mut sets: BTreeMap<u32, VariableSet> = BTreeMap::new();
    for arr in mat.arrays() {
        let Some((number, kind)) = classify_name(arr.name()) else {
            continue;
        };
        let size = arr.size();
        let (rows, cols) = (
            size.first().copied().unwrap_or(0),
            size.get(1).copied().unwrap_or(0),
        );
        let is_vector = size.len() == 2 && (rows == 1 || cols == 1);
        let set = sets.entry(number).or_insert_with(|| VariableSet {
            number,
            ..Default::default()
        });
        match kind {
            VarKind::Rpm => {
                // A stored rpm must be one finite positive number; anything else counts as absent.
                if let Some(v) = real_as_f64(arr.data()) {
                    if let [x] = v.as_slice() {
                        if x.is_finite() && *x > 0.0 {
                            set.rpm = Some(*x);
                        }
                    }
                }
            }
            VarKind::Channel(end) => {
                let not_vec = || DataError::NotAVector {
                    name: arr.name().to_owned(),
                    rows,
                    cols,
                };
                if !is_vector {
                    return Err(not_vec());
                }
                let v = real_as_f64(arr.data()).ok_or_else(not_vec)?;
                match end {
                    SensorEnd::DriveEnd => set.de = Some(v),
                    SensorEnd::FanEnd => set.fe = Some(v),
                    SensorEnd::Base => set.ba = Some(v),
                }
            }
        }
    }
    Ok(sets.into_values().collect())
}

/// Pick the variable set numbered `variable`, or, when `variable` is `None`, the only set that
/// has a drive-end channel. The chosen set always has a DE channel.
pub fn select_set(sets: Vec<VariableSet>, variable: Option<u32>) -> Result<VariableSet> {
    let with_de = sets.iter().filter(|s| s.de.is_some()).count();
    let found = sets
        .iter()
        .map(|s| {
            usize::from(s.de.is_some()) + usize::from(s.fe.is_some()) + usize::from(s.ba.is_some())
        })
        .sum();
    let chosen = match variable {
        Some(v) => sets.into_iter().find(|s| s.number == v),
        None if with_de == 1 => sets.into_iter().find(|s| s.de.is_some()),
        None if with_de == 0 => None,
        None => return Err(DataError::AmbiguousVariables { sets: with_de }),
    };
    match chosen {
        Some(s) if s.de.is_some() => Ok(s),
        _ => Err(DataError::NoDriveEnd {
            variable: variable.unwrap_or(0),
            found,
        }),
    }
}
