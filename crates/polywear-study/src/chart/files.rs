//! A chart's tables on disk and its lines for the console: the curves and the special points
//! (Bautin points, ends on the box) as Parquet with CSV beside them, and the uncertainty band's
//! unstable shares per cell. Here rather than in the command line so that a script writes the
//! same files and says the same lines as `polywear chart`.

use std::path::{Path, PathBuf};

use super::band::StructureBand;
use super::{band_columns, curve_columns, special_columns, ChartRequest, WheelCurves};
use crate::parquet_out::{write_csv, write_table, WriteError};
use crate::study::Study;

/// The four tables [`write_tables`] writes.
#[derive(Debug, Clone, PartialEq)]
pub struct ChartTables {
    /// FILE.parquet: every curve point, with the chart's metadata.
    pub table: PathBuf,
    /// FILE.csv: the same rows.
    pub csv: PathBuf,
    /// FILE_special.parquet: the special points.
    pub special: PathBuf,
    /// FILE_special.csv: the same rows.
    pub special_csv: PathBuf,
}

/// `out`'s sibling `STEM{suffix}.{ext}` (FILE_special.csv beside FILE.parquet).
pub fn sibling(out: &Path, suffix: &str, ext: &str) -> PathBuf {
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("chart");
    out.with_file_name(format!("{stem}{suffix}.{ext}"))
}

/// Writes the curves to `out` (FILE.parquet, with `meta`) and FILE.csv, the special points to
/// FILE_special.parquet and FILE_special.csv.
pub fn write_tables(
    out: &Path,
    req: &ChartRequest,
    charts: &[WheelCurves],
    meta: &[(String, String)],
) -> Result<ChartTables, WriteError> {
    let cols = curve_columns(req, charts);
    write_table(out, &cols, meta)?;
    let csv = out.with_extension("csv");
    write_csv(&csv, &cols)?;
    let special = special_columns(req, charts);
    let (special_pq, special_csv) = (
        sibling(out, "_special", "parquet"),
        sibling(out, "_special", "csv"),
    );
    write_table(&special_pq, &special, meta)?;
    write_csv(&special_csv, &special)?;
    Ok(ChartTables {
        table: out.to_path_buf(),
        csv,
        special: special_pq,
        special_csv,
    })
}

/// Writes the uncertainty band's unstable share per cell beside `out`: FILE_band.parquet (the
/// chart's `meta` with the study's and the draw's) and FILE_band.csv.
pub fn write_band_tables(
    out: &Path,
    req: &ChartRequest,
    band: &StructureBand,
    meta: &[(String, String)],
    study: &Study,
    k: u64,
) -> Result<(), WriteError> {
    let cols = band_columns(req, band);
    let band_meta = band.metadata(meta, study, k);
    write_table(&sibling(out, "_band", "parquet"), &cols, &band_meta)?;
    write_csv(&sibling(out, "_band", "csv"), &cols)
}

/// The chart's first line: its axes with their units and ranges, the variant and the time the
/// tracing took.
pub fn heading(req: &ChartRequest, secs: f64) -> String {
    let (lo, hi) = (req.bounds.lo, req.bounds.hi);
    format!(
        "chart of {} [{}] {}..{} x {} [{}] {}..{} (variant {}), {secs:.2} s",
        req.x.name(),
        req.x.spec().unit,
        lo[0],
        hi[0],
        req.y.name(),
        req.y.spec().unit,
        lo[1],
        hi[1],
        req.variant,
    )
}

/// The uncertainty band's line: how many structures from which study, and what they draw.
pub fn band_words(band: &StructureBand, study: &Study, k: u64) -> String {
    format!(
        "uncertainty band: {k} structures from study `{}` (seed {}), drawn: {}",
        study.name,
        study.seed,
        band.drawn
            .iter()
            .map(|d| d.name())
            .collect::<Vec<_>>()
            .join(", ")
    )
}
