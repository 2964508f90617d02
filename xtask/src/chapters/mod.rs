//! Dissertation chapters as pipelines: `cargo xtask chapter2|chapter3|chapter4|chapter5|all`.
//!
//! Each chapter runs model → observer → residual → window energies → classifier on the CWRU
//! recordings (and, for chapters 4–5, on a simulated substitute for the private SHSE multi-fault
//! data), then writes its tables beside the dissertation's under `results/chapterN/`:
//! `README.md` (people), `tables.csv` and `tables.json` (programs), `figures/*.png`.
//!
//! Layout of this module:
//! - the `pipeline` crate owns the method (model × observer, gains, residual, window energies,
//!   classifiers), the dissertation's tables as transcribed, which recording backs which cell,
//!   and each cell's dataset and protocols;
//! - [`report`]: the table model and the Markdown / CSV / JSON writers;
//! - [`inputs`]: the run's recordings, loaded once (in parallel, with progress);
//! - [`pipeline`]: what each chapter runs;
//! - [`cells`]: the window energies as the `pipeline` crate's table cells read them;
//! - [`notes`]: the report's notes, the observer-gain section and the headline;
//! - [`figures`]: PNG figures with plotters;
//! - `--check`: everything is generated in memory first, so checking is a byte comparison.

mod cells;
pub(crate) mod figures;
mod inputs;
mod notes;
mod report;
mod run;

use crate::common::Context;
use anyhow::Context as _;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Flags of the chapter tasks.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Args {
    /// Regenerate in memory and fail if the committed results differ (writes nothing).
    #[arg(long)]
    pub check: bool,
    /// Reduced configuration (one load, one speed, fewer windows, no figures) written to
    /// `fixtures/chapters-quick/`: what the `--check` test runs.
    #[arg(long)]
    pub quick: bool,
    /// Write (or check) under this directory instead of `results/` (or `fixtures/chapters-quick/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Skip the figures.
    #[arg(long)]
    pub no_figures: bool,
    /// Hide the progress bars.
    #[arg(long)]
    pub quiet: bool,
}

/// Generated files: path relative to the output root → bytes. Ordered, so output is stable.
pub type Files = BTreeMap<PathBuf, Vec<u8>>;

/// Run the given chapters.
pub fn run(ctx: &Context, chapters: &[u8], args: Args) -> anyhow::Result<()> {
    let root = output_root(ctx, &args);
    let t_all = Instant::now();
    let (files, timings, headline) = generate(ctx, chapters, &args)?;
    if args.check {
        let diffs = compare(&root, &files)?;
        if diffs.is_empty() {
            println!(
                "check: {} generated files match {} ({:.1} s)",
                files.len(),
                root.display(),
                t_all.elapsed().as_secs_f64()
            );
            return Ok(());
        }
        for d in &diffs {
            eprintln!("check: {d}");
        }
        anyhow::bail!(
            "{} of {} generated files differ from {}; run the task without --check to regenerate",
            diffs.len(),
            files.len(),
            root.display()
        );
    }
    for (rel, bytes) in &files {
        let p = root.join(rel);
        if let Some(dir) = p.parent() {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        std::fs::write(&p, bytes).with_context(|| format!("writing {}", p.display()))?;
    }
    println!("{headline}");
    for (ch, secs) in &timings {
        println!("chapter {ch}: {secs:.1} s");
    }
    println!(
        "total {:.1} s; results in {}",
        t_all.elapsed().as_secs_f64(),
        root.display()
    );
    for ch in chapters {
        println!(
            "  {}",
            root.join(format!("chapter{ch}/README.md")).display()
        );
    }
    Ok(())
}

/// Where the files go.
fn output_root(ctx: &Context, args: &Args) -> PathBuf {
    match (&args.out, args.quick) {
        (Some(p), _) => p.clone(),
        (None, true) => ctx.root.join("fixtures/chapters-quick"),
        (None, false) => ctx.root.join("results"),
    }
}

/// What [`generate`] returns: the files, the wall time per chapter, a headline for the terminal.
pub type Generated = (Files, Vec<(u8, f64)>, String);

/// Generate every file of the given chapters in memory; returns the files, the wall time per
/// chapter and a headline summary for the terminal.
pub fn generate(ctx: &Context, chapters: &[u8], args: &Args) -> anyhow::Result<Generated> {
    let cfg = run::Config::new(args.quick, !(args.no_figures || args.quick), !args.quiet);
    let mut files = Files::new();
    let mut timings = Vec::new();
    let mut headline = String::new();
    let mut cache = inputs::Cache::default();
    for &ch in chapters {
        let t0 = Instant::now();
        let out =
            run::run_chapter(ctx, &cfg, ch, &mut cache).with_context(|| format!("chapter {ch}"))?;
        let diss = ::pipeline::dissertation::chapter_tables(ch);
        let dir = PathBuf::from(format!("chapter{ch}"));
        files.insert(
            dir.join("README.md"),
            report::markdown(&out.report, &diss).into_bytes(),
        );
        files.insert(
            dir.join("tables.csv"),
            report::csv(&out.report, &diss)?.into_bytes(),
        );
        files.insert(
            dir.join("tables.json"),
            report::json(&out.report, &diss)?.into_bytes(),
        );
        for (name, bytes) in out.figures {
            files.insert(dir.join(name), bytes);
        }
        headline.push_str(&out.headline);
        timings.push((ch, t0.elapsed().as_secs_f64()));
    }
    Ok((files, timings, headline))
}

/// Compare generated files with those on disk; returns one line per difference.
fn compare(root: &Path, files: &Files) -> anyhow::Result<Vec<String>> {
    let mut diffs = Vec::new();
    for (rel, bytes) in files {
        let p = root.join(rel);
        match std::fs::read(&p) {
            Ok(old) if &old == bytes => {}
            Ok(old) => {
                let hint = first_difference(&old, bytes);
                diffs.push(format!("{} differs ({hint})", p.display()));
            }
            Err(_) => diffs.push(format!("{} is missing", p.display())),
        }
    }
    Ok(diffs)
}

/// Where two files first differ, as a short human hint.
fn first_difference(old: &[u8], new: &[u8]) -> String {
    let (Ok(a), Ok(b)) = (std::str::from_utf8(old), std::str::from_utf8(new)) else {
        return format!("binary, {} vs {} bytes", old.len(), new.len());
    };
    for (i, (la, lb)) in a.lines().zip(b.lines()).enumerate() {
        if la != lb {
            return format!("line {}: committed `{la}`, generated `{lb}`", i + 1);
        }
    }
    format!("{} vs {} lines", a.lines().count(), b.lines().count())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The context the CLI would build: `HYBRID_FDD_DATA` if set, else the default location.
    fn test_context() -> Context {
        let data_dir = std::env::var_os("HYBRID_FDD_DATA")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from);
        Context::new(&crate::common::GlobalArgs { data_dir }).unwrap()
    }

    /// `cargo xtask all --quick --check` as a test: the committed quick fixtures must be
    /// reproduced byte for byte. Skips without the data unless `CI=true`.
    /// The boundary: the chapters schedule and report, the `pipeline` crate owns the method and
    /// `classify` the protocols. xtask does not even depend on the crates that build observers,
    /// features or classifiers, so it cannot build an observer or fit a classifier itself; neither
    /// its sources nor the `pipeline` crate's hold a split of windows into training and test
    /// (`classify`'s protocols do that, through `pipeline::cell_plan`).
    #[test]
    fn xtask_builds_no_observer_and_fits_no_classifier() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut sources = Vec::new();
        for dir in ["src/chapters", "../crates/pipeline/src"] {
            for f in std::fs::read_dir(root.join(dir)).expect("source directory") {
                let p = f.expect("directory entry").path();
                if p.extension().is_some_and(|e| e == "rs") {
                    let text = std::fs::read_to_string(&p).expect("source file");
                    sources.push((p.display().to_string(), text));
                }
            }
        }
        assert!(sources.len() >= 10, "the scan found too few sources");
        for (name, src) in &sources {
            if name.ends_with("chapters/mod.rs") {
                continue; // this test names the needles
            }
            for needle in [
                "SplitMix",
                "shuffle",
                "fn random_split",
                "fn time_split",
                ".partition(",
                "WindowMeta {",
            ] {
                assert!(
                    !src.contains(needle),
                    "{name} splits windows or builds window metadata itself (`{needle}`): that \
                     belongs in `classify` (its protocols and `DatasetBuilder`)"
                );
            }
        }
        let manifest = include_str!("../../Cargo.toml");
        for dep in ["observers", "classify", "residual-features"] {
            assert!(
                !manifest
                    .lines()
                    .any(|l| l.trim_start().starts_with(&format!("{dep}."))
                        || l.trim_start().starts_with(&format!("{dep} ="))),
                "xtask depends on `{dep}`: the method belongs in the `pipeline` crate"
            );
        }
    }

    #[test]
    fn quick_check_matches_committed_fixtures() {
        let ctx = test_context();
        if !inputs::cwru_available(&ctx) {
            assert!(!ctx.ci, "CI=true but the CWRU data directory was not found");
            eprintln!("skipping quick_check_matches_committed_fixtures: CWRU data not found");
            return;
        }
        let args = Args {
            check: true,
            quick: true,
            quiet: true,
            ..Args::default()
        };
        run(&ctx, &[2, 3, 4, 5], args).expect("quick results differ from fixtures/chapters-quick");
    }

    #[test]
    fn generation_is_deterministic() {
        let ctx = test_context();
        if !inputs::cwru_available(&ctx) {
            assert!(!ctx.ci, "CI=true but the CWRU data directory was not found");
            eprintln!("skipping generation_is_deterministic: CWRU data not found");
            return;
        }
        let args = Args {
            quick: true,
            quiet: true,
            ..Args::default()
        };
        let (a, _, _) = generate(&ctx, &[2], &args).unwrap();
        let (b, _, _) = generate(&ctx, &[2], &args).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn first_difference_names_the_line() {
        assert_eq!(
            first_difference(b"a\nb\n", b"a\nc\n"),
            "line 2: committed `b`, generated `c`"
        );
    }
}
