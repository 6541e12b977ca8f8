//! A table as named, typed columns with units: what every stage hands to a file writer (the
//! Parquet and CSV writers of `polywear-study`), and what the record tables produce
//! ([`crate::records::record_columns`]).

/// The values of one column in one row group.
#[derive(Debug, Clone, PartialEq)]
pub enum ColumnData {
    /// Floating-point values.
    F64(Vec<f64>),
    /// Single-precision values: where seven digits are all a figure has (the calibration
    /// band's distances, one column per set), at half the bytes.
    F32(Vec<f32>),
    /// Integers.
    I64(Vec<i64>),
    /// Strings (UTF-8).
    Str(Vec<String>),
}

impl ColumnData {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            ColumnData::F64(v) => v.len(),
            ColumnData::F32(v) => v.len(),
            ColumnData::I64(v) => v.len(),
            ColumnData::Str(v) => v.len(),
        }
    }

    /// Whether there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A named column with its unit ("" for none), as written to the schema and the `units` metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The column's name.
    pub name: String,
    /// Its unit ("" for none).
    pub unit: &'static str,
    /// Its values.
    pub data: ColumnData,
}

impl Column {
    /// A floating-point column.
    pub fn f64(name: impl Into<String>, unit: &'static str, data: Vec<f64>) -> Self {
        Column {
            name: name.into(),
            unit,
            data: ColumnData::F64(data),
        }
    }
    /// A single-precision column.
    pub fn f32(name: impl Into<String>, unit: &'static str, data: Vec<f32>) -> Self {
        Column {
            name: name.into(),
            unit,
            data: ColumnData::F32(data),
        }
    }
    /// An integer column.
    pub fn i64(name: impl Into<String>, unit: &'static str, data: Vec<i64>) -> Self {
        Column {
            name: name.into(),
            unit,
            data: ColumnData::I64(data),
        }
    }
    /// A string column (no unit).
    pub fn str(name: impl Into<String>, data: Vec<String>) -> Self {
        Column {
            name: name.into(),
            unit: "",
            data: ColumnData::Str(data),
        }
    }
}
