//! `polywear validate`: the fast classifier against the brute-force reference on random points.

use std::path::PathBuf;

use clap::Args;

use super::common::{check_extension, BudgetArgs, CliError, CliResult};
use polywear_core::classify::ClassifierOptions;
use polywear_core::params::OPERATING_AXES;
use polywear_study::parquet_out::{write_csv, Column};
use polywear_study::validation::{compare_with, median, Comparison, HOPF_BAND};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  polywear validate --points 340 --seed 1 --out data/validate_340.csv\n",
    "\nGuide: docs/book/src/reference/validate.md#validate"
))]
pub struct ValidateArgs {
    /// Random operating points (each evaluated for 2 wheels × 3 variants), accepted [1, 100000]
    #[arg(long, default_value_t = 300, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--points", 1, 100_000))]
    pub points: u64,
    /// Seed of the point set, accepted [0, 4398046510080]
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = super::common::whole_in::<u64>("--seed", 0, polywear_study::study::SEED_MAX))]
    pub seed: u64,
    /// Worker threads for the reference (default: all cores), accepted [1, 1024]
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = super::common::parse_threads)]
    pub threads: Option<usize>,
    /// Per-wheel results as CSV
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub budget: BudgetArgs,
}

pub fn run(args: &ValidateArgs) -> CliResult {
    if !(1..=100_000).contains(&args.points) {
        return Err(CliError(format!(
            "--points = {} is outside [1, 100000]",
            args.points
        )));
    }
    if let Some(out) = &args.out {
        check_extension(out, &["csv"], "--out")?;
    }
    let opts = ClassifierOptions {
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let pool = super::common::thread_pool(args.threads)?;
    eprintln!(
        "classifying {} points x 2 wheels x 3 variants, fast and brute force (this takes minutes)...",
        args.points
    );
    let rows = pool.install(|| compare_with(args.seed, args.points, &opts));
    report(&rows);
    if let Some(out) = &args.out {
        write_rows(out, &rows)?;
        eprintln!("wrote {}", out.display());
    }
    let disagreements = rows
        .iter()
        .filter(|r| r.compared() && !r.classes_agree())
        .count();
    if disagreements > 0 {
        return Err(CliError(format!(
            "{disagreements} class disagreements outside the Hopf band"
        )));
    }
    Ok(())
}

fn report(rows: &[Comparison]) {
    let compared: Vec<&Comparison> = rows.iter().filter(|r| r.compared()).collect();
    let agree = compared.iter().filter(|r| r.classes_agree()).count();
    let cycles: Vec<&&Comparison> = compared
        .iter()
        .filter(|r| r.classes_agree() && r.fast.class.vibrates())
        .collect();
    let worst = cycles
        .iter()
        .map(|r| r.worst_relative_error())
        .fold(0.0, f64::max);
    let within = cycles
        .iter()
        .filter(|r| r.worst_relative_error() < 0.01)
        .count();
    println!("wheels evaluated:                      {}", rows.len());
    println!(
        "outside the Hopf band (|Re λ| >= {HOPF_BAND}): {} ({} limit cycles by the reference)",
        compared.len(),
        compared
            .iter()
            .filter(|r| r.reference.class.vibrates())
            .count()
    );
    println!(
        "class agreement there:                 {agree} / {}",
        compared.len()
    );
    println!(
        "limit cycles with amp_y, amp_v, freq within 1%: {within} / {} (worst {:.3}%)",
        cycles.len(),
        100.0 * worst
    );
    for r in compared.iter().filter(|r| !r.classes_agree()) {
        println!(
            "  DISAGREE #{} {} {}: fast {} ({}), reference {} (re {:.4})",
            r.index,
            r.wheel,
            r.variant,
            r.fast.class.as_str(),
            r.fast.reason,
            r.reference.class.as_str(),
            r.fast.eig_re_max
        );
    }
    let stat = |f: &dyn Fn(&Comparison) -> f64, sel: &dyn Fn(&Comparison) -> bool| {
        median(rows.iter().filter(|r| sel(r)).map(f).collect())
    };
    let all = |_: &Comparison| true;
    let lc = |r: &Comparison| r.fast.class.vibrates();
    println!();
    println!("cost per wheel (median, single thread)      fast classifier    brute-force reference   ratio");
    for (label, sel) in [
        ("all wheels", &all as &dyn Fn(&Comparison) -> bool),
        ("limit cycles only", &lc),
    ] {
        let (fu, ru) = (stat(&|r| r.fast_us, sel), stat(&|r| r.reference_us, sel));
        let (fe, re) = (
            stat(&|r| r.fast.rhs_evals as f64, sel),
            stat(&|r| r.reference.rhs_evals as f64, sel),
        );
        println!(
            "  {label:<20} time [µs]         {fu:>12.1}    {ru:>18.1}   {:>8.0}x",
            ru / fu
        );
        println!(
            "  {label:<20} RHS evaluations   {fe:>12.0}    {re:>18.0}   {:>8.0}x",
            re / fe.max(1.0)
        );
    }
}

fn write_rows(path: &std::path::Path, rows: &[Comparison]) -> CliResult {
    let f = |g: &dyn Fn(&Comparison) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let mut cols = vec![
        Column::i64("point", "", rows.iter().map(|r| r.index as i64).collect()),
        Column::str("wheel", rows.iter().map(|r| r.wheel.to_string()).collect()),
        Column::str(
            "variant",
            rows.iter().map(|r| r.variant.to_string()).collect(),
        ),
    ];
    for id in OPERATING_AXES {
        cols.push(Column::f64(id.name(), id.spec().unit, f(&|r| r.params[id])));
    }
    cols.extend([
        Column::f64("eig_re_max", "1/s", f(&|r| r.fast.eig_re_max)),
        Column::str(
            "fast_class",
            rows.iter().map(|r| r.fast.class.as_str().into()).collect(),
        ),
        Column::str(
            "reference_class",
            rows.iter()
                .map(|r| r.reference.class.as_str().into())
                .collect(),
        ),
        Column::f64("fast_amp_v_mps", "m/s", f(&|r| r.fast.amp_v_mps)),
        Column::f64("reference_amp_v_mps", "m/s", f(&|r| r.reference.amp_v_mps)),
        Column::f64("fast_freq_hz", "Hz", f(&|r| r.fast.freq_hz)),
        Column::f64("reference_freq_hz", "Hz", f(&|r| r.reference.freq_hz)),
        Column::f64("fast_us", "us", f(&|r| r.fast_us)),
        Column::f64("reference_us", "us", f(&|r| r.reference_us)),
        Column::f64("fast_rhs_evals", "", f(&|r| r.fast.rhs_evals as f64)),
        Column::f64(
            "reference_rhs_evals",
            "",
            f(&|r| r.reference.rhs_evals as f64),
        ),
    ]);
    write_csv(path, &cols)?;
    Ok(())
}
