//! Why rows have no verdict: the `failed` and `no_traction` rows grouped by their reason, with
//! the numbers in each reason blanked so that one cause is one group ("drive force … N exceeds
//! the adhesion limit … N"). Such rows are left out of every probability, so when more than
//! `LOUD_SHARE` of the rows have no verdict the summary and the report say so first: a
//! probability over the few rows that remain answers a different question (a pressure given
//! in bar leaves only the samples whose contact patch exists).

use std::collections::BTreeMap;
use std::path::PathBuf;

use super::rows::reason_counts;
use super::AnalysisError;
use polywear_core::classify::Class;

/// Above this share of rows without a verdict, the printed summary and `report.md` lead with
/// the reasons.
pub(crate) const LOUD_SHARE: f64 = 0.01;

/// The text that stands for a blanked number in a reason's pattern.
pub(crate) const BLANK: &str = "…";

/// The rows of one class that share one reason (up to its numbers).
#[derive(Debug, Clone, PartialEq)]
pub struct ReasonGroup {
    /// `failed` or `no_traction`.
    pub class: Class,
    /// The reason with its numbers blanked (`BLANK`).
    pub pattern: String,
    /// One full reason of the group (the smallest in text order, so the same on every run).
    pub example: String,
    /// Rows with this reason.
    pub rows: u64,
}

/// The rows without a verdict, grouped by reason.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Failures {
    /// All rows of the run.
    pub rows: u64,
    /// Rows without a verdict (failed or no traction).
    pub unclassified: u64,
    /// The groups, most rows first.
    pub groups: Vec<ReasonGroup>,
}

impl Failures {
    /// The share of rows without a verdict (0 without rows).
    pub fn share(&self) -> f64 {
        if self.rows == 0 {
            0.0
        } else {
            self.unclassified as f64 / self.rows as f64
        }
    }

    /// Whether the share is above `LOUD_SHARE`: the summary and report then lead with it.
    pub fn loud(&self) -> bool {
        self.share() > LOUD_SHARE
    }
}

/// The failed and no-traction rows of `files` grouped by reason; `rows` and `unclassified` are
/// the counts the occurrence query already has. Reads nothing when no row lacks a verdict.
pub(crate) fn failures(
    files: &[PathBuf],
    rows: u64,
    unclassified: u64,
) -> Result<Failures, AnalysisError> {
    let mut groups: BTreeMap<(Class, String), (String, u64)> = BTreeMap::new();
    if unclassified > 0 {
        reason_counts(
            files,
            &[Class::Failed, Class::NoTraction],
            &mut |class, reason, n| {
                let g = groups
                    .entry((class, pattern(reason)))
                    .or_insert_with(|| (reason.to_string(), 0));
                if reason < g.0.as_str() {
                    g.0 = reason.to_string();
                }
                g.1 += n;
            },
        )?;
    }
    let mut groups: Vec<ReasonGroup> = groups
        .into_iter()
        .map(|((class, pattern), (example, rows))| ReasonGroup {
            class,
            pattern,
            example,
            rows,
        })
        .collect();
    groups.sort_by(|a, b| b.rows.cmp(&a.rows).then(a.class.cmp(&b.class)));
    Ok(Failures {
        rows,
        unclassified,
        groups,
    })
}

/// A reason with each number blanked: a run of digits (with its sign, decimals and exponent)
/// that is not part of a name (`dop853`, `l1`, `2*r_b` keep theirs).
pub(crate) fn pattern(reason: &str) -> String {
    let chars: Vec<char> = reason.chars().collect();
    let name_char = |c: char| c.is_alphanumeric() || c == '_' || c == '*';
    let mut out = String::with_capacity(reason.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let starts_number =
            c.is_ascii_digit() || (c == '-' && chars.get(i + 1).is_some_and(char::is_ascii_digit));
        if !starts_number || (i > 0 && name_char(chars[i - 1])) {
            out.push(c);
            i += 1;
            continue;
        }
        let mut j = i + 1;
        while j < chars.len() {
            let d = chars[j];
            let exponent_sign = (d == '-' || d == '+') && matches!(chars[j - 1], 'e' | 'E');
            let exponent = (d == 'e' || d == 'E')
                && chars
                    .get(j + 1)
                    .is_some_and(|n| n.is_ascii_digit() || *n == '-');
            let decimal = d == '.' && chars.get(j + 1).is_some_and(char::is_ascii_digit);
            if d.is_ascii_digit() || decimal || exponent || exponent_sign {
                j += 1;
            } else {
                break;
            }
        }
        if chars.get(j).is_some_and(|&n| name_char(n)) {
            out.extend(&chars[i..j]);
        } else {
            out.push_str(BLANK);
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_blanked_and_names_kept() {
        assert_eq!(
            pattern("drive force 4512.3 N exceeds the adhesion limit 3900.0 N"),
            "drive force … N exceeds the adhesion limit … N"
        );
        assert_eq!(
            pattern("contact patch undefined: xi*deflection = 0.6012 m reaches the tire diameter 2*r_b = 0.5960 m"),
            "contact patch undefined: xi*deflection = … m reaches the tire diameter 2*r_b = … m"
        );
        assert_eq!(
            pattern("budget exceeded (max_rhs_evals 2000000, dop853 at t = 1.5e-3 s, l1 -2)"),
            "budget exceeded (max_rhs_evals …, dop853 at t = … s, l1 …)"
        );
        assert_eq!(
            pattern("shooting: Newton did not converge in 40 iterations"),
            "shooting: Newton did not converge in … iterations"
        );
    }

    #[test]
    fn the_share_is_loud_above_one_percent() {
        let f = |unclassified| Failures {
            rows: 1000,
            unclassified,
            groups: vec![],
        };
        assert!(!f(10).loud());
        assert!(f(11).loud());
        assert!(!Failures::default().loud());
    }
}
