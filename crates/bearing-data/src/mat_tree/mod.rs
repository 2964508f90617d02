//! Any MATLAB level-5 MAT-file (v5, v6 and v7, compressed or not) as a flat list of its numeric
//! and text leaves, for recordings that are not CWRU's: structs, struct arrays and cells are
//! walked, every numeric array and character array becomes a [`MatLeaf`] named by its path
//! (`bearing.gs`, `X.Y(7).Data`, `c{2}`).
//!
//! `matfile` (used for the CWRU files, [`crate::read_variable_sets`]) skips structs, cells and
//! character arrays, which is where other rigs keep their signals (MFPT's `bearing.gs` and
//! `bearing.sr`, Paderborn's `X.Y(k).Data` with `X.Y(k).Name = 'vibration_1'`). This reader walks
//! the element tree itself, with the same hardening as [`crate::validate_structure`]: every
//! length is checked against its container, dimension products against overflow, the
//! decompressed size of a compressed element against [`MAX_INFLATED_BYTES`] and the nesting
//! depth against [`MAX_DEPTH`]; a damaged file is a typed error, never a panic. Decompression
//! is `flate2` (already in the workspace through the PNG encoder; the reference zlib decoder in
//! Rust). MAT v7.3 files are HDF5 and are refused with a message that says so.
//!
//! Choosing the signal ([`select_signal`]): by `--channel` as a full path, a struct element's
//! `Name` (Paderborn's `vibration_1`, [`MatLeaf::alias`]) or a last path component (`gs`);
//! without one, the only real vector of at least [`MIN_SIGNAL_SAMPLES`] samples. The sampling
//! rate ([`sampling_rate_near`]): a positive scalar named `fs`, `sr`, `sample_rate`,
//! `sampling_rate`, `SampleFrequency`, `SamplingFrequency`, `freq_sampling`, … (case and `_`
//! ignored, [`is_sampling_rate_name`]) beside the signal, else the only one in the file. The shaft speed ([`shaft_speed_near`]): an `rpm` scalar beside the signal, or
//! a rotation frequency in Hz (`shaft_hz`, `fr`, or MFPT's `rate` where a sampling rate is stated
//! beside it).

use std::io::Read;

use crate::error::{DataError, Result};

mod select;
mod write;
pub use select::{
    MatSignal, SAMPLING_RATE_NAMES, StoredSpeed, is_sampling_rate_name, sampling_rate_near,
    select_signal, shaft_speed_near,
};
pub use write::{MatArray, write_mat};

/// Largest decompressed size of one compressed element (bytes): 1 GiB, far above any
/// single-channel recording, far below what a hostile stream could make us allocate unchecked.
pub const MAX_INFLATED_BYTES: u64 = 1 << 30;
/// Deepest nesting of structs and cells walked.
pub const MAX_DEPTH: usize = 32;
/// Fewest samples a vector needs to be offered as a signal without `--channel`.
pub const MIN_SIGNAL_SAMPLES: usize = 1024;

const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;

/// A leaf's content.
#[derive(Debug, Clone, PartialEq)]
pub enum MatValue {
    /// A real numeric array (any class, widened to `f64`; logical arrays included), column-major.
    Numeric {
        /// MATLAB dimensions.
        dims: Vec<usize>,
        /// The values.
        values: Vec<f64>,
    },
    /// A complex numeric array (not a signal; listed so that the user sees it).
    Complex {
        /// MATLAB dimensions.
        dims: Vec<usize>,
    },
    /// A character array, as text.
    Text(String),
}

/// One numeric or text array of the file, named by its path.
#[derive(Debug, Clone, PartialEq)]
pub struct MatLeaf {
    /// `name`, `name.field`, `name(k).field` (1-based, column-major, only when the struct array
    /// has more than one element), `name{k}` for cells.
    pub path: String,
    /// For the `Data` field of a struct element whose `Name` field is text: that text
    /// (Paderborn's `vibration_1`).
    pub alias: Option<String>,
    /// The content.
    pub value: MatValue,
}

impl MatLeaf {
    /// The samples of a real vector (N×1, 1×N or N), `None` for anything else.
    pub fn vector(&self) -> Option<&[f64]> {
        match &self.value {
            MatValue::Numeric { dims, values } => {
                let non_singleton = dims.iter().filter(|&&d| d != 1).count();
                (non_singleton <= 1 && values.len() >= 2).then_some(values.as_slice())
            }
            _ => None,
        }
    }

    /// The value of a real scalar, `None` for anything else.
    pub fn scalar(&self) -> Option<f64> {
        match &self.value {
            MatValue::Numeric { values, .. } if values.len() == 1 => Some(values[0]),
            _ => None,
        }
    }

    /// The last component of the path (`gs` of `bearing.gs`, `Data` of `X.Y(7).Data`).
    pub fn last_name(&self) -> &str {
        let tail = self.path.rsplit('.').next().unwrap_or(&self.path);
        tail.split(['(', '{']).next().unwrap_or(tail)
    }

    /// The path up to the last field (`bearing` of `bearing.gs`; empty at the top level).
    pub fn parent(&self) -> &str {
        self.path.rsplit_once('.').map_or("", |(p, _)| p)
    }
}

/// Byte order of a MAT-file (from its header's endian indicator).
#[derive(Clone, Copy)]
pub(crate) struct Endian {
    pub(crate) little: bool,
}

impl Endian {
    pub(crate) fn i32_at(self, b: &[u8], off: usize) -> Option<i32> {
        self.u32_at(b, off).map(|v| v as i32)
    }

    pub(crate) fn u32_at(self, b: &[u8], off: usize) -> Option<u32> {
        let s: [u8; 4] = b.get(off..off.checked_add(4)?)?.try_into().ok()?;
        Some(if self.little {
            u32::from_le_bytes(s)
        } else {
            u32::from_be_bytes(s)
        })
    }
}

fn malformed(offset: usize, reason: &'static str) -> DataError {
    DataError::MalformedMat { offset, reason }
}

/// A data element: type, data range and where the next element starts.
pub(crate) struct Tag {
    pub(crate) ty: u32,
    pub(crate) data: usize,
    pub(crate) len: usize,
    pub(crate) next: usize,
}

/// The tag at `off` of `b` (elements end at `end`); `pad` rounds the next offset up to 8 bytes.
pub(crate) fn tag_at(b: &[u8], e: Endian, off: usize, end: usize, pad: bool) -> Result<Tag> {
    if off.checked_add(8).is_none_or(|x| x > end) {
        return Err(malformed(off, "element tag runs past its container"));
    }
    let w = e
        .u32_at(b, off)
        .ok_or_else(|| malformed(off, "truncated tag"))?;
    if w >> 16 != 0 {
        let len = (w >> 16) as usize;
        if len > 4 {
            return Err(malformed(off, "small data element longer than 4 bytes"));
        }
        return Ok(Tag {
            ty: w & 0xFFFF,
            data: off + 4,
            len,
            next: off + 8,
        });
    }
    let len = e
        .u32_at(b, off + 4)
        .ok_or_else(|| malformed(off, "truncated tag"))? as usize;
    let data = off + 8;
    if len > end - data {
        return Err(malformed(off, "element longer than its container"));
    }
    let next = if pad {
        (data + len.div_ceil(8) * 8).min(end)
    } else {
        data + len
    };
    Ok(Tag {
        ty: w,
        data,
        len,
        next,
    })
}

/// Byte size of a numeric MAT data type.
pub(crate) fn type_size(ty: u32) -> Option<usize> {
    match ty {
        1 | 2 => Some(1),
        3 | 4 => Some(2),
        5..=7 => Some(4),
        9 | 12 | 13 => Some(8),
        _ => None,
    }
}

/// The numbers of a numeric data element, widened to `f64`.
fn numbers(b: &[u8], e: Endian, t: &Tag) -> Result<Vec<f64>> {
    let size = type_size(t.ty).ok_or_else(|| malformed(t.data, "non-numeric data element"))?;
    if t.len % size != 0 {
        return Err(malformed(
            t.data,
            "data length is not a whole number of values",
        ));
    }
    let raw = &b[t.data..t.data + t.len];
    let v = raw
        .chunks_exact(size)
        .map(|c| {
            let mut a = [0u8; 8];
            if e.little {
                a[..size].copy_from_slice(c);
            } else {
                for (i, &x) in c.iter().rev().enumerate() {
                    a[i] = x;
                }
            }
            match t.ty {
                1 => f64::from(a[0] as i8),
                2 => f64::from(a[0]),
                3 => f64::from(i16::from_le_bytes([a[0], a[1]])),
                4 => f64::from(u16::from_le_bytes([a[0], a[1]])),
                5 => f64::from(i32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                6 => f64::from(u32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                7 => f64::from(f32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                9 => f64::from_le_bytes(a),
                12 => i64::from_le_bytes(a) as f64,
                _ => u64::from_le_bytes(a) as f64,
            }
        })
        .collect();
    Ok(v)
}

/// The text of a character array's data element (UTF-8, UTF-16, 8- or 16-bit codes).
fn text(b: &[u8], e: Endian, t: &Tag) -> Result<String> {
    let raw = &b[t.data..t.data + t.len];
    Ok(match t.ty {
        16 | 1 | 2 => String::from_utf8_lossy(raw).into_owned(),
        17 | 4 | 3 => {
            let units: Vec<u16> = raw
                .chunks_exact(2)
                .map(|c| {
                    if e.little {
                        u16::from_le_bytes([c[0], c[1]])
                    } else {
                        u16::from_be_bytes([c[0], c[1]])
                    }
                })
                .collect();
            String::from_utf16_lossy(&units)
        }
        _ => return Err(malformed(t.data, "character data of an unknown type")),
    })
}

struct Walker {
    e: Endian,
    leaves: Vec<MatLeaf>,
}

impl Walker {
    /// Every element of `b[start..end]` (top level, or the inside of a compressed element).
    fn elements(&mut self, b: &[u8], start: usize, end: usize, depth: usize) -> Result<()> {
        let mut off = start;
        while off + 8 <= end {
            let t = tag_at(b, self.e, off, end, true)?;
            match t.ty {
                MI_MATRIX => self.matrix(b, &t, None, depth)?,
                MI_COMPRESSED => {
                    let t = tag_at(b, self.e, off, end, false)?;
                    let inflated = inflate(&b[t.data..t.data + t.len], t.data)?;
                    self.elements(&inflated, 0, inflated.len(), depth + 1)?;
                    off = t.next;
                    continue;
                }
                _ => {} // other top-level elements carry no array
            }
            off = t.next;
        }
        Ok(())
    }

    /// One miMATRIX element; `path` is its name inside a container (`None`: top level, named by
    /// its own name sub-element).
    fn matrix(&mut self, b: &[u8], t: &Tag, path: Option<String>, depth: usize) -> Result<()> {
        if depth > MAX_DEPTH {
            return Err(DataError::UnsupportedMat {
                offset: t.data,
                feature: "structs or cells nested deeper than 32 levels",
            });
        }
        if t.len == 0 {
            return Ok(()); // an empty array ([] in a struct field or cell)
        }
        let end = t.data + t.len;
        let e = self.e;
        let flags = tag_at(b, e, t.data, end, true)?;
        if flags.len < 8 {
            return Err(malformed(t.data, "array flags shorter than 8 bytes"));
        }
        let fw = e
            .u32_at(b, flags.data)
            .ok_or_else(|| malformed(flags.data, "truncated array flags"))?;
        let class = fw & 0xFF;
        let complex = fw & 0x0800 != 0;
        let dims_t = tag_at(b, e, flags.next, end, true)?;
        if dims_t.ty != 5 || dims_t.len % 4 != 0 || dims_t.len == 0 {
            return Err(malformed(dims_t.data, "bad dimensions sub-element"));
        }
        let mut dims = Vec::with_capacity(dims_t.len / 4);
        let mut numel: usize = 1;
        for k in 0..dims_t.len / 4 {
            let d = e.u32_at(b, dims_t.data + 4 * k).unwrap_or(0) as i32;
            if d < 0 {
                return Err(malformed(dims_t.data, "negative dimension"));
            }
            let d = d as usize;
            numel = numel
                .checked_mul(d)
                .ok_or_else(|| malformed(dims_t.data, "dimensions overflow"))?;
            dims.push(d);
        }
        let name_t = tag_at(b, e, dims_t.next, end, true)?;
        let own = String::from_utf8_lossy(&b[name_t.data..name_t.data + name_t.len])
            .trim_end_matches('\0')
            .to_string();
        let path = path.unwrap_or(own);
        let at = name_t.next;
        match class {
            // numeric classes (double … uint64); logical arrays are uint8
            6..=15 => {
                if complex {
                    self.leaves.push(MatLeaf {
                        path,
                        alias: None,
                        value: MatValue::Complex { dims },
                    });
                    return Ok(());
                }
                let re = tag_at(b, e, at, end, true)?;
                let values = numbers(b, e, &re)?;
                if values.len() != numel {
                    return Err(malformed(
                        re.data,
                        "data length does not match the dimensions",
                    ));
                }
                self.leaves.push(MatLeaf {
                    path,
                    alias: None,
                    value: MatValue::Numeric { dims, values },
                });
            }
            4 => {
                let d = tag_at(b, e, at, end, true)?;
                let s = text(b, e, &d)?;
                self.leaves.push(MatLeaf {
                    path,
                    alias: None,
                    value: MatValue::Text(s),
                });
            }
            1 => {
                let mut off = at;
                for k in 0..numel {
                    let c = tag_at(b, e, off, end, true)?;
                    if c.ty != MI_MATRIX {
                        return Err(malformed(off, "cell element is not an array"));
                    }
                    self.matrix(b, &c, Some(format!("{path}{{{}}}", k + 1)), depth + 1)?;
                    off = c.next;
                }
            }
            2 => self.structure(b, at, end, &path, numel, depth)?,
            // objects, sparse arrays, function handles: not signals
            _ => {}
        }
        Ok(())
    }

    fn structure(
        &mut self,
        b: &[u8],
        at: usize,
        end: usize,
        path: &str,
        numel: usize,
        depth: usize,
    ) -> Result<()> {
        let e = self.e;
        let len_t = tag_at(b, e, at, end, true)?;
        let name_len = e
            .u32_at(b, len_t.data)
            .ok_or_else(|| malformed(len_t.data, "truncated field-name length"))?
            as usize;
        let names_t = tag_at(b, e, len_t.next, end, true)?;
        if name_len == 0 || names_t.len % name_len != 0 {
            return Err(malformed(names_t.data, "bad struct field names"));
        }
        let names: Vec<String> = b[names_t.data..names_t.data + names_t.len]
            .chunks_exact(name_len)
            .map(|c| {
                String::from_utf8_lossy(c)
                    .trim_end_matches('\0')
                    .to_string()
            })
            .collect();
        if names.is_empty() {
            return Ok(());
        }
        let mut off = names_t.next;
        for k in 0..numel {
            let first = self.leaves.len();
            let prefix = if numel > 1 {
                format!("{path}({})", k + 1)
            } else {
                path.to_string()
            };
            for name in &names {
                let f = tag_at(b, e, off, end, true)?;
                if f.ty != MI_MATRIX {
                    return Err(malformed(off, "struct field is not an array"));
                }
                self.matrix(b, &f, Some(format!("{prefix}.{name}")), depth + 1)?;
                off = f.next;
            }
            // a struct element with a text `Name` and a `Data` array: the data is known by
            // that name
            let own = &self.leaves[first..];
            let label = own.iter().find_map(|l| match &l.value {
                MatValue::Text(s) if l.path == format!("{prefix}.Name") => {
                    Some(s.trim().to_string())
                }
                _ => None,
            });
            if let Some(label) = label.filter(|s| !s.is_empty()) {
                let data_path = format!("{prefix}.Data");
                for l in &mut self.leaves[first..] {
                    if l.path == data_path {
                        l.alias = Some(label.clone());
                    }
                }
            }
        }
        Ok(())
    }
}

/// Inflate a zlib stream, at most [`MAX_INFLATED_BYTES`].
fn inflate(z: &[u8], offset: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut d = flate2::read::ZlibDecoder::new(z).take(MAX_INFLATED_BYTES + 1);
    d.read_to_end(&mut out)
        .map_err(|_| malformed(offset, "compressed element is not a valid zlib stream"))?;
    if out.len() as u64 > MAX_INFLATED_BYTES {
        return Err(DataError::UnsupportedMat {
            offset,
            feature: "a compressed element larger than 1 GiB",
        });
    }
    Ok(out)
}

/// Every numeric and text leaf of a MAT v5/v6/v7 file, in file order.
///
/// # Errors
/// [`DataError::UnsupportedMat`] for a MAT v7.3 (HDF5) file; [`DataError::MalformedMat`] for a
/// file that is not a MAT-file or whose structure is damaged.
pub fn read_mat_tree(bytes: &[u8]) -> Result<Vec<MatLeaf>> {
    if bytes.len() >= 0x208 && &bytes[0x200..0x208] == b"\x89HDF\r\n\x1a\n" {
        return Err(DataError::UnsupportedMat {
            offset: 0x200,
            feature: "MAT v7.3 (HDF5); save with -v7 in MATLAB or export the signal to CSV",
        });
    }
    if bytes.len() < 128 {
        return Err(malformed(0, "shorter than the 128-byte MAT header"));
    }
    let little = match &bytes[126..128] {
        b"IM" => true,
        b"MI" => false,
        _ => return Err(malformed(126, "no MAT endian indicator (not a MAT-file)")),
    };
    let mut w = Walker {
        e: Endian { little },
        leaves: Vec::new(),
    };
    w.elements(bytes, 128, bytes.len(), 0)?;
    Ok(w.leaves)
}
