//! The long-term run as columns: the summary (one row per wheel), the history (per wheel, step
//! and order) and the profiles (per wheel, chosen distance and cell).

use super::{LongTermFigures, LongTermSolution, WheelLongTerm};
use crate::columns::Column;
use crate::wear::LifeAnswer;

impl LongTermSolution {
    /// One row per wheel: class, orders, lock, rates, the distance to a visible polygon, how the
    /// run ended (a polygon, the tyre worn out, the distance) and the tread's ageing;
    /// with `estimate`, the per-sample estimator's `estimate_*` columns beside them.
    pub fn summary_columns(&self, estimate: bool) -> Vec<Column> {
        let p = &self.params;
        let wheels = &self.wheels;
        let f: Vec<LongTermFigures> = wheels.iter().map(|w| w.figures(p)).collect();
        let col = |name: &str, unit: &'static str, get: &dyn Fn(&LongTermFigures) -> f64| {
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
                "axle",
                wheels
                    .iter()
                    .map(|w| w.solution.record.axle.as_str().to_string())
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
                    .map(|w| w.solution.record.polygon_order)
                    .collect(),
            ),
            col("polygon_order_wear", "", &|x| x.dominant_order),
            col("detuning_rev", "", &|x| x.detuning_rev),
            // 1 or 0, NaN where the wheel has no run (as every figure of a wheel without one).
            Column::f64(
                "locked",
                "",
                f.iter()
                    .zip(wheels)
                    .map(|(x, w)| match w.run {
                        Ok(_) => f64::from(u8::from(x.locked)),
                        Err(_) => f64::NAN,
                    })
                    .collect(),
            ),
            col("lock_halfwidth_hz", "Hz", &|x| x.lock_halfwidth_hz),
            col("wear_even_mm_per_1000km", "mm/1000 km", &|x| {
                x.even_mm_per_1000km
            }),
            col("growth_mm_per_1000km", "mm/1000 km", &|x| {
                x.growth_mm_per_1000km
            }),
            col("growth_rate_per_1000km", "1/1000 km", &|x| {
                x.growth_rate_per_1000km
            }),
            col("saturation_depth_mm", "mm", &|x| x.saturation_depth_mm),
            col("distance_to_visible_km", "km", &|x| {
                x.distance_to_visible_km
            }),
            Column::str(
                "run_end",
                f.iter()
                    .map(|x| x.ended.map_or("", |e| e.as_str()).to_string())
                    .collect(),
            ),
            col("worn_out_km", "km", &|x| x.worn_out_km),
            col("tread_height_end_mm", "mm", &|x| x.tread_height_end_mm),
            col("tread_freq_start_hz", "Hz", &|x| x.tread_freq_start_hz),
            col("tread_freq_end_hz", "Hz", &|x| x.tread_freq_end_hz),
            Column::f64(
                "wear_share_straight",
                "",
                vec![p.wear_share_straight; wheels.len()],
            ),
        ];
        if estimate {
            cols.extend(self.estimate_columns());
        }
        // The summary's old names, copies kept for one version (in RENAMED_COLUMNS, so the
        // Parquet footer's `deprecated` lists them), at the end so the new names keep their
        // places.
        for (old, new) in [
            ("wear_calibration_share", "wear_share_straight"),
            ("dominant_order", "polygon_order_wear"),
            ("estimate_dominant_order", "estimate_polygon_order_wear"),
        ] {
            if let Some(c) = cols.iter().find(|c| c.name == new) {
                let mut alias = c.clone();
                alias.name = old.to_string();
                cols.push(alias);
            }
        }
        cols
    }

    /// The estimator's columns beside the loop's: the one wear answer (`estimate_*`, for a
    /// drive cycle its legs', MODEL.md#the-forced-response-saturates) and the same on the loop's
    /// own legs (`estimate_on_legs_*`); the new tire's detuning and growth of the answer's
    /// order at a cruise's point (NaN on a cycle, whose point is not what it drives).
    fn estimate_columns(&self) -> Vec<Column> {
        let wheels = &self.wheels;
        let mut cols = Vec::new();
        type Reading = fn(&WheelLongTerm) -> Option<&LifeAnswer>;
        let readings: [(&str, Reading); 2] = [
            ("estimate", |w| w.estimate.as_ref()),
            ("estimate_on_legs", |w| w.on_legs.as_ref()),
        ];
        for (prefix, reading) in readings {
            let of = |get: &dyn Fn(&LifeAnswer) -> f64| -> Vec<f64> {
                wheels
                    .iter()
                    .map(|w| reading(w).map_or(f64::NAN, get))
                    .collect()
            };
            type Field = fn(&LifeAnswer) -> f64;
            let named: [(&str, &'static str, Field); 4] = [
                ("polygon_order_wear", "", |l| l.polygon_order_wear),
                ("distance_to_visible_km", "km", |l| l.distance_to_visible_km),
                ("tread_life_km", "km", |l| l.tread_life_km),
                ("peak_share_of_visible", "", |l| l.peak_share_of_visible),
            ];
            for (name, unit, get) in named {
                cols.push(Column::f64(format!("{prefix}_{name}"), unit, of(&get)));
            }
        }
        let point = |get: fn(&crate::wear::WearAnswer) -> f64| -> Vec<f64> {
            wheels
                .iter()
                .map(|w| match (&w.solution.wear, w.estimate.is_some()) {
                    (Some(e), true) if self.cruise => get(e),
                    _ => f64::NAN,
                })
                .collect()
        };
        cols.push(Column::f64(
            "estimate_detuning_rev",
            "",
            point(|e| e.detuning_rev),
        ));
        cols.push(Column::f64(
            "estimate_growth_rate_per_1000km",
            "1/1000 km",
            point(|e| e.growth_rate_per_1000km),
        ));
        cols
    }

    /// The history: one row per wheel, step and order (depth peak-to-valley).
    pub fn history_columns(&self) -> Vec<Column> {
        let (mut wheel, mut km, mut order, mut depth, mut height) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for w in &self.wheels {
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

    /// The profiles: one row per wheel, chosen distance and cell (the worn depth minus its
    /// mean, so r = −depth).
    pub fn profile_columns(&self) -> Vec<Column> {
        let (mut wheel, mut km, mut angle, mut depth) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for w in &self.wheels {
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
}
