//! `polywear wear`: the long-term wear loop (MODEL.md#the-long-term-loop) for one operating
//! point, both wheels in parallel: the summary, the history of every order, the profile at a
//! few distances, a figure and the verdict in words.

use std::path::PathBuf;

use clap::Args;

use super::batch::styled_bar;
use super::common::{BudgetArgs, CliError, CliResult, PointArgs};
use crate::wear_reading::WearReadingArgs;
use polywear_analysis::figures::wear::{plan_band_files, LongTermFiles};
use polywear_analysis::figures::FilesError;
use polywear_analysis::plot::FigureFormat;
use polywear_analysis::render::long_term::{lines as verdict_lines, plan_band_lines, Header};
use polywear_core::classify::ClassifierOptions;
use polywear_core::long_term::wheel_loop::{
    LoopSettings, FIRST_STEP_REVS, MAX_FIRST_STEP_TREAD_S, SPEED_NODES,
};
use polywear_core::long_term::{self, LongTermError};
use polywear_core::params::{ParamId, Params};
use polywear_core::wear::FittedConstants;
use polywear_core::wording::plain;
use polywear_study::calibration_band::{long_term::LoopSets, CalibrationBand};
use polywear_study::long_term_request::{
    LongTermPlan, LongTermRequest, LongTermRequestError, LongTermRun,
};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the default point, both wheels, 60,000 km with the shipped speed spread\n",
    "  polywear wear --out data/wear\n",
    "  # the worst case: every straight-running joule couples, a steady speed\n",
    "  polywear wear --set wear_share_straight=1 --speed-spread-kmh 0 --estimate --calibration-band off --out data/wear\n",
    "  # a drive cycle driven again and again\n",
    "  polywear wear --cycle data/cycles/hwfet.csv --out data/wear_cycle\n",
    "\nGuide: docs/book/src/reference/wear.md#wear"
))]
pub(crate) struct WearArgs {
    #[command(flatten)]
    pub(crate) point: PointArgs,
    /// Distance to run [km], accepted (0, 1e6]
    #[arg(
        long,
        value_name = "KM",
        default_value_t = 60_000.0,
        allow_negative_numbers = true
    )]
    pub(crate) distance_km: f64,
    /// Normal spread of the cruising speed [km/h], accepted [0, 100] (replaces the parameter
    /// speed_spread_kmh; give one of the two)
    #[arg(long, value_name = "KMH", allow_negative_numbers = true)]
    pub(crate) speed_spread_kmh: Option<f64>,
    /// Speeds driven, equal shares of the distance, each with its own tread state: the spread's
    /// quantiles, or the cycle's distance-weighted ones; accepted [1, 64]. The distance to a
    /// visible polygon settles with 5 on a cruising spread (within 15% of 40 at the reference
    /// point) and on HWFET, but a cycle of widely spread speeds needs about 40 (WLTC: 12,700 km
    /// on 5, 23,400 on 64); more cost that many times the time
    #[arg(long, value_name = "K", default_value_t = SPEED_NODES, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--speed-nodes", 1, MAX_SPEED_NODES as u64))]
    pub(crate) speed_nodes: usize,
    #[command(flatten)]
    pub(crate) wear: WearReadingArgs,
    /// Most RHS evaluations one wheel's long-term loop may spend over all its windows and
    /// speeds (a run over it fails that wheel with `budget exceeded`); accepted [1e6, 1e12],
    /// default 1e9 (30 times what the default point's 60,000 km take) per 5 speed nodes: 8e9
    /// on 40. A vibrating point over a long distance may need more
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub(crate) loop_max_rhs_evals: Option<f64>,
    /// Drive this cycle (CSV or Parquet: time_s, speed_kmh, as `polywear cycle` reads it) again
    /// and again instead of cruising at --speed
    #[arg(long, value_name = "CYCLE")]
    pub(crate) cycle: Option<PathBuf>,
    /// Seed of the new tyre's run-out phases, accepted [0, 4398046510080]
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, polywear_study::study::SEED_MAX))]
    pub(crate) seed: u64,
    /// The calibration band: a file of calibrated sets of the fitted wear constants (as
    /// data/calibration_band.toml, the default), or `off`. The loop is run again under the sets
    /// --band-sets chooses, and each wheel's verdict is printed with the band's two ends
    #[arg(long, value_name = "FILE|off")]
    pub(crate) calibration_band: Option<String>,
    /// Which calibrated sets the loop runs under: `ends` (for each wheel, the sets with the
    /// shortest and the longest distance by the per-sample wear answer at this point: a few
    /// runs) or `all` (every set: as many runs as the band has sets)
    #[arg(long, value_name = "ends|all", default_value = "ends", value_parser = parse_band_sets)]
    pub(crate) band_sets: LoopSets,
    /// Also print the per-sample wear answer at this point (explore's, over the tread's life
    /// with each speed's print saturated) beside the loop's verdict, and for a cruise the same
    /// answer on the loop's own speeds, and add `estimate_*` columns
    #[arg(long)]
    pub(crate) estimate: bool,
    /// Format of the figure
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub(crate) format: FigureFormat,
    /// No progress bar
    #[arg(long)]
    pub(crate) quiet: bool,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
    /// Output folder (created if missing, checked before any work) for the summary, history and
    /// profile tables and the figure; without it only the verdict is printed
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
}

fn parse_band_sets(s: &str) -> Result<LoopSets, String> {
    match s {
        "ends" => Ok(LoopSets::Ends),
        "all" => Ok(LoopSets::All),
        other => Err(format!(
            "--band-sets `{other}`: accepted: ends (the estimator's band ends at this point), all (every set)"
        )),
    }
}

/// Most speeds `--speed-nodes` accepts.
const MAX_SPEED_NODES: usize = 64;

/// Checks every input before any work, exit 2 with the flag and the accepted range: the flags
/// into a [`LongTermRequest`], its refusals into the flags' words.
fn plan(args: &WearArgs) -> CliResult<LongTermPlan> {
    let resolved = args.point.resolve()?;
    let mut p = resolved.params;
    long_term::check_distance_km(args.distance_km).map_err(refusal)?;
    // The cycle gives the speeds driven: a speed given as well would be dropped unseen.
    if let (Some(_), Some(by)) = (&args.cycle, resolved.given_by(ParamId::SpeedKmh)) {
        return Err(CliError(format!(
            "{by}: the cycle gives the speeds driven (its `speed_kmh` column); leave the speed out with --cycle"
        )));
    }
    if let Some(s) = args.speed_spread_kmh {
        if let Some(by) = resolved.given_by(ParamId::SpeedSpreadKmh) {
            return Err(CliError(format!(
                "--speed-spread-kmh and {by} both set the speed spread; give one"
            )));
        }
        if args.cycle.is_some() {
            return Err(CliError(
                "--speed-spread-kmh and --cycle both set the speeds driven; give one".into(),
            ));
        }
        p.try_set(ParamId::SpeedSpreadKmh, s)
            .map_err(|e| CliError(format!("--speed-spread-kmh: {e}")))?;
    }
    if let Some(out) = args.out.as_ref().filter(|o| o.is_file()) {
        return Err(CliError(format!(
            "--out {}: is a file; give a directory",
            out.display()
        )));
    }
    let max_rhs_evals = match args.loop_max_rhs_evals {
        None => LoopSettings::default_max_rhs_evals_for(args.speed_nodes),
        Some(n) => super::common::whole_count("--loop-max-rhs-evals", n, LOOP_RHS_EVALS_RANGE)?,
    };
    let band = CalibrationBand::asked(args.calibration_band.as_deref())?;
    // A set replaces the point's fitted constants: a value given for one of them is the run's,
    // not the band's, and the band says so.
    let given: Vec<String> = FittedConstants::PARAMS
        .iter()
        .filter_map(|&id| resolved.given_by(id).map(|by| format!("{id} ({by})")))
        .chain(
            args.speed_spread_kmh
                .map(|_| "speed_spread_kmh (--speed-spread-kmh)".to_string()),
        )
        .collect();
    if band.is_some() && !given.is_empty() && !args.quiet {
        eprintln!(
            "note: the calibration band's runs replace {} with each set's; the verdict above them is yours (--calibration-band off runs yours alone)",
            given.join(", ")
        );
    }
    let request = LongTermRequest {
        params: p,
        variant: args.point.variant.into(),
        cycle: args.cycle.clone(),
        accept_implausible: args.point.accept_implausible,
        speed_nodes: args.speed_nodes,
        distance_km: args.distance_km,
        seed: args.seed,
        reading: args.wear.settings(),
        max_rhs_evals,
        band,
        band_sets: args.band_sets,
        classifier: ClassifierOptions {
            budget: args.budget.apply(Default::default())?,
            ..ClassifierOptions::default()
        },
    };
    let plan = request.plan().map_err(|e| request_refusal(e, args, &p))?;
    for note in &plan.notes {
        eprintln!("note: {note}");
    }
    Ok(plan)
}

/// A refused request in the words of the command line.
fn request_refusal(e: LongTermRequestError, args: &WearArgs, p: &Params) -> CliError {
    match (e, &args.cycle) {
        (LongTermRequestError::Problem(e @ LongTermError::TooSlow { .. }), Some(path)) => {
            CliError(format!("--cycle {}: {e}", path.display()))
        }
        (
            LongTermRequestError::Problem(LongTermError::TooSlow {
                tread_s,
                min_kmh,
                legs: 1,
                ..
            }),
            None,
        ) => CliError(format!(
            "--speed = {} km/h is too slow for the wear loop: its first step integrates {FIRST_STEP_REVS} revolutions at each speed driven, {tread_s:.3e} s of tread time, over the {MAX_FIRST_STEP_TREAD_S} s it accepts; accepted: speed_kmh of at least {} km/h without a speed spread",
            plain(p.speed_kmh, 6),
            plain(min_kmh, 3)
        )),
        (LongTermRequestError::Problem(e @ LongTermError::TooSlow { .. }), None) => {
            CliError(format!(
                "--speed-spread-kmh = {} at --speed {} km/h: {e}; give a higher speed, a narrower spread or fewer --speed-nodes",
                plain(p.speed_spread_kmh, 6),
                plain(p.speed_kmh, 6)
            ))
        }
        (LongTermRequestError::Problem(e), _) => refusal(e),
        (e @ LongTermRequestError::CycleWithoutDistance { .. }, _) => {
            CliError(format!("--cycle {e}"))
        }
        (e @ LongTermRequestError::BandSet { .. }, _) => CliError(format!(
            "--calibration-band {e}; give --calibration-band off, or a point every set can run"
        )),
        (e, _) => CliError(e.to_string()),
    }
}

/// A refused problem in the words of the command line: the distance as `--distance-km`.
fn refusal(e: LongTermError) -> CliError {
    match e {
        LongTermError::Distance(km) => CliError(format!(
            "--distance-km = {} is outside its accepted range (0, 1e6] km",
            plain(km, 12)
        )),
        LongTermError::LegSpeed { speed_kmh, range } => CliError(format!(
            "the speed spread drives a leg at {} km/h, outside the accepted range of the speed {range} km/h: give a narrower --speed-spread-kmh (or speed_spread_kmh), or fewer --speed-nodes",
            plain(speed_kmh, 6)
        )),
        e => CliError(e.to_string()),
    }
}

/// The accepted range of `--loop-max-rhs-evals`.
const LOOP_RHS_EVALS_RANGE: (u64, u64) = (1_000_000, 1_000_000_000_000);

pub(crate) fn run(args: &WearArgs) -> CliResult {
    let plan = plan(args)?;
    if let Some(out) = &args.out {
        LongTermFiles::prepare(out).map_err(|e| CliError(format!("--out {e}")))?;
    }
    let run_km = 2.0 * plan.problem.settings.distance_km;
    let bar = styled_bar(args.quiet, run_km as u64, "", "km (both wheels)", "km");
    let started = std::time::Instant::now();
    let LongTermRun {
        solution,
        band_runs,
    } = plan
        .solve(&|km| bar.inc(km.round() as u64), &|runs| {
            bar.inc_length(run_km as u64 * runs as u64)
        })
        .map_err(|e| CliError(e.to_string()))?;
    bar.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    if let Some(out) = &args.out {
        LongTermFiles::of(&plan, &solution, args.estimate, args.format)
            .write(out)
            .map_err(|e| match e {
                FilesError::CreateDir { .. } => CliError(format!("--out {e}")),
                e => CliError(e.to_string()),
            })?;
        plan_band_files(out, &plan, band_runs.as_deref()).map_err(|e| CliError(e.to_string()))?;
    }
    let head = Header {
        usage: &plan.usage,
        secs,
    };
    let lines = verdict_lines(&plan.problem, &solution, &head, args.estimate);
    for line in lines
        .into_iter()
        .chain(plan_band_lines(&plan, band_runs.as_deref()))
    {
        println!("{line}");
    }
    Ok(())
}
