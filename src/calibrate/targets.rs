//! The targets file (`studies/paper_targets.toml`): parsed into a [`Problem`], every problem
//! refused with the key it concerns.

use super::{default_fit, Observable, Problem, Target};
use crate::model::{Variant, Wheel};
use crate::params::{ParamError, ParamId, Params};
use crate::toml_input::{self, Section, TomlError};

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
    #[error("`{key}` = {value} is outside its accepted range {range}")]
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
    /// The file has no `[[target]]`.
    #[error("no [[target]] entries")]
    NoTargets,
    /// A target kind that does not exist.
    #[error("`{key}.kind` = \"{kind}\" is unknown; accepted: hopf, frequency, amplitude_ratio")]
    UnknownKind {
        /// The target's key.
        key: String,
        /// The kind given.
        kind: String,
    },
    /// A Hopf target whose range is empty.
    #[error("`{key}`: from = {from} must be below to = {to}")]
    Unordered {
        /// The target's key.
        key: String,
        /// Start of the range.
        from: f64,
        /// End of the range.
        to: f64,
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

/// A parameter name at `key`.
fn param_name(name: &str, key: &str) -> Result<ParamId, TargetsError> {
    name.parse().map_err(|source| TargetsError::Param {
        key: key.to_string(),
        source,
    })
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

const TOP_KEYS: &[&str] = &[
    "description",
    "fit",
    "prior_sigma",
    "params",
    "choices",
    "target",
];
const TARGET_KEYS: &[&str] = &[
    "name",
    "kind",
    "param",
    "from",
    "to",
    "at",
    "wheel",
    "relative_to",
    "variant",
    "value",
    "weight",
    "tolerance",
];

/// An operating point `at = { name = value, ... }` of target `t`.
fn point(t: &Section) -> Result<Vec<(ParamId, f64)>, TargetsError> {
    let mut at = Vec::new();
    if let Some(v) = t.get("at") {
        let path = t.key("at");
        let a = Section::of(v, &path, "a table")?;
        for (k, x) in a.table {
            let s = param_name(k, &path)?;
            let x = toml_input::finite(x, &a.key(k))?;
            at.push((s, in_range(s, x, &path)?));
        }
    }
    Ok(at)
}

/// A positive-or-zero (`open` = false) or positive (`open` = true) number at `field`.
fn non_negative(
    t: &Section,
    field: &str,
    default: f64,
    open: bool,
    range: &'static str,
) -> Result<f64, TargetsError> {
    let value = t.opt(field, toml_input::finite)?.unwrap_or(default);
    if value < 0.0 || (open && value == 0.0) {
        return Err(TargetsError::OutOfRange {
            key: t.key(field),
            value,
            range,
        });
    }
    Ok(value)
}

fn parse_target(i: usize, v: &toml::Value) -> Result<Target, TargetsError> {
    let key = format!("target[{i}]");
    let t = Section::of(v, &key, "a table")?;
    t.deny_unknown(TARGET_KEYS)?;
    let kind = t.req("kind", toml_input::text)?;
    let wheel = t
        .opt("wheel", toml_input::parsed)?
        .unwrap_or(Wheel::Follower);
    let observable = match kind {
        "hopf" => {
            let s = param_name(t.req("param", toml_input::text)?, &t.key("param"))?;
            let from = in_range(s, t.req("from", toml_input::finite)?, &key)?;
            let to = in_range(s, t.req("to", toml_input::finite)?, &key)?;
            if from >= to {
                return Err(TargetsError::Unordered { key, from, to });
            }
            Observable::Hopf { param: s, from, to }
        }
        "frequency" => Observable::Frequency { at: point(&t)? },
        "amplitude_ratio" => {
            let relative_to = t
                .opt("relative_to", toml_input::parsed)?
                .unwrap_or(Wheel::Follower);
            if relative_to == wheel {
                return Err(TargetsError::SameWheel { key, wheel });
            }
            Observable::AmplitudeRatio {
                at: point(&t)?,
                relative_to,
            }
        }
        other => {
            return Err(TargetsError::UnknownKind {
                key: key.clone(),
                kind: other.to_string(),
            })
        }
    };
    let variant = t
        .opt("variant", toml_input::parsed)?
        .unwrap_or(Variant::DEFAULT);
    let value = t.req("value", toml_input::finite)?;
    if value == 0.0 {
        return Err(TargetsError::ZeroValue { key });
    }
    let weight = non_negative(&t, "weight", 1.0, false, "[0, inf)")?;
    let tolerance = non_negative(&t, "tolerance", 0.1, true, "(0, inf) (relative error)")?;
    let name = match t.opt("name", toml_input::text)? {
        Some(n) => n.to_string(),
        None => format!("{kind} {i}"),
    };
    Ok(Target {
        name,
        observable,
        wheel,
        variant,
        value,
        weight,
        tolerance,
    })
}

/// A list of distinct parameter names at `key`.
fn name_list(v: &toml::Value, key: &str) -> Result<Vec<ParamId>, TargetsError> {
    let mut out: Vec<ParamId> = Vec::new();
    for (i, x) in toml_input::array(v, key, "an array of parameter names")?
        .iter()
        .enumerate()
    {
        let k = format!("{key}[{i}]");
        let name = param_name(toml_input::text(x, &k)?, &k)?;
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

/// `[params]`: the starting values, on top of the defaults.
fn parse_start(top: &Section) -> Result<Params, TargetsError> {
    let mut start = Params::default();
    if let Some(v) = top.get("params") {
        let p = Section::of(v, "params", "a table")?;
        for (k, v) in p.table {
            let key = p.key(k);
            let x = toml_input::finite(v, &key)?;
            start
                .set(k, x)
                .map_err(|source| TargetsError::Param { key, source })?;
        }
        start.validate().map_err(|source| TargetsError::Param {
            key: "params".into(),
            source,
        })?;
    }
    Ok(start)
}

/// `[choices]`: each a parameter restricted to a few values.
fn parse_choices(top: &Section) -> Result<Vec<(ParamId, Vec<f64>)>, TargetsError> {
    let mut choices = Vec::new();
    if let Some(c) = top.get("choices") {
        let c = Section::of(c, "choices", "a table")?;
        for (k, v) in c.table {
            let key = c.key(k);
            let s = param_name(k, &key)?;
            let arr = toml_input::array(v, &key, "an array of numbers")?;
            if arr.is_empty() {
                return Err(TargetsError::NoValues { key });
            }
            let vals = arr
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    let k = format!("{key}[{i}]");
                    in_range(s, toml_input::finite(x, &k)?, &k)
                })
                .collect::<Result<Vec<f64>, _>>()?;
            choices.push((s, vals));
        }
    }
    let combos: usize = choices.iter().map(|(_, v)| v.len()).product();
    if combos > 4096 {
        return Err(TargetsError::TooManyCombinations(combos));
    }
    Ok(choices)
}

/// Parses a targets file; every problem is refused with the key it concerns.
pub fn parse_problem(text: &str) -> Result<Problem, TargetsError> {
    let table = toml_input::parse(text)?;
    let top = Section::top(&table);
    top.deny_unknown(TOP_KEYS)?;
    top.opt("description", toml_input::text)?;
    let prior_sigma = match top.opt("prior_sigma", toml_input::finite)? {
        Some(value) if value <= 0.0 => {
            return Err(TargetsError::OutOfRange {
                key: "prior_sigma".into(),
                value,
                range: "(0, inf)",
            })
        }
        s => s,
    };
    let start = parse_start(&top)?;
    let choices = parse_choices(&top)?;
    let fit = match top.get("fit") {
        None => default_fit()
            .into_iter()
            .filter(|n| !choices.iter().any(|(c, _)| c == n))
            .collect(),
        Some(v) => name_list(v, "fit")?,
    };
    if let Some((n, _)) = choices.iter().find(|(c, _)| fit.contains(c)) {
        return Err(TargetsError::FitAndChoice(*n));
    }
    if let Some(&n) = fit.iter().find(|&&n| start[n] <= 0.0) {
        return Err(TargetsError::ZeroStart(n));
    }
    let targets = top
        .get("target")
        .and_then(|v| v.as_array())
        .ok_or(TargetsError::NoTargets)?
        .iter()
        .enumerate()
        .map(|(i, v)| parse_target(i, v))
        .collect::<Result<Vec<_>, _>>()?;
    if targets.is_empty() {
        return Err(TargetsError::NoTargets);
    }
    Ok(Problem {
        fit,
        prior_sigma,
        start,
        targets,
        choices,
    })
}
