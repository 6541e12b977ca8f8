//! The chart's picture: each wheel's unstable region shaded in its colour (blue follower, red
//! driving, as in every other polywear figure) and outlined by its Hopf curves, solid where the
//! onset is soft (supercritical) and dashed where it is hard (subcritical); Bautin points and
//! the nominal operating point marked.

use std::path::Path;

use plotters::prelude::*;

use super::band::StructureBand;
use super::{ChartRequest, WheelCurves};
use crate::continuation::trace::SpecialKind;
use crate::model::Wheel;
use crate::plot::{figure, format_tick, PlotError, PALETTE};

/// Cells per axis of the shading (evaluated by eigenvalues at their centres).
pub const SHADE_CELLS: usize = 120;

fn colour(wheel: Wheel) -> RGBColor {
    match wheel {
        Wheel::Follower => PALETTE[0],
        Wheel::Driving => PALETTE[1],
    }
}

/// Draws the chart to `path`; `grids` holds each wheel's stability grid of
/// [`SHADE_CELLS`]² cells (see [`ChartRequest::stability_grid`]).
pub fn draw(
    path: &Path,
    req: &ChartRequest,
    charts: &[WheelCurves],
    grids: &[Vec<Option<bool>>],
    band: Option<&StructureBand>,
) -> Result<(), PlotError> {
    let (x, y) = (req.x, req.y);
    let title = format!(
        "Where the tread vibrates: {} × {} ({} variant; other parameters as given)",
        x.label(),
        y.label(),
        req.variant
    );
    figure(path, (1200, 950), &title, |area| {
        let (lo, hi) = (req.bounds.lo, req.bounds.hi);
        let mut chart = ChartBuilder::on(area)
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(lo[0]..hi[0], lo[1]..hi[1])
            .map_err(PlotError::from)?;
        chart
            .configure_mesh()
            .x_desc(crate::params::axis_label(x.name(), x.spec().unit))
            .y_desc(crate::params::axis_label(y.name(), y.spec().unit))
            .light_line_style(TRANSPARENT)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .x_label_formatter(&|v| format_tick(*v))
            .y_label_formatter(&|v| format_tick(*v))
            .draw()
            .map_err(PlotError::from)?;
        let n = SHADE_CELLS;
        let cell = |i: usize, j: usize| {
            let a = req
                .bounds
                .to_param([i as f64 / n as f64, j as f64 / n as f64]);
            let b = req
                .bounds
                .to_param([(i + 1) as f64 / n as f64, (j + 1) as f64 / n as f64]);
            [(a[0], a[1]), (b[0], b[1])]
        };
        let e = |e: DrawingAreaErrorKind<_>| PlotError::from(e);
        for (c, grid) in charts.iter().zip(grids) {
            let col = colour(c.wheel);
            let unstable = (0..n * n).filter(|k| grid[*k] == Some(true));
            chart
                .draw_series(
                    unstable.map(|k| Rectangle::new(cell(k % n, k / n), col.mix(0.22).filled())),
                )
                .map_err(e)?
                .label(format!(
                    "{} wheel unstable: self-excited vibration (polygonal wear risk)",
                    c.wheel
                ))
                .legend(move |(px, py)| {
                    Rectangle::new([(px, py - 6), (px + 18, py + 6)], col.mix(0.35).filled())
                });
            let missing: Vec<usize> = (0..n * n).filter(|k| grid[*k].is_none()).collect();
            if !missing.is_empty() {
                chart
                    .draw_series(missing.into_iter().map(|k| {
                        Rectangle::new(
                            cell(k % n, k / n),
                            RGBColor(150, 150, 150).mix(0.35).filled(),
                        )
                    }))
                    .map_err(e)?
                    .label(format!(
                        "{} wheel: no equilibrium (cannot transmit the drive)",
                        c.wheel
                    ))
                    .legend(|(px, py)| {
                        Rectangle::new(
                            [(px, py - 6), (px + 18, py + 6)],
                            RGBColor(150, 150, 150).mix(0.5).filled(),
                        )
                    });
            }
        }
        if let Some(b) = band {
            let m = b.cells;
            let cell = |i: usize, j: usize| {
                let a = req
                    .bounds
                    .to_param([i as f64 / m as f64, j as f64 / m as f64]);
                let c = req
                    .bounds
                    .to_param([(i + 1) as f64 / m as f64, (j + 1) as f64 / m as f64]);
                [(a[0], a[1]), (c[0], c[1])]
            };
            for (wheel, shares) in &b.shares {
                let col = colour(*wheel);
                let cells = (0..m * m).filter(|k| StructureBand::in_band(shares[*k]));
                chart
                    .draw_series(cells.map(|k| Rectangle::new(cell(k % m, k / m), col.mix(0.55).filled())))
                    .map_err(e)?
                    .label(format!(
                        "{wheel} wheel: boundary band, unstable for 5-95% of {} drawn tire structures",
                        b.structures.len()
                    ))
                    .legend(move |(px, py)| Rectangle::new([(px, py - 6), (px + 18, py + 6)], col.mix(0.7).filled()));
            }
        }
        let mut legend_sub = false;
        for c in charts {
            let col = colour(c.wheel);
            for curve in &c.curves.curves {
                for (sub, run) in runs(curve) {
                    if sub {
                        legend_sub = true;
                        chart
                            .draw_series(DashedLineSeries::new(run, 9, 7, col.stroke_width(3)))
                            .map_err(e)?;
                    } else {
                        chart
                            .draw_series(LineSeries::new(run, col.stroke_width(3)))
                            .map_err(e)?;
                    }
                }
            }
        }
        // Legend entries for the line styles, drawn in black (they apply to both colours).
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(e)?
            .label("Hopf boundary, supercritical (l1 < 0): soft onset, small vibration grows")
            .legend(|(px, py)| {
                PathElement::new(vec![(px, py), (px + 18, py)], BLACK.stroke_width(3))
            });
        if legend_sub {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(e)?
                .label("Hopf boundary, subcritical (l1 > 0): hard onset, vibration can persist outside")
                .legend(|(px, py)| {
                    EmptyElement::at((px, py))
                        + PathElement::new(vec![(0, 0), (6, 0)], BLACK.stroke_width(3))
                        + PathElement::new(vec![(11, 0), (18, 0)], BLACK.stroke_width(3))
                });
        }
        let bautin: Vec<(f64, f64)> = charts
            .iter()
            .flat_map(|c| c.curves.special.iter())
            .filter(|s| s.kind == SpecialKind::Bautin)
            .map(|s| (s.p[0], s.p[1]))
            .collect();
        if !bautin.is_empty() {
            chart
                .draw_series(
                    bautin
                        .into_iter()
                        .map(|p| TriangleMarker::new(p, 9, BLACK.filled())),
                )
                .map_err(e)?
                .label("Bautin point (l1 = 0): the onset turns from soft to hard")
                .legend(|(px, py)| TriangleMarker::new((px + 9, py), 7, BLACK.filled()));
        }
        let nom = req.nominal();
        let inside = (0..2).all(|k| (lo[k]..=hi[k]).contains(&nom[k]));
        let nom_label = format!(
            "nominal operating point ({} = {}, {} = {}){}",
            x.name(),
            format_tick(nom[0]),
            y.name(),
            format_tick(nom[1]),
            if inside { "" } else { ", outside this box" }
        );
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
            .map_err(e)?
            .label(nom_label)
            .legend(|(px, py)| Circle::new((px + 9, py), 6, BLACK.filled()));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(e)?;
        if charts.iter().all(|c| c.curves.curves.is_empty()) {
            let state = |w: Wheel, g: &Vec<Option<bool>>| {
                let any = g.contains(&Some(true));
                format!(
                    "{w} wheel {}",
                    if any {
                        "unstable everywhere"
                    } else {
                        "stable everywhere"
                    }
                )
            };
            let parts: Vec<String> = charts
                .iter()
                .zip(grids)
                .map(|(c, g)| state(c.wheel, g))
                .collect();
            let text = format!("No Hopf point in this box: {}", parts.join(", "));
            let mid = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
            chart
                .draw_series(std::iter::once(Text::new(
                    text,
                    mid,
                    TextStyle::from(("sans-serif", 22).into_font()).pos(
                        plotters::style::text_anchor::Pos::new(
                            plotters::style::text_anchor::HPos::Center,
                            plotters::style::text_anchor::VPos::Center,
                        ),
                    ),
                )))
                .map_err(e)?;
        }
        Ok(())
    })
}

/// The curve cut into runs of one criticality, split where l1 changes sign (at the linearly
/// interpolated zero, so the styles meet at the Bautin point).
fn runs(curve: &crate::continuation::trace::Curve) -> Vec<(bool, Vec<(f64, f64)>)> {
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
