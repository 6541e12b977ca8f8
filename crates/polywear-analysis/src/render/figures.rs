//! The report's figures (PNG or SVG), drawn from the small tables the queries return: conditional
//! probabilities with Wilson bands, risk maps per wheel with their difference, and severity
//! histograms.

use super::RenderError;
use crate::analysis::conditional::BinStat;
use crate::analysis::counts::RiskCounts;
use crate::analysis::risk_map::{draw_edges, RiskMap};
use crate::analysis::severity::{Severity, SEVERITY_QUANTITIES};
use crate::plot::{self, maps, FigureFile, Series};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::axle::Drivetrain;
use polywear_core::params::ParamId;

/// P(vibration | parameter) along every axis of one variant, both wheels, 95% Wilson bands;
/// bins with fewer than `min_count` classified rows are left out. `label` gives axis titles.
pub fn conditional(
    file: &FigureFile,
    variant: Variant,
    axes: &[ParamId],
    label: &dyn Fn(ParamId) -> String,
    bins: &[BinStat],
    min_count: u64,
) -> Result<(), RenderError> {
    let words = BandWording {
        what: "tread vibration".into(),
        y_label: "Risk of vibration",
    };
    conditional_figure(file, variant, axes, label, bins, &words, min_count)
}

/// What a conditional-probability figure says of its outcome.
pub(crate) struct BandWording {
    /// The outcome in the title, after "Risk of": "tread vibration".
    pub what: String,
    /// The panels' y-axis title: "Risk of vibration".
    pub y_label: &'static str,
}

/// P(outcome | parameter) along every axis of one variant, both wheels, 95% Wilson bands, in
/// the words of `words`; bins with fewer than `min_count` samples counted are left out.
pub(crate) fn conditional_figure<C: RiskCounts>(
    file: &FigureFile,
    variant: Variant,
    axes: &[ParamId],
    label: &dyn Fn(ParamId) -> String,
    bins: &[BinStat<C>],
    words: &BandWording,
    min_count: u64,
) -> Result<(), RenderError> {
    let cols = if axes.len() <= 4 { 2 } else { 3 };
    let rows = axes.len().div_ceil(cols).max(1);
    plot::panels(
        file,
        (520 * cols as u32, 360 * rows as u32 + 40),
        (rows, cols),
        &format!(
            "Risk of {} by parameter ({variant} variant; shaded or bars: 95% interval)",
            words.what
        ),
        |i, area| {
            let Some(axis) = axes.get(i) else {
                return Ok(());
            };
            let of_axis = || bins.iter().filter(|b| b.axis == *axis);
            // Levels (lo = hi) are drawn as points: nothing lies between them.
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
            maps::band_panel(area, &axis.label(), &label(*axis), words.y_label, &bands)
        },
    )
    .map_err(RenderError::Figure)
}

/// Width of a risk map panel's colour bar with its ticks and label \[px\].
pub(crate) const RISK_MAP_BAR_PX: i32 = 130;

/// Blank space between a colour bar's label and the next panel's y-axis label \[px\].
pub(crate) const RISK_MAP_GAP_PX: i32 = 50;

/// One panel of a risk map: title, values in percent (`[ix][iy]`), range, colours and the
/// colour bar's label.
struct MapPanel {
    title: String,
    values: Vec<Vec<f64>>,
    range: (f64, f64),
    cmap: maps::ColorMap,
    bar_label: String,
}

/// What a risk map's figure says of its outcome.
pub(crate) struct MapWording {
    /// The run's drivetrain, which names each wheel's axle in the panel titles.
    pub drivetrain: Drivetrain,
    /// The outcome in the figure's title, after "Risk of": "tread vibration (polygonal wear)".
    pub headline: String,
    /// The outcome in the wheels' panel titles, after "Risk of": "tread vibration".
    pub what: String,
    /// The colour bar's label: "Risk of vibration \[%\]".
    pub bar_label: &'static str,
    /// What the title says of the lines before its note on grey cells: "lines: Hopf curves; ",
    /// or nothing.
    pub lines_note: &'static str,
}

/// What a risk map shows: its axes and bins, each wheel's probability per cell (NaN: too few),
/// the nominal tire's Hopf curves, and the outcome in words.
struct MapFigure<'a> {
    /// The horizontal axis and its bins.
    x: (ParamId, &'a crate::analysis::bins::Bins),
    /// The vertical axis and its bins.
    y: (ParamId, &'a crate::analysis::bins::Bins),
    /// Follower, driving: probability per cell `[ix][iy]`.
    p: [Vec<Vec<f64>>; 2],
    /// The nominal tire's Hopf curves over the box.
    nominal: Option<&'a [polywear_study::chart::WheelCurves]>,
    /// The outcome, to follow "Risk of": "tread vibration", "a polygon within 40,000 km".
    what: &'a str,
    /// Follower, driving in words with their axles: "rear (follower)".
    wheels: [String; 2],
    /// The colour bar's label: "Risk of vibration \[%\]".
    bar_label: &'a str,
    /// The figure's title.
    title: String,
}

/// The three panels of a risk map: each wheel's risk in percent, and the difference in
/// percentage points on a symmetric range.
fn map_panels(fig: &MapFigure<'_>) -> [MapPanel; 3] {
    let percent = |p: &Vec<Vec<f64>>| -> Vec<Vec<f64>> {
        p.iter()
            .map(|c| c.iter().map(|p| 100.0 * p).collect())
            .collect()
    };
    let (pf, pd) = (percent(&fig.p[0]), percent(&fig.p[1]));
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
    let risk = |title: String, values| MapPanel {
        title,
        values,
        range: (0.0, 100.0),
        cmap: maps::viridis,
        bar_label: fig.bar_label.to_string(),
    };
    [
        risk(format!("Risk of {}, {} wheel", fig.what, fig.wheels[0]), pf),
        risk(format!("Risk of {}, {} wheel", fig.what, fig.wheels[1]), pd),
        MapPanel {
            title: format!(
                "{} minus {} (blue: {} wheel less exposed)",
                fig.wheels[1], fig.wheels[0], fig.wheels[1]
            ),
            values: diff,
            range: (-max_abs, max_abs),
            cmap: maps::diverging,
            bar_label: "Difference [percentage points]".into(),
        },
    ]
}

/// The nominal tire's Hopf curves over each panel: each wheel's on its own panel, both on the
/// difference.
fn map_overlays(nominal: Option<&[polywear_study::chart::WheelCurves]>) -> [Vec<maps::Overlay>; 3] {
    let curves = |wheel: Wheel, color: plotters::style::RGBColor| -> Vec<maps::Overlay> {
        nominal
            .iter()
            .copied()
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
    let (white, black) = (plotters::style::WHITE, plotters::style::BLACK);
    [
        curves(Wheel::Follower, white),
        curves(Wheel::Driving, black),
        curves(Wheel::Follower, white)
            .into_iter()
            .chain(curves(Wheel::Driving, black))
            .collect(),
    ]
}

/// One risk map: the risk of vibration of the follower and the driving wheel in percent, side
/// by side, and the difference in percentage points (blue where the driving wheel is less
/// exposed); grey cells hold fewer than `min_count` classified rows. Small grids carry their
/// numbers in the cells. Each panel is [heatmap | colour bar, ticks and label on its right |
/// gap], so a bar's label never stands against the next panel's y-axis label.
pub fn risk_map(
    file: &FigureFile,
    map: &RiskMap,
    label: &dyn Fn(ParamId) -> String,
    min_count: u64,
    drivetrain: Drivetrain,
) -> Result<(), RenderError> {
    let words = MapWording {
        drivetrain,
        headline: "tread vibration (polygonal wear)".into(),
        what: "tread vibration".into(),
        bar_label: "Risk of vibration [%]",
        lines_note: "",
    };
    map_figure(file, map, &words, label, min_count)
}

/// Draws a risk map's three panels ([`risk_map`]) in the words of `words`, whatever its cells
/// count.
pub(crate) fn map_figure<C: RiskCounts>(
    file: &FigureFile,
    map: &RiskMap<C>,
    words: &MapWording,
    label: &dyn Fn(ParamId) -> String,
    min_count: u64,
) -> Result<(), RenderError> {
    let fig = MapFigure {
        x: (map.x, &map.x_bins),
        y: (map.y, &map.y_bins),
        p: [
            map.probability(Wheel::Follower, min_count),
            map.probability(Wheel::Driving, min_count),
        ],
        nominal: map.nominal.as_deref(),
        what: &words.what,
        wheels: Wheel::BOTH.map(|w| words.drivetrain.words(w)),
        bar_label: words.bar_label,
        title: format!(
            "Risk of {} over {} and {} ({} variant; {}grey: fewer than {min_count} samples)",
            words.headline,
            map.x.label().to_lowercase(),
            map.y.label().to_lowercase(),
            map.variant,
            words.lines_note,
        ),
    };
    let ((x, xb), (y, yb)) = (fig.x, fig.y);
    let overlays = map_overlays(fig.nominal);
    let panels = map_panels(&fig);
    let (xe, ye) = (draw_edges(xb), draw_edges(yb));
    plot::figure(file, (2100, 760), &fig.title, |area| {
        let parts = area.split_evenly((1, 3));
        for ((part, panel), overlay) in parts.iter().zip(&panels).zip(&overlays) {
            let width = part.dim_in_pixel().0 as i32;
            let (main, rest) = part.split_horizontally(width - RISK_MAP_BAR_PX - RISK_MAP_GAP_PX);
            let (bar, _gap) = rest.split_horizontally(RISK_MAP_BAR_PX);
            maps::heatmap(
                &main,
                &panel.title,
                &label(x),
                &label(y),
                &xe,
                &ye,
                &panel.values,
                panel.range,
                panel.cmap,
                overlay,
            )?;
            maps::colorbar(&bar, &panel.bar_label, panel.range, panel.cmap)?;
        }
        Ok(())
    })
    .map_err(RenderError::Figure)
}

/// Bars of the severity figure: the fine histogram summed into this many.
pub(crate) const SEVERITY_FIGURE_BINS: usize = 40;

/// Severity histograms of one variant: each quantity's share of vibrating rows per bin, per
/// wheel, in engineering units (µm, mm/s, µJ) with titles in words.
pub(crate) fn severity(
    file: &FigureFile,
    variant: Variant,
    severity: &[Severity],
) -> Result<(), RenderError> {
    plot::panels(
        file,
        (1400, 900),
        (2, 2),
        &format!(
            "How severe the vibration is ({variant} variant): share of vibrating rows per bin"
        ),
        |i, area| {
            let q = &SEVERITY_QUANTITIES[i];
            let sets: Vec<&Severity> = severity
                .iter()
                .filter(|s| s.variant == variant && s.quantity == q.name() && s.n > 0)
                .collect();
            if sets.is_empty() {
                return plot::line_panel(
                    area,
                    &format!("{}: no vibrating rows", q.title),
                    &q.label(),
                    "share of vibrating rows",
                    &[],
                    false,
                );
            }
            let series: Vec<Series<'_>> = sets
                .iter()
                .map(|s| Series {
                    label: s.wheel.as_str(),
                    points: histogram_steps(s, q.scale),
                })
                .collect();
            plot::line_panel(
                area,
                q.title,
                &q.label(),
                "share of vibrating rows",
                &series,
                false,
            )
        },
    )
    .map_err(RenderError::Figure)
}

/// The fine histogram summed into [`SEVERITY_FIGURE_BINS`] bars, as a step line of
/// (value × `scale`, share of rows).
fn histogram_steps(s: &Severity, scale: f64) -> Vec<(f64, f64)> {
    let per = s.counts.len().div_ceil(SEVERITY_FIGURE_BINS);
    let n = s.n.max(1) as f64;
    s.counts
        .chunks(per)
        .enumerate()
        .flat_map(|(b, c)| {
            let lo = s.hist.range(b * per).0;
            let hi = s
                .hist
                .range((b * per + c.len() - 1).min(s.counts.len() - 1))
                .1;
            let share = c.iter().sum::<u64>() as f64 / n;
            [(lo * scale, share), (hi * scale, share)]
        })
        .collect()
}
