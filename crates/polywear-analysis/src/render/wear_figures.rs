//! The wear answer's figures: P(visible polygon within 40,000 km) per bin of every axis (Wilson
//! bands), the risk maps of polygonal-wear likelihood beside the vibration maps (same cells,
//! same stability boundaries), and the dominant orders' bars. The bands and the maps are drawn
//! by the vibration figures' own code ([`super::figures`]) in the wear analysis' words.

use super::figures::{conditional_figure, map_figure, BandWording, MapWording};
use super::wear::km;
use super::RenderError;
use crate::analysis::counts::WithinCounts;
use crate::analysis::risk_map::RiskMap;
use crate::analysis::wear_risk::{WearAnalysis, HEADLINE_WITHIN_KM, ORDERS_WITHIN_KM};
use crate::plot::{self, FigureFile, Series};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;

/// P(visible polygon within the headline distance | parameter) along every axis of one
/// variant, both wheels, 95% Wilson bands; bins with fewer than `min_count` wheels with a
/// distance are left out.
pub(crate) fn conditional(
    file: &FigureFile,
    variant: Variant,
    axes: &[ParamId],
    label: &dyn Fn(ParamId) -> String,
    w: &WearAnalysis,
    min_count: u64,
) -> Result<(), RenderError> {
    let h = w.headline_answer();
    let words = BandWording {
        what: h.words.clone(),
        y_label: "Risk of polygonal wear",
    };
    conditional_figure(
        file,
        variant,
        axes,
        label,
        &h.conditional,
        &words,
        min_count,
    )
}

/// A risk map of polygonal-wear likelihood: each wheel's P(visible polygon within
/// `HEADLINE_WITHIN_KM`) per cell and the difference, with the nominal tire's Hopf curves.
pub(crate) fn risk_map(
    file: &FigureFile,
    map: &RiskMap<WithinCounts>,
    label: &dyn Fn(ParamId) -> String,
    min_count: u64,
    drivetrain: polywear_core::params::axle::Drivetrain,
) -> Result<(), RenderError> {
    let within = km(HEADLINE_WITHIN_KM);
    let words = MapWording {
        drivetrain,
        headline: format!("a visible polygon within {within}"),
        what: format!("a polygon within {within}"),
        bar_label: "Risk of polygonal wear [%]",
        lines_note: "lines: Hopf curves; ",
    };
    map_figure(file, map, &words, label, min_count)
}

/// The dominant orders' shares per wheel among the wheels with a visible polygon within
/// `ORDERS_WITHIN_KM`, as bars (a step line per wheel).
pub(crate) fn orders(
    file: &FigureFile,
    variant: Variant,
    w: &WearAnalysis,
) -> Result<(), RenderError> {
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
