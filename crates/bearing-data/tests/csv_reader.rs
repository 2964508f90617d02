//! The CSV / plain-text reader.

use bearing_data::{Column, CsvOptions, DataError, HeaderRow, read_csv};

fn read(text: &str, column: Column) -> bearing_data::Result<Vec<f64>> {
    read_csv(text.as_bytes(), &CsvOptions::new(12_000.0, column))
        .map(bearing_data::Signal::into_samples)
}

#[test]
fn reads_the_simulate_csv_by_column_name() {
    // The shape `cargo xtask simulate` writes: a header row with an `accel` column.
    let text = "t,accel,force\n0.0,1.5,9\n8.3e-5,-2.25e-3,9\n1.6e-4,  3 ,9\n";
    assert_eq!(
        read(text, Column::Name("accel".into())).unwrap(),
        vec![1.5, -2.25e-3, 3.0]
    );
    assert!(matches!(
        read(text, Column::Name("vel".into())),
        Err(DataError::CsvNoSuchColumn { .. })
    ));
    assert_eq!(read(text, Column::Index(2)).unwrap(), vec![9.0, 9.0, 9.0]);
}

#[test]
fn reads_a_single_column_with_or_without_header_and_comments() {
    assert_eq!(
        read("1\n2\n\n3.5\n", Column::Single).unwrap(),
        vec![1.0, 2.0, 3.5]
    );
    assert_eq!(
        read("# my sensor\naccel\n1\n-2\n", Column::Single).unwrap(),
        vec![1.0, -2.0]
    );
    let opts = CsvOptions {
        header: HeaderRow::Present,
        ..CsvOptions::new(1.0, Column::Single)
    };
    assert_eq!(
        read_csv("5\n6\n".as_bytes(), &opts).unwrap().samples(),
        &[6.0]
    );
    let opts = CsvOptions {
        delimiter: b';',
        ..CsvOptions::new(1.0, Column::Index(1))
    };
    assert_eq!(
        read_csv("a;b\n1;2\n".as_bytes(), &opts).unwrap().samples(),
        &[2.0]
    );
    let s = read_csv("1\n2\n".as_bytes(), &CsvOptions::new(2.0, Column::Single)).unwrap();
    assert_eq!(s.duration_s(), 1.0);
}

#[test]
fn bad_csv_inputs_are_typed_errors() {
    assert!(matches!(
        read("", Column::Single),
        Err(DataError::Empty { .. })
    ));
    assert!(matches!(
        read("accel\n", Column::Single),
        Err(DataError::Empty { .. })
    ));
    assert!(matches!(
        read("1\n2\nabc\n", Column::Single),
        Err(DataError::CsvNotANumber { line: 3, .. })
    ));
    assert!(matches!(
        read("1\nNaN\n", Column::Single),
        Err(DataError::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        read("1\ninf\n", Column::Single),
        Err(DataError::NonFinite { .. })
    ));
    // finite, but its square overflows every energy downstream
    assert!(matches!(
        read("1\n2\n-1e300\n", Column::Single),
        Err(DataError::SampleTooLarge { index: 2, value, .. }) if value == -1e300
    ));
    assert!(read("1\n1e149\n", Column::Single).is_ok());
    assert!(matches!(
        read("1,2\n3,4\n", Column::Single),
        Err(DataError::CsvSeveralColumns { .. })
    ));
    assert!(matches!(
        read("1,2\n3\n", Column::Index(1)),
        Err(DataError::CsvMissingField { line: 2, .. })
    ));
    assert!(matches!(
        read_csv(&b"\xff\xfe\n"[..], &CsvOptions::new(1.0, Column::Single)),
        Err(DataError::Csv { .. })
    ));
    let bad_fs = CsvOptions::new(0.0, Column::Single);
    assert!(matches!(
        read_csv("1\n".as_bytes(), &bad_fs),
        Err(DataError::InvalidParameter { name: "fs_hz", .. })
    ));
}
