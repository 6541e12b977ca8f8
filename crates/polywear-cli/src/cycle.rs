//! `polywear cycle`: both wheels classified at every step of a drive cycle; the share of time
//! and distance in vibration, the longest stretch, the polygon orders, and a picture.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::common::{base_metadata, BudgetArgs, CliError, CliResult, VariantArg};
use polywear_analysis::figures::cycle::{CycleRun, FleetDraw};
use polywear_analysis::figures::FilesError;
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::WearStage;
use polywear_core::model::Variant;
use polywear_core::params::{Group, ParamError, ParamId, Params};
use polywear_core::sampling::design::Design;
use polywear_core::wear::{WearSettings, WearZone};
use polywear_core::wording::plain;
use polywear_study::cycle::{classify_cycles, DriveCycle, StepWheel};
use polywear_study::study::Study;

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
pub struct CycleArgs {
    /// Drive cycle (CSV or Parquet): `time_s` (increasing) and `speed_kmh` (0 = standstill),
    /// optionally a column per step for any parameter of `polywear params` (toe_deg, load_n,
    /// pressure_kpa, ...). Standard cycles: data/cycles/
    #[arg(value_name = "CYCLE.csv")]
    pub cycle: PathBuf,
    /// Output directory: cycle.parquet, cycle_summary.csv (+ .parquet), cycle.png
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Friction variant: sliding_share (default), paper or combined (see `simulate --help`)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub variant: VariantArg,
    /// Any model parameter for the whole cycle, e.g. `--set toe_deg=0.3` (repeatable); one the
    /// cycle file gives per step is refused
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = super::common::parse_assignment)]
    pub set: Vec<(String, f64)>,
    /// Parameter file (TOML `[params]`, e.g. from `polywear calibrate`), applied first; a
    /// parameter the cycle file or --study also sets is refused
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a cycle column,
    /// --set, --params or --study value such as pressure_kpa = 2.4 (bar, not kPa) is refused
    /// before any work without it
    #[arg(long)]
    pub accept_implausible: bool,
    /// Study whose drawn tire-structure, friction and vehicle parameters give the tire
    /// structures; with [operating_points] each structure sample also draws a row of the
    /// fleet, whose load, pressure and toe-in hold for the whole cycle (the cycle gives the
    /// speed). Its drawn speed, toe, load and pressure distributions are not used (said before
    /// the results); needs --structure-samples
    #[arg(long, value_name = "STUDY.toml", requires = "structure_samples")]
    pub study: Option<PathBuf>,
    /// Tire structures drawn from --study (samples 0..K of its design and seed): every share
    /// becomes a distribution, reported as mean and 90% interval. Accepted [2, 100000]
    #[arg(long, value_name = "K", requires = "study", allow_negative_numbers = true,
          value_parser = super::common::whole_in::<u64>("--structure-samples", 2, STRUCTURE_SAMPLES_MAX))]
    pub structure_samples: Option<u64>,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub threads: Option<usize>,
    /// No summary on stdout
    #[arg(long, short)]
    pub quiet: bool,
    /// Leave the wear stage out: no distance to a visible polygon, no wear columns
    #[arg(long, conflicts_with = "wear_zone")]
    pub no_wear: bool,
    /// Where the friction power wears the tread (MODEL.md#step-11-wear-zone): trailing (the
    /// default), whole_patch or whole_patch_uniform
    #[arg(long, value_name = "ZONE", value_parser = |s: &str| s.parse::<WearZone>().map_err(|e| e.to_string()))]
    pub wear_zone: Option<WearZone>,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

/// The tire structures of `--study`: the drawn non-operating parameters (and a fleet's columns
/// other than the operating axes) with their values per sample, each sample's parameter base,
/// the fleet rows drawn, and the lines that say what the cycle takes from the study.
struct Structures {
    names: Vec<ParamId>,
    values: Vec<Vec<f64>>,
    bases: Vec<Params>,
    fleet_rows: Option<Vec<usize>>,
    said: Vec<String>,
}

/// What the command line gives: the `--params` file's values and names, and the `--set` values
/// with their words.
struct CommandLine {
    file: Params,
    named: Vec<ParamId>,
    set: Vec<(ParamId, f64, String)>,
}

/// Reads `--params` and `--set`, refusing before any work: the speed (the cycle gives it), a
/// parameter set twice, one the cycle file gives per step (from `--set` or `--params`), and
/// implausible values unless accepted. A `--set` value replacing the file's is noted.
fn command_line(args: &CycleArgs, cycle: &DriveCycle) -> CliResult<CommandLine> {
    let accept = args.accept_implausible;
    let (file, named) = super::common::param_file(args.params.as_deref(), accept)?;
    let params_by = || {
        format!(
            "--params {}",
            args.params.as_deref().unwrap_or(Path::new("")).display()
        )
    };
    let mut set: Vec<(ParamId, f64, String)> = Vec::new();
    for (name, value) in &args.set {
        let by = format!("--set {name}={}", plain(*value, 12));
        let id: ParamId = name
            .parse()
            .map_err(|e: ParamError| CliError(format!("--set {name}: {e}")))?;
        if id == ParamId::SpeedKmh {
            return Err(CliError(
                "--set speed_kmh: the cycle gives the speed at every step (its `speed_kmh` column)"
                    .into(),
            ));
        }
        if let Some((_, _, first)) = set.iter().find(|(t, _, _)| *t == id) {
            return Err(CliError(format!(
                "`{id}` is given twice on the command line ({first} and {by}); give it once"
            )));
        }
        id.spec()
            .check(*value)
            .map_err(|e| CliError(format!("--set {name}: {e}")))?;
        if !accept {
            id.spec()
                .check_plausible(*value)
                .map_err(|e| CliError(format!("{by}: {e}")))?;
        }
        set.push((id, *value, by));
    }
    let column = |id: ParamId| cycle.names.contains(&id);
    for (id, by) in set
        .iter()
        .map(|(id, _, by)| (*id, by.clone()))
        .chain(named.iter().map(|&id| (id, params_by())))
    {
        if column(id) {
            return Err(CliError(format!(
                "{by} sets `{id}`, which {} gives at every step (its column `{id}`); a parameter comes from one place: leave it out of {by} or drop the column",
                cycle.path.display()
            )));
        }
    }
    if named.contains(&ParamId::SpeedKmh) {
        eprintln!(
            "note: the cycle's speed replaces speed_kmh = {} of {}",
            plain(file.speed_kmh, 12),
            params_by()
        );
    }
    for (id, value, by) in &set {
        if named.contains(id) && file[*id] != *value {
            eprintln!(
                "note: {by} replaces {id} = {} of {}",
                plain(file[*id], 12),
                params_by()
            );
        }
    }
    Ok(CommandLine { file, named, set })
}

/// Draws the structure samples of `--study` on top of the `--params` values, with `--set`
/// applied after the study's fixed values (a replaced fixed value is noted). With
/// `[operating_points]` each sample also draws a row, whose columns but the speed hold for the
/// whole cycle.
fn structures(
    args: &CycleArgs,
    path: &Path,
    k: u64,
    line: &CommandLine,
    cycle: &DriveCycle,
) -> CliResult<(Structures, Study)> {
    let origin = format!("--study {}", path.display());
    let source =
        super::common::read_input(path, "--study ", polywear_study::safe_read::Limit::Text)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let study =
        Study::parse_at(&source, line.file, dir).map_err(|e| CliError(format!("{origin}: {e}")))?;
    if !(args.accept_implausible || study.accept_implausible) {
        study
            .check_plausible()
            .map_err(|e| CliError(format!("{origin}: {e}")))?;
    }
    super::common::refuse_file_overlap(&line.named, args.params.as_deref(), &study, &origin)?;
    if study.design == Design::Saltelli {
        return Err(CliError(format!(
            "{origin}: a saltelli design's rows are arranged for Sobol indices, not a sample of tire structures; use random, lhs or sobol"
        )));
    }
    study
        .check_samples(k)
        .map_err(|e| CliError(format!("{origin}: --structure-samples: {e}")))?;
    let fleet = study.operating_points.as_ref();
    if let Some(op) = fleet {
        super::common::refuse_reserved_names(
            op.pass_through.iter().map(|c| c.name.as_str()),
            &op.path,
            "`operating_points.pass_through`",
            &[
                "sample_id",
                "operating_point_row",
                "step",
                "time_s",
                "step_duration_s",
                "tread_time_constant_s",
                "stability_change_time_s",
                "quasi_static",
            ],
        )?;
    }
    // The fleet's columns that hold for the whole cycle (the cycle gives the speed).
    let fleet_ids: Vec<ParamId> = fleet
        .iter()
        .flat_map(|op| op.names.iter())
        .map(|n| n.parse::<ParamId>().expect("a parameter column"))
        .filter(|&id| id != ParamId::SpeedKmh)
        .collect();
    let names: Vec<ParamId> = study
        .drawn
        .iter()
        .map(|d| d.param)
        .filter(|id| id.spec().group != Group::OperatingPoint)
        .chain(
            fleet_ids
                .iter()
                .copied()
                .filter(|id| !id.is_operating_axis()),
        )
        .collect();
    if names.is_empty() && fleet.is_none() {
        return Err(CliError(format!(
            "{origin}: the study draws no tire-structure, friction or vehicle parameter, so every structure sample would be the same"
        )));
    }
    refuse_study_overlaps(&study, &origin, line, cycle, &names, &fleet_ids)?;
    let sampler = study.sampler(study.seed, k);
    let mut out = Structures {
        names,
        values: Vec::new(),
        bases: Vec::new(),
        fleet_rows: fleet.map(|_| Vec::new()),
        said: said_about_study(&study, (&origin, dir), k, cycle, line),
    };
    for i in 0..k {
        let (p, _, row) = sampler.sample_with_row(i);
        let mut b = study.base;
        for &id in out.names.iter().chain(&fleet_ids) {
            b[id] = p[id];
        }
        for &(id, value, _) in &line.set {
            b.try_set(id, value)?;
        }
        out.values.push(out.names.iter().map(|&id| p[id]).collect());
        out.bases.push(b);
        if let (Some(rows), Some(r)) = (&mut out.fleet_rows, row) {
            rows.push(r);
        }
    }
    Ok((out, study))
}

/// Refuses what the study sets and another place sets too: a drawn structure parameter or a
/// fleet column given by `--set` or the cycle file, a fixed value the cycle file gives per
/// step. A `--set` replacing one of the study's fixed values is noted.
fn refuse_study_overlaps(
    study: &Study,
    origin: &str,
    line: &CommandLine,
    cycle: &DriveCycle,
    names: &[ParamId],
    fleet_ids: &[ParamId],
) -> CliResult {
    let cycle_by = format!("{} (a column)", cycle.path.display());
    let given = line
        .set
        .iter()
        .map(|(id, _, by)| (*id, by.as_str()))
        .chain(cycle.names.iter().map(|&id| (id, cycle_by.as_str())));
    for (id, by) in given {
        let how = if names.contains(&id) && !fleet_ids.contains(&id) {
            "draws per structure sample"
        } else if fleet_ids.contains(&id) {
            "gives per vehicle (a column of its [operating_points] file)"
        } else if study.fixed.contains(&id) && by == cycle_by {
            "fixes (`params.{id}`)"
        } else {
            continue;
        };
        return Err(CliError(format!(
            "{by} sets `{id}`, which {origin} {}; a parameter comes from one place, not both",
            how.replace("{id}", id.name())
        )));
    }
    for (id, value, by) in &line.set {
        if study.fixed.contains(id) && study.base[*id] != *value {
            eprintln!(
                "note: {by} replaces {origin}'s `params.{id}` = {}",
                plain(study.base[*id], 12)
            );
        }
    }
    Ok(())
}

/// The lines said before the results: which of the study's operating-point values the cycle
/// takes (a fleet's rows) and which it does not (the speed, drawn operating axes).
fn said_about_study(
    study: &Study,
    (origin, dir): (&str, &Path),
    k: u64,
    cycle: &DriveCycle,
    line: &CommandLine,
) -> Vec<String> {
    let mut said = Vec::new();
    let set_here = |id: ParamId| cycle.names.contains(&id) || line.set.iter().any(|s| s.0 == id);
    if let Some(op) = &study.operating_points {
        let taken: Vec<&str> = op
            .names
            .iter()
            .copied()
            .filter(|n| *n != "speed_kmh")
            .collect();
        let by = match (&op.weight, &op.weight_computed) {
            (_, Some(how)) => format!("by km = {how}"),
            (Some(w), None) => format!("by its `{w}`"),
            (None, None) => "with equal weight".to_string(),
        };
        let speed = if op.names.contains(&"speed_kmh") {
            "; its `speed_kmh` column is not used: the cycle gives the speed"
        } else {
            ""
        };
        said.push(format!(
            "fleet: each of the {k} structure samples drives the cycle with one row of {} drawn {by} ({} from the row{speed})",
            dir.join(&op.file).display(),
            if taken.is_empty() { "no column".to_string() } else { taken.join(", ") }
        ));
    }
    if study.fixed.contains(&ParamId::SpeedKmh) {
        said.push(format!(
            "{origin}: its `params.speed_kmh` = {} is not used: the cycle gives the speed",
            plain(study.base.speed_kmh, 6)
        ));
    }
    let unused: Vec<ParamId> = study
        .drawn
        .iter()
        .map(|d| d.param)
        .filter(|id| id.is_operating_axis())
        .collect();
    if !unused.is_empty() {
        let held: Vec<String> = unused
            .iter()
            .filter(|&&id| id != ParamId::SpeedKmh && !set_here(id))
            .map(|&id| format!("{id} = {}", plain(study.base[id], 6)))
            .collect();
        let speed = if unused.contains(&ParamId::SpeedKmh) {
            "the cycle gives the speed"
        } else {
            ""
        };
        let held = match (speed.is_empty(), held.is_empty()) {
            (_, true) => speed.to_string(),
            (true, false) => format!("{} hold for the whole cycle", held.join(", ")),
            (false, false) => format!("{speed}, and {} hold for the whole cycle", held.join(", ")),
        };
        said.push(format!(
            "{origin}: its distributions of {} are not used: {held} (a study with [operating_points] gives load, pressure and toe-in per vehicle)",
            unused.iter().map(|id| id.name()).collect::<Vec<_>>().join(", "),
        ));
    }
    said
}

pub fn run(args: &CycleArgs) -> CliResult {
    let mut request = resolve(args)?;
    if !args.quiet {
        for l in &request.structures.said {
            println!("{l}");
        }
    }
    let wear = wear_stage(args, &request.base, request.variant)?;
    if let Some(stage) = &wear {
        let stage = serde_json::to_string(stage).expect("json");
        request.metadata.push(("wear".into(), stage));
    }
    let pool = super::common::thread_pool(args.threads)?;
    let start = Instant::now();
    let steps = pool.install(|| {
        classify_cycles(
            &request.cycle,
            &request.structures.bases,
            request.variant,
            &request.opts,
            wear.as_ref(),
        )
    });
    let secs = start.elapsed().as_secs_f64();
    let threads = pool.current_num_threads();
    write(args, request, wear.is_some(), steps, secs, threads)
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
    if !args.accept_implausible {
        cycle
            .check_plausible()
            .map_err(|e| CliError(e.to_string()))?;
    }
    let line = command_line(args, &cycle)?;
    let mut base = line.file;
    for &(id, value, _) in &line.set {
        base.try_set(id, value)?;
    }
    let mut metadata = base_metadata(&base, variant);
    metadata.push(("cycle".into(), args.cycle.display().to_string()));
    metadata.push(("cycle_hash".into(), cycle.hash.clone()));
    let (structures, study) = match (&args.study, args.structure_samples) {
        (Some(path), Some(k)) => {
            let (s, study) = structures(args, path, k, &line, &cycle)?;
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
    steps: Vec<Vec<[StepWheel; 2]>>,
    secs: f64,
    threads: usize,
) -> CliResult {
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
        metadata: request.metadata,
        fleet,
        wear_bases: if wear { structures.bases } else { Vec::new() },
    };
    let written = run.write(&args.out).map_err(|e| match e {
        FilesError::CreateDir { .. } => CliError(format!("--out {e}")),
        e => CliError(e.to_string()),
    })?;
    if !args.quiet {
        print_summary(&run, secs, threads);
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
    let settings = WearSettings {
        zone: args.wear_zone.unwrap_or_default(),
    };
    WearStage::for_run(base, variant, settings, &ClassifierOptions::default())
        .map(Some)
        .map_err(|e| CliError(format!("the wear stage: {e} (leave it out with --no-wear)")))
}

/// The study's keys in the outputs' metadata (and the fleet's file, when it gives the rows).
fn study_metadata(study: &Study, k: u64, names: &[ParamId]) -> Vec<(String, String)> {
    let mut m = vec![
        ("study_name".into(), study.name.clone()),
        ("study".into(), study.source.clone()),
        ("study_hash".into(), study.source_hash()),
        ("seed".into(), study.seed.to_string()),
        ("design".into(), study.design.as_str().into()),
        ("structure_samples".into(), k.to_string()),
        ("rng".into(), polywear_core::sampling::RNG_NAME.into()),
        (
            "drawn_names".into(),
            serde_json::to_string(names).expect("json"),
        ),
    ];
    if let Some(op) = &study.operating_points {
        m.push(("operating_points".into(), op.to_json().to_string()));
    }
    m
}

/// The summary on stdout: per wheel, the shares in vibration (with the 90% interval over the
/// structures when there are several) and the dominant polygon order.
fn print_summary(run: &CycleRun<'_>, secs: f64, threads: usize) {
    let c = run.cycle;
    let dt = c.step_durations_s();
    let total_s: f64 = dt.iter().sum();
    let km: f64 = (0..c.len()).map(|i| c.speed_kmh[i] * dt[i] / 3600.0).sum();
    println!(
        "{}: {} steps, {total_s:.0} s, {km:.2} km; {} structure(s) x 2 wheels classified in {secs:.2} s ({threads} threads), variant {}",
        c.path.display(),
        c.len(),
        run.steps.len(),
        run.variant.as_str()
    );
    let all = run.summaries();
    for w in 0..2 {
        let pick = |f: &dyn Fn(&polywear_study::cycle::summary::WheelSummary) -> f64| {
            let mut xs: Vec<f64> = all.iter().map(|s| f(&s[w])).collect();
            xs.sort_by(f64::total_cmp);
            let mean = xs.iter().sum::<f64>() / xs.len() as f64;
            if xs.len() == 1 {
                format!("{:.1}%", 100.0 * mean)
            } else {
                let q = polywear_study::cycle::summary::quantile;
                format!(
                    "{:.1}% (90% interval {:.1}-{:.1}%)",
                    100.0 * mean,
                    100.0 * q(&xs, 0.05),
                    100.0 * q(&xs, 0.95)
                )
            }
        };
        let mean = |f: &dyn Fn(&polywear_study::cycle::summary::WheelSummary) -> f64| {
            all.iter().map(|s| f(&s[w])).sum::<f64>() / all.len() as f64
        };
        // Polygon orders: the mean share over the structures.
        let mut orders: std::collections::BTreeMap<i64, f64> = Default::default();
        for s in &all {
            for (n, share) in &s[w].order_shares {
                *orders.entry(*n).or_default() += share / all.len() as f64;
            }
        }
        let top = orders
            .iter()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(n, share)| format!("mostly {n}-gon ({:.0}% of it)", 100.0 * share))
            .unwrap_or_else(|| "no vibration".into());
        println!(
            "  {:>8}: in vibration {} of the time, {} of the distance; longest stretch {}{:.0} s / {:.2} km; {top}; quasi-static in doubt {:.1}% of the time",
            polywear_core::model::Wheel::BOTH[w].as_str(),
            pick(&|s| s.time_share),
            pick(&|s| s.distance_share),
            if all.len() > 1 { "(mean) " } else { "" },
            mean(&|s| s.longest_vibration_s),
            mean(&|s| s.longest_vibration_km),
            100.0 * mean(&|s| s.not_quasi_static_share),
        );
        if let Some(line) = wear_line(&all, w) {
            println!("            {line}");
        }
    }
}

/// The polygon of a lifetime on the cycle, in words: the distance to a visible polygon (the
/// median and 90% interval over the structures when there are several) and its order.
fn wear_line(
    all: &[[polywear_study::cycle::summary::WheelSummary; 2]],
    w: usize,
) -> Option<String> {
    let wear: Vec<polywear_study::cycle::wear::CycleWear> =
        all.iter().filter_map(|s| s[w].wear).collect();
    if wear.is_empty() {
        return None;
    }
    let km = |x: f64| format!("{} km", polywear_core::wording::thousands(x));
    let mut d: Vec<f64> = wear.iter().map(|c| c.distance_to_visible_km).collect();
    d.sort_by(f64::total_cmp);
    let q = polywear_study::cycle::summary::quantile;
    let mut orders: Vec<f64> = wear
        .iter()
        .map(|c| c.dominant_order)
        .filter(|n| n.is_finite())
        .collect();
    orders.sort_by(f64::total_cmp);
    let unknown = wear
        .iter()
        .map(|c| c.unknown_distance_share)
        .fold(0.0, f64::max);
    let unknown = if unknown > 0.0 {
        format!(
            "; {}% of the distance has no wear figures (failed or no traction) and is left out",
            polywear_core::wording::plain(100.0 * unknown, 2)
        )
    } else {
        String::new()
    };
    let life = "driving this cycle all its life";
    if d.len() == 1 {
        let c = wear[0];
        let what = if c.distance_to_visible_km.is_nan() {
            "no wear figures at any step".to_string()
        } else if c.distance_to_visible_km.is_infinite() {
            format!(
                "no polygon ever: every order levels out (the slowest, order {:.0}, at {} per 1000 km)",
                c.dominant_order,
                polywear_core::wording::plain(c.growth_rate_per_1000km, 3)
            )
        } else {
            format!(
                "a {:.0}-sided polygon becomes visible after {} (growth {} per 1000 km)",
                c.dominant_order,
                km(c.distance_to_visible_km),
                polywear_core::wording::plain(c.growth_rate_per_1000km, 3)
            )
        };
        return Some(format!("{life}: {what}{unknown}"));
    }
    let never = d.iter().filter(|x| x.is_infinite()).count() as f64 / d.len() as f64;
    let shown = |x: f64| {
        if x.is_infinite() {
            "never".to_string()
        } else if x.is_nan() {
            "unknown".to_string()
        } else {
            km(x)
        }
    };
    let order = orders.get(orders.len() / 2).map_or(String::new(), |n| {
        format!("; the fastest order mostly {n:.0}")
    });
    Some(format!(
        "{life}: distance to a visible polygon {} (median over the structures; 90% interval {} to {}); {}% of the structures never show one{order}{unknown}",
        shown(q(&d, 0.5)),
        shown(q(&d, 0.05)),
        shown(q(&d, 0.95)),
        polywear_core::wording::plain(100.0 * never, 3)
    ))
}
