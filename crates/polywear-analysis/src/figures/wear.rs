//! The files of a long-term run (`polywear wear`): `wear_summary.csv` (+ `.parquet`, one row
//! per wheel), `wear_history.parquet`, `wear_profile.parquet` and the figure `wear.png`, each
//! with the run's metadata.

use std::path::Path;

use super::FilesError;
use crate::plot::wear::{wear_figure, WearTrace};
use crate::plot::{FigureFile, FigureFormat};
use polywear_core::long_term::LongTermSolution;
use polywear_core::wear::long_term::{WheelWear, FEEDBACK_ORDERS};
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
