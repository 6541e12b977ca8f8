//! The picture of an optimisation: the objective over the box (a map over two varied
//! parameters, a curve over one) with the nominal tire's stability boundaries, the settings
//! within the best's interval and the optimum marked.

use crate::plot::maps::Overlay;
use crate::plot::surface::{marker, surface_curve, surface_map, MapPoint, VLine};
use crate::plot::FigureFile;
use crate::plot::PlotError;
use polywear_core::model::Wheel;
use polywear_study::optimize::{Problem, Solution};

/// The figure shows the objective in %, as the text says it (`pct` in [`super::optimize`]).
const PERCENT: f64 = 100.0;

/// The picture: a map over two parameters with the nominal tire's Hopf curves, or a curve over
/// one with its Hopf points.
/// Draws the figure; false where no setting has an objective to draw.
pub(super) fn draw(
    problem: &Problem,
    solution: &Solution,
    file: &FigureFile,
) -> Result<bool, PlotError> {
    let axes = &problem.axes;
    let label = |k: usize| {
        polywear_core::params::axis_label(axes[k].param.name(), axes[k].param.spec().unit)
    };
    let title = format!(
        "{} over the study's samples (variant {})",
        problem.objective.text(),
        problem.variant
    );
    let best = solution.best.map(|b| &solution.settings[b]);
    if axes.len() == 1 {
        // Where no setting meets the constraints, the curve shows them all: the answer is a NaN
        // optimum, and the picture says how far the box is from meeting them.
        let any_feasible = solution
            .settings
            .iter()
            .any(|s| s.feasible && s.objective.value.is_finite());
        let mut pts: Vec<(f64, f64, f64, f64)> = solution
            .settings
            .iter()
            .filter(|s| (s.feasible || !any_feasible) && s.objective.value.is_finite())
            .map(|s| {
                (
                    s.values[0],
                    PERCENT * s.objective.value,
                    PERCENT * s.objective.low,
                    PERCENT * s.objective.high,
                )
            })
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        if pts.is_empty() {
            return Ok(false);
        }
        let lines = nominal_points(problem);
        surface_curve(
            file,
            &title,
            (&label(0), "objective [%]"),
            &pts,
            best.map(|s| (s.values[0], PERCENT * s.objective.value)),
            &lines,
        )?;
        return Ok(true);
    }
    let (xb, yb) = ((axes[0].lo, axes[0].hi), (axes[1].lo, axes[1].hi));
    let points: Vec<MapPoint> = solution
        .settings
        .iter()
        .map(|s| MapPoint {
            x: s.values[0],
            y: s.values[1],
            value: if s.feasible {
                PERCENT * s.objective.value
            } else {
                f64::NAN
            },
        })
        .collect();
    let mut overlay = nominal_curves(problem);
    let within: Vec<Vec<(f64, f64)>> = solution
        .within_best()
        .iter()
        .flat_map(|&i| {
            let s = &solution.settings[i];
            marker((s.values[0], s.values[1]), xb, yb, 0.008, false)
        })
        .collect();
    overlay.push(Overlay {
        label: "within the best's 95% interval".into(),
        color: plotters::style::RGBColor(255, 140, 0),
        lines: within,
    });
    if let Some(s) = best {
        overlay.push(Overlay {
            label: "optimum".into(),
            color: plotters::style::RGBColor(220, 20, 60),
            lines: marker((s.values[0], s.values[1]), xb, yb, 0.02, true),
        });
    }
    surface_map(
        file,
        &title,
        (&label(0), &label(1)),
        xb,
        yb,
        &points,
        &overlay,
        &format!("{} [%]", problem.objective.text()),
    )?;
    Ok(true)
}

/// The nominal tire's Hopf curves over the box (white: follower, black: driving wheel).
fn nominal_curves(problem: &Problem) -> Vec<Overlay> {
    let (x, y) = (&problem.axes[0], &problem.axes[1]);
    let curves = polywear_study::chart::nominal_curves(
        &problem.study,
        problem.variant,
        x.param.name(),
        y.param.name(),
        &[x.lo, x.hi],
        &[y.lo, y.hi],
    )
    .unwrap_or_default();
    curves
        .iter()
        .map(|c| Overlay {
            label: format!("{} stability boundary of the nominal tire", c.wheel),
            color: match c.wheel {
                Wheel::Follower => plotters::style::WHITE,
                Wheel::Driving => plotters::style::BLACK,
            },
            lines: c
                .curves
                .curves
                .iter()
                .map(|k| k.points.iter().map(|d| (d.p[0], d.p[1])).collect())
                .collect(),
        })
        .collect()
}

/// The nominal tire's stability boundaries along the one axis, as lines.
fn nominal_points(problem: &Problem) -> Vec<VLine> {
    problem
        .nominal_stability_changes()
        .into_iter()
        .map(|(wheel, x)| VLine {
            x,
            label: format!("{wheel} stability boundary of the nominal tire"),
            color: 2 + Wheel::BOTH.iter().position(|w| *w == wheel).unwrap_or(0),
        })
        .collect()
}
