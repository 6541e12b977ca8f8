//! The wear answer's figures: P(visible polygon within 40,000 km) per bin of every axis (Wilson
//! bands), the risk maps of polygonal-wear likelihood beside the vibration maps (same cells,
//! same stability boundaries, [`super::figures::map_figure`]), and the dominant orders' bars.

use super::figures::{map_figure, MapFigure};
use super::wear::km;
use super::RenderError;
use crate::analysis::wear_risk::{WearAnalysis, WearMap, ORDERS_WITHIN_KM};
use crate::model::{Variant, Wheel};
use crate::params::ParamId;
use crate::plot::{self, maps, FigureFile, Series};

/// P(visible polygon within the headline distance | parameter) along every axis of one
/// variant, both wheels, 95% Wilson bands; bins with fewer than `min_count` wheels with a
/// distance are left out.
pub fn conditional(
    file: &FigureFile,
    variant: Variant,
    axes: &[ParamId],
    label: &dyn Fn(ParamId) -> String,
    w: &WearAnalysis,
    min_count: u64,
) -> Result<(), RenderError> {
    let cols = if axes.len() <= 4 { 2 } else { 3 };
    let rows = axes.len().div_ceil(cols).max(1);
    let within = w.conditional.first().map_or(String::new(), |_| {
        km(crate::analysis::wear_risk::HEADLINE_WITHIN_KM)
    });
    plot::panels(
        file,
        (520 * cols as u32, 360 * rows as u32 + 40),
        (rows, cols),
        &format!("Risk of a visible polygon within {within} by parameter ({variant} variant; shaded or bars: 95% interval)"),
        |i, area| {
            let Some(axis) = axes.get(i) else {
                return Ok(());
            };
            let of_axis = || w.conditional.iter().filter(|b| b.axis == *axis);
            let discrete = of_axis().all(|b| b.lo == b.hi);
            let bands: Vec<maps::Band<'_>> = Wheel::BOTH
                .iter()
                .map(|wh| maps::Band {
                    label: wh.as_str(),
                    discrete,
                    points: of_axis()
                        .filter(|b| {
                            b.variant == variant && b.wheel == *wh && b.counts.enough(min_count)
                        })
                        .map(|b| {
                            let (lo, hi) = b.counts.wilson();
                            (b.mid, b.counts.p(), lo, hi)
                        })
                        .collect(),
                })
                .collect();
            maps::band_panel(area, &axis.label(), &label(*axis), "Risk of polygonal wear", &bands)
        },
    )
    .map_err(RenderError::Figure)
}

/// A risk map of polygonal-wear likelihood: each wheel's P(visible polygon within the map's
/// distance) per cell and the difference, with the nominal tire's Hopf curves.
pub fn risk_map(
    file: &FigureFile,
    map: &WearMap,
    label: &dyn Fn(ParamId) -> String,
    min_count: u64,
) -> Result<(), RenderError> {
    let within = km(map.within_km);
    let fig = MapFigure {
        variant: map.variant,
        x: (map.x, &map.x_bins),
        y: (map.y, &map.y_bins),
        p: [
            map.probability(Wheel::Follower, min_count),
            map.probability(Wheel::Driving, min_count),
        ],
        nominal: map.nominal.as_deref(),
        what: format!("a polygon within {within}"),
        bar_label: "Risk of polygonal wear [%]".into(),
        title: format!(
            "Risk of a visible polygon within {within} over {} and {} ({} variant; lines: Hopf curves; grey: fewer than {min_count} samples)",
            map.x.label().to_lowercase(),
            map.y.label().to_lowercase(),
            map.variant
        ),
    };
    map_figure(file, &fig, label)
}

/// The dominant orders' shares per wheel among the wheels with a visible polygon within
/// [`ORDERS_WITHIN_KM`], as bars (a step line per wheel).
pub fn orders(file: &FigureFile, variant: Variant, w: &WearAnalysis) -> Result<(), RenderError> {
    let series: Vec<(Wheel, Vec<(f64, f64)>)> = Wheel::BOTH
        .iter()
        .map(|wh| {
            let of: Vec<_> = w
                .orders
                .iter()
                .filter(|o| o.variant == variant && o.wheel == *wh)
                .collect();
            let total = of.iter().map(|o| o.n).sum::<u64>().max(1) as f64;
            let points = of
                .iter()
                .flat_map(|o| {
                    let (x, y) = (o.order as f64, o.n as f64 / total);
                    [(x - 0.5, 0.0), (x - 0.5, y), (x + 0.5, y), (x + 0.5, 0.0)]
                })
                .collect();
            (*wh, points)
        })
        .collect();
    let lines: Vec<Series<'_>> = series
        .iter()
        .map(|(wh, p)| Series {
            label: wh.as_str(),
            points: p.clone(),
        })
        .collect();
    plot::figure(
        file,
        (900, 560),
        &format!(
            "Sides of the polygons visible within {} ({variant} variant)",
            km(ORDERS_WITHIN_KM)
        ),
        |area| {
            plot::line_panel(
                area,
                "Dominant order",
                "Dominant order (sides of the polygon)",
                "share of the wheels with a visible polygon",
                &lines,
                false,
            )
        },
    )
    .map_err(RenderError::Figure)
}
