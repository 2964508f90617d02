//! `hybrid-fdd bearings`: the built-in bearing catalogue (`bearing_model::catalog`) as a table,
//! every row with its geometry, its fault orders and the source of its geometry; or the one row
//! a designation names, as `--bearing` reads it.

/// Flags of `hybrid-fdd bearings`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Args {
    /// Show only the bearing this designation names, read as `--bearing` reads it
    /// (case-insensitive, a maker's name and seal or clearance suffixes ignored: `skf 6205-2rs`,
    /// `ucp204`); an unknown one is an error naming the nearest rows.
    pub designation: Option<String>,
}

/// The table of `rows`: designation, type, n, d and D in mm, contact angle, BPFO, BPFI, FTF and
/// the ball-defect rate (× shaft frequency), the name and aliases it is also found by, source.
pub fn table<'a>(rows: impl IntoIterator<Item = &'a bearing_model::CatalogEntry>) -> String {
    let header = [
        "designation",
        "type",
        "n",
        "d (mm)",
        "D (mm)",
        "angle",
        "BPFO",
        "BPFI",
        "FTF",
        "BSF",
        "also",
        "source",
    ];
    let mut cells: Vec<Vec<String>> = vec![header.iter().map(|h| h.to_string()).collect()];
    for e in rows {
        let o = e.orders();
        let also: Vec<&str> = std::iter::once(e.name)
            .filter(|n| *n != e.designation)
            .chain(e.aliases.iter().copied())
            .collect();
        cells.push(vec![
            e.designation.to_string(),
            e.kind.label().to_string(),
            e.n_elements.to_string(),
            format!("{:.3}", e.element_diameter.mm()),
            format!("{:.3}", e.pitch_diameter.mm()),
            format!("{}°", e.contact_angle_deg),
            format!("{:.4}", o.bpfo),
            format!("{:.4}", o.bpfi),
            format!("{:.4}", o.ftf),
            format!("{:.4}", o.ball_defect),
            if also.is_empty() {
                "-".to_string()
            } else {
                also.join(", ")
            },
            e.source.to_string(),
        ]);
    }
    let last = header.len() - 1;
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            cells
                .iter()
                .map(|r| r[c].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for row in &cells {
        let mut line = String::new();
        for (c, cell) in row.iter().enumerate() {
            if c == last {
                line.push_str(cell);
                continue;
            }
            let pad = widths[c] - cell.chars().count();
            // numbers right-aligned, words left-aligned
            if (2..10).contains(&c) {
                line.push_str(&" ".repeat(pad));
                line.push_str(cell);
            } else {
                line.push_str(cell);
                line.push_str(&" ".repeat(pad));
            }
            line.push_str("  ");
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

/// What the table's columns mean, printed above it.
pub const LEGEND: &str = "\
Built-in bearing catalogue. n: rolling elements (of one row); d: element diameter; D: pitch
diameter; BPFO, BPFI, FTF, BSF: multiples of the shaft frequency with the contact angle taken in
(r = d/D cos(angle)); BSF is the ball-defect rate, 2 x the ball spin (CWRU's convention).
--bearing takes a designation or an alias in any case, with a maker's name in front (SKF 6205)
and seal, shield or clearance suffixes (6205-2RS, 6206ZZ/C3) ignored. Rows marked \"typical, not
manufacturer-specific\" differ between makers by a few per cent: give n=...,d=...,D=... when the
bearing's own geometry is known.";

/// Print the catalogue (or the row `args.designation` names).
///
/// # Errors
/// An unknown designation ([`bearing_model::ModelError::UnknownBearing`], naming the nearest
/// rows).
pub fn run(args: &Args) -> anyhow::Result<()> {
    match &args.designation {
        Some(d) => {
            let e = bearing_model::catalog::lookup(d)?;
            crate::say!("{}", table([e]).trim_end());
        }
        None => {
            crate::say!("{LEGEND}\n");
            crate::say!("{}", table(bearing_model::catalog::entries()).trim_end());
        }
    }
    Ok(())
}
