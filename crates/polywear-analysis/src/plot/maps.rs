//! Heatmaps with colour bars (risk maps) and probability curves with interval bands.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{format_tick, tick_labels_for, PlotError, PALETTE};

/// A colour scale from a value in [0, 1].
pub(crate) type ColorMap = fn(f64) -> RGBColor;

fn lerp_anchors(anchors: &[(f64, (u8, u8, u8))], t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0);
    for w in anchors.windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if t <= t1 {
            let f = (t - t0) / (t1 - t0);
            let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
            return RGBColor(mix(c0.0, c1.0), mix(c0.1, c1.1), mix(c0.2, c1.2));
        }
    }
    let c = anchors.last().unwrap().1;
    RGBColor(c.0, c.1, c.2)
}

/// Viridis (perceptually uniform, colour-blind safe), for probabilities.
pub(crate) fn viridis(t: f64) -> RGBColor {
    lerp_anchors(
        &[
            (0.0, (68, 1, 84)),
            (0.25, (59, 82, 139)),
            (0.5, (33, 145, 140)),
            (0.75, (94, 201, 98)),
            (1.0, (253, 231, 37)),
        ],
        t,
    )
}

/// Blue–white–red, for differences centred on zero.
pub(crate) fn diverging(t: f64) -> RGBColor {
    lerp_anchors(
        &[
            (0.0, (33, 102, 172)),
            (0.5, (247, 247, 247)),
            (1.0, (178, 24, 43)),
        ],
        t,
    )
}

/// Colour of cells with too few samples.
pub(crate) const EMPTY: RGBColor = RGBColor(200, 200, 200);

/// One heatmap: `values[ix][iy]` over cells with edges `x_edges` × `y_edges` (NaN: too few
/// samples, drawn grey), values mapped from [vmin, vmax] by `cmap`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn heatmap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    x_edges: &[f64],
    y_edges: &[f64],
    values: &[Vec<f64>],
    (vmin, vmax): (f64, f64),
    cmap: ColorMap,
    overlay: &[Overlay],
) -> Result<(), PlotError> {
    let (x0, x1) = (x_edges[0], *x_edges.last().unwrap());
    let (y0, y1) = (y_edges[0], *y_edges.last().unwrap());
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 22))
        .margin(10)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(PlotError::from)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(tick_labels_for(area, 78, 10, (x0, x1), 16))
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(PlotError::from)?;
    let mut rects = Vec::new();
    for (ix, col) in values.iter().enumerate() {
        for (iy, v) in col.iter().enumerate() {
            let color = if v.is_finite() {
                cmap((v - vmin) / (vmax - vmin))
            } else {
                EMPTY
            };
            rects.push(Rectangle::new(
                [
                    (x_edges[ix], y_edges[iy]),
                    (x_edges[ix + 1], y_edges[iy + 1]),
                ],
                color.filled(),
            ));
        }
    }
    chart.draw_series(rects).map_err(PlotError::from)?;
    // The value in each cell, when the cells are few and large enough to hold it.
    let cells = values.len() * values.first().map_or(0, Vec::len);
    if cells > 0 && cells <= MAX_CELLS_WITH_NUMBERS {
        let texts = cell_texts(x_edges, y_edges, values, (vmin, vmax), cmap);
        chart.draw_series(texts).map_err(PlotError::from)?;
    }
    draw_overlays(&mut chart, overlay)
}

/// Each cell's value written in its centre, white on dark colours, "?" where unknown.
fn cell_texts(
    x_edges: &[f64],
    y_edges: &[f64],
    values: &[Vec<f64>],
    (vmin, vmax): (f64, f64),
    cmap: ColorMap,
) -> Vec<Text<'static, (f64, f64), String>> {
    let mut texts = Vec::new();
    for (ix, col) in values.iter().enumerate() {
        for (iy, v) in col.iter().enumerate() {
            let centre = (
                0.5 * (x_edges[ix] + x_edges[ix + 1]),
                0.5 * (y_edges[iy] + y_edges[iy + 1]),
            );
            let (text, dark) = if v.is_finite() {
                let t = (v - vmin) / (vmax - vmin);
                (cell_text(*v), luminance(cmap(t)) < 0.5)
            } else {
                ("?".to_string(), false)
            };
            let color = if dark { WHITE } else { BLACK };
            let style = ("sans-serif", 16)
                .into_font()
                .color(&color)
                .pos(Pos::new(HPos::Center, VPos::Center));
            texts.push(Text::new(text, centre, style));
        }
    }
    texts
}

/// Lines over a heatmap, each overlay once in a legend on mid grey (where white and black
/// lines both show).
fn draw_overlays<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    overlay: &[Overlay],
) -> Result<(), PlotError> {
    for o in overlay {
        for (k, line) in o.lines.iter().enumerate() {
            let style = o.color.stroke_width(3);
            let drawn = chart
                .draw_series(LineSeries::new(line.iter().copied(), style))
                .map_err(PlotError::from)?;
            if k == 0 {
                let color = o.color;
                drawn.label(o.label.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(3))
                });
            }
        }
    }
    if overlay.iter().any(|o| !o.lines.is_empty()) {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            // Mid grey, so that white and black overlay lines both show in the legend.
            .background_style(RGBColor(165, 165, 165).mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(PlotError::from)?;
    }
    Ok(())
}

/// Maps with at most this many cells get their values written in the cells.
pub(crate) const MAX_CELLS_WITH_NUMBERS: usize = 100;

/// A cell's value as written in it: whole numbers (the maps are in percent), one decimal below
/// 10 so small risks do not read as 0.
fn cell_text(v: f64) -> String {
    if v.abs() < 9.95 && v != 0.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.0}")
    }
}

/// Relative luminance of a colour (0 black, 1 white), to pick a legible text colour.
fn luminance(c: RGBColor) -> f64 {
    (0.2126 * c.0 as f64 + 0.7152 * c.1 as f64 + 0.0722 * c.2 as f64) / 255.0
}

/// Lines drawn over a heatmap (e.g. the nominal tire's Hopf curves), with their legend label.
pub(crate) struct Overlay {
    /// The legend's text for these lines.
    pub label: String,
    /// Their colour.
    pub color: RGBColor,
    /// Polylines in the map's axis units.
    pub lines: Vec<Vec<(f64, f64)>>,
}

/// A vertical colour bar for [vmin, vmax], its ticks and label on its right (as the bar reads
/// with the map to its left, never with the panel after it).
pub(crate) fn colorbar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    label: &str,
    (vmin, vmax): (f64, f64),
    cmap: ColorMap,
) -> Result<(), PlotError> {
    let mut chart = ChartBuilder::on(area)
        .margin_top(48)
        .margin_bottom(62)
        .margin_left(4)
        .margin_right(4)
        .right_y_label_area_size(COLORBAR_LABEL_AREA)
        .build_cartesian_2d(0.0..1.0, vmin..vmax)
        .map_err(PlotError::from)?
        .set_secondary_coord(0.0..1.0, vmin..vmax);
    chart
        .configure_secondary_axes()
        .y_desc(label)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(PlotError::from)?;
    let n = 100;
    chart
        .draw_series((0..n).map(|i| {
            let a = vmin + (vmax - vmin) * i as f64 / n as f64;
            let b = vmin + (vmax - vmin) * (i + 1) as f64 / n as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                cmap((i as f64 + 0.5) / n as f64).filled(),
            )
        }))
        .map_err(PlotError::from)?;
    Ok(())
}

/// Width of the label area right of a colour bar (ticks and label) \[px\].
pub(crate) const COLORBAR_LABEL_AREA: u32 = 76;

/// One probability curve with its interval band.
pub(crate) struct Band<'a> {
    /// The legend's label.
    pub label: &'a str,
    /// The x values are discrete levels: drawn as points with interval bars, not joined.
    pub discrete: bool,
    /// (x, p, lo, hi)
    pub points: Vec<(f64, f64, f64, f64)>,
}

/// Probability curves with shaded 95% intervals, y in [0, 1].
pub(crate) fn band_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    bands: &[Band<'_>],
) -> Result<(), PlotError> {
    let xs = bands
        .iter()
        .flat_map(|b| b.points.iter().map(|p| p.0))
        .filter(|x| x.is_finite());
    let (mut x0, mut x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if !x0.is_finite() {
        (x0, x1) = (0.0, 1.0);
    }
    if x1 <= x0 {
        (x0, x1) = (x0 - 0.5, x0 + 0.5);
    }
    let pad = if bands.iter().any(|b| b.discrete) {
        0.08
    } else {
        0.02
    } * (x1 - x0);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(8)
        .x_label_area_size(46)
        .y_label_area_size(64)
        .build_cartesian_2d(x0 - pad..x1 + pad, 0.0..1.0)
        .map_err(PlotError::from)?;
    chart
        .configure_mesh()
        .x_labels(tick_labels_for(area, 64, 8, (x0 - pad, x1 + pad), 15))
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&|v| format!("{:.0}%", 100.0 * v))
        .draw()
        .map_err(PlotError::from)?;
    for (i, b) in bands.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let pts: Vec<(f64, f64, f64, f64)> = b
            .points
            .iter()
            .copied()
            .filter(|p| p.1.is_finite())
            .collect();
        if pts.is_empty() {
            continue;
        }
        if b.discrete {
            // Side by side around each level, so that the wheels' points do not hide each other.
            let shift = (i as f64 - 0.5 * (bands.len() as f64 - 1.0)) * 0.012 * (x1 - x0);
            draw_level_points(&mut chart, b.label, &pts, shift, color)?;
        } else {
            draw_band(&mut chart, b.label, &pts, color)?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(PlotError::from)?;
    Ok(())
}

type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Points with interval bars at discrete levels, moved by `shift` along x.
fn draw_level_points<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart2d<'a, DB>,
    label: &str,
    pts: &[(f64, f64, f64, f64)],
    shift: f64,
    color: RGBColor,
) -> Result<(), PlotError> {
    let pts: Vec<(f64, f64, f64, f64)> = pts.iter().map(|p| (p.0 + shift, p.1, p.2, p.3)).collect();
    chart
        .draw_series(
            pts.iter()
                .map(|p| PathElement::new(vec![(p.0, p.2), (p.0, p.3)], color.stroke_width(2))),
        )
        .map_err(PlotError::from)?;
    chart
        .draw_series(
            pts.iter()
                .map(|p| Circle::new((p.0, p.1), 5, color.filled())),
        )
        .map_err(PlotError::from)?
        .label(label)
        .legend(move |(x, y)| Circle::new((x + 8, y), 5, color.filled()));
    Ok(())
}

/// A curve through the points with its interval shaded.
fn draw_band<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart2d<'a, DB>,
    label: &str,
    pts: &[(f64, f64, f64, f64)],
    color: RGBColor,
) -> Result<(), PlotError> {
    let mut poly: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.3)).collect();
    poly.extend(pts.iter().rev().map(|p| (p.0, p.2)));
    chart
        .draw_series(std::iter::once(Polygon::new(poly, color.mix(0.2).filled())))
        .map_err(PlotError::from)?;
    chart
        .draw_series(LineSeries::new(
            pts.iter().map(|p| (p.0, p.1)),
            color.stroke_width(2),
        ))
        .map_err(PlotError::from)?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(3)));
    chart
        .draw_series(
            pts.iter()
                .map(|p| Circle::new((p.0, p.1), 2, color.filled())),
        )
        .map_err(PlotError::from)?;
    Ok(())
}
