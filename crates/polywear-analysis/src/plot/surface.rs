//! An objective evaluated at scattered settings: over two parameters as a map (each pixel
//! coloured by the nearest evaluated setting, so refined regions show finer), with overlay
//! lines and markers; over one parameter as a curve with its interval band and vertical lines.

use plotters::prelude::*;

use super::maps::{self, Overlay};
use super::{format_tick, FigureFile, PlotError, PALETTE};

/// One evaluated setting of a two-parameter map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MapPoint {
    /// x \[axis units\].
    pub x: f64,
    /// y \[axis units\].
    pub y: f64,
    /// The objective there (NaN: unknown or infeasible, drawn grey).
    pub value: f64,
}

/// Pixels per axis of the map's raster.
pub(crate) const RASTER: usize = 96;

/// The objective over two parameters: the raster of nearest evaluated settings in
/// [x0, x1] × [y0, y1], the overlays (lines and markers), and a colour bar labelled `label`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn surface_map(
    file: &FigureFile,
    title: &str,
    (x_label, y_label): (&str, &str),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    points: &[MapPoint],
    overlay: &[Overlay],
    label: &str,
) -> Result<(), PlotError> {
    if points.is_empty() {
        return Err(PlotError::Empty);
    }
    let n = RASTER;
    let x_edges: Vec<f64> = (0..=n)
        .map(|i| x0 + (x1 - x0) * i as f64 / n as f64)
        .collect();
    let y_edges: Vec<f64> = (0..=n)
        .map(|j| y0 + (y1 - y0) * j as f64 / n as f64)
        .collect();
    // Distances in box units, so that both axes weigh the same.
    let nearest = |u: f64, v: f64| {
        points
            .iter()
            .min_by(|a, b| {
                let d = |p: &MapPoint| {
                    ((p.x - x0) / (x1 - x0) - u).powi(2) + ((p.y - y0) / (y1 - y0) - v).powi(2)
                };
                d(a).total_cmp(&d(b))
            })
            .map_or(f64::NAN, |p| p.value)
    };
    let values: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| nearest((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64))
                .collect()
        })
        .collect();
    let finite = points.iter().map(|p| p.value).filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let range = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else if lo.is_finite() {
        (lo - 0.5, lo + 0.5)
    } else {
        (0.0, 1.0)
    };
    super::figure(file, (1100, 860), title, |area| {
        let (main, bar) = area.split_horizontally(area.dim_in_pixel().0 as i32 - 130);
        maps::heatmap(
            &main,
            "",
            x_label,
            y_label,
            &x_edges,
            &y_edges,
            &values,
            range,
            maps::viridis,
            overlay,
        )?;
        maps::colorbar(&bar, label, range, maps::viridis)
    })
}

/// A marker as overlay lines: a `+` (or an `×` when `diagonal`) of half-size `r` in box units.
pub(crate) fn marker(
    (x, y): (f64, f64),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    r: f64,
    diagonal: bool,
) -> Vec<Vec<(f64, f64)>> {
    let (dx, dy) = (r * (x1 - x0), r * (y1 - y0));
    if diagonal {
        vec![
            vec![(x - dx, y - dy), (x + dx, y + dy)],
            vec![(x - dx, y + dy), (x + dx, y - dy)],
        ]
    } else {
        vec![
            vec![(x - dx, y), (x + dx, y)],
            vec![(x, y - dy), (x, y + dy)],
        ]
    }
}

/// A vertical line of a curve figure, with its legend label.
pub(crate) struct VLine {
    /// Where \[axis units\].
    pub x: f64,
    /// The legend's text.
    pub label: String,
    /// Its colour's index in [`PALETTE`].
    pub color: usize,
}

/// The objective over one parameter: (x, value, low, high) sorted by x, the best marked, and
/// vertical lines.
pub(crate) fn surface_curve(
    file: &FigureFile,
    title: &str,
    (x_label, y_label): (&str, &str),
    points: &[(f64, f64, f64, f64)],
    best: Option<(f64, f64)>,
    lines: &[VLine],
) -> Result<(), PlotError> {
    let pts: Vec<&(f64, f64, f64, f64)> = points.iter().filter(|p| p.1.is_finite()).collect();
    if pts.is_empty() {
        return Err(PlotError::Empty);
    }
    let (x0, x1) = (pts[0].0, pts[pts.len() - 1].0);
    let y1 = pts.iter().map(|p| p.3).fold(0.0f64, f64::max) * 1.1 + 1e-9;
    super::figure(file, (1000, 620), title, |area| {
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(46)
            .y_label_area_size(72)
            .build_cartesian_2d(x0..x1, 0.0..y1)
            .map_err(PlotError::from)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 16))
            .x_label_formatter(&|v| format_tick(*v))
            .y_label_formatter(&|v| format_tick(*v))
            .draw()
            .map_err(PlotError::from)?;
        let color = PALETTE[0];
        let mut band: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.3)).collect();
        band.extend(pts.iter().rev().map(|p| (p.0, p.2)));
        chart
            .draw_series(std::iter::once(Polygon::new(band, color.mix(0.2).filled())))
            .map_err(PlotError::from)?;
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|p| (p.0, p.1)),
                color.stroke_width(2),
            ))
            .map_err(PlotError::from)?
            .label("objective, 95% interval shaded")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(3))
            });
        if let Some((bx, by)) = best {
            let red = PALETTE[1];
            chart
                .draw_series(std::iter::once(Cross::new(
                    (bx, by),
                    8,
                    red.stroke_width(3),
                )))
                .map_err(PlotError::from)?
                .label("optimum")
                .legend(move |(x, y)| Cross::new((x + 8, y), 6, red.stroke_width(3)));
        }
        for l in lines.iter().filter(|l| l.x > x0 && l.x < x1) {
            let c = PALETTE[l.color % PALETTE.len()];
            chart
                .draw_series(DashedLineSeries::new(
                    [(l.x, 0.0), (l.x, y1)],
                    8,
                    5,
                    c.stroke_width(2),
                ))
                .map_err(PlotError::from)?
                .label(l.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                });
        }
        super::draw_legend(&mut chart)
    })
}
