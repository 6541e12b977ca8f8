//! `polywear wear`: the long-term wear loop (MODEL.md#the-long-term-loop) for one operating
//! point, both wheels in parallel: the summary, the history of every order, the profile at a
//! few distances, a figure and the verdict in words.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::common::{base_metadata, BudgetArgs, CliError, CliResult, PointArgs};
use polywear_analysis::plot::FigureFormat;
use polywear_core::classify::{Class, ClassifierOptions};
use polywear_core::ensemble::{self, Control};
use polywear_core::evaluate::{self, PointProblem, WearStage, WheelSolution};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::{ParamId, Params};
use polywear_core::wear::long_term::{
    cruise_legs, cycle_legs, run_wheel, Leg, LoopInputs, LoopSettings, SPEED_NODES,
};
use polywear_core::wear::long_term::{WheelWear, FEEDBACK_ORDERS};
use polywear_core::wear::tongue::{self, Tongue, TongueRequest};
use polywear_core::wear::{WearSettings, WearZone};
use polywear_core::wording::plain;
use polywear_study::cycle::DriveCycle;

mod outputs;
use outputs::{figures, write_outputs};

/// The largest distance `--distance-km` accepts \[km\].
const MAX_DISTANCE_KM: f64 = 1e6;
/// Orders drawn in the figure: the deepest at the end, per wheel.
const DRAWN_ORDERS: usize = 4;

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
    params: Params,
    variant: Variant,
    legs: Vec<Leg>,
    settings: LoopSettings,
    usage: String,
    metadata: Vec<(String, String)>,
}

/// Checks every input before any work, exit 2 with the flag and the accepted range.
fn plan(args: &WearArgs) -> CliResult<Plan> {
    let resolved = args.point.resolve()?;
    let mut p = resolved.params;
    if !(args.distance_km > 0.0 && args.distance_km <= MAX_DISTANCE_KM) {
        return Err(CliError(format!(
            "--distance-km = {} is outside its accepted range (0, 1e6] km",
            plain(args.distance_km, 12)
        )));
    }
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
    Ok(Plan {
        params: p,
        variant,
        legs,
        settings,
        usage,
        metadata,
    })
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
    let distances: Vec<f64> = cycle
        .step_durations_s()
        .iter()
        .zip(&cycle.speed_kmh)
        .map(|(dt, v)| dt * v / 3.6)
        .collect();
    let legs = cycle_legs(&cycle.speed_kmh, &distances, nodes);
    if legs.is_empty() {
        return Err(CliError(format!(
            "--cycle {}: covers no distance (every step at standstill)",
            path.display()
        )));
    }
    let km: f64 = distances.iter().sum::<f64>() / 1e3;
    Ok((
        legs,
        format!(
            "driving the cycle {} ({km:.2} km) again and again",
            path.display()
        ),
    ))
}

/// The state the loop starts a wheel from: on the classifier's cycle where it vibrates.
fn start_of(w: &WheelSolution) -> Option<[f64; 3]> {
    let m = w.model.as_ref().ok()?;
    let v = &w.verdict;
    (v.class.vibrates() && v.section_v_mps > 0.0)
        .then(|| [v.section_z_m, m.ode.equilibrium()[1], v.section_v_mps])
}

pub fn run(args: &WearArgs) -> CliResult {
    let plan = plan(args)?;
    let p = plan.params;
    let opts = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let settings = WearSettings {
        zone: plan.settings.zone,
    };
    let stage = WearStage::for_run(&p, plan.variant, settings, &opts)
        .map_err(|e| CliError(e.to_string()))?;
    let gamma = stage.calibration.gamma_m3_per_j(&p);
    let variants = [plan.variant];
    let point = evaluate::solve(&PointProblem::new(p, &variants, &opts).with_wear(Some(&stage)));
    let bar = progress_bar(args.quiet, 2.0 * plan.settings.distance_km);
    let stop = AtomicBool::new(false);
    let started = std::time::Instant::now();
    let runs = ensemble::solve(
        2,
        |i| {
            let w = &point.wheels[i];
            let inputs = LoopInputs {
                params: &p,
                wheel: Wheel::BOTH[i],
                variant: plan.variant,
                gamma_m3_per_j: gamma,
                legs: &plan.legs,
                start: start_of(w),
            };
            match &w.model {
                Ok(_) if !matches!(w.verdict.class, Class::NoTraction | Class::Failed) => {
                    run_wheel(&inputs, &plan.settings, &|km| bar.inc(km.round() as u64))
                        .map(|run| {
                            let tongue = measured_tongue(&run, &inputs, &plan.settings);
                            (run, tongue)
                        })
                        .map_err(|e| e.to_string())
                }
                Ok(_) => Err(format!("{}: {}", w.verdict.class, w.verdict.reason)),
                Err(e) => Err(e.to_string()),
            }
        },
        &Control {
            progress: &|_| {},
            stop: &|| stop.load(Ordering::Relaxed),
        },
    )
    .all();
    bar.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    let wheels: Vec<WheelOutcome> = point
        .wheels
        .iter()
        .zip(runs)
        .enumerate()
        .map(|(i, (w, outcome))| {
            let (run, tongue) = match outcome {
                Ok((run, tongue)) => (Ok(run), tongue),
                Err(e) => (Err(e), Err("no run".into())),
            };
            WheelOutcome {
                wheel: Wheel::BOTH[i],
                solution: w,
                run,
                tongue,
            }
        })
        .collect();
    write_outputs(args, &plan, &wheels)?;
    print_verdict(&plan, &wheels, args.estimate, secs);
    Ok(())
}

/// One wheel's verdict, its estimate and its loop.
struct WheelOutcome<'a> {
    wheel: Wheel,
    solution: &'a WheelSolution,
    run: Result<WheelWear, String>,
    /// The tongue measured at the end where a leg is locked (`None` where none is), or why it
    /// could not be.
    tongue: Result<Option<Tongue>, String>,
}

/// The lock-in tongue at the run's end, measured at its final profile around its locked leg
/// (`wear::tongue`); `None` where no leg is locked at the end.
fn measured_tongue(
    run: &WheelWear,
    inputs: &LoopInputs<'_>,
    settings: &LoopSettings,
) -> Result<Option<Tongue>, String> {
    let Some((leg, speed_kmh, order)) = run.locked_leg() else {
        return Ok(None);
    };
    let (Some(start), Some((_, depth_m))) = (run.end_states[leg], run.profiles.last()) else {
        return Ok(None);
    };
    tongue::measure(&TongueRequest {
        params: inputs.params,
        wheel: inputs.wheel,
        variant: inputs.variant,
        zone: settings.zone,
        depth_m,
        tread_height_m: run.end().tread_height_m,
        start,
        locked: (speed_kmh, order),
        orders: FEEDBACK_ORDERS,
        rtol: settings.rtol,
    })
    .map_err(|e| e.to_string())
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
fn verdict_words(o: &WheelOutcome<'_>, p: &Params, distance_km: f64) -> String {
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
    match run.visible {
        Some((order, km)) => format!(
            "{}: a{} {order}-sided polygon becomes visible after {} km ({lock})",
            o.wheel,
            if order == 8 || order == 11 || order == 18 {
                "n"
            } else {
                ""
            },
            thousands(km)
        ),
        None => {
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
    let rounded = if km < 1e3 {
        km.round()
    } else {
        (km / 100.0).round() * 100.0
    };
    let s = format!("{rounded:.0}");
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

fn print_verdict(plan: &Plan, wheels: &[WheelOutcome<'_>], estimate: bool, secs: f64) {
    let p = &plan.params;
    println!(
        "{} (wear zone {}, phi_s = {}, seed run-out {} um, visible at {} mm); {:.1} s",
        plan.usage,
        plan.settings.zone,
        plain(p.wear_share_straight, 4),
        plain(p.seed_runout_um, 4),
        plain(p.visible_depth_mm, 4),
        secs
    );
    let words: Vec<String> = wheels
        .iter()
        .map(|w| verdict_words(w, p, plan.settings.distance_km))
        .collect();
    println!("{}", words.join("; "));
    for w in wheels {
        let f = figures(w, p);
        // The growth from the seed (the estimator's figure) and over the last step, which can
        // differ in sign once the tread has worn and ν has moved.
        let at_end = w.run.as_ref().map_or(f64::NAN, |r| {
            r.end().growth_per_m[f.dominant as usize - 1] * 1e6
        });
        println!(
            "  {}: loop      dominant order {}, growth {} per 1000 km from the seed, {} at the end, distance {} km",
            w.wheel,
            plain(f.dominant, 4),
            plain(f.growth_rate, 3),
            plain(at_end, 3),
            plain(f.distance_km.round(), 8)
        );
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
