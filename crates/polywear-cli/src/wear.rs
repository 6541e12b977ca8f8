//! `polywear wear`: the long-term wear loop (MODEL.md#the-long-term-loop) for one operating
//! point, both wheels in parallel: the summary, the history of every order, the profile at a
//! few distances, a figure and the verdict in words.

use std::path::{Path, PathBuf};

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::common::{base_metadata, BudgetArgs, CliError, CliResult, PointArgs};
use crate::wear_reading::WearReadingArgs;
use polywear_analysis::figures::wear::LongTermFiles;
use polywear_analysis::figures::FilesError;
use polywear_analysis::plot::FigureFormat;
use polywear_core::classify::ClassifierOptions;
use polywear_core::long_term::wheel_loop::{
    cruise_legs, Leg, LoopSettings, FIRST_STEP_REVS, MAX_FIRST_STEP_TREAD_S, SPEED_NODES,
};
use polywear_core::long_term::{self, LongTermError, LongTermProblem};
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params};
use polywear_core::wear::FittedConstants;
use polywear_core::wording::plain;
use polywear_study::calibration_band::{self, long_term::LoopSets, CalibrationBand};
use polywear_study::cycle::DriveCycle;

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
pub struct WearArgs {
    #[command(flatten)]
    pub point: PointArgs,
    /// Distance to run [km], accepted (0, 1e6]
    #[arg(
        long,
        value_name = "KM",
        default_value_t = 60_000.0,
        allow_negative_numbers = true
    )]
    pub distance_km: f64,
    /// Normal spread of the cruising speed [km/h], accepted [0, 100] (replaces the parameter
    /// speed_spread_kmh; give one of the two)
    #[arg(long, value_name = "KMH", allow_negative_numbers = true)]
    pub speed_spread_kmh: Option<f64>,
    /// Speeds driven, equal shares of the distance, each with its own tread state: the spread's
    /// quantiles, or the cycle's distance-weighted ones; accepted [1, 64]. The distance to a
    /// visible polygon settles with 5 on a cruising spread (within 15% of 40 at the reference
    /// point) and on HWFET, but a cycle of widely spread speeds needs about 40 (WLTC: 12,700 km
    /// on 5, 23,400 on 64); more cost that many times the time
    #[arg(long, value_name = "K", default_value_t = SPEED_NODES, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--speed-nodes", 1, MAX_SPEED_NODES as u64))]
    pub speed_nodes: usize,
    #[command(flatten)]
    pub wear: WearReadingArgs,
    /// Most RHS evaluations one wheel's long-term loop may spend over all its windows and
    /// speeds (a run over it fails that wheel with `budget exceeded`); accepted [1e6, 1e12],
    /// default 1e9 (30 times what the default point's 60,000 km take) per 5 speed nodes: 8e9
    /// on 40. A vibrating point over a long distance may need more
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub loop_max_rhs_evals: Option<f64>,
    /// Drive this cycle (CSV or Parquet: time_s, speed_kmh, as `polywear cycle` reads it) again
    /// and again instead of cruising at --speed
    #[arg(long, value_name = "CYCLE")]
    pub cycle: Option<PathBuf>,
    /// Seed of the new tyre's run-out phases, accepted [0, 4398046510080]
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, polywear_study::study::SEED_MAX))]
    pub seed: u64,
    /// The calibration band: a file of calibrated sets of the fitted wear constants (as
    /// data/calibration_band.toml, the default), or `off`. The loop is run again under the sets
    /// --band-sets chooses, and each wheel's verdict is printed with the band's two ends
    #[arg(long, value_name = "FILE|off")]
    pub calibration_band: Option<String>,
    /// Which calibrated sets the loop runs under: `ends` (for each wheel, the sets with the
    /// shortest and the longest distance by the per-sample wear answer at this point: a few
    /// runs) or `all` (every set: as many runs as the band has sets)
    #[arg(long, value_name = "ends|all", default_value = "ends", value_parser = parse_band_sets)]
    pub band_sets: LoopSets,
    /// Also print the per-sample wear answer at this point (explore's, over the tread's life
    /// with each speed's print saturated) beside the loop's verdict, and for a cruise the same
    /// answer on the loop's own speeds, and add `estimate_*` columns
    #[arg(long)]
    pub estimate: bool,
    /// Format of the figure
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub format: FigureFormat,
    /// No progress bar
    #[arg(long)]
    pub quiet: bool,
    #[command(flatten)]
    pub budget: BudgetArgs,
    /// Output folder (created if missing, checked before any work) for the summary, history and
    /// profile tables and the figure; without it only the verdict is printed
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
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

/// The checked inputs of a run.
struct Plan {
    problem: LongTermProblem,
    usage: String,
    metadata: Vec<(String, String)>,
    /// The calibrated sets and where they come from (None: off).
    band: Option<(CalibrationBand, String)>,
    /// The legs of the point's constants replaced by a set's: a cruise's follow its spread.
    cruise: Option<(f64, usize)>,
}

/// Checks every input before any work, exit 2 with the flag and the accepted range.
fn plan(args: &WearArgs) -> CliResult<Plan> {
    let resolved = args.point.resolve()?;
    let mut p = resolved.params;
    long_term::check_distance_km(args.distance_km).map_err(refusal)?;
    let reading = args.wear.settings();
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
    let nodes = args.speed_nodes;
    let loop_budget = match args.loop_max_rhs_evals {
        None => LoopSettings::default_max_rhs_evals_for(nodes),
        Some(n) => super::common::whole_count("--loop-max-rhs-evals", n, LOOP_RHS_EVALS_RANGE)?,
    };
    let band = super::common::calibration_band(args.calibration_band.as_deref())?;
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
    let variant: Variant = args.point.variant.into();
    let mut metadata = base_metadata(&p, variant);
    let (legs, usage) = match &args.cycle {
        Some(path) => {
            let (legs, usage) = read_cycle(path, &p, nodes, args.point.accept_implausible)?;
            metadata.push(("cycle".into(), path.display().to_string()));
            (legs, usage)
        }
        None => (
            cruise_legs(p.speed_kmh, p.speed_spread_kmh, nodes),
            format!(
                "cruising at {} km/h, speed spread {} km/h{}",
                plain(p.speed_kmh, 6),
                plain(p.speed_spread_kmh, 6),
                match (p.speed_spread_kmh > 0.0, nodes) {
                    (false, _) => String::new(),
                    (true, 1) => ", driven at the mean speed only".into(),
                    (true, k) => format!(", driven at {k} of its speeds"),
                }
            ),
        ),
    };
    let settings = LoopSettings {
        distance_km: args.distance_km,
        seed: args.seed,
        zone: reading.zone,
        power: reading.power,
        max_rhs_evals: loop_budget,
        ..LoopSettings::default()
    };
    metadata.push(("wear_zone".into(), reading.zone.as_str().into()));
    metadata.push(("wear_power".into(), reading.power.as_str().into()));
    metadata.push((
        "wear_loop".into(),
        serde_json::to_string(&settings).expect("plain data"),
    ));
    metadata.push((
        "legs".into(),
        serde_json::to_string(&legs).expect("plain data"),
    ));
    metadata.push(("usage".into(), usage.clone()));
    metadata.push((
        "calibration_band".into(),
        match &band {
            Some((b, source)) => format!(
                "{source}: {} sets; the loop run again under --band-sets {}",
                b.sets.len(),
                args.band_sets.as_str()
            ),
            None => "off".into(),
        },
    ));
    let classifier = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let problem = LongTermProblem::new(p, variant, legs, settings, classifier).map_err(|e| {
        match (e, &args.cycle) {
            (e @ LongTermError::TooSlow { .. }, Some(path)) => {
                CliError(format!("--cycle {}: {e}", path.display()))
            }
            (
                LongTermError::TooSlow {
                    tread_s,
                    min_kmh,
                    legs: 1,
                    ..
                },
                None,
            ) => CliError(format!(
                "--speed = {} km/h is too slow for the wear loop: its first step integrates {FIRST_STEP_REVS} revolutions at each speed driven, {tread_s:.3e} s of tread time, over the {MAX_FIRST_STEP_TREAD_S} s it accepts; accepted: speed_kmh of at least {} km/h without a speed spread",
                plain(p.speed_kmh, 6),
                plain(min_kmh, 3)
            )),
            (e @ LongTermError::TooSlow { .. }, None) => CliError(format!(
                "--speed-spread-kmh = {} at --speed {} km/h: {e}; give a higher speed, a narrower spread or fewer --speed-nodes",
                plain(p.speed_spread_kmh, 6),
                plain(p.speed_kmh, 6)
            )),
            (e, _) => refusal(e),
        }
    })?;
    let plan = Plan {
        problem,
        usage,
        metadata,
        band,
        cruise: args.cycle.is_none().then_some((p.speed_kmh, nodes)),
    };
    // Every set's run is checked as the run's own is, before any work: a set's wider spread can
    // drive a leg the point's own does not.
    if let Some((band, source)) = &plan.band {
        for set in &band.sets {
            let q = set.constants().applied_to(&plan.problem.params);
            LongTermProblem::new(
                q,
                variant,
                plan.legs_for(&q),
                plan.problem.settings.clone(),
                classifier,
            )
            .map_err(|e| {
                CliError(format!(
                    "--calibration-band {source}: set `{}` (speed_spread_kmh = {}): {e}; give --calibration-band off, or a point every set can run",
                    set.id,
                    plain(set.speed_spread_kmh, 6)
                ))
            })?;
        }
    }
    Ok(plan)
}

impl Plan {
    /// The legs of the point with its fitted constants replaced by `q`'s: a cruise's follow
    /// `q`'s speed spread; a cycle's are the cycle's.
    fn legs_for(&self, q: &Params) -> Vec<Leg> {
        match self.cruise {
            Some((speed, nodes)) => cruise_legs(speed, q.speed_spread_kmh, nodes),
            None => self.problem.legs.clone(),
        }
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

/// The cycle's speeds as legs of equal distance, refused as `polywear cycle` refuses it.
fn read_cycle(
    path: &Path,
    p: &Params,
    nodes: usize,
    accept_implausible: bool,
) -> CliResult<(Vec<Leg>, String)> {
    let cycle = DriveCycle::read(path).map_err(|e| CliError(e.to_string()))?;
    if !accept_implausible {
        cycle
            .check_plausible()
            .map_err(|e| CliError(e.to_string()))?;
    }
    cycle.check_steps(p).map_err(|e| CliError(e.to_string()))?;
    if !cycle.names.is_empty() {
        let names: Vec<&str> = cycle.names.iter().map(|id| id.name()).collect();
        eprintln!(
            "note: {}: its columns {} are not used by `wear`, which drives the point's own toe, load and pressure at the cycle's speeds",
            path.display(),
            names.join(", ")
        );
    }
    let (legs, km) = cycle.wear_legs(nodes);
    if legs.is_empty() {
        return Err(CliError(format!(
            "--cycle {}: covers no distance (every step at standstill)",
            path.display()
        )));
    }
    if nodes < SETTLED_CYCLE_NODES {
        eprintln!(
            "note: --speed-nodes {nodes}: on a cycle of widely spread speeds the loop's distance settles only from about {SETTLED_CYCLE_NODES} speeds (WLTC: 12,700 km on 5, 22,700 on 40, 23,400 on 64; HWFET settles on 5); --speed-nodes {SETTLED_CYCLE_NODES} takes about 8 times the time (HWFET: 23 s on 5, 174 s on 40)"
        );
    }
    let usage = format!(
        "driving the cycle {} ({km:.2} km) again and again, at {} of its speeds",
        path.display(),
        legs.len()
    );
    Ok((legs, usage))
}

/// The speed nodes from which the loop's distance on a widely spread cycle has settled
/// (MODEL.md#along-a-drive-cycle: WLTC within 3% and 7% of 64 nodes on 40).
const SETTLED_CYCLE_NODES: usize = 40;

/// The accepted range of `--loop-max-rhs-evals`.
const LOOP_RHS_EVALS_RANGE: (u64, u64) = (1_000_000, 1_000_000_000_000);

pub fn run(args: &WearArgs) -> CliResult {
    let plan = plan(args)?;
    if let Some(out) = &args.out {
        LongTermFiles::prepare(out).map_err(|e| CliError(format!("--out {e}")))?;
    }
    let bar = progress_bar(args.quiet, 2.0 * plan.problem.settings.distance_km);
    let started = std::time::Instant::now();
    let solution = long_term::solve(&plan.problem, &|km| bar.inc(km.round() as u64))
        .map_err(|e| CliError(e.to_string()))?;
    let band_runs = match &plan.band {
        Some((band, _)) => {
            let sets =
                calibration_band::long_term::chosen(band, args.band_sets, &plan.problem, &solution)
                    .map_err(|e| CliError(e.to_string()))?;
            bar.inc_length((2.0 * plan.problem.settings.distance_km) as u64 * sets.len() as u64);
            let legs = |q: &Params| plan.legs_for(q);
            let runs = calibration_band::long_term::run(band, &sets, &plan.problem, &legs, &|km| {
                bar.inc(km.round() as u64)
            })
            .map_err(|e| CliError(format!("the calibration band's runs: {e}")))?;
            Some(runs)
        }
        None => None,
    };
    bar.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    if let Some(out) = &args.out {
        LongTermFiles {
            solution: &solution,
            metadata: &plan.metadata,
            estimate: args.estimate,
            format: args.format,
            title: format!("polywear wear: {}", plan.usage),
        }
        .write(out)
        .map_err(|e| match e {
            FilesError::CreateDir { .. } => CliError(format!("--out {e}")),
            e => CliError(e.to_string()),
        })?;
        match (&plan.band, &band_runs) {
            (Some((band, _)), Some(runs)) => polywear_analysis::figures::wear::write_band(
                out,
                &plan.metadata,
                band,
                runs,
                plan.problem.settings.distance_km,
            )
            .map_err(|e| CliError(e.to_string()))?,
            // No band of an earlier run beside this run's files.
            _ => polywear_analysis::figures::wear::remove_band(out)
                .map_err(|e| CliError(e.to_string()))?,
        }
    }
    let head = polywear_analysis::render::long_term::Header {
        usage: &plan.usage,
        secs,
    };
    for line in
        polywear_analysis::render::long_term::lines(&plan.problem, &solution, &head, args.estimate)
    {
        println!("{line}");
    }
    match (&plan.band, &band_runs) {
        (Some((band, source)), Some(runs)) => {
            let named: Vec<(&str, &polywear_core::long_term::LongTermSolution)> = runs
                .iter()
                .map(|r| (band.sets[r.set].id.as_str(), &r.solution))
                .collect();
            let chosen = match args.band_sets {
                LoopSets::Ends => format!(
                    "{source}: for each wheel the sets with the shortest and the longest per-sample wear answer here; the loop's own ends may lie at other sets, which --band-sets all checks"
                ),
                LoopSets::All => format!("{source}: every set"),
            };
            for line in polywear_analysis::render::long_term::band_lines(
                &plan.problem,
                &named,
                band.sets.len(),
                &chosen,
            ) {
                println!("{line}");
            }
        }
        _ => println!(
            "calibration band: off (--calibration-band off): the verdict is the run's own constants' alone"
        ),
    }
    Ok(())
}

fn progress_bar(quiet: bool, total_km: f64) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(total_km as u64), ProgressDrawTarget::stderr())
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} km (both wheels)  {rate}  ETA {eta}",
        )
        .expect("valid template")
        .with_key(
            "rate",
            |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.0} km/s", s.per_sec());
            },
        ),
    );
    bar
}
