//! The wear stage's queries ([`crate::analysis::wear_risk`]): per group, the wheels that reach a
//! visible polygon within each distance (weighted by distance where a fleet's weights are
//! hours), how the wear quantities spread (finite, +inf, unknown), their histograms, and the
//! dominant orders of the wheels that reach one.

use polars::prelude::*;

use super::scenario_pairs::code_expr;
use super::{
    bin_expr, collect, floats, groups_of, histogram_bins, ints, variant_wheel, Group, GroupKey,
    HistogramBin, OutcomeColumn, Rows,
};
use crate::analysis::bins::Bins;
use crate::analysis::counts::WithinCounts;
use crate::analysis::AnalysisError;
use polywear_core::model::{Variant, Wheel};
use polywear_core::records::{RecordColumn, WearColumn};

/// How much a row counts toward the wear probabilities.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleWeight {
    /// Every row counts once: the samples already stand for the distance driven (a study
    /// without an operating-point file, or a fleet weighted by km).
    Equal,
    /// In proportion to the row's `speed_kmh`: the samples of a fleet weighted by hours stand
    /// for time, and distance = hours × speed. Weights are whole tenths of a km/h
    /// (`WEIGHT_UNITS_PER_KMH`), so sums are exact.
    SpeedKmh,
}

/// Weight units per km/h of a [`SampleWeight::SpeedKmh`] weight.
pub(crate) const WEIGHT_UNITS_PER_KMH: f64 = 10.0;

/// The wear counts of one group, one per distance asked for, in that order.
pub(crate) type WearGroup = Group<Vec<WithinCounts>>;

/// How one wear quantity spreads over one variant and wheel's rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearSpread {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// Rows with a finite value.
    pub finite: u64,
    /// Rows at +inf (a distance: every order levels out), and for any other column the rows
    /// without a value whose distance is +inf: over the tread's life, where every order
    /// levels from its seed, no order is the wear's and its growth is NaN.
    pub pos_inf: u64,
    /// Rows with NaN (undefined).
    pub unknown: u64,
}

/// Wheels of one dominant order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrderCount {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The dominant order (sides of the polygon).
    pub order: i64,
    /// Wheels.
    pub n: u64,
}

/// How near one variant's and wheel's deepest orders came to the visible depth over the
/// tread's life (`wear_peak_share_of_visible`).
#[derive(Debug, Clone, PartialEq)]
pub struct NearMisses {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// Wheels with a peak share (finite; NaN on the new tire's level and for unknown wheels).
    pub known: u64,
    /// Wheels whose peak share reached each threshold of `NEAR_MISS_SHARES`.
    pub at_least: Vec<u64>,
}

/// The shares of the visible depth the near-miss table counts the wheels at or above.
pub(crate) const NEAR_MISS_SHARES: [f64; 4] = [0.1, 0.25, 0.5, 1.0];

const DISTANCE: &str = WearColumn::DistanceToVisibleKm.name();
const SPEED: &str = RecordColumn::SpeedKmh.name();

fn weight_expr(weight: SampleWeight) -> Expr {
    match weight {
        SampleWeight::Equal => lit(1i64),
        SampleWeight::SpeedKmh => (col(SPEED).cast(DataType::Float64) * lit(WEIGHT_UNITS_PER_KMH)
            + lit(0.5))
        .cast(DataType::Int64),
    }
}

/// The row's code for "a visible polygon within `km`": 0 no, 1 yes, 2 unknown.
fn within_code(km: f64) -> Expr {
    code_expr(OutcomeColumn::WithinKm {
        column: DISTANCE,
        km,
    })
}

/// Fine bins of a quantity that spans decades: each decade \[10^d, 10^(d+1)) from `decades.0`
/// to `decades.1` split into [`BINS_PER_DECADE`] equal widths (a value below the first decade in
/// the first bin), so the quantiles of a distance are exact to 0.9% of its value at any size.
pub(crate) const BINS_PER_DECADE: usize = 1000;

/// The decades `(first, last)` that hold `[lo, hi]`, at least the decade of 1 km.
pub(crate) fn decades(lo: f64, hi: f64) -> (i32, i32) {
    let d = |x: f64| x.max(1.0).log10().floor() as i32;
    (d(lo), d(hi).max(d(lo)))
}

/// The edges of the decade bins of [`BINS_PER_DECADE`].
pub(crate) fn decade_bins((d0, d1): (i32, i32)) -> Bins {
    let m = BINS_PER_DECADE;
    let mut edges: Vec<f64> = (d0..=d1)
        .flat_map(|d| (0..m).map(move |j| 10f64.powi(d) * (1.0 + 9.0 * j as f64 / m as f64)))
        .collect();
    edges.push(10f64.powi(d1 + 1));
    Bins {
        edges,
        levels: false,
    }
}

/// The decade bin of `x` ([`decade_bins`]) as a polars expression (Int64).
fn decade_bin_expr(x: Expr, (d0, d1): (i32, i32)) -> Expr {
    let m = BINS_PER_DECADE as i64;
    let decade = (d0 + 1..=d1).fold(lit(0i64), |acc, d| {
        acc + x.clone().gt_eq(lit(10f64.powi(d))).cast(DataType::Int64)
    });
    let scale = (d0..=d1).rev().fold(lit(10f64.powi(-d0)), |acc, d| {
        when(decade.clone().eq(lit((d - d0) as i64)))
            .then(lit(10f64.powi(-d)))
            .otherwise(acc)
    });
    let within = ((x * scale - lit(1.0)) * lit(m as f64 / 9.0)).cast(DataType::Int64);
    let within = when(within.clone().lt(lit(0i64)))
        .then(lit(0i64))
        .when(within.clone().gt_eq(lit(m)))
        .then(lit(m - 1))
        .otherwise(within);
    decade * lit(m) + within
}

impl Rows {
    /// Per variant, wheel and combination of `keys`: the wheels with a visible polygon within
    /// each of `within_km`, among those with a known distance, counted and weighted.
    pub fn within_counts(
        &self,
        keys: &[GroupKey<'_>],
        within_km: &[f64],
        weight: SampleWeight,
    ) -> Result<Vec<WearGroup>, AnalysisError> {
        let w = weight_expr(weight);
        let known = within_code(f64::INFINITY)
            .lt(lit(2i64))
            .cast(DataType::Int64);
        let mut aggs = vec![
            len().cast(DataType::Int64).alias("n"),
            known.clone().sum().alias("known"),
            (known.clone() * w.clone()).sum().alias("w_known"),
            (known * w.clone() * w.clone()).sum().alias("w2_known"),
        ];
        for (k, km) in within_km.iter().enumerate() {
            let yes = within_code(*km).eq(lit(1i64)).cast(DataType::Int64);
            aggs.push(yes.clone().sum().alias(format!("within{k}")));
            aggs.push((yes * w.clone()).sum().alias(format!("w_within{k}")));
        }
        let df = self.grouped(keys, aggs)?;
        let (n, known, w_known, w2) = (
            ints(&df, "n")?,
            ints(&df, "known")?,
            ints(&df, "w_known")?,
            ints(&df, "w2_known")?,
        );
        let within: Vec<(Vec<i64>, Vec<i64>)> = (0..within_km.len())
            .map(|k| {
                Ok((
                    ints(&df, &format!("within{k}"))?,
                    ints(&df, &format!("w_within{k}"))?,
                ))
            })
            .collect::<Result<_, AnalysisError>>()?;
        groups_of(&df, keys, |i| {
            Ok(within
                .iter()
                .map(|(y, wy)| WithinCounts {
                    within: y[i] as u64,
                    known: known[i] as u64,
                    unknown: (n[i] - known[i]) as u64,
                    w_within: wy[i],
                    w_known: w_known[i],
                    w2_known: w2[i],
                })
                .collect())
        })
    }

    /// How `column` spreads per variant and wheel, and the range of its finite values over all
    /// rows (NaN without any).
    pub fn wear_spread(
        &self,
        column: &str,
    ) -> Result<(Vec<WearSpread>, (f64, f64)), AnalysisError> {
        let x = col(column).cast(DataType::Float64);
        let count = |e: Expr| e.cast(DataType::Int64).sum();
        let missing = x.clone().is_nan().or(x.clone().is_null());
        let levels = if column == DISTANCE {
            lit(false)
        } else {
            missing
                .clone()
                .and(col(DISTANCE).cast(DataType::Float64).eq(lit(f64::INFINITY)))
        };
        let df = collect(
            self.lf
                .clone()
                .group_by([col("variant"), col("wheel")])
                .agg([
                    count(x.clone().is_finite()).alias("finite"),
                    count(x.clone().eq(lit(f64::INFINITY)).or(levels.clone())).alias("pos_inf"),
                    count(missing.and(levels.not())).alias("unknown"),
                    x.clone().filter(x.clone().is_finite()).min().alias("lo"),
                    x.clone().filter(x.is_finite()).max().alias("hi"),
                ]),
        )?;
        let (finite, pos_inf, unknown) = (
            ints(&df, "finite")?,
            ints(&df, "pos_inf")?,
            ints(&df, "unknown")?,
        );
        let (lo, hi) = (floats(&df, "lo")?, floats(&df, "hi")?);
        let range = (
            lo.iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(f64::NAN, f64::min),
            hi.iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(f64::NAN, f64::max),
        );
        let spread = variant_wheel(&df)?
            .into_iter()
            .enumerate()
            .map(|(i, (variant, wheel))| WearSpread {
                variant,
                wheel,
                finite: finite[i] as u64,
                pos_inf: pos_inf[i] as u64,
                unknown: unknown[i] as u64,
            })
            .collect();
        Ok((spread, range))
    }

    /// The histogram of the finite values of `column` per variant and wheel: on `bins` (equal
    /// widths), or on the [`decade_bins`] of `decades` where given (`bins` are then those).
    pub fn finite_histogram(
        &self,
        column: &str,
        bins: &Bins,
        decades: Option<(i32, i32)>,
    ) -> Result<Vec<HistogramBin>, AnalysisError> {
        let x = col(column).cast(DataType::Float64);
        let bin = match decades {
            Some(d) => decade_bin_expr(x.clone(), d),
            None => bin_expr(bins, x.clone()),
        };
        let df = collect(
            self.lf
                .clone()
                .filter(x.is_finite())
                .group_by([col("variant"), col("wheel"), bin.alias("bin")])
                .agg([len().cast(DataType::Int64).alias("n")]),
        )?;
        histogram_bins(&df, None)
    }

    /// Per variant and wheel, the wheels with a peak share and those at or above each of
    /// [`NEAR_MISS_SHARES`]; empty where the rows have no `wear_peak_share_of_visible` (rows
    /// written before it existed) or none has a value (the new tire's level).
    pub fn near_misses(&self) -> Result<Vec<NearMisses>, AnalysisError> {
        let name = WearColumn::WearPeakShareOfVisible.name();
        if !self.has_column(name)? {
            return Ok(Vec::new());
        }
        let x = col(name).cast(DataType::Float64);
        let count = |e: Expr| e.cast(DataType::Int64).sum();
        let mut aggs = vec![count(x.clone().is_finite()).alias("known")];
        aggs.extend(NEAR_MISS_SHARES.iter().enumerate().map(|(k, &t)| {
            count(x.clone().is_finite().and(x.clone().gt_eq(lit(t)))).alias(format!("at{k}"))
        }));
        let df = collect(
            self.lf
                .clone()
                .group_by([col("variant"), col("wheel")])
                .agg(aggs),
        )?;
        let known = ints(&df, "known")?;
        let at: Vec<Vec<i64>> = (0..NEAR_MISS_SHARES.len())
            .map(|k| ints(&df, &format!("at{k}")))
            .collect::<Result<_, _>>()?;
        let mut out: Vec<NearMisses> = variant_wheel(&df)?
            .into_iter()
            .enumerate()
            .map(|(i, (variant, wheel))| NearMisses {
                variant,
                wheel,
                known: known[i] as u64,
                at_least: at.iter().map(|a| a[i] as u64).collect(),
            })
            .filter(|m| m.known > 0)
            .collect();
        out.sort_by_key(|m| (m.variant, m.wheel));
        Ok(out)
    }

    /// Wheels per dominant order among those with a visible polygon within `within_km`.
    pub fn dominant_orders(&self, within_km: f64) -> Result<Vec<OrderCount>, AnalysisError> {
        let order = WearColumn::PolygonOrderWear.name();
        let df = collect(
            self.lf
                .clone()
                .filter(within_code(within_km).eq(lit(1i64)))
                .filter(col(order).cast(DataType::Float64).is_finite())
                .group_by([
                    col("variant"),
                    col("wheel"),
                    col(order).cast(DataType::Int64).alias("order"),
                ])
                .agg([len().cast(DataType::Int64).alias("n")]),
        )?;
        let (o, n) = (ints(&df, "order")?, ints(&df, "n")?);
        let mut out: Vec<OrderCount> = variant_wheel(&df)?
            .into_iter()
            .enumerate()
            .map(|(i, (variant, wheel))| OrderCount {
                variant,
                wheel,
                order: o[i],
                n: n[i] as u64,
            })
            .collect();
        out.sort_by_key(|c| (c.variant, c.wheel, c.order));
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_decade_bin_expression_agrees_with_the_decade_bins() {
        let span = decades(3.0, 2.5e6);
        assert_eq!(span, (0, 6));
        let bins = decade_bins(span);
        assert_eq!(bins.count(), 7 * BINS_PER_DECADE);
        let values: Vec<f64> = (0..=700).map(|i| 10f64.powf(i as f64 / 100.0)).collect();
        let df = df!("x" => values.clone()).unwrap();
        let out = df
            .lazy()
            .select([decade_bin_expr(col("x"), span).alias("b")])
            .collect()
            .unwrap();
        for (v, b) in values.iter().zip(ints(&out, "b").unwrap()) {
            let (lo, hi, _) = bins.range(b as usize);
            // Each value in its own bin (the top edge in the last), to rounding at the edges.
            assert!(
                *v >= lo * (1.0 - 1e-12) && (*v <= hi * (1.0 + 1e-12)),
                "{v} in bin {b} = [{lo}, {hi}]"
            );
        }
    }
}
