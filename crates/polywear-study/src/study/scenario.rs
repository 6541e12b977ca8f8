//! What-if scenarios: `[scenarios.NAME]` tables that change the study's parameters, each
//! evaluated on the same samples (the same sample ids, operating points and tire structures) as
//! the study itself, the *baseline*. A change is applied to a sample's parameter set after it is
//! drawn, so the baseline and every scenario see the same draws (common random numbers) and
//! only the change differs between them.
//!
//! The checks are in two steps: reading the file refuses what is wrong whatever the run (an
//! unknown parameter, a change with no or two kinds, a value outside its parameter's range, a
//! name used twice, an empty scenario, a `compare_to` that names the scenario itself or no
//! scenario of the study); [`Study::check_scenarios`] refuses, before a run starts,
//! a change that takes any of the run's samples outside its parameter's accepted range, and says
//! for how many.

use super::error::ChangeOutOfRange;
use super::schema::{ChangeSpec, ScenarioTables, COMPARE_TO};
use super::{Study, StudyError};
use crate::toml_input::finite_at;
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::Design;
use polywear_core::sampling::distribution::Distribution;
use polywear_core::wording::plain;

/// The name of the study without changes, in the `scenario` column and the report.
pub const BASELINE: &str = "baseline";

/// Longest accepted scenario name, in characters.
pub(crate) const NAME_MAX_CHARS: usize = 64;

/// Runs of more samples than this are not counted one by one (a second or so on 2 cores at the
/// limit): a change whose changed bounds leave the range is then refused without a count.
pub const COUNT_LIMIT: u64 = 2_000_000;

pub use super::change::{Change, CHANGE_KINDS};

/// One parameter's change in a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamChange {
    /// The parameter changed.
    pub param: ParamId,
    /// How.
    pub change: Change,
}

impl ParamChange {
    /// The change in words, with the parameter's unit: `toe_deg shifted by -0.15 deg`.
    pub fn words(&self) -> String {
        let unit = self.param.spec().unit;
        let unit = if unit == "-" {
            String::new()
        } else {
            format!(" {unit}")
        };
        let x = |v: f64| plain(v, 12);
        match self.change {
            Change::Set(v) => format!("{} set to {}{unit}", self.param, x(v)),
            Change::Shift(d) => format!("{} shifted by {}{unit}", self.param, signed(d)),
            Change::Scale(k) => format!("{} scaled by {}", self.param, x(k)),
            Change::Cap(c) => format!("{} capped at {}{unit}", self.param, x(c)),
        }
    }
}

/// A number with its sign, without float noise: `+20`, `-0.15`.
fn signed(x: f64) -> String {
    if x >= 0.0 {
        format!("+{}", plain(x, 12))
    } else {
        plain(x, 12)
    }
}

/// A named set of changes, evaluated on the baseline's samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Its name, in the `scenario` column and the report.
    pub name: String,
    /// The changes, in parameter order.
    pub changes: Vec<ParamChange>,
    /// The scenario its effects are measured against (`compare_to`), on the same samples; None
    /// for the baseline, the default. Its changes are still made to the baseline's values: the
    /// reference only says which rows the report subtracts.
    pub compare_to: Option<String>,
}

impl Scenario {
    /// The name of the rows this scenario is compared with: its `compare_to`, or `baseline`.
    pub fn reference(&self) -> &str {
        self.compare_to.as_deref().unwrap_or(BASELINE)
    }

    /// `p` with the scenario's changes applied.
    pub fn apply(&self, p: &Params) -> Params {
        let mut q = *p;
        for c in &self.changes {
            q[c.param] = c.change.apply(q.value_or_shared(c.param));
        }
        q
    }

    /// A sample's drawn values (named by `names`) with the scenario's changes applied.
    pub fn apply_values(&self, names: &[ParamId], values: &[f64]) -> Vec<f64> {
        names
            .iter()
            .zip(values)
            .map(|(id, &x)| {
                self.changes
                    .iter()
                    .filter(|c| c.param == *id)
                    .fold(x, |x, c| c.change.apply(x))
            })
            .collect()
    }

    /// The changes in words: `toe_deg shifted by -0.15 deg, pressure_kpa shifted by +20 kPa`.
    pub fn words(&self) -> String {
        self.changes
            .iter()
            .map(ParamChange::words)
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The scenario as JSON, in the study file's terms:
    /// `{"name":"toe-in","changes":{"toe_deg":{"shift":-0.15}}}`, with `"compare_to"` where the
    /// scenario names its reference.
    pub fn to_json(&self) -> serde_json::Value {
        let changes: serde_json::Map<String, serde_json::Value> = self
            .changes
            .iter()
            .map(|c| {
                let mut m = serde_json::Map::new();
                m.insert(c.change.kind().into(), c.change.amount().into());
                (c.param.name().to_string(), m.into())
            })
            .collect();
        let mut v = serde_json::json!({ "name": self.name, "changes": changes });
        // Only where named: a baseline-compared scenario is recorded as it always was.
        if let Some(r) = &self.compare_to {
            v["compare_to"] = r.as_str().into();
        }
        v
    }

    /// A scenario read back from [`Scenario::to_json`]'s form (a chunk's `scenarios` metadata);
    /// None for anything else.
    pub fn from_json(v: &serde_json::Value) -> Option<Scenario> {
        let name = v.get("name")?.as_str()?.to_string();
        let mut changes = Vec::new();
        for (param, c) in v.get("changes")?.as_object()? {
            let (kind, x) = c.as_object()?.iter().next()?;
            let x = x.as_f64()?;
            let change = match kind.as_str() {
                "set" => Change::Set(x),
                "shift" => Change::Shift(x),
                "scale" => Change::Scale(x),
                "cap" => Change::Cap(x),
                _ => return None,
            };
            changes.push(ParamChange {
                param: param.parse().ok()?,
                change,
            });
        }
        // In parameter order, as the study file's changes are.
        changes.sort_by_key(|c| c.param);
        let compare_to = match v.get("compare_to") {
            Some(r) => Some(r.as_str()?.to_string()),
            None => None,
        };
        Some(Scenario {
            name,
            changes,
            compare_to,
        })
    }

    /// The key of `param`'s change in the study file: `scenarios.NAME.param`, the name quoted
    /// where TOML needs it.
    pub fn key(&self, param: ParamId) -> String {
        format!("{}.{param}", scenario_key(&self.name))
    }
}

/// `scenarios.NAME`, the name quoted unless it is a bare TOML key.
pub fn scenario_key(name: &str) -> String {
    let bare = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        format!("scenarios.{name}")
    } else {
        format!("scenarios.{name:?}")
    }
}

/// The scenarios of a study file, checked (in name order, as TOML tables keep their keys).
/// `base` and `drawn` are the study's parameters: a toe-in change in mm is read at its fixed rim.
pub(super) fn scenarios(
    tables: &ScenarioTables,
    base: &Params,
    drawn: &[super::DrawnParam],
) -> Result<Vec<Scenario>, StudyError> {
    let mut out = Vec::new();
    for (name, table) in tables {
        check_name(name)?;
        let mut changes: Vec<(ParamId, Change, String)> = Vec::new();
        for (&param, spec) in &table.changes {
            let key = scenario_key_of(name, param.name());
            changes.push((param, change(spec, &key)?, key));
        }
        for (&input, spec) in &table.toe_changes {
            let key = scenario_key_of(name, input.name());
            let typed = change(spec, &key)?;
            changes.push((
                input.target(),
                super::change::toe_change(input, typed, &key, base, drawn)?,
                key,
            ));
        }
        if let Some(k) = super::change::toe_keys_twice(&changes) {
            return Err(StudyError::DrawnRule(format!(
                "`{k}`: the scenario changes the toe-in twice; give one of toe_deg, toe_mm and toe_total_deg (for an axle: toe_rear_deg, toe_rear_mm and toe_rear_total_deg)"
            )));
        }
        changes.sort_by_key(|c| c.0);
        if changes.is_empty() {
            return Err(StudyError::EmptyScenario {
                key: scenario_key(name),
            });
        }
        let mut scenario = Scenario {
            name: name.clone(),
            changes: Vec::new(),
            compare_to: table.compare_to.clone().filter(|r| r != BASELINE),
        };
        for (param, change, key) in changes {
            check_value(param, change, &key)?;
            scenario.changes.push(ParamChange { param, change });
        }
        // Names that differ only in the spaces around them read as one in the report.
        if let Some(other) = out
            .iter()
            .find(|o: &&Scenario| o.name.trim() == name.trim())
        {
            return Err(StudyError::RepeatedScenario {
                name: name.clone(),
                why: format!(
                    "{:?} and {name:?} differ only in the spaces around them",
                    other.name
                ),
            });
        }
        out.push(scenario);
    }
    for s in &out {
        check_reference(s, &out)?;
    }
    Ok(out)
}

/// Refuses a `compare_to` that names the scenario itself or no scenario of the study. A
/// reference that is itself compared with another is accepted: each comparison is one level,
/// the scenario's rows minus its reference's, on the same samples.
fn check_reference(s: &Scenario, all: &[Scenario]) -> Result<(), StudyError> {
    let Some(name) = &s.compare_to else {
        return Ok(());
    };
    let accepted: Vec<String> = std::iter::once(BASELINE)
        .chain(all.iter().map(|o| o.name.as_str()))
        .filter(|o| *o != s.name)
        .map(str::to_string)
        .collect();
    let key = format!("{}.{COMPARE_TO}", scenario_key(&s.name));
    if *name == s.name {
        return Err(StudyError::SelfReference {
            key,
            name: name.clone(),
            accepted,
        });
    }
    if !accepted.contains(name) {
        return Err(StudyError::UnknownReference {
            key,
            name: name.clone(),
            accepted,
        });
    }
    Ok(())
}

/// Refuses a name that is empty, too long, holds control characters, or is the baseline's.
fn check_name(name: &str) -> Result<(), StudyError> {
    let why = if name.trim().is_empty() {
        "is empty"
    } else if name.chars().count() > NAME_MAX_CHARS {
        "is longer than 64 characters"
    } else if name.chars().any(char::is_control) {
        "holds a control character"
    } else if name.trim().eq_ignore_ascii_case(BASELINE) {
        return Err(StudyError::RepeatedScenario {
            name: name.to_string(),
            why: "`baseline` names the study without changes".into(),
        });
    } else {
        return Ok(());
    };
    Err(StudyError::ScenarioName {
        key: scenario_key(name),
        why,
    })
}

/// The one change a table gives, its number finite.
/// `scenarios.NAME.KEY`, the name quoted where it needs it.
fn scenario_key_of(name: &str, key: &str) -> String {
    format!("{}.{key}", scenario_key(name))
}

fn change(spec: &ChangeSpec, key: &str) -> Result<Change, StudyError> {
    let given: Vec<(&'static str, f64)> = [
        ("set", spec.set),
        ("shift", spec.shift),
        ("scale", spec.scale),
        ("cap", spec.cap),
    ]
    .into_iter()
    .filter_map(|(k, v)| v.map(|v| (k, v)))
    .collect();
    let [(kind, x)] = given[..] else {
        return Err(StudyError::ChangeKinds {
            key: key.to_string(),
            given: given.iter().map(|g| g.0).collect::<Vec<_>>().join(", "),
        });
    };
    let x = finite_at(x, &format!("{key}.{kind}"))?;
    Ok(match kind {
        "set" => Change::Set(x),
        "shift" => Change::Shift(x),
        "scale" if x <= 0.0 => {
            return Err(StudyError::NotPositive {
                key: format!("{key}.scale"),
                value: x,
            })
        }
        "scale" => Change::Scale(x),
        _ => Change::Cap(x),
    })
}

/// A set or cap value must itself be accepted by the parameter (a cap below the range would
/// take every sample out of it).
fn check_value(param: ParamId, change: Change, key: &str) -> Result<(), StudyError> {
    if let Change::Set(x) | Change::Cap(x) = change {
        param.spec().check(x).map_err(|source| StudyError::Param {
            key: format!("{key}.{}", change.kind()),
            source,
        })?;
    }
    Ok(())
}

/// The values a parameter takes over a study's samples: the bounds of its distribution (hard
/// for uniform, truncated normal, levels, grids and operating-point columns; the extreme
/// quantiles, soft, for normal and lognormal tails), or its one fixed value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValueRange {
    /// The smallest value.
    pub lo: f64,
    /// The largest value.
    pub hi: f64,
    /// Whether draws can reach the bounds (false: tails that a run's samples rarely reach).
    pub hard: bool,
}

impl Study {
    /// The values `param` takes over the study's samples.
    pub fn value_range(&self, param: ParamId) -> ValueRange {
        if let Some(d) = self.drawn.iter().find(|d| d.param == param) {
            let grid = (self.design == Design::Grid)
                .then(|| d.dist.grid_values())
                .flatten();
            if let Some(levels) = grid {
                return hull(&levels);
            }
            return match &d.dist {
                Distribution::Uniform { min, max, .. }
                | Distribution::TruncatedNormal { min, max, .. } => ValueRange {
                    lo: *min,
                    hi: *max,
                    hard: true,
                },
                Distribution::Levels(levels) => hull(levels),
                dist @ (Distribution::Normal { .. } | Distribution::LogNormal { .. }) => {
                    let (lo, hi) = dist.draw_range();
                    ValueRange {
                        lo,
                        hi,
                        hard: false,
                    }
                }
            };
        }
        if let Some(op) = &self.operating_points {
            if let Some(j) = op.names.iter().position(|n| *n == param.name()) {
                let column: Vec<f64> = op.values.iter().map(|row| row[j]).collect();
                return hull(&column);
            }
        }
        let x = self.base[param];
        ValueRange {
            lo: x,
            hi: x,
            hard: true,
        }
    }

    /// Refuses, before a run of `samples` samples with `seed` starts, a scenario change that
    /// takes any sample's value outside its parameter's accepted range.
    pub fn check_scenarios(&self, seed: u64, samples: u64) -> Result<(), StudyError> {
        for s in &self.scenarios {
            for c in &s.changes {
                self.check_change(&s.key(c.param), *c, seed, samples)?;
            }
        }
        Ok(())
    }

    /// Refuses `change` when it takes any of the run's samples outside its parameter's accepted
    /// range; `key` names it in the message. The changed bounds decide where they are hard;
    /// otherwise (or to say how many) the run's samples are counted, up to [`COUNT_LIMIT`].
    pub fn check_change(
        &self,
        key: &str,
        change: ParamChange,
        seed: u64,
        samples: u64,
    ) -> Result<(), StudyError> {
        let spec = change.param.spec();
        let range = self.value_range(change.param);
        let (a, b) = (change.change.apply(range.lo), change.change.apply(range.hi));
        let to = (a.min(b), a.max(b));
        if spec.check(to.0).is_ok() && spec.check(to.1).is_ok() {
            return Ok(());
        }
        let leaving = (samples <= COUNT_LIMIT).then(|| self.count_leaving(change, seed, samples));
        if !range.hard && leaving == Some(0) {
            return Ok(());
        }
        Err(StudyError::ScenarioOutOfRange(Box::new(ChangeOutOfRange {
            key: key.to_string(),
            change: change.change.text(),
            param: change.param.name(),
            range: spec.range_text(),
            leaving,
            samples,
            from: (range.lo, range.hi),
            to,
        })))
    }

    /// How many of the run's samples the change takes outside the parameter's range.
    fn count_leaving(&self, change: ParamChange, seed: u64, samples: u64) -> u64 {
        let sampler = self.sampler(seed, samples);
        let spec = change.param.spec();
        let leaves = |i: usize| {
            let x = sampler.sample_with_row(i as u64).0[change.param];
            spec.check(change.change.apply(x)).is_err()
        };
        let control = polywear_core::ensemble::Control::QUIET;
        polywear_core::ensemble::solve(samples as usize, leaves, &control)
            .all()
            .into_iter()
            .filter(|&leaves| leaves)
            .count() as u64
    }

    /// Names of the row blocks of a sample, in row order: the baseline, then each scenario.
    pub fn scenario_names(&self) -> Vec<&str> {
        std::iter::once(BASELINE)
            .chain(self.scenarios.iter().map(|s| s.name.as_str()))
            .collect()
    }

    /// The scenarios as a JSON array (the `scenarios` metadata of every chunk).
    pub fn scenarios_json(&self) -> serde_json::Value {
        serde_json::Value::Array(self.scenarios.iter().map(Scenario::to_json).collect())
    }
}

/// The smallest and largest of finite values, hard.
fn hull(values: &[f64]) -> ValueRange {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    ValueRange { lo, hi, hard: true }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changes_apply_as_their_names_say() {
        assert_eq!(Change::Set(2.0).apply(5.0), 2.0);
        assert_eq!(Change::Shift(-0.5).apply(5.0), 4.5);
        assert_eq!(Change::Scale(2.0).apply(5.0), 10.0);
        assert_eq!(Change::Cap(4.0).apply(5.0), 4.0);
        assert_eq!(Change::Cap(6.0).apply(5.0), 5.0);
        let c = ParamChange {
            param: ParamId::ToeDeg,
            change: Change::Shift(-0.15),
        };
        assert_eq!(c.words(), "toe_deg shifted by -0.15 deg");
        let c = ParamChange {
            param: ParamId::PressureKpa,
            change: Change::Shift(20.0),
        };
        assert_eq!(c.words(), "pressure_kpa shifted by +20 kPa");
        assert_eq!(scenario_key("toe_in"), "scenarios.toe_in");
        assert_eq!(scenario_key("toe-in -0.15"), "scenarios.\"toe-in -0.15\"");
    }

    #[test]
    fn a_scenario_changes_its_parameters_and_their_drawn_values_only() {
        let s = Scenario {
            name: "x".into(),
            changes: vec![
                ParamChange {
                    param: ParamId::ToeDeg,
                    change: Change::Shift(0.1),
                },
                ParamChange {
                    param: ParamId::GMod,
                    change: Change::Scale(2.0),
                },
            ],
            compare_to: None,
        };
        let p = Params::default();
        let q = s.apply(&p);
        assert_eq!(q.toe_deg, p.toe_deg + 0.1);
        assert_eq!(q.g_mod, 2.0 * p.g_mod);
        assert_eq!(q.speed_kmh, p.speed_kmh);
        let names = [ParamId::SpeedKmh, ParamId::GMod];
        assert_eq!(s.apply_values(&names, &[100.0, 1.0]), vec![100.0, 2.0]);
        assert_eq!(Scenario::from_json(&s.to_json()), Some(s));
    }

    #[test]
    fn a_change_of_an_absent_axle_value_starts_from_the_shared_one() {
        let s = Scenario {
            name: "rear".into(),
            changes: vec![ParamChange {
                param: ParamId::ToeRearDeg,
                change: Change::Shift(0.1),
            }],
            compare_to: None,
        };
        let p = Params {
            toe_deg: 0.25,
            ..Params::default()
        };
        let q = s.apply(&p);
        assert_eq!(q.toe_rear_deg, 0.25 + 0.1);
        assert!(
            q.toe_front_deg.is_nan(),
            "the front keeps the shared toe-in"
        );
        assert_eq!(q.toe_deg, 0.25);
    }

    /// A study drawing toe-in with `scenarios` appended.
    fn study(scenarios: &str) -> Result<Study, StudyError> {
        Study::parse(&format!(
            "[params]\ntoe_deg = {{ dist = \"uniform\", min = 0.2, max = 0.4 }}\n{scenarios}"
        ))
    }

    #[test]
    fn a_scenario_names_its_reference_and_records_it() {
        let s = study(
            "[scenarios.phi_014]\nwear_share_straight = { set = 0.14 }\n\
             [scenarios.phi_014_toe]\ncompare_to = \"phi_014\"\n\
             wear_share_straight = { set = 0.14 }\ntoe_deg = { shift = -0.1 }\n\
             [scenarios.toe_only]\ncompare_to = \"phi_014_toe\"\ntoe_deg = { shift = -0.1 }\n\
             [scenarios.z]\ncompare_to = \"baseline\"\ntoe_deg = { shift = 0.1 }\n",
        )
        .unwrap();
        let refs: Vec<(&str, &str)> = s
            .scenarios
            .iter()
            .map(|s| (s.name.as_str(), s.reference()))
            .collect();
        // A reference compared with a third scenario is accepted; `baseline` is the default.
        assert_eq!(
            refs,
            [
                ("phi_014", "baseline"),
                ("phi_014_toe", "phi_014"),
                ("toe_only", "phi_014_toe"),
                ("z", "baseline")
            ]
        );
        assert_eq!(s.scenarios[3].compare_to, None);
        // The reference travels with the footers' `scenarios`; a baseline one is not written.
        let json = s.scenarios_json();
        assert_eq!(json[1]["compare_to"], "phi_014");
        assert!(json[0].get("compare_to").is_none() && json[3].get("compare_to").is_none());
        for sc in &s.scenarios {
            assert_eq!(Scenario::from_json(&sc.to_json()).as_ref(), Some(sc));
        }
    }

    #[test]
    fn an_unknown_or_own_reference_is_refused_naming_the_key() {
        let two = "[scenarios.phi_014]\nwear_share_straight = { set = 0.14 }\n\
                   [scenarios.\"toe -0.1\"]\ntoe_deg = { shift = -0.1 }\n";
        let e = study(&format!("{two}compare_to = \"phi_14\"\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "`scenarios.\"toe -0.1\".compare_to` = \"phi_14\" names no scenario of this study; \
             did you mean `phi_014`? accepted: \"baseline\", \"phi_014\""
        );
        let e = study(&format!("{two}compare_to = \"toe -0.1\"\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "`scenarios.\"toe -0.1\".compare_to` = \"toe -0.1\" compares the scenario with itself; \
             accepted: \"baseline\", \"phi_014\""
        );
        let e = study(&format!("{two}compare_to = \"Baseline\"\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("did you mean `baseline`?"), "{e}");
        let e = study(&format!("{two}compare = \"phi_014\"\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(".compare`; did you mean `compare_to`?"), "{e}");
        // A reference alone changes nothing.
        let e = study("[scenarios.a]\ncompare_to = \"baseline\"\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`scenarios.a` changes nothing"), "{e}");
    }
}
