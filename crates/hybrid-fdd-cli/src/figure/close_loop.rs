//! The closed loop's figure: the held-out PSD (measured, model before, model after) and the
//! residual log ratio before and after, effects marked (`hybrid-fdd close-loop`, `calibrate`).

use std::path::Path;

use close_loop::Outcome;

use super::font_available;

/// The PSD axis's label in the recording's unit: `PSD (dB re 1 g²/Hz)`,
/// `PSD (dB re 1 (m/s²)²/Hz)`, `PSD (dB re 1 (file units)²/Hz)`.
fn psd_axis_label(unit: &str) -> String {
    if unit == "g" {
        "PSD (dB re 1 g²/Hz)".to_string()
    } else {
        format!("PSD (dB re 1 ({unit})²/Hz)")
    }
}

/// Two panels: held-out PSD (measured, model before, model after) and the residual log ratio
/// 10·log10(S_y/S_m) before and after, effects marked by vertical lines.
pub fn figure(out: &Outcome, path: &Path, title: &str) -> anyhow::Result<()> {
    use plotters::prelude::*;
    let text = font_available();
    let s = &out.spectra;
    let l = &out.ledger;
    let (f_lo, f_hi) = (l.protocol.band_hz[0], l.protocol.band_hz[1]);
    let idx: Vec<usize> = (0..s.frequency_hz.len())
        .filter(|&k| s.frequency_hz[k] >= f_lo && s.frequency_hz[k] <= f_hi)
        .collect();
    let db = |v: f64| 10.0 * v.max(1e-300).log10();
    let series = |v: &[f64]| -> Vec<(f64, f64)> {
        decimate(idx.iter().map(|&k| (s.frequency_hz[k], db(v[k]))).collect())
    };
    let meas = series(&s.measured);
    let before = series(&s.model_before);
    let after = series(&s.model_after);
    let ratio = |m: &[f64]| -> Vec<(f64, f64)> {
        decimate(
            idx.iter()
                .map(|&k| (s.frequency_hz[k], db(s.measured[k]) - db(m[k])))
                .collect(),
        )
    };
    let rb = ratio(&s.model_before);
    let ra = ratio(&s.model_after);
    let (mut ymin, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY);
    for &(_, v) in meas.iter().chain(&before).chain(&after) {
        ymin = ymin.min(v);
        ymax = ymax.max(v);
    }
    let ymin = ymin.max(ymax - 120.0);
    let rmax = rb
        .iter()
        .chain(&ra)
        .map(|p| p.1.abs())
        .fold(3.0f64, f64::max)
        .min(60.0);

    let root = BitMapBackend::new(path, (FIG_W, FIG_H)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(FIG_H / 2);
    let mut c1 = chart(
        &top,
        text,
        (f_lo, f_hi),
        &format!(
            "{title}: held-out PSD, measured vs model (LSD {:.2} -> {:.2} dB)",
            l.error_before, l.error_after
        ),
        ymin,
        ymax + 3.0,
        &psd_axis_label(l.unit.label()),
    )?;
    let gray = RGBColor(120, 120, 120);
    c1.draw_series(LineSeries::new(meas, &gray))?
        .label("measured")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], gray));
    c1.draw_series(LineSeries::new(before, &BLUE))?
        .label("declared model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    c1.draw_series(LineSeries::new(after, &RED))?
        .label("augmented model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    if text {
        c1.configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
    }
    let mut c2 = chart(
        &bottom,
        text,
        (f_lo, f_hi),
        "residual spectrum 10·log10(S_measured / S_model): before (blue), after (red)",
        -rmax,
        rmax,
        "dB",
    )?;
    c2.draw_series(LineSeries::new(rb, &BLUE.mix(0.6)))?;
    c2.draw_series(LineSeries::new(ra, &RED))?;
    c2.draw_series(LineSeries::new(vec![(f_lo, 0.0), (f_hi, 0.0)], &BLACK))?;
    let font = 11;
    let marked: Vec<(usize, f64, String)> = l
        .effects
        .iter()
        .enumerate()
        .filter_map(|(i, e)| {
            e.frequency_hz
                .map(|f| (i, f, format!("{} {}", i + 1, e.kind.as_str())))
        })
        .collect();
    let right = c2.plotting_area().get_pixel_range().0.end;
    let at: Vec<(i32, &str)> = marked
        .iter()
        .map(|(_, f, label)| (c2.backend_coord(&(*f, rmax)).0, label.as_str()))
        .collect();
    let placed = crate::figure::place_labels(&at, font, right, 3, 8);
    let plot_h = f64::from(c2.plotting_area().dim_in_pixel().1.max(1));
    let row_step = 2.0 * rmax * 13.0 / plot_h;
    for ((i, f, label), p) in marked.into_iter().zip(placed) {
        let (row, right_aligned) = p.unwrap_or((0, false));
        let col = Palette99::pick(i + 2).to_rgba();
        c2.draw_series(LineSeries::new(
            vec![(f, -rmax), (f, rmax)],
            col.stroke_width(2),
        ))?;
        if text {
            c2.draw_series(std::iter::once(Text::new(
                label,
                (f, rmax - 0.2 * row_step - row_step * row as f64),
                crate::figure::label_style(font, &col, right_aligned),
            )))?;
        }
    }
    root.present()?;
    Ok(())
}

/// Figure size, pixels (keeps each PNG well under 150 kB).
const FIG_W: u32 = 660;
/// Figure height, pixels.
const FIG_H: u32 = 420;
/// Points per drawn curve: one (max, min) pair per bucket, about one bucket per 4 pixels.
const FIG_BUCKETS: usize = 150;

/// Min–max decimation for drawing: split the curve into [`FIG_BUCKETS`] runs of bins and keep
/// each run's largest and smallest value (in frequency order), so lines stay visible.
fn decimate(v: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if v.len() <= 2 * FIG_BUCKETS {
        return v;
    }
    let per = v.len().div_ceil(FIG_BUCKETS);
    let mut out = Vec::with_capacity(2 * FIG_BUCKETS);
    for run in v.chunks(per) {
        let hi = run
            .iter()
            .copied()
            .fold(run[0], |a, b| if b.1 > a.1 { b } else { a });
        let lo = run
            .iter()
            .copied()
            .fold(run[0], |a, b| if b.1 < a.1 { b } else { a });
        if hi.0 <= lo.0 {
            out.extend([hi, lo]);
        } else {
            out.extend([lo, hi]);
        }
    }
    out
}

type Chart<'a, 'b> = plotters::prelude::ChartContext<
    'a,
    plotters::prelude::BitMapBackend<'b>,
    plotters::prelude::Cartesian2d<
        plotters::coord::types::RangedCoordf64,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// One panel with a mesh; without a font, no caption, labels or axis text.
fn chart<'a, 'b>(
    area: &'a plotters::prelude::DrawingArea<
        plotters::prelude::BitMapBackend<'b>,
        plotters::coord::Shift,
    >,
    text: bool,
    x: (f64, f64),
    cap: &str,
    y0: f64,
    y1: f64,
    ylab: &str,
) -> anyhow::Result<Chart<'a, 'b>> {
    use plotters::prelude::*;
    let mut b = ChartBuilder::on(area);
    b.margin(12);
    if text {
        b.caption(cap, ("sans-serif", 13))
            .x_label_area_size(40)
            .y_label_area_size(60);
    }
    let mut c = b.build_cartesian_2d(x.0..x.1, y0..y1)?;
    let mut m = c.configure_mesh();
    // no minor grid: it costs PNG size and no information
    m.light_line_style(TRANSPARENT);
    if text {
        m.x_desc("frequency (Hz)").y_desc(ylab);
    } else {
        m.x_labels(0).y_labels(0);
    }
    m.draw()?;
    Ok(c)
}
