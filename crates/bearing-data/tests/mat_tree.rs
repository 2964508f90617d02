//! The generic MAT reader on files shaped like other rigs' (written here by `write_mat`, so
//! that no `.mat` file is committed): compressed structs, struct arrays with `Name`/`Data`,
//! cells, text, integer and single classes, complex arrays, and what `select_signal` and
//! `sampling_rate_near` make of them.

mod common;

use bearing_data::{DataError, MatValue, read_mat_tree, sampling_rate_near, select_signal};
use common::mat_fixtures::{expected_signal, fixture};

#[test]
fn a_compressed_struct_gives_its_fields_and_the_rate_beside_the_signal() {
    let leaves = read_mat_tree(&fixture("mfpt_like.mat")).unwrap();
    let paths: Vec<&str> = leaves.iter().map(|l| l.path.as_str()).collect();
    assert_eq!(
        paths,
        ["bearing.gs", "bearing.sr", "bearing.load", "bearing.rate"]
    );
    let s = select_signal(&leaves, None).unwrap();
    assert_eq!(s.path, "bearing.gs");
    assert_eq!(s.samples, expected_signal());
    assert_eq!(sampling_rate_near(&leaves, &s.path), Some(48828.0));
    // by its last path component too
    assert_eq!(
        select_signal(&leaves, Some("GS")).unwrap().path,
        "bearing.gs"
    );
}

#[test]
fn a_struct_arrays_data_is_known_by_its_name() {
    let leaves = read_mat_tree(&fixture("paderborn_like.mat")).unwrap();
    let s = select_signal(&leaves, Some("vibration_1")).unwrap();
    assert_eq!(s.path, "N15_M07_F10_KA01_1.Y(2).Data");
    assert_eq!(s.alias.as_deref(), Some("vibration_1"));
    assert_eq!(s.samples, expected_signal());
    assert!(
        leaves.iter().any(|l| l.path == "N15_M07_F10_KA01_1.Info"
            && l.value == MatValue::Text("N15_M07_F10".into()))
    );
    // three `Data` vectors: the last component alone is ambiguous, and the error lists them
    let err = select_signal(&leaves, Some("Data"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("3 signals fit") && err.contains("vibration_1"),
        "{err}"
    );
    // no rate stored: none invented
    assert_eq!(sampling_rate_near(&leaves, &s.path), None);
}

#[test]
fn top_level_variables_of_every_class_are_read() {
    let leaves = read_mat_tree(&fixture("plain.mat")).unwrap();
    let get = |p: &str| leaves.iter().find(|l| l.path == p).unwrap();
    let vib = get("vib").vector().unwrap();
    // stored as single precision
    assert!(
        vib.iter()
            .zip(expected_signal())
            .all(|(a, b)| (a - b).abs() < 1e-6)
    );
    let counts = get("counts").vector().unwrap();
    assert_eq!(counts[25], (expected_signal()[25] * 100.0).trunc());
    assert_eq!(get("fs").scalar(), Some(25600.0));
    assert_eq!(get("unit").value, MatValue::Text("g".into()));
    assert!(matches!(get("z").value, MatValue::Complex { .. }));
    // two vectors long enough: `vib` and `counts`
    assert!(matches!(
        select_signal(&leaves, None),
        Err(DataError::MatSignal { .. })
    ));
    let s = select_signal(&leaves, Some("vib")).unwrap();
    assert_eq!(sampling_rate_near(&leaves, &s.path), Some(25600.0));
    assert!(
        select_signal(&leaves, Some("unit")).is_err(),
        "text is not a signal"
    );
    let err = select_signal(&leaves, Some("nope"))
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("no signal `nope`"), "{err}");
}

#[test]
fn cells_are_walked_and_two_candidates_need_a_choice() {
    let leaves = read_mat_tree(&fixture("two_signals.mat")).unwrap();
    assert!(leaves.iter().any(|l| l.path.starts_with("c{")));
    let err = select_signal(&leaves, None).unwrap_err().to_string();
    assert!(err.contains("choose one with --channel"), "{err}");
    let s = select_signal(&leaves, Some("channel_2")).unwrap();
    assert_eq!(s.samples[25], -expected_signal()[25]);
}

#[test]
fn what_is_not_a_mat_file_is_a_typed_error() {
    assert!(matches!(
        read_mat_tree(b"time,accel\n0,1\n"),
        Err(DataError::MalformedMat { .. })
    ));
    let mut hdf = vec![0u8; 0x300];
    hdf[0x200..0x208].copy_from_slice(b"\x89HDF\r\n\x1a\n");
    let e = read_mat_tree(&hdf).unwrap_err().to_string();
    assert!(e.contains("v7.3"), "{e}");
    // a compressed element cut short
    let b = fixture("mfpt_like.mat");
    assert!(read_mat_tree(&b[..b.len() - 40]).is_err());
}

#[test]
fn the_shaft_speed_is_read_beside_the_signal_in_its_stated_unit() {
    use bearing_data::{MatArray, shaft_speed_near, write_mat};
    // MFPT's `rate` is the shaft's rotation frequency in Hz, beside its sampling rate `sr`
    let leaves = read_mat_tree(&fixture("mfpt_like.mat")).unwrap();
    let sp = shaft_speed_near(&leaves, "bearing.gs", 48828.0).unwrap();
    assert_eq!(
        (sp.rpm, sp.path.as_str(), sp.stored, sp.unit),
        (1500.0, "bearing.rate", 25.0, "Hz")
    );
    // no speed stored: none invented
    let leaves = read_mat_tree(&fixture("plain.mat")).unwrap();
    assert_eq!(shaft_speed_near(&leaves, "vib", 25600.0), None);

    let scalar = |v: f64| MatArray::Double(vec![1, 1], vec![v]);
    let signal = MatArray::Double(vec![2048, 1], expected_signal()[..2048].to_vec());
    let tree = |fields: &[(&str, MatArray)]| {
        let names = fields.iter().map(|(n, _)| n.to_string()).collect();
        let values = fields.iter().map(|(_, v)| v.clone()).collect();
        read_mat_tree(&write_mat(
            &[("s", MatArray::Struct(names, vec![values]))],
            false,
        ))
        .unwrap()
    };
    // `rate` alone may be the sampling rate: not a speed
    let l = tree(&[("x", signal.clone()), ("rate", scalar(25.0))]);
    assert_eq!(shaft_speed_near(&l, "s.x", 20000.0), None);
    // `rate` at the sampling rate is not a speed either
    let l = tree(&[
        ("x", signal.clone()),
        ("fs", scalar(20000.0)),
        ("rate", scalar(20000.0)),
    ]);
    assert_eq!(shaft_speed_near(&l, "s.x", 20000.0), None);
    // rpm in rev/min, fr in Hz; agreeing, either is the speed; disagreeing, neither
    let l = tree(&[
        ("x", signal.clone()),
        ("rpm", scalar(1797.0)),
        ("fr", scalar(29.95)),
    ]);
    assert_eq!(shaft_speed_near(&l, "s.x", 12000.0).unwrap().rpm, 1797.0);
    let l = tree(&[
        ("x", signal.clone()),
        ("rpm", scalar(1797.0)),
        ("fr", scalar(20.0)),
    ]);
    assert_eq!(shaft_speed_near(&l, "s.x", 12000.0), None);
    // a rotation frequency above the Nyquist frequency is not a speed
    let l = tree(&[("x", signal), ("shaft_hz", scalar(7000.0))]);
    assert_eq!(shaft_speed_near(&l, "s.x", 12000.0), None);
}

#[test]
fn a_stored_rate_is_found_under_its_common_names_with_case_and_underscores_ignored() {
    use bearing_data::{MatArray, is_sampling_rate_name, write_mat};
    for name in [
        "fs",
        "Fs",
        "FS",
        "sr",
        "sample_rate",
        "sampling_rate",
        "SampleRate",
        "SamplingRate",
        "SampleFrequency",
        "SamplingFrequency",
        "sampling_frequency",
        "freq_sampling",
        "samplerate",
        "fs_hz",
    ] {
        assert!(is_sampling_rate_name(name), "{name}");
    }
    for name in ["rate", "rpm", "Datacount", "frequency", "f", "fr", "sample"] {
        assert!(!is_sampling_rate_name(name), "{name}");
    }
    // UESTC's layout: `Data`, a scalar `Datacount` and `SampleFrequency`, all at the top level
    let signal = expected_signal()[..2048].to_vec();
    let bytes = write_mat(
        &[
            ("Data", MatArray::Double(vec![2048, 1], signal.clone())),
            ("Datacount", MatArray::Double(vec![1, 1], vec![2048.0])),
            (
                "SampleFrequency",
                MatArray::Double(vec![1, 1], vec![20000.0]),
            ),
        ],
        false,
    );
    let leaves = read_mat_tree(&bytes).unwrap();
    let s = select_signal(&leaves, None).unwrap();
    assert_eq!(s.path, "Data");
    assert_eq!(s.samples, signal);
    assert_eq!(sampling_rate_near(&leaves, &s.path), Some(20000.0));
}
