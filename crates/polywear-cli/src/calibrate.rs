//! `polywear calibrate`: fit parameters to target observations, write a parameter file.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use polywear_analysis::render::calibration::{fit_heading, parameters_text, targets_text};

use super::common::{CliError, CliResult};
use polywear_core::params::ParamError;
use polywear_study::calibrate::{calibrate, parameter_file, parse_problem, Fit, Problem};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the fit behind the defaults\n",
    "  polywear calibrate studies/paper_targets.toml --out data/fit.toml\n",
    "  # then use the fitted parameters\n",
    "  polywear simulate --params data/fit.toml\n",
    "\nGuide: docs/book/src/reference/calibrate.md#calibrate"
))]
pub(crate) struct CalibrateArgs {
    /// Targets file (TOML; see studies/paper_targets.toml)
    #[arg(value_name = "TARGETS.toml")]
    pub(crate) targets: PathBuf,
    /// Parameters to fit, comma-separated (overrides the file's `fit`)
    #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
    pub(crate) fit: Vec<String>,
    /// Where the fitted parameter file goes (a missing folder is created)
    #[arg(
        long,
        value_name = "FILE",
        default_value = "data/calibrated_params.toml"
    )]
    pub(crate) out: PathBuf,
    /// Write the parameter file even when a target is not met within its tolerance (by default
    /// such a fit writes no file and exits 1)
    #[arg(long)]
    pub(crate) write_anyway: bool,
    /// Start from [params] values outside their plausible ranges (`polywear params`) anyway
    #[arg(long)]
    pub(crate) accept_implausible: bool,
}

/// Reads and checks the targets and flags, fits, prints the fit, then writes the parameter file;
/// exit code 1 (not the 2 of bad input) when the fit misses a target and `--write-anyway` is not
/// given.
pub(crate) fn run(args: &CalibrateArgs) -> CliResult<ExitCode> {
    let problem = resolve(args)?;
    let start = Instant::now();
    let fit = calibrate(&problem);
    print_fit(&problem, &fit, start.elapsed().as_secs_f64());
    write(args, &fit)
}

/// The targets file as a problem, with `--fit` in place of the file's `fit`, and the folder of
/// `--out` created: everything checked before the fit starts.
fn resolve(args: &CalibrateArgs) -> CliResult<Problem> {
    let problem = read_problem(args)?;
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        polywear_study::safe_write::create_dir(dir)
            .map_err(|e| CliError(format!("--out {}: {e}", dir.display())))?;
    }
    Ok(problem)
}

/// The fit's headline, its targets and its parameters.
fn print_fit(problem: &Problem, fit: &Fit, secs: f64) {
    println!("{}", fit_heading(problem, fit, secs));
    let mut text = String::new();
    targets_text(fit, &mut text);
    parameters_text(fit, &mut text);
    print!("{text}");
}

/// The parameter file at `--out`, unless the fit misses a target without `--write-anyway`.
fn write(args: &CalibrateArgs, fit: &Fit) -> CliResult<ExitCode> {
    let file = parameter_file(fit, &args.targets.display().to_string())
        .map_err(|e| CliError(e.to_string()))?;
    if let Err(e) = fit.check_met() {
        if !args.write_anyway {
            // The fit ran on good input but does not stand: exit 1, not the 2 of bad input.
            eprintln!("error: {e}; --write-anyway writes it nonetheless");
            return Ok(ExitCode::from(1));
        }
        eprintln!("warning: {e}; written nonetheless (--write-anyway)");
    }
    polywear_study::safe_write::write_file(&args.out, file.as_bytes())
        .map_err(|e| CliError(format!("--out {}: {e}", args.out.display())))?;
    println!("\nwrote {} (use it with --params)", args.out.display());
    Ok(ExitCode::SUCCESS)
}

/// The targets file as a problem, with `--fit` in place of the file's `fit` (checked alike).
fn read_problem(args: &CalibrateArgs) -> CliResult<Problem> {
    let text =
        super::common::read_input(&args.targets, "", polywear_study::safe_read::Limit::Text)?;
    let at = |e: &dyn std::fmt::Display| CliError(format!("{}: {e}", args.targets.display()));
    let mut problem = parse_problem(&text).map_err(|e| at(&e))?;
    if !args.accept_implausible {
        // The defaults are plausible: only the file's [params] can fail here.
        problem.start.check_plausible().map_err(|e| {
            let key = match &e {
                ParamError::Implausible { name, .. } => format!("`params.{name}`: "),
                _ => String::new(),
            };
            at(&format!("{key}{e}"))
        })?;
    }
    problem
        .fit_instead(&args.fit)
        .map_err(|e| CliError(format!("--fit: {e}")))?;
    Ok(problem)
}
