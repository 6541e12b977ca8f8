//! `polywear simulate`: one operating point, both wheels: verdict, time series, plot.

use std::path::{Path, PathBuf};

use clap::Args;

use super::common::{base_metadata, check_extension, CliError, CliResult, PointArgs, WheelArg};
use polywear::classify::{classify_point, ClassifierOptions, Scales};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::parquet_out::{write_csv, write_table, Column};
use polywear::plot::{self, Series};
use polywear::records::WheelRecord;
use polywear::solver::{sample_uniform, SolverOptions};

#[derive(Debug, Args)]
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
    /// Print one JSON object per wheel (the columns of reference/points.csv and more)
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
    }
    if let Some(plot) = &args.plot {
        check_extension(plot, &["png"], "--plot")?;
    }
    let variant: Variant = args.point.variant.into();
    let opts = ClassifierOptions {
        kick_mps: args.kick,
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
                series.push((wheel, time_series(m, args, &opts)));
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

type Samples = Vec<(f64, [f64; 3])>;

/// Trajectory from the disturbed equilibrium (MODEL.md step 9) on a uniform grid.
fn time_series(m: &WheelModel, args: &SimulateArgs, opts: &ClassifierOptions) -> Samples {
    let scales = Scales::new(&m.ode);
    let x0 = [scales.z_eq, scales.y_eq + opts.disturbance_m, 0.0];
    let sopts = SolverOptions {
        rtol: 1e-9,
        atol: scales.atol(1e-9),
        h_max: 1e-3,
        h0: None,
        max_steps: 100_000_000,
    };
    let (samples, outcome) =
        sample_uniform(&m.ode, x0, args.duration, 1.0 / args.sample_rate, &sopts);
    if let Err(e) = outcome {
        eprintln!("warning: {} wheel time series ends early: {e}", m.wheel);
    }
    samples
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

fn plot_point(
    path: &Path,
    series: &[(Wheel, Samples)],
    records: &[WheelRecord],
    sample_rate: f64,
) -> Result<(), String> {
    let r0 = records.first().ok_or("nothing to plot")?;
    let title = format!(
        "{} km/h, toe {} deg, {} N, {} kPa ({} variant)",
        r0.speed_kmh, r0.toe_deg, r0.load_n, r0.pressure_kpa, r0.variant
    );
    let label = |w: Wheel| {
        let class = records
            .iter()
            .find(|r| r.wheel == w.as_str())
            .map_or("", |r| r.class);
        format!("{w} ({class})")
    };
    let labels: Vec<String> = series.iter().map(|(w, _)| label(*w)).collect();
    // Displacements are drawn about each wheel's equilibrium y0.
    let y0 = |w: Wheel| {
        records
            .iter()
            .find(|r| r.wheel == w.as_str())
            .map_or(0.0, |r| r.y0_m)
    };
    let series: Vec<(Wheel, Samples)> = series
        .iter()
        .map(|(w, s)| {
            (
                *w,
                s.iter()
                    .map(|(t, x)| (*t, [x[0], x[1] - y0(*w), x[2]]))
                    .collect(),
            )
        })
        .collect();
    let series = &series;
    plot::panels(path, (1500, 1000), (2, 2), &title, |i, area| {
        let make = |f: &dyn Fn(&Samples) -> Vec<(f64, f64)>| -> Vec<Series<'_>> {
            series
                .iter()
                .zip(&labels)
                .map(|((_, s), l)| Series {
                    label: l,
                    points: f(s),
                })
                .collect()
        };
        match i {
            0 => plot::line_panel(
                area,
                "Lateral velocity",
                "t [s]",
                "v [m/s]",
                &make(&|s| s.iter().map(|x| (x.0, x.1[2])).collect()),
                false,
            ),
            1 => {
                let tail = |s: &Samples| -> Vec<(f64, f64)> {
                    let t_end = s.last().map_or(0.0, |x| x.0);
                    s.iter()
                        .filter(|x| x.0 >= t_end - 0.05)
                        .map(|x| (x.0, x.1[1]))
                        .collect()
                };
                plot::line_panel(
                    area,
                    "Lateral displacement, last 50 ms",
                    "t [s]",
                    "y - y0 [m]",
                    &make(&tail),
                    false,
                )
            }
            2 => {
                let phase = |s: &Samples| -> Vec<(f64, f64)> {
                    let t_end = s.last().map_or(0.0, |x| x.0);
                    s.iter()
                        .filter(|x| x.0 >= t_end * 0.5)
                        .map(|x| (x.1[1], x.1[2]))
                        .collect()
                };
                plot::line_panel(
                    area,
                    "Phase portrait (second half)",
                    "y - y0 [m]",
                    "v [m/s]",
                    &make(&phase),
                    false,
                )
            }
            _ => {
                let spec = |s: &Samples| -> Vec<(f64, f64)> {
                    let half: Vec<f64> = s[s.len() / 2..].iter().map(|x| x.1[2]).collect();
                    plot::spectrum::amplitude_spectrum(&half, sample_rate)
                        .into_iter()
                        .filter(|(f, _)| *f <= 1000.0)
                        .collect()
                };
                plot::line_panel(
                    area,
                    "Spectrum of v (second half)",
                    "frequency [Hz]",
                    "amplitude [m/s]",
                    &make(&spec),
                    false,
                )
            }
        }
    })
}
