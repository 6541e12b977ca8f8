//! `polywear explore`: the batch study, with progress bar, summary, resume and shards.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::common::{BudgetArgs, CliError, CliResult};
use polywear::explore::{RunPlan, Shard};
use polywear::study::{Study, DEFAULT_STUDY, SEED_MAX};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the built-in study, one million samples\n",
    "  polywear explore --samples 1e6\n",
    "  # a shipped study; rerun to resume\n",
    "  polywear explore studies/decoding.toml --out data/decoding --resume\n",
    "  # shard 0 of 4\n",
    "  polywear explore studies/wide_structure.toml --shard 0/4 --out results/shard-0\n",
    "\nGuide: GUIDE.md#explore"
))]
pub struct ExploreArgs {
    /// Study file (TOML; see studies/ and GUIDE.md#studies). Without it: the built-in highway-fleet study
    /// (studies/default.toml)
    #[arg(value_name = "STUDY.toml")]
    pub study: Option<PathBuf>,
    /// Number of samples (1e6, 1_000_000 and 1000000 all work); default: the study's `samples`.
    /// For a grid design it must equal the grid's size; for a saltelli design it counts base
    /// points (each takes k + 2 evaluations for k drawn parameters)
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = parse_samples)]
    pub samples: Option<u64>,
    /// Seed; default: the study's `seed`. Same study + seed = same rows, whatever the threads.
    /// Accepted [0, 4398046510080]
    #[arg(long, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, SEED_MAX))]
    pub seed: Option<u64>,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub threads: Option<usize>,
    /// Output directory (must be empty or absent unless --resume)
    /// [default: data/explore_<study>_seed<seed>]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Continue a killed run in --out: complete chunk files are kept, the rest is redone
    /// (starts the run if --out is absent or empty)
    #[arg(long)]
    pub resume: bool,
    /// Evaluate only shard k of N (k from 0), e.g. `--shard $SLURM_ARRAY_TASK_ID/16`; the N
    /// shards' files together are the single-machine output
    #[arg(long, value_name = "k/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
    /// Parameter file (TOML `[params]`, e.g. from `polywear calibrate`): values for every
    /// parameter the study does not name
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// No progress bar and no summary
    #[arg(long, short)]
    pub quiet: bool,
    /// Skip the analysis report (risk maps, probabilities) written to DIR/_report at the end
    #[arg(long)]
    pub no_report: bool,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

pub fn run(args: &ExploreArgs) -> CliResult {
    let (source, origin) = match &args.study {
        Some(path) => (
            std::fs::read_to_string(path)
                .map_err(|e| CliError(format!("study {}: {e}", path.display())))?,
            path.display().to_string(),
        ),
        None => (
            DEFAULT_STUDY.to_string(),
            "built-in default study".to_string(),
        ),
    };
    let base = super::common::base_params(args.params.as_deref())?;
    // A relative `[operating_points]` file is found beside the study file.
    let study_dir = args.study.as_deref().and_then(Path::parent);
    let mut study = Study::parse_at(&source, base, study_dir.unwrap_or(Path::new("")))
        .map_err(|e| CliError(format!("{origin}: {e}")))?;
    study.budget = args.budget.apply(study.budget)?;
    let base_samples = args.samples.unwrap_or(study.samples);
    study
        .check_samples(base_samples)
        .map_err(|e| CliError(format!("{origin}: {e}")))?;
    // A Saltelli design needs k + 2 evaluations per base sample.
    let samples = study.evaluations(base_samples);
    let seed = args.seed.unwrap_or(study.seed);
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| default_out_dir(&study, seed));
    let plan = RunPlan {
        study,
        seed,
        samples,
        shard: args.shard.unwrap_or(Shard::WHOLE),
        out_dir,
        resume: args.resume,
        command: std::env::args().collect::<Vec<_>>().join(" "),
    };
    let pool = super::common::thread_pool(args.threads)?;
    // Checks and locks --out; the lock is held until this function returns.
    let prepared = plan.prepare_output().map_err(|e| CliError(e.to_string()))?;
    for line in &prepared.redone {
        eprintln!("resume: {line}");
    }
    let todo = prepared.pending_samples(&plan);
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(todo), ProgressDrawTarget::stderr())
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} samples  {rate}  ETA {eta}",
        )
        .expect("valid template")
        .with_key(
            "rate",
            |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.0} samples/s", s.per_sec());
            },
        ),
    );
    if !args.quiet {
        eprintln!(
            "{}: {} samples ({} design, seed {seed}, variants {}), shard {}, {} threads -> {}",
            plan.study.name,
            plan.samples,
            plan.study.design.as_str(),
            plan.study
                .variants
                .iter()
                .map(|v| v.as_str())
                .collect::<Vec<_>>()
                .join("+"),
            plan.shard,
            pool.current_num_threads(),
            plan.out_dir.display()
        );
    }
    let start = Instant::now();
    let result = pool.install(|| plan.run(&prepared, &|n| bar.inc(n)));
    bar.finish_and_clear();
    let summary = result.map_err(|e| CliError(e.to_string()))?;
    let secs = start.elapsed().as_secs_f64();
    if !args.quiet {
        println!(
            "{} samples evaluated in {secs:.1} s ({:.0} samples/s); {} already done; {} chunk files in {}",
            summary.samples_evaluated,
            summary.samples_evaluated as f64 / secs.max(1e-9),
            summary.samples_skipped,
            summary.chunks_written,
            plan.out_dir.display()
        );
        // In the order of the names, as always printed.
        let mut groups: Vec<_> = summary.classes.iter().collect();
        groups.sort_by_key(|((variant, wheel), _)| (variant.as_str(), wheel.as_str()));
        for ((variant, wheel), classes) in groups {
            let total: u64 = classes.values().sum();
            let vib: u64 = classes
                .iter()
                .filter(|(c, _)| c.vibrates())
                .map(|(_, n)| n)
                .sum();
            let mut rest: Vec<(&str, u64)> =
                classes.iter().map(|(c, n)| (c.as_str(), *n)).collect();
            rest.sort_unstable();
            let rest: Vec<String> = rest.iter().map(|(c, n)| format!("{c} {n}")).collect();
            println!(
                "  {:>8} {:>8}: limit cycle in {:.2}% ({})",
                variant.as_str(),
                wheel.as_str(),
                100.0 * vib as f64 / total.max(1) as f64,
                rest.join(", ")
            );
        }
    }
    // A shard that owns no chunk (fewer chunks than shards) did all it had to: say so, exit 0.
    if plan.owned_chunks().next().is_none() {
        if !args.no_report {
            empty_shard_report(&plan, args.quiet).map_err(CliError)?;
        }
        return Ok(());
    }
    // The analysis of the whole output directory (this shard's files), unless asked not to.
    if !args.no_report {
        super::analyze::report(
            std::slice::from_ref(&plan.out_dir),
            &polywear::analysis::report::ReportOptions::defaults(plan.out_dir.join("_report")),
            !args.quiet,
        )?;
    }
    Ok(())
}

/// The closing report of a shard that owns no chunk: `_report/report.md` says it holds no rows.
fn empty_shard_report(plan: &RunPlan, quiet: bool) -> Result<(), String> {
    let dir = plan.out_dir.join("_report");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let text = format!(
        "# Shard {k}/{n} of study `{name}`: no rows\n\nThis shard holds no rows: the run has {chunks} \
         chunk(s) of {size} samples ({samples} samples), fewer than the {n} shards, and shard k \
         owns the chunks whose index is k mod {n}. Nothing is missing; analyse all shards together \
         (`polywear analyze <shard directories>`).\n",
        k = plan.shard.index,
        n = plan.shard.count,
        name = plan.study.name,
        chunks = plan.n_chunks(),
        size = plan.study.chunk_size,
        samples = plan.samples,
    );
    let path = dir.join("report.md");
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    if quiet {
        return Ok(());
    }
    println!(
        "shard {}/{} holds no rows ({} chunk(s) for {} shards); report: {}",
        plan.shard.index,
        plan.shard.count,
        plan.n_chunks(),
        plan.shard.count,
        path.display()
    );
    Ok(())
}

/// Parses `--shard k/N` (k counted from 0, as Slurm array and Kubernetes indexed-job indices).
pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("--shard `{s}`: expected k/N, e.g. 0/4"))?;
    let k: u64 = k
        .trim()
        .parse()
        .map_err(|_| format!("--shard `{s}`: k is not a whole number"))?;
    let n: u64 = n
        .trim()
        .parse()
        .map_err(|_| format!("--shard `{s}`: N is not a whole number"))?;
    Shard::new(k, n).ok_or_else(|| format!("--shard `{s}`: need 0 <= k < N"))
}

/// Parses `--samples`: 1e6, 1_000_000 and 1000000 all mean one million.
pub fn parse_samples(s: &str) -> Result<u64, String> {
    let t = s.trim().replace('_', "");
    let x: f64 = t
        .parse()
        .map_err(|_| format!("--samples `{s}` is not a number (e.g. 1e6, 1_000_000)"))?;
    if !x.is_finite() || x < 1.0 || x.fract() != 0.0 || x > (1u64 << 40) as f64 {
        return Err(format!(
            "--samples `{s}` must be a whole number in [1, 2^40]"
        ));
    }
    Ok(x as u64)
}

/// Default output directory for a study and seed.
pub fn default_out_dir(study: &Study, seed: u64) -> PathBuf {
    Path::new("data").join(format!("explore_{}_seed{seed}", study.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_and_shards_parse() {
        assert_eq!(parse_samples("1e6"), Ok(1_000_000));
        assert_eq!(parse_samples("1_000_000"), Ok(1_000_000));
        assert_eq!(parse_samples("1000000"), Ok(1_000_000));
        assert!(parse_samples("1.5").is_err());
        assert!(parse_samples("0").is_err());
        assert!(parse_samples("-3").is_err());
        assert!(parse_samples("lots").is_err());
        assert_eq!(parse_shard("2/4"), Ok(Shard::new(2, 4).unwrap()));
        assert!(parse_shard("4/4").is_err());
        assert!(parse_shard("1").is_err());
        assert!(parse_shard("0/0").is_err());
    }
}
