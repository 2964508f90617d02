//! A little-endian MAT v5 writer for the arrays [`super::read_mat_tree`] reads: real double,
//! single and int16 arrays, complex doubles, text, structs (struct arrays) and cells, each
//! variable optionally zlib-compressed as MATLAB's `save` writes by default. For round-trip
//! tests and for exporting a signal to MATLAB; no file access (the bytes are returned).

use std::io::Write;

/// One MATLAB array.
#[derive(Debug, Clone, PartialEq)]
pub enum MatArray {
    /// A real double array, `dims` column-major.
    Double(Vec<usize>, Vec<f64>),
    /// A real single-precision array.
    Single(Vec<usize>, Vec<f32>),
    /// A real int16 array.
    Int16(Vec<usize>, Vec<i16>),
    /// A complex double array: dimensions, real and imaginary parts.
    Complex(Vec<usize>, Vec<f64>, Vec<f64>),
    /// A 1 × len character array (UTF-16 code units).
    Text(String),
    /// A 1 × n struct array: field names, then one row of field values per element.
    Struct(Vec<String>, Vec<Vec<MatArray>>),
    /// A 1 × n cell array.
    Cell(Vec<MatArray>),
}

fn u32le(v: u32, b: &mut Vec<u8>) {
    b.extend_from_slice(&v.to_le_bytes());
}

fn pad8(b: &mut Vec<u8>) {
    while b.len() % 8 != 0 {
        b.push(0);
    }
}

/// A data element: tag (type, byte length), data, padding to 8 bytes.
fn element(ty: u32, data: &[u8], b: &mut Vec<u8>) {
    u32le(ty, b);
    u32le(data.len() as u32, b);
    b.extend_from_slice(data);
    pad8(b);
}

/// One miMATRIX element named `name` (empty inside structs and cells).
fn matrix(name: &str, a: &MatArray) -> Vec<u8> {
    let (class, dims, complex): (u32, Vec<usize>, bool) = match a {
        MatArray::Double(d, _) => (6, d.clone(), false),
        MatArray::Single(d, _) => (7, d.clone(), false),
        MatArray::Int16(d, _) => (10, d.clone(), false),
        MatArray::Complex(d, ..) => (6, d.clone(), true),
        MatArray::Text(s) => (4, vec![1, s.encode_utf16().count()], false),
        MatArray::Struct(_, e) => (2, vec![1, e.len()], false),
        MatArray::Cell(e) => (1, vec![1, e.len()], false),
    };
    let mut body = Vec::new();
    let flags = class | if complex { 0x0800 } else { 0 };
    element(
        6,
        &[flags.to_le_bytes(), 0u32.to_le_bytes()].concat(),
        &mut body,
    );
    let d: Vec<u8> = dims
        .iter()
        .flat_map(|&v| (v as i32).to_le_bytes())
        .collect();
    element(5, &d, &mut body);
    element(1, name.as_bytes(), &mut body);
    let f64s = |v: &[f64]| -> Vec<u8> { v.iter().flat_map(|x| x.to_le_bytes()).collect() };
    match a {
        MatArray::Double(_, v) => element(9, &f64s(v), &mut body),
        MatArray::Single(_, v) => element(
            7,
            &v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<_>>(),
            &mut body,
        ),
        MatArray::Int16(_, v) => element(
            3,
            &v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<_>>(),
            &mut body,
        ),
        MatArray::Complex(_, re, im) => {
            element(9, &f64s(re), &mut body);
            element(9, &f64s(im), &mut body);
        }
        MatArray::Text(s) => element(
            4,
            &s.encode_utf16()
                .flat_map(u16::to_le_bytes)
                .collect::<Vec<_>>(),
            &mut body,
        ),
        MatArray::Struct(fields, elems) => {
            // field-name length as a small data element, then the padded names
            u32le((4 << 16) | 5, &mut body);
            u32le(32, &mut body);
            let names: Vec<u8> = fields
                .iter()
                .flat_map(|f| {
                    let mut n = f.as_bytes().to_vec();
                    n.resize(32, 0);
                    n
                })
                .collect();
            element(1, &names, &mut body);
            for e in elems {
                for v in e {
                    body.extend_from_slice(&matrix("", v));
                }
            }
        }
        MatArray::Cell(elems) => {
            for v in elems {
                body.extend_from_slice(&matrix("", v));
            }
        }
    }
    let mut out = Vec::with_capacity(body.len() + 8);
    u32le(14, &mut out);
    u32le(body.len() as u32, &mut out);
    out.extend_from_slice(&body);
    out
}

/// A MAT v5 file of the top-level variables `vars`, each zlib-compressed when `compress`.
pub fn write_mat(vars: &[(&str, MatArray)], compress: bool) -> Vec<u8> {
    let mut out = b"MATLAB 5.0 MAT-file, written by hybrid-fdd bearing-data".to_vec();
    out.resize(116, b' ');
    out.extend_from_slice(&[0u8; 8]);
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    for (name, a) in vars {
        let el = matrix(name, a);
        if compress {
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            // writing into a Vec cannot fail
            let z = z
                .write_all(&el)
                .and_then(|()| z.finish())
                .unwrap_or_default();
            u32le(15, &mut out);
            u32le(z.len() as u32, &mut out);
            out.extend_from_slice(&z);
        } else {
            out.extend_from_slice(&el);
        }
    }
    out
}
