//! The report's figures (PNG or SVG), drawn from the small tables the queries return: conditional
//! probabilities with Wilson bands, risk maps per wheel with their difference, and severity
//! histograms.

use std::path::Path;

use super::RenderError;
use crate::analysis::conditional::BinStat;
use crate::analysis::risk_map::{draw_edges, RiskMap};
use crate::analysis::severity::{Severity, SEVERITY_QUANTITIES};
use crate::model::{Variant, Wheel};
use crate::params::ParamId;
use crate::plot::{self, maps, Series};

/// P(limit cycle | parameter) along every axis of one variant, both wheels, 95% Wilson bands;
/// bins with fewer than `min_count` classified rows are left out. `label` gives axis titles.
pub fn conditional(
    path: &Path,
    variant: Variant,
    axes: &[ParamId],
    label: &dyn Fn(ParamId) -> String,
    bins: &[BinStat],
    min_count: u64,
) -> Result<(), RenderError> {
    let cols = if axes.len() <= 4 { 2 } else { 3 };
    let rows = axes.len().div_ceil(cols).max(1);
    plot::panels(
        path,
        (520 * cols as u32, 360 * rows as u32 + 40),
        (rows, cols),
        &format!("Risk of tread vibration by parameter ({variant} variant; shaded or bars: 95% interval)"),
        |i, area| {
            let Some(axis) = axes.get(i) else {
                return Ok(());
            };
            // Levels (lo = hi) are drawn as points: nothing lies between them.
            let discrete = bins
                .iter()
                .filter(|b| b.axis == *axis)
                .all(|b| b.lo == b.hi);
            let bands: Vec<maps::Band<'_>> = Wheel::BOTH
                .iter()
                .map(|wh| maps::Band {
                    label: wh.as_str(),
                    discrete,
                    points: bins
                        .iter()
                        .filter(|b| {
                            b.variant == variant
                                && b.wheel == *wh
                                && b.axis == *axis
                                && b.counts.enough(min_count)
                        })
                        .map(|b| {
                            let (lo, hi) = b.counts.wilson();
                            (b.mid, b.counts.p(), lo, hi)
                        })
                        .collect(),
                })
                .collect();
            maps::band_panel(
                area,
                &axis.label(),
                &label(*axis),
                "Risk of vibration",
                &bands,
            )
        },
    )
    .map_err(RenderError::Figure)
}

/// One risk map: the risk of vibration of the follower and the driving wheel in percent, side
/// by side, and the difference in percentage points (blue where the driving wheel is less
/// exposed); grey cells hold fewer than `min_count` classified rows. Small grids carry their
/// numbers in the cells.
pub fn risk_map(
    path: &Path,
    map: &RiskMap,
    label: &dyn Fn(ParamId) -> String,
    min_count: u64,
) -> Result<(), RenderError> {
    let nominal = map.nominal.as_deref();
    let (x, y) = (map.x, map.y);
    // The nominal tire's Hopf curves: each wheel's on its own panel, both on the difference.
    let curves = |wheel: Wheel, color: plotters::style::RGBColor| -> Vec<maps::Overlay> {
        nominal
            .into_iter()
            .flatten()
            .filter(|c| c.wheel == wheel)
            .map(|c| maps::Overlay {
                label: format!(
                    "{wheel} Hopf curve of the nominal tire (others at the study's median)"
                ),
                color,
                lines: c
                    .curves
                    .curves
                    .iter()
                    .map(|k| k.points.iter().map(|d| (d.p[0], d.p[1])).collect())
                    .collect(),
            })
            .collect()
    };
    let white = plotters::style::WHITE;
    let black = plotters::style::BLACK;
    let overlays = [
        curves(Wheel::Follower, white),
        curves(Wheel::Driving, black),
        curves(Wheel::Follower, white)
            .into_iter()
            .chain(curves(Wheel::Driving, black))
            .collect(),
    ];
    let (xe, ye) = (draw_edges(&map.x_bins), draw_edges(&map.y_bins));
    let percent = |w| -> Vec<Vec<f64>> {
        map.probability(w, min_count)
            .iter()
            .map(|c| c.iter().map(|p| 100.0 * p).collect())
            .collect()
    };
    let (pf, pd) = (percent(Wheel::Follower), percent(Wheel::Driving));
    let diff: Vec<Vec<f64>> = pd
        .iter()
        .zip(&pf)
        .map(|(a, b)| a.iter().zip(b).map(|(d, f)| d - f).collect())
        .collect();
    let max_abs = diff
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(0.1);
    let title = format!(
        "Risk of tread vibration (polygonal wear) over {} and {} ({} variant; grey: fewer than {min_count} samples)",
        x.label().to_lowercase(),
        y.label().to_lowercase(),
        map.variant
    );
    plot::figure(path, (2100, 760), &title, |area| {
        let parts = area.split_evenly((1, 3));
        for (k, (part, (name, values))) in parts
            .iter()
            .zip([
                ("Risk of tread vibration, follower wheel", &pf),
                ("Risk of tread vibration, driving wheel", &pd),
                (
                    "Driving minus follower (blue: driving wheel less exposed)",
                    &diff,
                ),
            ])
            .enumerate()
        {
            let (main, bar) = part.split_horizontally(part.dim_in_pixel().0 as i32 - 120);
            let (range, cmap, bar_label): ((f64, f64), maps::ColorMap, &str) = if k < 2 {
                ((0.0, 100.0), maps::viridis, "Risk of vibration [%]")
            } else {
                (
                    (-max_abs, max_abs),
                    maps::diverging,
                    "Difference [percentage points]",
                )
            };
            maps::heatmap(
                &main,
                name,
                &label(x),
                &label(y),
                &xe,
                &ye,
                values,
                range,
                cmap,
                &overlays[k],
            )?;
            maps::colorbar(&bar, bar_label, range, cmap)?;
        }
        Ok(())
    })
    .map_err(RenderError::Figure)
}

/// Bars of the severity figure: the fine histogram summed into this many.
pub const SEVERITY_FIGURE_BINS: usize = 40;

/// Severity histograms of one variant: each quantity's share of limit cycles per bin, per wheel.
pub fn severity(path: &Path, variant: Variant, severity: &[Severity]) -> Result<(), RenderError> {
    let quantities = SEVERITY_QUANTITIES.map(|q| q.name());
    plot::panels(
        path,
        (1400, 900),
        (2, 2),
        &format!("Severity among limit cycles ({variant} variant): share of cycles per bin"),
        |i, area| {
            let quantity = quantities[i];
            let sets: Vec<&Severity> = severity
                .iter()
                .filter(|s| s.variant == variant && s.quantity == quantity && s.n > 0)
                .collect();
            if sets.is_empty() {
                return plot::line_panel(
                    area,
                    &format!("{quantity}: no limit cycles"),
                    quantity,
                    "share",
                    &[],
                    false,
                );
            }
            let series: Vec<Series<'_>> = sets
                .iter()
                .map(|s| {
                    let per = s.counts.len().div_ceil(SEVERITY_FIGURE_BINS);
                    let n = s.n.max(1) as f64;
                    let points = s
                        .counts
                        .chunks(per)
                        .enumerate()
                        .flat_map(|(b, c)| {
                            let lo = s.hist.range(b * per).0;
                            let hi = s
                                .hist
                                .range((b * per + c.len() - 1).min(s.counts.len() - 1))
                                .1;
                            let share = c.iter().sum::<u64>() as f64 / n;
                            [(lo, share), (hi, share)]
                        })
                        .collect();
                    Series {
                        label: s.wheel.as_str(),
                        points,
                    }
                })
                .collect();
            let unit = sets.first().map_or("", |s| s.unit);
            plot::line_panel(
                area,
                quantity,
                &format!("{quantity} [{unit}]"),
                "share of limit cycles",
                &series,
                false,
            )
        },
    )
    .map_err(RenderError::Figure)
}
