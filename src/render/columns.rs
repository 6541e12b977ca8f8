//! The report tables' columns built from a list of rows, one closure per column (shared by the
//! vibration tables and the wear tables).

use crate::parquet_out::Column;

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
