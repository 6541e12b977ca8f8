//! `polywear simulate`: one operating point, both wheels: verdict, time series, plot.

use std::path::{Path, PathBuf};

use clap::Args;

use super::common::{
    base_metadata, check_extension, check_out_file, BudgetArgs, CliError, CliResult, PointArgs,
    WheelArg,
};
use polywear::classify::{classify_point, ClassifierOptions};
use polywear::model::{Variant, Wheel};
use polywear::parquet_out::{write_csv, write_table, Column};
use polywear::records::WheelRecord;
use polywear::trajectory::{plot_point, time_series, Samples};

#[derive(Debug, Args)]
#[command(after_help = concat!(
    "Examples:\n",
    "  # the default point, both wheels\n",
    "  polywear simulate\n",
    "  polywear simulate --speed 150 --toe 0.4 --variant paper --json\n",
    "  # figure and time series\n",
    "  polywear simulate --plot data/point.png --out data/point.parquet\n",
    "\nGuide: GUIDE.md#simulate"
))]
pub struct SimulateArgs {
    #[command(flatten)]
    pub point: PointArgs,
    /// Which wheel(s) to evaluate
    #[arg(long, value_enum, default_value_t = WheelArg::Both)]
    pub wheel: WheelArg,
    /// Simulated time of the time series [s], accepted (0, 600]
    #[arg(
        long,
        value_name = "S",
        default_value_t = 5.0,
        allow_negative_numbers = true
    )]
    pub duration: f64,
    /// Sampling rate of the written/plotted time series [Hz], accepted [100, 1e6]
    #[arg(long, value_name = "HZ", default_value_t = 20_000.0)]
    pub sample_rate: f64,
    /// Hard-excitation check: also start at this lateral velocity amplitude [m/s] to find a
    /// limit cycle coexisting with a stable equilibrium (class `bistable`)
    #[arg(long, value_name = "MPS", allow_negative_numbers = true)]
    pub kick: Option<f64>,
    #[command(flatten)]
    pub budget: BudgetArgs,
    /// Print one JSON object per wheel (the columns of tests/data/points.csv and more)
    #[arg(long)]
    pub json: bool,
    /// Write the time series (t, wheel, z, y, v) to FILE.parquet or FILE.csv
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Draw time history, phase portrait and spectrum of v to FILE.png
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

pub fn run(args: &SimulateArgs) -> CliResult {
    let p = args.point.params()?;
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
                "--kick = {k} m/s must be a positive number"
            )));
        }
    }
    if let Some(out) = &args.out {
        check_extension(out, &["parquet", "csv"], "--out")?;
        check_out_file(out, "--out")?;
    }
    if let Some(plot) = &args.plot {
        check_extension(plot, &["png"], "--plot")?;
        check_out_file(plot, "--plot")?;
    }
    let variant: Variant = args.point.variant.into();
    let opts = ClassifierOptions {
        kick_mps: args.kick,
        budget: args.budget.apply(Default::default())?,
        ..ClassifierOptions::default()
    };
    let wheels = args.wheel.wheels();

    let mut records = Vec::new();
    let mut series = Vec::new();
    for &wheel in &wheels {
        let (model, verdict) = classify_point(&p, wheel, variant, &opts);
        records.push(WheelRecord::new(&p, wheel, variant, &model, &verdict));
        if let Ok(m) = &model {
            if args.out.is_some() || args.plot.is_some() {
                series.push((
                    wheel,
                    time_series(m, args.duration, args.sample_rate, opts.disturbance_m),
                ));
            }
        }
    }

    if args.json {
        for r in &records {
            println!("{}", serde_json::to_string(r).expect("record serializes"));
        }
    } else {
        print_table(&records);
    }
    if let Some(out) = &args.out {
        write_series(out, &series, &p, variant)?;
        eprintln!("wrote time series to {}", out.display());
    }
    if let Some(path) = &args.plot {
        plot_point(path, &series, &records, args.sample_rate).map_err(CliError)?;
        eprintln!("wrote plot to {}", path.display());
    }
    Ok(())
}

fn print_table(records: &[WheelRecord]) {
    let Some(first) = records.first() else { return };
    println!(
        "operating point: {} km/h, toe {} deg, load {} N, pressure {} kPa, variant {}",
        first.speed_kmh, first.toe_deg, first.load_n, first.pressure_kpa, first.variant
    );
    type Cell = fn(&WheelRecord) -> String;
    let rows: [(&str, Cell); 14] = [
        ("class", |r| r.class.to_string()),
        ("slip ratio", |r| format!("{:.6}", r.slip_ratio)),
        ("contact length [m]", |r| {
            format!("{:.5}", r.contact_length_m)
        }),
        ("contact width [m]", |r| format!("{:.5}", r.contact_width_m)),
        ("K_s [N/m]", |r| format!("{:.4e}", r.k_s)),
        ("F_m / F_s [N]", |r| format!("{:.1} / {:.1}", r.f_m, r.f_s)),
        ("eig re max [1/s]", |r| format!("{:.4}", r.eig_re_max)),
        ("eig freq [Hz]", |r| format!("{:.2}", r.eig_freq_hz)),
        ("amplitude y [m]", |r| format!("{:.4e}", r.amp_y_m)),
        ("amplitude v [m/s]", |r| format!("{:.4e}", r.amp_v_mps)),
        ("cycle freq [Hz]", |r| format!("{:.2}", r.freq_hz)),
        ("polygon order", |r| format!("{:.2}", r.polygon_order)),
        ("energy/cycle [J]", |r| {
            format!("{:.4e}", r.energy_per_cycle_j)
        }),
        ("Floquet max |mu|", |r| format!("{:.4}", r.floquet_max)),
    ];
    print!("{:<20}", "");
    for r in records {
        print!("{:>22}", r.wheel);
    }
    println!();
    for (label, f) in rows {
        print!("{label:<20}");
        for r in records {
            print!("{:>22}", f(r));
        }
        println!();
    }
    for r in records.iter().filter(|r| !r.reason.is_empty()) {
        println!("{}: {}", r.wheel, r.reason);
    }
}

fn write_series(
    path: &Path,
    series: &[(Wheel, Samples)],
    p: &polywear::params::Params,
    variant: Variant,
) -> CliResult {
    let all = || {
        series
            .iter()
            .flat_map(|(w, s)| s.iter().map(move |x| (*w, x)))
    };
    let cols = vec![
        Column::str(
            "wheel",
            all().map(|(w, _)| w.as_str().to_string()).collect(),
        ),
        Column::f64("t_s", "s", all().map(|(_, x)| x.0).collect()),
        Column::f64("z_m", "m", all().map(|(_, x)| x.1[0]).collect()),
        Column::f64("y_m", "m", all().map(|(_, x)| x.1[1]).collect()),
        Column::f64("v_mps", "m/s", all().map(|(_, x)| x.1[2]).collect()),
    ];
    if path.extension().is_some_and(|e| e == "csv") {
        write_csv(path, &cols)?;
    } else {
        write_table(path, &cols, &base_metadata(p, variant))?;
    }
    Ok(())
}
