//! Measured operating points as study input: a study's `[operating_points]` names a CSV or
//! Parquet file whose columns are parameters of `polywear params` (and optionally one weight
//! column, e.g. hours driven there). Each sample of a study draws one row, with probability
//! proportional to its weight, through an alias table and the study's ChaCha12 generator; the
//! row's values set the parameters it names, and every other drawn parameter (the tire
//! structure) is drawn as without the file. So the file's correlations (load with pressure,
//! speed with load) are kept, and the structure still varies per sample.
//!
//! The whole file is checked before any work: every refusal names the file, row and column.

use std::path::{Path, PathBuf};

use crate::params::{ParamError, ParamId, Params};
use crate::sampling::alias::AliasTable;
use crate::sampling::Streams;
use crate::table_input::{NumericTable, TableError};

/// Why an operating-point file is refused, naming the file, row and column.
#[derive(Debug, thiserror::Error)]
pub enum OperatingPointsError {
    /// The file cannot be read as a table of numbers.
    #[error(transparent)]
    Table(#[from] TableError),
    /// The weight column named in the study is missing.
    #[error("{}: no column `{weight}`, which `operating_points.weight` names (columns: {})", path.display(), columns.join(", "))]
    NoWeightColumn {
        /// The file.
        path: PathBuf,
        /// The weight column named.
        weight: String,
        /// The columns it has.
        columns: Vec<String>,
    },
    /// A column that is neither a parameter nor the weight column.
    #[error("{}: column `{name}` (column {number}) is not a parameter of `polywear params`{}{}", path.display(), weight_hint(weight.as_deref()), did_you_mean(name))]
    UnknownColumn {
        /// The file.
        path: PathBuf,
        /// The column's name.
        name: String,
        /// Its position, counted from 1.
        number: usize,
        /// The weight column, if the study names one.
        weight: Option<String>,
    },
    /// Only a weight column.
    #[error("{}: no parameter column (columns: {}); name parameters of `polywear params`, e.g. speed_kmh,load_n,pressure_kpa", path.display(), columns.join(", "))]
    NoParameterColumn {
        /// The file.
        path: PathBuf,
        /// The columns it has.
        columns: Vec<String>,
    },
    /// A value outside its parameter's range, or a row whose values do not fit together.
    #[error("{at}: {source}")]
    Param {
        /// File and row (and column for one cell).
        at: String,
        /// The parameter's refusal.
        source: ParamError,
    },
    /// A negative weight.
    #[error("{at}: weight {} is negative; weights must be >= 0", crate::wording::plain(*weight, 12))]
    NegativeWeight {
        /// File, row and column.
        at: String,
        /// The weight given.
        weight: f64,
    },
    /// No row can be drawn.
    #[error("{}, column `{weight}`: every weight is zero; at least one row needs a positive weight", path.display())]
    AllWeightsZero {
        /// The file.
        path: PathBuf,
        /// The weight column.
        weight: String,
    },
}

/// " nor the weight column `hours`", or how to name one.
fn weight_hint(weight: Option<&str>) -> String {
    match weight {
        Some(w) => format!(" nor the weight column `{w}`"),
        None => " (a weight column needs `weight = \"NAME\"` in [operating_points])".to_string(),
    }
}

/// "; did you mean `speed_kmh`?" for a misspelt parameter name, or nothing.
fn did_you_mean(name: &str) -> String {
    crate::params::suggest_name(name)
        .map(|n| format!("; did you mean `{n}`?"))
        .unwrap_or_default()
}

/// The generator axis of the row draw within each sample's stream: the last axis a stream has
/// (2^36 − 1, see [`crate::sampling::rng`]), far from the drawn parameters' axes 0, 1, …, so
/// the row draw and the structure draws are independent and neither shifts the other.
pub const ROW_AXIS: u64 = (1 << 36) - 1;

/// The measured operating points of a study, checked, with their alias table.
#[derive(Debug, Clone, PartialEq)]
pub struct OperatingPoints {
    /// The path as the study writes it (`file`).
    pub file: String,
    /// The path read: `file` resolved against the study file's folder, made absolute, so that
    /// a run's metadata finds the file again from any working directory (analysis, resume).
    pub path: PathBuf,
    /// The weight column's name, when the study gives one.
    pub weight: Option<String>,
    /// The parameter columns, in file order.
    pub names: Vec<&'static str>,
    /// `values[i][j]`: data row i's value of `names[j]`.
    pub values: Vec<Vec<f64>>,
    /// Each row's weight (1 without a weight column).
    pub weights: Vec<f64>,
    /// FNV-1a 64 of the file's bytes (16 hex digits), recorded in the manifest and every chunk.
    pub hash: String,
    /// The file's size in bytes, recorded beside the hash.
    pub bytes: u64,
    table: AliasTable,
}

impl OperatingPoints {
    /// Reads and checks the file `file` (relative to `dir` unless absolute) against `base` (the
    /// study's fixed values): every column a parameter or the weight column, every value in
    /// its parameter's range, weights finite and non-negative and not all zero.
    /// `cross_rules_drawn`: whether the study draws a parameter of a cross-parameter rule
    /// (mu_s ≤ mu_m, n_driven ≤ n_wheels); if not, a row that breaks one is refused here.
    pub fn load(
        file: &str,
        weight: Option<&str>,
        dir: &Path,
        base: &Params,
        cross_rules_drawn: bool,
    ) -> Result<OperatingPoints, OperatingPointsError> {
        let path = dir.join(file);
        let t = NumericTable::read(&path)?;
        let weight_col = match weight {
            Some(w) => Some(
                t.column(w)
                    .ok_or_else(|| OperatingPointsError::NoWeightColumn {
                        path: path.clone(),
                        weight: w.to_string(),
                        columns: t.columns.clone(),
                    })?,
            ),
            None => None,
        };
        let mut names = Vec::new();
        let mut ids = Vec::new();
        let mut param_cols = Vec::new();
        for (j, c) in t.columns.iter().enumerate() {
            if Some(j) == weight_col {
                continue;
            }
            let id: ParamId = c.parse().map_err(|_| OperatingPointsError::UnknownColumn {
                path: path.clone(),
                name: c.clone(),
                number: j + 1,
                weight: weight.map(str::to_string),
            })?;
            ids.push(id);
            names.push(id.name());
            param_cols.push(j);
        }
        if names.is_empty() {
            return Err(OperatingPointsError::NoParameterColumn {
                path,
                columns: t.columns.clone(),
            });
        }
        let mut values = Vec::with_capacity(t.rows.len());
        for (i, row) in t.rows.iter().enumerate() {
            let mut p = *base;
            let mut v = Vec::with_capacity(names.len());
            for (&j, &id) in param_cols.iter().zip(&ids) {
                p.try_set(id, row[j])
                    .map_err(|source| OperatingPointsError::Param {
                        at: t.at(i, j),
                        source,
                    })?;
                v.push(row[j]);
            }
            if !cross_rules_drawn {
                if let Err(source @ ParamError::Inconsistent { .. }) = p.validate() {
                    return Err(OperatingPointsError::Param {
                        at: format!("{}, {}", path.display(), t.row_name(i)),
                        source,
                    });
                }
            }
            values.push(v);
        }
        let weights: Vec<f64> = match weight_col {
            Some(j) => {
                for (i, row) in t.rows.iter().enumerate() {
                    if row[j] < 0.0 {
                        return Err(OperatingPointsError::NegativeWeight {
                            at: t.at(i, j),
                            weight: row[j],
                        });
                    }
                }
                t.rows.iter().map(|r| r[j]).collect()
            }
            None => vec![1.0; t.rows.len()],
        };
        let table =
            AliasTable::new(&weights).ok_or_else(|| OperatingPointsError::AllWeightsZero {
                path: path.clone(),
                weight: weight.unwrap_or_default().to_string(),
            })?;
        Ok(OperatingPoints {
            file: file.to_string(),
            path: std::path::absolute(&path).unwrap_or(path),
            weight: weight.map(str::to_string),
            names,
            values,
            weights,
            hash: t.hash,
            bytes: t.bytes,
            table,
        })
    }

    /// The row (0-based) sample `index` draws: an alias-table draw from the sample's stream at
    /// [`ROW_AXIS`], a pure function of (seed, index).
    pub fn draw(&self, streams: &Streams, index: u64) -> usize {
        self.table.draw(&mut streams.at(index, ROW_AXIS))
    }

    /// The probability of drawing row `row` (weight / total weight, as the table holds it).
    pub fn probability(&self, row: usize) -> f64 {
        self.table.probability(row)
    }

    /// What the manifest and every chunk record: the file as named and as read, its hash and
    /// size, its rows, the weight column and the draw.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "file": self.file,
            "path": self.path.display().to_string(),
            "hash": self.hash,
            "hash_kind": "FNV-1a 64 of the file's bytes",
            "bytes": self.bytes,
            "rows": self.values.len(),
            "columns": self.names,
            "weight": self.weight,
            "draw": format!("alias table (Vose), rows of positive weight; axis {ROW_AXIS} of the sample's stream"),
        })
    }
}
