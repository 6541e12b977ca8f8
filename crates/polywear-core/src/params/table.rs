//! The parameter table in words: every parameter with its symbol, unit, default, provenance,
//! accepted and plausible ranges and meaning, then the wear stage's category settings, as
//! `polywear params` prints it and as MODEL.md#parameter-table embeds its Markdown (a test keeps
//! the two equal). Here, beside the specs it reads, so that any front end prints the same table.

use std::fmt::Write as _;

use super::{ParamSpec, SPECS};
use crate::wear::setting_rows;

/// The table for a terminal: fixed-width columns, the description last.
pub fn text_table() -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<28} {:<10} {:<10} {:>12}  {:<31} {:<22} {:<18} description",
        "name", "symbol", "unit", "default", "provenance", "accepted range", "plausible range"
    );
    for s in SPECS {
        let [name, symbol, unit, default, provenance, accepted, plausible, meaning] = cells(s);
        let _ = writeln!(
            out,
            "{name:<28} {symbol:<10} {unit:<10} {default:>12}  {provenance:<31} {accepted:<22} {plausible:<18} {meaning}"
        );
    }
    for [name, default, provenance, accepted, meaning] in setting_rows() {
        let _ = writeln!(
            out,
            "{name:<28} {:<10} {:<10} {default:>12}  {provenance:<31} {accepted:<22} {:<18} {meaning}",
            "-", "category", "-"
        );
    }
    out
}

/// The table as Markdown (MODEL.md#parameter-table embeds exactly this; tests/integration/docs.rs
/// keeps them equal).
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| name | symbol | unit | default | provenance | accepted range | plausible range | meaning |\n|---|---|---|---|---|---|---|---|\n",
    );
    for s in SPECS {
        let [name, symbol, unit, default, provenance, accepted, plausible, meaning] = cells(s);
        let _ = writeln!(
            out,
            "| `{name}` | {symbol} | {unit} | {default} | {provenance} | {accepted} | {plausible} | {meaning} |"
        );
    }
    for [name, default, provenance, accepted, meaning] in setting_rows() {
        let _ = writeln!(
            out,
            "| `{name}` | - | category | {default} | {provenance} | {accepted} | - | {meaning} |"
        );
    }
    out
}

/// One parameter's cells, in the table's column order: name, symbol, unit, default,
/// provenance, accepted range, plausible range, meaning.
fn cells(s: &ParamSpec) -> [String; 8] {
    [
        s.name.to_string(),
        s.symbol.to_string(),
        s.unit.to_string(),
        s.default.to_string(),
        s.provenance.as_str().to_string(),
        s.range_text(),
        plausible_cell(s),
        s.description.to_string(),
    ]
}

/// The plausible range, or `-` where the parameter has none (any accepted value is plausible).
fn plausible_cell(s: &ParamSpec) -> String {
    match s.plausible_text() {
        t if t.is_empty() => "-".to_string(),
        t => t,
    }
}
