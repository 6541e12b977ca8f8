//! `polywear params`: every model parameter with unit, default, provenance and accepted range.

use polywear::params::SPECS;

pub fn run(markdown: bool) {
    if markdown {
        print!("{}", markdown_table());
        return;
    }
    println!(
        "{:<14} {:<8} {:<8} {:>12}  {:<31} {:<22} description",
        "name", "symbol", "unit", "default", "provenance", "accepted range"
    );
    for s in SPECS {
        println!(
            "{:<14} {:<8} {:<8} {:>12}  {:<31} {:<22} {}",
            s.name,
            s.symbol,
            s.unit,
            s.default,
            s.provenance.as_str(),
            s.range_text(),
            s.description
        );
    }
}

/// The parameter table as Markdown (MODEL.md#parameter-table embeds exactly this; tests/integration/docs.rs
/// keeps them equal).
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| name | symbol | unit | default | provenance | accepted range | meaning |\n|---|---|---|---|---|---|---|\n",
    );
    for s in SPECS {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} | {} | {} |\n",
            s.name,
            s.symbol,
            s.unit,
            s.default,
            s.provenance.as_str(),
            s.range_text(),
            s.description
        ));
    }
    out
}
