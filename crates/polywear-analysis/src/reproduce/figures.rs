//! The files of a [`Reproduction`]: the paper's figures (PNG or SVG), the tables (Parquet, CSV)
//! and `report.md`, written in the order the report lists them.

use std::path::{Path, PathBuf};

use super::pairs::write_pairs;
use super::report::report;
use super::{ReproduceError, Reproduction, ADHESION_ANGLES_DEG};
use crate::figures::trajectory::plot_point;
use crate::plot::{self, FigureFile, FigureFormat, Series};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::records::{record_columns, WheelRecord};
use polywear_study::parquet_out::{write_csv, write_table, Column};

/// Writes every figure and table of `r` into `dir` (created if missing), figures in `format`
/// (the stability charts in PNG), then `report.md`; returns the files in that order.
pub(crate) fn write(
    r: &Reproduction,
    dir: &Path,
    format: FigureFormat,
) -> Result<Vec<PathBuf>, ReproduceError> {
    polywear_study::safe_write::create_dir(dir).map_err(|e| ReproduceError::io(dir, e))?;
    let mut files = Vec::new();
    adhesion_ellipse(r, dir, format, &mut files)?;
    for sw in &r.sweeps {
        let stem = format!("bifurcation_{}_{}", sw.param, sw.variant);
        let picture = FigureFile::named(dir, &stem, format);
        crate::figures::bifurcation::draw(&picture, sw).map_err(ReproduceError::Figure)?;
        files.push(picture.path);
    }
    files.push(bifurcation_table(r, dir)?);
    // Fig. 18: the cycle amplitude against speed, follower beside the driving wheel of each
    // variant (the follower is the same in every variant).
    amplitude_vs_speed(r, dir, format, &mut files)?;
    // Figs. 8–10, 13, 15, 17, 19: both wheels in each figure.
    for run in &r.points {
        let picture = FigureFile::named(dir, run.point.stem(), format);
        plot_point(&picture, &run.series, &run.records, 20_000.0)
            .map_err(ReproduceError::Figure)?;
        files.push(picture.path);
    }
    let (chart_files, charts_md) = write_pairs(&r.charts, dir).map_err(ReproduceError::Chart)?;
    files.extend(chart_files);
    let text = report(r, &charts_md, &files);
    let md = dir.join("report.md");
    polywear_study::safe_write::write_file(&md, text.as_bytes())
        .map_err(|e| ReproduceError::io(&md, e))?;
    files.push(md);
    Ok(files)
}

/// Every sweep's rows in one table, with the swept parameter and value of each.
fn bifurcation_table(r: &Reproduction, dir: &Path) -> Result<PathBuf, ReproduceError> {
    let sweeps = &r.sweeps;
    let mut cols = vec![
        Column::str(
            "sweep_param",
            sweeps
                .iter()
                .flat_map(|s| s.jobs.iter().map(|_| s.param.to_string()))
                .collect(),
        ),
        Column::f64(
            "sweep_value",
            "",
            sweeps
                .iter()
                .flat_map(|s| s.jobs.iter().map(|j| j.0))
                .collect(),
        ),
    ];
    let all: Vec<WheelRecord> = sweeps
        .iter()
        .flat_map(|s| s.records.iter().cloned())
        .collect();
    cols.extend(record_columns(&all));
    let pq = dir.join("bifurcation.parquet");
    let params = serde_json::to_string(&r.request.base).expect("json");
    write_table(&pq, &cols, &[("params".into(), params)])
        .map_err(|e| ReproduceError::Table(e.to_string()))?;
    Ok(pq)
}

/// Fig. 4: lateral against longitudinal force as the slip ratio grows, for several slip angles.
fn adhesion_ellipse(
    r: &Reproduction,
    dir: &Path,
    format: FigureFormat,
    files: &mut Vec<PathBuf>,
) -> Result<(), ReproduceError> {
    let base = &r.request.base;
    let rows = &r.adhesion;
    let labels: Vec<String> = ADHESION_ANGLES_DEG
        .iter()
        .map(|a| format!("alpha = {a} deg"))
        .collect();
    let series: Vec<Series> = ADHESION_ANGLES_DEG
        .iter()
        .zip(&labels)
        .map(|(a, label)| Series {
            label,
            points: rows
                .iter()
                .filter(|row| row.0 == *a)
                .map(|row| (row.2, row.3))
                .collect(),
        })
        .collect();
    let picture = FigureFile::named(dir, "fig4_adhesion", format);
    plot::panels(
        &picture,
        (1000, 760),
        (1, 1),
        "Fig. 4: lateral vs longitudinal force as the slip ratio grows (brush model)",
        |_, area| {
            plot::line_panel(
                area,
                &format!("F_Z = {} N, P = {} kPa", base.load_n, base.pressure_kpa),
                "longitudinal force F_X [N]",
                "lateral force F_Y [N]",
                &series,
                false,
            )
        },
    )
    .map_err(ReproduceError::Figure)?;
    files.push(picture.path);
    let csv = dir.join("fig4_adhesion.csv");
    write_csv(
        &csv,
        &[
            Column::f64("toe_deg", "deg", rows.iter().map(|r| r.0).collect()),
            Column::f64("slip_ratio", "-", rows.iter().map(|r| r.1).collect()),
            Column::f64("f_x_n", "N", rows.iter().map(|r| r.2).collect()),
            Column::f64("f_y_n", "N", rows.iter().map(|r| r.3).collect()),
        ],
    )
    .map_err(|e| ReproduceError::Table(e.to_string()))?;
    files.push(csv);
    Ok(())
}

/// Fig. 18 (both wheels): limit-cycle amplitude of y against speed, from the speed sweeps.
fn amplitude_vs_speed(
    r: &Reproduction,
    dir: &Path,
    format: FigureFormat,
    files: &mut Vec<PathBuf>,
) -> Result<(), ReproduceError> {
    let mut labels = Vec::new();
    let mut points = Vec::new();
    for (variant, wheel) in [
        (Variant::DEFAULT, Wheel::Follower),
        (Variant::Paper, Wheel::Driving),
        (Variant::Combined, Wheel::Driving),
        (Variant::SlidingShare, Wheel::Driving),
    ] {
        let sw = r.sweep(ParamId::SpeedKmh, variant);
        labels.push(match wheel {
            Wheel::Follower => "follower (every variant)".to_string(),
            Wheel::Driving => format!("driving, {variant}"),
        });
        points.push(
            sw.jobs
                .iter()
                .zip(&sw.records)
                .filter(|(j, _)| j.1 == wheel)
                .map(|(j, r)| {
                    (
                        j.0,
                        if r.amp_y_m.is_finite() {
                            r.amp_y_m
                        } else {
                            0.0
                        },
                    )
                })
                .collect::<Vec<_>>(),
        );
    }
    let series: Vec<Series> = labels
        .iter()
        .zip(points)
        .map(|(label, points)| Series { label, points })
        .collect();
    let picture = FigureFile::named(dir, "fig18_amplitude_vs_speed", format);
    plot::panels(
        &picture,
        (1000, 700),
        (1, 1),
        "Fig. 18: self-excited vibration amplitude against speed, follower and driving wheel",
        |_, area| {
            plot::line_panel(
                area,
                "half peak-to-peak of y on the limit cycle (0: stable)",
                "vehicle speed [km/h]",
                "amplitude of y [m]",
                &series,
                false,
            )
        },
    )
    .map_err(ReproduceError::Figure)?;
    files.push(picture.path);
    Ok(())
}
