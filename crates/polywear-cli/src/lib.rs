//! polywear's command line: each command's flags are resolved into the engine's problems
//! (`polywear-core`, `polywear-study`), solved, and their results turned into words, files and
//! figures (`polywear-analysis`). One module per subcommand; every refusal is exit code 2.
//! [`main`] is the whole program; the `polywear` binary only calls it.

// The flags' doc comments are clap's --help text, which writes units as `[km]` and placeholders
// as `<study>` (CONTRIBUTING.md): rustdoc reads those as links and HTML tags, and escaping them
// would print the backslashes in --help.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

pub(crate) mod analyze;
pub(crate) mod batch;
pub(crate) mod bifurcation;
pub(crate) mod calibrate;
pub(crate) mod chart;
pub(crate) mod classify;
pub(crate) mod common;
pub(crate) mod cycle;
pub(crate) mod explore;
pub(crate) mod optimize;
pub(crate) mod params;
pub(crate) mod reproduce;
pub(crate) mod simulate;
pub(crate) mod validate;
pub(crate) mod wear;
pub(crate) mod wear_reading;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Polygonal tire wear risk from tread lateral self-excited vibration (Zuo, Duan, Li 2014).
///
/// A brush tire model gives the contact patch and friction levels, a LuGre friction law drives a
/// 3-state ODE of the tread's lateral motion, and each wheel either settles (stable) or falls
/// into a limit cycle (self-excited vibration, the mechanism the wear model builds on; whether it
/// wears a visible polygon is the wear stage's answer). Driving and follower
/// wheels differ by their slip ratio.
#[derive(Debug, Parser)]
#[command(name = "polywear", version, about, long_about, max_term_width = 100)]
#[command(after_help = concat!(
    "Each command's --help explains its flags and ends with an example.\n",
    "Guide: docs/book/src/SUMMARY.md (every command, studies, output files); the model: MODEL.md#the-physics-step-by-step"
))]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Sample a study's operating points, classify both wheels of each, write Parquet
    ///
    /// The batch study: sample speed, toe-in, load, pressure and tire structure, classify both
    /// wheels of every sample in parallel, stream the rows to Parquet, and end with the analysis.
    Explore(crate::explore::ExploreArgs),
    /// Analyse explore output: occurrence, driving vs follower, risk maps, severity
    ///
    /// Analyse an explore output: occurrence probabilities, driving vs follower, risk maps,
    /// severity, Sobol sensitivity; writes tables, PNGs and report.md.
    Analyze(crate::analyze::AnalyzeArgs),
    /// Classify both wheels of every operating point of a CSV file, in parallel
    Classify(crate::classify::ClassifyArgs),
    /// Classify both wheels along a drive cycle: time and distance in vibration
    ///
    /// Classify both wheels at every step of a drive cycle (time_s, speed_kmh): share of time
    /// and distance in vibration, longest stretch, polygon orders, picture.
    Cycle(crate::cycle::CycleArgs),
    /// Find the setting in a box that minimises the risk of polygonal wear over a study
    ///
    /// Find the setting of one or two parameters (toe-in, pressure, ...) within a box that
    /// minimises the risk of polygonal wear, of vibration, or a weighted sum, over a study's
    /// samples (common random numbers): optimum with its interval, the region within it, the
    /// objective surface with the nominal tire's stability boundaries.
    Optimize(crate::optimize::OptimizeArgs),
    /// One operating point, both wheels: verdict table, JSON, time series, plot
    Simulate(crate::simulate::SimulateArgs),
    /// The long-term wear loop at one point, both wheels: the distance to a visible polygon
    ///
    /// The long-term wear loop for one operating point (or a drive cycle driven again and
    /// again), both wheels: the polygon's growth, lock-in, the distance to a visible polygon;
    /// summary, history and profile tables and a figure.
    Wear(crate::wear::WearArgs),
    /// Sweep one parameter for both wheels: Re λ, limit-cycle envelope, Hopf points
    ///
    /// Sweep one parameter for both wheels: eigenvalue and limit-cycle envelope, Hopf points,
    /// Parquet table and PNG.
    Bifurcation(crate::bifurcation::BifurcationArgs),
    /// Stability chart: every Hopf curve of both wheels in two parameters, with criticality
    ///
    /// Stability chart: every Hopf curve of both wheels in the plane of two parameters, with
    /// the onset's criticality (first Lyapunov coefficient); Parquet/CSV tables and PNG.
    Chart(crate::chart::ChartArgs),
    /// Regenerate the paper's figures and Table 3, with a comparison report
    ///
    /// Regenerate the paper's analyses (Figs. 4, 6-10, 12-23, Table 3) with a report that sets
    /// each result beside the paper's legible values.
    Reproduce(crate::reproduce::ReproduceArgs),
    /// Fit parameters to observed Hopf points and frequencies; writes a --params file
    Calibrate(crate::calibrate::CalibrateArgs),
    /// Check the fast classifier against brute-force integration (slow)
    Validate(crate::validate::ValidateArgs),
    /// List every model parameter: unit, default, provenance, accepted range
    #[command(after_help = concat!(
        "Examples:\n",
        "  polywear params\n",
        "  # the table of MODEL.md#parameter-table\n",
        "  polywear params --markdown\n",
        "\nGuide: docs/book/src/how-to/parameters-and-bad-input.md#parameters-and-bad-input"
    ))]
    Params {
        /// Print a Markdown table (as in MODEL.md#parameter-table)
        #[arg(long)]
        markdown: bool,
    },
}

/// The `polywear` program: parses the command line, runs the command, and maps every refusal
/// and failure to its message and exit code 2.
pub fn main() -> ExitCode {
    // Rust ignores SIGPIPE, which turns `polywear ... | head` into a panic on the next print;
    // the default action ends the process quietly, as command-line tools do.
    #[cfg(unix)]
    // SAFETY: called before any other thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    size_polars_group_tables(&cli.command);
    let done = |r: crate::common::CliResult| r.map(|()| ExitCode::SUCCESS);
    let result = match &cli.command {
        Command::Explore(a) => crate::explore::run(a),
        Command::Analyze(a) => done(crate::analyze::run(a)),
        Command::Classify(a) => done(crate::classify::run(a)),
        Command::Cycle(a) => done(crate::cycle::run(a)),
        Command::Optimize(a) => done(crate::optimize::run(a)),
        Command::Simulate(a) => done(crate::simulate::run(a)),
        Command::Wear(a) => done(crate::wear::run(a)),
        Command::Bifurcation(a) => done(crate::bifurcation::run(a)),
        Command::Chart(a) => done(crate::chart::run(a)),
        Command::Reproduce(a) => done(crate::reproduce::run(a)),
        Command::Calibrate(a) => crate::calibrate::run(a),
        Command::Validate(a) => done(crate::validate::run(a)),
        Command::Params { markdown } => {
            crate::params::run(*markdown);
            Ok(ExitCode::SUCCESS)
        }
    };
    // Every refusal and failure: its message, exit code 2.
    result.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

/// Sizes polars' streaming group-by tables for the analysis a command runs (`analyze`, and
/// `explore`'s closing report): polars 0.55 reads `POLARS_HOT_TABLE_SIZE` from the environment
/// and has no API for it, and the environment may only be changed while no other thread runs,
/// which holds here, before any work starts. A value the user set is kept.
fn size_polars_group_tables(command: &Command) {
    use polywear_analysis::analysis::AnalysisOptions;
    let opts = match command {
        Command::Analyze(a) => AnalysisOptions {
            map_bins: a.map_bins,
            ..AnalysisOptions::default()
        },
        Command::Explore(a) if !a.no_report => AnalysisOptions::default(),
        _ => return,
    };
    if std::env::var_os("POLARS_HOT_TABLE_SIZE").is_none() {
        std::env::set_var("POLARS_HOT_TABLE_SIZE", opts.hot_table_size().to_string());
    }
}
