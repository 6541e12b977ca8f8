//! `polywear chart`: every Hopf curve of both wheels in the plane of two parameters, with the
//! frequency, the first Lyapunov coefficient and the criticality along them.

use std::path::PathBuf;

use clap::Args;

use super::common::{
    check_extension, check_out_file, CliError, CliResult, PointArgs, Resolved, WheelArg,
};
use polywear_analysis::figures::chart::{draw, SHADE_CELLS};
use polywear_analysis::plot::{FigureFile, FigureFormat};
use polywear_core::continuation::trace::TraceOptions;
use polywear_core::continuation::ParamBox;
use polywear_core::params::{ParamError, ParamId};
use polywear_study::chart::band::{band_study, structure_band, StructureBand};
use polywear_study::chart::files::{band_words, heading, write_band_tables, write_tables};
use polywear_study::chart::{summary, ChartError, ChartRequest};

/// Cells per axis of the uncertainty band's grid.
const BAND_CELLS: usize = 100;

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # speed x toe-in, both wheels: Hopf curves, l1, Bautin points, picture\n",
    "  polywear chart --x speed_kmh --x-from 60 --x-to 250 --y toe_deg --y-from 0.05 --y-to 0.6 \\\n",
    "      --out data/chart_speed_toe.parquet\n",
    "  # load x pressure at 120 km/h, follower only\n",
    "  polywear chart --x load_n --x-from 2000 --x-to 8000 --y pressure_kpa --y-from 150 \\\n",
    "      --y-to 350 --speed 120 --wheel follower --out data/chart_load_pressure.parquet\n",
    "  # the boundary's uncertainty band over 64 tire structures of a study\n",
    "  polywear chart --x speed_kmh --x-from 60 --x-to 250 --y toe_deg --y-from 0.05 --y-to 0.6 \\\n",
    "      --study studies/default.toml --structure-samples 64 --out data/chart_band.parquet\n",
    "\nGuide: docs/book/src/reference/chart.md#stability-charts"
))]
pub(crate) struct ChartArgs {
    /// Parameter on the horizontal axis, by name (see `polywear params`), e.g. speed_kmh
    #[arg(long, value_name = "NAME")]
    pub(crate) x: String,
    /// Lower end of the horizontal axis (in the parameter's unit)
    #[arg(long = "x-from", value_name = "VALUE", allow_negative_numbers = true)]
    pub(crate) x_from: f64,
    /// Upper end of the horizontal axis
    #[arg(long = "x-to", value_name = "VALUE", allow_negative_numbers = true)]
    pub(crate) x_to: f64,
    /// Parameter on the vertical axis, e.g. toe_deg
    #[arg(long, value_name = "NAME")]
    pub(crate) y: String,
    /// Lower end of the vertical axis
    #[arg(long = "y-from", value_name = "VALUE", allow_negative_numbers = true)]
    pub(crate) y_from: f64,
    /// Upper end of the vertical axis
    #[arg(long = "y-to", value_name = "VALUE", allow_negative_numbers = true)]
    pub(crate) y_to: f64,
    /// Which wheel's curves to trace: front and rear are the wheels on those axles under --drivetrain
    #[arg(long, value_enum, default_value_t = WheelArg::Both)]
    pub(crate) wheel: WheelArg,
    /// The operating point and other parameters; the nominal point marked on the chart
    #[command(flatten)]
    pub(crate) point: PointArgs,
    /// Output table FILE.parquet; FILE.csv, FILE_special.parquet/.csv and FILE.png are written
    /// beside it
    #[arg(long, value_name = "FILE.parquet")]
    pub(crate) out: PathBuf,
    /// Study file whose distributions of the non-operating parameters (tire structure,
    /// friction, vehicle; not the chart's axes) are drawn for the boundary's uncertainty band
    #[arg(long, value_name = "STUDY.toml", requires = "structure_samples")]
    pub(crate) study: Option<PathBuf>,
    /// Number of tire structures drawn from --study, accepted [2, 10000]; the chart then shows
    /// where 5% to 95% of them put each wheel's boundary, and FILE_band.parquet/.csv hold the
    /// unstable share per grid cell
    #[arg(long, value_name = "K", requires = "study", allow_negative_numbers = true,
          value_parser = super::common::whole_in::<u64>("--structure-samples", 2, 10_000))]
    pub(crate) structure_samples: Option<u64>,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
}

/// An axis: its parameter, checked by name, range and plausibility (unless `accept`), with the
/// flags named in errors.
fn axis(name: &str, from: f64, to: f64, flag: &str, accept: bool) -> CliResult<ParamId> {
    let id: ParamId = name
        .parse()
        .map_err(|e: ParamError| CliError(format!("--{flag}: {e}")))?;
    let s = id.spec();
    for (which, v) in [("from", from), ("to", to)] {
        s.check(v)
            .map_err(|e| CliError(format!("--{flag}-{which}: {e}")))?;
        if !accept {
            s.check_plausible(v)
                .map_err(|e| CliError(format!("--{flag}-{which}: {e}")))?;
        }
    }
    if from >= to {
        return Err(CliError(format!(
            "--{flag}-from = {from} must be below --{flag}-to = {to} (the range of {} is empty or inverted; accepted values {} {})",
            s.name,
            s.range_text(),
            s.unit
        )));
    }
    Ok(id)
}

/// Checks the request and builds it, before any work.
pub(crate) fn request(args: &ChartArgs) -> CliResult<(ChartRequest, Resolved)> {
    let accept = args.point.accept_implausible;
    let x = axis(&args.x, args.x_from, args.x_to, "x", accept)?;
    let y = axis(&args.y, args.y_from, args.y_to, "y", accept)?;
    if x == y {
        return Err(CliError(format!(
            "--x and --y are both `{x}`; a chart needs two different parameters"
        )));
    }
    let resolved = args.point.resolve()?;
    super::common::sweep_owns(x, &format!("--x {x}"), &resolved)?;
    super::common::sweep_owns(y, &format!("--y {y}"), &resolved)?;
    let base = resolved.params;
    // Every corner must be a valid parameter set (e.g. mu_s on an axis may not exceed mu_m).
    let flag = |v: f64, from: f64, axis: &str| {
        format!("--{axis}-{}", if v == from { "from" } else { "to" })
    };
    let req = ChartRequest::new(
        base,
        args.point.variant.into(),
        args.wheel.wheels(base.drivetrain),
        (x, y),
        ParamBox {
            lo: [args.x_from, args.y_from],
            hi: [args.x_to, args.y_to],
        },
    )
    .map_err(|e| match e {
        ChartError::Corner {
            x_value,
            y_value,
            reason,
            ..
        } => CliError(format!(
            "corner {}, {}: {reason}",
            flag(x_value, args.x_from, "x"),
            flag(y_value, args.y_from, "y")
        )),
        e => CliError(e.to_string()),
    })?;
    check_extension(&args.out, &["parquet"], "--out")?;
    check_out_file(&args.out, "--out")?;
    Ok((req, resolved))
}

pub(crate) fn run(args: &ChartArgs) -> CliResult {
    let (req, resolved) = request(args)?;
    let band_plan = match (&args.study, args.structure_samples) {
        (Some(path), Some(k)) => Some((
            band_study(path, k, &req, &resolved, args.point.accept_implausible)?,
            k,
        )),
        _ => None,
    };
    let pool = super::common::thread_pool(args.threads)?;
    let opts = TraceOptions::default();
    let started = std::time::Instant::now();
    let (charts, grids) = pool.install(|| (req.trace(&opts), req.stability_grids(SHADE_CELLS)));
    let chart_s = started.elapsed().as_secs_f64();
    let band: Option<StructureBand> = band_plan
        .as_ref()
        .map(|(study, k)| pool.install(|| structure_band(&req, study, study.seed, *k, BAND_CELLS)));
    println!("{}", heading(&req, chart_s));
    for line in summary(&req, &charts) {
        println!("{line}");
    }
    let meta = req.metadata(&opts);
    let files = write_tables(&args.out, &req, &charts, &meta)?;
    if let (Some(b), Some((study, k))) = (&band, &band_plan) {
        println!("{}", band_words(b, study, *k));
        write_band_tables(&args.out, &req, b, &meta, study, *k)?;
    }
    let picture = FigureFile::beside(&args.out, FigureFormat::Png);
    draw(&picture, &req, &charts, &grids, band.as_ref()).map_err(|e| CliError(e.to_string()))?;
    eprintln!(
        "wrote {}, {}, {}, {} and {}",
        files.table.display(),
        files.csv.display(),
        files.special.display(),
        files.special_csv.display(),
        picture.path.display()
    );
    Ok(())
}
