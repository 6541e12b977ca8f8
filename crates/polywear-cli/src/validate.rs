//! `polywear validate`: the fast classifier against the brute-force reference on random points.

use std::path::PathBuf;

use clap::Args;

use super::common::{check_extension, BudgetArgs, CliError, CliResult};
use polywear_analysis::render::validation::report_lines;
use polywear_core::classify::ClassifierOptions;
use polywear_study::parquet_out::write_csv;
use polywear_study::validation::{compare_with, comparison_columns};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  polywear validate --points 340 --seed 1 --out data/validate_340.csv\n",
    "\nGuide: docs/book/src/reference/validate.md#validate"
))]
pub(crate) struct ValidateArgs {
    /// Random operating points (each evaluated for 2 wheels × 3 variants), accepted [1, 100000]
    #[arg(long, default_value_t = 300, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--points", 1, 100_000))]
    pub(crate) points: u64,
    /// Seed of the point set, accepted [0, 4398046510080]
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, polywear_study::study::SEED_MAX))]
    pub(crate) seed: u64,
    /// Worker threads for the reference (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
    /// Per-wheel results as CSV
    #[arg(long, value_name = "FILE.csv")]
    pub(crate) out: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
}

pub(crate) fn run(args: &ValidateArgs) -> CliResult {
    if !(1..=100_000).contains(&args.points) {
        return Err(CliError(format!(
            "--points = {} is outside [1, 100000]",
            args.points
        )));
    }
    if let Some(out) = &args.out {
        check_extension(out, &["csv"], "--out")?;
    }
    let opts = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let pool = super::common::thread_pool(args.threads)?;
    eprintln!(
        "classifying {} points x 2 wheels x 3 variants, fast and brute force (this takes minutes)...",
        args.points
    );
    let rows = pool.install(|| compare_with(args.seed, args.points, &opts));
    for line in report_lines(&rows) {
        println!("{line}");
    }
    if let Some(out) = &args.out {
        write_csv(out, &comparison_columns(&rows))?;
        eprintln!("wrote {}", out.display());
    }
    let disagreements = rows
        .iter()
        .filter(|r| r.compared() && !r.classes_agree())
        .count();
    if disagreements > 0 {
        return Err(CliError(format!(
            "{disagreements} class disagreements outside the Hopf band"
        )));
    }
    Ok(())
}
