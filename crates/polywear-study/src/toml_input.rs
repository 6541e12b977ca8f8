//! One typed reading of the TOML input files: study files ([`crate::study`]), calibration
//! targets ([`crate::calibrate`]) and parameter files (`--params`). Each file is parsed into a
//! table once, then read into a derived serde schema by [`from_value`]: unknown keys are
//! refused and every error names the full key (`target[0].weight`,
//! `params.toe_deg.levels[2]`). Checks of meaning (ranges, consistency) stay with the stage that
//! owns them, in a typed pass that knows each key.

mod de;
pub use de::from_value;

/// A problem with the shape of a TOML input: syntax, an unknown key, a missing key or a value
/// of the wrong type. Every variant names the key it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TomlError {
    /// Not TOML; where, and the parser's reason.
    #[error("malformed TOML {0}")]
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
    #[error("`{key}` = \"{name}\" is unknown;{hint} accepted: {accepted}", hint = polywear_core::wording::did_you_mean(name, accepted.split(", ")))]
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
    #[error("`{key}` = {} must be a whole number in [{lo}, {hi}]", polywear_core::wording::plain(*value, 12))]
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
    match polywear_core::wording::closest(typed, accepted.iter().copied()) {
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
pub(crate) fn finite_at(x: f64, key: &str) -> Result<f64, TomlError> {
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
pub(crate) fn whole_at(x: f64, key: &str, lo: u64, hi: u64) -> Result<u64, TomlError> {
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

/// Parses a TOML document into its top-level table. A syntax error is reported by line,
/// column and the parser's reason, without the parser's excerpt of the line: a file given by
/// mistake (a password file as a study) is named, never shown.
pub fn parse(text: &str) -> Result<toml::Table, TomlError> {
    text.parse().map_err(|e: toml::de::Error| {
        let reason = e.message().trim().replace('\n', "; ");
        TomlError::Malformed(match e.span() {
            Some(span) => {
                let before = &text.as_bytes()[..span.start.min(text.len())];
                let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
                let line_start = before
                    .iter()
                    .rposition(|&b| b == b'\n')
                    .map_or(0, |i| i + 1);
                let column = 1 + String::from_utf8_lossy(&before[line_start..])
                    .chars()
                    .count();
                format!("at line {line}, column {column}: {reason}")
            }
            None => reason,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_full_key() {
        let e = finite_at(f64::NAN, "a.y").unwrap_err().to_string();
        assert_eq!(e, "`a.y` = NaN must be finite");
        let e = whole_at(2.5, "a.z", 0, 9).unwrap_err().to_string();
        assert_eq!(e, "`a.z` = 2.5 must be a whole number in [0, 9]");
        let e = whole_at(1e300, "seed", 0, 9).unwrap_err().to_string();
        assert_eq!(e, "`seed` = 1e300 must be a whole number in [0, 9]");
        assert!(matches!(parse("x = "), Err(TomlError::Malformed(_))));
        // The offending line is located, never quoted.
        let e = parse("a = 1\nroot:$6$saltsalt$hash:19000:0:99999:7:::\n").unwrap_err();
        let e = e.to_string();
        assert!(e.starts_with("malformed TOML at line 2, column "), "{e}");
        assert!(!e.contains("salt"), "{e}");
    }
}
