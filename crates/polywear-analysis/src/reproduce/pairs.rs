//! The six charts of the paper's four operating axes taken two at a time, both wheels, for
//! `polywear reproduce`: pictures, tables, and a report section that says where the driving
//! wheel's unstable region lies relative to the follower's and how the onset behaves.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::figures::chart::{draw, SHADE_CELLS};
use crate::plot::{FigureFile, FigureFormat, PlotError};
use polywear_core::continuation::trace::{SpecialKind, TraceOptions};
use polywear_core::continuation::ParamBox;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::{ParamId, Params};
use polywear_study::chart::{criticality, curve_columns, ChartRequest, WheelCurves};
use polywear_study::parquet_out::{write_table, WriteError};

/// Why a chart of the operating pairs was not written.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// The picture could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The table could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// One chart of two operating axes: the request, both wheels' curves and stability grids.
pub struct PairChart {
    /// The chart's parameters, axes and box.
    pub request: ChartRequest,
    /// Every Hopf curve of each wheel.
    pub curves: Vec<WheelCurves>,
    /// Each wheel's stability on a `SHADE_CELLS`² grid (the shading).
    pub grids: Vec<Vec<Option<bool>>>,
}

impl PairChart {
    /// The file stem, `chart_<x>_<y>`.
    pub fn stem(&self) -> String {
        format!("chart_{}_{}", self.request.x, self.request.y)
    }
}

/// Traces the six charts of `axes` (name, from, to) taken two at a time, both wheels.
pub(crate) fn solve_pairs(
    base: &Params,
    variant: Variant,
    axes: &[(ParamId, f64, f64)],
) -> Vec<PairChart> {
    let opts = TraceOptions::default();
    let mut out = Vec::new();
    for i in 0..axes.len() {
        for j in i + 1..axes.len() {
            let (x, y) = (axes[i], axes[j]);
            // The paper's axes are operating axes over accepted ranges, and no rule ties an
            // operating axis to another parameter: a valid base gives valid corners.
            let request = ChartRequest::new(
                *base,
                variant,
                Wheel::BOTH.to_vec(),
                (x.0, y.0),
                ParamBox {
                    lo: [x.1, y.1],
                    hi: [x.2, y.2],
                },
            )
            .expect("the paper's pairs of operating axes make a valid chart");
            let curves = request.trace(&opts);
            let grids = request
                .wheels
                .iter()
                .map(|&w| request.stability_grid(w, SHADE_CELLS, SHADE_CELLS))
                .collect();
            out.push(PairChart {
                request,
                curves,
                grids,
            });
        }
    }
    out
}

/// Draws the charts into `dir` as `chart_<x>_<y>.png` and `.parquet`; returns the files and
/// the report's Markdown section.
pub(crate) fn write_pairs(
    charts: &[PairChart],
    dir: &Path,
) -> Result<(Vec<PathBuf>, String), ChartError> {
    let mut files = Vec::new();
    let mut md = String::new();
    let variant = charts
        .first()
        .map_or(Variant::DEFAULT, |c| c.request.variant);
    let _ = writeln!(
        md,
        "## Stability charts: the boundary in two operating parameters at a time\n\n\
         Each chart traces every Hopf curve of both wheels (`{variant}` variant) in the plane of \
         two operating parameters, the other two at their values in `polywear params`, by \
         pseudo-arclength continuation (`polywear chart`). Along the curves the first Lyapunov \
         coefficient l1 says whether vibration sets in softly (supercritical, l1 < 0) or jumps \
         to a large cycle that persists outside the region (subcritical, l1 > 0).\n\n\
         | chart | follower: curves | driving: curves | driving region inside the follower's | onset |\n\
         |---|---|---|---|---|"
    );
    for chart in charts {
        let (req, stem) = (&chart.request, chart.stem());
        let picture = FigureFile::named(dir, &stem, FigureFormat::Png);
        draw(&picture, req, &chart.curves, &chart.grids, None)?;
        let pq = dir.join(format!("{stem}.parquet"));
        let meta = vec![
            (
                "polywear_version".into(),
                polywear_study::provenance::POLYWEAR_VERSION.into(),
            ),
            ("variant".into(), req.variant.as_str().into()),
            (
                "params".into(),
                serde_json::to_string(&req.base).expect("json"),
            ),
            ("chart_x".into(), req.x.name().into()),
            ("chart_y".into(), req.y.name().into()),
        ];
        write_table(&pq, &curve_columns(req, &chart.curves), &meta)?;
        let _ = writeln!(
            md,
            "| [{stem}]({stem}.png) | {} | {} | {} | {} |",
            describe(&chart.curves, Wheel::Follower),
            describe(&chart.curves, Wheel::Driving),
            inside(&chart.grids),
            onset(&chart.curves, req)
        );
        files.push(picture.path);
        files.push(pq);
    }
    let _ = writeln!(
        md,
        "\nA closed curve is an island: the region it encloses touches no edge of the box. Where \
         the driving wheel's region lies inside the follower's, every operating point that makes \
         the driving wheel vibrate makes the follower vibrate too: the paper's conclusion that \
         the driving wheel is the safer one, seen in the plane.\n"
    );
    Ok((files, md))
}

fn describe(charts: &[WheelCurves], wheel: Wheel) -> String {
    let Some(c) = charts.iter().find(|c| c.wheel == wheel) else {
        return "-".into();
    };
    let n = c.curves.curves.len();
    let closed = c.curves.curves.iter().filter(|k| k.closed).count();
    match (n, closed) {
        (0, _) => "none".into(),
        (n, 0) => format!("{n}, ending on the box"),
        (n, c) if c == n => format!("{n}, closed (an island)"),
        (n, c) => format!("{n} ({c} closed)"),
    }
}

/// Share of the driving wheel's unstable cells where the follower is unstable too.
fn inside(grids: &[Vec<Option<bool>>]) -> String {
    let (f, d) = (&grids[0], &grids[1]);
    let driving: Vec<usize> = (0..d.len()).filter(|k| d[*k] == Some(true)).collect();
    if driving.is_empty() {
        return "driving wheel stable throughout".into();
    }
    let both = driving.iter().filter(|k| f[**k] == Some(true)).count();
    let share = both as f64 / driving.len() as f64;
    if both == driving.len() {
        "yes, entirely".into()
    } else {
        format!("{:.1}% of it", 100.0 * share)
    }
}

fn onset(charts: &[WheelCurves], req: &ChartRequest) -> String {
    let mut parts = Vec::new();
    for c in charts {
        let pts: Vec<f64> = c
            .curves
            .curves
            .iter()
            .flat_map(|k| k.points.iter().map(|d| d.l1))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let sub = pts.iter().filter(|l| **l > 0.0).count();
        let text = if sub == 0 {
            criticality(-1.0).to_string()
        } else if sub == pts.len() {
            criticality(1.0).to_string()
        } else {
            let bautin: Vec<String> = c
                .curves
                .special
                .iter()
                .filter(|s| s.kind == SpecialKind::Bautin)
                .map(|s| {
                    format!(
                        "{} = {:.4}, {} = {:.4}",
                        req.x.name(),
                        s.p[0],
                        req.y.name(),
                        s.p[1]
                    )
                })
                .collect();
            format!(
                "subcritical on {:.0}% of the curve; Bautin at {}",
                100.0 * sub as f64 / pts.len() as f64,
                bautin.join("; ")
            )
        };
        parts.push(format!("{}: {text}", c.wheel));
    }
    if parts.is_empty() {
        "-".into()
    } else {
        parts.join("; ")
    }
}
