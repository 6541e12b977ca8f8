//! `polywear simulate`: one operating point, both wheels: verdict, time series, plot.

use std::path::PathBuf;

use clap::Args;

use super::common::{
    base_metadata, check_extension, check_out_file, figure_file, BudgetArgs, CliError, CliResult,
    PointArgs, WheelArg,
};
use polywear_analysis::figures::trajectory::plot_point;
use polywear_analysis::plot::FigureFile;
use polywear_analysis::render::verdict::verdict_table;
use polywear_core::classify::ClassifierOptions;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::Params;
use polywear_study::parquet_out::{write_csv, write_table};
use polywear_study::trajectory::{series_columns, simulate_point, PointRun};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the default point, both wheels\n",
    "  polywear simulate\n",
    "  polywear simulate --speed 150 --toe 0.4 --variant paper --json\n",
    "  # figure and time series\n",
    "  polywear simulate --plot data/point.png --out data/point.parquet\n",
    "\nGuide: docs/book/src/reference/simulate.md#simulate"
))]
pub(crate) struct SimulateArgs {
    #[command(flatten)]
    pub(crate) point: PointArgs,
    /// Which wheel(s) to evaluate: front and rear are the wheels on those axles under --drivetrain
    #[arg(long, value_enum, default_value_t = WheelArg::Both)]
    pub(crate) wheel: WheelArg,
    /// Simulated time of the time series [s], accepted (0, 600]
    #[arg(
        long,
        value_name = "S",
        default_value_t = 5.0,
        allow_negative_numbers = true
    )]
    pub(crate) duration: f64,
    /// Sampling rate of the written/plotted time series [Hz], accepted [100, 1e6]
    #[arg(long, value_name = "HZ", default_value_t = 20_000.0)]
    pub(crate) sample_rate: f64,
    /// Hard-excitation check: also start at this lateral velocity amplitude [m/s] to find a
    /// limit cycle coexisting with a stable equilibrium (class `bistable`)
    #[arg(long, value_name = "MPS", allow_hyphen_values = true)]
    pub(crate) kick: Option<f64>,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
    /// Print one JSON object per wheel (the columns of tests/data/points.csv and more)
    #[arg(long)]
    pub(crate) json: bool,
    /// Write the time series (t, wheel, z, y, v) to FILE.parquet or FILE.csv (a missing folder
    /// is created)
    #[arg(long, value_name = "FILE")]
    pub(crate) out: Option<PathBuf>,
    /// Draw time history, phase portrait and spectrum of v to FILE.png or FILE.svg (a missing
    /// folder is created)
    #[arg(long, value_name = "FILE")]
    pub(crate) plot: Option<PathBuf>,
}

pub(crate) fn run(args: &SimulateArgs) -> CliResult {
    let request = resolve(args)?;
    // The time series only where a file needs it.
    let series = (request.out.is_some() || request.plot.is_some())
        .then_some((request.duration_s, request.sample_rate_hz));
    let run = simulate_point(
        request.params,
        request.variant,
        &request.wheels,
        &request.opts,
        series,
    );
    for w in &run.ended_early {
        eprintln!("warning: {w}");
    }
    write(args, &request, &run)
}

/// One `simulate`, checked: the point, its wheels, the classifier's options, and the files to
/// write.
struct SimulateRequest {
    params: Params,
    variant: Variant,
    wheels: Vec<Wheel>,
    opts: ClassifierOptions,
    duration_s: f64,
    sample_rate_hz: f64,
    out: Option<PathBuf>,
    plot: Option<FigureFile>,
}

/// Every flag checked, in the order the refusals name them, before any work starts.
fn resolve(args: &SimulateArgs) -> CliResult<SimulateRequest> {
    let params = args.point.params()?;
    if !(args.duration > 0.0 && args.duration <= 600.0) {
        return Err(CliError(format!(
            "--duration = {} s is outside its accepted range (0, 600] s",
            args.duration
        )));
    }
    if !(100.0..=1e6).contains(&args.sample_rate) {
        return Err(CliError(format!(
            "--sample-rate = {} Hz is outside its accepted range [100, 1e6] Hz",
            args.sample_rate
        )));
    }
    if let Some(k) = args.kick {
        if !(k > 0.0 && k.is_finite()) {
            return Err(CliError(format!(
                "--kick = {k} m/s is refused; accepted: a positive lateral velocity amplitude in m/s, e.g. 0.05"
            )));
        }
    }
    if let Some(out) = &args.out {
        check_extension(out, &["parquet", "csv"], "--out")?;
        check_out_file(out, "--out")?;
    }
    let plot = match &args.plot {
        Some(path) => {
            let file = figure_file(path, "--plot")?;
            check_out_file(path, "--plot")?;
            Some(file)
        }
        None => None,
    };
    let opts = ClassifierOptions {
        kick_mps: args.kick,
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    Ok(SimulateRequest {
        params,
        variant: args.point.variant.into(),
        wheels: args.wheel.wheels(params.drivetrain),
        opts,
        duration_s: args.duration,
        sample_rate_hz: args.sample_rate,
        out: args.out.clone(),
        plot,
    })
}

/// The verdicts (a table, or JSON lines with `--json`), then the time series and the plot.
fn write(args: &SimulateArgs, request: &SimulateRequest, run: &PointRun) -> CliResult {
    let PointRun {
        records, series, ..
    } = run;
    if args.json {
        for r in records {
            println!("{}", serde_json::to_string(r).expect("record serializes"));
        }
    } else {
        print!("{}", verdict_table(records));
    }
    if let Some(out) = &request.out {
        let cols = series_columns(series);
        if out.extension().is_some_and(|e| e == "csv") {
            write_csv(out, &cols)?;
        } else {
            write_table(out, &cols, &base_metadata(&request.params, request.variant))?;
        }
        eprintln!("wrote time series to {}", out.display());
    }
    if let Some(file) = &request.plot {
        plot_point(file, series, records, request.sample_rate_hz)
            .map_err(|e| CliError(e.to_string()))?;
        eprintln!("wrote plot to {}", file.path.display());
    }
    Ok(())
}
