//! The figure of a one-parameter sweep (`polywear bifurcation`, the paper's Figs. 6-7 and 12-17).

use polywear_core::model::Wheel;
use polywear_core::records::WheelRecord;
use polywear_study::bifurcation::Sweep;

use crate::plot::{self, FigureFile, PlotError, Series};

/// Half-height of the zoomed eigenvalue panel: twice the largest |Re λ| at the sweep values
/// next to a sign change (so each crossing is seen with its neighbours), or twice the smallest
/// |Re λ| when there is none (how close the sweep comes to a Hopf point).
fn zoom_half_height(pts: &[(Wheel, Vec<(f64, f64)>)]) -> f64 {
    let mut near = 0.0f64;
    let mut closest = f64::INFINITY;
    for (_, p) in pts {
        for w in p.windows(2) {
            let (a, b) = (w[0].1, w[1].1);
            if a.is_finite() && b.is_finite() && (a < 0.0) != (b < 0.0) {
                near = near.max(a.abs()).max(b.abs());
            }
        }
        for q in p.iter().filter(|q| q.1.is_finite()) {
            closest = closest.min(q.1.abs());
        }
    }
    let h = if near > 0.0 { near } else { closest };
    if h.is_finite() && h > 0.0 {
        2.0 * h
    } else {
        1.0
    }
}

/// Points drawn for one sweep value and its record.
type PointsOf = dyn Fn(f64, &WheelRecord) -> Vec<(f64, f64)>;

/// Draws the paper's two views of a sweep: Re λ against the parameter (in full, and zoomed on
/// zero where the Hopf points are), and the limit-cycle envelope, into `file`.
pub fn draw(file: &FigureFile, sw: &Sweep) -> Result<(), PlotError> {
    let (name, unit, variant) = (sw.param.name(), sw.unit, sw.variant);
    let (jobs, records) = (&sw.jobs, &sw.records);
    let per_wheel = |f: &PointsOf| -> Vec<(Wheel, Vec<(f64, f64)>)> {
        Wheel::BOTH
            .iter()
            .map(|&w| {
                let pts = jobs
                    .iter()
                    .zip(records)
                    .filter(|(j, _)| j.1 == w)
                    .flat_map(|(j, r)| f(j.0, r))
                    .collect();
                (w, pts)
            })
            .collect()
    };
    let eig = per_wheel(&|x, r| vec![(x, r.eig_re_max)]);
    let amp = per_wheel(&|x, r| vec![(x, r.amp_y_m * 1e3), (x, -r.amp_y_m * 1e3)]);
    let zoom = zoom_half_height(&eig);
    let windows: Vec<String> = Wheel::BOTH
        .iter()
        .flat_map(|&w| sw.windows_in_words(w))
        .collect();
    let title = format!(
        "{} sweep at {} ({variant} variant)",
        sw.param.label(),
        sw.held_fixed(),
    );
    let zoom_title = format!("Zoomed on zero: {}", windows.join("; "));
    let x_label = polywear_core::params::axis_label(name, unit);
    plot::panels(file, (1400, 1500), (3, 1), &title, |i, area| {
        let (data, title, y, points, range) = match i {
            0 => (
                &eig,
                "Growth rate of a disturbance: real part of the leading eigenvalue (above 0: vibrates)",
                "max Re(lambda) [1/s]",
                false,
                None,
            ),
            1 => (
                &eig,
                zoom_title.as_str(),
                "max Re(lambda) [1/s]",
                false,
                Some((-zoom, zoom)),
            ),
            _ => (
                &amp,
                "Limit-cycle envelope of y - y0 (Figs. 7, 12, 14, 16)",
                "+/- amplitude of y [mm]",
                true,
                None,
            ),
        };
        let series: Vec<Series<'_>> = data
            .iter()
            .map(|(w, pts)| Series {
                label: w.as_str(),
                points: pts.clone(),
            })
            .collect();
        plot::line_panel_with(area, title, &x_label, y, &series, points, range, i < 2)
    })
}
