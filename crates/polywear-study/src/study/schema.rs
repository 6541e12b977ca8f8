//! The study file and the parameter file as derived serde schemas, and the typed pass that
//! checks their values. The schemas refuse unknown keys and wrong types (naming the full key,
//! through [`crate::toml_input::from_value`]); the typed pass checks what a type cannot say
//! (finite, whole, in range, ordered, consistent) and names the same keys.

use std::collections::BTreeMap;

use serde::de::{self, MapAccess, Visitor};
use serde::Deserialize;

use super::{DrawnParam, StudyError, SEED_MAX};
use crate::toml_input::{finite_at, whole_at, TomlError};
use polywear_core::classify::WheelBudget;
use polywear_core::model::Variant;
use polywear_core::params::axle::{check_one_place, Drivetrain};
use polywear_core::params::{ParamId, ParamSpec, Params};
use polywear_core::sampling::design::Design;
use polywear_core::sampling::distribution::Distribution;
use polywear_core::wear::{WearPower, WearSettings, WearZone};

mod scenario_table;
mod toe;
pub(super) use scenario_table::{ChangeSpec, ScenarioTables, COMPARE_TO};
use toe::toe_as_angle;
pub(super) use toe::ParamKey;

/// The distributions a drawn parameter may take, as the study file names them.
pub(super) const DISTS: &str = "uniform, normal, truncated_normal, lognormal, levels";

/// A study file as written: every key optional except where a distribution needs it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StudyFile {
    name: Option<String>,
    description: Option<String>,
    seed: Option<f64>,
    pub(super) samples: Option<f64>,
    design: Option<Design>,
    variants: Option<Vec<Variant>>,
    chunk_size: Option<f64>,
    max_rhs_evals: Option<f64>,
    max_wheel_seconds: Option<f64>,
    accept_implausible: Option<bool>,
    wear: Option<bool>,
    wear_zone: Option<WearZone>,
    wear_power: Option<WearPower>,
    wear_estimate: Option<String>,
    drivetrain: Option<Drivetrain>,
    pub(super) params: Option<BTreeMap<ParamKey, ParamEntry>>,
    pub(super) operating_points: Option<OperatingPointsSection>,
    pub(super) scenarios: Option<ScenarioTables>,
}

/// `[operating_points]`: the file of measured rows and its weight column.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OperatingPointsSection {
    /// The CSV or Parquet file, relative to the study's folder.
    pub(super) file: String,
    /// The column of row weights (hours, km, counts), if any.
    pub(super) weight: Option<String>,
    /// Columns that are not parameters, carried into the output unchanged (vehicle ids, a
    /// second weight).
    pub(super) pass_through: Option<Vec<String>>,
}

/// A parameter file (`--params`, as `polywear calibrate` writes): only `[params]`, numbers.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParamFile {
    /// Parameters, and the toe-in as `toe_mm` or `toe_total_deg` (keys order parameters first,
    /// so the file's `rim_diameter_mm` is set before a toe in mm is read at it).
    pub(super) params: Option<BTreeMap<ParamKey, f64>>,
}

/// One `[params]` entry: a number (fixed) or a table with `dist`.
#[derive(Debug)]
pub(super) enum ParamEntry {
    /// `name = 3.5`.
    Fixed(f64),
    /// `name = { dist = "...", ... }`.
    Table(DistSpec),
}

/// A distribution table, tagged by its `dist` key; each kind takes exactly its own keys.
#[derive(Debug, Deserialize)]
#[serde(tag = "dist", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum DistSpec {
    /// Uniform on [min, max]; `count` equally spaced levels on a grid.
    Uniform {
        min: f64,
        max: f64,
        count: Option<f64>,
    },
    /// Normal with mean and standard deviation.
    Normal { mean: f64, sd: f64 },
    /// Normal truncated to [min, max].
    TruncatedNormal {
        mean: f64,
        sd: f64,
        min: f64,
        max: f64,
    },
    /// Log-normal with median and log-space sigma.
    Lognormal { median: f64, sigma: f64 },
    /// Equally likely levels.
    Levels { levels: Vec<f64> },
    /// A fixed value written as a table.
    Fixed { value: f64 },
}

/// The keys of each kind of distribution table (`dist` included), for messages.
fn dist_keys(dist: &str) -> Option<&'static [&'static str]> {
    Some(match dist {
        "uniform" => &["dist", "min", "max", "count"],
        "normal" => &["dist", "mean", "sd"],
        "truncated_normal" => &["dist", "mean", "sd", "min", "max"],
        "lognormal" => &["dist", "median", "sigma"],
        "levels" => &["dist", "levels"],
        "fixed" => &["dist", "value"],
        _ => return None,
    })
}

impl<'de> Deserialize<'de> for ParamEntry {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<ParamEntry, D::Error> {
        struct EntryVisitor;
        impl<'de> Visitor<'de> for EntryVisitor {
            type Value = ParamEntry;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number (fixed) or a table with `dist`")
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<ParamEntry, E> {
                Ok(ParamEntry::Fixed(x as f64))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<ParamEntry, E> {
                Ok(ParamEntry::Fixed(x as f64))
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<ParamEntry, E> {
                Ok(ParamEntry::Fixed(x))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<ParamEntry, A::Error> {
                DistSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(ParamEntry::Table)
            }
        }
        d.deserialize_any(EntryVisitor)
    }
}

/// Reads a study file's text into its schema. A distribution table is read whole (its `dist`
/// decides its keys), so a problem inside one is named here, from the raw table, with the
/// distribution and the full key.
pub(super) fn read_study(raw: &toml::Value) -> Result<StudyFile, StudyError> {
    crate::toml_input::from_value(raw).map_err(|e| explain(e, raw))
}

/// Turns a schema error inside `params.NAME = { ... }` into the distribution's own terms, and
/// says what `variants` holds.
fn explain(e: TomlError, raw: &toml::Value) -> StudyError {
    if let TomlError::WrongType { key, got, .. } = &e {
        if key == "variants" {
            return TomlError::WrongType {
                key: key.clone(),
                expected: "an array of strings".into(),
                got: got.clone(),
            }
            .into();
        }
    }
    let key = e.key().to_string();
    let Some(name) = key
        .strip_prefix("params.")
        .map(|r| r.split(['.', '[']).next().unwrap_or(r))
    else {
        return e.into();
    };
    let Some(table) = raw
        .get("params")
        .and_then(|p| p.get(name))
        .and_then(toml::Value::as_table)
    else {
        return e.into();
    };
    let at = format!("params.{name}");
    let dist = table.get("dist").and_then(toml::Value::as_str);
    match (e, dist) {
        (TomlError::UnknownName { name, .. }, _) => StudyError::UnknownDist {
            key: at,
            dist: name,
        },
        (TomlError::Missing { field, .. }, _) if field == "dist" => StudyError::NoDist { key: at },
        (TomlError::Missing { field, .. }, Some(dist)) => StudyError::DistNeeds {
            key: at,
            dist: dist.to_string(),
            field,
        },
        (TomlError::UnknownKey { key, .. }, Some(dist)) => {
            let field = key.rsplit('.').next().unwrap_or(&key).to_string();
            StudyError::NotADistKey {
                key: at,
                field,
                dist: dist.to_string(),
                accepted: dist_keys(dist).unwrap_or(&[]).join(", "),
            }
        }
        (e @ TomlError::WrongType { .. }, _) => wrong_type_in(table, &at).unwrap_or(e).into(),
        (e, _) => e.into(),
    }
}

/// The first value of a distribution table whose type is wrong, named in full.
fn wrong_type_in(table: &toml::Table, at: &str) -> Option<TomlError> {
    let wrong = |key: String, expected: &str, v: &toml::Value| TomlError::WrongType {
        key,
        expected: expected.to_string(),
        got: v.type_str().to_string(),
    };
    for (k, v) in table {
        let key = format!("{at}.{k}");
        match (k.as_str(), v) {
            ("dist", toml::Value::String(_)) => {}
            ("dist", v) => return Some(wrong(key, "a string", v)),
            ("levels", toml::Value::Array(a)) => {
                if let Some((i, x)) = a.iter().enumerate().find(|(_, x)| !is_number(x)) {
                    return Some(wrong(format!("{key}[{i}]"), "a number", x));
                }
            }
            ("levels", v) => return Some(wrong(key, "an array of numbers", v)),
            (_, v) if !is_number(v) => return Some(wrong(key, "a number", v)),
            _ => {}
        }
    }
    None
}

fn is_number(v: &toml::Value) -> bool {
    matches!(v, toml::Value::Integer(_) | toml::Value::Float(_))
}

/// The study's settings other than its parameters, checked.
pub(super) struct Header {
    pub(super) name: String,
    pub(super) description: String,
    pub(super) seed: u64,
    pub(super) design: Design,
    pub(super) variants: Vec<Variant>,
    pub(super) chunk_size: u64,
    pub(super) budget: WheelBudget,
    pub(super) accept_implausible: bool,
    pub(super) wear: Option<WearSettings>,
}

impl StudyFile {
    /// Checks the settings other than `[params]`, with their defaults.
    pub(super) fn header(&self) -> Result<Header, StudyError> {
        let name = self.name.clone().unwrap_or_else(|| "study".to_string());
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(StudyError::BadName(name));
        }
        let seed = match self.seed {
            Some(x) => whole_at(x, "seed", 0, SEED_MAX)?,
            None => 1,
        };
        let variants = match &self.variants {
            Some(list) => {
                let mut out = Vec::new();
                for &var in list {
                    if out.contains(&var) {
                        return Err(StudyError::RepeatedVariant(var.to_string()));
                    }
                    out.push(var);
                }
                if out.is_empty() {
                    return Err(StudyError::Empty("variants".into()));
                }
                out
            }
            None => vec![Variant::DEFAULT],
        };
        let chunk_size = match self.chunk_size {
            Some(x) => whole_at(x, "chunk_size", 1, 1 << 20)?,
            None => 4096,
        };
        let mut budget = WheelBudget::default();
        if let Some(x) = self.max_rhs_evals {
            let (lo, hi) = WheelBudget::RHS_EVALS_RANGE;
            budget.max_rhs_evals = whole_at(x, "max_rhs_evals", lo, hi)?;
        }
        if let Some(x) = self.max_wheel_seconds {
            budget.max_wheel_seconds = x;
        }
        budget.check()?;
        if let Some(given) = &self.wear_estimate {
            refuse_wear_level(given)?;
        }
        Ok(Header {
            name,
            description: self.description.clone().unwrap_or_default(),
            seed,
            design: self.design.unwrap_or(Design::Random),
            variants,
            chunk_size,
            budget,
            accept_implausible: self.accept_implausible.unwrap_or(false),
            wear: match self.wear {
                Some(false) => {
                    let set = [
                        ("wear_zone", self.wear_zone.is_some()),
                        ("wear_power", self.wear_power.is_some()),
                        ("wear_estimate", self.wear_estimate.is_some()),
                    ];
                    if let Some((key, _)) = set.iter().find(|(_, given)| *given) {
                        return Err(StudyError::WearSettingWithoutWear(key));
                    }
                    None
                }
                _ => Some(WearSettings {
                    zone: self.wear_zone.unwrap_or_default(),
                    power: self.wear_power.unwrap_or_default(),
                }),
            },
        })
    }

    /// `[params]`: fixed values applied to `base`, drawn ones in canonical order (as in
    /// `polywear params`, independent of the file's key order), and the names fixed.
    pub(super) fn params(
        &self,
        mut base: Params,
    ) -> Result<(Params, Vec<DrawnParam>, Vec<ParamId>), StudyError> {
        let mut drawn = Vec::new();
        let mut fixed = Vec::new();
        let mut toe_inputs = Vec::new();
        for (&key, entry) in self.params.iter().flatten() {
            let param = match key {
                ParamKey::Param(id) => id,
                ParamKey::Toe(input) => {
                    toe_inputs.push((input, entry));
                    continue;
                }
            };
            let key = format!("params.{param}");
            let set = |base: &mut Params, x: f64| {
                base.try_set(param, x).map_err(|source| StudyError::Param {
                    key: key.clone(),
                    source,
                })
            };
            match entry {
                ParamEntry::Fixed(x) => {
                    set(&mut base, *x)?;
                    fixed.push(param);
                }
                ParamEntry::Table(DistSpec::Fixed { value }) => {
                    set(&mut base, finite_at(*value, &format!("{key}.value"))?)?;
                    fixed.push(param);
                }
                ParamEntry::Table(spec) => {
                    let dist = distribution(spec, &key)?;
                    check_support(param.spec(), &dist)?;
                    drawn.push(DrawnParam { param, dist });
                }
            }
        }
        for (input, entry) in toe_inputs {
            toe_as_angle(input, entry, &mut base, &mut drawn, &mut fixed)?;
        }
        let given: Vec<ParamId> = fixed
            .iter()
            .copied()
            .chain(drawn.iter().map(|d| d.param))
            .collect();
        check_one_place(&given, "the study's [params]").map_err(StudyError::Inconsistent)?;
        if let Some(d) = self.drivetrain {
            base.drivetrain = d;
        }
        fixed.sort();
        drawn.sort_by_key(|d| d.param);
        base.validate().map_err(StudyError::FixedParams)?;
        check_drawn_rules(&base, &drawn)?;
        Ok((base, drawn, fixed))
    }
}

/// A cross-parameter rule of [`Params::validate`] that orders two parameters: `small` must not
/// exceed (or, `strict`, must stay below) `large`, read in `small`'s unit.
pub(super) struct OrderedPair {
    /// The one that must not exceed.
    pub small: ParamId,
    /// The other.
    pub large: ParamId,
    /// `large`'s unit in `small`'s (1e3 for a depth in mm against a height in m).
    pub large_in_small_units: f64,
    /// Whether `small` must stay strictly below `large`.
    pub strict: bool,
    /// Why, in words.
    pub why: &'static str,
}

impl OrderedPair {
    /// Whether `small` at `small_max` breaks the rule against `large` at `large_min`.
    pub fn broken(&self, small_max: f64, large_min: f64) -> bool {
        let large = large_min * self.large_in_small_units;
        if self.strict {
            small_max >= large
        } else {
            small_max > large
        }
    }

    /// "at most" or "below", as the rule reads.
    pub fn bound_words(&self) -> &'static str {
        if self.strict {
            "below"
        } else {
            "at most"
        }
    }
}

const fn pair(small: ParamId, large: ParamId, why: &'static str) -> OrderedPair {
    OrderedPair {
        small,
        large,
        large_in_small_units: 1.0,
        strict: false,
        why,
    }
}

/// The cross-parameter rules of [`Params::validate`] that order two parameters: μ_s ≤ μ_m,
/// n_d ≤ n_w, d_visible ≤ d_limit, d_new ≤ h and d_out < d_new.
pub(super) const ORDERED_PAIRS: [OrderedPair; 5] = [
    pair(
        ParamId::MuS,
        ParamId::MuM,
        "sliding friction is at most the static maximum",
    ),
    pair(
        ParamId::NDriven,
        ParamId::NWheels,
        "a vehicle drives at most all its wheels",
    ),
    pair(
        ParamId::VisibleDepthMm,
        ParamId::LimitDepthMm,
        "a polygon is visible before it reaches the service limit",
    ),
    OrderedPair {
        large_in_small_units: 1e3,
        ..pair(
            ParamId::TreadDepthNewMm,
            ParamId::TreadHeight,
            "the usable groove depth is part of the tread",
        )
    },
    OrderedPair {
        strict: true,
        ..pair(
            ParamId::TreadDepthWornOutMm,
            ParamId::TreadDepthNewMm,
            "a tire is worn out before its usable tread is gone",
        )
    },
];

/// The smallest and largest value parameter `p` takes in a study: its draws' extremes (the
/// values the study's range check covers) or its fixed value; and whether it is drawn.
pub(super) fn value_range(base: &Params, drawn: &[DrawnParam], p: ParamId) -> ((f64, f64), bool) {
    match drawn.iter().find(|d| d.param == p) {
        Some(d) => (d.dist.draw_range(), true),
        None => ((base[p], base[p]), false),
    }
}

/// Refuses a study whose draws can break an ordering rule: the largest value the first
/// parameter can take must not exceed the smallest of the second, whichever of them is drawn.
/// Checked on the bounds, before any work, rather than found as failed rows afterwards.
fn check_drawn_rules(base: &Params, drawn: &[DrawnParam]) -> Result<(), StudyError> {
    use polywear_core::wording::plain;
    for rule in &ORDERED_PAIRS {
        let (small, large, why) = (rule.small, rule.large, rule.why);
        let ((_, small_max), small_drawn) = value_range(base, drawn, small);
        let ((large_min, _), large_drawn) = value_range(base, drawn, large);
        if !(small_drawn || large_drawn) || !rule.broken(small_max, large_min) {
            continue;
        }
        let side = |p: ParamId, drawn: bool, bound: &str, x: f64| {
            if drawn {
                format!("`params.{p}` is drawn {bound} {}", plain(x, 6))
            } else {
                format!("`{p}` is fixed at {}", plain(x, 6))
            }
        };
        return Err(StudyError::DrawnRule(format!(
            "{} and {}: samples with {small} above {large} would fail ({why}); draw them so that {small} stays {} {large}",
            side(small, small_drawn, "up to", small_max),
            side(large, large_drawn, "down to", large_min),
            rule.bound_words(),
        )));
    }
    Ok(())
}

/// A distribution table's values checked: finite, spreads positive, bounds ordered, levels
/// non-empty; `key` is the parameter's (`params.NAME`).
fn distribution(spec: &DistSpec, key: &str) -> Result<Distribution, StudyError> {
    let finite = |field: &str, x: f64| finite_at(x, &format!("{key}.{field}"));
    let positive = |field: &str, x: f64| -> Result<f64, StudyError> {
        let value = finite(field, x)?;
        if value <= 0.0 {
            return Err(StudyError::NotPositive {
                key: format!("{key}.{field}"),
                value,
            });
        }
        Ok(value)
    };
    let ordered = |min: f64, max: f64| -> Result<(), StudyError> {
        if min >= max {
            return Err(StudyError::Unordered {
                key: key.to_string(),
                min,
                max,
            });
        }
        Ok(())
    };
    Ok(match *spec {
        DistSpec::Uniform { min, max, count } => {
            let (min, max) = (finite("min", min)?, finite("max", max)?);
            let count = count
                .map(|c| whole_at(c, &format!("{key}.count"), 1, 1_000_000))
                .transpose()?
                .map(|c| c as usize);
            if count != Some(1) {
                ordered(min, max)?;
            }
            Distribution::Uniform { min, max, count }
        }
        DistSpec::Normal { mean, sd } => Distribution::Normal {
            mean: finite("mean", mean)?,
            sd: positive("sd", sd)?,
        },
        DistSpec::TruncatedNormal { mean, sd, min, max } => {
            let (min, max) = (finite("min", min)?, finite("max", max)?);
            ordered(min, max)?;
            Distribution::TruncatedNormal {
                mean: finite("mean", mean)?,
                sd: positive("sd", sd)?,
                min,
                max,
            }
        }
        DistSpec::Lognormal { median, sigma } => Distribution::LogNormal {
            median: positive("median", median)?,
            sigma: positive("sigma", sigma)?,
        },
        DistSpec::Levels { ref levels } => {
            let levels = levels
                .iter()
                .enumerate()
                .map(|(i, &x)| finite_at(x, &format!("{key}.levels[{i}]")))
                .collect::<Result<Vec<f64>, _>>()?;
            if levels.is_empty() {
                return Err(StudyError::Empty(format!("{key}.levels")));
            }
            Distribution::Levels(levels)
        }
        DistSpec::Fixed { .. } => unreachable!("a fixed table is a fixed value"),
    })
}

/// Refuses a distribution that can produce a value outside parameter `s`'s accepted range: the
/// quantiles at the extreme coordinates (normal tails reach about ±8.1 sd), and every level.
fn check_support(s: &ParamSpec, d: &Distribution) -> Result<(), StudyError> {
    let key = format!("params.{}", s.name);
    // Levels are checked one by one, each named by its place in the list (counted from 0, as
    // every `levels[i]` in a message).
    if let Distribution::Levels(levels) = d {
        for (i, x) in levels.iter().enumerate() {
            s.check(*x).map_err(|source| StudyError::Param {
                key: format!("{key}.levels[{i}]"),
                source,
            })?;
        }
        return Ok(());
    }
    let (lo, hi) = (d.quantile(0.0), d.quantile(1.0 - f64::EPSILON));
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(StudyError::CannotSample {
            key,
            dist: format!("{d:?}"),
        });
    }
    for (which, x) in [("smallest", lo), ("largest", hi)] {
        if let Err(source) = s.check(x) {
            let hint = match d {
                Distribution::Normal { .. } => {
                    "; normal tails reach mean ± 8.1 sd: use truncated_normal"
                }
                Distribution::LogNormal { .. } => {
                    "; lognormal tails reach median·exp(±8.1 sigma): use truncated_normal"
                }
                _ => "",
            };
            return Err(StudyError::TailOutOfRange {
                key,
                which,
                source,
                hint,
            });
        }
    }
    Ok(())
}

/// A study's `wear_estimate`: the one answer polywear gives is accepted (studies written for 0.5
/// said it), a retired one is refused with what replaced it, anything else with what is
/// accepted.
pub(crate) fn refuse_wear_level(given: &str) -> Result<(), StudyError> {
    use polywear_core::wear::{retired_level, SHIPPED_LEVEL};
    if given == SHIPPED_LEVEL {
        return Ok(());
    }
    let why = retired_level(given).unwrap_or_else(|| {
        format!(
            "no such wear answer; the one answer is `{SHIPPED_LEVEL}`, and the key may be left out"
        )
    });
    Err(StudyError::RetiredWearLevel {
        given: given.to_string(),
        why,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The keys named in messages are the keys the schema takes: each distribution refuses a
    /// stray key with exactly `dist_keys` (less `dist`, which the tag takes) as accepted.
    #[test]
    fn dist_keys_are_the_schemas_keys() {
        for dist in DISTS.split(", ").chain(["fixed"]) {
            let text = format!("x = {{ dist = \"{dist}\", zzz = 1 }}");
            let t = toml::Value::Table(crate::toml_input::parse(&text).unwrap());
            let e = crate::toml_input::from_value::<BTreeMap<String, ParamEntry>>(&t).unwrap_err();
            let TomlError::UnknownKey { accepted, .. } = e else {
                panic!("{dist}: {e}");
            };
            let keys = &dist_keys(dist).unwrap()[1..];
            assert!(
                accepted.ends_with(&format!("accepted: {}", keys.join(", "))),
                "{dist}: {accepted}"
            );
        }
    }
}
