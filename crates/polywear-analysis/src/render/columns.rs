//! The report tables' columns built from a list of rows, one closure per column (shared by the
//! vibration tables and the wear tables).

use crate::analysis::counts::RiskCounts;
use polywear_study::parquet_out::Column;

/// The proportion every probability table carries, for counts of either kind: p (NaN below
/// `min_count`) and its 95% Wilson interval.
pub(super) fn proportion_columns<T, C: RiskCounts>(
    rows: &[T],
    c: impl Fn(&T) -> C,
    min_count: u64,
) -> [Column; 3] {
    [
        f64_col("p", rows, |r| {
            if c(r).enough(min_count) {
                c(r).p()
            } else {
                f64::NAN
            }
        }),
        f64_col("wilson95_lo", rows, |r| c(r).wilson().0),
        f64_col("wilson95_hi", rows, |r| c(r).wilson().1),
    ]
}

/// A count column.
pub(super) fn count_col<T>(name: &str, rows: &[T], f: impl Fn(&T) -> u64) -> Column {
    Column::i64(name, "", rows.iter().map(|r| f(r) as i64).collect())
}

/// A float column.
pub(super) fn f64_col<T>(name: &str, rows: &[T], f: impl Fn(&T) -> f64) -> Column {
    Column::f64(name, "", rows.iter().map(f).collect())
}

/// A name column.
pub(super) fn str_col<T>(name: &str, rows: &[T], f: impl Fn(&T) -> String) -> Column {
    Column::str(name, rows.iter().map(f).collect())
}
