//! The MAT reader on hand-built MAT v5 bytes: the CWRU quirks and typed errors on bad input.

mod common;

use bearing_data::{
    DataError, RpmSource, parse_record, read_variable_sets, select_set, validate_structure,
};
use common::{MatData, build_mat, tiny_cwru};

#[test]
fn small_element_uint16_rpm_is_widened_to_double() {
    // The CWRU X###RPM layout: mxDOUBLE_CLASS whose data is a miUINT16 small data element.
    let bytes = tiny_cwru(105, 1797);
    let sets = read_variable_sets(&bytes).unwrap();
    assert_eq!(sets.len(), 1);
    assert_eq!(sets[0].number, 105);
    assert_eq!(sets[0].rpm, Some(1797.0));
    assert_eq!(sets[0].de.as_ref().unwrap().len(), 8);
    assert_eq!(sets[0].ba, None);
}

#[test]
fn parse_record_uses_stored_rpm_and_catalog_labels() {
    let rec = parse_record(&tiny_cwru(105, 1795), 105).unwrap();
    assert_eq!(rec.rpm().value, 1795.0);
    assert_eq!(rec.rpm().source, RpmSource::Stored);
    assert_eq!(rec.fs_hz(), 12_000.0);
    assert_eq!(rec.labels().fault_diameter_in, Some(0.007));
    assert_eq!(rec.de()[1], -0.5);
    assert!(rec.fe().is_some());
    assert!(rec.ba().is_none());
}

#[test]
fn file_174_reads_x173() {
    let rec = parse_record(&tiny_cwru(173, 1796), 174).unwrap();
    assert_eq!(rec.variable(), 173);
    // A file that really holds X174 is not what the catalog says 174.mat is.
    assert!(matches!(
        parse_record(&tiny_cwru(174, 1796), 174),
        Err(DataError::NoDriveEnd { variable: 173, .. })
    ));
}

#[test]
fn file_3001_reads_x056_without_rpm_and_uses_nominal() {
    let de = [0.1, -0.2, 0.3];
    let bytes = build_mat(&[("X056_DE_time", MatData::Double(&de))]);
    let rec = parse_record(&bytes, 3001).unwrap();
    assert_eq!(rec.variable(), 56);
    assert_eq!(rec.rpm().source, RpmSource::Nominal);
    assert_eq!(rec.rpm().value, 1797.0);
    assert_eq!(rec.de(), &de);
    assert!(rec.fe().is_none());
    let bytes = build_mat(&[("X048_DE_time", MatData::Double(&de))]);
    assert_eq!(parse_record(&bytes, 3005).unwrap().variable(), 48);
}

#[test]
fn file_99_picks_x099_over_the_duplicate_x098_set() {
    let a = [1.0, 2.0];
    let b = [3.0, 4.0];
    let bytes = build_mat(&[
        ("X098_DE_time", MatData::Double(&a)),
        ("X098_FE_time", MatData::Double(&a)),
        ("X099_DE_time", MatData::Double(&b)),
        ("X099_FE_time", MatData::Double(&b)),
    ]);
    let rec = parse_record(&bytes, 99).unwrap();
    assert_eq!(rec.de(), &b);
    assert_eq!(rec.rpm().source, RpmSource::Nominal);
    assert_eq!(rec.rpm().value, 1750.0);
    // Without a number, two DE sets are ambiguous.
    let sets = read_variable_sets(&bytes).unwrap();
    assert!(matches!(
        select_set(sets, None),
        Err(DataError::AmbiguousVariables { sets: 2 })
    ));
}

#[test]
fn unknown_record_number_is_a_typed_error() {
    assert!(matches!(
        parse_record(&tiny_cwru(105, 1797), 4242),
        Err(DataError::UnknownRecord { number: 4242 })
    ));
}

#[test]
fn file_without_de_variable_is_a_typed_error() {
    let fe = [1.0];
    let bytes = build_mat(&[
        ("X105_FE_time", MatData::Double(&fe)),
        ("X105RPM", MatData::SmallU16(1797)),
    ]);
    assert!(matches!(
        parse_record(&bytes, 105),
        Err(DataError::NoDriveEnd {
            variable: 105,
            found: 1
        })
    ));
}

#[test]
fn channels_of_different_lengths_are_rejected() {
    let bytes = build_mat(&[
        ("X105_DE_time", MatData::Double(&[1.0, 2.0])),
        ("X105_FE_time", MatData::Double(&[1.0])),
    ]);
    assert!(matches!(
        parse_record(&bytes, 105),
        Err(DataError::ChannelLengthMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
}

#[test]
fn non_finite_samples_are_rejected() {
    let bytes = build_mat(&[("X105_DE_time", MatData::Double(&[1.0, f64::NAN]))]);
    assert!(matches!(
        parse_record(&bytes, 105),
        Err(DataError::NonFinite { index: 1, .. })
    ));
}

#[test]
fn non_mat_and_truncated_inputs_are_typed_errors() {
    assert!(matches!(
        validate_structure(b""),
        Err(DataError::MalformedMat { .. })
    ));
    let text = "file,rel_path\n".repeat(20);
    assert!(matches!(
        parse_record(text.as_bytes(), 105),
        Err(DataError::MalformedMat { offset: 126, .. })
    ));
    let good = tiny_cwru(105, 1797);
    // Just the header is a valid, empty MAT-file: no DE channel.
    assert!(matches!(
        parse_record(&good[..128], 105),
        Err(DataError::NoDriveEnd { found: 0, .. })
    ));
    for cut in [10, 127, 131, 200, good.len() - 1] {
        let r = parse_record(&good[..cut], 105);
        assert!(
            matches!(r, Err(DataError::MalformedMat { .. })),
            "cut at {cut}: {r:?}"
        );
    }
}

#[test]
fn compressed_and_sparse_and_overflowing_dims_are_rejected() {
    let mut bytes = tiny_cwru(105, 1797);
    bytes[128] = 15; // first element type -> miCOMPRESSED
    assert!(matches!(
        validate_structure(&bytes),
        Err(DataError::UnsupportedMat { offset: 128, .. })
    ));
    let mut bytes = tiny_cwru(105, 1797);
    bytes[136 + 8] = 5; // class -> sparse
    assert!(matches!(
        validate_structure(&bytes),
        Err(DataError::UnsupportedMat { .. })
    ));
    let mut bytes = tiny_cwru(105, 1797);
    // dims 8x1 -> 0x10000 x 0x10000: product overflows i32 (would panic inside matfile).
    bytes[160..164].copy_from_slice(&0x10000i32.to_le_bytes());
    bytes[164..168].copy_from_slice(&0x10000i32.to_le_bytes());
    assert!(matches!(
        validate_structure(&bytes),
        Err(DataError::MalformedMat {
            reason: "dimensions overflow",
            ..
        })
    ));
    let mut bytes = tiny_cwru(105, 1797);
    bytes[132..136].copy_from_slice(&u32::MAX.to_le_bytes()); // element length ~4 GiB
    assert!(matches!(
        validate_structure(&bytes),
        Err(DataError::MalformedMat { .. })
    ));
}
