//! `polywear bifurcation`: a 1-D sweep of any parameter for both wheels, in parallel, with the
//! Hopf points located by root-finding on the leading eigenvalue's real part.

use std::path::PathBuf;

use clap::Args;
use rayon::prelude::*;

use super::common::{base_metadata, CliError, CliResult, PointArgs};
use polywear::classify::{classify_point, ClassifierOptions};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::numeric::brent;
use polywear::params::{spec, Params};
use polywear::parquet_out::{write_table, Column};
use polywear::plot::{self, Series};
use polywear::records::{record_columns, WheelRecord};

#[derive(Debug, Args)]
pub struct BifurcationArgs {
    /// Parameter to sweep, by name (see `polywear params`), e.g. speed_kmh, toe_deg, load_n
    #[arg(long, value_name = "NAME")]
    pub param: String,
    /// First value of the sweep (in the parameter's unit)
    #[arg(long, allow_negative_numbers = true)]
    pub from: f64,
    /// Last value of the sweep
    #[arg(long, allow_negative_numbers = true)]
    pub to: f64,
    /// Number of values, accepted [2, 100000]
    #[arg(long, default_value_t = 101)]
    pub steps: usize,
    #[command(flatten)]
    pub point: PointArgs,
    /// Hard-excitation check at each value (lateral velocity amplitude [m/s])
    #[arg(long, value_name = "MPS")]
    pub kick: Option<f64>,
    /// Output prefix: writes PREFIX.parquet and PREFIX.png [default: data/bifurcation_<param>]
    #[arg(long, value_name = "PREFIX")]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
}

/// A located Hopf point.
#[derive(Debug, Clone, Copy)]
pub struct HopfPoint {
    pub wheel: Wheel,
    pub value: f64,
    /// True when the equilibrium loses stability as the parameter increases.
    pub destabilizing: bool,
}

fn eig_re(p: &Params, name: &str, x: f64, wheel: Wheel, variant: Variant) -> f64 {
    let mut q = *p;
    *q.get_mut(name).expect("name checked") = x;
    WheelModel::build(&q, wheel, variant).map_or(f64::NAN, |m| m.ode.linear_stability().eig_re_max)
}

pub fn run(args: &BifurcationArgs) -> CliResult {
    let base = args.point.params()?;
    let s = spec(&args.param).ok_or_else(|| {
        CliError(
            polywear::params::ParamError::Unknown {
                name: args.param.clone(),
            }
            .to_string(),
        )
    })?;
    if !(2..=100_000).contains(&args.steps) {
        return Err(CliError(format!(
            "--steps = {} is outside its accepted range [2, 100000]",
            args.steps
        )));
    }
    for (flag, v) in [("--from", args.from), ("--to", args.to)] {
        s.check(v).map_err(|e| CliError(format!("{flag}: {e}")))?;
        let mut p = base;
        p.set(s.name, v)?;
        p.validate().map_err(|e| CliError(format!("{flag}: {e}")))?;
    }
    if args.from == args.to {
        return Err(CliError("--from and --to must differ".into()));
    }
    if let Some(k) = args.kick {
        if k.is_nan() || k <= 0.0 {
            return Err(CliError(format!(
                "--kick = {k} m/s must be a positive number"
            )));
        }
    }
    let prefix = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("data/bifurcation_{}", s.name)));
    if let Some(dir) = prefix.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError(format!("--out {}: {e}", dir.display())))?;
    }
    let variant: Variant = args.point.variant.into();
    let opts = ClassifierOptions {
        kick_mps: args.kick,
        ..ClassifierOptions::default()
    };
    let values: Vec<f64> = (0..args.steps)
        .map(|i| args.from + (args.to - args.from) * i as f64 / (args.steps - 1) as f64)
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError(format!("cannot start threads: {e}")))?;
    let jobs: Vec<(f64, Wheel)> = values
        .iter()
        .flat_map(|&x| Wheel::BOTH.map(|w| (x, w)))
        .collect();
    let records: Vec<WheelRecord> = pool.install(|| {
        jobs.par_iter()
            .map(|&(x, wheel)| {
                let mut p = base;
                *p.get_mut(s.name).expect("known") = x;
                let (model, verdict) = classify_point(&p, wheel, variant, &opts);
                WheelRecord::new(&p, wheel, variant, &model, &verdict)
            })
            .collect()
    });
    let hopf = locate_hopf(&base, s.name, &jobs, &records, variant);

    println!(
        "sweep of {} from {} to {} {} ({} values, variant {variant})",
        s.name, args.from, args.to, s.unit, args.steps
    );
    for wheel in Wheel::BOTH {
        let rows: Vec<&WheelRecord> = records
            .iter()
            .filter(|r| r.wheel == wheel.as_str())
            .collect();
        let vib = rows
            .iter()
            .filter(|r| r.class == "limit_cycle" || r.class == "bistable")
            .count();
        println!("{wheel:>9}: {vib} of {} values vibrate", rows.len());
        for h in hopf.iter().filter(|h| h.wheel == wheel) {
            println!(
                "           Hopf point at {} = {:.6} {} ({} as it increases)",
                s.name,
                h.value,
                s.unit,
                if h.destabilizing {
                    "loses stability"
                } else {
                    "regains stability"
                }
            );
        }
    }

    // The swept value gets its own column (the parameter may also be a record column).
    let mut cols = vec![Column::f64(
        "sweep_value",
        s.unit,
        jobs.iter().map(|j| j.0).collect(),
    )];
    cols.extend(record_columns(&records));
    let mut meta = base_metadata(&base, variant);
    meta.push(("sweep_param".into(), s.name.into()));
    let hopf_json: Vec<serde_json::Value> = hopf
        .iter()
        .map(|h| serde_json::json!({"wheel": h.wheel.as_str(), "value": h.value, "destabilizing": h.destabilizing}))
        .collect();
    meta.push((
        "hopf_points".into(),
        serde_json::Value::from(hopf_json).to_string(),
    ));
    let pq = prefix.with_extension("parquet");
    write_table(&pq, &cols, &meta)?;
    let png = prefix.with_extension("png");
    draw(&png, s.name, s.unit, variant, &jobs, &records, &hopf).map_err(CliError)?;
    eprintln!("wrote {} and {}", pq.display(), png.display());
    Ok(())
}

/// Brent on Re λ between neighbouring sweep values whose signs differ, to 1e-6 relative.
fn locate_hopf(
    base: &Params,
    name: &str,
    jobs: &[(f64, Wheel)],
    records: &[WheelRecord],
    variant: Variant,
) -> Vec<HopfPoint> {
    let mut out = Vec::new();
    for wheel in Wheel::BOTH {
        let pts: Vec<(f64, f64)> = jobs
            .iter()
            .zip(records)
            .filter(|(j, _)| j.1 == wheel)
            .map(|(j, r)| (j.0, r.eig_re_max))
            .collect();
        for w in pts.windows(2) {
            let ((x0, f0), (x1, f1)) = (w[0], w[1]);
            if f0.is_finite() && f1.is_finite() && (f0 < 0.0) != (f1 < 0.0) {
                let tol = 1e-7 * x0.abs().max(x1.abs());
                if let Some(x) = brent(|x| eig_re(base, name, x, wheel, variant), x0, x1, tol, 200)
                {
                    out.push(HopfPoint {
                        wheel,
                        value: x,
                        destabilizing: (f1 > f0) == (x1 > x0),
                    });
                }
            }
        }
    }
    out
}

/// Points drawn for one sweep value and its record.
type PointsOf = dyn Fn(f64, &WheelRecord) -> Vec<(f64, f64)>;

fn draw(
    path: &std::path::Path,
    name: &str,
    unit: &str,
    variant: Variant,
    jobs: &[(f64, Wheel)],
    records: &[WheelRecord],
    hopf: &[HopfPoint],
) -> Result<(), String> {
    let per_wheel = |f: &PointsOf| -> Vec<(Wheel, Vec<(f64, f64)>)> {
        Wheel::BOTH
            .iter()
            .map(|&w| {
                let pts = jobs
                    .iter()
                    .zip(records)
                    .filter(|(j, _)| j.1 == w)
                    .flat_map(|(j, r)| f(j.0, r))
                    .collect();
                (w, pts)
            })
            .collect()
    };
    let eig = per_wheel(&|x, r| vec![(x, r.eig_re_max)]);
    let amp = per_wheel(&|x, r| vec![(x, r.amp_y_m * 1e3), (x, -r.amp_y_m * 1e3)]);
    let hopf_text: Vec<String> = hopf
        .iter()
        .map(|h| format!("{} {:.4}", h.wheel, h.value))
        .collect();
    let title = format!(
        "Bifurcation in {name} ({variant} variant); Hopf: {}",
        if hopf_text.is_empty() {
            "none".into()
        } else {
            hopf_text.join(", ")
        }
    );
    let x_label = format!("{name} [{unit}]");
    plot::panels(path, (1300, 1100), (2, 1), &title, |i, area| {
        let (data, title, y, points) = if i == 0 {
            (
                &eig,
                "Real part of the leading eigenvalue (Fig. 6)",
                "max Re(lambda) [1/s]",
                false,
            )
        } else {
            (
                &amp,
                "Limit-cycle envelope of y - y0 (Figs. 7, 12, 14, 16)",
                "+/- amplitude of y [mm]",
                true,
            )
        };
        let series: Vec<Series<'_>> = data
            .iter()
            .map(|(w, pts)| Series {
                label: w.as_str(),
                points: pts.clone(),
            })
            .collect();
        plot::line_panel(area, title, &x_label, y, &series, points)
    })
}
