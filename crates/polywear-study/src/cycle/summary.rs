//! What a classified cycle means for each wheel: the share of time and of distance in
//! self-excited vibration, the longest continuous stretch in vibration, the polygon orders the
//! vibration has, and how much of the time the quasi-static verdict is in doubt. Over several
//! tire structures, each becomes a distribution (mean and 90% interval).

use std::collections::BTreeMap;

use super::wear::CycleWear;
use super::{DriveCycle, StepWheel};
use crate::parquet_out::Column;
use polywear_core::model::Wheel;

/// One wheel over one cycle (one tire structure).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelSummary {
    /// The wheel summarised.
    pub wheel: Wheel,
    /// Share of the cycle's time in vibration (limit cycle or bistable).
    pub time_share: f64,
    /// Share of the cycle's distance covered in vibration (0 when the cycle does not move).
    pub distance_share: f64,
    /// The longest run of consecutive vibrating steps \[s\].
    pub longest_vibration_s: f64,
    /// The distance covered in that longest run \[km\].
    pub longest_vibration_km: f64,
    /// Time in vibration \[s\].
    pub vibration_s: f64,
    /// Distance covered in vibration \[km\].
    pub vibration_km: f64,
    /// Share of the cycle's time at standstill (speed 0).
    pub standstill_share: f64,
    /// Share of the cycle's time where the quasi-static verdict does not hold.
    pub not_quasi_static_share: f64,
    /// Share of the vibrating time at each polygon order (rounded to the nearest whole number
    /// of facets); empty without vibration.
    pub order_shares: BTreeMap<i64, f64>,
    /// The polygon of a lifetime on this cycle, when the wear stage ran.
    pub wear: Option<CycleWear>,
    /// The same under each calibrated set of the fitted wear constants (the calibration band;
    /// empty without one).
    pub wear_band: Vec<CycleWear>,
}

impl WheelSummary {
    /// The distance to a visible polygon over the calibrated sets, (lowest, highest) \[km\];
    /// None without a band or where no set gives a distance.
    pub fn distance_band_km(&self) -> Option<(f64, f64)> {
        let d: Vec<f64> = self
            .wear_band
            .iter()
            .map(|c| c.distance_to_visible_km)
            .filter(|x| !x.is_nan())
            .collect();
        (!d.is_empty()).then(|| {
            (
                d.iter().copied().fold(f64::INFINITY, f64::min),
                d.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            )
        })
    }
}

/// Summarises wheel `w` (0 follower, 1 driving) of a classified cycle.
pub fn summarise(cycle: &DriveCycle, steps: &[[StepWheel; 2]], w: usize) -> WheelSummary {
    let dt = cycle.step_durations_s();
    let km = |i: usize| cycle.speed_kmh[i] * dt[i] / 3600.0;
    let total_s: f64 = dt.iter().sum();
    let total_km: f64 = (0..dt.len()).map(km).sum();
    let (mut vib_s, mut vib_km, mut still_s, mut doubt_s) = (0.0, 0.0, 0.0, 0.0);
    let (mut run_s, mut run_km, mut best_s, mut best_km) = (0.0, 0.0, 0.0_f64, 0.0_f64);
    let mut orders: BTreeMap<i64, f64> = BTreeMap::new();
    for (i, s) in steps.iter().enumerate() {
        let s = &s[w];
        if s.standstill() {
            still_s += dt[i];
        }
        if !s.quasi_static {
            doubt_s += dt[i];
        }
        if s.vibrates() {
            vib_s += dt[i];
            vib_km += km(i);
            run_s += dt[i];
            run_km += km(i);
            best_s = best_s.max(run_s);
            best_km = best_km.max(run_km);
            let n = s.record.polygon_order;
            if n.is_finite() {
                *orders.entry(n.round() as i64).or_default() += dt[i];
            }
        } else {
            run_s = 0.0;
            run_km = 0.0;
        }
    }
    let ordered: f64 = orders.values().sum();
    for v in orders.values_mut() {
        *v /= ordered;
    }
    WheelSummary {
        wheel: Wheel::BOTH[w],
        time_share: vib_s / total_s,
        distance_share: if total_km > 0.0 {
            vib_km / total_km
        } else {
            0.0
        },
        longest_vibration_s: best_s,
        longest_vibration_km: best_km,
        vibration_s: vib_s,
        vibration_km: vib_km,
        standstill_share: still_s / total_s,
        not_quasi_static_share: doubt_s / total_s,
        order_shares: orders,
        wear: None,
        wear_band: Vec::new(),
    }
}

/// The summary's numbers by column name (polygon orders as `order_N_share`).
fn named(s: &WheelSummary, orders: &[i64]) -> Vec<(String, f64)> {
    let mut v = vec![
        ("time_share".to_string(), s.time_share),
        ("distance_share".into(), s.distance_share),
        ("longest_vibration_s".into(), s.longest_vibration_s),
        ("longest_vibration_km".into(), s.longest_vibration_km),
        ("vibration_s".into(), s.vibration_s),
        ("vibration_km".into(), s.vibration_km),
        ("standstill_share".into(), s.standstill_share),
        ("not_quasi_static_share".into(), s.not_quasi_static_share),
    ];
    for n in orders {
        let share = s.order_shares.get(n).copied().unwrap_or(0.0);
        v.push((format!("order_{n}_share"), share));
    }
    if let Some(w) = &s.wear {
        v.extend([
            ("polygon_order_wear".to_string(), w.dominant_order),
            ("growth_rate_per_1000km".into(), w.growth_rate_per_1000km),
            ("distance_to_visible_km".into(), w.distance_to_visible_km),
            (
                "wear_unknown_distance_share".into(),
                w.unknown_distance_share,
            ),
            // Its old name, a copy kept for one version (RENAMED_COLUMNS).
            ("wear_dominant_order".into(), w.dominant_order),
            // Over the tread's life (NaN as the new tire).
            ("tread_life_km".into(), w.tread_life_km),
            ("wear_peak_share_of_visible".into(), w.peak_share_of_visible),
        ]);
        if !s.wear_band.is_empty() {
            let (lo, hi) = s.distance_band_km().unwrap_or((f64::NAN, f64::NAN));
            v.extend([
                ("distance_to_visible_km_band_low".to_string(), lo),
                ("distance_to_visible_km_band_high".into(), hi),
            ]);
        }
    }
    v
}

fn unit(name: &str) -> &'static str {
    if name.ends_with("_per_1000km") {
        "1/1000km"
    } else if name.ends_with("_s") {
        "s"
    } else if name.ends_with("_km") {
        "km"
    } else {
        "-"
    }
}

/// Quantile `q` of `xs` (sorted ascending; linear interpolation between order statistics, the
/// usual "type 7" definition).
pub fn quantile(xs: &[f64], q: f64) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    let h = (xs.len() - 1) as f64 * q;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    // Equal or infinite neighbours (a distance that never comes): no interpolation, which
    // would give inf − inf = NaN.
    if lo == hi || xs[lo] == xs[hi] || xs[hi].is_infinite() || xs[lo].is_infinite() {
        return if h > lo as f64 { xs[hi] } else { xs[lo] };
    }
    xs[lo] + (h - lo as f64) * (xs[hi] - xs[lo])
}

/// The summary table: one row per wheel with `statistic` = `value` for one tire structure; with
/// several (`per_sample[k][wheel]`), three rows per wheel: `mean`, `p05` and `p95` (the 90%
/// interval over the structures).
pub fn summary_columns(per_sample: &[[WheelSummary; 2]]) -> Vec<Column> {
    let mut orders: Vec<i64> = per_sample
        .iter()
        .flat_map(|s| s.iter().flat_map(|w| w.order_shares.keys().copied()))
        .collect();
    orders.sort_unstable();
    orders.dedup();
    let stats: &[&str] = if per_sample.len() == 1 {
        &["value"]
    } else {
        &["mean", "p05", "p95"]
    };
    let mut wheels = Vec::new();
    let mut statistic = Vec::new();
    let mut values: Vec<(String, Vec<f64>)> = named(&per_sample[0][0], &orders)
        .into_iter()
        .map(|(n, _)| (n, Vec::new()))
        .collect();
    for w in 0..2 {
        let table: Vec<Vec<(String, f64)>> =
            per_sample.iter().map(|s| named(&s[w], &orders)).collect();
        for stat in stats {
            wheels.push(Wheel::BOTH[w].as_str().to_string());
            statistic.push(stat.to_string());
            for (q, (_, col)) in values.iter_mut().enumerate() {
                let mut xs: Vec<f64> = table.iter().map(|r| r[q].1).collect();
                xs.sort_by(f64::total_cmp);
                col.push(match *stat {
                    "mean" => xs.iter().sum::<f64>() / xs.len() as f64,
                    "p05" => quantile(&xs, 0.05),
                    "p95" => quantile(&xs, 0.95),
                    _ => xs[0],
                });
            }
        }
    }
    let mut cols = vec![
        Column::str("wheel", wheels),
        Column::str("statistic", statistic),
    ];
    for (name, v) in values {
        let u = unit(&name);
        cols.push(Column::f64(name, u, v));
    }
    cols
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate() {
        let xs = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&xs, 0.0), 1.0);
        assert_eq!(quantile(&xs, 0.5), 3.0);
        assert!((quantile(&xs, 0.05) - 1.2).abs() < 1e-12);
        assert!((quantile(&xs, 0.95) - 4.8).abs() < 1e-12);
    }
}
