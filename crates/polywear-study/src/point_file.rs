//! A file of operating points (`polywear classify`): one point per row, each row applied on top
//! of the defaults (or a `--params` file) and validated before any work, with a fleet's weight
//! and passed-through columns; and the output's columns.

use std::path::Path;

use polywear_core::model::Wheel;
use polywear_core::params::Params;
use polywear_core::records::{record_columns, WheelRecord};

use crate::operating_points::{computed_weight_note, FleetColumns, FleetKeys};
use crate::param_sources::{param_file, refuse_reserved_names, Conflict, Refusal};
use crate::parquet_out::Column;

/// The points of a file, checked.
#[derive(Debug, Clone)]
pub struct PointFile {
    /// Every row's parameters.
    pub points: Vec<Params>,
    /// The file's columns: parameters, weight and passed-through ones.
    pub fleet: FleetColumns,
    /// The defaults with the `--params` file applied.
    pub base: Params,
    /// What to say before the work (how a computed weight is made).
    pub notes: Vec<String>,
}

/// The keys of the weight and passed-through columns, as classify's flags.
const KEYS: FleetKeys = FleetKeys {
    weight: "--weight",
    pass_through: "--pass-through",
};

/// Reads the points file, each row applied on top of the defaults (or `--params`) and validated,
/// before any work; a parameter both in `--params` and the file is refused.
pub fn read_points(
    path: &Path,
    params: Option<&Path>,
    weight: Option<&str>,
    pass_through: &[String],
    accept: bool,
) -> Result<PointFile, Refusal> {
    let (base, named) = param_file(params, accept)?;
    let (f, t) = FleetColumns::read(path, weight, pass_through, KEYS)?;
    if f.ids.is_empty() {
        return Err(Refusal::NoParameterColumn {
            path: path.to_path_buf(),
            columns: t.columns.clone(),
        });
    }
    if !accept {
        f.check_plausible()?;
    }
    if let (Some(file), Some(&id)) = (params, named.iter().find(|id| f.ids.contains(id))) {
        return Err(Conflict::PointColumn {
            params: file.to_path_buf(),
            id,
            points: path.to_path_buf(),
        }
        .into());
    }
    let carried = f
        .weight
        .iter()
        .map(String::as_str)
        .chain(f.pass_through.iter().map(|c| c.name.as_str()));
    refuse_reserved_names(carried, path, "--weight or --pass-through", &["point"])?;
    let mut points = Vec::with_capacity(f.values.len());
    for (i, row) in f.values.iter().enumerate() {
        let mut p = base;
        for (&id, &x) in f.ids.iter().zip(row) {
            p[id] = x;
        }
        p.validate().map_err(|source| Refusal::Param {
            by: format!("{}, {}", path.display(), t.row_name(i)),
            source,
        })?;
        points.push(p);
    }
    let notes = f
        .weight_computed
        .iter()
        .map(|how| computed_weight_note(path, how))
        .collect();
    Ok(PointFile {
        points,
        fleet: f,
        base,
        notes,
    })
}

/// The output's columns: `point`, the weight and the passed-through columns, the records.
pub fn output_columns(
    jobs: &[(usize, Wheel)],
    f: &FleetColumns,
    records: &[WheelRecord],
) -> Vec<Column> {
    let rows: Vec<usize> = jobs.iter().map(|j| j.0).collect();
    let mut cols = vec![Column::i64(
        "point",
        "",
        rows.iter().map(|&r| r as i64).collect(),
    )];
    if let Some(w) = &f.weight {
        if !f.pass_through.iter().any(|c| &c.name == w) {
            cols.push(Column::f64(
                w.as_str(),
                "",
                rows.iter().map(|&r| f.weights[r]).collect(),
            ));
        }
    }
    cols.extend(f.pass_through.iter().map(|c| c.column(&rows)));
    cols.extend(record_columns(records));
    cols
}
