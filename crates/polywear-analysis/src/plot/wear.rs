//! The figure of `polywear wear`: per wheel, the tread's profile as an exaggerated polar plot
//! at a few distances, beside every harmonic's depth against distance with the visible depth
//! marked.

use plotters::style::{RGBColor, BLACK};

use super::maps::viridis;
use super::{line_panel_coloured, panels, FigureFile, PlotError, Series};

/// One wheel of the figure.
pub(crate) struct WearTrace<'a> {
    /// The wheel's name.
    pub wheel: &'a str,
    /// The depth profile d(θ) \[m\] at distances \[km\].
    pub profiles: &'a [(f64, Vec<f64>)],
    /// (order, points (distance \[km\], depth D_n \[mm\])) of the orders drawn.
    pub depths: Vec<(u32, Vec<(f64, f64)>)>,
    /// The visible depth d_visible \[mm\].
    pub visible_mm: f64,
}

/// The radius of the polar plot's unit circle that the profile's largest deviation spans.
const EXAGGERATION_SHARE: f64 = 0.3;

/// The profile as a closed (x, y) curve: radius 1 + k·r(θ), k scaled so that the deepest
/// deviation of all `profiles` spans [`EXAGGERATION_SHARE`] of the circle.
fn polar_points(depth_m: &[f64], scale: f64) -> Vec<(f64, f64)> {
    let m = depth_m.len();
    let mean = depth_m.iter().sum::<f64>() / m as f64;
    (0..=m)
        .map(|i| {
            let k = i % m;
            let theta = std::f64::consts::TAU * (k as f64 + 0.5) / m as f64;
            let radius = 1.0 - scale * (depth_m[k] - mean);
            (radius * theta.cos(), radius * theta.sin())
        })
        .collect()
}

/// The orders' colours: warm ones, none on the profiles' dark-to-light sequence
/// ([`viridis`]), so that no legend entry of the figure shares a colour with another.
const ORDER_COLOURS: [RGBColor; 4] = [
    RGBColor(255, 127, 14),
    RGBColor(214, 39, 40),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
];

/// Draws the figure into `path` (PNG or SVG, as it says).
pub(crate) fn wear_figure(
    path: &FigureFile,
    title: &str,
    wheels: &[WearTrace<'_>],
) -> Result<(), PlotError> {
    let deepest = wheels
        .iter()
        .flat_map(|w| w.profiles.iter())
        .map(|(_, d)| {
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            d.iter().fold(0.0f64, |m, x| m.max((x - mean).abs()))
        })
        .fold(0.0f64, f64::max);
    let scale = if deepest > 0.0 {
        EXAGGERATION_SHARE / deepest
    } else {
        0.0
    };
    panels(
        path,
        (1400, 700 * wheels.len() as u32),
        (wheels.len(), 2),
        title,
        |i, area| {
            let w = &wheels[i / 2];
            if i % 2 == 0 {
                let labels: Vec<String> = w
                    .profiles
                    .iter()
                    .map(|(km, _)| format!("{km:.0} km"))
                    .collect();
                let series: Vec<Series> = w
                    .profiles
                    .iter()
                    .zip(&labels)
                    .map(|((_, d), label)| Series {
                        label,
                        points: polar_points(d, scale),
                    })
                    .collect();
                let caption = format!(
                    "{}: profile, radius exaggerated ({:.0} µm = 30% of the circle)",
                    w.wheel,
                    deepest * 1e6
                );
                // A sequence by distance, dark to light, in colours the depth panel never uses.
                let last = (series.len().max(2) - 1) as f64;
                let colours: Vec<RGBColor> = (0..series.len())
                    .map(|k| viridis(0.85 * k as f64 / last))
                    .collect();
                line_panel_coloured(area, &caption, ("x", "y"), &series, &colours)
            } else {
                let labels: Vec<String> =
                    w.depths.iter().map(|(n, _)| format!("order {n}")).collect();
                let mut series: Vec<Series> = w
                    .depths
                    .iter()
                    .zip(&labels)
                    .map(|((_, pts), label)| Series {
                        label,
                        points: pts.clone(),
                    })
                    .collect();
                let end = w
                    .depths
                    .iter()
                    .flat_map(|(_, p)| p.last())
                    .fold(0.0f64, |m, p| m.max(p.0));
                series.push(Series {
                    label: "visible depth",
                    points: vec![(0.0, w.visible_mm), (end, w.visible_mm)],
                });
                let caption = format!("{}: depth peak-to-valley", w.wheel);
                // The orders in warm colours, the visible depth black after them.
                let mut colours: Vec<RGBColor> = (0..series.len() - 1)
                    .map(|k| ORDER_COLOURS[k % ORDER_COLOURS.len()])
                    .collect();
                colours.push(BLACK);
                line_panel_coloured(
                    area,
                    &caption,
                    ("distance [km]", "depth [mm]"),
                    &series,
                    &colours,
                )
            }
        },
    )
}
