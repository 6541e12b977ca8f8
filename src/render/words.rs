//! Small wordings the report's sections share: a probability in percent, a file by its name,
//! a McNemar p-value.

use std::path::Path;

use crate::analysis::paired::Paired;
use crate::analysis::stats::format_p;

/// A probability in percent with two decimals; "n/a" where there is no data.
pub(crate) fn pct(p: f64) -> String {
    if p.is_finite() {
        format!("{:.2}%", 100.0 * p)
    } else {
        "n/a".into()
    }
}

/// A file as the report links it: its name (the report sits beside its files).
pub(crate) fn rel(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// McNemar's p-value in words: "n/a (no discordant pairs)" when there is nothing to test.
pub(crate) fn mcnemar_text(p: &Paired) -> String {
    if p.p_value.is_nan() {
        "n/a (no discordant pairs)".into()
    } else {
        format!("{} ({})", format_p(p.p_value), p.method)
    }
}
