//! `polywear classify`: the verdict for every operating point of a CSV file, both wheels, in
//! parallel. For batches of specific points (measured conditions, a peer benchmark's set).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::common::{check_extension, check_out_file, BudgetArgs, CliResult, VariantArg};
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::solve_points;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::Params;
use polywear_core::records::WheelRecord;
use polywear_study::operating_points::FleetColumns;
use polywear_study::parquet_out::{write_csv, write_table};
use polywear_study::point_file::{output_columns, read_points, PointFile};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  printf 'speed_kmh,toe_deg\\n100,0.3\\n150,0.2\\n' > points.csv\n",
    "  polywear classify points.csv --out data/points_classified.csv\n",
    "  # a fleet's telematics file, as a study's [operating_points] reads it\n",
    "  polywear classify studies/fleet_telematics.csv --weight hours --out data/fleet_points.csv\n",
    "\nGuide: docs/book/src/reference/classify.md#classify"
))]
pub(crate) struct ClassifyArgs {
    /// CSV or Parquet with a header of parameter names (e.g. speed_kmh,toe_deg,load_n,pressure_kpa)
    /// and one operating point per row; other columns need --weight or --pass-through, missing
    /// parameters keep their defaults
    #[arg(value_name = "POINTS.csv")]
    pub(crate) points: PathBuf,
    /// Output: FILE.csv or FILE.parquet, one row per point and wheel (column `point` = row index);
    /// a missing folder is created
    #[arg(long, value_name = "FILE")]
    pub(crate) out: PathBuf,
    /// Friction variant: sliding_share (default), paper or combined (see `simulate --help`)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub(crate) variant: VariantArg,
    /// Parameter file for the parameters the file does not give (one it gives is refused)
    #[arg(long, value_name = "FILE")]
    pub(crate) params: Option<PathBuf>,
    /// The file's weight column (hours or km driven at each point; `km` without a km column is
    /// computed as hours * speed_kmh), carried into the output beside each point
    #[arg(long, value_name = "COLUMN")]
    pub(crate) weight: Option<String>,
    /// Columns that are no parameters (vehicle ids, a second weight), carried into the output
    /// unchanged, comma-separated
    #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
    pub(crate) pass_through: Vec<String>,
    /// Run values outside their plausible ranges (`polywear params`) anyway: a cell such as
    /// pressure_kpa = 2.4 (bar, not kPa) is refused before any work without it
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
}

pub(crate) fn run(args: &ClassifyArgs) -> CliResult {
    let request = resolve(args)?;
    let pool = super::common::thread_pool(args.threads)?;
    let start = Instant::now();
    let (jobs, records) =
        pool.install(|| solve_points(&request.points, request.variant, &request.opts));
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
    let file = read_points(
        &args.points,
        args.params.as_deref(),
        args.weight.as_deref(),
        &args.pass_through,
        args.accept_implausible,
    )?;
    for note in &file.notes {
        eprintln!("{note}");
    }
    let PointFile {
        points,
        fleet,
        base,
        ..
    } = file;
    Ok(ClassifyRequest {
        points,
        fleet,
        base,
        variant: args.variant.into(),
        opts,
    })
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
        meta.extend(fleet.metadata(&args.points));
        write_table(&args.out, &cols, &meta)?;
    }
    Ok(())
}
