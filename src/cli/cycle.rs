//! `polywear cycle`: both wheels classified at every step of a drive cycle; the share of time
//! and distance in vibration, the longest stretch, the polygon orders, and a picture.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::common::{base_metadata, BudgetArgs, CliError, CliResult, VariantArg};
use polywear::classify::ClassifierOptions;
use polywear::cycle::output::CycleRun;
use polywear::cycle::{classify_cycles, CycleError, DriveCycle};
use polywear::model::Variant;
use polywear::params::{Group, ParamError, ParamId, Params};
use polywear::sampling::design::Design;
use polywear::study::Study;

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
    "\nGuide: GUIDE.md#drive-cycles-polywear-cycle"
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
    /// Any model parameter for the whole cycle, e.g. `--set toe_deg=0.3` (repeatable); a
    /// column of the cycle file wins over it at its steps
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = super::common::parse_assignment)]
    pub set: Vec<(String, f64)>,
    /// Parameter file (TOML `[params]`, e.g. from `polywear calibrate`), applied first
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// Study whose drawn tire-structure, friction and vehicle parameters give the tire
    /// structures (its drawn speed, toe, load and pressure and its [operating_points] are not
    /// used: the cycle and --set give those); needs --structure-samples
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
    #[command(flatten)]
    pub budget: BudgetArgs,
}

/// The tire structures: `(names, values per sample, parameter base per sample)`, and the
/// study's metadata.
type Structures = (Vec<ParamId>, Vec<Vec<f64>>, Vec<Params>);

/// Draws the structure samples of `--study` on top of `base`.
fn structures(
    path: &Path,
    k: u64,
    base: Params,
    fixed_elsewhere: &[(ParamId, &str)],
) -> CliResult<(Structures, Study)> {
    let origin = format!("--study {}", path.display());
    let source = super::common::read_input(path, "--study ", polywear::safe_read::Limit::Text)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let study =
        Study::parse_at(&source, base, dir).map_err(|e| CliError(format!("{origin}: {e}")))?;
    if study.operating_points.is_some() {
        eprintln!(
            "note: {origin}: its [operating_points] are not used here: the cycle gives the operating point at every step"
        );
    }
    if study.design == Design::Saltelli {
        return Err(CliError(format!(
            "{origin}: a saltelli design's rows are arranged for Sobol indices, not a sample of tire structures; use random, lhs or sobol"
        )));
    }
    study
        .check_samples(k)
        .map_err(|e| CliError(format!("{origin}: --structure-samples: {e}")))?;
    let names: Vec<ParamId> = study
        .drawn
        .iter()
        .map(|d| d.param)
        .filter(|id| id.spec().group != Group::OperatingPoint)
        .collect();
    if names.is_empty() {
        return Err(CliError(format!(
            "{origin}: the study draws no tire-structure, friction or vehicle parameter, so every structure sample would be the same"
        )));
    }
    for (name, by) in fixed_elsewhere {
        if names.contains(name) {
            return Err(CliError(format!(
                "{by} sets `{name}`, which {origin} draws per structure sample; a parameter is drawn or set, not both"
            )));
        }
    }
    let sampler = study.sampler(study.seed, k);
    let mut values = Vec::new();
    let mut bases = Vec::new();
    for i in 0..k {
        let (p, _) = sampler.sample(i);
        let mut b = study.base;
        let mut v = Vec::with_capacity(names.len());
        for &id in &names {
            b[id] = p[id];
            v.push(p[id]);
        }
        values.push(v);
        bases.push(b);
    }
    Ok(((names, values, bases), study))
}

pub fn run(args: &CycleArgs) -> CliResult {
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
    let mut base = super::common::base_params(args.params.as_deref())?;
    let mut set_by: Vec<(ParamId, &str)> = Vec::new();
    let mut set: Vec<(ParamId, f64)> = Vec::new();
    for (name, value) in &args.set {
        let id: ParamId = name
            .parse()
            .map_err(|e: ParamError| CliError(format!("--set {name}: {e}")))?;
        if id == ParamId::SpeedKmh {
            return Err(CliError(
                "--set speed_kmh: the cycle gives the speed at every step (its `speed_kmh` column)"
                    .into(),
            ));
        }
        base.try_set(id, *value)
            .map_err(|e| CliError(format!("--set {name}: {e}")))?;
        set_by.push((id, "--set"));
        set.push((id, *value));
    }
    let cycle_by = format!("{} (a column)", args.cycle.display());
    for &id in &cycle.names {
        set_by.push((id, cycle_by.as_str()));
    }
    let mut metadata = base_metadata(&base, variant);
    metadata.push(("cycle".into(), args.cycle.display().to_string()));
    metadata.push(("cycle_hash".into(), cycle.hash.clone()));
    let (names, values, bases) = match (&args.study, args.structure_samples) {
        (Some(path), Some(k)) => {
            // --set applies after the study's fixed values, as on the command line.
            let study_base = super::common::base_params(args.params.as_deref())?;
            let ((names, values, mut bases), study) = structures(path, k, study_base, &set_by)?;
            for b in &mut bases {
                for &(id, value) in &set {
                    b.try_set(id, value)?;
                }
            }
            // The study's work limits, unless the flags say otherwise.
            opts.budget = args.budget.apply(study.budget)?;
            metadata.push(("study_name".into(), study.name.clone()));
            metadata.push(("study".into(), study.source.clone()));
            metadata.push(("study_hash".into(), study.source_hash()));
            metadata.push(("seed".into(), study.seed.to_string()));
            metadata.push(("design".into(), study.design.as_str().into()));
            metadata.push(("structure_samples".into(), k.to_string()));
            metadata.push(("rng".into(), polywear::sampling::RNG_NAME.into()));
            metadata.push((
                "drawn_names".into(),
                serde_json::to_string(&names).expect("json"),
            ));
            (names, values, bases)
        }
        _ => (Vec::new(), vec![Vec::new()], vec![base]),
    };
    // Every step's parameters fit together on the first base (rules tying several parameters:
    // mu_s <= mu_m, n_driven <= n_wheels), before any work.
    cycle
        .check_steps(&bases[0])
        .map_err(|e| CliError(e.to_string()))?;
    let pool = super::common::thread_pool(args.threads)?;
    let start = Instant::now();
    let steps = pool.install(|| classify_cycles(&cycle, &bases, variant, &opts));
    let secs = start.elapsed().as_secs_f64();
    let run = CycleRun {
        cycle: &cycle,
        variant,
        structure_names: names,
        structure_values: values,
        steps,
        metadata,
    };
    let written = run.write(&args.out).map_err(|e| match e {
        CycleError::CreateDir { .. } => CliError(format!("--out {e}")),
        e => CliError(e.to_string()),
    })?;
    if !args.quiet {
        print_summary(&run, secs, pool.current_num_threads());
        for p in written {
            println!("  wrote {}", p.display());
        }
    }
    Ok(())
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
        let pick = |f: &dyn Fn(&polywear::cycle::summary::WheelSummary) -> f64| {
            let mut xs: Vec<f64> = all.iter().map(|s| f(&s[w])).collect();
            xs.sort_by(f64::total_cmp);
            let mean = xs.iter().sum::<f64>() / xs.len() as f64;
            if xs.len() == 1 {
                format!("{:.1}%", 100.0 * mean)
            } else {
                let q = polywear::cycle::summary::quantile;
                format!(
                    "{:.1}% (90% interval {:.1}-{:.1}%)",
                    100.0 * mean,
                    100.0 * q(&xs, 0.05),
                    100.0 * q(&xs, 0.95)
                )
            }
        };
        let mean = |f: &dyn Fn(&polywear::cycle::summary::WheelSummary) -> f64| {
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
            polywear::model::Wheel::BOTH[w].as_str(),
            pick(&|s| s.time_share),
            pick(&|s| s.distance_share),
            if all.len() > 1 { "(mean) " } else { "" },
            mean(&|s| s.longest_vibration_s),
            mean(&|s| s.longest_vibration_km),
            100.0 * mean(&|s| s.not_quasi_static_share),
        );
    }
}
