//! What can be wrong with a study or a parameter file: one error per problem, each naming the
//! key it concerns and the accepted values.

use crate::toml_input::TomlError;
use polywear_core::params::ParamError;
use polywear_core::wording::{did_you_mean, plain};

use super::schema::DISTS;

/// A study problem, with the key it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StudyError {
    /// A wear setting (`wear_zone`, `wear_power`, the key named) is set for a study whose wear
    /// stage is off.
    #[error("`{0}` is set but `wear = false` leaves the wear stage out; remove one of the two")]
    WearSettingWithoutWear(&'static str),
    /// `wear_estimate` names a retired wear answer, or none polywear gives (the message says
    /// what replaced it).
    #[error("`wear_estimate` = \"{given}\": {why}; remove the key")]
    RetiredWearLevel {
        /// The value given.
        given: String,
        /// Why it is refused, and what replaced it.
        why: String,
    },
    /// A per-wheel budget key out of its accepted range (the message names the key).
    #[error("{0}")]
    Budget(#[from] polywear_core::classify::BudgetError),
    /// Syntax, unknown or missing keys, values of the wrong type.
    #[error(transparent)]
    Input(#[from] TomlError),
    /// A value refused by its parameter's accepted range, or an unknown parameter name.
    #[error("`{key}`: {source}")]
    Param {
        /// The key, in full.
        key: String,
        /// Why it was refused.
        source: ParamError,
    },
    /// The parameters of a parameter file do not fit together.
    #[error("{0}")]
    Inconsistent(ParamError),
    /// The study's fixed parameters do not fit together.
    #[error("fixed parameters: {0}")]
    FixedParams(ParamError),
    /// A `name` that cannot name a directory.
    #[error("`name` = \"{0}\" must be non-empty letters, digits, `_` or `-`")]
    BadName(String),
    /// A design that does not exist.
    #[error("`design` = \"{0}\" is unknown;{hint} accepted: random, lhs, sobol, grid, saltelli", hint = did_you_mean(.0, ["random", "lhs", "sobol", "grid", "saltelli"]))]
    UnknownDesign(String),
    /// A variant listed twice.
    #[error("`variants` lists \"{0}\" twice")]
    RepeatedVariant(String),
    /// A list or text that must not be empty.
    #[error("`{0}` must not be empty")]
    Empty(String),
    /// A distribution table without `dist`.
    #[error("`{key}` needs `dist` (one of {DISTS})")]
    NoDist {
        /// The key, in full.
        key: String,
    },
    /// A distribution that does not exist.
    #[error("`{key}.dist` = \"{dist}\" is unknown;{hint} accepted: {DISTS}, fixed", hint = did_you_mean(dist, DISTS.split(", ").chain(["fixed"])))]
    UnknownDist {
        /// The key, in full.
        key: String,
        /// The name given.
        dist: String,
    },
    /// A key the distribution does not take.
    #[error("`{key}.{field}` is not a key of a {dist} distribution;{hint} accepted: {accepted}", hint = did_you_mean(field, accepted.split(", ")))]
    NotADistKey {
        /// The parameter's key.
        key: String,
        /// The key it does not take.
        field: String,
        /// The distribution.
        dist: String,
        /// The keys it takes.
        accepted: String,
    },
    /// A distribution missing one of its keys.
    #[error("`{key}` ({dist}) needs `{field}`")]
    DistNeeds {
        /// The parameter's key.
        key: String,
        /// The distribution.
        dist: String,
        /// The missing key.
        field: String,
    },
    /// A spread (sd, sigma) that is not positive.
    #[error("`{key}` = {} must be positive", polywear_core::wording::plain(*value, 12))]
    NotPositive {
        /// The key, in full.
        key: String,
        /// The value given.
        value: f64,
    },
    /// Bounds with min not below max.
    #[error("`{key}`: min = {} must be below max = {}", polywear_core::wording::plain(*min, 12), polywear_core::wording::plain(*max, 12))]
    Unordered {
        /// The parameter's key.
        key: String,
        /// The lower bound given.
        min: f64,
        /// The upper bound given.
        max: f64,
    },
    /// A distribution can produce values outside its parameter's accepted range.
    #[error("`{key}`: its {which} value is outside the accepted range ({source}){hint}")]
    TailOutOfRange {
        /// The parameter's key.
        key: String,
        /// Which end: `smallest` or `largest`.
        which: &'static str,
        /// The range check that failed.
        source: ParamError,
        /// How to fix it (e.g. use a truncated normal), or empty.
        hint: &'static str,
    },
    /// Draws that can break a cross-parameter rule (μ_s ≤ μ_m, n_d ≤ n_w).
    #[error("{0}")]
    DrawnRule(String),
    /// A distribution whose values cannot be computed in floating point.
    #[error("`{key}`: {dist} gives no finite values; choose a mean and spread of the parameter's own magnitude")]
    CannotSample {
        /// The parameter's key.
        key: String,
        /// The distribution, as given.
        dist: String,
    },
    /// A grid design with a parameter that has no grid values.
    #[error("`{0}`: a grid design needs `levels` or a uniform `count` on every drawn parameter")]
    GridNeedsLevels(String),
    /// A grid of more than 2^40 points.
    #[error("`params`: the grid has more than 2^40 points")]
    GridTooLarge,
    /// `samples` that differs from the grid's size.
    #[error("`samples` = {samples} disagrees with the grid's size {size}")]
    GridSamples {
        /// The sample count given.
        samples: u64,
        /// The grid's size.
        size: u64,
    },
    /// More drawn parameters than the design supports.
    #[error(
        "`design` = \"{design}\" supports at most {max} drawn parameters, this study draws {drawn}"
    )]
    TooManyAxes {
        /// The design.
        design: &'static str,
        /// Its limit.
        max: usize,
        /// Parameters the study draws.
        drawn: usize,
    },
    /// A study that draws nothing.
    #[error("the study draws no parameter: give at least one a `dist` in [params]")]
    NothingDrawn,
    /// A problem with `[operating_points]` or its file (the message names file, row, column).
    #[error("[operating_points]: {0}")]
    OperatingPoints(String),
    /// A sample count of 0 (the command line names the flag that gave it).
    #[error("the sample count must be at least 1")]
    NoSamples,
    /// A sample count for a run that differs from the grid's size.
    #[error("{samples} samples disagree with the grid's size {size}: a grid study takes exactly its size")]
    SamplesNotGridSize {
        /// The sample count given.
        samples: u64,
        /// The grid's size.
        size: u64,
    },
    /// More samples than the design can address.
    #[error("a {design} design supports at most {max} samples")]
    TooManySamples {
        /// The design.
        design: &'static str,
        /// Its limit, as people read it.
        max: &'static str,
    },
    /// A scenario name that cannot be written in the rows and the report.
    #[error("`{key}`: the scenario's name {why}; accepted: 1 to 64 printable characters")]
    ScenarioName {
        /// The scenario's key.
        key: String,
        /// What is wrong with the name.
        why: &'static str,
    },
    /// A scenario name used twice (or the baseline's).
    #[error("scenario `{name}` is used twice: {why}; accepted: a name of its own for every [scenarios.NAME]")]
    RepeatedScenario {
        /// The name.
        name: String,
        /// Where it was used before.
        why: String,
    },
    /// A scenario without changes.
    #[error("`{key}` changes nothing; accepted: at least one parameter, e.g. toe_deg = {{ shift = -0.1 }}")]
    EmptyScenario {
        /// The scenario's key.
        key: String,
    },
    /// A change table without exactly one kind of change.
    #[error("`{key}` needs exactly one of set, shift, scale, cap; {}", if given.is_empty() { "it has none".to_string() } else { format!("it has {given}") })]
    ChangeKinds {
        /// The parameter's key in the scenario.
        key: String,
        /// The kinds given, comma-separated.
        given: String,
    },
    /// A scenario change that takes samples outside the parameter's accepted range.
    #[error("{0}")]
    ScenarioOutOfRange(Box<ChangeOutOfRange>),
    /// A `compare_to` that names no scenario of the study.
    #[error("`{key}` = {name:?} names no scenario of this study;{hint} accepted: {}", names_text(accepted), hint = did_you_mean(name, accepted.iter().map(String::as_str)))]
    UnknownReference {
        /// The scenario's `compare_to` key.
        key: String,
        /// The name given.
        name: String,
        /// The names it may take: `baseline` and the study's other scenarios.
        accepted: Vec<String>,
    },
    /// A scenario whose `compare_to` names itself: it would differ from itself by zero.
    #[error(
        "`{key}` = {name:?} compares the scenario with itself; accepted: {}",
        names_text(accepted)
    )]
    SelfReference {
        /// The scenario's `compare_to` key.
        key: String,
        /// The name given (the scenario's own).
        name: String,
        /// The names it may take: `baseline` and the study's other scenarios.
        accepted: Vec<String>,
    },
}

/// Scenario names as the study file writes them, quoted: `"baseline", "+20 kPa"`.
fn names_text(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("{n:?}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A change that takes samples outside its parameter's accepted range, and how many.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{key}` = {change} takes {param} outside its accepted range {range} for {} (its values [{}, {}] become [{}, {}]); accepted: a change that keeps every sample in range", leaving_text(*leaving, *samples), plain(from.0, 6), plain(from.1, 6), plain(to.0, 6), plain(to.1, 6))]
pub struct ChangeOutOfRange {
    /// The change's key.
    pub key: String,
    /// The change as written.
    pub change: String,
    /// The parameter.
    pub param: &'static str,
    /// Its accepted range.
    pub range: String,
    /// How many of the run's samples leave the range (None: too many samples to count).
    pub leaving: Option<u64>,
    /// The run's samples.
    pub samples: u64,
    /// The parameter's values over the samples, before the change.
    pub from: (f64, f64),
    /// After it.
    pub to: (f64, f64),
}

/// How many samples a change takes out of range, in words.
fn leaving_text(leaving: Option<u64>, samples: u64) -> String {
    match leaving {
        Some(0) => format!(
            "none of this run's {samples} samples but for the bounds of its distribution, which a longer run reaches"
        ),
        Some(n) => format!("{n} of this run's {samples} samples"),
        None => format!(
            "the bounds of its distribution (this run's {samples} samples are too many to count one by one)"
        ),
    }
}
