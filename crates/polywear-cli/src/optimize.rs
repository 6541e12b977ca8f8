//! `polywear optimize`: the setting within a box that minimises the risk of polygonal wear (or
//! of vibration, or a weighted sum) over a study's samples.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use polywear_analysis::plot::FigureFormat;

use super::common::{base_metadata, BudgetArgs, CliError, CliResult};
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::WearStage;
use polywear_core::params::ParamId;
use polywear_core::sampling::design::Design;
use polywear_core::wording::plain;
use polywear_study::optimize::evaluate::{solve, wear_available, Progress};
use polywear_study::optimize::objective::{parse_terms, Objective, Term, WheelChoice};
use polywear_study::optimize::search::SearchOptions;
use polywear_study::optimize::{Axis, Constraint, Problem};
use polywear_study::study::{Study, DEFAULT_STUDY, SEED_MAX};

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
pub struct OptimizeArgs {
    /// Study file (TOML): every setting is evaluated on its samples. Without it: the built-in
    /// highway-fleet study (studies/default.toml)
    #[arg(value_name = "STUDY.toml")]
    pub study: Option<PathBuf>,
    /// A parameter and its range, `NAME=LO..HI` (once or twice; names as `polywear params`
    /// lists them). For a parameter the study fixes, a setting is its value; for a drawn one,
    /// the centre of its distribution (every sample moved by the same amount, the spread kept;
    /// a lognormal's median, every sample scaled)
    #[arg(long, value_name = "NAME=LO..HI", required = true, allow_hyphen_values = true, value_parser = parse_vary)]
    pub vary: Vec<(ParamId, f64, f64)>,
    /// What is minimised: `wear` (a visible polygon within --within-km), `vibration`, or a
    /// weighted sum such as `0.7*wear+0.3*vibration`
    #[arg(long, default_value = "wear", value_parser = parse_objective)]
    pub objective: Terms,
    /// Which wheel: `follower`, `driving`, `both` (the mean of the two) or `worst` (a sample
    /// counts when either wheel has it)
    #[arg(long, default_value = "worst", value_parser = parse_wheel)]
    pub wheel: WheelChoice,
    /// The distance within which a visible polygon counts [km], accepted (0, 1e6]
    #[arg(long, value_name = "KM", default_value_t = 40_000.0, allow_negative_numbers = true, value_parser = super::analyze::parse_km)]
    pub within_km: f64,
    /// A bound a setting must meet (repeatable): on a varied parameter (`pressure_kpa>=230`,
    /// which narrows the box), or on a risk, `wear` or `vibration`, optionally of a wheel
    /// (`vibration:driving<=0.3`, a probability in [0, 1])
    #[arg(long, value_name = "NAME<=V|NAME>=V")]
    pub constraint: Vec<String>,
    /// Samples of the study every setting is evaluated on (1e4 and 10_000 work), accepted
    /// [1, 1e7]
    #[arg(long, value_name = "N", default_value = "10000", allow_negative_numbers = true, value_parser = parse_samples)]
    pub samples: u64,
    /// Seed; default: the study's `seed`. Accepted [0, 4398046510080]
    #[arg(long, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, SEED_MAX))]
    pub seed: Option<u64>,
    /// Points per axis of the coarse grid, accepted [2, 65]
    #[arg(long, value_name = "N", default_value_t = SearchOptions::DEFAULT.grid, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--grid", 2, 65))]
    pub grid: usize,
    /// Refinements after the coarse grid, each halving the step, accepted [0, 6]
    #[arg(long, value_name = "N", default_value_t = SearchOptions::DEFAULT.levels, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--levels", 0, 6))]
    pub levels: usize,
    /// Settings refined around at each level (the best ones within the best's interval),
    /// accepted [1, 100]
    #[arg(long, value_name = "N", default_value_t = SearchOptions::DEFAULT.keep, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--keep", 1, 100))]
    pub keep: usize,
    /// Output directory, created when missing; its files are replaced
    /// [default: data/optimize_<study>_seed<seed>]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Parameter file (TOML `[params]`): values for every parameter the study does not name
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a study value or a
    /// box end such as pressure_kpa = 2.4 (bar, not kPa) is refused before any work without it
    #[arg(long)]
    pub accept_implausible: bool,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub threads: Option<usize>,
    /// No progress bar
    #[arg(long, short)]
    pub quiet: bool,
    /// File type of the picture
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub format: FigureFormat,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

/// The terms of `--objective`.
#[derive(Debug, Clone)]
pub struct Terms(pub Vec<(f64, Term)>);

fn parse_objective(s: &str) -> Result<Terms, String> {
    parse_terms(s)
        .map(Terms)
        .map_err(|e| format!("--objective {e}"))
}

fn parse_wheel(s: &str) -> Result<WheelChoice, String> {
    s.parse().map_err(|e| format!("--wheel {e}"))
}

/// Parses `--samples` within [1, 1e7].
fn parse_samples(s: &str) -> Result<u64, String> {
    let n = super::explore::parse_samples(s)?;
    if n > 10_000_000 {
        return Err(format!(
            "--samples `{s}` must be a whole number in [1, 1e7]"
        ));
    }
    Ok(n)
}

/// Parses `--vary NAME=LO..HI`; the range's meaning is checked against the study later.
fn parse_vary(s: &str) -> Result<(ParamId, f64, f64), String> {
    let form = "expected NAME=LO..HI, e.g. toe_deg=0.05..0.40";
    let (name, range) = s
        .split_once('=')
        .ok_or_else(|| format!("--vary `{s}`: {form}"))?;
    let id: ParamId = name
        .trim()
        .parse()
        .map_err(|e| format!("--vary `{s}`: {e}"))?;
    let (lo, hi) = range
        .split_once("..")
        .ok_or_else(|| format!("--vary `{s}`: {form}"))?;
    let num = |x: &str| {
        x.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                format!(
                    "--vary `{s}`: `{}` is not a finite number; {form}",
                    x.trim()
                )
            })
    };
    let (lo, hi) = (num(lo)?, num(hi)?);
    if lo >= hi {
        return Err(format!(
            "--vary `{s}`: the box is empty; accepted: LO below HI, e.g. {id}={}..{}",
            plain(lo.min(hi), 6),
            plain(lo.max(hi), 6)
        ));
    }
    Ok((id, lo, hi))
}

/// One `--constraint`: a bound on a varied parameter, or on a risk.
enum Bound {
    Param(ParamId, bool, f64),
    Risk(Constraint),
}

fn parse_constraint(s: &str, wheel: WheelChoice) -> CliResult<Bound> {
    let refuse = |why: String| {
        CliError(format!(
            "--constraint `{s}`: {why}; accepted: NAME<=V or NAME>=V, NAME a varied parameter (pressure_kpa>=230) or a risk, wear or vibration, optionally of a wheel (vibration:driving<=0.3)"
        ))
    };
    let (name, at_most, value) = if let Some((n, v)) = s.split_once("<=") {
        (n, true, v)
    } else if let Some((n, v)) = s.split_once(">=") {
        (n, false, v)
    } else {
        return Err(refuse("no <= or >=".into()));
    };
    let value: f64 = value
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| refuse(format!("`{}` is not a finite number", value.trim())))?;
    let name = name.trim();
    let (term, wheel) = match name.split_once(':') {
        Some((t, w)) => (t.trim(), w.parse::<WheelChoice>().map_err(refuse)?),
        None => (name, wheel),
    };
    if let Ok(term) = term.parse::<Term>() {
        if !(0.0..=1.0).contains(&value) {
            return Err(refuse(format!(
                "a risk is a probability, {value} is not in [0, 1]"
            )));
        }
        return Ok(Bound::Risk(Constraint {
            term,
            wheel,
            at_most,
            bound: value,
            text: s.to_string(),
        }));
    }
    let id: ParamId = name.parse().map_err(|e| refuse(format!("{e}")))?;
    Ok(Bound::Param(id, at_most, value))
}

pub fn run(args: &OptimizeArgs) -> CliResult {
    let problem = problem(args)?;
    let pool = super::common::thread_pool(args.threads)?;
    let out_dir = args.out.clone().unwrap_or_else(|| {
        PathBuf::from("data").join(format!(
            "optimize_{}_seed{}",
            problem.study.name, problem.seed
        ))
    });
    if out_dir.is_file() {
        return Err(CliError(format!(
            "--out {}: is a file; accepted: a directory",
            out_dir.display()
        )));
    }
    if !args.quiet {
        eprintln!(
            "{}: {} of {} samples (seed {}, variant {}), {}, {} threads -> {}",
            problem.study.name,
            problem.objective.text(),
            problem.samples,
            problem.seed,
            problem.variant,
            problem
                .axes
                .iter()
                .map(|a| format!("{} {}..{}", a.param, plain(a.lo, 6), plain(a.hi, 6)))
                .collect::<Vec<_>>()
                .join(", "),
            pool.current_num_threads(),
            out_dir.display()
        );
    }
    let bar = progress_bar(args.quiet);
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
        &metadata(args, &problem),
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

/// The progress bar: evaluations done of those the levels so far take, rate and ETA.
fn progress_bar(quiet: bool) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr())
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {msg} {wide_bar} {pos}/{len} evaluations  {rate}  ETA {eta}",
        )
        .expect("valid template")
        .with_key(
            "rate",
            |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.0} evaluations/s", s.per_sec());
            },
        ),
    );
    bar
}

/// The problem of the command line, every value checked before any work starts.
fn problem(args: &OptimizeArgs) -> CliResult<Problem> {
    let (source, origin) = match &args.study {
        Some(path) => (
            super::common::read_input(path, "study ", polywear_study::safe_read::Limit::Text)?,
            path.display().to_string(),
        ),
        None => (DEFAULT_STUDY.to_string(), "built-in default study".into()),
    };
    let base = super::common::base_params(args.params.as_deref(), args.accept_implausible)?;
    let dir = args
        .study
        .as_ref()
        .and_then(|p| p.parent().map(PathBuf::from))
        .unwrap_or_default();
    let mut study =
        Study::parse_at(&source, base, &dir).map_err(|e| CliError(format!("{origin}: {e}")))?;
    if !(args.accept_implausible || study.accept_implausible) {
        study
            .check_plausible()
            .map_err(|e| CliError(format!("{origin}: {e}")))?;
    }
    study.budget = args.budget.apply(study.budget)?;
    if study.design == Design::Saltelli {
        return Err(CliError(format!(
            "{origin}: `design` = \"saltelli\" draws blocks for Sobol indices, not a fleet's samples; accepted: a study with design random, lhs, sobol or grid"
        )));
    }
    study
        .check_samples(args.samples)
        .map_err(|e| CliError(format!("{origin}: --samples {}: {e}", args.samples)))?;
    let seed = args.seed.unwrap_or(study.seed);
    let objective = Objective {
        terms: args.objective.0.clone(),
        wheel: args.wheel,
    };
    let mut axes = axes(args, &study)?;
    let mut constraints = Vec::new();
    for c in &args.constraint {
        match parse_constraint(c, args.wheel)? {
            Bound::Risk(r) => constraints.push(r),
            Bound::Param(id, at_most, v) => narrow(&mut axes, id, at_most, v, c)?,
        }
    }
    let wear = objective.uses_wear() || constraints.iter().any(|c| c.term == Term::Wear);
    if wear && !wear_available() {
        return Err(CliError(
            "--objective wear: this build's rows have no `distance_to_visible_km` (the wear stage's distance to a visible polygon), so there is no risk of wear to minimise; accepted here: --objective vibration".into(),
        ));
    }
    let settings = match (wear, study.wear) {
        (false, _) => None,
        (true, Some(s)) => Some(s),
        (true, None) => {
            return Err(CliError(
                "--objective wear: the study sets `wear = false`, so its rows have no distance to a visible polygon; remove it, or use --objective vibration".into(),
            ))
        }
    };
    for (a, given) in axes.iter().zip(&args.vary) {
        check_axis(a, &study, seed, args.samples, given)?;
    }
    let classifier = ClassifierOptions {
        budget: study.budget,
        ..ClassifierOptions::default()
    };
    let wear = settings
        .map(|s| WearStage::for_run(&study.base, study.variants[0], s, &classifier))
        .transpose()
        .map_err(|e| CliError(format!("the wear stage: {e}")))?;
    Ok(Problem {
        variant: study.variants[0],
        classifier,
        wear,
        study,
        seed,
        samples: args.samples,
        axes,
        objective,
        constraints,
        within_km: args.within_km,
        search: SearchOptions {
            grid: args.grid,
            levels: args.levels,
            keep: args.keep,
        },
    })
}

/// The axes of `--vary`: one or two distinct parameters.
fn axes(args: &OptimizeArgs, study: &Study) -> CliResult<Vec<Axis>> {
    if args.vary.len() > 2 {
        return Err(CliError(format!(
            "--vary is given {} times; accepted: one or two parameters",
            args.vary.len()
        )));
    }
    if let [a, b] = &args.vary[..] {
        if a.0 == b.0 {
            return Err(CliError(format!(
                "--vary names {} twice; accepted: two different parameters",
                a.0
            )));
        }
    }
    if !(args.accept_implausible || study.accept_implausible) {
        for &(id, lo, hi) in &args.vary {
            for v in [lo, hi] {
                id.spec()
                    .check_plausible(v)
                    .map_err(|e| CliError(format!("--vary {id}: {e}")))?;
            }
        }
    }
    Ok(args
        .vary
        .iter()
        .map(|&(id, lo, hi)| Axis::new(study, id, lo, hi))
        .collect())
}

/// A bound on a varied parameter narrows its box.
fn narrow(axes: &mut [Axis], id: ParamId, at_most: bool, v: f64, text: &str) -> CliResult {
    let Some(a) = axes.iter_mut().find(|a| a.param == id) else {
        return Err(CliError(format!(
            "--constraint `{text}`: {id} is not varied; accepted: a bound on a --vary parameter, or on wear or vibration"
        )));
    };
    if at_most {
        a.hi = a.hi.min(v);
    } else {
        a.lo = a.lo.max(v);
    }
    if a.lo >= a.hi {
        return Err(CliError(format!(
            "--constraint `{text}`: leaves an empty box for {id}; accepted: a bound inside the --vary range"
        )));
    }
    Ok(())
}

/// Refuses a box whose ends take any sample outside the parameter's accepted range.
fn check_axis(
    a: &Axis,
    study: &Study,
    seed: u64,
    samples: u64,
    given: &(ParamId, f64, f64),
) -> CliResult {
    let key = format!(
        "--vary {}={}..{}",
        given.0,
        plain(given.1, 12),
        plain(given.2, 12)
    );
    if let polywear_study::optimize::SettingKind::Set = a.kind {
        for end in [a.lo, a.hi] {
            a.param.spec().check(end).map_err(|e| {
                CliError(format!("{key}: the box is outside the accepted range: {e}"))
            })?;
        }
        return Ok(());
    }
    a.check(study, seed, samples, &key).map_err(|e| {
        CliError(format!(
            "{key}: the box is outside the accepted range for the study's samples: a setting is the centre of {}'s distribution, every sample moved with it; {e}",
            a.param
        ))
    })
}

/// The metadata of every output file: the run, the objective, the box, the search.
fn metadata(args: &OptimizeArgs, problem: &Problem) -> Vec<(String, String)> {
    let study = &problem.study;
    let mut m = base_metadata(&study.base, problem.variant);
    let json = |v: serde_json::Value| v.to_string();
    m.extend([
        ("study_name".into(), study.name.clone()),
        ("study".into(), study.source.clone()),
        ("study_hash".into(), study.source_hash()),
        ("seed".into(), problem.seed.to_string()),
        ("samples".into(), problem.samples.to_string()),
        ("design".into(), study.design.as_str().into()),
        ("rng".into(), polywear_core::sampling::RNG_NAME.into()),
        ("drawn".into(), json(study.drawn_json())),
        ("objective".into(), problem.objective.text()),
        ("within_km".into(), plain(problem.within_km, 12)),
        (
            "box".into(),
            json(serde_json::Value::Array(
                problem
                    .axes
                    .iter()
                    .map(|a| {
                        serde_json::json!({
                            "name": a.param.name(), "lo": a.lo, "hi": a.hi, "setting": a.meaning()
                        })
                    })
                    .collect(),
            )),
        ),
        ("constraints".into(), json(args.constraint.clone().into())),
        (
            "search".into(),
            json(serde_json::json!({
                "grid": problem.search.grid, "levels": problem.search.levels, "keep": problem.search.keep
            })),
        ),
    ]);
    m
}
