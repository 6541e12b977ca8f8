//! `polywear analyze`: occurrence probabilities, driving vs follower, risk maps, severity and
//! sensitivity from an explore output.

use std::path::PathBuf;

use clap::Args;
use polywear_analysis::plot::FigureFormat;

use super::common::{CliError, CliResult};
use polywear_analysis::analysis::{AnalysisError, AnalysisOptions};
use polywear_analysis::render::summary::{analysed_line, default_report_dir, summary_lines};
use polywear_analysis::render::RenderOptions;
use polywear_analysis::run_report::{write_report, ReportError, RunReport};
use polywear_core::params::ParamId;

#[derive(Debug, Args, Clone)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # an extra risk map\n",
    "  polywear analyze data/explore_highway_fleet_seed2014 --pair g_mod,load_n\n",
    "  # the shards of one run, together\n",
    "  polywear analyze results/shard-*\n",
    "\nGuide: docs/book/src/reference/analyze.md#analyze"
))]
pub(crate) struct AnalyzeArgs {
    /// Explore output: a directory of chunk files, a Parquet file, or several (e.g. shard
    /// directories)
    #[arg(value_name = "DIR", required = true)]
    pub(crate) inputs: Vec<PathBuf>,
    /// Where the report goes, created when missing [default: <first input>/_report]
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Bins per axis for conditional probabilities, accepted [2, 200]
    #[arg(long, default_value_t = AnalysisOptions::DEFAULT_BINS, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--bins", 2, 200))]
    pub(crate) bins: usize,
    /// Bins per axis for risk maps, accepted [2, 200]
    #[arg(long, default_value_t = AnalysisOptions::DEFAULT_MAP_BINS, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--map-bins", 2, 200))]
    pub(crate) map_bins: usize,
    /// Cells and bins with fewer samples are shown as "too few", accepted [1, 1e9]
    #[arg(long, default_value_t = AnalysisOptions::DEFAULT_MIN_COUNT, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--min-count", 1, 1_000_000_000))]
    pub(crate) min_count: u64,
    /// Extra risk map over two drawn parameters, e.g. `--pair g_mod,load_n` (repeatable); the
    /// maps speed_kmh,toe_deg and load_n,pressure_kpa are always drawn
    #[arg(long, value_name = "X,Y", value_parser = parse_pair)]
    pub(crate) pair: Vec<(ParamId, ParamId)>,
    /// Bootstrap resamples for the Sobol indices' intervals, accepted [10, 100000]
    #[arg(long, default_value_t = AnalysisOptions::DEFAULT_BOOTSTRAP, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--bootstrap", 10, 100_000))]
    pub(crate) bootstrap: usize,
    /// A run with scenarios compares each with its reference (the baseline, or its
    /// `compare_to`) on the risk of a visible polygon within this distance [km] (and on
    /// vibration); the report's first-order indices of the wear outcome use it too. Accepted
    /// (0, 1e6]
    #[arg(long, value_name = "KM", default_value_t = AnalysisOptions::DEFAULT_SCENARIO_WITHIN_KM, allow_negative_numbers = true, value_parser = parse_km)]
    pub(crate) scenario_within_km: f64,
    /// P(visible polygonal wear within each distance) per wheel [km], comma-separated, each
    /// within (0, 1e6]; 40000 (the headline) is always added
    #[arg(long, value_name = "KM,...", default_value = "10000,25000,40000,60000", allow_negative_numbers = true, value_parser = parse_km_list)]
    pub(crate) within_km: KmList,
    /// File type of the figures
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub(crate) format: FigureFormat,
}

/// The distances of `--within-km` \[km\].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct KmList(pub Vec<f64>);

/// Parses `--within-km`: distances in km within (0, 1e6], comma-separated.
pub(crate) fn parse_km_list(s: &str) -> Result<KmList, String> {
    let km: Vec<f64> = s
        .split(',')
        .map(|v| {
            parse_km(v).map_err(|_| {
                format!("--within-km `{}` must be a distance in km within (0, 1e6], e.g. --within-km 10000,25000,40000,60000", v.trim())
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(KmList(km))
}

/// Parses a distance in km within (0, 1e6].
pub(crate) fn parse_km(s: &str) -> Result<f64, String> {
    s.trim()
        .replace('_', "")
        .parse::<f64>()
        .ok()
        .filter(|x| *x > 0.0 && *x <= 1e6)
        .ok_or_else(|| format!("`{s}` must be a distance in km within (0, 1e6]"))
}

fn parse_pair(s: &str) -> Result<(ParamId, ParamId), String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("--pair `{s}`: expected X,Y"))?;
    let parse = |n: &str| {
        n.trim()
            .parse::<ParamId>()
            .map_err(|e| format!("--pair `{s}`: {e}"))
    };
    let (a, b) = (parse(a)?, parse(b)?);
    if a == b {
        return Err(format!("--pair `{s}`: the two axes must differ; accepted: two different parameter names, e.g. g_mod,load_n"));
    }
    Ok((a, b))
}

pub(crate) fn run(args: &AnalyzeArgs) -> CliResult {
    run_with(args, true)
}

/// Runs the analysis; prints the summary when `verbose`.
pub(crate) fn run_with(args: &AnalyzeArgs, verbose: bool) -> CliResult {
    for (flag, v, lo, hi) in [
        ("--bins", args.bins as u64, 2, 200),
        ("--map-bins", args.map_bins as u64, 2, 200),
        ("--min-count", args.min_count, 1, 1_000_000_000),
        ("--bootstrap", args.bootstrap as u64, 10, 100_000),
    ] {
        if !(lo..=hi).contains(&v) {
            return Err(CliError(format!(
                "{flag} = {v} is outside its accepted range [{lo}, {hi}]"
            )));
        }
    }
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| default_report_dir(&args.inputs[0]));
    let mut pairs = AnalysisOptions::default_pairs();
    for p in &args.pair {
        if !pairs.contains(p) {
            pairs.push(*p);
        }
    }
    let opts = AnalysisOptions {
        bins: args.bins,
        map_bins: args.map_bins,
        min_count: args.min_count,
        pairs,
        bootstrap: args.bootstrap,
        scenario_within_km: args.scenario_within_km,
        within_km: args.within_km.0.clone(),
    };
    let render = RenderOptions {
        out_dir,
        figure_format: args.format,
    };
    report(
        &args.inputs,
        &opts,
        &render,
        verbose,
        "choose another folder with --out",
    )
}

/// An analysis error in the words of the command line.
pub(crate) fn analysis_error(e: AnalysisError) -> CliError {
    match e {
        AnalysisError::NoRows { inputs } => CliError(format!(
            "{inputs} hold no rows: every directory is an explore output without chunk files (empty shards or a run stopped before its first chunk; `polywear explore --resume --out DIR` continues one)"
        )),
        e => CliError(e.to_string()),
    }
}

/// The analysis for the command line ([`write_report`]: the inputs checked before any work,
/// the analysis, the report), then its words ([`report_words`]). A report that cannot be
/// written ends with `elsewhere`, how to write it elsewhere.
pub(crate) fn report(
    inputs: &[PathBuf],
    opts: &AnalysisOptions,
    render: &RenderOptions,
    verbose: bool,
    elsewhere: &str,
) -> CliResult {
    let written = write_report(inputs, opts, render, &mut |_| release_freed_memory())
        .map_err(|e| report_error(e, elsewhere))?;
    report_words(&written, verbose)
}

/// A report that was not written, in the words of the command line; `elsewhere` says how to
/// write it elsewhere when its folder is the trouble.
pub(crate) fn report_error(e: ReportError, elsewhere: &str) -> CliError {
    match e {
        ReportError::Analysis(e) => analysis_error(e),
        e @ ReportError::Write(_) => CliError(format!("{e}; {elsewhere}")),
        e => CliError(e.to_string()),
    }
}

/// A written report's end: a failure where no row has a verdict, else the summary, printed
/// when `verbose` (`analyze` and `explore` print it, `explore`'s even with --quiet).
pub(crate) fn report_words(written: &RunReport, verbose: bool) -> CliResult {
    if let Some(why) = written.no_verdict() {
        return Err(CliError(why));
    }
    if verbose {
        let a = &written.analysis;
        let last = analysed_line(a, written.secs, &written.rendered.report);
        for line in summary_lines(a).into_iter().chain([last]) {
            println!("{line}");
        }
    }
    Ok(())
}

/// Hands the memory a finished query freed back to the system. glibc's malloc keeps freed
/// blocks in its per-thread arenas, so without this the resident size creeps up with every
/// query although the live data stays the same (a few MB at the peak of a 400,000-row report).
pub(crate) fn release_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only returns free heap pages to the kernel; no pointer is touched.
    unsafe {
        libc::malloc_trim(0);
    }
}
