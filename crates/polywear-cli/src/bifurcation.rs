//! `polywear bifurcation`: a 1-D sweep of any parameter for both wheels, in parallel, with the
//! Hopf points located by root-finding on the leading eigenvalue's real part.

use std::path::PathBuf;

use clap::Args;
use polywear_analysis::plot::{FigureFile, FigureFormat};
use polywear_analysis::render::sweep::sweep_lines;

use super::common::{BudgetArgs, CliError, CliResult, PointArgs};
use polywear_core::classify::ClassifierOptions;
use polywear_core::model::Variant;
use polywear_core::params::{ParamError, ParamId, Params};
use polywear_core::wording::plain;
use polywear_study::bifurcation::{linspace, sweep};
use polywear_study::parquet_out::write_table;

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  polywear bifurcation --param speed_kmh --from 40 --to 260 --steps 221\n",
    "  polywear bifurcation --param toe_deg --from 0.05 --to 1 --params studies/params_r0.toml\n",
    "\nGuide: docs/book/src/reference/bifurcation.md#bifurcation"
))]
pub(crate) struct BifurcationArgs {
    /// Parameter to sweep, by name (see `polywear params`), e.g. speed_kmh, toe_deg, load_n
    #[arg(long, value_name = "NAME")]
    pub(crate) param: String,
    /// First value of the sweep (in the parameter's unit)
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) from: f64,
    /// Last value of the sweep
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) to: f64,
    /// Number of values, accepted [2, 100000]
    #[arg(long, default_value_t = 101, allow_negative_numbers = true, value_parser = super::common::whole_in::<usize>("--steps", 2, 100_000))]
    pub(crate) steps: usize,
    #[command(flatten)]
    pub(crate) point: PointArgs,
    /// Hard-excitation check at each value (lateral velocity amplitude [m/s])
    #[arg(long, value_name = "MPS")]
    pub(crate) kick: Option<f64>,
    #[command(flatten)]
    pub(crate) budget: BudgetArgs,
    /// Output prefix: writes PREFIX.parquet and PREFIX.png (or .svg); a missing folder is
    /// created [default: data/bifurcation_<param>]
    #[arg(long, value_name = "PREFIX")]
    pub(crate) out: Option<PathBuf>,
    /// File type of the figure
    #[arg(long, default_value_t = FigureFormat::Png, value_parser = super::common::figure_formats())]
    pub(crate) format: FigureFormat,
    /// Worker threads (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub(crate) threads: Option<usize>,
}

pub(crate) fn run(args: &BifurcationArgs) -> CliResult {
    let req = resolve(args)?;
    let values = linspace(args.from, args.to, args.steps);
    let pool = super::common::thread_pool(args.threads)?;
    let sw = pool.install(|| sweep(&req.base, req.param, &values, req.variant, &req.opts));
    for line in sweep_lines(&sw, (args.from, args.to), args.steps) {
        println!("{line}");
    }
    write(args, &req, &sw)
}

/// The sweep the flags ask for, checked before any work.
struct SweepRequest {
    base: Params,
    param: ParamId,
    variant: Variant,
    opts: ClassifierOptions,
    /// The output files' path without extension (its folder created).
    prefix: PathBuf,
}

fn resolve(args: &BifurcationArgs) -> CliResult<SweepRequest> {
    let resolved = args.point.resolve()?;
    let base = resolved.params;
    let param: ParamId = args
        .param
        .parse()
        .map_err(|e: ParamError| CliError(format!("--param: {e}")))?;
    super::common::sweep_owns(param, &format!("--param {param}"), &resolved)?;
    let s = param.spec();
    if !(2..=100_000).contains(&args.steps) {
        return Err(CliError(format!(
            "--steps = {} is outside its accepted range [2, 100000]",
            args.steps
        )));
    }
    for (flag, v) in [("--from", args.from), ("--to", args.to)] {
        s.check(v).map_err(|e| CliError(format!("{flag}: {e}")))?;
        if !args.point.accept_implausible {
            s.check_plausible(v)
                .map_err(|e| CliError(format!("{flag}: {e}")))?;
        }
        let mut p = base;
        p.try_set(param, v)?;
        p.validate().map_err(|e| CliError(format!("{flag}: {e}")))?;
    }
    if args.from == args.to {
        return Err(CliError(format!(
            "--from and --to are both {}; accepted: two different values of {} in its range {} {}",
            plain(args.from, 12),
            s.name,
            s.range_text(),
            s.unit
        )));
    }
    if let Some(k) = args.kick {
        if k.is_nan() || k <= 0.0 {
            return Err(CliError(format!(
                "--kick = {k} m/s is refused; accepted: a positive lateral velocity amplitude in m/s, e.g. 0.05"
            )));
        }
    }
    let prefix = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("data/bifurcation_{}", s.name)));
    if let Some(dir) = prefix.parent().filter(|d| !d.as_os_str().is_empty()) {
        polywear_study::safe_write::create_dir(dir)
            .map_err(|e| CliError(format!("--out {}: {e}", dir.display())))?;
    }
    let variant: Variant = args.point.variant.into();
    let opts = ClassifierOptions {
        kick_mps: args.kick,
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    Ok(SweepRequest {
        base,
        param,
        variant,
        opts,
        prefix,
    })
}

/// The sweep's table (Parquet, with the Hopf points in its metadata) and picture.
fn write(
    args: &BifurcationArgs,
    req: &SweepRequest,
    sw: &polywear_study::bifurcation::Sweep,
) -> CliResult {
    let pq = req.prefix.with_extension("parquet");
    write_table(&pq, &sw.columns(), &sw.metadata())?;
    let figure = FigureFile::beside(&req.prefix, args.format);
    polywear_analysis::figures::bifurcation::draw(&figure, sw)
        .map_err(|e| CliError(e.to_string()))?;
    eprintln!("wrote {} and {}", pq.display(), figure.path.display());
    Ok(())
}
