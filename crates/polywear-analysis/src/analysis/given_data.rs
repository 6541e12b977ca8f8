//! Which parameters drive the risk, from the rows of any design: the first-order index of the
//! vibration indicator with respect to each drawn parameter, S_i = Var(E[Y | X_i]) / Var(Y),
//! estimated from the rows already there by binning X_i (a *given-data* estimator, Plischke,
//! Borgonovo & Smith 2013), so that a random, LHS, Sobol or grid run answers the question
//! without a second, Saltelli run.
//!
//! The estimator is SALib's (`SALib.analyze.delta`, its `S1`): the rows are split into M
//! classes of equal frequency along X_i, M = min(⌈N^(2 / (7 + tanh((1500 − N) / 500)))⌉, 48),
//! and S_i = Σ_j (n_j / N) (ȳ_j − ȳ)² / Var(Y); its 95% interval is ±1.96 bootstrap standard
//! deviations, as SALib's `S1_conf`. The classes come from a fine histogram of X_i (one
//! streaming query, whatever the row count): a fine bin that straddles a class boundary is
//! shared between the two classes in proportion, as SALib's ranks share its rows. A
//! parameter without influence still shows about (M − 1) / N (the estimator's bias), given
//! as `noise`.
//!
//! Y is 1 for a vibrating row and 0 for a stable one, over the classified rows; of a Saltelli
//! design, over the rows of its two independent base matrices. Where the
//! drawn parameters are correlated (the columns of an operating-point file), each index also
//! carries the effect of the parameters that move with it.

use std::collections::BTreeMap;

use rand_distr::Distribution as _;

use super::bins::axis_bins;
use super::inputs::RunInfo;
use super::rows::{GroupKey, Rows, SampleWeight};
use super::stats::Z95;
use super::AnalysisError;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::sampling::design::Design;

/// Fine bins along each axis behind the equal-frequency classes.
pub(crate) const FINE_BINS: usize = 4000;

/// SALib's largest number of classes.
pub(crate) const MAX_CLASSES: usize = 48;

/// The first-order index of the vibration indicator with respect to one parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct FirstOrder {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The drawn parameter.
    pub param: ParamId,
    /// Classified rows behind the estimate.
    pub rows: u64,
    /// Equal-frequency classes along the parameter (M).
    pub classes: usize,
    /// The index S_i.
    pub s1: f64,
    /// Half width of its 95% interval: 1.96 bootstrap standard deviations.
    pub conf: f64,
    /// What a parameter without influence shows on average: (M − 1) / N.
    pub noise: f64,
}

/// SALib's number of equal-frequency classes for `n` rows.
pub(crate) fn classes(n: u64) -> usize {
    let n = n as f64;
    let exp = 2.0 / (7.0 + ((1500.0 - n) / 500.0).tanh());
    (n.powf(exp).ceil() as usize).clamp(1, MAX_CLASSES)
}

/// Rows and vibrating rows of one class (fractional where a fine bin is shared).
pub(crate) type ClassRows = (f64, f64);

/// The fine bins' (rows, vibrating rows), in order along the axis, regrouped into `m`
/// classes of equal frequency; a fine bin that straddles a boundary is shared in proportion.
pub(crate) fn equal_frequency(fine: &[ClassRows], m: usize) -> Vec<ClassRows> {
    let total: f64 = fine.iter().map(|b| b.0).sum();
    let mut out = vec![(0.0, 0.0); m.max(1)];
    let per = total / out.len() as f64;
    let (mut g, mut filled) = (0, 0.0);
    for &(n, v) in fine {
        let mut left = n;
        while left > 0.0 {
            let last = g + 1 == out.len();
            let take = if last { left } else { left.min(per - filled) };
            out[g].0 += take;
            out[g].1 += v * take / n;
            left -= take;
            filled += take;
            if !last && filled >= per * (1.0 - 1e-12) {
                (g, filled) = (g + 1, 0.0);
            }
        }
    }
    out
}

/// S = Σ_j (n_j / N) (ȳ_j − ȳ)² / Var(Y) of a 0/1 output over classes; 0 when Y is constant
/// (nothing to explain), as SALib.
pub(crate) fn first_order(classes: &[ClassRows]) -> f64 {
    let n: f64 = classes.iter().map(|c| c.0).sum();
    let v: f64 = classes.iter().map(|c| c.1).sum();
    if n <= 0.0 {
        return f64::NAN;
    }
    let p = v / n;
    let var = p * (1.0 - p);
    if var <= 0.0 {
        return 0.0;
    }
    classes
        .iter()
        .filter(|c| c.0 > 0.0)
        .map(|c| c.0 / n * (c.1 / c.0 - p).powi(2))
        .sum::<f64>()
        / var
}

/// 1.96 standard deviations of [`first_order`] over `resamples` bootstrap resamples of the
/// rows (a multinomial draw of N rows over the cells class × outcome).
pub(crate) fn bootstrap_conf(classes: &[ClassRows], resamples: usize, seed: u64) -> f64 {
    let n: f64 = classes.iter().map(|c| c.0).sum();
    let rows = n.round() as u64;
    let cells: Vec<f64> = classes
        .iter()
        .flat_map(|c| [c.1.max(0.0), (c.0 - c.1).max(0.0)])
        .collect();
    let streams = polywear_core::sampling::Streams::new(seed);
    let mut draws = Vec::with_capacity(resamples);
    let mut drawn = vec![0.0; cells.len()];
    for r in 0..resamples {
        let mut rng = streams.at(r as u64, 0);
        let (mut left_rows, mut left_mass) = (rows, n);
        for (k, &mass) in cells.iter().enumerate() {
            let p = if left_mass > 0.0 {
                (mass / left_mass).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let x = rand_distr::Binomial::new(left_rows, p).map_or(0, |b| b.sample(&mut rng));
            drawn[k] = x as f64;
            left_rows -= x;
            left_mass -= mass;
        }
        let regrouped: Vec<ClassRows> = drawn.chunks(2).map(|c| (c[0] + c[1], c[0])).collect();
        let s = first_order(&regrouped);
        if s.is_finite() {
            draws.push(s);
        }
    }
    if draws.len() < 2 {
        return f64::NAN;
    }
    let mean = draws.iter().sum::<f64>() / draws.len() as f64;
    let var = draws.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (draws.len() - 1) as f64;
    Z95 * var.sqrt()
}

/// The first-order index of every drawn parameter, per variant and wheel, with `resamples`
/// bootstrap resamples behind each interval; `ranges` holds the axes' observed ranges.
pub(crate) fn first_order_indices(
    rows: &Rows,
    info: &RunInfo,
    ranges: &BTreeMap<String, (f64, f64)>,
    resamples: usize,
) -> Result<Vec<FirstOrder>, AnalysisError> {
    indices_of_outcome(rows, info, ranges, resamples, 17, |rows, key| {
        Ok(rows
            .class_counts(key)?
            .into_iter()
            .map(|g| {
                let c = (g.counts.classified() as f64, g.counts.vibrating() as f64);
                (g.variant, g.wheel, g.bins[0], c)
            })
            .collect())
    })
}

/// [`first_order_indices`] of the wear outcome: the indicator is 1 when the wheel's polygon is
/// visible within `within_km`, 0 when it is not (later, or never); rows without wear figures are
/// left out, as the vibration's unclassified rows are.
pub(crate) fn first_order_wear_indices(
    rows: &Rows,
    info: &RunInfo,
    ranges: &BTreeMap<String, (f64, f64)>,
    resamples: usize,
    within_km: f64,
) -> Result<Vec<FirstOrder>, AnalysisError> {
    indices_of_outcome(rows, info, ranges, resamples, 71, |rows, key| {
        Ok(rows
            .within_counts(key, &[within_km], SampleWeight::Equal)?
            .into_iter()
            .map(|g| {
                let c = (g.counts[0].known as f64, g.counts[0].within as f64);
                (g.variant, g.wheel, g.bins[0], c)
            })
            .collect())
    })
}

/// Per-bin (rows, rows with the outcome) of one variant and wheel, bin index first.
type BinCounts = Vec<(Variant, Wheel, i64, ClassRows)>;

/// The first-order indices of the outcome whose per-bin counts `counts` gives for a grouping
/// key; the bootstrap of parameter m is seeded with `seed_base + m`.
fn indices_of_outcome(
    rows: &Rows,
    info: &RunInfo,
    ranges: &BTreeMap<String, (f64, f64)>,
    resamples: usize,
    seed_base: u64,
    counts: impl Fn(&Rows, &[GroupKey]) -> Result<BinCounts, AnalysisError>,
) -> Result<Vec<FirstOrder>, AnalysisError> {
    // A Saltelli design's rows share values between blocks (AB_i takes every column but the
    // i-th from A): only its base matrices A and B are independent draws.
    let base;
    let rows = if info.design == Design::Saltelli {
        base = rows.sample_blocks_below(info.drawn_names.len() as i64 + 2, 2);
        &base
    } else {
        rows
    };
    let mut out = Vec::new();
    for (m, &param) in info.drawn_names.iter().enumerate() {
        let bins = axis_bins(info, ranges, param, FINE_BINS);
        let mut fine: BTreeMap<(Variant, Wheel), Vec<ClassRows>> = BTreeMap::new();
        for (variant, wheel, bin, (total, hits)) in
            counts(rows, &[GroupKey::Bin(param.name(), &bins)])?
        {
            let per = fine
                .entry((variant, wheel))
                .or_insert_with(|| vec![(0.0, 0.0); bins.count()]);
            if let Some(b) = usize::try_from(bin).ok().and_then(|b| per.get_mut(b)) {
                b.0 += total;
                b.1 += hits;
            }
        }
        for ((variant, wheel), per) in fine {
            let seed = seed_base + m as u64;
            out.push(index_of(variant, wheel, param, &per, resamples, seed));
        }
    }
    out.sort_by_key(|f| (f.variant, f.wheel));
    Ok(out)
}

fn index_of(
    variant: Variant,
    wheel: Wheel,
    param: ParamId,
    fine: &[ClassRows],
    resamples: usize,
    seed: u64,
) -> FirstOrder {
    let rows = fine.iter().map(|b| b.0).sum::<f64>().round() as u64;
    let m = classes(rows);
    let grouped = equal_frequency(fine, m);
    FirstOrder {
        variant,
        wheel,
        param,
        rows,
        classes: m,
        s1: first_order(&grouped),
        conf: bootstrap_conf(&grouped, resamples, seed),
        noise: if rows > 0 {
            (m as f64 - 1.0) / rows as f64
        } else {
            f64::NAN
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_follow_salib() {
        // SALib: M = round(min(ceil(N ** exp), 48)), exp = 2 / (7 + tanh((1500 - N) / 500)).
        assert_eq!(classes(100), 4);
        assert_eq!(classes(2000), 12);
        assert_eq!(classes(20_000), 28);
        assert_eq!(classes(1_000_000), 48);
    }

    #[test]
    fn equal_frequency_classes_share_straddling_bins() {
        let fine = [(3.0, 3.0), (3.0, 0.0), (2.0, 2.0)];
        let g = equal_frequency(&fine, 2);
        assert_eq!(g.len(), 2);
        assert!((g[0].0 - 4.0).abs() < 1e-12 && (g[1].0 - 4.0).abs() < 1e-12);
        // The second bin is split 1 : 2; its vibrating rows (none) with it.
        assert!((g[0].1 - 3.0).abs() < 1e-12 && (g[1].1 - 2.0).abs() < 1e-12);
    }

    #[test]
    fn an_indicator_that_is_the_parameter_is_explained_entirely() {
        // Y = 1 above the median of X, 0 below: E[Y | X] = Y, so S = 1 (two classes).
        let fine: Vec<ClassRows> = (0..100)
            .map(|i| (10.0, if i >= 50 { 10.0 } else { 0.0 }))
            .collect();
        assert!((first_order(&equal_frequency(&fine, 2)) - 1.0).abs() < 1e-12);
        // Y independent of X: every class at the mean, S = 0.
        let flat: Vec<ClassRows> = (0..100).map(|_| (10.0, 3.0)).collect();
        assert!(first_order(&equal_frequency(&flat, 10)).abs() < 1e-12);
        assert_eq!(first_order(&[(10.0, 10.0)]), 0.0);
    }

    #[test]
    fn the_bootstrap_interval_shrinks_with_the_rows() {
        let make = |per: f64| -> Vec<ClassRows> {
            (0..10)
                .map(|i| (per, per * (0.3 + 0.04 * i as f64)))
                .collect()
        };
        let small = bootstrap_conf(&make(100.0), 200, 5);
        let large = bootstrap_conf(&make(10_000.0), 200, 5);
        assert!(
            small > 0.0 && large > 0.0 && large < small / 5.0,
            "{small} {large}"
        );
        // Deterministic for a seed.
        assert_eq!(small, bootstrap_conf(&make(100.0), 200, 5));
    }
}
