//! `polywear optimize`: the setting within a box that minimises the risk of polygonal wear (or
//! of vibration, or a weighted sum) over a study's samples.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use polywear_analysis::plot::FigureFormat;

use super::batch::styled_bar;
use super::common::{BudgetArgs, CliError, CliResult};
use polywear_analysis::render::run_words::optimize_lines;
use polywear_core::params::ParamId;
use polywear_core::wording::plain;
use polywear_study::optimize::evaluate::{solve, Progress};
use polywear_study::optimize::input;
use polywear_study::optimize::objective::{parse_terms, Objective, Term, WheelChoice};
use polywear_study::optimize::search::SearchOptions;
use polywear_study::optimize::{Problem, ProblemBand, ProblemSpec};
use polywear_study::study::SEED_MAX;

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the toe-in and pressure that minimise the risk of a visible polygon within 40,000 km\n",
    "  polywear optimize studies/toe_and_pressure.toml --vary toe_deg=0.05..0.40 --vary pressure_kpa=200..300 --out data/optimum\n",
    "  # the follower's vibration, with the pressure at least 230 kPa\n",
    "  polywear optimize studies/toe_and_pressure.toml --vary toe_deg=0.05..0.40 --vary pressure_kpa=200..300 \\\n",
    "      --objective vibration --wheel follower --constraint pressure_kpa>=230 --samples 2000 --out data/optimum_vib\n",
    "\nGuide: docs/book/src/reference/optimize.md#optimize"
))]
pub(crate) struct OptimizeArgs {
    /// Study file (TOML): every setting is evaluated on its samples. Without it: the built-in
    /// highway-fleet study (studies/default.toml)
    #[arg(value_name = "STUDY.toml")]
    pub(crate) study: Option<PathBuf>,
    /// A parameter and its range, `NAME=LO..HI` (once or twice; names as `polywear params`
    /// lists them). For a parameter the study fixes, a setting is its value; for a drawn one,
    /// the centre of its distribution (every sample moved by the same amount, the spread kept;
    /// a lognormal's median, every sample scaled)
    #[arg(long, value_name = "NAME=LO..HI", required = true, allow_hyphen_values = true, value_parser = parse_vary)]
    pub(crate) vary: Vec<(ParamId, f64, f64)>,
    /// What is minimised: `wear` (a visible polygon within --within-km), `vibration`, or a
    /// weighted sum such as `0.7*wear+0.3*vibration`
    #[arg(long, default_value = "wear", allow_hyphen_values = true, value_parser = parse_objective)]
    pub(crate) objective: Terms,
    /// Which wheel: `follower`, `driving`, `front` or `rear` (the wheel on that axle under the
    /// study's drivetrain), `both` (the mean of the two) or `worst` (a sample counts when either
    /// wheel has it)
    #[arg(long, default_value = "worst", value_parser = parse_wheel)]
    pub(crate) wheel: WheelChoice,
    /// The distance within which a visible polygon counts [km], accepted (0, 1e6]
    #[arg(long, value_name = "KM", default_value_t = 40_000.0, allow_negative_numbers = true, value_parser = super::analyze::parse_km)]
    pub(crate) within_km: f64,
    /// A bound a setting must meet (repeatable): on a varied parameter (`pressure_kpa>=230`,
    /// which narrows the box), or on a risk, `wear` or `vibration`, optionally of a wheel
    /// (`vibration:driving<=0.3`, a probability in [0, 1])
    #[arg(long, value_name = "NAME<=V|NAME>=V")]
    pub(crate) constraint: Vec<String>,
    /// The calibration band: a file of calibrated sets of the fitted wear constants (phi_s,
    /// sigma_V, k_d, carcass_share, belt_mass_share; TOML as data/calibration_band.toml), or
    /// `off` for the nominal constants' answer alone. Default: the shipped sets, when the objective or a constraint weighs wear.
    /// Every setting's wear answer is re-evaluated under each set on the same samples (closed
    /// form, no second classification), and the optimum under each set is reported
    #[arg(long, value_name = "FILE|off")]
    pub(crate) calibration_band: Option<String>,
    /// Samples the calibration band's sets are evaluated on (every sample where --samples is at
    /// most this), accepted [100, 1000000], default 2000. Under each set a setting's objective is then the
    /// nominal constants' on every sample plus the set's paired difference on this subsample (a
    /// control variate), at that share of the band's work
    #[arg(long, value_name = "N", value_parser = super::common::whole_in::<u64>("--band-samples", 100, 1_000_000))]
    pub(crate) band_samples: Option<u64>,
    /// Samples of the study every setting is evaluated on (1e4 and 10_000 work), accepted
    /// [1, 1e7]
    #[arg(long, value_name = "N", default_value = "10000", allow_negative_numbers = true, value_parser = parse_samples)]
    pub(crate) samples: u64,
    /// Seed; default: the study's `seed`. Accepted [0, 4398046510080]
    #[arg(long, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, SEED_MAX))]
    pub(crate) seed: Option<u64>,
    /// Points per axis of the coarse grid, accepted [2, 65]
    #[arg(long, value_name = "N", default_value_t = SearchOptions::DEFAULT.grid, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--grid", 2, 65))]
    pub(crate) grid: usize,
    /// Refinements after the coarse grid, each halving the step, accepted [0, 6]
    #[arg(long, value_name = "N", default_value_t = SearchOptions::DEFAULT.levels, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--levels", 0, 6))]
    pub(crate) levels: usize,
    /// Settings refined around at each level (the best ones within the best's interval),
    /// accepted [1, 100]
    #[arg(long, value_name = "N", default_value_t = SearchOptions::DEFAULT.keep, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--keep", 1, 100))]
    pub(crate) keep: usize,
    /// Output directory, created when missing; its files are replaced
    /// [default: data/optimize_<study>_seed<seed>]
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Parameter file (TOML `[params]`): values for every parameter the study does not name
    #[arg(long, value_name = "FILE")]
    pub(crate) params: Option<PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a study value or a
    /// box end such as pressure_kpa = 2.4 (bar, not kPa) is refused before any work without it
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
    /// No progress bar
    #[arg(long, short)]
    pub(crate) quiet: bool,
    /// File type of the picture
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub(crate) format: FigureFormat,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
}

/// The terms of `--objective`.
#[derive(Debug, Clone)]
pub(crate) struct Terms(pub Vec<(f64, Term)>);

fn parse_objective(s: &str) -> Result<Terms, String> {
    parse_terms(s)
        .map(Terms)
        .map_err(|e| format!("--objective {e}"))
}

fn parse_wheel(s: &str) -> Result<WheelChoice, String> {
    s.parse().map_err(|e| format!("--wheel {e}"))
}

/// Parses `--samples` within [1, 1e7] (1e4 and 10_000 work).
fn parse_samples(s: &str) -> Result<u64, String> {
    super::explore::samples_up_to(s, 10_000_000, "1e7")
}

/// Parses `--vary NAME=LO..HI`; the range's meaning is checked against the study later.
fn parse_vary(s: &str) -> Result<(ParamId, f64, f64), String> {
    input::parse_vary(s).map_err(|e| format!("--vary {e}"))
}

pub(crate) fn run(args: &OptimizeArgs) -> CliResult {
    let problem = problem(args)?;
    let pool = super::common::thread_pool(args.threads)?;
    let out_dir = args.out.clone().unwrap_or_else(|| {
        PathBuf::from("data").join(format!(
            "optimize_{}_seed{}",
            problem.study.name, problem.seed
        ))
    });
    // The folder is resolved before any work: a path through a file or a link to nothing is
    // refused in safe_write's words, not after the search.
    polywear_study::safe_write::create_dir(&out_dir)
        .map_err(|e| CliError(format!("--out {}: {e}", out_dir.display())))?;
    super::batch::say_and_exit_on_signal(
        "optimize",
        format!(
            "the search does not resume, and its files are written only at its end: nothing \
             new is in {}; run it again (fewer --samples or a coarser --grid for a quicker answer)",
            out_dir.display()
        ),
    )?;
    if !args.quiet {
        let off = args.calibration_band.as_deref() == Some("off");
        let threads = pool.current_num_threads();
        for line in optimize_lines(&problem, off, threads, &out_dir) {
            eprintln!("{line}");
        }
    }
    // Evaluations done of those the levels so far take, rate and ETA.
    let bar = styled_bar(args.quiet, 0, "{msg} ", "evaluations", "evaluations");
    let start = Instant::now();
    // A batch log (stderr not a terminal) gets a line per level instead of the bar.
    let log = !args.quiet && !std::io::stderr().is_terminal();
    let level = |l: usize, n: u64| {
        bar.set_message(format!("level {l}"));
        bar.inc_length(n);
        if log {
            eprintln!(
                "level {l}: {} settings ({n} evaluations), {} s so far",
                n / problem.samples,
                plain(start.elapsed().as_secs_f64(), 3)
            );
        }
    };
    let done = |n: u64| bar.inc(n);
    let solution = pool.install(|| {
        solve(
            &problem,
            &Progress {
                level: &level,
                done: &done,
            },
        )
    });
    bar.finish_and_clear();
    let files = polywear_analysis::figures::optimize::write(
        &problem,
        &solution,
        &out_dir,
        &problem.metadata(),
        args.format,
    )
    .map_err(|e| CliError(format!("cannot write output: {e}")))?;
    if !args.quiet {
        println!(
            "{} settings × {} samples evaluated in {} s",
            solution.settings.len(),
            problem.samples,
            plain(start.elapsed().as_secs_f64(), 3)
        );
    }
    for line in polywear_analysis::figures::optimize::summary(&problem, &solution) {
        println!("{line}");
    }
    if !args.quiet {
        let names: Vec<String> = files
            .iter()
            .filter_map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        println!("files in {}: {}", out_dir.display(), names.join(", "));
    }
    Ok(())
}

/// The problem of the command line: the study read ([`input::read_study`]) and its work limits
/// set here, every other value checked by [`Problem::new`] before any work starts.
fn problem(args: &OptimizeArgs) -> CliResult<Problem> {
    let (study, origin) = input::read_study(
        args.study.as_deref(),
        args.params.as_deref(),
        args.accept_implausible,
        &|b| args.budget.apply(b),
    )?;
    Ok(Problem::new(ProblemSpec {
        study,
        origin,
        seed: args.seed,
        samples: args.samples,
        vary: args.vary.clone(),
        constraints: args.constraint.clone(),
        objective: Objective {
            terms: args.objective.0.clone(),
            wheel: args.wheel,
        },
        within_km: args.within_km,
        search: SearchOptions {
            grid: args.grid,
            levels: args.levels,
            keep: args.keep,
        },
        accept_implausible: args.accept_implausible,
        band: ProblemBand::asked(args.calibration_band.as_deref(), args.band_samples)?,
    })?)
}
