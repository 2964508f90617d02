//! The `hybrid-fdd` command as a library, so `cargo xtask diagnose`, `calibrate`, `close-loop`
//! and `simulate` run the very same code (xtask keeps only the shared-data batches, `--all-real`):
//! argument types, recording loading (CWRU `.mat` via `bearing-data`, one-column CSV), baseline
//! preparation (decimated with `bearing-data`'s anti-aliasing decimator when its rate is an
//! integer multiple of the recording's), the call into the `diagnosis` crate, and the reports
//! (JSON, Markdown, PNG figure); the closed loop and calibration on one recording
//! ([`close_loop`]), the 5-DOF simulation to CSV ([`simulate`]), the bearing catalogue as a
//! table ([`bearings`]); the flags several commands share and the parsers of the typed ones
//! ([`flags`]). No signal processing lives here.

/// `println!` that ignores a closed standard output (`hybrid-fdd simulate … | head`): the
/// files are written either way, and a reader that went away is not an error of the command.
#[macro_export]
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

pub mod bearings;
pub mod close_loop;
pub mod diagnose;
pub mod figure;
pub mod flags;
pub mod simulate;
pub mod simulate_life;
pub mod train;
pub mod trend;

/// Parse a `--bearing` spec with bearing-model's parser and say on stderr what looks wrong
/// without being an error ([`bearing_model::BearingSpec::warnings`]: a `bsf` away from the
/// kinematics of the other multiples).
///
/// # Errors
/// The parser's typed errors (a textbook ball spin given as `bsf` among them).
pub fn parse_bearing(spec: &str) -> anyhow::Result<bearing_model::BearingSpec> {
    let b = bearing_model::BearingSpec::parse(spec)?;
    for w in b.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(b)
}

/// The path of `p` with its directory resolved (`None` when the directory does not exist, so
/// nothing there can be overwritten).
pub(crate) fn resolved(p: &std::path::Path) -> Option<std::path::PathBuf> {
    let dir = p
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    Some(std::fs::canonicalize(dir).ok()?.join(p.file_name()?))
}

/// Refuse, with a one-line error, outputs that would replace what the command reads: each of
/// `inputs` (a recording, a baseline, a machine model) and, for a text recording
/// (`.csv`/`.tsv`/`.txt`), its JSON sidecar `x.json`, which carries its unit and speed — a
/// report written over it makes the next run read the recording in the wrong unit.
///
/// # Errors
/// When an output and a protected file are the same path (directories resolved).
pub fn refuse_overwrite(
    flag: &str,
    outputs: &[std::path::PathBuf],
    inputs: &[&std::path::Path],
) -> anyhow::Result<()> {
    let mut protected: Vec<(std::path::PathBuf, &'static str)> = Vec::new();
    for i in inputs {
        protected.push((i.to_path_buf(), "an input of this command"));
        let text = i.extension().and_then(|e| e.to_str()).is_some_and(|e| {
            ["csv", "tsv", "txt"]
                .iter()
                .any(|x| e.eq_ignore_ascii_case(x))
        });
        let side = i.with_extension("json");
        if text && side.is_file() {
            protected.push((side, "a recording's sidecar (its unit and speed)"));
        }
    }
    for o in outputs {
        let Some(ro) = resolved(o) else { continue };
        for (p, what) in &protected {
            if resolved(p).is_some_and(|rp| rp == ro) {
                anyhow::bail!(
                    "{flag} would overwrite {} ({what}) with {}: choose another path",
                    p.display(),
                    o.display()
                );
            }
        }
    }
    Ok(())
}

/// A report's three files: `x.json`, `x.md`, `x.png`.
pub fn report_files(report: &std::path::Path) -> Vec<std::path::PathBuf> {
    ["json", "md", "png"]
        .iter()
        .map(|e| report.with_extension(e))
        .collect()
}
