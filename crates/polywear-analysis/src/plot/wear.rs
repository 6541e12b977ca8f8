//! The figure of `polywear wear`: per wheel, the tread's profile as an exaggerated polar plot
//! at a few distances, beside every harmonic's depth against distance with the visible depth
//! marked.

use super::{line_panel, panels, FigureFile, PlotError, Series};

/// One wheel of the figure.
pub struct WearTrace<'a> {
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

/// Draws the figure into `path` (PNG or SVG, as it says).
pub fn wear_figure(
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
                line_panel(area, &caption, "x", "y", &series, false)
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
                line_panel(
                    area,
                    &caption,
                    "distance [km]",
                    "depth [mm]",
                    &series,
                    false,
                )
            }
        },
    )
}
