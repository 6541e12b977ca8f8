//! `polywear cycle`: both wheels classified at every step of a drive cycle; the share of time
//! and distance in vibration, the longest stretch, the polygon orders, and a picture.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;

use super::batch::Progress;
use super::common::{base_metadata, BudgetArgs, CliError, CliResult, VariantArg};
use crate::wear_reading::WearReadingArgs;
use polywear_analysis::figures::cycle::{CycleRun, FleetDraw};
use polywear_analysis::figures::FilesError;
use polywear_analysis::render::cycle::summary_lines;
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::WearStage;
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params};
use polywear_core::wear::FittedConstants;
use polywear_study::cycle::structures::{draw_structures, study_metadata, CommandLine, Structures};
use polywear_study::cycle::{classify_cycles, ClassifiedCycle, DriveCycle};
use polywear_study::study::Study;

/// Most tire structures `--structure-samples` accepts.
const STRUCTURE_SAMPLES_MAX: u64 = 100_000;

/// The most memory the `tread_life_saturated` level's speed bins may take, over every structure
/// and both wheels (each bin one 66 KB profile a wheel: WLTC's 846 bins of 0.1 km/h are 112 MB
/// a structure).
const SATURATED_BINS_MAX_BYTES: u64 = 4 << 30;

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
    let mut request = resolve(args)?;
    if !args.quiet {
        for l in &request.structures.said {
            println!("{l}");
        }
    }
    // The band's file is read before any work; without the wear stage there is none.
    let band = super::common::calibration_band(args.calibration_band.as_deref())?;
    let wear = wear_stage(args, &request.base, request.variant)?;
    if wear.is_some() {
        let per_wheel = polywear_study::cycle::wear::saturated_bins_bytes(&request.cycle);
        let bases = request.structures.bases.len() as u64;
        let bytes = 2 * bases * per_wheel;
        if bytes > SATURATED_BINS_MAX_BYTES {
            let most = SATURATED_BINS_MAX_BYTES / (2 * per_wheel).max(1);
            return Err(CliError(format!(
                "--structure-samples: {bases} structures would hold {:.1} GiB of speed bins on this cycle ({:.0} MB a structure); accepted: at most {most} structures, or --no-wear",
                bytes as f64 / (1u64 << 30) as f64,
                (2 * per_wheel) as f64 / 1e6
            )));
        }
    }
    if let Some(stage) = &wear {
        let stage = serde_json::to_string(stage).expect("json");
        request.metadata.push(("wear".into(), stage));
    }
    let band_sets: Vec<FittedConstants> = match (&wear, band) {
        (Some(_), Some((band, source))) => {
            let said = format!("{} sets from {source}", band.sets.len());
            request.metadata.push(("calibration_band".into(), said));
            band.sets.iter().map(|s| s.constants()).collect()
        }
        _ => Vec::new(),
    };
    let pool = super::common::thread_pool(args.threads)?;
    let todo = request.cycle.len() as u64 * request.structures.bases.len() as u64;
    let progress = Progress::new(args.quiet, todo, "steps", Duration::from_secs(10));
    let start = Instant::now();
    let steps = pool.install(|| {
        classify_cycles(
            &request.cycle,
            &request.structures.bases,
            request.variant,
            &request.opts,
            wear.as_ref(),
            &|n| progress.add(n),
        )
    });
    progress.finish();
    let secs = start.elapsed().as_secs_f64();
    let threads = pool.current_num_threads();
    write(
        args,
        request,
        wear.is_some(),
        band_sets,
        steps,
        secs,
        threads,
    )
}

/// One `cycle`, checked: the cycle, variant, options, tire structures and outputs' metadata.
struct CycleRequest {
    cycle: DriveCycle,
    variant: Variant,
    opts: ClassifierOptions,
    /// The nominal tire (`--params` and `--set`), on which the wear stage is calibrated.
    base: Params,
    structures: Structures,
    study: Option<Study>,
    metadata: Vec<(String, String)>,
}

/// Every input checked before any work: `--out`, the cycle, `--set`, the study, each step.
fn resolve(args: &CycleArgs) -> CliResult<CycleRequest> {
    if args.out.is_file() {
        return Err(CliError(format!(
            "--out {}: is a file; give a directory",
            args.out.display()
        )));
    }
    let mut opts = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let variant: Variant = args.variant.into();
    let cycle = DriveCycle::read(&args.cycle).map_err(|e| CliError(e.to_string()))?;
    cycle
        .check_work(args.structure_samples.unwrap_or(1))
        .map_err(|e| CliError(e.to_string()))?;
    if !args.accept_implausible {
        cycle
            .check_plausible()
            .map_err(|e| CliError(e.to_string()))?;
    }
    let rim = polywear_study::toe_input::rim_diameter_mm(
        args.params.as_deref(),
        &args.set,
        args.accept_implausible,
    )?;
    let (set, toe_notes) =
        polywear_study::toe_input::set_as_angles(&args.set, rim, args.accept_implausible)?;
    for note in toe_notes {
        eprintln!("{note}");
    }
    let (line, notes) = CommandLine::read(
        args.params.as_deref(),
        &set,
        args.accept_implausible,
        &cycle,
    )?;
    for note in notes {
        eprintln!("{note}");
    }
    let mut base = line.file;
    for t in &line.set {
        if t.id == ParamId::SpeedSpreadKmh {
            return Err(CliError(format!(
                "--set {}: {}; leave it out",
                t.id,
                polywear_study::cycle::NO_SPREAD
            )));
        }
        base.try_set(t.id, t.value)?;
    }
    let mut metadata = base_metadata(&base, variant);
    metadata.push(("cycle".into(), args.cycle.display().to_string()));
    metadata.push(("cycle_hash".into(), cycle.hash.clone()));
    let (structures, study) = match (&args.study, args.structure_samples) {
        (Some(path), Some(k)) => {
            let (s, study, notes) = draw_structures(&line, path, k, &cycle)?;
            for note in notes {
                eprintln!("{note}");
            }
            // The study's work limits, unless the flags say otherwise.
            opts.budget = args.budget.apply(study.budget)?;
            metadata.extend(study_metadata(&study, k, &s.names));
            (s, Some(study))
        }
        _ => (
            Structures {
                names: Vec::new(),
                values: vec![Vec::new()],
                bases: vec![base],
                fleet_rows: None,
                said: Vec::new(),
            },
            None,
        ),
    };
    // Every step's parameters fit together on the first base (rules tying several parameters:
    // mu_s <= mu_m, n_driven <= n_wheels), before any work.
    cycle
        .check_steps(&structures.bases[0])
        .map_err(|e| CliError(e.to_string()))?;
    Ok(CycleRequest {
        cycle,
        variant,
        opts,
        base,
        structures,
        study,
        metadata,
    })
}

/// The cycle's files in `--out`, then the summary and the files written (unless `--quiet`).
fn write(
    args: &CycleArgs,
    request: CycleRequest,
    wear: bool,
    band_sets: Vec<FittedConstants>,
    classified: Vec<ClassifiedCycle>,
    secs: f64,
    threads: usize,
) -> CliResult {
    let (steps, life): (Vec<_>, Vec<_>) = classified.into_iter().map(|c| (c.steps, c.life)).unzip();
    let (structures, study) = (request.structures, &request.study);
    let fleet = match (study, structures.fleet_rows) {
        (Some(s), Some(rows)) => s
            .operating_points
            .as_ref()
            .map(|points| FleetDraw { points, rows }),
        _ => None,
    };
    let run = CycleRun {
        cycle: &request.cycle,
        variant: request.variant,
        structure_names: structures.names,
        structure_values: structures.values,
        steps,
        life,
        metadata: request.metadata,
        fleet,
        // The lifetime verdict reads the tire's life constants as its steps do: a cycle's
        // constant column of one of them is the whole life's.
        wear_bases: if wear {
            structures
                .bases
                .iter()
                .map(|b| request.cycle.whole_life(b))
                .collect()
        } else {
            Vec::new()
        },
        band_sets,
    };
    let summaries = run.summaries();
    let written = run.write(&args.out, &summaries).map_err(|e| match e {
        FilesError::CreateDir { .. } => CliError(format!("--out {e}")),
        e => CliError(e.to_string()),
    })?;
    for line in summary_lines(&run, &summaries, secs, threads) {
        println!("{line}");
    }
    if !args.quiet {
        for p in written {
            println!("  wrote {}", p.display());
        }
    }
    Ok(())
}

/// The wear stage of the run (none with `--no-wear`), calibrated on the nominal tire `base`.
fn wear_stage(args: &CycleArgs, base: &Params, variant: Variant) -> CliResult<Option<WearStage>> {
    if args.no_wear {
        return Ok(None);
    }
    WearStage::for_run(
        base,
        variant,
        args.wear.settings(),
        &ClassifierOptions::default(),
    )
    .map(Some)
    .map_err(|e| CliError(format!("the wear stage: {e} (leave it out with --no-wear)")))
}
