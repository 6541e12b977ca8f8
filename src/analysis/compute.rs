//! The analysis tables, computed from plain vectors: occurrence probabilities, the paired
//! driving-vs-follower comparison, conditional probabilities along each axis, risk maps over
//! pairs of axes, severity among limit cycles, and Sobol sensitivity indices.

use std::collections::HashMap;

use super::load::{Dataset, RowClass};
use super::stats::{mcnemar, sobol_with_bootstrap, wilson};
use crate::model::{Variant, Wheel};

/// Probability of self-excited vibration for one variant and wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct Occurrence {
    pub variant: Variant,
    pub wheel: Wheel,
    /// Rows (samples) of this variant and wheel.
    pub n: u64,
    /// Rows that vibrate (limit cycle or bistable).
    pub k: u64,
    pub counts: Vec<(RowClass, u64)>,
    pub p: f64,
    pub lo: f64,
    pub hi: f64,
}

pub fn occurrence(ds: &Dataset) -> Vec<Occurrence> {
    ds.groups()
        .into_iter()
        .map(|(variant, wheel)| {
            let mut counts: HashMap<RowClass, u64> = HashMap::new();
            for i in 0..ds.len() {
                if ds.variant[i] == variant && ds.wheel[i] == wheel {
                    *counts.entry(ds.class[i]).or_default() += 1;
                }
            }
            let n: u64 = counts.values().sum();
            let k: u64 = counts
                .iter()
                .filter(|(c, _)| c.vibrates())
                .map(|(_, n)| n)
                .sum();
            let (lo, hi) = wilson(k, n);
            let mut counts: Vec<(RowClass, u64)> = counts.into_iter().collect();
            counts.sort();
            Occurrence {
                variant,
                wheel,
                n,
                k,
                counts,
                p: k as f64 / n.max(1) as f64,
                lo,
                hi,
            }
        })
        .collect()
}

/// The paired comparison on the same samples (McNemar).
#[derive(Debug, Clone, PartialEq)]
pub struct Paired {
    pub variant: Variant,
    pub pairs: u64,
    pub only_follower: u64,
    pub only_driving: u64,
    pub both: u64,
    pub neither: u64,
    pub chi2: f64,
    pub p_value: f64,
    pub method: &'static str,
}

pub fn paired(ds: &Dataset) -> Vec<Paired> {
    let mut out = Vec::new();
    for variant in Variant::ALL {
        let mut by_sample: HashMap<i64, [Option<bool>; 2]> = HashMap::new();
        for i in 0..ds.len() {
            if ds.variant[i] == variant {
                let slot = if ds.wheel[i] == Wheel::Follower { 0 } else { 1 };
                by_sample.entry(ds.sample_id[i]).or_default()[slot] = Some(ds.class[i].vibrates());
            }
        }
        if by_sample.is_empty() {
            continue;
        }
        let (mut f, mut d, mut both, mut neither) = (0, 0, 0, 0);
        for v in by_sample.values() {
            match (v[0], v[1]) {
                (Some(true), Some(false)) => f += 1,
                (Some(false), Some(true)) => d += 1,
                (Some(true), Some(true)) => both += 1,
                (Some(false), Some(false)) => neither += 1,
                _ => {}
            }
        }
        let (chi2, p_value, method) = mcnemar(f, d);
        out.push(Paired {
            variant,
            pairs: f + d + both + neither,
            only_follower: f,
            only_driving: d,
            both,
            neither,
            chi2,
            p_value,
            method,
        });
    }
    out
}

/// Bins of one axis: its distinct values when there are few (a grid), else equal widths.
#[derive(Debug, Clone, PartialEq)]
pub struct Bins {
    /// Bin edges (len = bins + 1), or the levels themselves when `levels` is true.
    pub edges: Vec<f64>,
    pub levels: bool,
}

impl Bins {
    pub fn new(values: &[f64], n_bins: usize) -> Bins {
        let mut distinct: Vec<f64> = Vec::new();
        for v in values.iter().filter(|v| v.is_finite()) {
            if !distinct.contains(v) {
                distinct.push(*v);
                if distinct.len() > 40 {
                    break;
                }
            }
        }
        if distinct.len() <= 40 && distinct.len() <= n_bins.max(2) * 2 {
            distinct.sort_by(f64::total_cmp);
            return Bins {
                edges: distinct,
                levels: true,
            };
        }
        let lo = values
            .iter()
            .cloned()
            .filter(|v| v.is_finite())
            .fold(f64::INFINITY, f64::min);
        let hi = values
            .iter()
            .cloned()
            .filter(|v| v.is_finite())
            .fold(f64::NEG_INFINITY, f64::max);
        let edges = (0..=n_bins)
            .map(|i| lo + (hi - lo) * i as f64 / n_bins as f64)
            .collect();
        Bins {
            edges,
            levels: false,
        }
    }

    pub fn count(&self) -> usize {
        if self.levels {
            self.edges.len()
        } else {
            self.edges.len() - 1
        }
    }

    /// Bin index of a value.
    pub fn index(&self, v: f64) -> Option<usize> {
        if !v.is_finite() {
            return None;
        }
        if self.levels {
            return self.edges.iter().position(|x| *x == v);
        }
        let (lo, hi) = (self.edges[0], *self.edges.last().unwrap());
        if v < lo || v > hi {
            return None;
        }
        let n = self.count();
        Some((((v - lo) / (hi - lo) * n as f64) as usize).min(n - 1))
    }

    /// (low, high, centre) of bin `i`; a level is its own centre with zero width.
    pub fn range(&self, i: usize) -> (f64, f64, f64) {
        if self.levels {
            let v = self.edges[i];
            (v, v, v)
        } else {
            let (a, b) = (self.edges[i], self.edges[i + 1]);
            (a, b, 0.5 * (a + b))
        }
    }
}

/// Probability in one bin.
#[derive(Debug, Clone, PartialEq)]
pub struct BinStat {
    pub variant: Variant,
    pub wheel: Wheel,
    pub axis: String,
    pub lo: f64,
    pub hi: f64,
    pub mid: f64,
    pub n: u64,
    pub k: u64,
    pub p: f64,
    pub ci_lo: f64,
    pub ci_hi: f64,
}

/// P(vibration | axis in bin), per variant, wheel and axis.
pub fn conditional(ds: &Dataset, n_bins: usize) -> Vec<BinStat> {
    let mut out = Vec::new();
    for axis in &ds.axes {
        let bins = Bins::new(&axis.values, n_bins);
        for (variant, wheel) in ds.groups() {
            let mut nk = vec![(0u64, 0u64); bins.count()];
            for i in 0..ds.len() {
                if ds.variant[i] == variant && ds.wheel[i] == wheel {
                    if let Some(b) = bins.index(axis.values[i]) {
                        nk[b].0 += 1;
                        nk[b].1 += ds.class[i].vibrates() as u64;
                    }
                }
            }
            for (b, (n, k)) in nk.into_iter().enumerate() {
                let (lo, hi, mid) = bins.range(b);
                let (ci_lo, ci_hi) = wilson(k, n);
                out.push(BinStat {
                    variant,
                    wheel,
                    axis: axis.name.clone(),
                    lo,
                    hi,
                    mid,
                    n,
                    k,
                    p: if n > 0 { k as f64 / n as f64 } else { f64::NAN },
                    ci_lo,
                    ci_hi,
                });
            }
        }
    }
    out
}

/// (samples, vibrating) per cell, indexed [ix][iy].
pub type CountGrid = Vec<Vec<(u64, u64)>>;

/// A risk map: vibration counts over a 2-D grid of bins of two axes, per wheel.
#[derive(Debug, Clone)]
pub struct RiskMap {
    pub variant: Variant,
    pub x: String,
    pub y: String,
    pub x_bins: Bins,
    pub y_bins: Bins,
    /// (wheel, counts[ix][iy] = (n, k)).
    pub cells: Vec<(Wheel, CountGrid)>,
}

impl RiskMap {
    /// Probability per cell, NaN where fewer than `min_count` samples fell.
    pub fn probability(&self, wheel: Wheel, min_count: u64) -> Vec<Vec<f64>> {
        let grid = &self
            .cells
            .iter()
            .find(|(w, _)| *w == wheel)
            .expect("wheel present")
            .1;
        grid.iter()
            .map(|col| {
                col.iter()
                    .map(|(n, k)| {
                        if *n >= min_count.max(1) {
                            *k as f64 / *n as f64
                        } else {
                            f64::NAN
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

pub fn risk_map(
    ds: &Dataset,
    variant: Variant,
    x: &str,
    y: &str,
    n_bins: usize,
) -> Result<RiskMap, String> {
    let ax = ds.axis(x).ok_or_else(|| {
        format!(
            "risk map: `{x}` is not a drawn parameter of this run ({})",
            ds.info.drawn_names.join(", ")
        )
    })?;
    let ay = ds.axis(y).ok_or_else(|| {
        format!(
            "risk map: `{y}` is not a drawn parameter of this run ({})",
            ds.info.drawn_names.join(", ")
        )
    })?;
    let (xb, yb) = (Bins::new(&ax.values, n_bins), Bins::new(&ay.values, n_bins));
    let mut cells = Vec::new();
    for wheel in Wheel::BOTH {
        let mut grid = vec![vec![(0u64, 0u64); yb.count()]; xb.count()];
        for i in 0..ds.len() {
            if ds.variant[i] == variant && ds.wheel[i] == wheel {
                if let (Some(ix), Some(iy)) = (xb.index(ax.values[i]), yb.index(ay.values[i])) {
                    grid[ix][iy].0 += 1;
                    grid[ix][iy].1 += ds.class[i].vibrates() as u64;
                }
            }
        }
        cells.push((wheel, grid));
    }
    Ok(RiskMap {
        variant,
        x: x.into(),
        y: y.into(),
        x_bins: xb,
        y_bins: yb,
        cells,
    })
}

/// Distribution of one cycle quantity among the vibrating rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Severity {
    pub variant: Variant,
    pub wheel: Wheel,
    pub quantity: &'static str,
    pub unit: &'static str,
    pub n: u64,
    pub mean: f64,
    /// 5, 25, 50, 75, 95 %.
    pub quantiles: [f64; 5],
    pub values: Vec<f64>,
}

pub fn severity(ds: &Dataset) -> Vec<Severity> {
    let quantities: [(&'static str, &'static str, &Vec<f64>); 4] = [
        ("amp_y_m", "m", &ds.amp_y_m),
        ("amp_v_mps", "m/s", &ds.amp_v_mps),
        ("energy_per_cycle_j", "J", &ds.energy_per_cycle_j),
        ("polygon_order", "-", &ds.polygon_order),
    ];
    let mut out = Vec::new();
    for (variant, wheel) in ds.groups() {
        for (quantity, unit, col) in quantities {
            let mut values: Vec<f64> = (0..ds.len())
                .filter(|&i| {
                    ds.variant[i] == variant && ds.wheel[i] == wheel && ds.class[i].vibrates()
                })
                .map(|i| col[i])
                .filter(|v| v.is_finite())
                .collect();
            values.sort_by(f64::total_cmp);
            let n = values.len();
            let q = |f: f64| {
                if n == 0 {
                    f64::NAN
                } else {
                    values[((f * (n - 1) as f64).round() as usize).min(n - 1)]
                }
            };
            let quantiles = [q(0.05), q(0.25), q(0.5), q(0.75), q(0.95)];
            let mean = if n == 0 {
                f64::NAN
            } else {
                values.iter().sum::<f64>() / n as f64
            };
            out.push(Severity {
                variant,
                wheel,
                quantity,
                unit,
                n: n as u64,
                mean,
                quantiles,
                values,
            });
        }
    }
    out
}

/// First-order and total Sobol indices of one output with respect to one parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    pub variant: Variant,
    pub wheel: Wheel,
    /// `limit_cycle` (the 0/1 indicator) or `amp_v_mps` (0 without a cycle).
    pub output: &'static str,
    pub param: String,
    pub base_samples: u64,
    pub s: (f64, f64, f64),
    pub st: (f64, f64, f64),
}

/// Sobol indices from a Saltelli design (sample_id = j·(k+2) + block); None for other designs.
pub fn sensitivity(ds: &Dataset, resamples: usize) -> Option<Vec<Sensitivity>> {
    if ds.info.design != "saltelli" {
        return None;
    }
    let k = ds.axes.len();
    let stride = k as i64 + 2;
    let mut out = Vec::new();
    for (variant, wheel) in ds.groups() {
        type Output<'a> = (&'static str, Box<dyn Fn(usize) -> f64 + 'a>);
        let outputs: [Output<'_>; 2] = [
            (
                "limit_cycle",
                Box::new(|i| ds.class[i].vibrates() as u8 as f64),
            ),
            (
                "amp_v_mps",
                Box::new(|i| {
                    if ds.class[i].vibrates() {
                        ds.amp_v_mps[i]
                    } else {
                        0.0
                    }
                }),
            ),
        ];
        // rows[j][block] = row index
        let mut rows: HashMap<i64, Vec<Option<usize>>> = HashMap::new();
        for i in 0..ds.len() {
            if ds.variant[i] == variant && ds.wheel[i] == wheel {
                let (j, b) = (
                    ds.sample_id[i] / stride,
                    (ds.sample_id[i] % stride) as usize,
                );
                rows.entry(j).or_insert_with(|| vec![None; k + 2])[b] = Some(i);
            }
        }
        // Only complete base points (a resumed or sharded run may miss some).
        let mut complete: Vec<(i64, Vec<usize>)> = rows
            .into_iter()
            .filter_map(|(j, r)| {
                r.into_iter()
                    .collect::<Option<Vec<usize>>>()
                    .map(|r| (j, r))
            })
            .collect();
        complete.sort();
        if complete.len() < 2 {
            continue;
        }
        for (output, f) in &outputs {
            let fa: Vec<f64> = complete.iter().map(|(_, r)| f(r[0])).collect();
            let fb: Vec<f64> = complete.iter().map(|(_, r)| f(r[1])).collect();
            for (m, axis) in ds.axes.iter().enumerate() {
                let fab: Vec<f64> = complete.iter().map(|(_, r)| f(r[2 + m])).collect();
                let (s, st) = sobol_with_bootstrap(&fa, &fb, &fab, resamples, 17 + m as u64);
                out.push(Sensitivity {
                    variant,
                    wheel,
                    output,
                    param: axis.name.clone(),
                    base_samples: complete.len() as u64,
                    s,
                    st,
                });
            }
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_use_levels_for_grids_and_widths_otherwise() {
        let b = Bins::new(&[1.0, 2.0, 3.0, 2.0, 1.0], 20);
        assert!(b.levels && b.count() == 3 && b.index(2.0) == Some(1) && b.index(2.5).is_none());
        let vals: Vec<f64> = (0..1000).map(|i| i as f64 / 10.0).collect();
        let b = Bins::new(&vals, 10);
        assert!(!b.levels && b.count() == 10);
        assert_eq!(b.index(0.0), Some(0));
        assert_eq!(b.index(99.9), Some(9));
        assert_eq!(b.index(50.0), Some(5));
    }
}
