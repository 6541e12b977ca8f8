//! `polywear cycle`: both wheels classified at every step of a drive cycle; the share of time
//! and distance in vibration, the longest stretch, the polygon orders, and a picture.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;

use super::batch::Progress;
use super::common::{BudgetArgs, CliError, CliResult, VariantArg};
use crate::wear_reading::WearReadingArgs;
use polywear_analysis::figures::cycle::CycleRun;
use polywear_analysis::figures::FilesError;
use polywear_analysis::render::cycle::summary_lines;
use polywear_study::calibration_band::CalibrationBand;
use polywear_study::cycle::request::{CycleInput, CycleRequest};

/// Most tire structures `--structure-samples` accepts.
const STRUCTURE_SAMPLES_MAX: u64 = 100_000;

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the WLTC at 0.3 deg toe-in: share of time and distance in vibration per wheel\n",
    "  polywear cycle data/cycles/wltc_class3b.csv --set toe_deg=0.3 --out data/wltc\n",
    "  # the highway cycle over 100 tire structures of a study: means and 90% intervals\n",
    "  polywear cycle data/cycles/hwfet.csv --study studies/default.toml --structure-samples 100 \\\n",
    "      --out data/hwfet\n",
    "\nGuide: docs/book/src/reference/cycle.md#drive-cycles-polywear-cycle"
))]
pub(crate) struct CycleArgs {
    /// Drive cycle (CSV or Parquet): `time_s` (increasing) and `speed_kmh` (0 = standstill),
    /// optionally a column per step for any parameter of `polywear params` (toe_deg, load_n,
    /// pressure_kpa, ...). Standard cycles: data/cycles/. At most 1,000,000 steps (steps x
    /// --structure-samples, for a distribution): every step's records stay in memory until the
    /// files are written: about 3 KB a step, 7 KB with the wear stage
    #[arg(value_name = "CYCLE.csv")]
    pub(crate) cycle: PathBuf,
    /// Output directory: cycle.parquet, cycle_summary.csv (+ .parquet), cycle.png
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// Friction variant: sliding_share (default), paper or combined (see `simulate --help`)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub(crate) variant: VariantArg,
    /// Any model parameter for the whole cycle, e.g. `--set toe_deg=0.3` (repeatable); one the
    /// cycle file gives per step is refused. The toe-in may also be given in mm at the rim
    /// (`--set toe_mm=2`, across rim_diameter_mm) or as total toe (`--set toe_total_deg=0.6`)
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = super::common::parse_assignment)]
    pub(crate) set: Vec<(String, f64)>,
    /// Which axle the engine drives: `fwd` (default; the follower is a rear wheel) or `rwd`.
    /// Each wheel reads its own axle's toe-in, load and pressure (`--set toe_rear_deg=0.4`)
    #[arg(long, value_name = "fwd|rwd", value_parser = super::common::drivetrains())]
    pub(crate) drivetrain: Option<polywear_core::params::axle::Drivetrain>,
    /// Parameter file (TOML `[params]`, e.g. from `polywear calibrate`), applied first; a
    /// parameter the cycle file or --study also sets is refused
    #[arg(long, value_name = "FILE")]
    pub(crate) params: Option<PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a cycle column,
    /// --set, --params or --study value such as pressure_kpa = 2.4 (bar, not kPa) is refused
    /// before any work without it
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// Study whose drawn tire-structure, friction and vehicle parameters give the tire
    /// structures; with [operating_points] each structure sample also draws a row of the
    /// fleet, whose load, pressure and toe-in hold for the whole cycle (the cycle gives the
    /// speed). Its drawn speed, toe, load and pressure distributions are not used (said before
    /// the results); needs --structure-samples
    #[arg(long, value_name = "STUDY.toml", requires = "structure_samples")]
    pub(crate) study: Option<PathBuf>,
    /// Tire structures drawn from --study (samples 0..K of its design and seed): every share
    /// becomes a distribution, reported as mean and 90% interval. Accepted [2, 100000], and at
    /// most 1,000,000 steps in all (555 structures over the WLTC's 1,801 steps)
    #[arg(long, value_name = "K", requires = "study", allow_negative_numbers = true,
          value_parser = super::common::whole_in::<u64>("--structure-samples", 2, STRUCTURE_SAMPLES_MAX))]
    pub(crate) structure_samples: Option<u64>,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
    /// No progress bar or progress lines, no notes and no list of the files written; the
    /// answer (the summary per wheel) is still printed, as ripgrep's and cargo's -q silence
    /// progress, not the result
    #[arg(long, short)]
    pub(crate) quiet: bool,
    /// Leave the wear stage out: no distance to a visible polygon, no wear columns
    #[arg(long, conflicts_with_all = ["wear_zone", "wear_estimate"])]
    pub(crate) no_wear: bool,
    /// The calibration band of the distance to a visible polygon: a file of calibrated sets of
    /// the fitted wear constants (as data/calibration_band.toml, the default), or `off`. Each
    /// set's phi_s and k_d give the distance again in closed form (sigma_V does not enter: the
    /// cycle's speeds are its spread; the carcass and belt shares stay the run's, the steps'
    /// profiles being laid out at them), and its range is printed beside it
    #[arg(long, value_name = "FILE|off", conflicts_with = "no_wear")]
    pub(crate) calibration_band: Option<String>,
    #[command(flatten)]
    pub(crate) wear: WearReadingArgs,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
}

pub(crate) fn run(args: &CycleArgs) -> CliResult {
    if args.out.is_file() {
        return Err(CliError(format!(
            "--out {}: is a file; give a directory",
            args.out.display()
        )));
    }
    let input = CycleInput {
        cycle: &args.cycle,
        variant: args.variant.into(),
        set: &args.set,
        params: args.params.as_deref(),
        accept_implausible: args.accept_implausible,
        study: args.study.as_deref().zip(args.structure_samples),
        drivetrain: args.drivetrain,
    };
    let budget = |b| args.budget.apply(b);
    let request = CycleRequest::new(&input, &budget, &|note| eprintln!("{note}"))?;
    if !args.quiet {
        for l in &request.structures.said {
            println!("{l}");
        }
    }
    // The band's file is read before any work; without the wear stage there is none.
    let band = CalibrationBand::asked(args.calibration_band.as_deref())?;
    let plan = request.prepare((!args.no_wear).then(|| args.wear.settings()), band)?;
    let pool = super::common::thread_pool(args.threads)?;
    let progress = Progress::new(
        args.quiet,
        plan.steps_to_do(),
        "steps",
        Duration::from_secs(10),
    );
    let start = Instant::now();
    let classified = pool.install(|| plan.classify(&|n| progress.add(n)));
    progress.finish();
    let secs = start.elapsed().as_secs_f64();
    let run = CycleRun::new(&plan, classified);
    let summaries = run.summaries();
    let written = run.write(&args.out, &summaries).map_err(|e| match e {
        FilesError::CreateDir { .. } => CliError(format!("--out {e}")),
        e => CliError(e.to_string()),
    })?;
    for line in summary_lines(&run, &summaries, secs, pool.current_num_threads()) {
        println!("{line}");
    }
    if !args.quiet {
        for p in written {
            println!("  wrote {}", p.display());
        }
    }
    Ok(())
}
