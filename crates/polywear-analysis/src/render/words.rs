//! Small wordings the report's sections share: a probability in percent, a file by its name,
//! a paired comparison's row.

use std::path::Path;

use crate::analysis::paired::Paired;

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

/// A paired comparison's cells in a Markdown table row: pairs, only follower, only driving,
/// both, neither, a wheel unclassified, McNemar's p-value.
pub(crate) fn paired_cells(p: &Paired) -> String {
    format!(
        "{} | {} | {} | {} | {} | {} | {}",
        p.pairs,
        p.only_follower,
        p.only_driving,
        p.both,
        p.neither,
        p.unclassified,
        p.mcnemar_text()
    )
}
