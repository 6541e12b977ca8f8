//! A `[scenarios.NAME]` table as written: its changes, one per parameter, and the scenario it is
//! compared with (`compare_to`, the baseline when absent). One table holds both kinds of key, so
//! it is read by hand: `compare_to` takes a name, every other key a parameter and its change.

use std::collections::BTreeMap;

use serde::de::{self, MapAccess, Visitor};
use serde::Deserialize;

use polywear_core::params::toe::ToeInput;
use polywear_core::params::ParamId;
use polywear_core::wording::closest;

/// The key of a scenario's reference in its table.
pub(in crate::study) const COMPARE_TO: &str = "compare_to";

/// One change of a scenario as written (`[scenarios.NAME]`): exactly one of the four keys.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(in crate::study) struct ChangeSpec {
    pub(in crate::study) set: Option<f64>,
    pub(in crate::study) shift: Option<f64>,
    pub(in crate::study) scale: Option<f64>,
    pub(in crate::study) cap: Option<f64>,
}

/// One `[scenarios.NAME]` table as written.
#[derive(Debug, Default)]
pub(in crate::study) struct ScenarioTable {
    /// `compare_to = "OTHER"`: the scenario whose rows this one is compared with.
    pub(in crate::study) compare_to: Option<String>,
    /// Parameter → change.
    pub(in crate::study) changes: BTreeMap<ParamId, ChangeSpec>,
    /// The toe-in changed as an alignment sheet gives it (`toe_mm`, `toe_total_deg`), read as a
    /// change of `toe_deg` when the study's rim is known.
    pub(in crate::study) toe_changes: BTreeMap<ToeInput, ChangeSpec>,
}

/// `[scenarios]` as written: scenario name → its table.
pub(in crate::study) type ScenarioTables = BTreeMap<String, ScenarioTable>;

/// A key of a scenario table.
enum ScenarioKey {
    CompareTo,
    Param(ParamId),
    Toe(ToeInput),
}

impl<'de> Deserialize<'de> for ScenarioKey {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<ScenarioKey, D::Error> {
        let name = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        if name == COMPARE_TO {
            return Ok(ScenarioKey::CompareTo);
        }
        if let Some(t) = ToeInput::parse(&name) {
            return Ok(ScenarioKey::Toe(t));
        }
        match name.parse() {
            Ok(id) => Ok(ScenarioKey::Param(id)),
            // A misspelt `compare_to` is named as such, not as an unknown parameter.
            Err(_)
                if closest(&name, ParamId::names().into_iter().chain([COMPARE_TO]))
                    == Some(COMPARE_TO) =>
            {
                Err(de::Error::unknown_field(
                    &name,
                    &[COMPARE_TO, "a parameter of `polywear params`"],
                ))
            }
            Err(e) => Err(de::Error::custom(e)),
        }
    }
}

impl<'de> Deserialize<'de> for ScenarioTable {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<ScenarioTable, D::Error> {
        struct TableVisitor;
        impl<'de> Visitor<'de> for TableVisitor {
            type Value = ScenarioTable;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table of parameter changes")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ScenarioTable, A::Error> {
                let mut table = ScenarioTable::default();
                while let Some(key) = map.next_key::<ScenarioKey>()? {
                    match key {
                        ScenarioKey::CompareTo => table.compare_to = Some(map.next_value()?),
                        ScenarioKey::Param(id) => {
                            table.changes.insert(id, map.next_value()?);
                        }
                        ScenarioKey::Toe(t) => {
                            table.toe_changes.insert(t, map.next_value()?);
                        }
                    }
                }
                Ok(table)
            }
        }
        d.deserialize_map(TableVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<ScenarioTables, crate::toml_input::TomlError> {
        let t = toml::Value::Table(crate::toml_input::parse(text).unwrap());
        crate::toml_input::from_value(&t)
    }

    #[test]
    fn a_table_holds_changes_and_its_reference() {
        let t =
            read("[a]\ntoe_deg = { shift = -0.1 }\ncompare_to = \"b\"\n[b]\ng_mod = { scale = 2 }")
                .unwrap();
        assert_eq!(t["a"].compare_to.as_deref(), Some("b"));
        assert_eq!(t["a"].changes[&ParamId::ToeDeg].shift, Some(-0.1));
        assert_eq!(t["b"].compare_to, None);
        let e = read("[a]\ntoe_deg = { shift = -0.1 }\ncompare_to = 3")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "`a.compare_to` must be a string, got integer");
        let e = read("[a]\ntoe_deg = { shift = -0.1 }\ncompare = \"b\"")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("unknown key `a.compare`; did you mean `compare_to`?"),
            "{e}"
        );
        // An unknown parameter is still said as before.
        let e = read("[a]\ntoe = { shift = -0.1 }").unwrap_err().to_string();
        assert!(
            e.starts_with("`a.toe`: unknown parameter `toe`; did you mean `toe_deg`?"),
            "{e}"
        );
        let e = read("[a]\ntoe_deg = { shfit = -0.1 }")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("unknown key `a.toe_deg.shfit`"), "{e}");
    }
}
