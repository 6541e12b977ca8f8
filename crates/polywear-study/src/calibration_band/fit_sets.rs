//! From the fit's accepted points to the shipped sets: the nominal set (the accepted points'
//! medoid), at most [`SHIPPED_SETS_MAX`] of them chosen space-filling, the sentence that says where
//! the accepted region lies, and the design's table.

use polywear_core::params::ParamId;
use polywear_core::wear::FittedConstants;
use polywear_core::wording::plain;

use super::{Fit, FitOptions, GridPoint, FEW_SETS, METHOD, SHIPPED_SETS_MAX, SIDES_SHARE_MIN};
use crate::calibration_band::{
    BandError, CalibratedSet, CalibrationBand, ConstantRange, DesignTableError, FitSettings,
};
use crate::parquet_out::Column;

impl Fit {
    /// The accepted points.
    pub fn accepted(&self) -> impl Iterator<Item = &GridPoint> {
        self.points.iter().filter(|p| p.accepted)
    }

    /// Coordinates of `c` in the unit cube of the prior ranges (φ_s on its log scale, as the
    /// design lays it): distances between sets are measured there.
    fn unit(&self, c: &FittedConstants) -> [f64; 5] {
        let r = &self.options.ranges;
        let mut u = [0.0; 5];
        for (k, x) in c.values().into_iter().enumerate() {
            let (lo, hi) = (r[k].min, r[k].max);
            u[k] = if r[k].param == ParamId::WearShareStraight.name() {
                (x.ln() - lo.ln()) / (hi.ln() - lo.ln())
            } else if hi > lo {
                (x - lo) / (hi - lo)
            } else {
                0.0
            };
        }
        u
    }

    fn distance(&self, a: &FittedConstants, b: &FittedConstants) -> f64 {
        let (u, v) = (self.unit(a), self.unit(b));
        u.iter()
            .zip(&v)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
            .sqrt()
    }

    /// The shipped sets: the nominal (the medoid of the accepted points: the one nearest all
    /// the others, a typical member of the region, not one chosen for its answer) and, of more
    /// than [`SHIPPED_SETS_MAX`] accepted, that many chosen greedily farthest from those
    /// already chosen (maximin), starting from the nominal. None accepted: `fallback` alone.
    fn shipped(&self, fallback: &FittedConstants) -> (Vec<(GridPoint, bool)>, String) {
        let accepted: Vec<GridPoint> = self.accepted().copied().collect();
        if accepted.is_empty() {
            let point = GridPoint {
                index: u64::MAX,
                constants: *fallback,
                highway_median_km: f64::NAN,
                fleet_median_km: f64::NAN,
                fleet_visible_share: f64::NAN,
                sides_share: f64::NAN,
                accepted: false,
            };
            return (
                vec![(point, true)],
                "no point met every target: the constants shipped before, alone, as the nominal set".into(),
            );
        }
        let total = |p: &GridPoint| -> f64 {
            accepted
                .iter()
                .map(|q| self.distance(&p.constants, &q.constants))
                .sum()
        };
        let nominal = accepted
            .iter()
            .copied()
            .min_by(|a, b| total(a).total_cmp(&total(b)))
            .expect("some accepted");
        let mut chosen = vec![nominal];
        while chosen.len() < accepted.len().min(SHIPPED_SETS_MAX) {
            let nearest = |p: &GridPoint| {
                chosen
                    .iter()
                    .map(|q| self.distance(&p.constants, &q.constants))
                    .fold(f64::INFINITY, f64::min)
            };
            let next = accepted
                .iter()
                .filter(|p| !chosen.iter().any(|q| q.index == p.index))
                .max_by(|a, b| nearest(a).total_cmp(&nearest(b)))
                .copied()
                .expect("more accepted than chosen");
            chosen.push(next);
        }
        chosen.sort_by_key(|p| p.index);
        let n = accepted.len();
        let how = if n > SHIPPED_SETS_MAX {
            format!("{SHIPPED_SETS_MAX} of the {n} accepted points, space-filling (greedy maximin from the nominal); the nominal is their medoid")
        } else if n < FEW_SETS {
            format!("all {n} accepted points, fewer than {FEW_SETS}; the nominal is their medoid")
        } else {
            format!("all {n} accepted points; the nominal is their medoid")
        };
        let sets = chosen
            .into_iter()
            .map(|p| (p, p.index == nominal.index))
            .collect();
        (sets, how)
    }

    /// Where the accepted region lies, in one sentence: each constant the targets narrow (its
    /// accepted points span less than four fifths of its prior range, on the design's scale),
    /// each pair that moves together (|r| ≥ 0.7 on that scale), and the constants the targets
    /// leave free; or that no point is accepted.
    pub fn region_words(&self) -> String {
        let accepted: Vec<&GridPoint> = self.accepted().collect();
        let n = self.points.len();
        if accepted.is_empty() {
            return format!(
                "no point of the {n} evaluated meets every target: on the shipped level the field's facts lie outside the prior ranges of the five constants"
            );
        }
        let units: Vec<[f64; 5]> = accepted.iter().map(|p| self.unit(&p.constants)).collect();
        let ranges = &self.options.ranges;
        let (mut narrowed, mut free) = (Vec::new(), Vec::new());
        for (k, r) in ranges.iter().enumerate() {
            let v = accepted.iter().map(|p| p.constants.values()[k]);
            let (lo, hi) = (
                v.clone().fold(f64::INFINITY, f64::min),
                v.fold(f64::NEG_INFINITY, f64::max),
            );
            let u = units.iter().map(|u| u[k]);
            let span =
                u.clone().fold(f64::NEG_INFINITY, f64::max) - u.fold(f64::INFINITY, f64::min);
            let words = format!("{} {}–{}", r.param, plain(lo, 2), plain(hi, 2));
            if span < 0.8 {
                narrowed.push(format!(
                    "{words} (of {}–{})",
                    plain(r.min, 2),
                    plain(r.max, 2)
                ));
            } else {
                free.push(words);
            }
        }
        let mut together = Vec::new();
        for a in 0..5 {
            for b in a + 1..5 {
                let r = correlation(&units, a, b);
                if r.abs() >= 0.7 {
                    together.push(format!(
                        "{} {} with {} (r = {})",
                        ranges[b].param,
                        if r > 0.0 { "rising" } else { "falling" },
                        ranges[a].param,
                        plain(r, 2)
                    ));
                }
            }
        }
        let mut parts = Vec::new();
        if !narrowed.is_empty() {
            parts.push(format!("the field's facts need {}", narrowed.join(", ")));
        }
        if !together.is_empty() {
            parts.push(together.join(", "));
        }
        if !free.is_empty() {
            parts.push(format!(
                "they are met across {} (the whole searched range, or nearly)",
                free.join(", ")
            ));
        }
        format!(
            "{} of the {n} points meet every target; {}",
            accepted.len(),
            parts.join("; ")
        )
    }

    /// The accepted points as a file of calibrated sets (`Fit::shipped` chooses them); where none is
    /// accepted, `fallback` (the constants shipped before) alone, the file saying so.
    pub fn band(
        &self,
        fallback: &FittedConstants,
        generated_by: &str,
    ) -> Result<CalibrationBand, BandError> {
        let (chosen, shipped) = self.shipped(fallback);
        // A figure as the file keeps it: km rounded, +inf (none) kept, NaN (none evaluated) left out.
        let figure = |x: f64, scale: f64| {
            (!x.is_nan()).then(|| {
                if x.is_finite() {
                    (x * scale).round() / scale
                } else {
                    x
                }
            })
        };
        let sets: Vec<CalibratedSet> = chosen
            .iter()
            .map(|(g, nominal)| {
                let c = g.constants;
                CalibratedSet {
                    id: if *nominal {
                        "nominal".to_string()
                    } else {
                        format!("p{:04}", g.index)
                    },
                    nominal: *nominal,
                    wear_share_straight: round_constant(c.wear_share_straight),
                    speed_spread_kmh: round_constant(c.speed_spread_kmh),
                    wear_rate_driven_factor: round_constant(c.wear_rate_driven_factor),
                    carcass_share: round_constant(c.carcass_share),
                    belt_mass_share: round_constant(c.belt_mass_share),
                    highway_median_km: figure(g.highway_median_km, 1.0),
                    fleet_median_km: figure(g.fleet_median_km, 1.0),
                    sides_share: figure(g.sides_share, 1000.0),
                }
            })
            .collect();
        let band = CalibrationBand {
            method: METHOD.to_string(),
            generated_by: generated_by.to_string(),
            fit: FitSettings {
                design: "sobol".into(),
                points: self.options.points,
                fleet_samples: self.options.fleet_samples,
                sides_share_min: SIDES_SHARE_MIN,
                accepted: self.accepted().count() as u64,
                shipped,
                region: self.region_words(),
            },
            ranges: self.options.ranges.clone(),
            sets,
        };
        // The file must read back as it will be read.
        CalibrationBand::parse(&band.to_toml(), "the fit")
    }
}

/// A design point's constant as the file ships it: six significant digits (the design's
/// resolution is far coarser), so that the file reads as people write numbers.
fn round_constant(x: f64) -> f64 {
    plain(x, 6).parse().unwrap_or(x)
}

/// The design's table, a row per point evaluated: its index, constants, target figures and
/// whether it was accepted (`data/calibration_design.csv`).
pub fn design_columns(fit: &Fit, ranges: &[ConstantRange]) -> Vec<Column> {
    let p = &fit.points;
    let f = |name: &str, unit: &'static str, get: &dyn Fn(&GridPoint) -> f64| {
        Column::f64(name, unit, p.iter().map(get).collect())
    };
    let mut cols = vec![Column::i64(
        "point",
        "",
        p.iter().map(|g| g.index as i64).collect(),
    )];
    for (k, r) in ranges.iter().enumerate() {
        let unit = FittedConstants::PARAMS[k].spec().unit;
        cols.push(f(&r.param, unit, &|g| g.constants.values()[k]));
    }
    cols.extend([
        f("highway_median_km", "km", &|g| g.highway_median_km),
        f("fleet_median_km", "km", &|g| g.fleet_median_km),
        f("fleet_visible_share", "-", &|g| g.fleet_visible_share),
        f("sides_share", "-", &|g| g.sides_share),
        Column::i64(
            "accepted",
            "",
            p.iter().map(|g| i64::from(g.accepted)).collect(),
        ),
    ]);
    cols
}

/// Pearson's correlation of coordinates `a` and `b` over `units` (NaN for fewer than two).
fn correlation(units: &[[f64; 5]], a: usize, b: usize) -> f64 {
    let n = units.len() as f64;
    if units.len() < 2 {
        return f64::NAN;
    }
    let mean = |k: usize| units.iter().map(|u| u[k]).sum::<f64>() / n;
    let (ma, mb) = (mean(a), mean(b));
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for u in units {
        let (x, y) = (u[a] - ma, u[b] - mb);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    sab / (saa * sbb).sqrt()
}

impl Fit {
    /// The fit recorded in a design table ([`design_columns`], `data/calibration_design.csv`)
    /// for the design `options`: what the shipped sets are chosen from again without evaluating
    /// a point, and what CI's reduced design is checked against.
    pub fn from_design(
        options: &FitOptions,
        path: &std::path::Path,
    ) -> Result<Fit, DesignTableError> {
        let figure_columns = [
            "highway_median_km",
            "fleet_median_km",
            "fleet_visible_share",
            "sides_share",
        ];
        let t = crate::table_input::NumericTable::read_with_text(path, &|c| {
            figure_columns.contains(&c)
        })?;
        let at = |name: &str| {
            t.column(name).ok_or_else(|| DesignTableError::NoColumn {
                path: path.to_path_buf(),
                name: name.to_string(),
            })
        };
        let number = |name: &str| -> Result<Vec<f64>, DesignTableError> {
            let j = at(name)?;
            match t.text_of(j) {
                Some(text) => text
                    .iter()
                    .map(|x| {
                        x.trim()
                            .parse::<f64>()
                            .map_err(|_| DesignTableError::NotANumber {
                                path: path.to_path_buf(),
                                name: name.to_string(),
                                value: x.to_string(),
                            })
                    })
                    .collect(),
                None => Ok(t.rows.iter().map(|r| r[j]).collect()),
            }
        };
        let index = number("point")?;
        let constants: Vec<Vec<f64>> = options
            .ranges
            .iter()
            .map(|r| number(&r.param))
            .collect::<Result<_, _>>()?;
        let figures: Vec<Vec<f64>> = figure_columns
            .iter()
            .map(|c| number(c))
            .collect::<Result<_, _>>()?;
        let accepted = number("accepted")?;
        let points = (0..index.len())
            .map(|i| GridPoint {
                index: index[i] as u64,
                constants: FittedConstants::from_values(std::array::from_fn(|k| constants[k][i])),
                highway_median_km: figures[0][i],
                fleet_median_km: figures[1][i],
                fleet_visible_share: figures[2][i],
                sides_share: figures[3][i],
                accepted: accepted[i] == 1.0,
            })
            .collect();
        Ok(Fit {
            options: options.clone(),
            points,
            highway_wheels: 0,
            fleet_wheels: 0,
        })
    }
}
