//! Reading a drive cycle file, and the checks that refuse a cycle before any work, naming the
//! file, row and column: its columns, its times and speeds, the constants of the tire's life,
//! its sums, the plausible ranges and the rules tying several parameters together.

use std::path::Path;

use super::{CycleError, DriveCycle, LIFE_CONSTANTS, NO_SPREAD, STEP_EVALUATIONS_MAX};
use crate::table_input::NumericTable;
use polywear_core::params::{ParamId, Params};

impl DriveCycle {
    /// Reads and checks a cycle file (CSV or Parquet): `time_s` strictly increasing, `speed_kmh`
    /// in [0, 400], every other column a parameter of `polywear params` within its range, at
    /// least two steps. Refusals name the file, row and column.
    pub fn read(path: &Path) -> Result<DriveCycle, CycleError> {
        // A column that is neither `time_s` nor a parameter is refused by its name, before its
        // cells are read as numbers.
        let t = NumericTable::read_at_most(
            path,
            &|c| c != "time_s" && c.parse::<ParamId>().is_err(),
            Some((
                STEP_EVALUATIONS_MAX,
                "a drive cycle's steps, each kept in memory with its records: about 3 KB a step, \
                 7 KB with the wear stage; resample it to fewer steps, e.g. 1 Hz",
            )),
        )?;
        let need = |name: &'static str| {
            t.column(name).ok_or_else(|| CycleError::MissingColumn {
                path: path.to_path_buf(),
                name,
                columns: t.columns.clone(),
            })
        };
        let (tc, vc) = (need("time_s")?, need("speed_kmh")?);
        let (names, cols) = parameter_columns(path, &t, (tc, vc))?;
        if t.rows.len() < 2 {
            return Err(CycleError::OneStep {
                path: path.to_path_buf(),
            });
        }
        let values = checked_steps(&t, (tc, vc), &cols, &names)?;
        check_unused_and_life_columns(path, &t, &cols, &names, &values)?;
        let cycle = DriveCycle {
            path: path.to_path_buf(),
            hash: t.hash.clone(),
            time_s: t.rows.iter().map(|r| r[tc]).collect(),
            speed_kmh: t.rows.iter().map(|r| r[vc]).collect(),
            names,
            values,
            table: t,
        };
        cycle.check_sums()?;
        Ok(cycle)
    }

    /// Refuses a cycle whose step durations, total time or distance overflow: every sum a
    /// summary forms must be finite, or its shares would be NaN.
    fn check_sums(&self) -> Result<(), CycleError> {
        let durations = self.step_durations_s();
        let bad = |what, value: f64| CycleError::NotFiniteSum {
            path: self.path.clone(),
            what,
            value,
        };
        if let Some(d) = durations.iter().find(|d| !d.is_finite()) {
            return Err(bad("step duration", *d));
        }
        let total: f64 = durations.iter().sum();
        if !total.is_finite() {
            return Err(bad("total time", total));
        }
        let distance: f64 = durations
            .iter()
            .zip(&self.speed_kmh)
            .map(|(d, v)| d * v / 3.6)
            .sum();
        if !distance.is_finite() {
            return Err(bad("distance", distance));
        }
        Ok(())
    }

    /// Refuses, before any work, the first step whose value of a parameter column lies outside
    /// its plausible range (a likely unit mix-up, MODEL.md#parameter-table), naming its row
    /// and column.
    pub fn check_plausible(&self) -> Result<(), CycleError> {
        let cols: Vec<usize> = self
            .names
            .iter()
            .map(|id| self.table.column(id.name()).expect("a column of the file"))
            .collect();
        for (i, step) in self.values.iter().enumerate() {
            for ((&id, &x), &j) in self.names.iter().zip(step).zip(&cols) {
                id.spec()
                    .check_plausible(x)
                    .map_err(|source| CycleError::Param {
                        at: self.table.at(i, j),
                        source,
                    })?;
            }
        }
        Ok(())
    }

    /// Refuses, before any work, a step whose parameters break a rule tying several together
    /// (e.g. mu_s ≤ mu_m) on top of `base`, naming its row.
    pub fn check_steps(&self, base: &Params) -> Result<(), CycleError> {
        for i in 0..self.len() {
            self.step_params(base, i)
                .validate()
                .map_err(|source| CycleError::Param {
                    at: format!("{}, {}", self.path.display(), self.table.row_name(i)),
                    source,
                })?;
        }
        Ok(())
    }
}

/// The parameter given per step by each column other than `time_s` and `speed_kmh` (`tc`,
/// `vc`), with its column, in file order; a toe-in given another way than the angle, or a
/// column that is no parameter, is refused.
fn parameter_columns(
    path: &Path,
    t: &NumericTable,
    (tc, vc): (usize, usize),
) -> Result<(Vec<ParamId>, Vec<usize>), CycleError> {
    let mut names = Vec::new();
    let mut cols = Vec::new();
    for (j, c) in t.columns.iter().enumerate() {
        if j == tc || j == vc {
            continue;
        }
        if polywear_core::params::toe::ToeInput::parse(c).is_some() {
            return Err(CycleError::ToeColumn {
                path: path.to_path_buf(),
                name: c.clone(),
                number: j + 1,
            });
        }
        let id: ParamId = c.parse().map_err(|_| CycleError::UnknownColumn {
            path: path.to_path_buf(),
            name: c.clone(),
            number: j + 1,
        })?;
        names.push(id);
        cols.push(j);
    }
    polywear_core::params::axle::check_one_place(&names, "the cycle's columns").map_err(
        |source| CycleError::AxleColumns {
            path: path.to_path_buf(),
            source,
        },
    )?;
    Ok((names, cols))
}

/// Each step's values of the parameter columns (`cols`, of `names`), checked row by row: the
/// time (column `tc`) strictly increasing, the speed (column `vc`) 0 or within its range, every
/// parameter within its range.
fn checked_steps(
    t: &NumericTable,
    (tc, vc): (usize, usize),
    cols: &[usize],
    names: &[ParamId],
) -> Result<Vec<Vec<f64>>, CycleError> {
    let speed_spec = ParamId::SpeedKmh.spec();
    let mut values = Vec::with_capacity(t.rows.len());
    for (i, row) in t.rows.iter().enumerate() {
        if i > 0 && row[tc] <= t.rows[i - 1][tc] {
            return Err(CycleError::TimeNotIncreasing {
                at: t.at(i, tc),
                time_s: row[tc],
                previous_s: t.rows[i - 1][tc],
            });
        }
        let v = row[vc];
        if v < 0.0 {
            return Err(CycleError::NegativeSpeed {
                at: t.at(i, vc),
                speed_kmh: v,
                range: speed_spec.range_text(),
            });
        }
        if v > 0.0 {
            speed_spec.check(v).map_err(|source| CycleError::Param {
                at: t.at(i, vc),
                source,
            })?;
        }
        let mut step = Vec::with_capacity(cols.len());
        for (&j, id) in cols.iter().zip(names) {
            id.spec()
                .check(row[j])
                .map_err(|source| CycleError::Param {
                    at: t.at(i, j),
                    source,
                })?;
            step.push(row[j]);
        }
        values.push(step);
    }
    Ok(values)
}

/// Refuses a column the cycle does not use (the speed spread: its speeds are its spread) and a
/// column of one of the [`LIFE_CONSTANTS`] whose value changes from step to step (`values`, the
/// steps' values of the columns `cols`, of `names`).
fn check_unused_and_life_columns(
    path: &Path,
    t: &NumericTable,
    cols: &[usize],
    names: &[ParamId],
    values: &[Vec<f64>],
) -> Result<(), CycleError> {
    for (k, (&j, &id)) in cols.iter().zip(names).enumerate() {
        if id == ParamId::SpeedSpreadKmh {
            return Err(CycleError::UnusedColumn {
                path: path.to_path_buf(),
                name: id.name(),
                why: NO_SPREAD,
            });
        }
        if !LIFE_CONSTANTS.contains(&id) {
            continue;
        }
        let first = values[0][k];
        if let Some(i) = values.iter().position(|step| step[k] != first) {
            return Err(CycleError::VaryingLifeConstant {
                at: t.at(i, j),
                name: id.name(),
                first,
                value: values[i][k],
            });
        }
    }
    Ok(())
}
