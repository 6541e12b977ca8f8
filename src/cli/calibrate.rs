//! `polywear calibrate`: fit parameters to target observations, write a parameter file.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::common::{CliError, CliResult};
use polywear::calibrate::{calibrate, parameter_file, parse_problem};

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Targets file (TOML; see studies/paper_targets.toml)
    #[arg(value_name = "TARGETS.toml")]
    pub targets: PathBuf,
    /// Parameters to fit, comma-separated (overrides the file's `fit`)
    #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
    pub fit: Vec<String>,
    /// Where the fitted parameter file goes
    #[arg(
        long,
        value_name = "FILE",
        default_value = "data/calibrated_params.toml"
    )]
    pub out: PathBuf,
}

pub fn run(args: &CalibrateArgs) -> CliResult {
    let text = std::fs::read_to_string(&args.targets)
        .map_err(|e| CliError(format!("{}: {e}", args.targets.display())))?;
    let mut problem =
        parse_problem(&text).map_err(|e| CliError(format!("{}: {e}", args.targets.display())))?;
    if !args.fit.is_empty() {
        problem.fit = args
            .fit
            .iter()
            .map(|n| {
                polywear::params::spec(n.trim())
                    .map(|s| s.name)
                    .ok_or_else(|| CliError(format!("--fit: unknown parameter `{n}`")))
            })
            .collect::<Result<_, _>>()?;
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
        "\n{:<28} {:>12} {:>14} {:>14} {:>10}",
        "target", "value", "model (start)", "model (fit)", "error"
    );
    for (name, value, before, after) in &fit.residuals {
        println!(
            "{name:<28} {value:>12.5} {before:>14.5} {after:>14.5} {:>9.2}%",
            100.0 * (after - value) / value
        );
    }
    println!(
        "\n{:<14} {:>14} {:>14} {:>9}",
        "parameter", "start", "fitted", "change"
    );
    for (name, a, b) in &fit.fitted {
        println!(
            "{name:<14} {a:>14.6e} {b:>14.6e} {:>8.2}%",
            100.0 * (b - a) / a
        );
    }
    println!("\nsensitivity d ln(target) / d ln(parameter) at the fit:");
    print!("{:<28}", "");
    for (name, _, _) in &fit.fitted {
        print!(" {name:>10}");
    }
    println!();
    for ((name, ..), row) in fit.residuals.iter().zip(&fit.sensitivity) {
        print!("{name:<28}");
        for v in row {
            print!(" {v:>10.3}");
        }
        println!();
    }
    std::fs::write(
        &args.out,
        parameter_file(&fit, &args.targets.display().to_string()),
    )
    .map_err(|e| CliError(format!("--out {}: {e}", args.out.display())))?;
    println!("\nwrote {} (use it with --params)", args.out.display());
    Ok(())
}
