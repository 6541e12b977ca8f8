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

use crate::params::{spec, ParamError, Params};
use crate::sampling::alias::AliasTable;
use crate::sampling::Streams;
use crate::table_input::NumericTable;

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
    ) -> Result<OperatingPoints, String> {
        let path = dir.join(file);
        let t = NumericTable::read(&path).map_err(|e| e.0)?;
        let shown = path.display();
        let weight_col = match weight {
            Some(w) => Some(t.column(w).ok_or_else(|| {
                format!(
                    "{shown}: no column `{w}`, which `operating_points.weight` names (columns: {})",
                    t.columns.join(", ")
                )
            })?),
            None => None,
        };
        let mut names = Vec::new();
        let mut param_cols = Vec::new();
        for (j, c) in t.columns.iter().enumerate() {
            if Some(j) == weight_col {
                continue;
            }
            let s = spec(c).ok_or_else(|| {
                let weight_hint = match weight {
                    Some(w) => format!(" nor the weight column `{w}`"),
                    None => " (a weight column needs `weight = \"NAME\"` in [operating_points])"
                        .to_string(),
                };
                let hint = crate::params::suggest_name(c)
                    .map(|n| format!("; did you mean `{n}`?"))
                    .unwrap_or_default();
                format!(
                    "{shown}: column `{c}` (column {}) is not a parameter of `polywear params`{weight_hint}{hint}",
                    j + 1
                )
            })?;
            names.push(s.name);
            param_cols.push(j);
        }
        if names.is_empty() {
            return Err(format!(
                "{shown}: no parameter column (columns: {}); name parameters of `polywear params`, e.g. speed_kmh,load_n,pressure_kpa",
                t.columns.join(", ")
            ));
        }
        let mut values = Vec::with_capacity(t.rows.len());
        for (i, row) in t.rows.iter().enumerate() {
            let mut p = *base;
            let mut v = Vec::with_capacity(names.len());
            for (&j, name) in param_cols.iter().zip(&names) {
                p.set(name, row[j])
                    .map_err(|e| format!("{}: {e}", t.at(i, j)))?;
                v.push(row[j]);
            }
            if !cross_rules_drawn {
                if let Err(e @ ParamError::Inconsistent { .. }) = p.validate() {
                    return Err(format!("{shown}, {}: {e}", t.row_name(i)));
                }
            }
            values.push(v);
        }
        let weights: Vec<f64> = match weight_col {
            Some(j) => {
                for (i, row) in t.rows.iter().enumerate() {
                    if row[j] < 0.0 {
                        return Err(format!(
                            "{}: weight {} is negative; weights must be >= 0",
                            t.at(i, j),
                            row[j]
                        ));
                    }
                }
                t.rows.iter().map(|r| r[j]).collect()
            }
            None => vec![1.0; t.rows.len()],
        };
        let table = AliasTable::new(&weights).ok_or_else(|| {
            format!(
                "{shown}, column `{}`: every weight is zero; at least one row needs a positive weight",
                weight.unwrap_or_default()
            )
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
