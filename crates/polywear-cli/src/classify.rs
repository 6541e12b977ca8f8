//! `polywear classify`: the verdict for every operating point of a CSV file, both wheels, in
//! parallel. For batches of specific points (measured conditions, a peer benchmark's set).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::common::{check_extension, check_out_file, BudgetArgs, CliError, CliResult, VariantArg};
use polywear_core::classify::ClassifierOptions;
use polywear_core::ensemble::{self, Control};
use polywear_core::evaluate;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::Params;
use polywear_core::records::{record_columns, WheelRecord};
use polywear_study::operating_points::{FleetColumns, FleetKeys};
use polywear_study::parquet_out::{write_csv, write_table, Column};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  printf 'speed_kmh,toe_deg\\n100,0.3\\n150,0.2\\n' > points.csv\n",
    "  polywear classify points.csv --out data/points_classified.csv\n",
    "  # a fleet's telematics file, as a study's [operating_points] reads it\n",
    "  polywear classify studies/fleet_telematics.csv --weight hours --out data/fleet_points.csv\n",
    "\nGuide: docs/book/src/reference/classify.md#classify"
))]
pub struct ClassifyArgs {
    /// CSV or Parquet with a header of parameter names (e.g. speed_kmh,toe_deg,load_n,pressure_kpa)
    /// and one operating point per row; other columns need --weight or --pass-through, missing
    /// parameters keep their defaults
    #[arg(value_name = "POINTS.csv")]
    pub points: PathBuf,
    /// Output: FILE.csv or FILE.parquet, one row per point and wheel (column `point` = row index);
    /// a missing folder is created
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Friction variant: sliding_share (default), paper or combined (see `simulate --help`)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub variant: VariantArg,
    /// Parameter file for the parameters the file does not give (one it gives is refused)
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// The file's weight column (hours or km driven at each point; `km` without a km column is
    /// computed as hours * speed_kmh), carried into the output beside each point
    #[arg(long, value_name = "COLUMN")]
    pub weight: Option<String>,
    /// Columns that are no parameters (vehicle ids, a second weight), carried into the output
    /// unchanged, comma-separated
    #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
    pub pass_through: Vec<String>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a cell such as
    /// pressure_kpa = 2.4 (bar, not kPa) is refused before any work without it
    #[arg(long)]
    pub accept_implausible: bool,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

/// The keys of the weight and passed-through columns, as classify's flags.
const KEYS: FleetKeys = FleetKeys {
    weight: "--weight",
    pass_through: "--pass-through",
};

/// Reads the points, each row applied on top of the defaults (or `--params`) and validated,
/// before any work; a parameter both in `--params` and the file is refused.
fn read_points(args: &ClassifyArgs) -> CliResult<(Vec<Params>, FleetColumns, Params)> {
    let accept = args.accept_implausible;
    let (base, named) = super::common::param_file(args.params.as_deref(), accept)?;
    let path = &args.points;
    let (f, t) = FleetColumns::read(path, args.weight.as_deref(), &args.pass_through, KEYS)
        .map_err(|e| CliError(e.to_string()))?;
    if f.ids.is_empty() {
        return Err(CliError(format!(
            "{}: no parameter column (columns: {}); name parameters of `polywear params`, e.g. speed_kmh,toe_deg",
            path.display(),
            t.columns.join(", ")
        )));
    }
    if !accept {
        f.check_plausible().map_err(|e| CliError(e.to_string()))?;
    }
    if let (Some(file), Some(id)) = (&args.params, named.iter().find(|id| f.ids.contains(id))) {
        return Err(CliError(format!(
            "--params {} sets `{id}`, which {} gives per point (column `{id}`); a parameter comes from one file: remove it from one of them",
            file.display(),
            path.display()
        )));
    }
    let carried = f
        .weight
        .iter()
        .map(String::as_str)
        .chain(f.pass_through.iter().map(|c| c.name.as_str()));
    super::common::refuse_reserved_names(carried, path, "--weight or --pass-through", &["point"])?;
    let mut points = Vec::with_capacity(f.values.len());
    for (i, row) in f.values.iter().enumerate() {
        let mut p = base;
        for (&id, &x) in f.ids.iter().zip(row) {
            p[id] = x;
        }
        p.validate()
            .map_err(|e| CliError(format!("{}, {}: {e}", path.display(), t.row_name(i))))?;
        points.push(p);
    }
    if let Some(how) = &f.weight_computed {
        eprintln!(
            "{}",
            polywear_study::operating_points::computed_weight_note(path, how)
        );
    }
    Ok((points, f, base))
}

/// The output's columns: `point`, the weight and the passed-through columns, the records.
fn output_columns(
    jobs: &[(usize, Wheel)],
    f: &FleetColumns,
    records: &[WheelRecord],
) -> Vec<Column> {
    let rows: Vec<usize> = jobs.iter().map(|j| j.0).collect();
    let mut cols = vec![Column::i64(
        "point",
        "",
        rows.iter().map(|&r| r as i64).collect(),
    )];
    if let Some(w) = &f.weight {
        if !f.pass_through.iter().any(|c| &c.name == w) {
            cols.push(Column::f64(
                w.as_str(),
                "",
                rows.iter().map(|&r| f.weights[r]).collect(),
            ));
        }
    }
    cols.extend(f.pass_through.iter().map(|c| c.column(&rows)));
    cols.extend(record_columns(records));
    cols
}

pub fn run(args: &ClassifyArgs) -> CliResult {
    let request = resolve(args)?;
    let pool = super::common::thread_pool(args.threads)?;
    let start = Instant::now();
    let (jobs, records) = pool.install(|| classify(&request));
    let secs = start.elapsed().as_secs_f64();
    write(args, &request, &jobs, &records)?;
    eprintln!(
        "classified {} points x 2 wheels in {secs:.3} s ({:.0} points/s, {} threads) -> {}",
        request.points.len(),
        request.points.len() as f64 / secs.max(1e-9),
        pool.current_num_threads(),
        args.out.display()
    );
    Ok(())
}

/// One `classify`, checked: every point's parameters, the file's columns, the base parameters,
/// the variant and the classifier's options.
struct ClassifyRequest {
    points: Vec<Params>,
    fleet: FleetColumns,
    base: Params,
    variant: Variant,
    opts: ClassifierOptions,
}

/// `--out`, the budget and the points file, checked before any work.
fn resolve(args: &ClassifyArgs) -> CliResult<ClassifyRequest> {
    check_extension(&args.out, &["csv", "parquet"], "--out")?;
    check_out_file(&args.out, "--out")?;
    let opts = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let (points, fleet, base) = read_points(args)?;
    Ok(ClassifyRequest {
        points,
        fleet,
        base,
        variant: args.variant.into(),
        opts,
    })
}

/// Both wheels of every point through the ensemble: the (point, wheel) jobs and their records,
/// in the points' order.
fn classify(request: &ClassifyRequest) -> (Vec<(usize, Wheel)>, Vec<WheelRecord>) {
    let jobs: Vec<(usize, Wheel)> = (0..request.points.len())
        .flat_map(|i| Wheel::BOTH.map(|w| (i, w)))
        .collect();
    let record = |k: usize| {
        let (i, wheel) = jobs[k];
        evaluate::solve_wheel(request.points[i], request.variant, wheel, &request.opts).record
    };
    let records = ensemble::solve(jobs.len(), record, &Control::QUIET).all();
    (jobs, records)
}

/// The rows as CSV, or as Parquet with the run's metadata (and the points file's, for a fleet).
fn write(
    args: &ClassifyArgs,
    request: &ClassifyRequest,
    jobs: &[(usize, Wheel)],
    records: &[WheelRecord],
) -> CliResult {
    let fleet = &request.fleet;
    let cols = output_columns(jobs, fleet, records);
    if args.out.extension().is_some_and(|e| e == "csv") {
        write_csv(&args.out, &cols)?;
    } else {
        let mut meta = super::common::base_metadata(&request.base, request.variant);
        if fleet.weight.is_some() || !fleet.pass_through.is_empty() {
            meta.push(("points".into(), args.points.display().to_string()));
            meta.push(("weight".into(), fleet.weight.clone().unwrap_or_default()));
            meta.push(("weight_kind".into(), fleet.weight_kind.as_str().into()));
            if let Some(how) = &fleet.weight_computed {
                meta.push(("weight_computed".into(), how.clone()));
            }
        }
        write_table(&args.out, &cols, &meta)?;
    }
    Ok(())
}
