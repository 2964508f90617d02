//! Recordings from other rigs as their rigs store them: MAT-files with the signal inside a
//! struct (MFPT's `bearing.gs` beside its rate `bearing.sr` and shaft rate `bearing.rate`,
//! compressed as MATLAB saves),
//! inside a struct array with `Name`/`Data` (Paderborn's `X.Y(k)`), at the top level beside a
//! scalar `SampleFrequency` and a scalar `Datacount` (UESTC's), and text files named by date
//! with no extension (IMS). Each is diagnosed as it is.

mod common;

use bearing_data::{MatArray, write_mat};
use clap::Parser as _;
use common::{BEARING, Diagnose, Fault, dir, json, machine, s};

fn diagnose(input: &std::path::Path, extra: &[&str]) -> anyhow::Result<serde_json::Value> {
    let report = input.with_extension("report.json");
    let mut v = vec![
        "diagnose",
        "--input",
        s(input),
        "--rpm",
        "1500",
        "--bearing",
        BEARING,
        "--report",
        s(&report),
    ];
    v.extend_from_slice(extra);
    hybrid_fdd_cli::diagnose::run(&Diagnose::try_parse_from(v).unwrap().a)?;
    Ok(json(&report))
}

#[test]
fn a_signal_in_a_compressed_struct_is_found_with_its_stored_rate() {
    let d = dir("other-mat-struct");
    let x = machine(Fault::Outer, 20_000.0, 1500.0, 2.0, 3);
    let f = d.join("OuterRaceFault_1.mat");
    std::fs::write(
        &f,
        write_mat(
            &[(
                "bearing",
                MatArray::Struct(
                    ["gs", "sr", "load", "rate"].map(String::from).to_vec(),
                    vec![vec![
                        MatArray::Double(vec![x.len(), 1], x.clone()),
                        MatArray::Double(vec![1, 1], vec![20_000.0]),
                        MatArray::Double(vec![1, 1], vec![270.0]),
                        MatArray::Double(vec![1, 1], vec![25.0]),
                    ]],
                ),
            )],
            true,
        ),
    )
    .unwrap();
    // no --fs, no --channel: the only signal and the rate stored beside it
    let r = diagnose(&f, &[]).expect("diagnosed");
    assert_eq!(r["verdict"], "outer", "{r}");
    // a --fs that disagrees with the stored rate is refused
    let e = diagnose(&f, &["--fs", "19000"]).unwrap_err();
    assert!(format!("{e:#}").contains("disagrees"), "{e:#}");
    // no --rpm: the shaft rate MFPT stores as `rate` (Hz) is the declared speed
    let report = d.join("no-rpm.json");
    let args = [
        "diagnose",
        "--input",
        s(&f),
        "--bearing",
        BEARING,
        "--report",
        s(&report),
    ];
    hybrid_fdd_cli::diagnose::run(&Diagnose::try_parse_from(args).unwrap().a).expect("diagnosed");
    let r = json(&report);
    assert_eq!(r["operating_point"]["rpm"], 1500.0, "{r}");
    assert_eq!(r["verdict"], "outer", "{r}");
}

#[test]
fn a_bad_sample_in_another_mat_file_is_named_with_its_variable() {
    let d = dir("other-mat-bad-sample");
    for (name, bad, says) in [
        (
            "nan.mat",
            f64::NAN,
            "non-finite sample in `vib` at index 123",
        ),
        (
            "huge.mat",
            1e300,
            "sample 1e300 in `vib` at index 123 is too large",
        ),
    ] {
        let mut x = machine(Fault::Outer, 20_000.0, 1500.0, 1.0, 3);
        x[123] = bad;
        let f = d.join(name);
        let vars = [
            ("vib", MatArray::Double(vec![x.len(), 1], x)),
            ("fs", MatArray::Double(vec![1, 1], vec![20_000.0])),
        ];
        std::fs::write(&f, write_mat(&vars, false)).unwrap();
        let e = format!("{:#}", diagnose(&f, &[]).unwrap_err());
        assert!(e.contains(name) && e.contains(says), "{e}");
    }
}

#[test]
fn a_struct_arrays_signal_is_chosen_by_its_name() {
    let d = dir("other-mat-named");
    let x = machine(Fault::Outer, 20_000.0, 1500.0, 2.0, 4);
    let healthy = machine(Fault::None, 20_000.0, 1500.0, 2.0, 5);
    let f = d.join("N15_M07_F10_KA01_1.mat");
    let elem = |name: &str, v: &[f64]| {
        vec![
            MatArray::Text(name.into()),
            MatArray::Double(vec![1, v.len()], v.to_vec()),
        ]
    };
    std::fs::write(
        &f,
        write_mat(
            &[(
                "N15_M07_F10_KA01_1",
                MatArray::Struct(
                    ["Info", "Y"].map(String::from).to_vec(),
                    vec![vec![
                        MatArray::Text("test rig".into()),
                        MatArray::Struct(
                            ["Name", "Data"].map(String::from).to_vec(),
                            vec![
                                elem("force", &healthy[..4000]),
                                elem("vibration_1", &x),
                                elem("vibration_2", &healthy),
                            ],
                        ),
                    ]],
                ),
            )],
            false,
        ),
    )
    .unwrap();
    // three vectors: the default channel is ambiguous, and the error lists the names
    let e = format!("{:#}", diagnose(&f, &["--fs", "20000"]).unwrap_err());
    assert!(e.contains("vibration_1") && e.contains("--channel"), "{e}");
    let r = diagnose(&f, &["--fs", "20000", "--channel", "vibration_1"]).expect("diagnosed");
    assert_eq!(r["verdict"], "outer", "{r}");
    let r = diagnose(&f, &["--fs", "20000", "--channel", "vibration_2"]).expect("diagnosed");
    assert_eq!(r["verdict"], "normal", "{r}");
    // no rate stored and no --fs: said
    let e = format!(
        "{:#}",
        diagnose(&f, &["--channel", "vibration_1"]).unwrap_err()
    );
    assert!(e.contains("give --fs"), "{e}");
}

#[test]
fn a_text_file_without_extension_is_read_by_content() {
    let d = dir("other-text-noext");
    let x = machine(Fault::Outer, 20_000.0, 1500.0, 2.0, 6);
    let f = d.join("2004.02.12.10.32.39");
    let body: String = x
        .iter()
        .map(|v| format!("{v:.6}\t{:.6}\n", 0.5 * v))
        .collect();
    std::fs::write(&f, body).unwrap();
    let r = diagnose(&f, &["--fs", "20000", "--channel", "1"]).expect("diagnosed");
    assert_eq!(r["verdict"], "outer", "{r}");
    let bin = d.join("blob.bin");
    std::fs::write(&bin, [0u8, 159, 146, 150, 0, 1]).unwrap();
    let e = format!("{:#}", diagnose(&bin, &["--fs", "20000"]).unwrap_err());
    assert!(e.contains("neither a MAT-file nor text"), "{e}");
}

#[test]
fn a_directory_of_date_named_records_is_a_batch() {
    let d = dir("other-ims-batch");
    let input = d.join("2nd_test");
    std::fs::create_dir_all(&input).unwrap();
    for (name, fault, seed) in [
        ("2004.02.12.10.32.39", Fault::None, 7),
        ("2004.02.12.10.42.39", Fault::Outer, 8),
    ] {
        let x = machine(fault, 20_000.0, 1500.0, 2.0, seed);
        let body: String = x
            .iter()
            .map(|v| format!("{v:.6}\t{:.6}\n", 0.5 * v))
            .collect();
        std::fs::write(input.join(name), body).unwrap();
    }
    // not recordings: another extension, and a binary file without one
    std::fs::write(input.join("notes.md"), "# test rig\n").unwrap();
    std::fs::write(input.join("blob"), [0u8, 159, 146, 150]).unwrap();
    let out = d.join("out");
    let a = Diagnose::try_parse_from([
        "diagnose",
        "--input",
        s(&input),
        "--fs",
        "20000",
        "--rpm",
        "1500",
        "--channel",
        "1",
        "--bearing",
        BEARING,
        "--report",
        s(&out),
    ])
    .unwrap()
    .a;
    hybrid_fdd_cli::diagnose::run(&a).expect("batch");
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 3, "{summary}");
    assert_eq!(
        json(&out.join("2004.02.12.10.32.json"))["verdict"],
        "normal"
    );
    assert_eq!(json(&out.join("2004.02.12.10.42.json"))["verdict"], "outer");
}

/// UESTC's layout: `Data` (the signal), `Datacount` (a scalar) and the rate as
/// `SampleFrequency`, all at the top level; other spellings of a stored rate too.
#[test]
fn a_rate_stored_as_sample_frequency_is_read_whatever_its_case_and_underscores() {
    let d = dir("other-mat-sample-frequency");
    let x = machine(Fault::Outer, 20_000.0, 1500.0, 2.0, 5);
    let write = |name: &str, rate: Option<&str>| {
        let f = d.join(name);
        let mut vars = vec![
            ("Data", MatArray::Double(vec![x.len(), 1], x.clone())),
            (
                "Datacount",
                MatArray::Double(vec![1, 1], vec![x.len() as f64]),
            ),
        ];
        if let Some(r) = rate {
            vars.push((r, MatArray::Double(vec![1, 1], vec![20_000.0])));
        }
        std::fs::write(&f, write_mat(&vars, false)).unwrap();
        f
    };
    for rate in [
        "SampleFrequency",
        "SamplingFrequency",
        "SampleRate",
        "Sampling_Rate",
        "Fs",
        "freq_sampling",
    ] {
        let f = write(&format!("{rate}.mat"), Some(rate));
        let l = hybrid_fdd_cli::diagnose::load(&f, "DE", None).expect(rate);
        assert_eq!(l.fs_hz, 20_000.0, "{rate}");
        // `Data` is the signal, not the scalar `Datacount`
        assert_eq!(l.samples, x, "{rate}");
    }
    // diagnosed end to end without --fs, the bearing given by its catalogue designation
    let f = write("N_1500_1.mat", Some("SampleFrequency"));
    let report = d.join("n.json");
    let args = [
        "diagnose",
        "--input",
        s(&f),
        "--rpm",
        "1500",
        "--bearing",
        "uc204",
        "--report",
        s(&report),
    ];
    hybrid_fdd_cli::diagnose::run(&Diagnose::try_parse_from(args).unwrap().a).expect("diagnosed");
    let r = json(&report);
    assert_eq!(r["operating_point"]["fs_hz"], 20_000.0, "{r}");
    assert_eq!(r["operating_point"]["bearing"], "UC204", "{r}");
    assert_eq!(r["operating_point"]["bearing_spec"], "uc204 (UC204)", "{r}");
    // no rate stored: the error names the accepted spellings and --fs
    let f = write("no-rate.mat", None);
    let e = format!(
        "{:#}",
        hybrid_fdd_cli::diagnose::load(&f, "DE", None).unwrap_err()
    );
    assert!(
        e.contains("stores no sampling rate")
            && e.contains("SampleFrequency")
            && e.contains("--fs"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The UESTC recording the project keeps for development (data/uestc, not committed): its
/// `SampleFrequency` is the rate and `Data` the signal. Skipped where the data is absent.
#[test]
fn the_uestc_recording_gives_its_stored_rate_and_its_data() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let data = bearing_data::DataLocation::from_env(&root).ok();
    let Some(f) = data
        .as_ref()
        .and_then(|l| l.path())
        .map(|p| p.join("uestc/Data/N_1000/N_1000_1.mat"))
        .filter(|f| f.is_file())
    else {
        eprintln!("skipped: no data/uestc/Data/N_1000/N_1000_1.mat");
        return;
    };
    let l = hybrid_fdd_cli::diagnose::load(&f, "DE", None).expect("UESTC file");
    assert_eq!(l.fs_hz, 20_000.0);
    // README: `Data` holds 262,144 samples
    assert_eq!(l.samples.len(), 262_144);
    assert_eq!(l.rpm, None);
}
