//! Bins of one axis: the levels a study draws a parameter from (the sampler's own grid values,
//! or an operating-point column's few distinct values), else equal widths over the observed
//! range.

use std::collections::BTreeMap;

use super::inputs::RunInfo;
use polywear_core::params::ParamId;
use polywear_core::sampling::design::Design;
use polywear_core::sampling::distribution::Distribution;

/// Bins of one axis: the levels of a `levels` distribution (or a grid's values), else equal
/// widths between the observed minimum and maximum.
#[derive(Debug, Clone, PartialEq)]
pub struct Bins {
    /// Bin edges (len = bins + 1), or the levels themselves when `levels` is true.
    pub edges: Vec<f64>,
    /// True when the bins are the levels of a `levels` distribution or a grid.
    pub levels: bool,
}

impl Bins {
    /// `n_bins` bins of equal width between `lo` and `hi`.
    pub fn equal_width(lo: f64, hi: f64, n_bins: usize) -> Bins {
        Bins {
            edges: (0..=n_bins)
                .map(|i| lo + (hi - lo) * i as f64 / n_bins as f64)
                .collect(),
            levels: false,
        }
    }

    /// One bin per distinct level, in increasing order.
    pub fn levels(mut levels: Vec<f64>) -> Bins {
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        Bins {
            edges: levels,
            levels: true,
        }
    }

    /// Number of bins.
    pub fn count(&self) -> usize {
        if self.levels {
            self.edges.len()
        } else {
            self.edges.len() - 1
        }
    }

    /// Bin index of a value: for levels, the nearest level (ties to the lower one); for equal
    /// widths, the bin it falls in, the top edge in the last bin. The queries bin by the same
    /// rule.
    pub fn index(&self, v: f64) -> Option<usize> {
        if !v.is_finite() {
            return None;
        }
        if self.levels {
            return Some(self.midpoints().filter(|m| v > *m).count());
        }
        let (lo, hi) = (self.edges[0], *self.edges.last().unwrap());
        if v < lo || v > hi {
            return None;
        }
        let n = self.count();
        if hi == lo {
            return Some(0);
        }
        Some((((v - lo) * (n as f64 / (hi - lo))) as usize).min(n - 1))
    }

    /// The midpoints between neighbouring levels (the boundaries of level bins).
    pub fn midpoints(&self) -> impl Iterator<Item = f64> + '_ {
        self.edges.windows(2).map(|w| 0.5 * (w[0] + w[1]))
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

/// The bins of each drawn parameter: the study's levels where it draws `levels` (or a grid's
/// counted values), else `n_bins` equal widths over the observed range.
pub(crate) fn axis_bins(
    info: &RunInfo,
    ranges: &BTreeMap<String, (f64, f64)>,
    param: ParamId,
    n_bins: usize,
) -> Bins {
    if let Some(levels) = study_levels(info, param) {
        return Bins::levels(levels);
    }
    let (lo, hi) = ranges.get(param.name()).copied().unwrap_or((0.0, 1.0));
    Bins::equal_width(lo, hi, n_bins)
}

/// At most this many distinct values of an operating-point column are used as its levels; a
/// column with more (raw telematics rather than bins) is binned in equal widths.
pub(crate) const MAX_OPERATING_POINT_LEVELS: usize = 40;

/// The levels a study draws a parameter from: `levels`, or a grid's `count` values, as the
/// sampler itself lists them ([`Distribution::grid_values`]), so a label is always a sampled
/// value; for a column of `[operating_points]`, its distinct values among the rows that can be
/// drawn (positive weight), when there are few.
pub(crate) fn study_levels(info: &RunInfo, param: ParamId) -> Option<Vec<f64>> {
    let study = info.study.as_ref()?;
    if let Some(op) = &study.operating_points {
        if let Some(j) = op.names.iter().position(|n| *n == param.name()) {
            let mut levels: Vec<f64> = op
                .values
                .iter()
                .zip(&op.weights)
                .filter(|(_, w)| **w > 0.0)
                .map(|(row, _)| row[j])
                .collect();
            levels.sort_by(f64::total_cmp);
            levels.dedup();
            return (levels.len() <= MAX_OPERATING_POINT_LEVELS).then_some(levels);
        }
    }
    let d = study.drawn.iter().find(|d| d.param == param)?;
    match &d.dist {
        Distribution::Levels(_) => d.dist.grid_values(),
        Distribution::Uniform { count: Some(_), .. } if study.design == Design::Grid => {
            d.dist.grid_values()
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_use_levels_for_grids_and_widths_otherwise() {
        let b = Bins::levels(vec![3.0, 1.0, 2.0, 2.0]);
        assert!(b.levels && b.count() == 3);
        assert_eq!(b.index(2.0), Some(1));
        assert_eq!(b.index(1.0), Some(0));
        assert_eq!(b.index(3.0), Some(2));
        let b = Bins::equal_width(0.0, 99.9, 10);
        assert!(!b.levels && b.count() == 10);
        assert_eq!(b.index(0.0), Some(0));
        assert_eq!(b.index(99.9), Some(9));
        assert_eq!(b.index(50.0), Some(5));
    }
}
