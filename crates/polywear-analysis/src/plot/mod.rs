//! Figures with plotters, PNG or SVG ([`FigureFormat`]): what the paper shows for one point
//! (time history, phase portrait, spectrum: its Figs. 8–10) and bifurcation diagrams (its Figs. 6,
//! 7, 12, ...).

use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use backend::{FigureBackend, FigureBuffer};
pub use format::{FigureFile, FigureFormat};

pub(crate) mod backend;
pub mod cycle;
pub(crate) mod effects;
mod format;
pub(crate) mod maps;
pub(crate) mod spectrum;
pub(crate) mod surface;
pub(crate) mod wear;

/// One curve of a figure, in a colour picked by the caller.
pub(crate) struct Series<'a> {
    /// The legend's label.
    pub label: &'a str,
    /// (x, y) points, in order.
    pub points: Vec<(f64, f64)>,
}

/// The embedded font (DejaVu Sans, Bitstream Vera licence) so plots need no system fonts.
static FONT: &[u8] = include_bytes!("DejaVuSans.ttf");
static FONT_ONCE: Once = Once::new();

fn ensure_font() {
    FONT_ONCE.call_once(|| {
        // Plotters keeps its font table globally; register ours once per process.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// The colours of a figure's series, in order.
pub(crate) const PALETTE: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// Why a figure was not drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlotError {
    /// plotters refused to draw (its own message: a backend or font error).
    #[error("{0}")]
    Draw(String),
    /// A figure file could not be drawn or written.
    #[error("{}: {message}", path.display())]
    Figure {
        /// The figure file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// No series to draw.
    #[error("nothing to plot")]
    Empty,
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(e.to_string())
    }
}

/// For callers whose errors are still messages.
impl From<PlotError> for String {
    fn from(e: PlotError) -> Self {
        e.to_string()
    }
}

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Figure {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Padded bounds of all series' points.
fn bounds<'a>(series: impl Iterator<Item = &'a (f64, f64)> + Clone) -> ((f64, f64), (f64, f64)) {
    let fold = |f: fn(&(f64, f64)) -> f64| {
        series
            .clone()
            .map(f)
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    let pad = |(lo, hi): (f64, f64)| {
        if !lo.is_finite() {
            return (0.0, 1.0);
        }
        let span = if hi > lo {
            hi - lo
        } else {
            lo.abs().max(1e-12)
        };
        (lo - 0.05 * span, hi + 0.05 * span)
    };
    (pad(fold(|p| p.0)), pad(fold(|p| p.1)))
}

/// Draws line series into one panel with axis labels and a legend.
pub(crate) fn line_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series<'_>],
    points_only: bool,
) -> Result<(), PlotError> {
    line_panel_with(
        area,
        title,
        x_label,
        y_label,
        series,
        points_only,
        None,
        false,
    )
}

/// [`line_panel`] with a colour per series, given by the caller (one colour per legend entry
/// across a figure's panels, where the palette's cycle would repeat one).
pub(crate) fn line_panel_coloured<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    labels: (&str, &str),
    series: &[Series<'_>],
    colours: &[RGBColor],
) -> Result<(), PlotError> {
    let colour = |i: usize| colours[i % colours.len()];
    let (x_label, y_label) = labels;
    draw_lines(
        area, title, x_label, y_label, series, false, None, false, &colour,
    )
}

/// [`line_panel`] with a fixed y range (points outside it are clipped) and, when `zero_line`,
/// a dashed line at y = 0 (where an eigenvalue's real part changes sign).
#[allow(clippy::too_many_arguments)]
pub(crate) fn line_panel_with<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series<'_>],
    points_only: bool,
    y_range: Option<(f64, f64)>,
    zero_line: bool,
) -> Result<(), PlotError> {
    let colour = |i: usize| PALETTE[i % PALETTE.len()];
    let (range, zero) = (y_range, zero_line);
    draw_lines(
        area,
        title,
        x_label,
        y_label,
        series,
        points_only,
        range,
        zero,
        &colour,
    )
}

/// The drawing of [`line_panel_with`], series `i` in `colour(i)`.
#[allow(clippy::too_many_arguments)]
fn draw_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series<'_>],
    points_only: bool,
    y_range: Option<(f64, f64)>,
    zero_line: bool,
    colour: &dyn Fn(usize) -> RGBColor,
) -> Result<(), PlotError> {
    let ((x0, x1), (mut y0, mut y1)) = bounds(series.iter().flat_map(|s| s.points.iter()));
    if let Some(r) = y_range {
        (y0, y1) = r;
    }
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(72)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(PlotError::from)?;
    chart
        .configure_mesh()
        .x_labels(tick_labels_for(area, 72, 12, (x0, x1), 14))
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .y_label_formatter(&|v| format_tick(*v))
        .x_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(PlotError::from)?;
    if zero_line && y0 < 0.0 && y1 > 0.0 {
        chart
            .draw_series(DashedLineSeries::new(
                [(x0, 0.0), (x1, 0.0)],
                8,
                5,
                BLACK.stroke_width(1),
            ))
            .map_err(PlotError::from)?;
    }
    // Clipped to the panel: a fixed y range may leave points outside it.
    let inside = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && p.1 >= y0 && p.1 <= y1;
    for (i, s) in series.iter().enumerate() {
        let color = colour(i);
        let anno = if points_only {
            chart
                .draw_series(
                    s.points
                        .iter()
                        .filter(|p| inside(p))
                        .map(|p| Circle::new(*p, 2, color.filled())),
                )
                .map_err(PlotError::from)?
        } else {
            let finite: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            // Consecutive clipped segments joined into one path each, so that an SVG holds one
            // polyline per unbroken stretch rather than one element per segment.
            let mut paths: Vec<Vec<(f64, f64)>> = Vec::new();
            for (a, b) in finite
                .windows(2)
                .filter_map(|w| clip_segment(w[0], w[1], y0, y1))
            {
                match paths.last_mut() {
                    Some(path) if path.last() == Some(&a) => path.push(b),
                    _ => paths.push(vec![a, b]),
                }
            }
            chart
                .draw_series(
                    paths
                        .into_iter()
                        .map(|path| PathElement::new(path, color.stroke_width(2))),
                )
                .map_err(PlotError::from)?
        };
        anno.label(s.label).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(3))
        });
    }
    if series.len() > 1 || series.first().is_some_and(|s| !s.label.is_empty()) {
        draw_legend(&mut chart)?;
    }
    Ok(())
}

/// The legend every line figure uses: upper right, on white, framed.
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
) -> Result<(), PlotError> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(PlotError::from)
}

/// The part of the segment a–b with y in [y0, y1] (None when it lies wholly outside), so that
/// a curve leaving a fixed y range is cut at the edge instead of drawn along it.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    y0: f64,
    y1: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let at = |y: f64| (a.0 + (b.0 - a.0) * (y - a.1) / (b.1 - a.1), y);
    let clip = |p: (f64, f64)| {
        if p.1 < y0 {
            at(y0)
        } else if p.1 > y1 {
            at(y1)
        } else {
            p
        }
    };
    let out = |p: (f64, f64)| (p.1 < y0, p.1 > y1);
    let (oa, ob) = (out(a), out(b));
    if (oa.0 && ob.0) || (oa.1 && ob.1) {
        return None;
    }
    Some((clip(a), clip(b)))
}

/// plotters' default number of tick labels per axis, the most any axis asks for.
pub(crate) const MAX_TICK_LABELS: usize = 10;

/// The most tick labels (up to [`MAX_TICK_LABELS`]) along a horizontal axis over `range`,
/// `width_px` long, whose texts ([`format_tick`] in the embedded font at `font_px`) stand apart
/// by at least half a character height: scientific labels of a narrow panel (`3.10e7`) would
/// otherwise run together. plotters picks at most this many round values.
pub(crate) fn fitting_tick_labels(range: (f64, f64), width_px: u32, font_px: u32) -> usize {
    use plotters::coord::ranged1d::Ranged;
    ensure_font();
    let (lo, hi) = range;
    if hi.is_nan() || lo.is_nan() || hi <= lo || width_px == 0 {
        return MAX_TICK_LABELS;
    }
    let font = ("sans-serif", font_px).into_font();
    let width_of = |v: f64| font.box_size(&format_tick(v)).map_or(0.0, |b| b.0 as f64);
    let gap = 0.5 * font_px as f64;
    (2..=MAX_TICK_LABELS)
        .rev()
        .find(|&n| {
            let keys = RangedCoordf64::from(lo..hi).key_points(n);
            let at = |v: f64| (v - lo) / (hi - lo) * width_px as f64;
            keys.windows(2)
                .all(|w| at(w[1]) - at(w[0]) >= 0.5 * (width_of(w[0]) + width_of(w[1])) + gap)
        })
        .unwrap_or(2)
}

/// [`fitting_tick_labels`] for a chart built on `area` with a y label area of
/// `y_label_area_px` and `margin_px` on each side.
pub(crate) fn tick_labels_for<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    y_label_area_px: u32,
    margin_px: u32,
    range: (f64, f64),
    font_px: u32,
) -> usize {
    let width = area
        .dim_in_pixel()
        .0
        .saturating_sub(y_label_area_px + 2 * margin_px);
    fitting_tick_labels(range, width, font_px)
}

/// Tick label: plain for ordinary magnitudes, scientific for very small or large ones.
pub(crate) fn format_tick(v: f64) -> String {
    let a = v.abs();
    if a < 1e-15 {
        return "0".into();
    }
    if !(9.99e-3..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    // Four significant digits, trailing zeros trimmed.
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A figure with a title, drawn in the file's format and written to its path; `draw` lays out
/// and draws the area under the title.
pub(crate) fn figure(
    file: &FigureFile,
    size: (u32, u32),
    title: &str,
    draw: impl FnOnce(&DrawingArea<FigureBackend<'_>, plotters::coord::Shift>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    ensure_font();
    let path = file.path.as_path();
    let mut buffer = FigureBuffer::new(file.format, size);
    {
        let root = buffer.backend().into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(path, e))?;
        let area = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| err(path, e))?;
        draw(&area).map_err(|e| err(path, e))?;
        root.present().map_err(|e| err(path, e))?;
    }
    let bytes = buffer.into_bytes().map_err(|e| err(path, e))?;
    polywear_study::safe_write::write_file(path, &bytes).map_err(|e| err(path, e))
}

/// A figure of several panels laid out in a grid, each drawn by `draw`.
pub(crate) fn panels(
    file: &FigureFile,
    size: (u32, u32),
    grid: (usize, usize),
    title: &str,
    mut draw: impl FnMut(
        usize,
        &DrawingArea<FigureBackend<'_>, plotters::coord::Shift>,
    ) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    figure(file, size, title, |area| {
        for (i, a) in area.split_evenly(grid).iter().enumerate() {
            draw(i, a)?;
        }
        Ok(())
    })
}
