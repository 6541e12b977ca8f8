//! `polywear`: command-line entry point. See `polywear --help`.

mod cli;

use clap::{Parser, Subcommand};

/// Polygonal tire wear risk from tread lateral self-excited vibration (Zuo, Duan, Li 2014).
///
/// A brush tire model gives the contact patch and friction levels, a LuGre friction law drives a
/// 3-state ODE of the tread's lateral motion, and each wheel either settles (stable) or falls
/// into a limit cycle (self-excited vibration, the cause of polygonal wear). Driving and follower
/// wheels differ by their slip ratio.
#[derive(Debug, Parser)]
#[command(name = "polywear", version, about, long_about, max_term_width = 100)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// The batch study: sample speed, toe-in, load, pressure and tire structure, classify both
    /// wheels of every sample in parallel, stream the rows to Parquet
    Explore(cli::explore::ExploreArgs),
    /// Analyse an explore output: occurrence probabilities, driving vs follower, risk maps,
    /// severity, Sobol sensitivity; writes tables, PNGs and report.md
    Analyze(cli::analyze::AnalyzeArgs),
    /// Classify every operating point of a CSV file (both wheels, in parallel)
    Classify(cli::classify::ClassifyArgs),
    /// Evaluate one operating point for both wheels: verdict table, JSON, time series, plot
    Simulate(cli::simulate::SimulateArgs),
    /// Sweep one parameter for both wheels: eigenvalue and limit-cycle envelope, Hopf points,
    /// Parquet table and PNG
    Bifurcation(cli::bifurcation::BifurcationArgs),
    /// Stability chart: every Hopf curve of both wheels in the plane of two parameters, with
    /// the onset's criticality (first Lyapunov coefficient); Parquet/CSV tables and PNG
    Chart(cli::chart::ChartArgs),
    /// Regenerate the paper's analyses (Figs. 4, 6-10, 12-23, Table 3) with a comparison report
    Reproduce(cli::reproduce::ReproduceArgs),
    /// Fit parameters to target observations (Hopf points, frequency); writes a --params file
    Calibrate(cli::calibrate::CalibrateArgs),
    /// Check the fast classifier against brute-force integration on random points (slow)
    Validate(cli::validate::ValidateArgs),
    /// List every model parameter: name, unit, default, provenance and accepted range
    Params {
        /// Print a Markdown table (as in README.md)
        #[arg(long)]
        markdown: bool,
    },
}

fn main() {
    // Rust ignores SIGPIPE, which turns `polywear ... | head` into a panic on the next print;
    // the default action ends the process quietly, as command-line tools do.
    #[cfg(unix)]
    // SAFETY: called before any other thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Explore(a) => cli::explore::run(a),
        Command::Analyze(a) => cli::analyze::run(a),
        Command::Classify(a) => cli::classify::run(a),
        Command::Simulate(a) => cli::simulate::run(a),
        Command::Bifurcation(a) => cli::bifurcation::run(a),
        Command::Chart(a) => cli::chart::run(a),
        Command::Reproduce(a) => cli::reproduce::run(a),
        Command::Calibrate(a) => cli::calibrate::run(a),
        Command::Validate(a) => cli::validate::run(a),
        Command::Params { markdown } => {
            cli::params::run(*markdown);
            Ok(())
        }
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}
