//! `polywear classify`: the verdict for every operating point of a CSV file, both wheels, in
//! parallel. For batches of specific points (measured conditions, a peer benchmark's set).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use super::common::{check_extension, check_out_file, BudgetArgs, CliError, CliResult, VariantArg};
use polywear::classify::ClassifierOptions;
use polywear::ensemble::{self, Control};
use polywear::evaluate;
use polywear::model::{Variant, Wheel};
use polywear::params::{ParamError, ParamId, Params};
use polywear::parquet_out::{write_csv, write_table, Column};
use polywear::records::{record_columns, WheelRecord};
use polywear::table_input::csv_records;

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  printf 'speed_kmh,toe_deg\\n100,0.3\\n150,0.2\\n' > points.csv\n",
    "  polywear classify points.csv --out data/points_classified.csv\n",
    "\nGuide: GUIDE.md#classify"
))]
pub struct ClassifyArgs {
    /// CSV with a header of parameter names (e.g. speed_kmh,toe_deg,load_n,pressure_kpa) and
    /// one operating point per row; other columns are refused, missing parameters keep defaults
    #[arg(value_name = "POINTS.csv")]
    pub points: PathBuf,
    /// Output: FILE.csv or FILE.parquet, one row per point and wheel (column `point` = row index);
    /// a missing folder is created
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Friction variant: sliding_share (default), paper or combined (see `simulate --help`)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub variant: VariantArg,
    /// Parameter file for the parameters the CSV does not give
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

/// Reads the points: each row applied on top of `base` and validated, before any work.
fn read_points(path: &std::path::Path, base: &Params) -> CliResult<Vec<Params>> {
    let text = super::common::read_input(path, "", polywear::safe_read::Limit::Table)?;
    let records = csv_records(path, &text).map_err(|e| CliError(e.to_string()))?;
    let mut lines = records.into_iter().map(|(_, cells)| cells);
    let header: Vec<ParamId> = lines
        .next()
        .ok_or_else(|| CliError(format!("{}: empty file", path.display())))?
        .iter()
        .map(|h| {
            h.parse()
                .map_err(|e: ParamError| CliError(format!("{}: column `{h}`: {e}", path.display())))
        })
        .collect::<CliResult<_>>()?;
    for (i, name) in header.iter().enumerate() {
        if header[..i].contains(name) {
            return Err(CliError(format!(
                "{}: column `{name}` appears more than once in the header",
                path.display()
            )));
        }
    }
    let mut out = Vec::new();
    for (i, cells) in lines.enumerate() {
        if cells.len() != header.len() {
            return Err(CliError(format!(
                "{}: row {} has {} cells, the header {}",
                path.display(),
                i + 1,
                cells.len(),
                header.len()
            )));
        }
        let mut p = *base;
        for (&name, cell) in header.iter().zip(&cells) {
            let v: f64 = cell.parse().map_err(|_| {
                CliError(format!(
                    "{}: row {}, `{name}` = `{cell}` is not a number; accepted: a number in the parameter's unit",
                    path.display(),
                    i + 1
                ))
            })?;
            p.try_set(name, v)
                .map_err(|e| CliError(format!("{}: row {}: {e}", path.display(), i + 1)))?;
        }
        p.validate()
            .map_err(|e| CliError(format!("{}: row {}: {e}", path.display(), i + 1)))?;
        out.push(p);
    }
    Ok(out)
}

pub fn run(args: &ClassifyArgs) -> CliResult {
    check_extension(&args.out, &["csv", "parquet"], "--out")?;
    check_out_file(&args.out, "--out")?;
    let opts = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let base = super::common::base_params(args.params.as_deref())?;
    let points = read_points(&args.points, &base)?;
    let variant: Variant = args.variant.into();
    let pool = super::common::thread_pool(args.threads)?;
    let start = Instant::now();
    let jobs: Vec<(usize, Wheel)> = (0..points.len())
        .flat_map(|i| Wheel::BOTH.map(|w| (i, w)))
        .collect();
    let record = |k: usize| {
        let (i, wheel) = jobs[k];
        evaluate::solve_wheel(points[i], variant, wheel, &opts).record
    };
    let records: Vec<WheelRecord> =
        pool.install(|| ensemble::solve(jobs.len(), record, &Control::QUIET).all());
    let secs = start.elapsed().as_secs_f64();
    let mut cols = vec![Column::i64(
        "point",
        "",
        jobs.iter().map(|j| j.0 as i64).collect(),
    )];
    cols.extend(record_columns(&records));
    if args.out.extension().is_some_and(|e| e == "csv") {
        write_csv(&args.out, &cols)?;
    } else {
        write_table(
            &args.out,
            &cols,
            &super::common::base_metadata(&base, variant),
        )?;
    }
    eprintln!(
        "classified {} points x 2 wheels in {secs:.3} s ({:.0} points/s, {} threads) -> {}",
        points.len(),
        points.len() as f64 / secs.max(1e-9),
        pool.current_num_threads(),
        args.out.display()
    );
    Ok(())
}
