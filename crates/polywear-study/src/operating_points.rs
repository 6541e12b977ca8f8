//! Measured operating points as study input: a study's `[operating_points]` names a CSV or
//! Parquet file whose columns are parameters of `polywear params`, optionally one weight column
//! (hours or km driven there; `km` is computed as `hours` × `speed_kmh` where the file has no
//! `km` column), and columns the study passes through to the output unchanged (`pass_through`:
//! vehicle ids, a second weight). Each sample of a study draws one row, with probability
//! proportional to its weight, through an alias table and the study's ChaCha12 generator; the
//! row's values set the parameters it names, and every other drawn parameter (the tire
//! structure) is drawn as without the file. So the file's correlations (load with pressure,
//! speed with load) are kept, and the structure still varies per sample.
//!
//! The whole file is checked before any work: every refusal names the file, row and column.
//! The same columns make the points of `polywear classify` ([`FleetColumns`]).

use std::path::{Path, PathBuf};

use crate::parquet_out::Column;
use crate::table_input::{NumericTable, TableError};
use polywear_core::params::{ParamError, ParamId, Params};
use polywear_core::sampling::alias::AliasTable;
use polywear_core::sampling::Streams;
use polywear_core::wording::closest;

/// Why an operating-point file is refused, naming the file, row and column.
#[derive(Debug, thiserror::Error)]
pub enum OperatingPointsError {
    /// The file cannot be read as a table of numbers.
    #[error(transparent)]
    Table(#[from] TableError),
    /// A shared column beside an axle's own column of the same quantity (`toe_deg` and
    /// `toe_rear_deg`).
    #[error("{}: {source}", path.display())]
    AxleColumns {
        /// The operating-point file.
        path: PathBuf,
        /// Which keys.
        source: ParamError,
    },
    /// The weight column named in the study is missing.
    #[error("{}: no column `{weight}`, which {key} names{}{} (columns: {})", path.display(), km_hint(weight, columns), column_hint(weight, columns), columns.join(", "))]
    NoWeightColumn {
        /// The file.
        path: PathBuf,
        /// The key or flag that names it.
        key: String,
        /// The weight column named.
        weight: String,
        /// The columns it has.
        columns: Vec<String>,
    },
    /// A weight column that is a parameter: it would be the weight and never set the parameter.
    #[error("{key} = \"{weight}\" names a parameter of `polywear params`; a parameter column sets the model's value at each row, the weight says how much the row counts: name a column of hours or km driven there (e.g. `hours`, `km`)")]
    WeightIsParameter {
        /// The key or flag that names it.
        key: String,
        /// The column named.
        weight: String,
    },
    /// A column that is neither a parameter, the weight column nor passed through.
    #[error("{}: column `{name}` (column {number}) is not a parameter of `polywear params`{hint}", path.display())]
    UnknownColumn {
        /// The file.
        path: PathBuf,
        /// The column's name.
        name: String,
        /// Its position, counted from 1.
        number: usize,
        /// Nor the weight column, did you mean, and how to name a weight or a column carried
        /// through.
        hint: String,
    },
    /// A column to pass through that the file does not have, or names twice.
    #[error("{key}: {problem}")]
    PassThrough {
        /// The key or flag.
        key: String,
        /// What is wrong, with the accepted names.
        problem: String,
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
    #[error("{at}: weight {} is negative; weights must be >= 0", polywear_core::wording::plain(*weight, 12))]
    NegativeWeight {
        /// File, row and column.
        at: String,
        /// The weight given.
        weight: f64,
    },
    /// A weight computed as hours × speed that is not a finite number.
    #[error("{at}: weight `km` computed as hours × speed_kmh = {} × {} is not a finite number; accepted: hours × speed_kmh below 1.8e308 km (give the distance as a `km` column, or hours in a smaller unit of the same ratio)", polywear_core::wording::plain(*hours, 6), polywear_core::wording::plain(*speed_kmh, 6))]
    ComputedWeightNotFinite {
        /// File, row and column.
        at: String,
        /// The row's hours.
        hours: f64,
        /// Its speed \[km/h\].
        speed_kmh: f64,
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

/// The end of an unknown column's refusal: " nor the weight column `hours`", the closest
/// parameter or passed-through name, and how to name a weight (where none is named) or a column
/// carried into the output.
fn unknown_column_hint(
    name: &str,
    weight: Option<&str>,
    pass_through: &[String],
    keys: FleetKeys,
) -> String {
    let nor = weight
        .map(|w| format!(" nor the weight column `{w}`"))
        .unwrap_or_default();
    let how = if weight.is_some() {
        format!(
            "; a column carried into the output unchanged is named in {}",
            keys.pass_through
        )
    } else {
        format!(
            "; a weight column is named in {}, a column carried into the output unchanged in {}",
            keys.weight, keys.pass_through
        )
    };
    format!("{nor}{}{how}", did_you_mean(name, pass_through))
}

/// "; did you mean `speed_kmh`?" for a misspelt parameter or passed-through name, or nothing.
fn did_you_mean(name: &str, pass_through: &[String]) -> String {
    let params = polywear_core::params::ParamId::names();
    closest(
        name,
        params
            .into_iter()
            .chain(pass_through.iter().map(String::as_str)),
    )
    .map(|n| format!("; did you mean `{n}`?"))
    .unwrap_or_default()
}

/// How `km` is computed where the file has none, or why it cannot be.
fn km_hint(weight: &str, columns: &[String]) -> String {
    let has = |c: &str| columns.iter().any(|x| x == c);
    match (weight == KM, has(HOURS), has("speed_kmh")) {
        (true, true, false) => "; km can be computed as `hours` × `speed_kmh` only where the file gives each row's speed (a `speed_kmh` column)".into(),
        (true, false, _) => "; km can be computed as `hours` × `speed_kmh` only from an `hours` column".into(),
        _ => String::new(),
    }
}

/// "; did you mean `hours`?" for a misspelt column of the file, or nothing.
fn column_hint(typed: &str, columns: &[String]) -> String {
    closest(typed, columns.iter().map(String::as_str))
        .map(|c| format!("; did you mean `{c}`?"))
        .unwrap_or_default()
}

/// The weight column of time driven at a row.
pub(crate) const HOURS: &str = "hours";
/// The weight column of distance driven at a row.
pub const KM: &str = "km";

/// The generator axis of the row draw within each sample's stream: the last axis a stream has
/// (2^36 − 1, see [`polywear_core::sampling::rng`]), far from the drawn parameters' axes 0, 1, …, so
/// the row draw and the structure draws are independent and neither shifts the other.
pub const ROW_AXIS: u64 = (1 << 36) - 1;

/// What a row's weight measures, as the manifest records it (`weight_kind`), so that a report
/// can say what its probabilities are shares of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WeightKind {
    /// Time driven at the row (`hours`): probabilities are shares of the driving time.
    Time,
    /// Distance driven at the row (`km`): shares of the distance, which is what wears a tire.
    Distance,
    /// No weight column: every row counts the same.
    Equal,
    /// Another column (trips, counts), as the file defines it.
    Other,
}

impl WeightKind {
    /// The kind as recorded: `time`, `distance`, `equal` or `other`.
    pub fn as_str(self) -> &'static str {
        match self {
            WeightKind::Time => "time",
            WeightKind::Distance => "distance",
            WeightKind::Equal => "equal",
            WeightKind::Other => "other",
        }
    }

    /// The kind of a weight column by its name (`hours`, `km`; None: no weight).
    pub fn of(weight: Option<&str>) -> WeightKind {
        match weight {
            None => WeightKind::Equal,
            Some(HOURS) => WeightKind::Time,
            Some(KM) => WeightKind::Distance,
            Some(_) => WeightKind::Other,
        }
    }
}

/// The values of a column carried from the file into the outputs unchanged.
#[derive(Debug, Clone, PartialEq)]
pub enum PassValues {
    /// Every cell a finite number.
    Numbers(Vec<f64>),
    /// Identifiers or labels, as written.
    Text(Vec<String>),
}

/// A column carried from the file into the outputs unchanged (`pass_through`).
#[derive(Debug, Clone, PartialEq)]
pub struct PassThrough {
    /// The column's name, as in the file.
    pub name: String,
    /// One value per row of the file.
    pub values: PassValues,
}

impl PassThrough {
    /// The output column for `rows` (0-based rows of the file, one per output row).
    pub fn column(&self, rows: &[usize]) -> Column {
        match &self.values {
            PassValues::Numbers(v) => {
                Column::f64(&self.name, "", rows.iter().map(|&r| v[r]).collect())
            }
            PassValues::Text(v) => {
                Column::str(&self.name, rows.iter().map(|&r| v[r].clone()).collect())
            }
        }
    }
}

/// The keys (or flags) that name a file's weight and passed-through columns, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FleetKeys {
    /// `operating_points.weight` or `--weight`.
    pub weight: &'static str,
    /// `operating_points.pass_through` or `--pass-through`.
    pub pass_through: &'static str,
}

/// The keys of a study's `[operating_points]`.
pub(crate) const STUDY_KEYS: FleetKeys = FleetKeys {
    weight: "`operating_points.weight`",
    pass_through: "`operating_points.pass_through`",
};

/// A file's columns sorted into parameters, one weight and passed-through columns, every cell
/// checked: parameter values in their accepted ranges, weights finite and non-negative. Both
/// `[operating_points]` and the points of `polywear classify` are read through it.
#[derive(Debug, Clone, PartialEq)]
pub struct FleetColumns {
    /// The parameter columns, in file order.
    pub ids: Vec<ParamId>,
    /// `values[i][j]`: row i's value of `ids[j]`.
    pub values: Vec<Vec<f64>>,
    /// The weight column's name, as the study or flag gives it.
    pub weight: Option<String>,
    /// What the weight measures.
    pub weight_kind: WeightKind,
    /// How the weight is computed where the file has no such column (`hours * speed_kmh`).
    pub weight_computed: Option<String>,
    /// Each row's weight (1 without a weight column).
    pub weights: Vec<f64>,
    /// The columns passed through, in the order the study names them.
    pub pass_through: Vec<PassThrough>,
    /// The first cell outside its parameter's plausible range, with where it is
    /// (`FILE, row R (line L), column `NAME``); refused unless accepted.
    pub first_implausible: Option<(String, ParamError)>,
}

impl FleetColumns {
    /// What a points file read from `path` adds to its output's metadata: the file, the weight
    /// column and what it measures (and how it is computed), so that a fleet's weighted rows
    /// keep their meaning; nothing for a file of plain points.
    pub fn metadata(&self, path: &Path) -> Vec<(String, String)> {
        if self.weight.is_none() && self.pass_through.is_empty() {
            return Vec::new();
        }
        let mut meta = vec![
            ("points".into(), path.display().to_string()),
            ("weight".into(), self.weight.clone().unwrap_or_default()),
            ("weight_kind".into(), self.weight_kind.as_str().into()),
        ];
        if let Some(how) = &self.weight_computed {
            meta.push(("weight_computed".into(), how.clone()));
        }
        meta
    }

    /// Reads `path` and sorts its columns (see [`FleetColumns`]).
    pub fn read(
        path: &Path,
        weight: Option<&str>,
        pass_through: &[String],
        keys: FleetKeys,
    ) -> Result<(FleetColumns, NumericTable), OperatingPointsError> {
        // Every column that is no parameter is read as text, so that it is judged by its name
        // (weight, passed through, or refused as unknown) before its cells.
        let t = NumericTable::read_with_text(path, &|c| c.parse::<ParamId>().is_err())?;
        let f = FleetColumns::of(&t, weight, pass_through, keys)?;
        Ok((f, t))
    }

    /// Sorts the columns of a table read with `pass_through` as text.
    fn of(
        t: &NumericTable,
        weight: Option<&str>,
        pass_through: &[String],
        keys: FleetKeys,
    ) -> Result<FleetColumns, OperatingPointsError> {
        check_pass_through(t, pass_through, keys)?;
        let (weight_col, computed) = weight_source(t, weight, keys)?;
        let mut ids = Vec::new();
        let mut param_cols = Vec::new();
        for (j, c) in t.columns.iter().enumerate() {
            let used = Some(j) == weight_col
                || computed.is_some_and(|(h, _)| h == j)
                || pass_through.contains(c);
            if used {
                continue;
            }
            let id: ParamId = c.parse().map_err(|_| OperatingPointsError::UnknownColumn {
                path: t.path.clone(),
                name: c.clone(),
                number: j + 1,
                hint: unknown_column_hint(c, weight, pass_through, keys),
            })?;
            ids.push(id);
            param_cols.push(j);
        }
        polywear_core::params::axle::check_one_place(&ids, "the file's columns").map_err(
            |source| OperatingPointsError::AxleColumns {
                path: t.path.clone(),
                source,
            },
        )?;
        let mut values = Vec::with_capacity(t.rows.len());
        let mut first_implausible = None;
        for (i, row) in t.rows.iter().enumerate() {
            let mut v = Vec::with_capacity(ids.len());
            for (&j, &id) in param_cols.iter().zip(&ids) {
                let s = id.spec();
                s.check(row[j])
                    .map_err(|source| OperatingPointsError::Param {
                        at: t.at(i, j),
                        source,
                    })?;
                if first_implausible.is_none() {
                    first_implausible = s.check_plausible(row[j]).err().map(|e| (t.at(i, j), e));
                }
                v.push(row[j]);
            }
            values.push(v);
        }
        let weights = weights(t, weight_col, computed)?;
        Ok(FleetColumns {
            ids,
            values,
            weight: weight.map(str::to_string),
            weight_kind: WeightKind::of(weight),
            weight_computed: computed.map(|_| format!("{HOURS} * speed_kmh")),
            weights,
            pass_through: pass_through
                .iter()
                .map(|name| pass_values(t, name))
                .collect(),
            first_implausible,
        })
    }

    /// Refuses the first implausible cell (see `first_implausible`).
    pub fn check_plausible(&self) -> Result<(), OperatingPointsError> {
        refuse_implausible(&self.first_implausible)
    }
}

/// The line that says how a computed weight is made (before any work): `weight: FILE has no
/// `km` column; each row's km = hours * speed_kmh (its hours at its speed)`.
pub(crate) fn computed_weight_note(path: &Path, how: &str) -> String {
    format!(
        "weight: {} has no `{KM}` column; each row's km = {how} (its hours at its speed)",
        path.display()
    )
}

/// The refusal of a recorded implausible cell, if any.
fn refuse_implausible(found: &Option<(String, ParamError)>) -> Result<(), OperatingPointsError> {
    match found {
        Some((at, source)) => Err(OperatingPointsError::Param {
            at: at.clone(),
            source: source.clone(),
        }),
        None => Ok(()),
    }
}

/// Refuses a passed-through name the file does not have, a name given twice, and a parameter.
fn check_pass_through(
    t: &NumericTable,
    pass_through: &[String],
    keys: FleetKeys,
) -> Result<(), OperatingPointsError> {
    let refuse = |problem: String| OperatingPointsError::PassThrough {
        key: keys.pass_through.to_string(),
        problem,
    };
    for (k, name) in pass_through.iter().enumerate() {
        if pass_through[..k].contains(name) {
            return Err(refuse(format!("`{name}` is named twice")));
        }
        if name.parse::<ParamId>().is_ok() {
            return Err(refuse(format!(
                "`{name}` is a parameter of `polywear params`: a parameter column sets the model's value at each row and is in the output already; pass through only other columns"
            )));
        }
        if t.column(name).is_none() {
            return Err(refuse(format!(
                "{} has no column `{name}`{} (columns: {})",
                t.path.display(),
                column_hint(name, &t.columns),
                t.columns.join(", ")
            )));
        }
    }
    Ok(())
}

/// The weight's column, or the `hours` and `speed_kmh` columns `km` is computed from.
type WeightSource = (Option<usize>, Option<(usize, usize)>);

/// Where the weight comes from: its column, or for `km` without one, `hours` × `speed_kmh`.
fn weight_source(
    t: &NumericTable,
    weight: Option<&str>,
    keys: FleetKeys,
) -> Result<WeightSource, OperatingPointsError> {
    let Some(w) = weight else {
        return Ok((None, None));
    };
    if w.parse::<ParamId>().is_ok() {
        return Err(OperatingPointsError::WeightIsParameter {
            key: keys.weight.to_string(),
            weight: w.to_string(),
        });
    }
    if let Some(j) = t.column(w) {
        return Ok((Some(j), None));
    }
    if let (KM, Some(h), Some(v)) = (w, t.column(HOURS), t.column("speed_kmh")) {
        return Ok((None, Some((h, v))));
    }
    Err(OperatingPointsError::NoWeightColumn {
        path: t.path.clone(),
        key: keys.weight.to_string(),
        weight: w.to_string(),
        columns: t.columns.clone(),
    })
}

/// Each row's weight, checked finite and non-negative (1 without a weight).
fn weights(
    t: &NumericTable,
    weight_col: Option<usize>,
    computed: Option<(usize, usize)>,
) -> Result<Vec<f64>, OperatingPointsError> {
    let Some(j) = weight_col.or(computed.map(|(h, _)| h)) else {
        return Ok(vec![1.0; t.rows.len()]);
    };
    let mut out = Vec::with_capacity(t.rows.len());
    for (i, row) in t.rows.iter().enumerate() {
        let x = row[j];
        if !x.is_finite() {
            let text = t.text_of(j).map_or(String::new(), |c| c[i].clone());
            let at = t.at(i, j);
            return Err(match text.parse::<f64>() {
                _ if text.is_empty() => TableError::EmptyCell { at },
                Ok(value) => TableError::NotFinite { at, value },
                Err(_) => TableError::NotANumber { at, text },
            }
            .into());
        }
        if x < 0.0 {
            return Err(OperatingPointsError::NegativeWeight {
                at: t.at(i, j),
                weight: x,
            });
        }
        let w = match computed {
            Some((_, v)) => x * row[v],
            None => x,
        };
        if !w.is_finite() {
            return Err(OperatingPointsError::ComputedWeightNotFinite {
                at: t.at(i, j),
                hours: x,
                speed_kmh: computed.map_or(f64::NAN, |(_, v)| row[v]),
            });
        }
        out.push(w);
    }
    Ok(out)
}

/// A passed-through column's values: numbers where every cell is one, text otherwise.
fn pass_values(t: &NumericTable, name: &str) -> PassThrough {
    let j = t.column(name).expect("checked by check_pass_through");
    let cells = t.text_of(j).expect("read as text");
    let numbers: Vec<f64> = t.rows.iter().map(|r| r[j]).collect();
    let values = if numbers.iter().all(|x| x.is_finite()) {
        PassValues::Numbers(numbers)
    } else {
        PassValues::Text(cells.to_vec())
    };
    PassThrough {
        name: name.to_string(),
        values,
    }
}

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
    /// What the weight measures.
    pub weight_kind: WeightKind,
    /// How the weight is computed where the file has no such column (`hours * speed_kmh`).
    pub weight_computed: Option<String>,
    /// The columns the study passes through to the output (`pass_through`).
    pub pass_through: Vec<PassThrough>,
    /// FNV-1a 64 of the file's bytes (16 hex digits), recorded in the manifest and every chunk.
    pub hash: String,
    /// The file's size in bytes, recorded beside the hash.
    pub bytes: u64,
    first_implausible: Option<(String, ParamError)>,
    table: AliasTable,
}

impl OperatingPoints {
    /// Reads and checks the file `file` (relative to `dir` unless absolute) against `base` (the
    /// study's fixed values): every column a parameter, the weight column or passed through,
    /// every value in its parameter's range, weights finite and non-negative and not all zero.
    /// `cross_rules_drawn`: whether the study draws a parameter of a cross-parameter rule
    /// (mu_s ≤ mu_m, n_driven ≤ n_wheels); if not, a row that breaks one is refused here.
    pub fn load(
        file: &str,
        weight: Option<&str>,
        pass_through: &[String],
        dir: &Path,
        base: &Params,
        cross_rules_drawn: bool,
    ) -> Result<OperatingPoints, OperatingPointsError> {
        let path = dir.join(file);
        let (f, t) = FleetColumns::read(&path, weight, pass_through, STUDY_KEYS)?;
        if f.ids.is_empty() {
            return Err(OperatingPointsError::NoParameterColumn {
                path,
                columns: t.columns.clone(),
            });
        }
        if !cross_rules_drawn {
            for (i, row) in f.values.iter().enumerate() {
                let mut p = *base;
                for (&id, &x) in f.ids.iter().zip(row) {
                    p[id] = x;
                }
                if let Err(source @ ParamError::Inconsistent { .. }) = p.validate() {
                    return Err(OperatingPointsError::Param {
                        at: format!("{}, {}", path.display(), t.row_name(i)),
                        source,
                    });
                }
            }
        }
        let table =
            AliasTable::new(&f.weights).ok_or_else(|| OperatingPointsError::AllWeightsZero {
                path: path.clone(),
                weight: weight.unwrap_or_default().to_string(),
            })?;
        Ok(OperatingPoints {
            file: file.to_string(),
            path: std::path::absolute(&path).unwrap_or(path),
            weight: f.weight,
            names: f.ids.iter().map(|id| id.name()).collect(),
            values: f.values,
            weights: f.weights,
            weight_kind: f.weight_kind,
            weight_computed: f.weight_computed,
            pass_through: f.pass_through,
            hash: t.hash,
            bytes: t.bytes,
            first_implausible: f.first_implausible,
            table,
        })
    }

    /// Refuses the first cell outside its parameter's plausible range, naming file, row and
    /// column, with the likely unit mix-up.
    pub fn check_plausible(&self) -> Result<(), OperatingPointsError> {
        refuse_implausible(&self.first_implausible)
    }

    /// The columns passed through, for `rows` (0-based rows of the file, one per output row).
    pub fn pass_through_columns(&self, rows: &[usize]) -> Vec<Column> {
        self.pass_through.iter().map(|c| c.column(rows)).collect()
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
    /// size, its rows, the weight column, what it measures and how it is computed, the columns
    /// passed through, and the draw.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "file": self.file,
            "path": self.path.display().to_string(),
            "hash": self.hash,
            "hash_kind": "FNV-1a 64 of the file's bytes",
            "bytes": self.bytes,
            "rows": self.values.len(),
            "columns": self.names,
            "pass_through": self.pass_through.iter().map(|c| &c.name).collect::<Vec<_>>(),
            "weight": self.weight,
            "weight_computed": self.weight_computed,
            "weight_kind": self.weight_kind.as_str(),
            "draw": format!("alias table (Vose), rows of positive weight; axis {ROW_AXIS} of the sample's stream"),
        })
    }
}
