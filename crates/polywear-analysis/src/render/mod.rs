//! Render stage: writes an [`Analysis`] as files: the tables (`tables`, CSV and Parquet), the
//! figures ([`figures`]) and `report.md` (`markdown`), which ties them together in words. It
//! computes nothing; everything it shows is in the `Analysis`.

mod answer_tables;
mod answer_words;
pub(crate) mod band;
pub mod calibration;
mod columns;
pub mod cycle;
pub(crate) mod drivers;
pub mod figures;
pub(crate) mod fleet;
pub mod long_term;
pub(crate) mod markdown;
pub mod run_words;
pub(crate) mod scenarios;
pub mod summary;
pub mod sweep;
pub(crate) mod tables;
pub mod validation;
pub mod verdict;
pub(crate) mod wear;
pub(crate) mod wear_figures;
mod wear_tables;
mod words;

use std::path::{Path, PathBuf};

use crate::analysis::counts::RiskCounts;
use crate::analysis::risk_map::RiskMap;
use crate::analysis::Analysis;
use crate::plot::FigureFile;
/// The figures' file format, PNG or SVG, as [`RenderOptions::figure_format`] takes it.
pub use crate::plot::FigureFormat;
use polywear_core::model::Variant;
use polywear_core::params::ParamId;

/// Where and how the report is written.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Where the tables, figures and `report.md` go (created when missing).
    pub out_dir: PathBuf,
    /// The figures' file format.
    pub figure_format: FigureFormat,
}

/// A risk map's figure.
#[derive(Debug, Clone, PartialEq)]
pub struct RiskMapFigure {
    /// The friction variant.
    pub variant: Variant,
    /// The horizontal axis.
    pub x: ParamId,
    /// The vertical axis.
    pub y: ParamId,
    /// The file.
    pub path: PathBuf,
}

/// The figures written, by kind.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Figures {
    /// P(vibration) per bin of every parameter drawn per sample, one figure per variant.
    pub conditional: Vec<(Variant, PathBuf)>,
    /// One figure per risk map (pair of axes and variant), in the analysis' map order.
    pub risk_maps: Vec<RiskMapFigure>,
    /// Severity histograms, one figure per variant.
    pub severity: Vec<(Variant, PathBuf)>,
    /// Every scenario's effect with its interval (a run with scenarios only).
    pub scenarios: Option<PathBuf>,
    /// P(visible polygon within the headline distance) per bin of every parameter, one figure
    /// per variant (a run with the wear stage only).
    pub wear_conditional: Vec<(Variant, PathBuf)>,
    /// One risk map of polygonal-wear likelihood per drawn vibration map.
    pub wear_maps: Vec<RiskMapFigure>,
    /// The dominant orders' bars, one figure per variant.
    pub wear_orders: Vec<(Variant, PathBuf)>,
}

impl Figures {
    /// Every figure, in the order written.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.conditional
            .iter()
            .map(|(_, p)| p.as_path())
            .chain(self.risk_maps.iter().map(|f| f.path.as_path()))
            .chain(self.severity.iter().map(|(_, p)| p.as_path()))
            .chain(self.scenarios.as_deref())
            .chain(self.wear_conditional.iter().map(|(_, p)| p.as_path()))
            .chain(self.wear_maps.iter().map(|f| f.path.as_path()))
            .chain(self.wear_orders.iter().map(|(_, p)| p.as_path()))
    }
}

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    /// The tables (CSV and Parquet), in order.
    pub tables: Vec<PathBuf>,
    /// The figures.
    pub figures: Figures,
    /// `report.md`.
    pub report: PathBuf,
}

impl Rendered {
    /// Every file written: tables, figures, then the page.
    pub fn files(&self) -> Vec<PathBuf> {
        self.tables
            .iter()
            .cloned()
            .chain(self.figures.paths().map(Path::to_path_buf))
            .chain([self.report.clone()])
            .collect()
    }
}

/// Why a report cannot be written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    /// The output directory or the page cannot be written.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A table cannot be written.
    #[error("{0}")]
    Write(String),
    /// A figure cannot be drawn.
    #[error("{0}")]
    Figure(crate::plot::PlotError),
}

/// Writes the tables, figures and `report.md` of `a` into `opts.out_dir`.
pub fn write(a: &Analysis, opts: &RenderOptions) -> Result<Rendered, RenderError> {
    let dir = &opts.out_dir;
    polywear_study::safe_write::create_dir(dir).map_err(|e| RenderError::Io {
        path: dir.clone(),
        message: e.to_string(),
    })?;
    let tables = tables::write_all(dir, a)?;
    let figures = write_figures(a, opts)?;
    let page = markdown::page(a, &figures);
    let report = dir.join("report.md");
    polywear_study::safe_write::write_file(&report, page.as_bytes()).map_err(|e| {
        RenderError::Io {
            path: report.clone(),
            message: e.to_string(),
        }
    })?;
    Ok(Rendered {
        tables,
        figures,
        report,
    })
}

fn write_figures(a: &Analysis, opts: &RenderOptions) -> Result<Figures, RenderError> {
    let (dir, format) = (&opts.out_dir, opts.figure_format);
    let min_count = a.options.min_count;
    let info = &a.info;
    let label = |p: ParamId| polywear_core::params::axis_label(p.name(), info.unit(p.name()));
    let mut out = Figures::default();
    // The columns of an operating-point file move together: the per-row table shows them.
    let fleet_columns: Vec<&str> = a
        .fleet
        .as_ref()
        .map_or(vec![], |f| f.columns.iter().map(String::as_str).collect());
    let axes: Vec<ParamId> = info
        .drawn_names
        .iter()
        .copied()
        .filter(|p| !fleet_columns.contains(&p.name()))
        .collect();
    for variant in a.variants().into_iter().filter(|_| !axes.is_empty()) {
        let f = FigureFile::named(dir, &format!("conditional_{variant}"), format);
        figures::conditional(
            &f,
            variant,
            &axes,
            &label,
            &a.vibration.conditional,
            min_count,
        )?;
        out.conditional.push((variant, f.path));
    }
    let drawn = a.vibration.maps.iter().filter(|m| a.is_drawn(m));
    out.risk_maps = map_figures(drawn, (dir, "riskmap", format), |f, map| {
        figures::risk_map(f, map, &label, min_count, info.params.drivetrain)
    })?;
    for variant in a.variants() {
        let f = FigureFile::named(dir, &format!("severity_{variant}"), format);
        figures::severity(&f, variant, &a.severity)?;
        out.severity.push((variant, f.path));
    }
    if !a.scenarios.is_empty() {
        let f = FigureFile::named(dir, "scenarios", format);
        scenarios::figure(&f, &a.scenarios)?;
        out.scenarios = Some(f.path);
    }
    if let Some(w) = &a.wear {
        for variant in a.variants().into_iter().filter(|_| !axes.is_empty()) {
            let f = FigureFile::named(dir, &format!("wear_conditional_{variant}"), format);
            wear_figures::conditional(&f, variant, &axes, &label, w, min_count)?;
            out.wear_conditional.push((variant, f.path));
        }
        out.wear_maps = map_figures(
            w.headline_answer().maps.iter(),
            (dir, "wear_riskmap", format),
            |f, map| wear_figures::risk_map(f, map, &label, min_count, info.params.drivetrain),
        )?;
        let with_orders = |v: &Variant| w.orders.iter().any(|o| o.variant == *v);
        for variant in a.variants().into_iter().filter(with_orders) {
            let f = FigureFile::named(dir, &format!("wear_orders_{variant}"), format);
            wear_figures::orders(&f, variant, w)?;
            out.wear_orders.push((variant, f.path));
        }
    }
    Ok(out)
}

/// One figure per map of `maps`, drawn by `draw`, each in `<prefix>_<x>_<y>_<variant>` of the
/// folder and format of `to`: the vibration and the wear maps go through the same loop.
fn map_figures<'a, C, F>(
    maps: impl Iterator<Item = &'a RiskMap<C>>,
    (dir, prefix, format): (&Path, &str, FigureFormat),
    draw: F,
) -> Result<Vec<RiskMapFigure>, RenderError>
where
    C: RiskCounts + 'a,
    F: Fn(&FigureFile, &RiskMap<C>) -> Result<(), RenderError>,
{
    maps.map(|map| {
        let stem = format!("{prefix}_{}_{}_{}", map.x, map.y, map.variant);
        let f = FigureFile::named(dir, &stem, format);
        draw(&f, map)?;
        Ok(RiskMapFigure {
            variant: map.variant,
            x: map.x,
            y: map.y,
            path: f.path,
        })
    })
    .collect()
}
