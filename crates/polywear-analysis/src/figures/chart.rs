//! The chart's picture: each wheel's unstable region shaded in its colour (blue follower, red
//! driving, as in every other polywear figure) and outlined by its Hopf curves, solid where the
//! onset is soft (supercritical) and dashed where it is hard (subcritical); Bautin points and
//! the nominal operating point marked.

use plotters::prelude::*;

use crate::plot::{figure, format_tick, tick_labels_for, FigureFile, PlotError, PALETTE};
use polywear_core::continuation::trace::SpecialKind;
use polywear_core::model::Wheel;
use polywear_study::chart::band::StructureBand;
use polywear_study::chart::{ChartRequest, WheelCurves};

/// Cells per axis of the shading (evaluated by eigenvalues at their centres).
pub const SHADE_CELLS: usize = 120;

fn colour(wheel: Wheel) -> RGBColor {
    match wheel {
        Wheel::Follower => PALETTE[0],
        Wheel::Driving => PALETTE[1],
    }
}

/// What a drawn chart says in words, for the caller and for tests that check the picture.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ChartLayout {
    /// The figure's title.
    pub title: String,
    /// The legend's entries, in order.
    pub legend: Vec<String>,
}

type Chart<'a, 'b> = ChartContext<
    'a,
    crate::plot::backend::FigureBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The operating point a chart is drawn at, in words: each operating axis that is not one of
/// the chart's own, "speed 100 km/h, toe-in 0.2 deg".
pub(crate) fn fixed_operating_point(req: &ChartRequest) -> String {
    polywear_core::params::OPERATING_AXES
        .iter()
        .filter(|&&id| id != req.x && id != req.y)
        .map(|&id| {
            format!(
                "{} {} {}",
                id.label().to_lowercase(),
                format_tick(req.base[id]),
                id.spec().unit
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The chart's title: its axes, the operating point it is drawn at, and the variant.
pub(crate) fn title(req: &ChartRequest) -> String {
    format!(
        "Where the tread vibrates: {} × {} at {} ({} variant)",
        req.x.label(),
        req.y.label(),
        fixed_operating_point(req),
        req.variant
    )
}

/// Draws the chart into `file`; `grids` holds each wheel's stability grid of
/// [`SHADE_CELLS`]² cells (see [`ChartRequest::stability_grid`]). Returns what the picture
/// says in words.
pub fn draw(
    file: &FigureFile,
    req: &ChartRequest,
    charts: &[WheelCurves],
    grids: &[Vec<Option<bool>>],
    band: Option<&StructureBand>,
) -> Result<ChartLayout, PlotError> {
    let (x, y) = (req.x, req.y);
    let mut layout = ChartLayout {
        title: title(req),
        legend: Vec::new(),
    };
    figure(file, (1200, 950), &layout.title.clone(), |area| {
        let (lo, hi) = (req.bounds.lo, req.bounds.hi);
        let mut chart = ChartBuilder::on(area)
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(lo[0]..hi[0], lo[1]..hi[1])
            .map_err(PlotError::from)?;
        chart
            .configure_mesh()
            .x_labels(tick_labels_for(area, 80, 16, (lo[0], hi[0]), 15))
            .x_desc(polywear_core::params::axis_label(x.name(), x.spec().unit))
            .y_desc(polywear_core::params::axis_label(y.name(), y.spec().unit))
            .light_line_style(TRANSPARENT)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .x_label_formatter(&|v| format_tick(*v))
            .y_label_formatter(&|v| format_tick(*v))
            .draw()
            .map_err(PlotError::from)?;
        let legend = &mut layout.legend;
        shade_regions(&mut chart, req, charts, grids, legend)?;
        if let Some(b) = band {
            shade_band(&mut chart, req, b, legend)?;
        }
        draw_curves(&mut chart, charts, legend)?;
        mark_points(&mut chart, req, charts, legend)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(PlotError::from)?;
        if charts.iter().all(|c| c.curves.curves.is_empty()) {
            no_hopf_note(&mut chart, req, charts, grids)?;
        }
        Ok(())
    })?;
    Ok(layout)
}

/// The cell `(i, j)` of an `n` × `n` grid over the chart's box, as a rectangle's corners.
fn cell(req: &ChartRequest, n: usize, i: usize, j: usize) -> [(f64, f64); 2] {
    let a = req
        .bounds
        .to_param([i as f64 / n as f64, j as f64 / n as f64]);
    let b = req
        .bounds
        .to_param([(i + 1) as f64 / n as f64, (j + 1) as f64 / n as f64]);
    [(a[0], a[1]), (b[0], b[1])]
}

/// Each wheel's unstable cells in its colour (translucent, so that where both wheels are
/// unstable the two colours mix, with a legend entry of its own), and the cells without an
/// equilibrium in grey.
fn shade_regions<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    req: &ChartRequest,
    charts: &[WheelCurves],
    grids: &[Vec<Option<bool>>],
    legend: &mut Vec<String>,
) -> Result<(), PlotError> {
    let n = SHADE_CELLS;
    for (c, grid) in charts.iter().zip(grids) {
        let col = colour(c.wheel);
        let unstable = (0..n * n).filter(|k| grid[*k] == Some(true));
        let label = format!(
            "{} wheel unstable: self-excited vibration (polygonal wear risk)",
            c.wheel
        );
        chart
            .draw_series(
                unstable
                    .map(|k| Rectangle::new(cell(req, n, k % n, k / n), col.mix(0.22).filled())),
            )
            .map_err(PlotError::from)?
            .label(label.clone())
            .legend(move |(px, py)| {
                Rectangle::new([(px, py - 6), (px + 18, py + 6)], col.mix(0.35).filled())
            });
        legend.push(label);
        let missing: Vec<usize> = (0..n * n).filter(|k| grid[*k].is_none()).collect();
        if !missing.is_empty() {
            let grey = RGBColor(150, 150, 150);
            let label = format!(
                "{} wheel: no equilibrium (cannot transmit the drive)",
                c.wheel
            );
            chart
                .draw_series(
                    missing.into_iter().map(|k| {
                        Rectangle::new(cell(req, n, k % n, k / n), grey.mix(0.35).filled())
                    }),
                )
                .map_err(PlotError::from)?
                .label(label.clone())
                .legend(move |(px, py)| {
                    Rectangle::new([(px, py - 6), (px + 18, py + 6)], grey.mix(0.5).filled())
                });
            legend.push(label);
        }
    }
    let both = grids.len() == 2 && (0..n * n).any(|k| grids.iter().all(|g| g[k] == Some(true)));
    if both {
        // The swatch overlays the two translucent colours as the cells do.
        let (a, b) = (colour(charts[0].wheel), colour(charts[1].wheel));
        let label = "both wheels unstable (the colours overlap)".to_string();
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(PlotError::from)?
            .label(label.clone())
            .legend(move |(px, py)| {
                EmptyElement::at((px, py))
                    + Rectangle::new([(0, -6), (18, 6)], WHITE.filled())
                    + Rectangle::new([(0, -6), (18, 6)], a.mix(0.35).filled())
                    + Rectangle::new([(0, -6), (18, 6)], b.mix(0.35).filled())
            });
        legend.push(label);
    }
    Ok(())
}

/// The structure band: cells unstable for 5–95% of the drawn tire structures, per wheel.
fn shade_band<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    req: &ChartRequest,
    b: &StructureBand,
    legend: &mut Vec<String>,
) -> Result<(), PlotError> {
    let m = b.cells;
    for (wheel, shares) in &b.shares {
        let col = colour(*wheel);
        let cells = (0..m * m).filter(|k| StructureBand::in_band(shares[*k]));
        let label = format!(
            "{wheel} wheel: boundary band, unstable for 5-95% of {} drawn tire structures",
            b.structures.len()
        );
        chart
            .draw_series(
                cells.map(|k| Rectangle::new(cell(req, m, k % m, k / m), col.mix(0.55).filled())),
            )
            .map_err(PlotError::from)?
            .label(label.clone())
            .legend(move |(px, py)| {
                Rectangle::new([(px, py - 6), (px + 18, py + 6)], col.mix(0.7).filled())
            });
        legend.push(label);
    }
    Ok(())
}

/// The Hopf curves, solid where the onset is soft and dashed where it is hard, and the
/// legend entries of the two line styles (in black: they apply to both colours).
fn draw_curves<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    charts: &[WheelCurves],
    legend: &mut Vec<String>,
) -> Result<(), PlotError> {
    let mut legend_sub = false;
    for c in charts {
        let col = colour(c.wheel);
        for curve in &c.curves.curves {
            for (sub, run) in runs(curve) {
                if sub {
                    legend_sub = true;
                    chart
                        .draw_series(DashedLineSeries::new(run, 9, 7, col.stroke_width(3)))
                        .map_err(PlotError::from)?;
                } else {
                    chart
                        .draw_series(LineSeries::new(run, col.stroke_width(3)))
                        .map_err(PlotError::from)?;
                }
            }
        }
    }
    let soft = "Hopf boundary, supercritical (l1 < 0): soft onset, small vibration grows";
    chart
        .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
        .map_err(PlotError::from)?
        .label(soft)
        .legend(|(px, py)| PathElement::new(vec![(px, py), (px + 18, py)], BLACK.stroke_width(3)));
    legend.push(soft.to_string());
    if legend_sub {
        let hard = "Hopf boundary, subcritical (l1 > 0): hard onset, vibration can persist outside";
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(PlotError::from)?
            .label(hard)
            .legend(|(px, py)| {
                EmptyElement::at((px, py))
                    + PathElement::new(vec![(0, 0), (6, 0)], BLACK.stroke_width(3))
                    + PathElement::new(vec![(11, 0), (18, 0)], BLACK.stroke_width(3))
            });
        legend.push(hard.to_string());
    }
    Ok(())
}

/// The nominal operating point, in words: "nominal operating point (speed 100 km/h, toe-in
/// 0.2 deg)", and whether it lies outside the box.
pub(crate) fn nominal_label(req: &ChartRequest, inside: bool) -> String {
    let nom = req.nominal();
    let words = |id: polywear_core::params::ParamId, v: f64| {
        format!(
            "{} {} {}",
            id.label().to_lowercase(),
            format_tick(v),
            id.spec().unit
        )
    };
    format!(
        "nominal operating point ({}, {}){}",
        words(req.x, nom[0]),
        words(req.y, nom[1]),
        if inside { "" } else { ", outside this box" }
    )
}

/// Bautin points and the nominal operating point.
fn mark_points<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    req: &ChartRequest,
    charts: &[WheelCurves],
    legend: &mut Vec<String>,
) -> Result<(), PlotError> {
    let bautin: Vec<(f64, f64)> = charts
        .iter()
        .flat_map(|c| c.curves.special.iter())
        .filter(|s| s.kind == SpecialKind::Bautin)
        .map(|s| (s.p[0], s.p[1]))
        .collect();
    if !bautin.is_empty() {
        let label = "Bautin point (l1 = 0): the onset turns from soft to hard";
        chart
            .draw_series(
                bautin
                    .into_iter()
                    .map(|p| TriangleMarker::new(p, 9, BLACK.filled())),
            )
            .map_err(PlotError::from)?
            .label(label)
            .legend(|(px, py)| TriangleMarker::new((px + 9, py), 7, BLACK.filled()));
        legend.push(label.to_string());
    }
    let (lo, hi) = (req.bounds.lo, req.bounds.hi);
    let nom = req.nominal();
    let inside = (0..2).all(|k| (lo[k]..=hi[k]).contains(&nom[k]));
    let label = nominal_label(req, inside);
    let shown: Vec<(f64, f64)> = if inside {
        vec![(nom[0], nom[1])]
    } else {
        vec![]
    };
    chart
        .draw_series(shown.into_iter().map(|p| {
            EmptyElement::at(p)
                + Circle::new((0, 0), 7, BLACK.filled())
                + Circle::new((0, 0), 4, WHITE.filled())
        }))
        .map_err(PlotError::from)?
        .label(label.clone())
        .legend(|(px, py)| Circle::new((px + 9, py), 6, BLACK.filled()));
    legend.push(label);
    Ok(())
}

/// Without any Hopf curve in the box: a note in its middle saying how each wheel is there.
fn no_hopf_note<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    req: &ChartRequest,
    charts: &[WheelCurves],
    grids: &[Vec<Option<bool>>],
) -> Result<(), PlotError> {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let (lo, hi) = (req.bounds.lo, req.bounds.hi);
    let parts: Vec<String> = charts
        .iter()
        .zip(grids)
        .map(|(c, g)| {
            let state = if g.contains(&Some(true)) {
                "unstable everywhere"
            } else {
                "stable everywhere"
            };
            format!("{} wheel {state}", c.wheel)
        })
        .collect();
    let text = format!("No Hopf point in this box: {}", parts.join(", "));
    let mid = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let style =
        TextStyle::from(("sans-serif", 22).into_font()).pos(Pos::new(HPos::Center, VPos::Center));
    chart
        .draw_series(std::iter::once(Text::new(text, mid, style)))
        .map_err(PlotError::from)?;
    Ok(())
}

/// The curve cut into runs of one criticality, split where l1 changes sign (at the linearly
/// interpolated zero, so the styles meet at the Bautin point).
fn runs(curve: &polywear_core::continuation::trace::Curve) -> Vec<(bool, Vec<(f64, f64)>)> {
    let mut out: Vec<(bool, Vec<(f64, f64)>)> = Vec::new();
    for (k, d) in curve.points.iter().enumerate() {
        let sub = d.l1 > 0.0;
        let here = (d.p[0], d.p[1]);
        match out.last_mut() {
            Some((s, run)) if *s == sub => run.push(here),
            _ => {
                if k > 0 {
                    let a = &curve.points[k - 1];
                    let t = a.l1 / (a.l1 - d.l1);
                    let cut = (
                        a.p[0] + t * (d.p[0] - a.p[0]),
                        a.p[1] + t * (d.p[1] - a.p[1]),
                    );
                    if let Some((_, run)) = out.last_mut() {
                        run.push(cut);
                    }
                    out.push((sub, vec![cut, here]));
                } else {
                    out.push((sub, vec![here]));
                }
            }
        }
    }
    out
}
