//! The targets file (`studies/paper_targets.toml`): read into a derived serde schema
//! ([`TargetsFile`], through [`crate::toml_input::from_value`], whose errors name the full key:
//! `target[2].weight`), then checked in a typed pass into a [`Problem`]: every target reachable
//! (its value a value the observable can take: inside the parameter's accepted range and the
//! searched `[from, to]` for a Hopf point, positive for a frequency or a ratio) with a positive
//! weight, and `fit` naming only continuous parameters that no target sets itself. Every
//! refusal names the key it concerns.

use std::collections::BTreeMap;

use serde::Deserialize;

use super::{default_fit, Observable, Problem, Target};
use crate::toml_input::{self, finite_at, TomlError};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::{ParamError, ParamId, Params};
use polywear_core::wording::plain;

/// A targets file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TargetsFile {
    /// Accepted and not used: a sentence for the people who read the file.
    #[allow(dead_code)]
    description: Option<String>,
    fit: Option<Vec<ParamId>>,
    prior_sigma: Option<f64>,
    params: Option<BTreeMap<ParamId, f64>>,
    choices: Option<BTreeMap<ParamId, Vec<f64>>>,
    target: Option<Vec<TargetEntry>>,
}

/// What a target observes, as `kind` names it.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case")]
enum Kind {
    Hopf,
    Frequency,
    AmplitudeRatio,
}

/// One `[[target]]` as written; which keys a kind needs is checked in the typed pass.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TargetEntry {
    name: Option<String>,
    kind: Kind,
    param: Option<ParamId>,
    from: Option<f64>,
    to: Option<f64>,
    at: Option<BTreeMap<ParamId, f64>>,
    wheel: Option<Wheel>,
    relative_to: Option<Wheel>,
    variant: Option<Variant>,
    value: f64,
    weight: Option<f64>,
    tolerance: Option<f64>,
}

/// A targets-file problem, with the key it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TargetsError {
    /// Syntax, unknown or missing keys, values of the wrong type.
    #[error(transparent)]
    Input(#[from] TomlError),
    /// An unknown parameter name, or a value outside its parameter's accepted range.
    #[error("`{key}`: {source}")]
    Param {
        /// The key, in full.
        key: String,
        /// Why it was refused.
        source: ParamError,
    },
    /// A setting outside its accepted range.
    #[error("`{key}` = {} is outside its accepted range {range}", plain(*value, 12))]
    OutOfRange {
        /// The key, in full.
        key: String,
        /// The value given.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
    /// A `choices` list without values.
    #[error("`{key}` must hold at least one value")]
    NoValues {
        /// The key, in full.
        key: String,
    },
    /// `choices` would try too many combinations.
    #[error("`choices` make {0} combinations; accepted at most 4096")]
    TooManyCombinations(usize),
    /// A parameter named twice in one list.
    #[error("`{key}` names `{name}` twice")]
    Repeated {
        /// The list's key.
        key: String,
        /// The parameter named twice.
        name: ParamId,
    },
    /// An empty list of parameters.
    #[error("`{0}` must name at least one parameter")]
    NoneNamed(String),
    /// A parameter both fitted and restricted to choices.
    #[error(
        "`{0}` is both in `fit` (continuous) and in `choices` (discrete); name it in one only"
    )]
    FitAndChoice(ParamId),
    /// A fitted parameter that starts at 0 (log space cannot move it).
    #[error("`fit`: `{0}` starts at 0 and cannot be fitted in log space")]
    ZeroStart(ParamId),
    /// A fitted parameter that takes whole numbers only.
    #[error("`fit`: `{0}` is a whole number (a count) and cannot be fitted continuously; restrict it to a few values with [choices]")]
    WholeNumber(ParamId),
    /// A fitted parameter that a target sets itself (its sweep, or its point `at`).
    #[error("`fit`: `{param}` is set by `{target}` itself (its `{how}`), so fitting it changes nothing the target sees; fit another parameter")]
    SetByTarget {
        /// The parameter.
        param: ParamId,
        /// The target's key (`target[0]`).
        target: String,
        /// `param` (the sweep) or `at`.
        how: &'static str,
    },
    /// The file has no `[[target]]`.
    #[error("no [[target]] entries")]
    NoTargets,
    /// A Hopf target whose range is empty.
    #[error("`{key}`: from = {} must be below to = {}", plain(*from, 12), plain(*to, 12))]
    Unordered {
        /// The target's key.
        key: String,
        /// Start of the range.
        from: f64,
        /// End of the range.
        to: f64,
    },
    /// A Hopf point searched where it cannot be.
    #[error("`{key}.value` = {} lies outside the searched range [from, to] = [{}, {}]: the Hopf point found there can never be at the target; widen [from, to] or correct the value", plain(*value, 12), plain(*from, 12), plain(*to, 12))]
    OutsideSearch {
        /// The target's key.
        key: String,
        /// The target value.
        value: f64,
        /// Start of the range.
        from: f64,
        /// End of the range.
        to: f64,
    },
    /// A frequency or an amplitude ratio that is not positive.
    #[error("`{key}.value` = {} cannot be met: a {what} is positive", plain(*value, 12))]
    NotPositive {
        /// The target's key.
        key: String,
        /// The target value.
        value: f64,
        /// What the target observes.
        what: &'static str,
    },
    /// An amplitude ratio of a wheel to itself.
    #[error("`{key}`: `relative_to` must name the other wheel than `wheel` = {wheel}")]
    SameWheel {
        /// The target's key.
        key: String,
        /// The wheel named twice.
        wheel: Wheel,
    },
    /// A target value of 0 (errors are relative to it).
    #[error("`{key}.value` must not be 0 (errors are relative)")]
    ZeroValue {
        /// The target's key.
        key: String,
    },
}

/// `value` checked against parameter `s`'s accepted range, errors under `key`.
fn in_range(s: ParamId, value: f64, key: &str) -> Result<f64, TargetsError> {
    s.spec()
        .check(value)
        .map_err(|source| TargetsError::Param {
            key: key.to_string(),
            source,
        })?;
    Ok(value)
}

/// The key `field` of the target at `key`, refused when absent.
fn need<T: Copy>(v: Option<T>, key: &str, field: &str) -> Result<T, TargetsError> {
    v.ok_or_else(|| {
        TargetsError::Input(TomlError::Missing {
            key: key.to_string(),
            field: field.to_string(),
        })
    })
}

/// A target's point `at = { name = value, ... }`, each value finite and in its range.
fn point(t: &TargetEntry, key: &str) -> Result<Vec<(ParamId, f64)>, TargetsError> {
    let mut at = Vec::new();
    for (&s, &x) in t.at.iter().flatten() {
        let k = format!("{key}.at.{s}");
        at.push((s, in_range(s, finite_at(x, &k)?, &k)?));
    }
    Ok(at)
}

/// A Hopf target's sweep: `param` from `from` to `to`, ordered, with the value inside it.
fn hopf(t: &TargetEntry, key: &str, value: f64) -> Result<Observable, TargetsError> {
    let s = need(t.param, key, "param")?;
    let bound = |v: Option<f64>, field: &str| -> Result<f64, TargetsError> {
        let k = format!("{key}.{field}");
        in_range(s, finite_at(need(v, key, field)?, &k)?, &k)
    };
    let (from, to) = (bound(t.from, "from")?, bound(t.to, "to")?);
    if from >= to {
        return Err(TargetsError::Unordered {
            key: key.to_string(),
            from,
            to,
        });
    }
    in_range(s, value, &format!("{key}.value"))?;
    if !(from..=to).contains(&value) {
        return Err(TargetsError::OutsideSearch {
            key: key.to_string(),
            value,
            from,
            to,
        });
    }
    Ok(Observable::Hopf { param: s, from, to })
}

/// A non-negative (`open` = false) or positive (`open` = true) setting of a target.
fn positive(
    v: Option<f64>,
    key: String,
    default: f64,
    range: &'static str,
) -> Result<f64, TargetsError> {
    let value = v
        .map(|x| finite_at(x, &key))
        .transpose()?
        .unwrap_or(default);
    if value <= 0.0 {
        return Err(TargetsError::OutOfRange { key, value, range });
    }
    Ok(value)
}

fn parse_target(i: usize, t: &TargetEntry) -> Result<Target, TargetsError> {
    let key = format!("target[{i}]");
    let wheel = t.wheel.unwrap_or(Wheel::Follower);
    let value = finite_at(t.value, &format!("{key}.value"))?;
    if value == 0.0 {
        return Err(TargetsError::ZeroValue { key });
    }
    let not_positive = |what| TargetsError::NotPositive {
        key: key.clone(),
        value,
        what,
    };
    let observable = match t.kind {
        Kind::Hopf => hopf(t, &key, value)?,
        Kind::Frequency if value < 0.0 => return Err(not_positive("frequency")),
        Kind::Frequency => Observable::Frequency {
            at: point(t, &key)?,
        },
        Kind::AmplitudeRatio if value < 0.0 => return Err(not_positive("ratio of amplitudes")),
        Kind::AmplitudeRatio => {
            let relative_to = t.relative_to.unwrap_or(Wheel::Follower);
            if relative_to == wheel {
                return Err(TargetsError::SameWheel { key, wheel });
            }
            Observable::AmplitudeRatio {
                at: point(t, &key)?,
                relative_to,
            }
        }
    };
    let weight = positive(t.weight, format!("{key}.weight"), 1.0, "(0, inf)")?;
    let tolerance = positive(
        t.tolerance,
        format!("{key}.tolerance"),
        0.1,
        "(0, inf) (relative error)",
    )?;
    let kind = match t.kind {
        Kind::Hopf => "hopf",
        Kind::Frequency => "frequency",
        Kind::AmplitudeRatio => "amplitude_ratio",
    };
    Ok(Target {
        name: t.name.clone().unwrap_or_else(|| format!("{kind} {i}")),
        observable,
        wheel,
        variant: t.variant.unwrap_or(Variant::DEFAULT),
        value,
        weight,
        tolerance,
    })
}

/// `[params]`: the starting values, on top of the defaults.
fn parse_start(params: Option<&BTreeMap<ParamId, f64>>) -> Result<Params, TargetsError> {
    let mut start = Params::default();
    for (&s, &x) in params.into_iter().flatten() {
        let key = format!("params.{s}");
        start
            .try_set(s, finite_at(x, &key)?)
            .map_err(|source| TargetsError::Param { key, source })?;
    }
    start.validate().map_err(|source| TargetsError::Param {
        key: "params".into(),
        source,
    })?;
    Ok(start)
}

/// `[choices]`: each a parameter restricted to a few values.
fn parse_choices(
    choices: Option<&BTreeMap<ParamId, Vec<f64>>>,
) -> Result<Vec<(ParamId, Vec<f64>)>, TargetsError> {
    let mut out = Vec::new();
    for (&s, values) in choices.into_iter().flatten() {
        let key = format!("choices.{s}");
        if values.is_empty() {
            return Err(TargetsError::NoValues { key });
        }
        let vals = values
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                let k = format!("{key}[{i}]");
                in_range(s, finite_at(x, &k)?, &k)
            })
            .collect::<Result<Vec<f64>, _>>()?;
        out.push((s, vals));
    }
    // In the order of their names, as the file's table lists them: the order of the
    // combinations and of the written file.
    out.sort_by_key(|(s, _)| s.name());
    let combos: usize = out.iter().map(|(_, v)| v.len()).product();
    if combos > 4096 {
        return Err(TargetsError::TooManyCombinations(combos));
    }
    Ok(out)
}

/// A list of distinct parameter names at `key`.
fn name_list(names: &[ParamId], key: &str) -> Result<Vec<ParamId>, TargetsError> {
    let mut out: Vec<ParamId> = Vec::new();
    for &name in names {
        if out.contains(&name) {
            return Err(TargetsError::Repeated {
                key: key.to_string(),
                name,
            });
        }
        out.push(name);
    }
    if out.is_empty() {
        return Err(TargetsError::NoneNamed(key.to_string()));
    }
    Ok(out)
}

/// Refuses a `fit` that names a parameter the fit cannot move: one restricted by `choices`, a
/// whole number, one starting at 0, or one a target sets itself (its sweep or its point). Also
/// checked for a `fit` given on the command line.
pub fn check_fit(problem: &Problem) -> Result<(), TargetsError> {
    for &n in &problem.fit {
        if problem.choices.iter().any(|(c, _)| *c == n) {
            return Err(TargetsError::FitAndChoice(n));
        }
        if n.spec().integer {
            return Err(TargetsError::WholeNumber(n));
        }
        if problem.start[n] <= 0.0 {
            return Err(TargetsError::ZeroStart(n));
        }
        for (i, t) in problem.targets.iter().enumerate() {
            let how = match &t.observable {
                Observable::Hopf { param, .. } if *param == n => "param",
                Observable::Frequency { at } | Observable::AmplitudeRatio { at, .. }
                    if at.iter().any(|(p, _)| *p == n) =>
                {
                    "at"
                }
                _ => continue,
            };
            return Err(TargetsError::SetByTarget {
                param: n,
                target: format!("target[{i}]"),
                how,
            });
        }
    }
    Ok(())
}

/// Parses a targets file; every problem is refused with the key it concerns.
pub fn parse_problem(text: &str) -> Result<Problem, TargetsError> {
    let file: TargetsFile = toml_input::from_str(text)?;
    let prior_sigma = match file.prior_sigma {
        Some(x) => Some(positive(Some(x), "prior_sigma".into(), 1.0, "(0, inf)")?),
        None => None,
    };
    let start = parse_start(file.params.as_ref())?;
    let choices = parse_choices(file.choices.as_ref())?;
    let entries = file.target.as_deref().unwrap_or_default();
    if entries.is_empty() {
        return Err(TargetsError::NoTargets);
    }
    let targets = entries
        .iter()
        .enumerate()
        .map(|(i, t)| parse_target(i, t))
        .collect::<Result<Vec<_>, _>>()?;
    let mut problem = Problem {
        fit: Vec::new(),
        prior_sigma,
        start,
        targets,
        choices,
    };
    problem.fit = match &file.fit {
        // The default set less what the file restricts and what its targets set themselves.
        None => default_fit()
            .into_iter()
            .filter(|&n| {
                let alone = Problem {
                    fit: vec![n],
                    ..problem.clone()
                };
                check_fit(&alone).is_ok()
            })
            .collect(),
        Some(names) => name_list(names, "fit")?,
    };
    check_fit(&problem)?;
    Ok(problem)
}
