//! What `polywear wear` writes: the summary (one row per wheel), the history, the profiles
//! and the figure, each with the run's metadata.

use super::super::common::{CliError, CliResult};
use super::{Plan, WearArgs, WheelOutcome, DRAWN_ORDERS};
use polywear_analysis::plot::wear::{wear_figure, WearTrace};
use polywear_analysis::plot::FigureFile;
use polywear_core::params::Params;
use polywear_core::wear::long_term::{WheelWear, FEEDBACK_ORDERS};
use polywear_core::wear::WearEstimate;
use polywear_study::parquet_out::{write_csv, write_table, Column};

/// An `estimate_*` column: name, unit and how it reads a wheel's estimate.
type EstimateColumn = (&'static str, &'static str, fn(&WearEstimate) -> f64);

/// The summary's figures of one wheel (NaN where undefined).
pub(super) struct Figures {
    pub(super) dominant: f64,
    pub(super) detuning: f64,
    pub(super) locked: bool,
    pub(super) lock_halfwidth_hz: f64,
    pub(super) even: f64,
    pub(super) growth_mm: f64,
    pub(super) growth_rate: f64,
    pub(super) saturation_mm: f64,
    pub(super) distance_km: f64,
}

pub(super) fn figures(o: &WheelOutcome<'_>, p: &Params) -> Figures {
    let nan = f64::NAN;
    let Ok(run) = &o.run else {
        return Figures {
            dominant: nan,
            detuning: nan,
            locked: false,
            lock_halfwidth_hz: nan,
            even: nan,
            growth_mm: nan,
            growth_rate: nan,
            saturation_mm: nan,
            distance_km: nan,
        };
    };
    let n = run.dominant_order();
    let e = run.end();
    let i = n as usize - 1;
    let nu = o.solution.verdict.polygon_order;
    // The tongue measured at the end; NaN where no leg is locked or it could not be measured.
    let lock_halfwidth_hz = match &o.tongue {
        Ok(Some(t)) => t.halfwidth_hz,
        _ => nan,
    };
    Figures {
        dominant: n as f64,
        detuning: nu - n as f64,
        locked: run.locked_speed_kmh().is_some(),
        lock_halfwidth_hz,
        even: run.even_wear_m_per_m * 1e9,
        growth_mm: e.depth_rate_m_per_m[i] * 1e9,
        growth_rate: run.linear_growth_per_m(n) * 1e6,
        saturation_mm: run.saturation_depth_m() * 1e3,
        distance_km: run.distance_to_visible_km(p.visible_depth_mm * 1e-3),
    }
}

fn summary_columns(p: &Params, wheels: &[WheelOutcome<'_>], estimate: bool) -> Vec<Column> {
    let f: Vec<Figures> = wheels.iter().map(|w| figures(w, p)).collect();
    let col = |name: &str, unit: &'static str, get: &dyn Fn(&Figures) -> f64| {
        Column::f64(name, unit, f.iter().map(get).collect())
    };
    let mut cols = vec![
        Column::str(
            "wheel",
            wheels
                .iter()
                .map(|w| w.wheel.as_str().to_string())
                .collect(),
        ),
        Column::str(
            "class",
            wheels
                .iter()
                .map(|w| w.solution.verdict.class.to_string())
                .collect(),
        ),
        Column::f64(
            "polygon_order",
            "",
            wheels
                .iter()
                .map(|w| w.solution.verdict.polygon_order)
                .collect(),
        ),
        col("dominant_order", "", &|x| x.dominant),
        col("detuning_rev", "", &|x| x.detuning),
        Column::i64("locked", "", f.iter().map(|x| x.locked as i64).collect()),
        col("lock_halfwidth_hz", "Hz", &|x| x.lock_halfwidth_hz),
        col("wear_even_mm_per_1000km", "mm/1000 km", &|x| x.even),
        col("growth_mm_per_1000km", "mm/1000 km", &|x| x.growth_mm),
        col("growth_rate_per_1000km", "1/1000 km", &|x| x.growth_rate),
        col("saturation_depth_mm", "mm", &|x| x.saturation_mm),
        col("distance_to_visible_km", "km", &|x| x.distance_km),
        Column::f64(
            "wear_calibration_share",
            "",
            vec![p.wear_share_straight; wheels.len()],
        ),
    ];
    if estimate {
        let est = |get: &dyn Fn(&WearEstimate) -> f64| -> Vec<f64> {
            wheels
                .iter()
                .map(|w| w.solution.wear.as_ref().map_or(f64::NAN, get))
                .collect()
        };
        let columns: [EstimateColumn; 4] = [
            ("estimate_dominant_order", "", |e| e.polygon_order_dominant),
            ("estimate_detuning_rev", "", |e| e.detuning_rev),
            ("estimate_growth_rate_per_1000km", "1/1000 km", |e| {
                e.growth_rate_per_1000km
            }),
            ("estimate_distance_to_visible_km", "km", |e| {
                e.distance_to_visible_km
            }),
        ];
        for (name, unit, get) in columns {
            cols.push(Column::f64(name, unit, est(&get)));
        }
    }
    cols
}

/// The history: one row per wheel, step and order.
fn history_columns(wheels: &[WheelOutcome<'_>]) -> Vec<Column> {
    let (mut wheel, mut km, mut order, mut depth, mut height) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for w in wheels {
        let Ok(run) = &w.run else { continue };
        for h in &run.history {
            for (n, d) in h.depths_m.iter().enumerate() {
                wheel.push(w.wheel.as_str().to_string());
                km.push(h.distance_km);
                order.push(n as i64 + 1);
                depth.push(d * 1e3);
                height.push(h.tread_height_m * 1e3);
            }
        }
    }
    vec![
        Column::str("wheel", wheel),
        Column::f64("distance_km", "km", km),
        Column::i64("order", "", order),
        Column::f64("depth_mm", "mm", depth),
        Column::f64("tread_height_mm", "mm", height),
    ]
}

/// The profiles: one row per wheel, chosen distance and cell.
fn profile_columns(wheels: &[WheelOutcome<'_>]) -> Vec<Column> {
    let (mut wheel, mut km, mut angle, mut depth) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for w in wheels {
        let Ok(run) = &w.run else { continue };
        for (s, d) in &run.profiles {
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            for (i, x) in d.iter().enumerate() {
                wheel.push(w.wheel.as_str().to_string());
                km.push(*s);
                angle.push(360.0 * (i as f64 + 0.5) / d.len() as f64);
                depth.push((x - mean) * 1e3);
            }
        }
    }
    vec![
        Column::str("wheel", wheel),
        Column::f64("distance_km", "km", km),
        Column::f64("angle_deg", "deg", angle),
        Column::f64("depth_mm", "mm", depth),
    ]
}

pub(super) fn write_outputs(
    args: &WearArgs,
    plan: &Plan,
    wheels: &[WheelOutcome<'_>],
) -> CliResult {
    let dir = &args.out;
    polywear_study::safe_write::create_dir(dir)
        .map_err(|e| CliError(format!("--out {}: {e}", dir.display())))?;
    let err = |e: &dyn std::fmt::Display| CliError(e.to_string());
    let mut meta = plan.metadata.clone();
    meta.push((
        "profile".into(),
        "depth_mm: the worn depth minus its mean (r = -depth); depth peak-to-valley in history"
            .into(),
    ));
    let summary = summary_columns(&plan.params, wheels, args.estimate);
    write_csv(&dir.join("wear_summary.csv"), &summary).map_err(|e| err(&e))?;
    write_table(&dir.join("wear_summary.parquet"), &summary, &meta).map_err(|e| err(&e))?;
    write_table(
        &dir.join("wear_history.parquet"),
        &history_columns(wheels),
        &meta,
    )
    .map_err(|e| err(&e))?;
    write_table(
        &dir.join("wear_profile.parquet"),
        &profile_columns(wheels),
        &meta,
    )
    .map_err(|e| err(&e))?;
    let traces: Vec<WearTrace> = wheels
        .iter()
        .filter_map(|w| w.run.as_ref().ok().map(|r| (w.wheel, r)))
        .map(|(wheel, r)| WearTrace {
            wheel: wheel.as_str(),
            profiles: &r.profiles,
            depths: drawn_depths(r),
            visible_mm: plan.params.visible_depth_mm,
        })
        .collect();
    if !traces.is_empty() {
        let figure = FigureFile::named(dir, "wear", args.format);
        let title = format!("polywear wear: {}", plan.usage);
        wear_figure(&figure, &title, &traces).map_err(|e| err(&e))?;
    }
    Ok(())
}

/// The [`DRAWN_ORDERS`] deepest orders at the end, their depth \[mm\] against distance.
fn drawn_depths(run: &WheelWear) -> Vec<(u32, Vec<(f64, f64)>)> {
    let end = &run.end().depths_m;
    let mut orders: Vec<usize> = (0..end.len().min(FEEDBACK_ORDERS)).collect();
    orders.sort_by(|a, b| end[*b].total_cmp(&end[*a]));
    orders
        .into_iter()
        .take(DRAWN_ORDERS)
        .map(|i| {
            let pts = run
                .history
                .iter()
                .map(|h| (h.distance_km, h.depths_m[i] * 1e3))
                .collect();
            (i as u32 + 1, pts)
        })
        .collect()
}
