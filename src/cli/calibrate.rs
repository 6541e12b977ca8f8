//! `polywear calibrate`: fit parameters to target observations, write a parameter file.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::common::{CliError, CliResult};
use polywear::calibrate::{calibrate, parameter_file, parse_problem};
use polywear::params::{ParamError, ParamId};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the fit behind the defaults\n",
    "  polywear calibrate studies/paper_targets.toml --out data/fit.toml\n",
    "  # then use the fitted parameters\n",
    "  polywear simulate --params data/fit.toml\n",
    "\nGuide: GUIDE.md#calibrate"
))]
pub struct CalibrateArgs {
    /// Targets file (TOML; see studies/paper_targets.toml)
    #[arg(value_name = "TARGETS.toml")]
    pub targets: PathBuf,
    /// Parameters to fit, comma-separated (overrides the file's `fit`)
    #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
    pub fit: Vec<String>,
    /// Where the fitted parameter file goes (a missing folder is created)
    #[arg(
        long,
        value_name = "FILE",
        default_value = "data/calibrated_params.toml"
    )]
    pub out: PathBuf,
    /// Start from [params] values outside their plausible ranges (`polywear params`) anyway
    #[arg(long)]
    pub accept_implausible: bool,
}

pub fn run(args: &CalibrateArgs) -> CliResult {
    let text = std::fs::read_to_string(&args.targets)
        .map_err(|e| CliError(format!("{}: {e}", args.targets.display())))?;
    let mut problem =
        parse_problem(&text).map_err(|e| CliError(format!("{}: {e}", args.targets.display())))?;
    if !args.accept_implausible {
        // The defaults are plausible: only the file's [params] can fail here.
        problem.start.check_plausible().map_err(|e| {
            let key = match &e {
                ParamError::Implausible { name, .. } => format!("`params.{name}`: "),
                _ => String::new(),
            };
            CliError(format!("{}: {key}{e}", args.targets.display()))
        })?;
    }
    if !args.fit.is_empty() {
        let mut fit: Vec<ParamId> = Vec::new();
        for n in &args.fit {
            let name: ParamId = n
                .trim()
                .parse()
                .map_err(|e: ParamError| CliError(format!("--fit: {e}")))?;
            if fit.contains(&name) {
                return Err(CliError(format!("--fit: `{name}` is named twice")));
            }
            if problem.choices.iter().any(|(c, _)| *c == name) {
                return Err(CliError(format!(
                    "--fit: `{name}` is restricted by the file's `choices`; it cannot also be fitted"
                )));
            }
            fit.push(name);
        }
        problem.fit = fit;
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError(format!("--out {}: {e}", dir.display())))?;
    }
    let start = Instant::now();
    let fit = calibrate(&problem);
    println!(
        "fitted {} parameters to {} targets in {:.1} s ({} cost evaluations), cost {:.4e}",
        fit.fitted.len(),
        problem.targets.len(),
        start.elapsed().as_secs_f64(),
        fit.evaluations,
        fit.cost
    );
    println!(
        "\n{:<38} {:<9} {:<14} {:>11} {:>13} {:>13} {:>8}  met",
        "target", "wheel", "variant", "value", "model start", "model fit", "error"
    );
    for t in &fit.targets {
        println!(
            "{:<38} {:<9} {:<14} {:>11.5} {:>13.5} {:>13.5} {:>7.2}%  {}",
            t.name,
            t.wheel,
            t.variant,
            t.value,
            t.start,
            t.fitted,
            100.0 * t.rel_error(),
            if t.met() { "yes" } else { "NO" }
        );
    }
    let shortfalls: Vec<String> = fit.targets.iter().filter_map(|t| t.shortfall()).collect();
    if shortfalls.is_empty() {
        println!("\nevery target is met within its tolerance");
    } else {
        println!();
        for s in &shortfalls {
            println!("warning: {s}");
        }
    }
    if !fit.chosen.is_empty() {
        println!(
            "\nchosen among {} combinations of `choices`: {}",
            fit.combinations,
            fit.chosen
                .iter()
                .map(|(n, v)| format!("{n} = {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    println!(
        "\n{:<14} {:>14} {:>14} {:>9}",
        "parameter", "start", "fitted", "change"
    );
    for (name, a, b) in &fit.fitted {
        println!(
            "{:<14} {a:>14.6e} {b:>14.6e} {:>8.2}%",
            name.name(),
            100.0 * (b - a) / a
        );
    }
    println!("\nsensitivity d ln(target) / d ln(parameter) at the fit:");
    print!("{:<28}", "");
    for (name, _, _) in &fit.fitted {
        print!(" {:>10}", name.name());
    }
    println!();
    for (t, row) in fit.targets.iter().zip(&fit.sensitivity) {
        print!("{:<28}", t.name);
        for v in row {
            print!(" {v:>10.3}");
        }
        println!();
    }
    let file = parameter_file(&fit, &args.targets.display().to_string())
        .map_err(|e| CliError(e.to_string()))?;
    std::fs::write(&args.out, file)
        .map_err(|e| CliError(format!("--out {}: {e}", args.out.display())))?;
    println!("\nwrote {} (use it with --params)", args.out.display());
    Ok(())
}
