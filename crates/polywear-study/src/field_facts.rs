//! The field facts as data (MODEL.md#field-facts): what the field says about polygonal wear,
//! with its source and its figure, and whether the wear answer is fitted to it, only checked
//! against it, or takes a constant from it. The shipped table is `data/field_facts.toml`; the
//! tests take the calibration's targets from it, so that the document, the data and the checks
//! cannot drift apart.

use std::collections::BTreeSet;

/// The shipped table.
pub const SHIPPED: &str = include_str!("../../../data/field_facts.toml");
/// Its name in messages.
pub const SHIPPED_NAME: &str = "data/field_facts.toml";

/// What a fact is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// A fitting target: the calibrated constants are chosen to meet it.
    Target,
    /// A held-out check: never fitted, reported as a prediction.
    Check,
    /// Published data a constant is taken from.
    Data,
}

impl Role {
    /// The word in the table.
    pub fn word(self) -> &'static str {
        match self {
            Role::Target => "target",
            Role::Check => "check",
            Role::Data => "data",
        }
    }
}

/// One fact.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Fact {
    /// A stable name the code refers to.
    pub id: String,
    /// What it says, in words.
    pub says: String,
    /// Where it comes from.
    pub source: String,
    /// The figure's lower bound in `unit` (absent: none).
    pub min: Option<f64>,
    /// The figure's upper bound in `unit` (absent: none).
    pub max: Option<f64>,
    /// The figure's unit; "sign" for a direction (rises, falls).
    pub unit: String,
    /// Target, check or data.
    pub role: Role,
}

impl Fact {
    /// The figure as written in the table: "25,000–40,000 km", "≥ 60,000 km", "a sign".
    pub fn figure(&self) -> String {
        let n = number;
        match (self.min, self.max) {
            (Some(a), Some(b)) if a == b => format!("{} {}", n(a), self.unit),
            (Some(a), Some(b)) => format!("{}–{} {}", n(a), n(b), self.unit),
            (Some(a), None) => format!("≥ {} {}", n(a), self.unit),
            (None, Some(b)) => format!("≤ {} {}", n(b), self.unit),
            (None, None) => "a sign".to_string(),
        }
    }

    /// Whether `x` lies within the fact's bounds (inclusive).
    pub fn holds_for(&self, x: f64) -> bool {
        self.min.is_none_or(|a| x >= a) && self.max.is_none_or(|b| x <= b)
    }
}

/// A whole table, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldFacts {
    /// The facts, in file order.
    pub facts: Vec<Fact>,
}

/// Why a table is refused: the file, and the fact and key where that applies.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{file}: {what}")]
pub struct FactsError {
    /// The file named in the message.
    pub file: String,
    /// What is wrong.
    pub what: String,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    #[serde(default)]
    fact: Vec<Fact>,
}

impl FieldFacts {
    /// The shipped table (checked by the tests, so this cannot fail on a build that passed them).
    pub fn shipped() -> Self {
        Self::parse(SHIPPED, SHIPPED_NAME).expect("the shipped field facts are checked by tests")
    }

    /// Reads a table: TOML with one `[[fact]]` per fact. Refused: text that is not TOML of
    /// that shape, no fact, a repeated or empty id, an empty statement or source, a bound that
    /// is not finite, min above max, and a sign fact with bounds.
    pub fn parse(text: &str, file: &str) -> Result<Self, FactsError> {
        let refuse = |what: String| FactsError {
            file: file.to_string(),
            what,
        };
        let table: Table = toml::from_str(text).map_err(|e| refuse(e.message().to_string()))?;
        if table.fact.is_empty() {
            return Err(refuse("no [[fact]]: a table needs at least one".into()));
        }
        let mut ids = BTreeSet::new();
        for (i, f) in table.fact.iter().enumerate() {
            let at = format!("fact {} (`{}`)", i + 1, f.id);
            if f.id.trim().is_empty()
                || !f
                    .id
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
            {
                return Err(refuse(format!(
                    "{at}: `id` must be non-empty lowercase letters, digits or `_`"
                )));
            }
            if !ids.insert(f.id.clone()) {
                return Err(refuse(format!("{at}: `id` repeats an earlier fact's")));
            }
            for (key, v) in [("says", &f.says), ("source", &f.source), ("unit", &f.unit)] {
                if v.trim().is_empty() {
                    return Err(refuse(format!("{at}: `{key}` is empty")));
                }
            }
            for (key, v) in [("min", f.min), ("max", f.max)] {
                if v.is_some_and(|x| !x.is_finite()) {
                    return Err(refuse(format!("{at}: `{key}` must be a finite number")));
                }
            }
            if let (Some(a), Some(b)) = (f.min, f.max) {
                if a > b {
                    return Err(refuse(format!(
                        "{at}: `min` = {a} is above `max` = {b}; accepted: min ≤ max"
                    )));
                }
            }
            if f.unit == "sign" && (f.min.is_some() || f.max.is_some()) {
                return Err(refuse(format!(
                    "{at}: a fact of unit \"sign\" has no `min` or `max`"
                )));
            }
        }
        Ok(FieldFacts { facts: table.fact })
    }

    /// The fact named `id`.
    pub fn get(&self, id: &str) -> Option<&Fact> {
        self.facts.iter().find(|f| f.id == id)
    }

    /// The table as MODEL.md#field-facts prints it.
    pub fn markdown(&self) -> String {
        let mut s = String::from("| fact | figure | role | source |\n|---|---|---|---|\n");
        for f in &self.facts {
            s.push_str(&format!(
                "| {} (`{}`) | {} | {} | {} |\n",
                f.says,
                f.id,
                f.figure(),
                f.role.word(),
                f.source
            ));
        }
        s
    }
}

/// A figure as the table writes it: a whole number with thousands separators (25,000), any
/// other as it is (1.6).
fn number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        polywear_core::wording::thousands(x)
    } else {
        polywear_core::wording::plain(x, 12)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_table_is_accepted_and_has_the_calibration_targets() {
        let t = FieldFacts::parse(SHIPPED, SHIPPED_NAME).unwrap();
        let d = t.get("highway_follower_distance").unwrap();
        assert_eq!(
            (d.min, d.max, d.role),
            (Some(25_000.0), Some(40_000.0), Role::Target)
        );
        assert_eq!(d.figure(), "25,000–40,000 km");
        assert!(d.holds_for(30_000.0) && !d.holds_for(24_999.0));
        assert_eq!(t.get("fleet_median_never").unwrap().figure(), "≥ 60,000 km");
        assert_eq!(t.get("rises_with_toe").unwrap().figure(), "a sign");
        for id in [
            "follower_more_than_driving",
            "rises_with_speed",
            "rises_as_pressure_falls",
        ] {
            assert_eq!(t.get(id).unwrap().role, Role::Check, "{id}");
        }
    }

    #[test]
    fn a_damaged_table_is_refused_naming_the_file_and_key() {
        let good = "[[fact]]\nid = \"a\"\nsays = \"x\"\nsource = \"y\"\nunit = \"km\"\nrole = \"target\"\n";
        assert!(FieldFacts::parse(good, "f.toml").is_ok());
        let cases = [
            ("", "no [[fact]]"),
            ("[[fact]]\nid = \"a\"\n", "missing field"),
            (&good.replace("target", "goal"), "unknown variant"),
            (
                &format!("{good}min = 5\nmax = 1\n"),
                "`min` = 5 is above `max` = 1",
            ),
            (&format!("{good}{good}"), "repeats"),
            (&good.replace("\"x\"", "\"  \""), "`says` is empty"),
            (
                &good
                    .replace("\"km\"", "\"sign\"")
                    .replace("role", "min = 1\nrole"),
                "no `min` or `max`",
            ),
            (&good.replace("id = \"a\"", "id = \"A b\""), "lowercase"),
            (&format!("{good}colour = 3\n"), "unknown field"),
        ];
        for (text, want) in cases {
            let e = FieldFacts::parse(text, "f.toml").unwrap_err().to_string();
            assert!(
                e.starts_with("f.toml: ") && e.contains(want),
                "{text:?}: {e}"
            );
        }
    }
}
