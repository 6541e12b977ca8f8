//! What can be wrong with a file of calibrated sets ([`BandError`], naming the file, and the
//! set, range, key and line where that applies), with a fit of the sets ([`FitError`]), and
//! with a design table read back ([`DesignTableError`]).

use std::path::PathBuf;

use polywear_core::params::ParamId;
use polywear_core::wear::{FittedConstants, WearError};
use polywear_core::wording::plain;

use super::{evaluate, MAX_SETS, MAX_TEXT_CHARS};
use crate::study::{ParamChange, StudyError};
use crate::table_input::TableError;

/// Why a file of calibrated sets is refused: the file, and the set and key where that applies.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{file}: {what}")]
pub struct BandError {
    /// The file named in the message.
    pub file: String,
    /// What is wrong (boxed: a scenario's refusal carries its key, change, set and values).
    pub what: Box<BandProblem>,
}

/// What is wrong with a file of calibrated sets.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BandProblem {
    /// No text.
    #[error(
        "empty file; accepted: TOML with `method`, `generated_by`, `[fit]`, a `[[range]]` per calibrated constant and a `[[set]]` per calibrated set"
    )]
    Empty,
    /// Not TOML of a band's shape: where (the line, and the `[[set]]` it falls in) and what.
    #[error("{}{message}", toml_place(*line, *set))]
    Toml {
        /// The line, counted from 1 (None where the parser gives no place).
        line: Option<usize>,
        /// The `[[set]]` the line falls in, counted from 1 (None before the first).
        set: Option<usize>,
        /// What the parser says.
        message: String,
    },
    /// A text key (`method`, `generated_by`, `fit.shipped`, `fit.region`) that is not one
    /// plain line.
    #[error(
        "`{key}` {why}; accepted: one line of printable text, at most {} characters",
        MAX_TEXT_CHARS
    )]
    NotALine {
        /// The key.
        key: &'static str,
        /// Why.
        why: NotALine,
    },
    /// A `[[range]]` refused.
    #[error("range {number} (`{param}`): {why}")]
    Range {
        /// Its place among the ranges, counted from 1.
        number: usize,
        /// Its `param` as written.
        param: String,
        /// Why.
        why: RangeProblem,
    },
    /// A calibrated constant with no `[[range]]`.
    #[error(
        "no `[[range]]` for `{}`; accepted: one for each of {}",
        .0.name(),
        calibrated_names()
    )]
    MissingRange(ParamId),
    /// No `[[set]]`.
    #[error("no [[set]]: a band needs at least one")]
    NoSets,
    /// More sets than `MAX_SETS`.
    #[error("{0} sets; accepted at most {max}", max = MAX_SETS)]
    TooManySets(usize),
    /// A `[[set]]` refused.
    #[error("set {number} (`{id}`): {why}")]
    Set {
        /// Its place among the sets, counted from 1.
        number: usize,
        /// Its `id` as written.
        id: String,
        /// Why.
        why: SetProblem,
    },
    /// Not exactly one nominal set.
    #[error("{0} sets say `nominal = true`; accepted: exactly one")]
    Nominals(usize),
    /// A study's scenario that takes a set's constant outside its accepted range.
    #[error(
        "{scenario_key}: {} takes {out} of the band's {sets} sets outside the accepted range {} of `{}` (set `{set}` from {} to {}); change the scenario, or give another band (--calibration-band FILE or off)",
        change.words(),
        change.param.spec().range_text(),
        change.param.spec().name,
        plain(*from, 12),
        plain(*to, 12)
    )]
    ScenarioOutside {
        /// The scenario's key for the parameter (`scenarios.wet.wear_share_straight`).
        scenario_key: String,
        /// The change to a calibrated constant.
        change: ParamChange,
        /// The sets it takes outside.
        out: usize,
        /// The band's sets.
        sets: usize,
        /// The first set taken outside.
        set: String,
        /// That set's value.
        from: f64,
        /// Its value with the change.
        to: f64,
    },
}

/// "line 3: ", "line 12 (set 2): " or nothing: where in the file a TOML error lies.
fn toml_place(line: Option<usize>, set: Option<usize>) -> String {
    match (line, set) {
        (None, _) => String::new(),
        (Some(line), None) => format!("line {line}: "),
        (Some(line), Some(set)) => format!("line {line} (set {set}): "),
    }
}

/// The calibrated constants' names, as a list.
fn calibrated_names() -> String {
    FittedConstants::PARAMS
        .iter()
        .map(|p| p.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why a text is not one plain line for the report and the summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum NotALine {
    /// More than [`MAX_TEXT_CHARS`] characters.
    #[error("holds {0} characters")]
    TooLong(usize),
    /// Empty, or blank.
    #[error("is empty")]
    Empty,
    /// A line break or another control character.
    #[error("holds the control character {0:?}")]
    Control(char),
}

/// Why a `[[range]]` is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RangeProblem {
    /// Its `param` names no calibrated constant.
    #[error(
        "`param` names no calibrated constant; accepted: {}",
        calibrated_names()
    )]
    UnknownConstant,
    /// A second range for one constant.
    #[error("names `{0}` a second time")]
    Repeated(ParamId),
    /// Not a range within the parameter's accepted range.
    #[error(
        "[{}, {}] is not a range within `{}`'s accepted {}",
        plain(*min, 12),
        plain(*max, 12),
        id.spec().name,
        id.spec().range_text()
    )]
    NotWithin {
        /// The constant.
        id: ParamId,
        /// The range's lower end.
        min: f64,
        /// Its upper end.
        max: f64,
    },
    /// A `provenance` that is not one plain line.
    #[error("`provenance` {0}")]
    Provenance(NotALine),
}

/// Why a `[[set]]` is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SetProblem {
    /// An empty or malformed `id`.
    #[error("`id` must be non-empty letters, digits, `_`, `-` or `.`")]
    BadId,
    /// The `id` the band's rows give the run's own constants.
    #[error(
        "`id` = `{}` is reserved for the run's own constants in the band's rows; choose another id",
        evaluate::RUN_SET
    )]
    ReservedId,
    /// An `id` an earlier set has.
    #[error("`id` repeats an earlier set's")]
    RepeatedId,
    /// A constant outside its parameter's accepted range.
    #[error(
        "`{}` = {}: accepted {} ({})",
        id.spec().name,
        plain(*value, 12),
        id.spec().range_text(),
        id.spec().unit
    )]
    OutsideAccepted {
        /// The constant.
        id: ParamId,
        /// Its value.
        value: f64,
    },
    /// A constant outside the file's prior range for it.
    #[error(
        "`{}` = {} is outside the file's range [{}, {}] for it",
        id.spec().name,
        plain(*value, 12),
        plain(*min, 12),
        plain(*max, 12)
    )]
    OutsidePrior {
        /// The constant.
        id: ParamId,
        /// Its value.
        value: f64,
        /// The prior range's lower end.
        min: f64,
        /// Its upper end.
        max: f64,
    },
}

/// Why the calibrated sets cannot be fitted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The wear stage of the nominal tire cannot be calibrated.
    #[error(transparent)]
    Wear(#[from] WearError),
    /// The default study does not read on the nominal tire.
    #[error(transparent)]
    Study(#[from] StudyError),
    /// No wheel of the population has a loop.
    #[error("no wheel with a loop to fit on")]
    NoWheels,
    /// A fitting target missing from the field facts.
    #[error("the field facts have no `{0}`")]
    MissingFact(&'static str),
    /// `fleet_median_never` without the distance it is read at.
    #[error("`fleet_median_never` has no `min` distance")]
    NoFleetMin,
}

/// Why a design table ([`super::fit::design_columns`]) cannot be read back.
#[derive(Debug, thiserror::Error)]
pub enum DesignTableError {
    /// Not a table.
    #[error(transparent)]
    Table(#[from] TableError),
    /// A column missing.
    #[error("{}: no column `{name}`", path.display())]
    NoColumn {
        /// The table.
        path: PathBuf,
        /// The column.
        name: String,
    },
    /// A cell that is not a number.
    #[error("{}: `{name}` = `{value}` is not a number", path.display())]
    NotANumber {
        /// The table.
        path: PathBuf,
        /// The column.
        name: String,
        /// The cell as written.
        value: String,
    },
}

/// The band a command's `--calibration-band FILE` names, refused
/// ([`super::CalibrationBand::asked`]): the file cannot be read, or is not a band.
#[derive(Debug, thiserror::Error)]
pub enum BandFileError {
    /// The file cannot be read.
    #[error("--calibration-band {0}")]
    Unreadable(#[source] crate::safe_read::ReadError),
    /// The file is not a band.
    #[error("--calibration-band {0}")]
    Band(#[source] Box<BandError>),
}
