//! `polywear wear`: the long-term wear loop (MODEL.md#the-long-term-loop) for one operating
//! point, both wheels in parallel: the summary, the history of every order, the profile at a
//! few distances, a figure and the verdict in words.

use std::path::{Path, PathBuf};

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::common::{base_metadata, BudgetArgs, CliError, CliResult, PointArgs};
use polywear_analysis::figures::wear::LongTermFiles;
use polywear_analysis::figures::FilesError;
use polywear_analysis::plot::FigureFormat;
use polywear_core::classify::ClassifierOptions;
use polywear_core::long_term::{
    self, LongTermError, LongTermProblem, LongTermSolution, WheelLongTerm,
};
use polywear_core::model::{Variant, WheelModel};
use polywear_core::params::{ParamId, Params};
use polywear_core::wear::long_term::{cruise_legs, Leg, LoopSettings, RunEnd, SPEED_NODES};
use polywear_core::wear::WearZone;
use polywear_core::wording::plain;
use polywear_study::cycle::DriveCycle;

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the default point, both wheels, 60,000 km with the shipped speed spread\n",
    "  polywear wear --out data/wear\n",
    "  # the worst case: every straight-running joule couples, a steady speed\n",
    "  polywear wear --set wear_share_straight=1 --speed-spread-kmh 0 --estimate --out data/wear\n",
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
    /// visible polygon settles with 5 (within 15% of 40 at the reference point); more
    /// cost that many times the time
    #[arg(long, value_name = "K", default_value_t = SPEED_NODES as i64, allow_negative_numbers = true)]
    pub speed_nodes: i64,
    /// Where the friction power wears the tread: trailing (default), whole_patch,
    /// whole_patch_uniform
    #[arg(long, value_name = "ZONE", default_value = "trailing")]
    pub wear_zone: String,
    /// Drive this cycle (CSV or Parquet: time_s, speed_kmh, as `polywear cycle` reads it) again
    /// and again instead of cruising at --speed
    #[arg(long, value_name = "CYCLE")]
    pub cycle: Option<PathBuf>,
    /// Seed of the new tyre's run-out phases
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Also print the per-sample estimator's figures and add `estimate_*` columns
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
    /// Output folder (created if missing)
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// Most speeds `--speed-nodes` accepts.
const MAX_SPEED_NODES: usize = 64;

/// The checked inputs of a run.
struct Plan {
    problem: LongTermProblem,
    usage: String,
    metadata: Vec<(String, String)>,
}

/// Checks every input before any work, exit 2 with the flag and the accepted range.
fn plan(args: &WearArgs) -> CliResult<Plan> {
    let resolved = args.point.resolve()?;
    let mut p = resolved.params;
    long_term::check_distance_km(args.distance_km).map_err(refusal)?;
    let zone: WearZone = args
        .wear_zone
        .parse()
        .map_err(|e| CliError(format!("--wear-zone: {e}")))?;
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
    if args.out.is_file() {
        return Err(CliError(format!(
            "--out {}: is a file; give a directory",
            args.out.display()
        )));
    }
    let nodes = match args.speed_nodes {
        k if (1..=MAX_SPEED_NODES as i64).contains(&k) => k as usize,
        k => {
            return Err(CliError(format!(
                "--speed-nodes = {k} is outside its accepted range [1, {MAX_SPEED_NODES}]"
            )))
        }
    };
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
        zone,
        ..LoopSettings::default()
    };
    metadata.push(("wear_zone".into(), zone.as_str().into()));
    metadata.push((
        "wear_loop".into(),
        serde_json::to_string(&settings).expect("plain data"),
    ));
    metadata.push((
        "legs".into(),
        serde_json::to_string(&legs).expect("plain data"),
    ));
    metadata.push(("usage".into(), usage.clone()));
    let classifier = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let problem = LongTermProblem::new(p, variant, legs, settings, classifier).map_err(refusal)?;
    Ok(Plan {
        problem,
        usage,
        metadata,
    })
}

/// A refused problem in the words of the command line: the distance as `--distance-km`.
fn refusal(e: LongTermError) -> CliError {
    match e {
        LongTermError::Distance(km) => CliError(format!(
            "--distance-km = {} is outside its accepted range (0, 1e6] km",
            plain(km, 12)
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
    Ok((
        legs,
        format!(
            "driving the cycle {} ({km:.2} km) again and again",
            path.display()
        ),
    ))
}

pub fn run(args: &WearArgs) -> CliResult {
    let plan = plan(args)?;
    let bar = progress_bar(args.quiet, 2.0 * plan.problem.settings.distance_km);
    let started = std::time::Instant::now();
    let solution = long_term::solve(&plan.problem, &|km| bar.inc(km.round() as u64))
        .map_err(|e| CliError(e.to_string()))?;
    bar.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    LongTermFiles {
        solution: &solution,
        metadata: &plan.metadata,
        estimate: args.estimate,
        format: args.format,
        title: format!("polywear wear: {}", plan.usage),
    }
    .write(&args.out)
    .map_err(|e| match e {
        FilesError::CreateDir { .. } => CliError(format!("--out {e}")),
        e => CliError(e.to_string()),
    })?;
    print_verdict(&plan, &solution, args.estimate, secs);
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

/// The verdict of one wheel in words.
fn verdict_words(o: &WheelLongTerm, p: &Params, distance_km: f64) -> String {
    let run = match &o.run {
        Ok(r) => r,
        Err(e) => return format!("{}: no wear figures ({e})", o.wheel),
    };
    let lock = match (run.locked_speed_kmh(), &o.tongue) {
        (Some(v), Ok(Some(t))) => format!(
            "locked at {} km/h; its tongue spans {}±{} km/h",
            plain(v, 4),
            if t.at_bound { "at least " } else { "" },
            plain(t.halfwidth_kmh, 2)
        ),
        (Some(v), Err(e)) => format!(
            "locked at {} km/h; its tongue not measured: {e}",
            plain(v, 4)
        ),
        (Some(v), Ok(None)) => format!("locked at {} km/h", plain(v, 4)),
        (None, _) => "vibration not locked".into(),
    };
    let n = run.dominant_order();
    match run.ended() {
        RunEnd::Visible { order, km } => format!(
            "{}: a{} {order}-sided polygon becomes visible after {} km ({lock})",
            o.wheel,
            if order == 8 || order == 11 || order == 18 {
                "n"
            } else {
                ""
            },
            thousands(km)
        ),
        RunEnd::WornOut { km } => format!(
            "{}: tire worn out before a polygon, after {} km ({} mm of usable tread gone; the deepest order, {n}, {} µm peak-to-valley) ({lock})",
            o.wheel,
            thousands(km),
            plain(p.usable_wear_m() * 1e3, 4),
            plain(run.end().depths_m[n as usize - 1] * 1e6, 2)
        ),
        RunEnd::Distance => {
            let s = run.distance_to_visible_km(p.visible_depth_mm * 1e-3);
            if s.is_infinite() {
                format!(
                    "{}: no polygon in {} km, every order levels out ({lock})",
                    o.wheel,
                    thousands(distance_km)
                )
            } else {
                format!(
                    "{}: no polygon in {} km; order {n} still grows and would be visible after about {} km ({lock})",
                    o.wheel,
                    thousands(distance_km),
                    thousands(s)
                )
            }
        }
    }
}

/// A distance in words: to the km below 1,000 km, to 100 km above, with thousands separators.
fn thousands(km: f64) -> String {
    polywear_core::wording::thousands(if km < 1e3 {
        km
    } else {
        (km / 100.0).round() * 100.0
    })
}

fn print_verdict(plan: &Plan, solution: &LongTermSolution, estimate: bool, secs: f64) {
    let p = &plan.problem.params;
    let settings = &plan.problem.settings;
    let wheels = &solution.wheels;
    println!(
        "{} (wear zone {}, phi_s = {}, seed run-out {} um, visible at {} mm); {:.1} s",
        plan.usage,
        settings.zone,
        plain(p.wear_share_straight, 4),
        plain(p.seed_runout_um, 4),
        plain(p.visible_depth_mm, 4),
        secs
    );
    let words: Vec<String> = wheels
        .iter()
        .map(|w| verdict_words(w, p, settings.distance_km))
        .collect();
    println!("{}", words.join("; "));
    for w in wheels {
        let f = w.figures(p);
        // The growth from the seed (the estimator's figure) and over the last step, which can
        // differ in sign once the tread has worn and ν has moved.
        let at_end = w.run.as_ref().map_or(f64::NAN, |r| {
            r.end().growth_per_m[f.dominant_order as usize - 1] * 1e6
        });
        println!(
            "  {}: loop      dominant order {}, growth {} per 1000 km from the seed, {} at the end, distance {} km",
            w.wheel,
            plain(f.dominant_order, 4),
            plain(f.growth_rate_per_1000km, 3),
            plain(at_end, 3),
            plain(f.distance_to_visible_km.round(), 8)
        );
        if w.run.is_ok() {
            let f_rot = WheelModel::rotation_hz(p);
            println!(
                "  {}: tread     height {} -> {} mm, frequency {} -> {} Hz, nu {} -> {}{}",
                w.wheel,
                plain(p.tread_height * 1e3, 4),
                plain(f.tread_height_end_mm, 3),
                plain(f.tread_freq_start_hz, 4),
                plain(f.tread_freq_end_hz, 4),
                plain(f.tread_freq_start_hz / f_rot, 4),
                plain(f.tread_freq_end_hz / f_rot, 4),
                if f.worn_out_km.is_nan() {
                    String::new()
                } else {
                    format!(", worn out at {} km", plain(f.worn_out_km.round(), 8))
                }
            );
        }
        if estimate {
            match &w.solution.wear {
                Some(e) => println!(
                    "  {}: estimate  dominant order {}, growth {} per 1000 km, distance {} km{}",
                    w.wheel,
                    plain(e.polygon_order_dominant, 4),
                    plain(e.growth_rate_per_1000km, 3),
                    plain(e.distance_to_visible_km.round(), 8),
                    if e.reason.is_empty() {
                        String::new()
                    } else {
                        format!(" ({})", e.reason)
                    }
                ),
                None => println!("  {}: estimate  none", w.wheel),
            }
        }
    }
}
