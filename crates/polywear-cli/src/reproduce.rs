//! `polywear reproduce`: the paper's analyses, figures, Table 3 and a comparison report.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use polywear_analysis::plot::FigureFormat;

use super::common::{CliError, CliResult};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # data/paper_2014/report.md and the figures\n",
    "  polywear reproduce\n",
    "  # at the constants R0\n",
    "  polywear reproduce --params studies/params_r0.toml --out data/paper_r0\n",
    "\nGuide: docs/book/src/reference/reproduce.md#reproduce"
))]
pub(crate) struct ReproduceArgs {
    /// Output directory, created when missing
    #[arg(long, value_name = "DIR", default_value = "data/paper_2014")]
    pub(crate) out: PathBuf,
    /// Values per bifurcation sweep, accepted [11, 2001]
    #[arg(long, default_value_t = 161, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--steps", 11, 2001))]
    pub(crate) steps: usize,
    /// Samples of the default study for the paired driving-vs-follower comparison, accepted
    /// [10, 1000000]
    #[arg(long, value_name = "N", default_value_t = 4000)]
    pub(crate) paired_samples: u64,
    /// Parameter file (e.g. from `polywear calibrate`, or studies/params_r0.toml for the reference
    /// constants R0, MODEL.md#r0-and-the-shipped-defaults) instead of the defaults
    #[arg(long, value_name = "FILE")]
    pub(crate) params: Option<PathBuf>,
    /// Run --params values outside their plausible ranges (`polywear params`) anyway
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// File type of the figures
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub(crate) format: FigureFormat,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
}

pub(crate) fn run(args: &ReproduceArgs) -> CliResult {
    if !(11..=2001).contains(&args.steps) {
        return Err(CliError(format!(
            "--steps = {} is outside its accepted range [11, 2001]",
            args.steps
        )));
    }
    if !(10..=1_000_000).contains(&args.paired_samples) {
        return Err(CliError(format!(
            "--paired-samples = {} is outside its accepted range [10, 1000000]",
            args.paired_samples
        )));
    }
    let base = super::common::base_params(args.params.as_deref(), args.accept_implausible)?;
    let pool = super::common::thread_pool(args.threads)?;
    let start = Instant::now();
    let request = polywear_analysis::reproduce::Request {
        base,
        steps: args.steps,
        paired_samples: args.paired_samples,
    };
    let (_, files) = pool
        .install(|| polywear_analysis::reproduce::reproduce(&request, &args.out, args.format))
        .map_err(|e| CliError(e.to_string()))?;
    println!(
        "reproduced the paper's analyses in {:.1} s: {} files in {}; read {}",
        start.elapsed().as_secs_f64(),
        files.len(),
        args.out.display(),
        args.out.join("report.md").display()
    );
    Ok(())
}
