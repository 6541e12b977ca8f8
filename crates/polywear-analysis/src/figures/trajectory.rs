//! The figure the paper shows for one point: time history, phase portrait and spectrum of the
//! lateral velocity (its Figs. 8–10), from [`polywear_study::trajectory`]'s samples.

use polywear_core::model::Wheel;
use polywear_core::records::WheelRecord;
use polywear_study::trajectory::Samples;

use crate::plot::{self, FigureFile, PlotError, Series};

/// One panel of [`plot_point`]: title, axis labels, and the curve it draws from a wheel's
/// samples (displacements about the equilibrium) at the given sample rate \[Hz\].
type PointPanel = (
    &'static str,
    &'static str,
    &'static str,
    fn(&Samples, f64) -> Vec<(f64, f64)>,
);

/// The four panels of the paper's Figs. 8–10 for one point.
const POINT_PANELS: [PointPanel; 4] = [
    ("Lateral velocity", "t [s]", "v [m/s]", velocity),
    (
        "Lateral displacement, last 50 ms",
        "t [s]",
        "y - y0 [m]",
        displacement_tail,
    ),
    (
        "Phase portrait (second half)",
        "y - y0 [m]",
        "v [m/s]",
        phase_portrait,
    ),
    (
        "Spectrum of v (second half)",
        "frequency [Hz]",
        "amplitude [m/s]",
        velocity_spectrum,
    ),
];

fn velocity(s: &Samples, _: f64) -> Vec<(f64, f64)> {
    s.iter().map(|x| (x.0, x.1[2])).collect()
}

fn displacement_tail(s: &Samples, _: f64) -> Vec<(f64, f64)> {
    let t_end = s.last().map_or(0.0, |x| x.0);
    s.iter()
        .filter(|x| x.0 >= t_end - 0.05)
        .map(|x| (x.0, x.1[1]))
        .collect()
}

fn phase_portrait(s: &Samples, _: f64) -> Vec<(f64, f64)> {
    let t_end = s.last().map_or(0.0, |x| x.0);
    s.iter()
        .filter(|x| x.0 >= t_end * 0.5)
        .map(|x| (x.1[1], x.1[2]))
        .collect()
}

fn velocity_spectrum(s: &Samples, sample_rate: f64) -> Vec<(f64, f64)> {
    let half: Vec<f64> = s[s.len() / 2..].iter().map(|x| x.1[2]).collect();
    plot::spectrum::amplitude_spectrum(&half, sample_rate)
        .into_iter()
        .filter(|(f, _)| *f <= 1000.0)
        .collect()
}

/// Time history, displacement detail, phase portrait and spectrum for the given wheels.
pub fn plot_point(
    file: &FigureFile,
    series: &[(Wheel, Samples)],
    records: &[WheelRecord],
    sample_rate: f64,
) -> Result<(), PlotError> {
    let r0 = records.first().ok_or(PlotError::Empty)?;
    let title = format!(
        "{} km/h, toe {} deg, {} N, {} kPa ({} variant)",
        r0.speed_kmh, r0.toe_deg, r0.load_n, r0.pressure_kpa, r0.variant
    );
    let record = |w: Wheel| records.iter().find(|r| r.wheel == w);
    let labels: Vec<String> = series
        .iter()
        .map(|(w, _)| format!("{w} ({})", record(*w).map_or("", |r| r.class.as_str())))
        .collect();
    // Displacements are drawn about each wheel's equilibrium y0.
    let series: Vec<Samples> = series
        .iter()
        .map(|(w, s)| {
            let y0 = record(*w).map_or(0.0, |r| r.y0_m);
            s.iter()
                .map(|(t, x)| (*t, [x[0], x[1] - y0, x[2]]))
                .collect()
        })
        .collect();
    plot::panels(file, (1500, 1000), (2, 2), &title, |i, area| {
        let (panel_title, x_label, y_label, curve) = POINT_PANELS[i];
        let curves: Vec<Series<'_>> = series
            .iter()
            .zip(&labels)
            .map(|(s, l)| Series {
                label: l,
                points: curve(s, sample_rate),
            })
            .collect();
        plot::line_panel(area, panel_title, x_label, y_label, &curves, false)
    })
}
