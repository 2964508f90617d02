//! PNG figures with plotters: residual traces per class (Figs 2.5, 3.3, 4.9, 4.10, 5.4–5.6),
//! window energies per class (Fig. 5.7), confusion matrices, the decision tree (Fig. 5.8).
//!
//! Text and PNG encoding as every figure of the workspace: `hybrid_fdd_cli::figure`
//! (DejaVu Sans when present, figures without text otherwise; deterministic bytes).

use super::inputs::{Cache, RecKey};
use super::report::{Cell, OurTable, class_label};
use ::pipeline::Protocol;
use ::pipeline::dissertation::{Condition, DissTable};
use ::pipeline::{Method, TreeDraw};
use plotters::prelude::*;
use std::collections::BTreeMap;

const FONT: &str = "sans-serif";

use hybrid_fdd_cli::figure::{Area, font_available as has_font, render_png as render};

fn e<E: std::fmt::Display>(err: E) -> anyhow::Error {
    anyhow::anyhow!("plotting: {err}")
}

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Stacked residual traces, one panel per (label, samples).
fn traces(title: &str, rows: &[(String, Vec<f64>)], fs: f64) -> anyhow::Result<Vec<u8>> {
    let text = has_font();
    let h = 140 * rows.len() as u32 + 60;
    render(900, h, |root| {
        let body = if text {
            root.titled(title, (FONT, 20)).map_err(e)?
        } else {
            root.clone()
        };
        let panels = body.split_evenly((rows.len(), 1));
        for (i, ((label, y), area)) in rows.iter().zip(panels.iter()).enumerate() {
            let amp = y.iter().fold(1e-12f64, |a, v| a.max(v.abs()));
            let t_end = y.len() as f64 / fs;
            let mut b = ChartBuilder::on(area);
            b.margin(6)
                .x_label_area_size(if text { 28 } else { 0 })
                .y_label_area_size(if text { 60 } else { 0 });
            if text {
                b.caption(label, (FONT, 15));
            }
            let mut chart = b
                .build_cartesian_2d(0.0..t_end, -amp * 1.05..amp * 1.05)
                .map_err(e)?;
            let mut mesh = chart.configure_mesh();
            mesh.disable_mesh();
            if text {
                mesh.x_desc("time (s)")
                    .y_desc("residual (g)")
                    .label_style((FONT, 11))
                    .x_labels(6)
                    .y_labels(7);
            } else {
                mesh.x_labels(0).y_labels(0);
            }
            mesh.draw().map_err(e)?;
            chart
                .draw_series(LineSeries::new(
                    y.iter().enumerate().map(|(k, v)| (k as f64 / fs, *v)),
                    COLORS[i % COLORS.len()].stroke_width(1),
                ))
                .map_err(e)?;
        }
        Ok(())
    })
}

/// Window energies per class against window index, log scale (Fig. 5.7).
fn energies(title: &str, series: &[(String, Vec<f64>)]) -> anyhow::Result<Vec<u8>> {
    let text = has_font();
    let n = series
        .iter()
        .map(|(_, v)| v.len())
        .max()
        .unwrap_or(1)
        .max(1);
    let lo = series
        .iter()
        .flat_map(|(_, v)| v.iter())
        .fold(f64::INFINITY, |a, &v| a.min(v))
        .max(1e-12);
    let hi = series
        .iter()
        .flat_map(|(_, v)| v.iter())
        .fold(0.0f64, |a, &v| a.max(v))
        .max(lo * 10.0);
    render(900, 520, |root| {
        let mut b = ChartBuilder::on(root);
        b.margin(10)
            .x_label_area_size(if text { 35 } else { 0 })
            .y_label_area_size(if text { 70 } else { 0 });
        if text {
            b.caption(title, (FONT, 18));
        }
        let mut chart = b
            .build_cartesian_2d(0..n, (lo * 0.8..hi * 1.25).log_scale())
            .map_err(e)?;
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc("window")
                .y_desc("energy Σr² (g²)")
                .label_style((FONT, 12));
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw().map_err(e)?;
        for (i, (label, v)) in series.iter().enumerate() {
            let c = COLORS[i % COLORS.len()];
            let s = chart
                .draw_series(
                    v.iter()
                        .enumerate()
                        .map(|(k, &y)| Circle::new((k, y.max(lo)), 2, c.filled())),
                )
                .map_err(e)?;
            if text {
                s.label(label.clone())
                    .legend(move |(x, y)| Circle::new((x, y), 4, c.filled()));
            }
        }
        if text {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .label_font((FONT, 13))
                .draw()
                .map_err(e)?;
        }
        Ok(())
    })
}

/// Confusion matrices side by side (rows: true class, columns: predicted).
fn confusions(
    title: &str,
    mats: &[(String, Vec<Vec<u64>>)],
    labels: &[String],
) -> anyhow::Result<Vec<u8>> {
    let text = has_font();
    let k = labels.len().max(1);
    let cell = if k > 4 { 44 } else { 64 };
    let pw = (cell * k + 130) as u32;
    let w = pw * mats.len() as u32 + 20;
    let h = (cell * k + 170) as u32;
    render(w, h, |root| {
        let body = if text {
            root.titled(title, (FONT, 18)).map_err(e)?
        } else {
            root.clone()
        };
        let panels = body.split_evenly((1, mats.len().max(1)));
        for ((sub, m), area) in mats.iter().zip(panels.iter()) {
            let x0 = 110i32;
            let y0 = 40i32;
            if text {
                area.draw(&Text::new(sub.clone(), (x0, 8), (FONT, 14)))
                    .map_err(e)?;
            }
            for (i, row) in m.iter().enumerate() {
                let tot: u64 = row.iter().sum::<u64>().max(1);
                for (j, &v) in row.iter().enumerate() {
                    let f = v as f64 / tot as f64;
                    let shade = (255.0 * (1.0 - f)) as u8;
                    let color = if i == j {
                        RGBColor(shade, 255, shade)
                    } else {
                        RGBColor(255, shade, shade)
                    };
                    let (x, y) = (x0 + (j * cell) as i32, y0 + (i * cell) as i32);
                    area.draw(&Rectangle::new(
                        [(x, y), (x + cell as i32, y + cell as i32)],
                        color.filled(),
                    ))
                    .map_err(e)?;
                    area.draw(&Rectangle::new(
                        [(x, y), (x + cell as i32, y + cell as i32)],
                        BLACK,
                    ))
                    .map_err(e)?;
                    if text {
                        area.draw(&Text::new(
                            format!("{v}"),
                            (x + 6, y + cell as i32 / 2 - 6),
                            (FONT, 12),
                        ))
                        .map_err(e)?;
                    }
                }
                if text {
                    area.draw(&Text::new(
                        labels.get(i).cloned().unwrap_or_default(),
                        (4, y0 + (i * cell) as i32 + cell as i32 / 2 - 6),
                        (FONT, 12),
                    ))
                    .map_err(e)?;
                }
            }
            if text {
                for (j, l) in labels.iter().enumerate() {
                    let style =
                        TextStyle::from((FONT, 11).into_font()).transform(FontTransform::Rotate90);
                    area.draw(&Text::new(
                        l.clone(),
                        (
                            x0 + (j * cell) as i32 + cell as i32 / 2 + 4,
                            y0 + (k * cell) as i32 + 6,
                        ),
                        style,
                    ))
                    .map_err(e)?;
                }
            }
        }
        Ok(())
    })
}

/// The decision tree as boxes and arrows (Fig. 5.8).
pub fn decision_tree(tree: &TreeDraw, labels: &[String]) -> anyhow::Result<Vec<u8>> {
    fn depth(t: &TreeDraw) -> usize {
        match t {
            TreeDraw::Leaf { .. } => 1,
            TreeDraw::Split { left, right, .. } => 1 + depth(left).max(depth(right)),
        }
    }
    fn leaves(t: &TreeDraw) -> usize {
        match t {
            TreeDraw::Leaf { .. } => 1,
            TreeDraw::Split { left, right, .. } => leaves(left) + leaves(right),
        }
    }
    let text = has_font();
    let d = depth(tree);
    let nl = leaves(tree).max(1);
    let w = (nl as u32 * 170).max(500);
    let h = d as u32 * 110 + 40;
    render(w, h, |root| {
        // Assign x by in-order leaf index.
        fn draw(
            area: &Area<'_>,
            t: &TreeDraw,
            level: usize,
            next_leaf: &mut usize,
            labels: &[String],
            text: bool,
            leaf_w: f64,
        ) -> anyhow::Result<(i32, i32)> {
            let y = 20 + level as i32 * 110;
            match t {
                TreeDraw::Leaf { class } => {
                    let x = ((*next_leaf as f64 + 0.5) * leaf_w) as i32;
                    *next_leaf += 1;
                    let c = COLORS[*class % COLORS.len()];
                    area.draw(&Rectangle::new(
                        [(x - 70, y), (x + 70, y + 40)],
                        c.mix(0.35).filled(),
                    ))
                    .map_err(e)?;
                    area.draw(&Rectangle::new([(x - 70, y), (x + 70, y + 40)], BLACK))
                        .map_err(e)?;
                    if text {
                        area.draw(&Text::new(
                            labels.get(*class).cloned().unwrap_or_default(),
                            (x - 60, y + 12),
                            (FONT, 15),
                        ))
                        .map_err(e)?;
                    }
                    Ok((x, y))
                }
                TreeDraw::Split {
                    threshold,
                    left,
                    right,
                } => {
                    let (xl, yl) = draw(area, left, level + 1, next_leaf, labels, text, leaf_w)?;
                    let (xr, yr) = draw(area, right, level + 1, next_leaf, labels, text, leaf_w)?;
                    let x = (xl + xr) / 2;
                    area.draw(&PathElement::new(vec![(x, y + 40), (xl, yl)], BLACK))
                        .map_err(e)?;
                    area.draw(&PathElement::new(vec![(x, y + 40), (xr, yr)], BLACK))
                        .map_err(e)?;
                    area.draw(&Rectangle::new(
                        [(x - 80, y), (x + 80, y + 40)],
                        WHITE.filled(),
                    ))
                    .map_err(e)?;
                    area.draw(&Rectangle::new([(x - 80, y), (x + 80, y + 40)], BLACK))
                        .map_err(e)?;
                    if text {
                        area.draw(&Text::new(
                            format!("E ≤ {}", sig(*threshold)),
                            (x - 72, y + 12),
                            (FONT, 14),
                        ))
                        .map_err(e)?;
                        area.draw(&Text::new("yes", ((x + xl) / 2 - 30, y + 60), (FONT, 12)))
                            .map_err(e)?;
                        area.draw(&Text::new("no", ((x + xr) / 2 + 8, y + 60), (FONT, 12)))
                            .map_err(e)?;
                    }
                    Ok((x, y))
                }
            }
        }
        let mut next = 0;
        draw(root, tree, 0, &mut next, labels, text, w as f64 / nl as f64)?;
        Ok(())
    })
}

/// Four significant digits.
pub fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let dec = (3 - mag).max(0) as usize;
        format!("{v:.dec$}")
    } else {
        format!("{v:.3e}")
    }
}

/// All figures of a chapter: the residuals and energies of the first CWRU fixed-load table, of
/// the simulated multi-fault substitute, and a confusion figure per table.
#[allow(clippy::too_many_arguments)]
pub fn chapter_figures(
    ch: u8,
    cache: &Cache,
    diss: &[&DissTable],
    tabs: &[OurTable],
    feats: &Series,
    traces_map: &Series,
    methods: &[Method],
) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    if let Some(d) = diss
        .iter()
        .find(|d| matches!(d.condition, Condition::FixedLoad { .. }))
    {
        out.extend(cwru_figures(ch, cache, d, feats, traces_map, methods)?);
    }
    if let Some(d) = diss
        .iter()
        .find(|d| matches!(d.condition, Condition::FixedSpeed { .. }))
    {
        out.extend(multi_fault_figures(ch, d, feats, traces_map, methods)?);
    }
    out.extend(confusion_figures(diss, tabs)?);
    Ok(out)
}

/// Per-method, per-recording series (residual traces or window energies).
type Series = BTreeMap<(String, RecKey), Vec<f64>>;

/// The first 1200 samples (0.1 s at 12 kHz) of the residual trace of each class of `d` under
/// each of `methods` (class `c`'s recording `key(c)`), labelled `label(method, c, key(c))`.
fn residual_rows(
    d: &DissTable,
    methods: &[Method],
    traces_map: &Series,
    key: impl Fn(&str) -> RecKey,
    label: impl Fn(&Method, &str, RecKey) -> anyhow::Result<String>,
) -> anyhow::Result<Vec<(String, Vec<f64>)>> {
    let mut rows = Vec::new();
    for m in methods {
        for c in &d.classes {
            let k = key(c);
            if let Some(tr) = traces_map.get(&(m.name().to_string(), k)) {
                let n = tr.len().min(1200);
                rows.push((label(m, c, k)?, tr[..n].to_vec()));
            }
        }
    }
    Ok(rows)
}

/// The figure `title` of `method`'s residual window energies for each class of `d` (class
/// `c`'s recording `key(c)`).
fn energies_figure(
    d: &DissTable,
    method: Method,
    feats: &Series,
    key: impl Fn(&str) -> RecKey,
    title: &str,
) -> anyhow::Result<Vec<u8>> {
    let series: Vec<(String, Vec<f64>)> = d
        .classes
        .iter()
        .filter_map(|c| {
            feats
                .get(&(method.name().to_string(), key(c)))
                .map(|v| (class_label(c), v.clone()))
        })
        .collect();
    energies(title, &series)
}

/// Residual traces and energies on the CWRU fixed-load table `d`, largest crack: every method's
/// residuals in chapter 5, the first method's elsewhere; the first method's energies.
fn cwru_figures(
    ch: u8,
    cache: &Cache,
    d: &DissTable,
    feats: &Series,
    traces_map: &Series,
    methods: &[Method],
) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    let fig_residual = match ch {
        2 => "fig2_5",
        3 => "fig3_3",
        4 => "fig4_9",
        _ => "fig5_4_to_5_6",
    };
    let load = match d.condition {
        Condition::FixedLoad { load_hp } => load_hp,
        _ => 0,
    };
    let ci = d.cracks.len() - 1;
    let shown: Vec<Method> = if ch == 5 {
        methods.to_vec()
    } else {
        vec![methods[0]]
    };
    let key = |c: &str| super::inputs::cwru_key(c, load, ci);
    let rows = residual_rows(d, &shown, traces_map, key, |m, c, k| {
        Ok(format!(
            "{} residual, {} ({})",
            m.name(),
            class_label(c),
            cache.get(&k)?.id
        ))
    })?;
    out.push((
        format!("figures/{fig_residual}_residuals_cwru.png"),
        traces(
            &format!(
                "Residuals, CWRU {load} hp, {} in (first 0.1 s)",
                d.cracks[ci]
            ),
            &rows,
            super::inputs::CWRU_FS,
        )?,
    ));
    let name = if ch == 5 {
        "fig5_7_energies_cwru.png".to_string()
    } else {
        format!("energies_ch{ch}_cwru.png")
    };
    out.push((
        format!("figures/{name}"),
        energies_figure(
            d,
            methods[0],
            feats,
            key,
            &format!(
                "{} residual window energies, CWRU {load} hp, {} in",
                methods[0].name(),
                d.cracks[ci]
            ),
        )?,
    ));
    Ok(out)
}

/// The multi-fault substitute's table `d` (simulated), largest crack: the first method's residual
/// traces (Fig. 4.10) and window energies.
fn multi_fault_figures(
    ch: u8,
    d: &DissTable,
    feats: &Series,
    traces_map: &Series,
    methods: &[Method],
) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    let rpm = match d.condition {
        Condition::FixedSpeed { rpm } => rpm,
        _ => 0,
    };
    let ci = d.cracks.len() - 1;
    let key = |c: &str| super::inputs::multi_key(c, rpm, ci);
    let rows = residual_rows(d, &methods[..1], traces_map, key, |m, c, _| {
        Ok(format!(
            "{} residual, {} (simulated)",
            m.name(),
            class_label(c)
        ))
    })?;
    let fname = if ch == 4 {
        "fig4_10_residuals_multi_simulated.png"
    } else {
        "residuals_multi_simulated.png"
    };
    out.push((
        format!("figures/{fname}"),
        traces(
            &format!(
                "Residuals, SIMULATED multi-fault substitute, {rpm} rpm, {} mm",
                d.cracks[ci]
            ),
            &rows,
            super::inputs::MULTI_FS,
        )?,
    ));
    out.push((
        "figures/energies_multi_simulated.png".to_string(),
        energies_figure(
            d,
            methods[0],
            feats,
            key,
            &format!(
                "{} window energies, SIMULATED substitute {rpm} rpm, {} mm",
                methods[0].name(),
                d.cracks[ci]
            ),
        )?,
    ));
    Ok(out)
}

/// Confusion matrices of the proposed method under the dissertation's protocol (random windows),
/// one figure per table, one matrix per crack size.
fn confusion_figures(
    diss: &[&DissTable],
    tabs: &[OurTable],
) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    for d in diss {
        let Some(t) = tabs
            .iter()
            .find(|t| t.table == d.id && t.protocol == Protocol::RandomWindows)
        else {
            continue;
        };
        let Some(s) = t.sources.first() else { continue };
        let mats: Vec<(String, Vec<Vec<u64>>)> = s
            .cells
            .iter()
            .enumerate()
            .filter_map(|(ci, c)| match c {
                Cell::Measured(o) => Some((
                    format!("{} {}", d.cracks[ci], d.crack_unit),
                    o.confusion.clone(),
                )),
                Cell::NotApplicable(_) => None,
            })
            .collect();
        let labels: Vec<String> = d.class_labels();
        out.push((
            format!("figures/confusion_table_{}.png", d.id.replace('.', "_")),
            confusions(
                &format!(
                    "Table {}: {} confusion (random split, summed over seeds)",
                    d.id, s.source
                ),
                &mats,
                &labels,
            )?,
        ));
    }
    Ok(out)
}

/// One spectrum panel: title, frequency grid (Hz), labelled curves (PSD values).
pub type SpectrumPanel = (String, Vec<f64>, Vec<(String, Vec<f64>)>);

/// Power spectra in dB, one panel per (title, frequency grid, curves), the curves overlaid
/// (measured against simulated: `cargo xtask calibrate-rig`).
pub fn spectra(title: &str, panels: &[SpectrumPanel]) -> anyhow::Result<Vec<u8>> {
    let text = has_font();
    let cols = 2usize;
    let rows = panels.len().div_ceil(cols).max(1);
    render(1100, 230 * rows as u32 + 50, |root| {
        let body = if text {
            root.titled(title, (FONT, 20)).map_err(e)?
        } else {
            root.clone()
        };
        let areas = body.split_evenly((rows, cols));
        for ((name, f, curves), area) in panels.iter().zip(areas.iter()) {
            let db: Vec<Vec<f64>> = curves
                .iter()
                .map(|(_, p)| p.iter().map(|v| 10.0 * v.max(1e-30).log10()).collect())
                .collect();
            let (lo, hi) = db
                .iter()
                .flatten()
                .skip(1)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(*v), b.max(*v))
                });
            let f_max = f.last().copied().unwrap_or(1.0);
            let mut b = ChartBuilder::on(area);
            b.margin(6)
                .x_label_area_size(if text { 28 } else { 0 })
                .y_label_area_size(if text { 50 } else { 0 });
            if text {
                b.caption(name, (FONT, 14));
            }
            let mut chart = b
                .build_cartesian_2d(0.0..f_max, (lo - 3.0).max(hi - 90.0)..hi + 3.0)
                .map_err(e)?;
            let mut mesh = chart.configure_mesh();
            mesh.disable_mesh();
            if text {
                mesh.x_desc("frequency (Hz)")
                    .y_desc("dB (units²/Hz)")
                    .label_style((FONT, 11))
                    .x_labels(7)
                    .y_labels(5);
            } else {
                mesh.x_labels(0).y_labels(0);
            }
            mesh.draw().map_err(e)?;
            for (i, ((label, _), d)) in curves.iter().zip(&db).enumerate() {
                let s = chart
                    .draw_series(LineSeries::new(
                        f.iter().zip(d).skip(1).map(|(a, b)| (*a, *b)),
                        COLORS[i % COLORS.len()].stroke_width(1),
                    ))
                    .map_err(e)?;
                if text {
                    let c = COLORS[i % COLORS.len()];
                    s.label(label.as_str()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                    });
                }
            }
            if text {
                chart
                    .configure_series_labels()
                    .label_font((FONT, 11))
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()
                    .map_err(e)?;
            }
        }
        Ok(())
    })
}
