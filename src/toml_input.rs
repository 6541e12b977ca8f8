//! One typed reading of the TOML input files: study files ([`crate::study`]), calibration
//! targets ([`crate::calibrate`]) and parameter files (`--params`). Each file is parsed into a
//! table once, then read into a derived serde schema by [`from_value`] (or, for the targets,
//! key by key through [`Section`]); either way unknown keys are refused and every error names
//! the full key (`target[0].weight`, `params.toe_deg.levels[2]`). Checks of meaning (ranges,
//! consistency) stay with the stage that owns them, in a typed pass that knows each key.

use std::str::FromStr;

mod de;
pub use de::from_value;

/// A problem with the shape of a TOML input: syntax, an unknown key, a missing key or a value
/// of the wrong type. Every variant names the key it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TomlError {
    /// Not TOML; the parser's message.
    #[error("malformed TOML: {0}")]
    Malformed(String),
    /// A key the file may not hold.
    #[error("unknown key `{key}`; {accepted}")]
    UnknownKey {
        /// The key, in full.
        key: String,
        /// The keys accepted there.
        accepted: String,
    },
    /// A required key that is absent.
    #[error("`{key}` needs `{field}`")]
    Missing {
        /// The table's key.
        key: String,
        /// The missing key.
        field: String,
    },
    /// A value of the wrong type.
    #[error("`{key}` must be {expected}, got {got}")]
    WrongType {
        /// The key, in full.
        key: String,
        /// The type wanted, in words ("a number").
        expected: String,
        /// The type given, as TOML names it.
        got: String,
    },
    /// A name (a distribution, an enum's case) that names nothing.
    #[error("`{key}` = \"{name}\" is unknown;{hint} accepted: {accepted}", hint = crate::wording::did_you_mean(name, accepted.split(", ")))]
    UnknownName {
        /// The key, in full.
        key: String,
        /// The name given.
        name: String,
        /// The accepted names, comma-separated.
        accepted: String,
    },
    /// NaN or an infinity where a finite number is wanted.
    #[error("`{key}` = {value} must be finite")]
    NotFinite {
        /// The key, in full.
        key: String,
        /// The value given.
        value: f64,
    },
    /// A count that is not a whole number in its range.
    #[error("`{key}` = {value} must be a whole number in [{lo}, {hi}]")]
    NotWhole {
        /// The key, in full.
        key: String,
        /// The value given.
        value: f64,
        /// Smallest accepted value.
        lo: u64,
        /// Largest accepted value.
        hi: u64,
    },
    /// A value that does not parse into its type (a wheel, a variant, a design).
    #[error("`{key}`: {problem}")]
    Unparsable {
        /// The key, in full.
        key: String,
        /// Why it does not parse, with the accepted names.
        problem: String,
    },
}

impl TomlError {
    /// The error as seen from the table or array that holds the value: `segment` (a key, or
    /// `[i]`) is put in front of the key, so that the key is complete once the error leaves the
    /// file's top level.
    pub fn within(mut self, segment: &str) -> TomlError {
        match &mut self {
            TomlError::Malformed(_) => {}
            TomlError::UnknownKey { key, .. }
            | TomlError::Missing { key, .. }
            | TomlError::WrongType { key, .. }
            | TomlError::UnknownName { key, .. }
            | TomlError::NotFinite { key, .. }
            | TomlError::NotWhole { key, .. }
            | TomlError::Unparsable { key, .. } => {
                *key = if key.is_empty() {
                    segment.to_string()
                } else if key.starts_with('[') {
                    format!("{segment}{key}")
                } else {
                    format!("{segment}.{key}")
                };
            }
        }
        self
    }

    /// The key the error names, in full (empty for a syntax error).
    pub fn key(&self) -> &str {
        match self {
            TomlError::Malformed(_) => "",
            TomlError::UnknownKey { key, .. }
            | TomlError::Missing { key, .. }
            | TomlError::WrongType { key, .. }
            | TomlError::UnknownName { key, .. }
            | TomlError::NotFinite { key, .. }
            | TomlError::NotWhole { key, .. }
            | TomlError::Unparsable { key, .. } => key,
        }
    }
}

/// "did you mean `x`? " (when a name is close) followed by `hint`.
fn accepted_hint(typed: &str, accepted: &[&str], hint: &str) -> String {
    match crate::wording::closest(typed, accepted.iter().copied()) {
        Some(c) => format!("did you mean `{c}`? {hint}"),
        None => hint.to_string(),
    }
}

/// Parses a TOML document and reads it into the derived schema `T`; errors name the full key.
pub fn from_str<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, TomlError> {
    let table = toml::Value::Table(parse(text)?);
    from_value(&table)
}

/// A finite number at `key` (already read as a number).
pub fn finite_at(x: f64, key: &str) -> Result<f64, TomlError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(TomlError::NotFinite {
            key: key.to_string(),
            value: x,
        })
    }
}

/// A whole number in [lo, hi] at `key` (already read as a number; `1e3` is 1000).
pub fn whole_at(x: f64, key: &str, lo: u64, hi: u64) -> Result<u64, TomlError> {
    if x.fract() != 0.0 || x < lo as f64 || x > hi as f64 {
        return Err(TomlError::NotWhole {
            key: key.to_string(),
            value: x,
            lo,
            hi,
        });
    }
    Ok(x as u64)
}

/// Parses a TOML document into its top-level table.
pub fn parse(text: &str) -> Result<toml::Table, TomlError> {
    text.parse()
        .map_err(|e: toml::de::Error| TomlError::Malformed(e.to_string().trim().to_string()))
}

/// A number (integer or float, NaN and infinities included) at `key`.
pub fn number(v: &toml::Value, key: &str) -> Result<f64, TomlError> {
    match v {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        _ => Err(wrong_type(key, "a number", v)),
    }
}

/// A finite number at `key`.
pub fn finite(v: &toml::Value, key: &str) -> Result<f64, TomlError> {
    finite_at(number(v, key)?, key)
}

/// A whole number in [lo, hi] at `key` (`1e3` is accepted as 1000).
pub fn whole(v: &toml::Value, key: &str, lo: u64, hi: u64) -> Result<u64, TomlError> {
    whole_at(number(v, key)?, key, lo, hi)
}

/// A string at `key`.
pub fn text<'v>(v: &'v toml::Value, key: &str) -> Result<&'v str, TomlError> {
    v.as_str().ok_or_else(|| wrong_type(key, "a string", v))
}

/// A string at `key` parsed into `T` (e.g. a [`crate::model::Wheel`]).
pub fn parsed<T: FromStr>(v: &toml::Value, key: &str) -> Result<T, TomlError>
where
    T::Err: std::fmt::Display,
{
    text(v, key)?
        .parse()
        .map_err(|e: T::Err| TomlError::Unparsable {
            key: key.to_string(),
            problem: e.to_string(),
        })
}

/// An array at `key`; `expected` says of what, for the message.
pub fn array<'v>(
    v: &'v toml::Value,
    key: &str,
    expected: &'static str,
) -> Result<&'v [toml::Value], TomlError> {
    v.as_array()
        .map(Vec::as_slice)
        .ok_or_else(|| wrong_type(key, expected, v))
}

fn wrong_type(key: &str, expected: &'static str, v: &toml::Value) -> TomlError {
    TomlError::WrongType {
        key: key.to_string(),
        expected: expected.to_string(),
        got: v.type_str().to_string(),
    }
}

/// A table of an input file with the dotted path that leads to it (`""` at the top,
/// `"target[0]"`, `"params.speed_kmh"`), so that every key read from it is named in full.
#[derive(Debug, Clone, Copy)]
pub struct Section<'a> {
    /// The table.
    pub table: &'a toml::Table,
    /// Its dotted path (`""` at the top).
    pub path: &'a str,
}

impl<'a> Section<'a> {
    /// The top-level table of a file.
    pub fn top(table: &'a toml::Table) -> Self {
        Section { table, path: "" }
    }

    /// The value at `path` as a table section (`path` must outlive it).
    pub fn of(
        v: &'a toml::Value,
        path: &'a str,
        expected: &'static str,
    ) -> Result<Self, TomlError> {
        let table = v.as_table().ok_or_else(|| wrong_type(path, expected, v))?;
        Ok(Section { table, path })
    }

    /// The full name of `field` in this section.
    pub fn key(&self, field: &str) -> String {
        if self.path.is_empty() {
            field.to_string()
        } else {
            format!("{}.{field}", self.path)
        }
    }

    /// Refuses any key not in `accepted`, listing them.
    pub fn deny_unknown(&self, accepted: &[&str]) -> Result<(), TomlError> {
        self.deny_unknown_with(accepted, &format!("accepted: {}", accepted.join(", ")))
    }

    /// Refuses any key not in `accepted`, with `hint` after the key.
    pub fn deny_unknown_with(&self, accepted: &[&str], hint: &str) -> Result<(), TomlError> {
        match self.table.keys().find(|k| !accepted.contains(&k.as_str())) {
            Some(k) => Err(TomlError::UnknownKey {
                key: self.key(k),
                accepted: accepted_hint(k, accepted, hint),
            }),
            None => Ok(()),
        }
    }

    /// The raw value of `field`, if present.
    pub fn get(&self, field: &str) -> Option<&'a toml::Value> {
        self.table.get(field)
    }

    /// The value of `field`, refused when absent.
    pub fn need(&self, field: &str) -> Result<&'a toml::Value, TomlError> {
        self.get(field).ok_or_else(|| TomlError::Missing {
            key: self.path.to_string(),
            field: field.to_string(),
        })
    }

    /// Reads `field` with `read` (one of this module's functions) when present.
    pub fn opt<T>(
        &self,
        field: &str,
        read: impl FnOnce(&'a toml::Value, &str) -> Result<T, TomlError>,
    ) -> Result<Option<T>, TomlError> {
        self.get(field)
            .map(|v| read(v, &self.key(field)))
            .transpose()
    }

    /// Reads `field` with `read`, refused when absent.
    pub fn req<T>(
        &self,
        field: &str,
        read: impl FnOnce(&'a toml::Value, &str) -> Result<T, TomlError>,
    ) -> Result<T, TomlError> {
        read(self.need(field)?, &self.key(field))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_full_key() {
        let t = parse("[a]\nx = \"s\"\ny = nan\nz = 2.5\n").unwrap();
        let a = Section::of(t.get("a").unwrap(), "a", "a table").unwrap();
        let e = a.req("x", number).unwrap_err().to_string();
        assert_eq!(e, "`a.x` must be a number, got string");
        let e = a.req("y", finite).unwrap_err().to_string();
        assert_eq!(e, "`a.y` = NaN must be finite");
        let e = a
            .req("z", |v, k| whole(v, k, 0, 9))
            .unwrap_err()
            .to_string();
        assert_eq!(e, "`a.z` = 2.5 must be a whole number in [0, 9]");
        assert_eq!(a.need("w").unwrap_err().to_string(), "`a` needs `w`");
        let e = a.deny_unknown(&["x", "y"]).unwrap_err().to_string();
        assert_eq!(e, "unknown key `a.z`; accepted: x, y");
        assert!(matches!(parse("x = "), Err(TomlError::Malformed(_))));
    }
}
