//! `polywear explore`: the batch study, with progress bar, summary, resume and shards.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::OnceLock;

use clap::Args;
use polywear_analysis::plot::FigureFormat;

mod band;
mod errors;
mod resume;
mod shown;

use super::analyze::report_words;
use super::batch::{signal_name, Interrupt, Progress};
use super::common::{BudgetArgs, CliResult};
use crate::wear_reading::WearReadingArgs;
use errors::{explore_error, run_error};
use polywear_analysis::explore_run::{ClosingReport, ExploreOutcome, ExploreRun};
use polywear_analysis::render::run_words::{analyze_command, empty_shard_line, explore_lines};
use polywear_study::calibration_band::evaluate::DEFAULT_BAND_SAMPLES;
use polywear_study::explore::{chunk_size_warning, ExploreRequest, ExploreSession, RunPlan, Shard};
use polywear_study::study::SEED_MAX;
use resume::resume_command;
use shown::{every, Shown};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the built-in study, one million samples\n",
    "  polywear explore --samples 1e6\n",
    "  # a shipped study; rerun to resume\n",
    "  polywear explore studies/decoding.toml --out data/decoding --resume\n",
    "  # shard 0 of 4\n",
    "  polywear explore studies/wide_structure.toml --shard 0/4 --out results/shard-0\n",
    "\nGuide: docs/book/src/reference/explore.md#explore"
))]
pub(crate) struct ExploreArgs {
    /// Study file (TOML; see studies/ and docs/book/src/how-to/studies.md#studies). Without it: the built-in highway-fleet study
    /// (studies/default.toml)
    #[arg(value_name = "STUDY.toml")]
    pub(crate) study: Option<PathBuf>,
    /// Number of samples (1e6, 1_000_000 and 1000000 all work); default: the study's `samples`.
    /// For a grid design it must equal the grid's size; for a saltelli design it counts base
    /// points (each takes k + 2 evaluations for k drawn parameters)
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = parse_samples)]
    pub(crate) samples: Option<u64>,
    /// Seed; default: the study's `seed`. Same study + seed = same rows, whatever the threads.
    /// Accepted [0, 4398046510080]
    #[arg(long, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, SEED_MAX))]
    pub(crate) seed: Option<u64>,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
    /// Output directory, created when missing (must be empty or absent unless --resume)
    /// [default: data/explore_<study>_seed<seed>]
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Continue a stopped run in --out with its own study, parameters, samples, seed and shard
    /// (`polywear explore --resume --out DIR`; repeating them is accepted, contradicting them is
    /// refused). Complete chunk files are kept, the rest is redone; starts the run if --out is
    /// absent or empty. SIGINT/SIGTERM stop a run cleanly and print this command
    #[arg(long)]
    pub(crate) resume: bool,
    /// Evaluate only shard k of N (k from 0), e.g. `--shard $SLURM_ARRAY_TASK_ID/16`; the N
    /// shards' files together are the single-machine output
    #[arg(long, value_name = "k/N", allow_hyphen_values = true, value_parser = parse_shard)]
    pub(crate) shard: Option<Shard>,
    /// Parameter file (TOML `[params]`, e.g. from `polywear calibrate`): values for parameters
    /// the study does not name (one the study or its operating-point file sets too is refused)
    #[arg(long, value_name = "FILE")]
    pub(crate) params: Option<PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a study value,
    /// distribution bound or operating-point cell such as pressure_kpa = 2.4 (bar, not kPa) is
    /// refused before any work without it (a study can say `accept_implausible = true`)
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// No progress bar, progress lines or chatter; the answer (the analysis summary) is still
    /// printed, as ripgrep's and cargo's -q silence progress, not the result
    #[arg(long, short)]
    pub(crate) quiet: bool,
    /// When stderr is not a terminal (a batch log), print a progress line (done, rate, ETA)
    /// every S seconds instead of the bar, accepted [0.1, 86400]
    #[arg(long, value_name = "S", default_value_t = 5.0, value_parser = parse_log_every)]
    pub(crate) log_every: f64,
    /// Leave the wear stage out: the rows then carry no wear columns (distance to a visible
    /// polygon, growth rate, dominant order) and the run is about as fast as vibration alone.
    /// A study can say `wear = false`
    #[arg(long, conflicts_with_all = ["wear_zone", "wear_power", "wear_estimate"])]
    pub(crate) no_wear: bool,
    #[command(flatten)]
    pub(crate) wear: WearReadingArgs,
    /// Which axle the engine drives, over the study's `drivetrain`: `fwd` (the study's default;
    /// the follower is a rear wheel) or `rwd`. Rows say each wheel's `axle`
    #[arg(long, value_name = "fwd|rwd", value_parser = super::common::drivetrains())]
    pub(crate) drivetrain: Option<polywear_core::params::axle::Drivetrain>,
    /// The calibration band: a file of calibrated sets of the fitted wear constants (phi_s,
    /// sigma_V, k_d, carcass_share, belt_mass_share; TOML as data/calibration_band.toml, which
    /// `cargo run --release --example calibrate_band -- 1024 2000` regenerates), or `off` for
    /// the nominal constants' answer alone.
    /// Default: the shipped sets. Every wear figure is re-evaluated under each set on
    /// --band-samples of the run's own samples, and its range printed beside its sampling
    /// interval
    #[arg(long, value_name = "FILE|off")]
    pub(crate) calibration_band: Option<String>,
    /// Samples of the run the calibration band is evaluated on (all of them when the run has
    /// fewer), accepted [100, 1000000]; default 20000
    #[arg(long, value_name = "N", value_parser = super::common::whole_in::<u64>("--band-samples", 100, 1_000_000))]
    pub(crate) band_samples: Option<u64>,
    /// Skip the analysis report (risk maps, probabilities) written to DIR/_report at the end
    #[arg(long)]
    pub(crate) no_report: bool,
    /// File type of the report's figures
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub(crate) format: FigureFormat,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
}

pub(crate) fn run(args: &ExploreArgs) -> CliResult<ExitCode> {
    let plan = resolve(args)?;
    let band = band::choose(args, &plan)?;
    let pool = super::common::thread_pool(args.threads)?;
    // Checks and locks --out; the lock is held until this function returns.
    let prepared = plan.prepare_output().map_err(explore_error)?;
    for line in &prepared.redone {
        eprintln!("resume: {line}");
    }
    let todo = prepared.pending_samples(&plan);
    if !args.quiet {
        if let Some(w) = chunk_size_warning(plan.study.chunk_size) {
            eprintln!("{w}");
        }
        let kept = prepared.kept_samples(&plan);
        for line in explore_lines(&plan, kept, todo, pool.current_num_threads()) {
            eprintln!("{line}");
        }
    }
    let stop = Interrupt::install()?;
    let shown = Shown {
        args,
        plan: &plan,
        rows: Progress::new(args.quiet, todo, "samples", every(args)),
        band: OnceLock::new(),
        stop: &stop,
    };
    let session = ExploreSession {
        plan: &plan,
        prepared: &prepared,
        band: band.as_ref(),
        band_samples: args.band_samples.unwrap_or(DEFAULT_BAND_SAMPLES),
    };
    let report = (!args.no_report).then_some(args.format);
    let outcome = ExploreRun::new(session, report)
        .on_pool(&pool)
        .solve(&shown)
        .map_err(|e| run_error(args, &plan, e))?;
    let signal = stop.signal().unwrap_or(0);
    match outcome {
        ExploreOutcome::Finished(run) => {
            closing_words(args, &plan, &run.report).map(|()| ExitCode::SUCCESS)
        }
        ExploreOutcome::StoppedInRows(summary) => {
            drop(prepared);
            let saved = summary.samples_skipped + summary.samples_evaluated;
            eprintln!(
                "\nstopped by {}: {saved} of {} samples are saved in {}; the chunks in flight were dropped and are redone on resume",
                signal_name(signal),
                plan.owned_samples(),
                plan.out_dir.display()
            );
            eprintln!("resume with: {}", resume_command(args, &plan));
            Ok(ExitCode::from((128 + signal) as u8))
        }
        ExploreOutcome::StoppedInBand(_) => {
            drop(prepared);
            eprintln!(
                "\nstopped by {} during the calibration band: every sample's rows are saved in {}; the band is not finished, and analyze refuses the run until it is",
                signal_name(signal),
                plan.out_dir.display()
            );
            eprintln!("finish it with: {}", resume_command(args, &plan));
            Ok(ExitCode::from((128 + signal) as u8))
        }
    }
}

/// The run the flags ask for ([`ExploreRequest::plan`]), its notes on stderr.
fn resolve(args: &ExploreArgs) -> CliResult<RunPlan> {
    let request = ExploreRequest {
        study: args.study.clone(),
        samples: args.samples,
        seed: args.seed,
        out: args.out.clone(),
        resume: args.resume,
        shard: args.shard,
        params: args.params.clone(),
        accept_implausible: args.accept_implausible,
        no_wear: args.no_wear,
        wear_zone: args.wear.wear_zone,
        wear_power: args.wear.wear_power,
        drivetrain: args.drivetrain,
    };
    let (plan, notes) = request.plan(&|b| args.budget.apply(b))?;
    if !args.quiet {
        for note in notes {
            eprintln!("{note}");
        }
    }
    Ok(plan)
}

/// The closing report of a finished run in words (the run's own summary is printed when its
/// rows are saved, by [`Shown`]): an empty shard's page, the command that analyses the run
/// when no report was asked for, or the analysis's summary (printed even with --quiet: it is
/// the answer).
fn closing_words(args: &ExploreArgs, plan: &RunPlan, report: &ClosingReport) -> CliResult {
    match report {
        ClosingReport::EmptyShard(Some(page)) if !args.quiet => {
            println!("{}", empty_shard_line(plan, page));
        }
        ClosingReport::NotAsked if !args.quiet => {
            let command = analyze_command(plan, false);
            println!("no report (--no-report); the whole run's summary: {command}");
        }
        ClosingReport::Written(written) => return report_words(written, true),
        ClosingReport::EmptyShard(_) | ClosingReport::NotAsked => {}
    }
    Ok(())
}

/// Parses `--shard k/N` (k counted from 0, as Slurm array and Kubernetes indexed-job indices).
fn parse_shard(s: &str) -> Result<Shard, String> {
    s.parse().map_err(|e| format!("--shard {e}"))
}

/// Parses `--log-every`: seconds in [0.1, 86400].
fn parse_log_every(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| (0.1..=86_400.0).contains(x))
        .ok_or_else(|| format!("--log-every `{s}` must be a number of seconds in [0.1, 86400]"))
}

/// Parses `--samples`: 1e6, 1_000_000 and 1000000 all mean one million.
pub(crate) fn parse_samples(s: &str) -> Result<u64, String> {
    samples_up_to(s, 1 << 40, "2^40")
}

/// Parses `--samples` as [`parse_samples`] does, accepted [1, `most`] (`most_text` in the
/// refusal): optimize's range is narrower than explore's.
pub(crate) fn samples_up_to(s: &str, most: u64, most_text: &str) -> Result<u64, String> {
    let t = s.trim().replace('_', "");
    let x: f64 = t
        .parse()
        .map_err(|_| format!("--samples `{s}` is not a number (e.g. 1e6, 1_000_000)"))?;
    if !x.is_finite() || x < 1.0 || x.fract() != 0.0 || x > most as f64 {
        return Err(format!(
            "--samples `{s}` must be a whole number in [1, {most_text}]"
        ));
    }
    Ok(x as u64)
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
