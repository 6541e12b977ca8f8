//! The picture of a classified drive cycle: the speed trace with each wheel's vibrating
//! stretches marked beneath it, and the polygon order of the vibration over time.

use plotters::prelude::*;

use super::{draw_legend, figure, format_tick, tick_labels_for, FigureFile, PlotError, PALETTE};

/// What the figure shows of one wheel: its name and, per step, whether it vibrates and its
/// polygon order (NaN when it does not vibrate).
pub struct WheelTrace<'a> {
    /// The wheel's name in the legend.
    pub label: &'a str,
    /// Per step: whether the wheel vibrates.
    pub vibrates: Vec<bool>,
    /// Per step: the polygon order n = f / f_rot (NaN when not vibrating).
    pub polygon_order: Vec<f64>,
}

/// The radius of wheel `k`'s markers among `wheels` \[px\]: the first wheel's the largest,
/// each later one's smaller, so that a later wheel's marker drawn over an earlier one's at the
/// same step leaves it showing as a ring (the driving wheel vibrates only where the follower
/// does, and would hide it).
pub(crate) fn marker_radius(k: usize, wheels: usize) -> i32 {
    2 + 2 * (wheels.saturating_sub(k + 1)) as i32
}

/// Draws `time_s`/`speed_kmh` with one lane of vibrating stretches per wheel under the trace,
/// and the polygon order over time, into `file`.
pub fn cycle_figure(
    file: &FigureFile,
    title: &str,
    time_s: &[f64],
    speed_kmh: &[f64],
    wheels: &[WheelTrace<'_>],
) -> Result<(), PlotError> {
    figure(file, (1400, 900), title, |area| {
        let (top, bottom) = area.split_vertically(520);
        speed_panel(&top, time_s, speed_kmh, wheels)?;
        order_panel(&bottom, time_s, wheels)
    })
}

/// The time span of the trace.
fn span(time_s: &[f64]) -> (f64, f64) {
    let t0 = time_s.first().copied().unwrap_or(0.0);
    (t0, time_s.last().copied().unwrap_or(1.0).max(t0 + 1e-9))
}

/// The speed trace, coloured where each wheel vibrates, and one lane per wheel below 0 km/h
/// with its vibrating stretches.
fn speed_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    time_s: &[f64],
    speed_kmh: &[f64],
    wheels: &[WheelTrace<'_>],
) -> Result<(), PlotError> {
    let (t0, t1) = span(time_s);
    let v_max = speed_kmh.iter().copied().fold(1.0_f64, f64::max) * 1.08;
    // Each wheel's lane sits below 0 km/h: 8% of the speed axis per lane.
    let lane = 0.08 * v_max;
    let v_min = -lane * wheels.len() as f64 - 0.02 * v_max;
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(72)
        .build_cartesian_2d(t0..t1, v_min..v_max)
        .map_err(PlotError::from)?;
    chart
        .configure_mesh()
        .x_labels(tick_labels_for(area, 72, 12, (t0, t1), 14))
        .x_desc("time [s]")
        .y_desc("speed [km/h]")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .y_label_formatter(&|v| {
            if *v < 0.0 {
                String::new()
            } else {
                format_tick(*v)
            }
        })
        .draw()
        .map_err(PlotError::from)?;
    chart
        .draw_series(LineSeries::new(
            time_s.iter().copied().zip(speed_kmh.iter().copied()),
            BLACK.stroke_width(2),
        ))
        .map_err(PlotError::from)?
        .label("speed")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(3)));
    let n = time_s.len();
    let step_end = |i: usize| {
        if i + 1 < n {
            time_s[i + 1]
        } else {
            time_s[i] + (time_s[i] - time_s[i.saturating_sub(1)])
        }
    };
    for (k, w) in wheels.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let (y_hi, y_lo) = (-lane * k as f64 - 0.01 * v_max, -lane * (k + 1) as f64);
        let bars = (0..n)
            .filter(|&i| w.vibrates[i])
            .map(|i| {
                Rectangle::new(
                    [(time_s[i], y_lo), (step_end(i).min(t1), y_hi)],
                    color.filled(),
                )
            })
            .collect::<Vec<_>>();
        // The trace itself is marked where this wheel vibrates, each later wheel's markers
        // smaller ([`marker_radius`]).
        let r = marker_radius(k, wheels.len());
        let marked = (0..n)
            .filter(|&i| w.vibrates[i])
            .map(|i| Circle::new((time_s[i], speed_kmh[i]), r, color.filled()));
        chart.draw_series(marked).map_err(PlotError::from)?;
        chart
            .draw_series(bars)
            .map_err(PlotError::from)?
            .label(format!("{} vibrates (lane {})", w.label, k + 1))
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 18, y + 5)], color.filled()));
    }
    draw_legend(&mut chart)
}

/// The polygon order of each wheel's vibration over time, each later wheel's markers smaller.
fn order_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    time_s: &[f64],
    wheels: &[WheelTrace<'_>],
) -> Result<(), PlotError> {
    let (t0, t1) = span(time_s);
    let orders = wheels
        .iter()
        .flat_map(|w| w.polygon_order.iter().copied())
        .filter(|x| x.is_finite());
    let (o_lo, o_hi) = orders.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let (o_lo, o_hi) = if o_lo.is_finite() {
        ((o_lo - 1.0).floor(), (o_hi + 1.0).ceil())
    } else {
        (0.0, 1.0)
    };
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(72)
        .build_cartesian_2d(t0..t1, o_lo..o_hi)
        .map_err(PlotError::from)?;
    chart
        .configure_mesh()
        .x_labels(tick_labels_for(area, 72, 12, (t0, t1), 14))
        .x_desc("time [s]")
        .y_desc("polygon order n = f / f_rot")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .y_label_formatter(&|v| format_tick(*v))
        .draw()
        .map_err(PlotError::from)?;
    let n = time_s.len();
    for (k, w) in wheels.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let r = marker_radius(k, wheels.len());
        chart
            .draw_series(
                (0..n)
                    .filter(|&i| w.polygon_order[i].is_finite())
                    .map(|i| Circle::new((time_s[i], w.polygon_order[i]), r, color.filled())),
            )
            .map_err(PlotError::from)?
            .label(w.label)
            .legend(move |(x, y)| Circle::new((x + 9, y), r.max(3), color.filled()));
    }
    draw_legend(&mut chart)
}
