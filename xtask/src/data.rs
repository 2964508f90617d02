//! `cargo xtask data`: the embedded CWRU catalog against what is on disk (present, verified,
//! missing), including the records the shared copy lacks. Exits non-zero on a checksum mismatch,
//! or when a file the shared copy should hold is missing.

use anyhow::Context as _;
use bearing_data::{
    CatalogEntry, FileStatus, LoadOptions, Query, Verify, catalog, check_file, load_record,
};

use crate::common::Context;

/// Flags of this task.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Skip SHA-256 verification (only check that files exist).
    #[arg(long)]
    pub no_verify: bool,
    /// Also parse every present file and check its sample count against the catalog.
    #[arg(long)]
    pub parse: bool,
    /// Only records at this sampling rate (12000 or 48000).
    #[arg(long)]
    pub fs: Option<u32>,
    /// Only records with this fault diameter in inches (0.007, 0.014, 0.021, 0.028).
    #[arg(long)]
    pub diameter: Option<f64>,
    /// Only records at this motor load (0-3 hp).
    #[arg(long)]
    pub load: Option<u8>,
    /// Download missing files (not implemented: this environment has no network access).
    #[arg(long)]
    pub download: bool,
}

fn status_text(e: &CatalogEntry, s: &FileStatus) -> String {
    match (s, e.in_shared_copy) {
        (FileStatus::Verified, _) => "verified".into(),
        (FileStatus::Present, _) if e.sha256.is_none() => "present (no pinned SHA-256)".into(),
        (FileStatus::Present, _) => "present (not verified)".into(),
        (FileStatus::Mismatch { found }, _) => format!("SHA-256 MISMATCH ({}…)", &found[..12]),
        (FileStatus::Missing, true) => "MISSING (expected in shared copy)".into(),
        (FileStatus::Missing, false) => "missing (not in shared copy)".into(),
    }
}

/// How many catalogued files fell in each status, and how many failed to parse.
#[derive(Default)]
struct Tally {
    verified: usize,
    present: usize,
    mismatched: usize,
    missing_expected: usize,
    absent: usize,
    parse_fail: usize,
}

impl Tally {
    /// Count one file's status (`in_shared_copy`: whether the shared copy should hold it).
    fn count(&mut self, status: &FileStatus, in_shared_copy: bool) {
        match (status, in_shared_copy) {
            (FileStatus::Verified, _) => self.verified += 1,
            (FileStatus::Present, _) => self.present += 1,
            (FileStatus::Mismatch { .. }, _) => self.mismatched += 1,
            (FileStatus::Missing, true) => self.missing_expected += 1,
            (FileStatus::Missing, false) => self.absent += 1,
        }
    }
}

/// Run the task.
pub fn run(ctx: &Context, args: Args) -> anyhow::Result<()> {
    if args.download {
        anyhow::bail!(
            "--download is not implemented: this build has no network access. Fetch the files from \
             https://engineering.case.edu/sites/default/files/<number>.mat into <data-dir>/cwru/ \
             (see the rel_path column) and rerun `cargo xtask data` to verify them"
        );
    }
    let dir = ctx.data_dir_or_skip()?;
    let cwru = dir.map(bearing_data::cwru_dir);
    match &cwru {
        Some(c) => println!("data directory: {}", c.display()),
        None => println!(
            "data directory: none found (set --data-dir or HYBRID_FDD_DATA); every file is missing"
        ),
    }
    let entries = selected(&args);
    println!();
    println!("| file | fs (Hz) | class | load (hp) | rpm | samples | channels | status |");
    println!("|---:|---:|---|---:|---:|---:|---|---|");
    let mut tally = Tally::default();
    for e in &entries {
        let status = match &cwru {
            Some(c) => check_file(c, e, !args.no_verify)
                .with_context(|| format!("checking {}", e.number))?,
            None => FileStatus::Missing,
        };
        let mut text = if cwru.is_some() {
            status_text(e, &status)
        } else {
            "missing (no data directory)".into()
        };
        tally.count(&status, e.in_shared_copy);
        let parse_dir = dir.filter(|_| args.parse && status != FileStatus::Missing);
        if let Some(d) = parse_dir {
            match parse_text(d, e) {
                Ok(t) => text.push_str(&t),
                Err(t) => {
                    tally.parse_fail += 1;
                    text.push_str(&t);
                }
            }
        }
        print_row(e, &text);
    }
    print_summary(&entries, &tally, args.parse);
    if tally.mismatched > 0
        || tally.parse_fail > 0
        || (cwru.is_some() && tally.missing_expected > 0)
    {
        anyhow::bail!("data check failed");
    }
    Ok(())
}

/// The catalogue's entries that the flags select, by sampling rate then number.
fn selected(args: &Args) -> Vec<&'static CatalogEntry> {
    let mut q = Query::new();
    if let Some(fs) = args.fs {
        q = q.fs_hz(fs);
    }
    if let Some(d) = args.diameter {
        q = q.diameter_in(d);
    }
    if let Some(l) = args.load {
        q = q.load_hp(l);
    }
    let mut entries: Vec<&CatalogEntry> = catalog().filter(|e| q.matches(e)).collect();
    entries.sort_by_key(|e| (e.fs_hz, e.number));
    entries
}

/// Parse record `e` from `d` and check its sample count against the catalogue: the status
/// column's suffix, as `Err` when the parse failed or the count differs.
fn parse_text(d: &std::path::Path, e: &CatalogEntry) -> Result<String, String> {
    match load_record(
        d,
        e.number,
        &LoadOptions {
            verify: Verify::Skip,
        },
    ) {
        Ok(r) if e.n_samples.is_none_or(|n| n == r.len()) => Ok(", parsed".to_string()),
        Ok(r) => Err(format!(
            ", PARSED {} samples, catalog {:?}",
            r.len(),
            e.n_samples
        )),
        Err(err) => Err(format!(", PARSE ERROR: {err}")),
    }
}

/// One row of the table: the catalogue's fields of `e` and its status `text`.
fn print_row(e: &CatalogEntry, text: &str) {
    let rpm = match e.stored_rpm {
        Some(r) => r.to_string(),
        None => format!("{} (nominal)", e.nominal_rpm),
    };
    let samples = e
        .n_samples
        .map_or_else(|| "?".to_owned(), |n| n.to_string());
    let ch = [
        ("DE", e.channels.de),
        ("FE", e.channels.fe),
        ("BA", e.channels.ba),
    ]
    .iter()
    .filter(|(_, on)| *on)
    .map(|(s, _)| *s)
    .collect::<Vec<_>>()
    .join("+");
    println!(
        "| {} | {} | {} | {} | {} | {} | {} | {} |",
        e.number,
        e.fs_hz,
        e.class_name(),
        e.load_hp,
        rpm,
        samples,
        ch,
        text
    );
}

/// The summary line under the table (the parse failures only with `--parse`).
fn print_summary(entries: &[&CatalogEntry], t: &Tally, parse: bool) {
    let pinned_absent = entries
        .iter()
        .filter(|e| !e.in_shared_copy && e.sha256.is_some())
        .count();
    println!();
    println!(
        "summary: {} catalogued; {} verified, {} present unverified, {} SHA-256 mismatches, {} missing \
         from the shared copy; {} records the shared copy lacks are absent ({} with a pinned SHA-256){}",
        entries.len(),
        t.verified,
        t.present,
        t.mismatched,
        t.missing_expected,
        t.absent,
        pinned_absent,
        if parse {
            format!("; {} parse failures", t.parse_fail)
        } else {
            String::new()
        }
    );
}
