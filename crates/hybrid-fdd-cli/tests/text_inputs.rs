//! Recordings from other tools: `,` `;` or tab delimited, a time column, a named or numbered
//! signal column; ambiguous files are refused with a one-line error naming the columns.

use hybrid_fdd_cli::diagnose::load;

fn write(name: &str, body: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hybrid-fdd-text-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = dir.join(name);
    std::fs::write(&p, body).expect("write");
    p
}

/// `n` rows of (time at `fs`, a signal that is not the time), joined by `sep`.
fn rows(n: usize, fs: f64, sep: &str) -> (String, Vec<f64>) {
    let x: Vec<f64> = (0..n).map(|k| ((k * 7919) % 23) as f64 - 11.0).collect();
    let body = x
        .iter()
        .enumerate()
        .map(|(k, v)| format!("{:.9}{sep}{v}\n", k as f64 / fs))
        .collect();
    (body, x)
}

#[test]
fn time_and_signal_in_any_delimiter_give_the_signal_and_its_rate() {
    for (sep, ext) in [(",", "csv"), (";", "csv"), ("\t", "tsv")] {
        let (body, x) = rows(500, 25_600.0, sep);
        let p = write(&format!("ts.{ext}"), &format!("Time{sep}vib\n{body}"));
        let l = load(&p, "DE", None).expect("time + signal");
        assert_eq!(l.samples, x, "delimiter {sep:?}");
        assert_eq!(l.fs_hz, 25_600.0);
        assert!(l.unit.is_unknown());
        // the column by name (any case) or by number
        assert_eq!(load(&p, "VIB", None).expect("by name").samples, x);
        assert_eq!(load(&p, "2", None).expect("by number").samples, x);
    }
}

#[test]
fn ambiguous_or_unknown_columns_are_refused_by_name() {
    let (body, x) = rows(100, 1000.0, ",");
    let p = write("nohdr.csv", &body);
    let e = load(&p, "DE", Some(1000.0)).expect_err("two unnamed columns");
    assert!(e.to_string().contains("--channel"), "{e}");
    assert_eq!(load(&p, "2", Some(1000.0)).expect("numbered").samples, x);
    let e = load(&p, "2", None).expect_err("no rate");
    assert!(e.to_string().contains("--fs"), "{e}");
    let p = write("named.csv", &format!("time,vib\n{body}"));
    let e = load(&p, "foo", None).expect_err("no such column");
    assert!(e.to_string().contains("time, vib"), "{e}");
    let e = load(&p, "3", None).expect_err("no third column");
    assert!(e.to_string().contains("no column `3`"), "{e}");
}

/// QA m1: a non-finite sample is named with the file, its line and the column numbered from 1
/// (as `--channel`).
#[test]
fn a_non_finite_sample_names_the_file_line_and_column() {
    let (body, _) = rows(50, 1000.0, ",");
    let mut lines: Vec<String> = body.lines().map(str::to_string).collect();
    lines[6] = format!("{},NaN", lines[6].split(',').next().unwrap());
    let p = write("nan2.csv", &format!("time,vib\n{}\n", lines.join("\n")));
    let e = load(&p, "DE", None).expect_err("NaN").to_string();
    assert!(e.contains("nan2.csv"), "{e}");
    assert!(
        e.contains("line 8") && e.contains("column 2 (`vib`)"),
        "{e}"
    );
    assert!(e.contains("non-finite"), "{e}");
}

/// A finite sample whose square overflows is named like a non-finite one.
#[test]
fn a_sample_whose_square_overflows_names_the_file_line_and_column() {
    let (body, _) = rows(50, 1000.0, ",");
    let mut lines: Vec<String> = body.lines().map(str::to_string).collect();
    lines[9] = format!("{},1e300", lines[9].split(',').next().unwrap());
    let p = write("huge2.csv", &format!("time,vib\n{}\n", lines.join("\n")));
    let e = load(&p, "DE", None).expect_err("1e300").to_string();
    assert!(e.contains("huge2.csv") && e.contains("line 11"), "{e}");
    assert!(
        e.contains("column 2 (`vib`)") && e.contains("too large"),
        "{e}"
    );
}

/// QA m2: a UTF-8 byte-order mark and double quotes around header names and numbers.
#[test]
fn a_byte_order_mark_and_quotes_are_dropped() {
    let (body, x) = rows(200, 8000.0, ",");
    let quoted: String = body
        .lines()
        .map(|l| {
            let (t, v) = l.split_once(',').unwrap();
            format!("\"{t}\",\"{v}\"\n")
        })
        .collect();
    let p = write("bom.csv", &format!("\u{feff}\"Time\",\"vib\"\n{quoted}"));
    let l = load(&p, "DE", None).expect("BOM + quotes");
    assert_eq!(l.samples, x);
    assert_eq!(l.fs_hz, 8000.0);
    assert_eq!(load(&p, "vib", None).expect("by name").samples, x);
    // a BOM before a headerless one-column file
    let one: String = x.iter().map(|v| format!("{v}\n")).collect();
    let p = write("bom1.csv", &format!("\u{feff}{one}"));
    assert_eq!(load(&p, "DE", Some(8000.0)).expect("BOM").samples, x);
}
