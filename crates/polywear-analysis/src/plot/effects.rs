//! Effects with their intervals (a forest plot): one row per effect, its estimate as a dot and
//! its 95% interval as a bar, against a line at zero; one panel per outcome.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{format_tick, FigureFile, PlotError, PALETTE};

/// One effect: a labelled estimate with its interval, in a colour of [`PALETTE`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Effect {
    /// The row's label (e.g. the scenario's name).
    pub label: String,
    /// The index of its colour in [`PALETTE`] (e.g. the wheel).
    pub color: usize,
    /// The estimate.
    pub estimate: f64,
    /// The interval's lower end.
    pub lo: f64,
    /// Its upper end.
    pub hi: f64,
}

/// One panel of effects.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct EffectPanel {
    /// The panel's title.
    pub title: String,
    /// The x axis' label.
    pub x_label: String,
    /// The effects, top to bottom.
    pub effects: Vec<Effect>,
}

/// Draws `panels` side by side into `file`; the title says what
/// the colours are.
pub(crate) fn effects_figure(
    file: &FigureFile,
    title: &str,
    panels: &[EffectPanel],
) -> Result<(), PlotError> {
    let rows = panels.iter().map(|p| p.effects.len()).max().unwrap_or(0);
    if rows == 0 {
        return Err(PlotError::Empty);
    }
    let size = (
        (760 * panels.len() as u32).max(1100),
        140 + 34 * rows as u32,
    );
    super::figure(file, size, title, |area| {
        for (panel, part) in panels.iter().zip(area.split_evenly((1, panels.len()))) {
            draw_panel(&part, panel, rows)?;
        }
        Ok(())
    })
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &EffectPanel,
    rows: usize,
) -> Result<(), PlotError> {
    let (lo, hi) = panel
        .effects
        .iter()
        .flat_map(|e| [e.lo, e.hi, e.estimate])
        .filter(|x| x.is_finite())
        .fold((0.0f64, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    let pad = 0.08 * (hi - lo).max(1e-9);
    let label_width = 16
        + 8 * panel
            .effects
            .iter()
            .map(|e| e.label.chars().count())
            .max()
            .unwrap_or(0)
            .min(40) as u32;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(48)
        .y_label_area_size(label_width)
        .build_cartesian_2d(lo - pad..hi + pad, -0.5..rows as f64 - 0.5)
        .map_err(PlotError::from)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .disable_y_axis()
        .x_desc(panel.x_label.as_str())
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .x_label_formatter(&|v| format_tick(*v))
        .light_line_style(WHITE)
        .draw()
        .map_err(PlotError::from)?;
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(0.0, -0.5), (0.0, rows as f64 - 0.5)],
            BLACK.stroke_width(1),
        )))
        .map_err(PlotError::from)?;
    // Row k from the top.
    let y = |k: usize| (rows - 1 - k) as f64;
    for (k, e) in panel.effects.iter().enumerate() {
        let color = PALETTE[e.color % PALETTE.len()];
        if e.lo.is_finite() && e.hi.is_finite() {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(e.lo, y(k)), (e.hi, y(k))],
                    color.stroke_width(3),
                )))
                .map_err(PlotError::from)?;
        }
        if e.estimate.is_finite() {
            chart
                .draw_series(std::iter::once(Circle::new(
                    (e.estimate, y(k)),
                    5,
                    color.filled(),
                )))
                .map_err(PlotError::from)?;
        }
        let style = ("sans-serif", 14)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Right, VPos::Center));
        // The chart's pixels are the figure's; the panel's text is placed relative to it.
        let at = chart.backend_coord(&(lo - pad, y(k)));
        let base = area.get_base_pixel();
        let at = (at.0 - base.0 - 6, at.1 - base.1);
        area.draw(&Text::new(e.label.clone(), at, style))
            .map_err(PlotError::from)?;
    }
    Ok(())
}
