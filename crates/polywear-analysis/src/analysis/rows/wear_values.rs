//! The wear columns' values against what the wear stage writes (MODEL.md#wear-columns): a
//! distance to a visible polygon is at least 0 (inf where every order levels out), a growth
//! rate is not +inf, and a wheel with a verdict has a distance unless `wear_reason` says why
//! not. A chunk that breaks one was changed after the run, even with its journal made to
//! match, and is refused naming the file, the column and what is accepted.

use std::path::PathBuf;

use polars::prelude::*;

use super::{collect, ints, outcome_expr, Rows, CLASS};
use crate::analysis::AnalysisError;
use polywear_core::records::WearColumn;

const DISTANCE: &str = WearColumn::DistanceToVisibleKm.name();
const GROWTH: &str = WearColumn::GrowthRatePer1000km.name();
const REASON: &str = WearColumn::WearReason.name();

/// Refuses the first file of `files` whose wear columns hold a value the wear stage never
/// writes.
pub(crate) fn check_wear_values(files: &[PathBuf]) -> Result<(), AnalysisError> {
    for f in files {
        let lf = Rows::scan(std::slice::from_ref(f))?.lf;
        let count = |e: Expr, name: &str| e.cast(DataType::Int64).sum().alias(name);
        let verdict = outcome_expr().lt(lit(2i64));
        let no_reason = col(REASON).is_null().or(col(REASON).eq(lit("")));
        let df = collect(lf.select([
            count(col(DISTANCE).lt(lit(0.0)), "negative"),
            count(col(GROWTH).eq(lit(f64::INFINITY)), "infinite"),
            count(
                col(DISTANCE).is_nan().and(verdict).and(no_reason),
                "unexplained",
            ),
            col(CLASS).count().alias("rows"),
        ]))?;
        let checks = [
            (
                "negative",
                DISTANCE,
                "values below 0",
                "[0, inf] km (inf: every order levels out)",
            ),
            (
                "infinite",
                GROWTH,
                "+inf",
                "a finite rate, or NaN with a `wear_reason`",
            ),
            (
                "unexplained",
                DISTANCE,
                "NaN on rows with a verdict and no `wear_reason`",
                "a distance in [0, inf] km wherever the wheel has a verdict, NaN only with a `wear_reason`",
            ),
        ];
        for (name, column, what, accepted) in checks {
            let rows = ints(&df, name)?.first().copied().unwrap_or(0);
            if rows > 0 {
                return Err(AnalysisError::WearValue {
                    path: f.clone(),
                    column,
                    rows: rows as u64,
                    what,
                    accepted,
                });
            }
        }
    }
    Ok(())
}
