//! The parameter table in words: every parameter with its symbol, unit, default, provenance,
//! accepted and plausible ranges and meaning, then the wear stage's category settings, as
//! `polywear params` prints it and as MODEL.md#parameter-table embeds its Markdown (a test keeps
//! the two equal). Here, beside the specs it reads, so that any front end prints the same table.

use std::fmt::Write as _;

use super::{Group, ParamSpec, SPECS};

/// The category settings' rows: the drivetrain (MODEL.md#the-car-axles-and-drivetrain), then the
/// wear stage's.
fn setting_rows() -> Vec<[String; 5]> {
    let drivetrain = [
        "drivetrain".to_string(),
        "fwd".to_string(),
        "judgement".to_string(),
        "fwd, rwd".to_string(),
        "Which axle is driven, a category: fwd = the driving wheel is a front wheel, the follower a rear one (the compact cars of the field reports); rwd = the driving wheel is a rear wheel.".to_string(),
    ];
    std::iter::once(drivetrain)
        .chain(crate::wear::setting_rows())
        .collect()
}

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
    for s in SPECS.iter().filter(|s| s.group != Group::Axle) {
        let [name, symbol, unit, default, provenance, accepted, plausible, meaning] = cells(s);
        let _ = writeln!(
            out,
            "| `{name}` | {symbol} | {unit} | {default} | {provenance} | {accepted} | {plausible} | {meaning} |"
        );
    }
    // An axle's own values in one row: each is its shared key's, per axle (`polywear params`
    // lists them one by one).
    let per_axle: Vec<String> = SPECS
        .iter()
        .filter(|s| s.group == Group::Axle)
        .map(|s| format!("`{}`", s.name))
        .collect();
    let _ = writeln!(
        out,
        "| {} | - | as the shared key | = the shared key | given per axle | as the shared key | as the shared key | An axle's own toe-in, load or pressure; absent = the shared key's (MODEL.md#the-car-axles-and-drivetrain). |",
        per_axle.join(", ")
    );
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
        default_cell(s),
        provenance_cell(s),
        s.range_text(),
        plausible_cell(s),
        s.description.to_string(),
    ]
}

/// The default, or the shared key an axle's own value stands in for when absent.
fn default_cell(s: &ParamSpec) -> String {
    match shared_of(s) {
        Some(shared) => format!("= {shared}"),
        None => s.default.to_string(),
    }
}

/// The provenance, or "the axle's own, when given" for a per-axle value.
fn provenance_cell(s: &ParamSpec) -> String {
    match shared_of(s) {
        Some(_) => "given per axle".to_string(),
        None => s.provenance.as_str().to_string(),
    }
}

/// The shared key of a per-axle parameter (`toe_deg` for `toe_rear_deg`).
fn shared_of(s: &ParamSpec) -> Option<&'static str> {
    let id: super::ParamId = s.name.parse().ok()?;
    id.is_per_axle()
        .then(|| id.axle_quantity().map(|q| q.shared.name()))
        .flatten()
}

/// The plausible range, or `-` where the parameter has none (any accepted value is plausible).
fn plausible_cell(s: &ParamSpec) -> String {
    match s.plausible_text() {
        t if t.is_empty() => "-".to_string(),
        t => t,
    }
}
