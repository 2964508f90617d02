//! Source generation: `src/catalog_table.rs` is rendered from the shared copy's `MANIFEST.csv`.
//! This test regenerates it in memory and fails on a difference (rust-analyzer's sourcegen
//! pattern); `UPDATE_CATALOG=1 cargo test -p bearing-data --test catalog_table` rewrites it.
//! Skips when the data directory is absent (fails under `CI=true`).

mod common;

use std::fmt::Write as _;

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or_else(|| "None".to_owned(), |x| format!("Some({x})"))
}

fn render(manifest: &str) -> String {
    let mut rdr = csv::Reader::from_reader(manifest.as_bytes());
    let headers = rdr.headers().expect("manifest header").clone();
    let col = |name: &str| headers.iter().position(|h| h == name).expect(name);
    let (
        c_file,
        c_rel,
        c_fs,
        c_fault,
        c_diam,
        c_pos,
        c_load,
        c_nom,
        c_rpm,
        c_de,
        c_fe,
        c_ba,
        c_n,
        c_sha,
    ) = (
        col("file"),
        col("rel_path"),
        col("sample_rate_hz"),
        col("fault"),
        col("fault_diameter_in"),
        col("outer_position"),
        col("load_hp"),
        col("nominal_rpm"),
        col("stored_rpm"),
        col("de_var"),
        col("fe_var"),
        col("ba_var"),
        col("n_samples"),
        col("sha256"),
    );
    let mut rows = String::new();
    let mut count = 0;
    for rec in rdr.records() {
        let r = rec.expect("manifest row");
        let number: u32 = r[c_file]
            .trim_end_matches(".mat")
            .parse()
            .expect("file number");
        let variable: u32 = r[c_de]
            .strip_prefix('X')
            .and_then(|s| s.strip_suffix("_DE_time"))
            .expect("de_var")
            .parse()
            .expect("variable number");
        let fault = match &r[c_fault] {
            "normal" => "Normal",
            "inner" => "InnerRace",
            "ball" => "Ball",
            "outer" => "OuterRace",
            other => panic!("unknown fault {other}"),
        };
        let mils = (!r[c_diam].is_empty())
            .then(|| (r[c_diam].parse::<f64>().expect("diameter") * 1000.0).round() as u16);
        let pos = match &r[c_pos] {
            "" => None,
            "centered6" => Some("P::Centered6"),
            "orthogonal3" => Some("P::Orthogonal3"),
            "opposite12" => Some("P::Opposite12"),
            other => panic!("unknown position {other}"),
        };
        let stored = (!r[c_rpm].is_empty()).then(|| r[c_rpm].to_owned());
        let channels = match (!r[c_fe].is_empty(), !r[c_ba].is_empty()) {
            (true, true) => "DE_FE_BA",
            (true, false) => "DE_FE",
            (false, false) => "DE",
            (false, true) => panic!("BA without FE"),
        };
        let n: usize = r[c_n].parse().expect("n_samples");
        let n_sep = {
            let s = n.to_string();
            let mut out = String::new();
            for (i, ch) in s.chars().enumerate() {
                if i > 0 && (s.len() - i) % 3 == 0 {
                    out.push('_');
                }
                out.push(ch);
            }
            out
        };
        let fs: u32 = r[c_fs].parse().expect("fs");
        let fs_sep = format!("{}_{:03}", fs / 1000, fs % 1000);
        writeln!(
            rows,
            "    CatalogEntry {{\n        number: {number},\n        variable: {variable},\n        \
             rel_path: \"{rel}\",\n        fs_hz: {fs_sep},\n        fault: F::{fault},\n        \
             diameter_mils: {mils},\n        outer_position: {pos},\n        load_hp: {load},\n        \
             nominal_rpm: {nom},\n        stored_rpm: {stored},\n        channels: Channels::{channels},\n        \
             n_samples: Some({n_sep}),\n        sha256: Some(\"{sha}\"),\n        in_shared_copy: true,\n    }},",
            rel = &r[c_rel],
            mils = opt(mils),
            pos = opt(pos),
            load = &r[c_load],
            nom = &r[c_nom],
            stored = opt(stored),
            sha = &r[c_sha],
        )
        .expect("write");
        count += 1;
    }
    format!(
        "//! Catalog rows of the records in the shared data copy.\n//!\n\
         //! Generated from `shared/data/cwru/MANIFEST.csv` by `tests/catalog_table.rs`\n\
         //! (`UPDATE_CATALOG=1 cargo test -p bearing-data --test catalog_table`). Do not edit.\n\n\
         use crate::catalog::{{CatalogEntry, Channels, FaultLabel as F, OuterPosition as P}};\n\n\
         /// The records the shared copy holds, in manifest order.\n\
         pub(crate) static PRESENT: [CatalogEntry; {count}] = [\n{rows}];\n"
    )
}

#[test]
fn catalog_table_is_fresh() {
    let Some(data) = common::data_dir() else {
        return;
    };
    let manifest =
        std::fs::read_to_string(data.join("cwru").join("MANIFEST.csv")).expect("MANIFEST.csv");
    let want = render(&manifest);
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src")
        .join("catalog_table.rs");
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    if have != want {
        if std::env::var_os("UPDATE_CATALOG").is_some() {
            std::fs::write(&path, want).expect("write catalog_table.rs");
            eprintln!("updated {}", path.display());
        } else {
            panic!(
                "{} is stale; run UPDATE_CATALOG=1 cargo test -p bearing-data --test catalog_table",
                path.display()
            );
        }
    }
}
