//! The workspace's figures and what they share (the font, label placement, PNG rendering):
//! here the diagnosis report's figure — the residual's squared envelope spectrum in the chosen
//! band, with the BPFO, BPFI, BSF (ball-defect rate), FTF and fr harmonics and the
//! distinguishing sidebands (BPFI ± fr, BSF ± FTF) overlaid and labelled, used by
//! `hybrid-fdd diagnose` and `cargo xtask diagnose` — and in [`close_loop`] the closed loop's.
//! The chapters' figures (`cargo xtask chapterN`) draw through [`font_available`] and
//! [`render_png`] too.

use std::path::Path;

use diagnosis::Diagnosis;
use plotters::prelude::*;

pub mod close_loop;

/// Figure size, pixels.
const W: u32 = 900;
/// Figure height, pixels.
const H: u32 = 480;

/// Register DejaVu Sans with plotters (once) if it exists; `false` means draw without text.
/// Every figure of the workspace (these and `cargo xtask`'s) draws text through this.
pub fn font_available() -> bool {
    static ONCE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ONCE.get_or_init(|| {
        let path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
        match std::fs::read(path) {
            Ok(bytes) => {
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok()
            }
            Err(_) => false,
        }
    })
}

/// Rows for labels placed along a horizontal axis so that no two overlap: `spans` are the
/// labels' (left, width) in pixels; each label, taken from left to right, goes to the first row
/// whose last label ends at least `gap` pixels before it starts, or, when all `rows` are taken
/// there, to the row that frees up first. Returns the row of each span, in input order.
pub fn label_rows(spans: &[(i32, i32)], gap: i32, rows: usize) -> Vec<usize> {
    let rows = rows.max(1);
    let mut order: Vec<usize> = (0..spans.len()).collect();
    order.sort_by_key(|&i| (spans[i].0, i));
    let mut right = vec![i32::MIN / 2; rows];
    let mut out = vec![0; spans.len()];
    for i in order {
        let (left, width) = spans[i];
        let row = (0..rows)
            .find(|&r| right[r] + gap <= left)
            .unwrap_or_else(|| (0..rows).min_by_key(|&r| (right[r], r)).unwrap_or(0));
        right[row] = right[row].max(left + width);
        out[i] = row;
    }
    out
}

/// Where the label of a vertical line at pixel `x` goes: its left edge and whether it is drawn
/// right-aligned, ending at the line. A label `width` pixels wide starts at the line unless it
/// would run past `right`, the plotting area's right edge (a mark near the top of the band:
/// "4 resonance" at 5389 Hz of a 12 kHz record was cut to "4 r"); then it ends at the line,
/// when there is room on that side.
pub fn label_span(x: i32, width: i32, right: i32) -> (i32, bool) {
    if x + width > right && x - width >= 0 {
        (x - width, true)
    } else {
        (x, false)
    }
}

/// Where each label of a set of vertical lines goes: `labels` are the lines' pixel `x` and their
/// label text (`""`: a line without a label). Each label is placed by [`label_span`] (ending at its
/// line near the plot's right edge `right`), then the labelled ones get rows by [`label_rows`]
/// (`gap`, `rows`). Returns, in input order, `(row, right_aligned)` for each labelled line and
/// `None` for an unlabelled one. One placement for every figure (close-loop residual, diagnosis
/// envelope).
pub fn place_labels(
    labels: &[(i32, &str)],
    font: u32,
    right: i32,
    gap: i32,
    rows: usize,
) -> Vec<Option<(usize, bool)>> {
    let placed: Vec<Option<((i32, i32), bool)>> = labels
        .iter()
        .map(|&(x, label)| {
            (!label.is_empty()).then(|| {
                let width = label_width(label, font);
                let (left, right_aligned) = label_span(x, width, right);
                ((left, width), right_aligned)
            })
        })
        .collect();
    let spans: Vec<(i32, i32)> = placed.iter().flatten().map(|p| p.0).collect();
    let mut row = label_rows(&spans, gap, rows).into_iter();
    placed
        .into_iter()
        .map(|p| p.map(|(_, right_aligned)| (row.next().unwrap_or(0), right_aligned)))
        .collect()
}

/// The text style of a label placed by [`label_span`]: anchored at its top left, or at its top
/// right when `right_aligned`.
pub fn label_style(font: u32, color: &RGBAColor, right_aligned: bool) -> TextStyle<'static> {
    let h = if right_aligned {
        plotters::style::text_anchor::HPos::Right
    } else {
        plotters::style::text_anchor::HPos::Left
    };
    ("sans-serif", font)
        .into_font()
        .color(color)
        .pos(plotters::style::text_anchor::Pos::new(
            h,
            plotters::style::text_anchor::VPos::Top,
        ))
}

/// Width in pixels of `label` drawn in a sans-serif font of `size` pixels (an estimate: 0.6 em
/// per character, DejaVu Sans' average advance).
pub fn label_width(label: &str, size: u32) -> i32 {
    (label.chars().count() as f64 * 0.6 * size as f64).ceil() as i32
}

/// A drawing area of a bitmap figure.
pub type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Render a `w` × `h` figure drawn by `draw` into PNG bytes (through a temporary file:
/// plotters' encoder writes to paths). Pixels depend only on what is drawn, so the bytes are
/// deterministic.
///
/// # Errors
/// Drawing, encoding or temporary-file errors.
pub fn render_png(
    w: u32,
    h: u32,
    draw: impl FnOnce(&Area<'_>) -> anyhow::Result<()>,
) -> anyhow::Result<Vec<u8>> {
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!("hybrid-fdd-fig-{}-{n}.png", std::process::id()));
    {
        let root = BitMapBackend::new(&path, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
        draw(&root)?;
        root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    let bytes = std::fs::read(&path)?;
    let _ = std::fs::remove_file(&path);
    Ok(bytes)
}

/// Draw the envelope-spectrum figure of `d` into `path` (PNG).
///
/// # Errors
/// Drawing or file errors.
pub fn envelope_figure(d: &Diagnosis, path: &Path, title: &str) -> anyhow::Result<()> {
    let panels = 1 + d.secondary.len();
    let root = BitMapBackend::new(path, (W, H * panels as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let areas = root.split_evenly((panels, 1));
    let reference = match d.reference {
        diagnosis::Reference::Baseline => "baseline",
        diagnosis::Reference::SelfReference => "self",
    };
    envelope_panel(
        &areas[0],
        d,
        &d.envelope,
        &d.evidence,
        format!(
            "{title}: {} — squared envelope spectrum of the residual, band {:.0}–{:.0} Hz ({reference} reference)",
            d.verdict, d.band.low_hz, d.band.high_hz,
        ),
    )?;
    for (r, area) in d.secondary.iter().zip(&areas[1..]) {
        envelope_panel(
            area,
            d,
            &r.envelope,
            std::slice::from_ref(&r.evidence),
            format!(
                "{title}: {} in a band of its own, {:.0}–{:.0} Hz ({reference} reference)",
                r.hypothesis.name(),
                r.band.low_hz,
                r.band.high_hz,
            ),
        )?;
    }
    Ok(())
}

/// One panel: the squared envelope spectrum `env` (dB over its median) with the kinematic
/// markers of `d`'s operating point and, as dots, the counting lines of `evidence` in that band.
fn envelope_panel(
    root: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    d: &Diagnosis,
    env: &diagnosis::EnvelopeSpectrum,
    evidence: &[diagnosis::HypothesisEvidence],
    caption: String,
) -> anyhow::Result<()> {
    let text = font_available();
    // the markers at the speed the reported fault's lines were read at (over the range, when
    // no comb confirmed the declared speed), else at the speed used
    let op = &d.operating_point;
    let read_at = d.fault_read_at_rpm(evidence).map(|(_, rpm)| rpm);
    let fr = read_at.map_or(op.shaft_hz, |rpm| op.shaft_hz * rpm / op.rpm_used);
    let scaled;
    let (f, caption) = match read_at {
        None => (&op.frequencies_hz, caption),
        Some(rpm) => {
            scaled = op.orders.at(fr);
            (&scaled, format!("{caption}; markers at {rpm:.0} rpm"))
        }
    };
    let top = 3.4 * f.bpfo.max(f.bpfi).max(f.ball_defect) + fr;
    let pts: Vec<(f64, f64)> = env
        .power
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, p)| (k as f64 * env.resolution_hz, *p))
        .take_while(|(x, _)| *x <= top)
        .collect();
    let mut sorted: Vec<f64> = pts.iter().map(|p| p.1).collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted
        .get(sorted.len() / 2)
        .copied()
        .filter(|m| *m > 0.0)
        .unwrap_or(1.0);
    let db: Vec<(f64, f64)> = pts
        .iter()
        .map(|(x, p)| (*x, 10.0 * (p.max(1e-300) / median).log10()))
        .collect();
    let ymax = db.iter().map(|p| p.1).fold(10.0f64, f64::max) + 8.0;
    let ymin = db.iter().map(|p| p.1).fold(0.0f64, f64::min).max(-20.0);

    let mut b = ChartBuilder::on(root);
    b.margin(12);
    if text {
        b.caption(caption, ("sans-serif", 14))
            .x_label_area_size(40)
            .y_label_area_size(55);
    }
    let mut c = b.build_cartesian_2d(0.0..top, ymin..ymax)?;
    let mut mesh = c.configure_mesh();
    mesh.light_line_style(TRANSPARENT);
    if text {
        mesh.x_desc(match &d.order_tracking {
            // an order-tracked record: its "Hz" are orders × the mean shaft rate
            Some(t) => format!(
                "envelope frequency (Hz at the mean speed, {:.0} rpm: order tracked over {:.0}–{:.0} rpm)",
                t.mean_rpm, t.min_rpm, t.max_rpm
            ),
            None => "envelope frequency (Hz)".to_string(),
        })
        .y_desc("power re median (dB)");
    } else {
        mesh.x_labels(0).y_labels(0);
    }
    mesh.draw()?;
    // marker families: (label, frequency, colour, dashed sideband?)
    let blue = RGBColor(31, 119, 180);
    let red = RGBColor(214, 39, 40);
    let green = RGBColor(44, 160, 44);
    let purple = RGBColor(148, 103, 189);
    let gray = RGBColor(150, 150, 150);
    let mut marks: Vec<(String, f64, RGBColor, bool)> = Vec::new();
    for k in 1..=3 {
        let kf = k as f64;
        marks.push((format!("fr×{k}"), kf * fr, gray, false));
        marks.push((format!("BPFO×{k}"), kf * f.bpfo, blue, false));
        marks.push((format!("BPFI×{k}"), kf * f.bpfi, red, false));
        marks.push((format!("BSF×{k}"), kf * f.ball_defect, green, false));
        marks.push((format!("FTF×{k}"), kf * f.ftf, purple, false));
    }
    for s in [-1.0, 1.0] {
        marks.push((String::new(), f.bpfi + s * fr, red, true));
        marks.push((String::new(), f.ball_defect + s * f.ftf, green, true));
    }
    let marks: Vec<_> = marks
        .into_iter()
        .filter(|(_, x, _, _)| *x > 0.0 && *x < top)
        .collect();
    // label rows that keep neighbouring labels apart (FTF×k and fr×k crowd the low end)
    let font = 10;
    let row_px = 12.0;
    let plot_h = f64::from(c.plotting_area().dim_in_pixel().1.max(1));
    let row_step = (ymax - ymin) * row_px / plot_h;
    let right = c.plotting_area().get_pixel_range().0.end;
    let at: Vec<(i32, &str)> = marks
        .iter()
        .map(|(label, x, _, _)| (c.backend_coord(&(*x, ymax)).0, label.as_str()))
        .collect();
    let placed = place_labels(&at, font, right, 3, 6);
    for (i, (label, x, col, side)) in marks.iter().enumerate() {
        let style = if *side {
            col.mix(0.45).stroke_width(1)
        } else {
            col.mix(0.8).stroke_width(1)
        };
        c.draw_series(LineSeries::new(vec![(*x, ymin), (*x, ymax)], style))?;
        if let (true, Some((row, right_aligned))) = (text, placed[i]) {
            let y = ymax - 0.3 * row_step - row_step * row as f64;
            c.draw_series(std::iter::once(Text::new(
                label.clone(),
                (*x, y),
                label_style(font, &col.to_rgba(), right_aligned),
            )))?;
        }
    }
    c.draw_series(LineSeries::new(db, &BLACK))?;
    // found lines of each hypothesis, as dots where they count; a detected hypothesis's last,
    // so a line two families share shows the colour of the one the verdict rests on
    let mut drawn: Vec<&diagnosis::HypothesisEvidence> = evidence.iter().collect();
    drawn.sort_by_key(|e| e.detected);
    for e in drawn {
        let col = match e.hypothesis {
            diagnosis::Hypothesis::Inner => red,
            diagnosis::Hypothesis::Outer => blue,
            diagnosis::Hypothesis::Ball => green,
        };
        if e.band_hz != env.band_hz {
            continue;
        }
        for l in e
            .harmonics
            .iter()
            .chain(&e.sidebands)
            .filter(|l| l.counts())
        {
            let k = (l.found_hz / env.resolution_hz).round() as usize;
            if let Some(p) = env.power.get(k) {
                let y = 10.0 * (p.max(1e-300) / median).log10();
                c.draw_series(std::iter::once(Circle::new(
                    (l.found_hz, y),
                    4,
                    col.filled(),
                )))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{label_rows, label_span, place_labels};

    /// A label that would run past the plot's right edge ends at its line instead; one with room
    /// starts at it; one with room on neither side keeps its start (the plot clips it).
    #[test]
    fn labels_near_the_right_edge_end_at_their_line() {
        assert_eq!(label_span(100, 60, 640), (100, false));
        assert_eq!(label_span(600, 60, 640), (540, true));
        assert_eq!(label_span(580, 60, 640), (580, false));
        assert_eq!(label_span(581, 60, 640), (521, true));
        assert_eq!(label_span(30, 60, 50), (30, false));
    }

    /// Unlabelled lines get no place; overlapping labels get different rows, and the one near
    /// the right edge ends at its line.
    #[test]
    fn place_labels_skips_unlabelled_lines_and_places_the_rest() {
        let at = [
            (100, "BPFO"),
            (104, ""),
            (106, "2xBPFO"),
            (630, "resonance"),
        ];
        let placed = place_labels(&at, 10, 640, 3, 6);
        assert_eq!(placed[1], None);
        let rows: Vec<usize> = [0, 2, 3].iter().map(|&i| placed[i].unwrap().0).collect();
        // the first two overlap (100 + 24 px > 106), so they take different rows
        assert_ne!(rows[0], rows[1]);
        assert!(
            !placed[0].unwrap().1,
            "room on the right: starts at its line"
        );
        assert!(
            placed[3].unwrap().1,
            "630 px + 54 px > 640: ends at its line"
        );
    }

    /// Labels that share a row never overlap while rows remain; crowded labels spread over rows.
    #[test]
    fn label_rows_keep_labels_apart() {
        // FTF×1..3 and fr×1..3 of a 6205 at 1797 rpm: 12, 24, 36 Hz and 30, 60, 90 Hz at ~1.5 px/Hz
        let spans: Vec<(i32, i32)> = [12.0, 24.0, 36.0, 30.0, 60.0, 90.0]
            .iter()
            .map(|f: &f64| ((f * 1.5) as i32 + 60, 36))
            .collect();
        let rows = label_rows(&spans, 3, 6);
        for i in 0..spans.len() {
            for j in 0..i {
                if rows[i] == rows[j] {
                    let (a, b) = if spans[i].0 < spans[j].0 {
                        (spans[i], spans[j])
                    } else {
                        (spans[j], spans[i])
                    };
                    assert!(
                        a.0 + a.1 + 3 <= b.0,
                        "{i} and {j} overlap in row {}",
                        rows[i]
                    );
                }
            }
        }
        assert!(rows.iter().max().unwrap() >= &2, "{rows:?}");
        // far-apart labels stay in the first row
        assert_eq!(
            label_rows(&[(0, 30), (100, 30), (200, 30)], 3, 6),
            vec![0, 0, 0]
        );
        // more labels than rows at one place: still a row each, the one that frees first
        let rows = label_rows(&[(0, 50); 3], 3, 2);
        assert_eq!(rows.len(), 3);
        assert!(rows.iter().all(|r| *r < 2));
    }
}
