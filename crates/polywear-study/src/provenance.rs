//! What every output file records about the run that wrote it (the brief's "every output file
//! records the study, the seed, the model variant, all parameter values and the program
//! version"): one place for the keys every command shares; each command appends its own
//! (study, seed, cycle, loop settings) after them.

use polywear_core::model::Variant;
use polywear_core::params::Params;

/// The program version written as `polywear_version`.
pub const POLYWEAR_VERSION: &str = env!("CARGO_PKG_VERSION");

/// The command line of this process, as typed (`command`).
pub fn command_line() -> String {
    std::env::args().collect::<Vec<_>>().join(" ")
}

/// The keys every output starts with: `polywear_version`, `command`, `variant` and `params`
/// (every parameter value, as JSON).
pub fn run_metadata(p: &Params, variant: Variant) -> Vec<(String, String)> {
    vec![
        ("polywear_version".into(), POLYWEAR_VERSION.into()),
        ("command".into(), command_line()),
        ("variant".into(), variant.as_str().into()),
        (
            "params".into(),
            serde_json::to_string(p).expect("params serialize"),
        ),
    ]
}
