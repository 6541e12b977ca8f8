//! Columns renamed for one version ([`RENAMED_COLUMNS`]): rows written before the rename carry
//! only the old name, so the scan adds the new one as a copy of it and the analysis names every
//! column by its new name; [`deprecation_notes`] says so in the report and summary.

use std::path::PathBuf;

use polars::prelude::*;

use super::{pl_err, Rows};
use crate::analysis::AnalysisError;
use polywear_core::records::{WearColumn, RENAMED_COLUMNS};

/// The renamed columns the frame carries only under their old name.
fn old_only(schema: &Schema) -> Vec<(&'static str, &'static str)> {
    RENAMED_COLUMNS
        .iter()
        .copied()
        .filter(|(old, new)| schema.contains(old) && !schema.contains(new))
        .collect()
}

/// The frame with each old-only column copied under its new name, and rows written before the
/// wear stage gave a tread life read as tires that never wear out (a visible polygon then
/// counts at any distance, as those versions counted it).
pub(super) fn with_new_names(lf: LazyFrame) -> Result<LazyFrame, AnalysisError> {
    let schema = lf.clone().collect_schema().map_err(pl_err)?;
    let mut copies: Vec<Expr> = old_only(&schema)
        .into_iter()
        .map(|(old, new)| col(old).alias(new))
        .collect();
    let (distance, life) = (
        WearColumn::DistanceToVisibleKm.name(),
        WearColumn::TreadLifeKm.name(),
    );
    if schema.contains(distance) && !schema.contains(life) {
        copies.push(lit(f64::INFINITY).alias(life));
    }
    Ok(if copies.is_empty() {
        lf
    } else {
        lf.with_columns(copies)
    })
}

/// "deprecated: ..." for each column the files carry only under its old name.
pub(crate) fn deprecation_notes(files: &[PathBuf]) -> Result<Vec<String>, AnalysisError> {
    let Some(first) = files.first() else {
        return Ok(Vec::new());
    };
    let mut raw = Rows::scan_raw(std::slice::from_ref(first))?;
    let schema = raw.collect_schema().map_err(pl_err)?;
    Ok(old_only(&schema)
        .into_iter()
        .map(|(old, new)| {
            format!(
                "deprecated: column `{old}` is read as `{new}`, its new name; the old name goes in the next version"
            )
        })
        .collect())
}
