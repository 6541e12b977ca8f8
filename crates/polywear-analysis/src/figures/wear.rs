//! The files of a long-term run (`polywear wear`): `wear_summary.csv` (+ `.parquet`, one row
//! per wheel), `wear_history.parquet`, `wear_profile.parquet` and the figure `wear.png`, each
//! with the run's metadata.

use std::path::Path;

use super::FilesError;
use crate::plot::wear::{wear_figure, WearTrace};
use crate::plot::{FigureFile, FigureFormat};
use polywear_core::long_term::wheel_loop::{WheelWear, FEEDBACK_ORDERS};
use polywear_core::long_term::LongTermSolution;
use polywear_study::long_term_request::LongTermPlan;
use polywear_study::parquet_out::{write_csv, write_table};

/// Orders drawn in the figure: the deepest at the end, per wheel.
const DRAWN_ORDERS: usize = 4;

/// A long-term run and how its files are written.
pub struct LongTermFiles<'a> {
    /// The run.
    pub solution: &'a LongTermSolution,
    /// Written into every table (version, command, parameters, variant, usage, loop settings).
    pub metadata: &'a [(String, String)],
    /// Add the per-sample estimator's `estimate_*` columns to the summary.
    pub estimate: bool,
    /// The figure's format.
    pub format: FigureFormat,
    /// The figure's title.
    pub title: String,
}

impl<'a> LongTermFiles<'a> {
    /// The files of `plan`'s run `solution`, titled with the usage: `estimate` adds the
    /// per-sample estimator's columns, `format` is the figure's.
    pub fn of(
        plan: &'a LongTermPlan,
        solution: &'a LongTermSolution,
        estimate: bool,
        format: FigureFormat,
    ) -> Self {
        LongTermFiles {
            solution,
            metadata: &plan.metadata,
            estimate,
            format,
            title: format!("polywear wear: {}", plan.usage),
        }
    }
}

impl LongTermFiles<'_> {
    /// Writes the tables and, where a wheel has a run, the figure into `dir`.
    /// Creates the output folder, refused with the reason where it cannot be one: a caller
    /// calls this before the work, so that a bad `--out` costs no run.
    pub fn prepare(dir: &Path) -> Result<(), FilesError> {
        polywear_study::safe_write::create_dir(dir).map_err(|source| FilesError::CreateDir {
            dir: dir.to_path_buf(),
            source,
        })
    }

    /// Writes the three tables and the figure into `dir` (created if missing).
    pub fn write(&self, dir: &Path) -> Result<(), FilesError> {
        Self::prepare(dir)?;
        // An earlier run's figure in this folder is not this run's: remove it before any new
        // table is written, so that neither a run whose wheels have no wear figures nor one
        // killed while drawing leaves it beside the new tables.
        for format in [FigureFormat::Png, FigureFormat::Svg] {
            let old = FigureFile::named(dir, "wear", format).path;
            if old.is_file() {
                std::fs::remove_file(&old).map_err(|source| FilesError::CreateDir {
                    dir: old.clone(),
                    source,
                })?;
            }
        }
        let mut meta = self.metadata.to_vec();
        meta.push((
            "profile".into(),
            "depth_mm: the worn depth minus its mean (r = -depth); depth peak-to-valley in history"
                .into(),
        ));
        let s = self.solution;
        let summary = s.summary_columns(self.estimate);
        write_csv(&dir.join("wear_summary.csv"), &summary)?;
        write_table(&dir.join("wear_summary.parquet"), &summary, &meta)?;
        write_table(
            &dir.join("wear_history.parquet"),
            &s.history_columns(),
            &meta,
        )?;
        write_table(
            &dir.join("wear_profile.parquet"),
            &s.profile_columns(),
            &meta,
        )?;
        let visible_mm = s.params.visible_depth_mm;
        let traces: Vec<WearTrace> = s
            .wheels
            .iter()
            .filter_map(|w| w.run.as_ref().ok().map(|r| (w.wheel, r)))
            .map(|(wheel, r)| WearTrace {
                wheel: wheel.as_str(),
                profiles: &r.profiles,
                depths: drawn_depths(r),
                visible_mm,
            })
            .collect();
        if !traces.is_empty() {
            let figure = FigureFile::named(dir, "wear", self.format);
            wear_figure(&figure, &self.title, &traces)?;
        }
        Ok(())
    }
}

/// The [`DRAWN_ORDERS`] deepest orders at the end, their depth \[mm\] against distance.
fn drawn_depths(run: &WheelWear) -> Vec<(u32, Vec<(f64, f64)>)> {
    let end = &run.end().depths_m;
    let mut orders: Vec<usize> = (0..end.len().min(FEEDBACK_ORDERS)).collect();
    orders.sort_by(|a, b| end[*b].total_cmp(&end[*a]));
    orders
        .into_iter()
        .take(DRAWN_ORDERS)
        .map(|i| {
            let pts = run
                .history
                .iter()
                .map(|h| (h.distance_km, h.depths_m[i] * 1e3))
                .collect();
            (i as u32 + 1, pts)
        })
        .collect()
}

/// The loop's verdict under each calibrated set run, one row per set and wheel:
/// `wear_calibration_band.csv` and `.parquet` (with the run's metadata).
pub(crate) fn write_band(
    dir: &Path,
    metadata: &[(String, String)],
    band: &polywear_study::calibration_band::CalibrationBand,
    runs: &[polywear_study::calibration_band::long_term::SetRun],
    distance_km: f64,
) -> Result<(), FilesError> {
    use crate::render::long_term::band_verdict;
    use polywear_study::parquet_out::Column;
    let rows: Vec<(&polywear_study::calibration_band::long_term::SetRun, usize)> = runs
        .iter()
        .flat_map(|r| (0..r.solution.wheels.len()).map(move |i| (r, i)))
        .collect();
    let verdicts: Vec<_> = rows
        .iter()
        .map(|(r, i)| band_verdict(&r.solution.wheels[*i], &r.solution.params, distance_km))
        .collect();
    let set = |r: &polywear_study::calibration_band::long_term::SetRun| &band.sets[r.set];
    let f = |name: &str, unit: &'static str, get: &dyn Fn(usize) -> f64| {
        Column::f64(name, unit, (0..rows.len()).map(get).collect())
    };
    let cols = vec![
        Column::str("set", rows.iter().map(|(r, _)| set(r).id.clone()).collect()),
        Column::str(
            "chosen_as",
            rows.iter().map(|(r, _)| r.chosen_as.clone()).collect(),
        ),
        Column::str(
            "wheel",
            rows.iter()
                .map(|(r, i)| r.solution.wheels[*i].wheel.to_string())
                .collect(),
        ),
        f("wear_share_straight", "-", &|k| {
            set(rows[k].0).wear_share_straight
        }),
        f("speed_spread_kmh", "km/h", &|k| {
            set(rows[k].0).speed_spread_kmh
        }),
        f("wear_rate_driven_factor", "-", &|k| {
            set(rows[k].0).wear_rate_driven_factor
        }),
        f("carcass_share", "-", &|k| set(rows[k].0).carcass_share),
        f("belt_mass_share", "-", &|k| set(rows[k].0).belt_mass_share),
        Column::str(
            "verdict",
            verdicts.iter().map(|v| v.kind.to_string()).collect(),
        ),
        f("polygon_order", "-", &|k| verdicts[k].order),
        f("end_km", "km", &|k| verdicts[k].end_km),
        f("distance_to_visible_km", "km", &|k| verdicts[k].km),
    ];
    write_csv(&dir.join("wear_calibration_band.csv"), &cols)?;
    write_table(&dir.join("wear_calibration_band.parquet"), &cols, metadata)?;
    Ok(())
}

/// The band's files of `plan`'s run in `dir`: `write_band` under the sets run (`runs`), or,
/// with the band off, `remove_band`, so that no band of an earlier run lies beside this
/// run's files.
pub fn plan_band_files(
    dir: &Path,
    plan: &LongTermPlan,
    runs: Option<&[polywear_study::calibration_band::long_term::SetRun]>,
) -> Result<(), FilesError> {
    match (&plan.band, runs) {
        (Some((band, _)), Some(runs)) => write_band(
            dir,
            &plan.metadata,
            band,
            runs,
            plan.problem.settings.distance_km,
        ),
        _ => remove_band(dir),
    }
}

/// Removes [`write_band`]'s files of an earlier run from `dir` (a run with the band off).
pub(crate) fn remove_band(dir: &Path) -> Result<(), FilesError> {
    for name in ["wear_calibration_band.csv", "wear_calibration_band.parquet"] {
        let path = dir.join(name);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(FilesError::CreateDir {
                    dir: path,
                    source: e,
                })
            }
            _ => {}
        }
    }
    Ok(())
}
