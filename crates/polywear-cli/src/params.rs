//! `polywear params`: every model parameter with unit, default, provenance, accepted range and
//! plausible range, and the wear stage's category settings (wear zone, wear power).

use polywear_core::params::{ParamSpec, SPECS};
use polywear_core::wear::setting_rows;

pub(crate) fn run(markdown: bool) {
    if markdown {
        print!("{}", markdown_table());
        return;
    }
    println!(
        "{:<28} {:<10} {:<10} {:>12}  {:<31} {:<22} {:<18} description",
        "name", "symbol", "unit", "default", "provenance", "accepted range", "plausible range"
    );
    for s in SPECS {
        println!(
            "{:<28} {:<10} {:<10} {:>12}  {:<31} {:<22} {:<18} {}",
            s.name,
            s.symbol,
            s.unit,
            s.default,
            s.provenance.as_str(),
            s.range_text(),
            plausible_cell(s),
            s.description
        );
    }
    for [name, default, provenance, accepted, meaning] in setting_rows() {
        println!(
            "{name:<28} {:<10} {:<10} {default:>12}  {provenance:<31} {accepted:<22} {:<18} {meaning}",
            "-", "category", "-"
        );
    }
}

/// The parameter table as Markdown (MODEL.md#parameter-table embeds exactly this; tests/integration/docs.rs
/// keeps them equal).
pub(crate) fn markdown_table() -> String {
    let mut out = String::from(
        "| name | symbol | unit | default | provenance | accepted range | plausible range | meaning |\n|---|---|---|---|---|---|---|---|\n",
    );
    for s in SPECS {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} | {} | {} | {} |\n",
            s.name,
            s.symbol,
            s.unit,
            s.default,
            s.provenance.as_str(),
            s.range_text(),
            plausible_cell(s),
            s.description
        ));
    }
    for [name, default, provenance, accepted, meaning] in setting_rows() {
        out.push_str(&format!(
            "| `{name}` | - | category | {default} | {provenance} | {accepted} | - | {meaning} |\n"
        ));
    }
    out
}

/// The plausible range, or `-` where the parameter has none (any accepted value is plausible).
fn plausible_cell(s: &ParamSpec) -> String {
    match s.plausible_text() {
        t if t.is_empty() => "-".to_string(),
        t => t,
    }
}
