//! Where the risk lives over two axes: class counts over a grid of bins, per variant and wheel.

use std::collections::BTreeMap;

use super::bins::Bins;
use super::counts::ClassCounts;
use super::rows::{GroupKey, Rows};
use super::AnalysisError;
use crate::chart::WheelCurves;
use crate::model::{Variant, Wheel};
use crate::params::ParamId;

/// Class counts per cell, indexed `[ix][iy]`.
pub(crate) type CountGrid = Vec<Vec<ClassCounts>>;

/// A risk map: class counts over a 2-D grid of bins of two axes, per wheel.
#[derive(Debug, Clone)]
pub struct RiskMap {
    /// The friction variant.
    pub variant: Variant,
    /// The parameter on the horizontal axis.
    pub x: ParamId,
    /// The parameter on the vertical axis.
    pub y: ParamId,
    /// Bins of the horizontal axis.
    pub x_bins: Bins,
    /// Bins of the vertical axis.
    pub y_bins: Bins,
    /// (wheel, `counts[ix][iy]`).
    pub cells: Vec<(Wheel, CountGrid)>,
    /// The Hopf curves of the run's nominal tire over the map's box (the study's median values
    /// elsewhere), when they can be traced: the stability boundary the map should follow.
    pub nominal: Option<Vec<WheelCurves>>,
}

impl RiskMap {
    /// (cells where some wheel has at least `min_count` classified samples, all cells).
    pub fn coverage(&self, min_count: u64) -> (usize, usize) {
        let cells = self.x_bins.count() * self.y_bins.count();
        let filled = (0..self.x_bins.count())
            .flat_map(|ix| (0..self.y_bins.count()).map(move |iy| (ix, iy)))
            .filter(|&(ix, iy)| self.cells.iter().any(|(_, g)| g[ix][iy].enough(min_count)))
            .count();
        (filled, cells)
    }

    /// Probability per cell, NaN where fewer than `min_count` classified samples fell.
    pub fn probability(&self, wheel: Wheel, min_count: u64) -> Vec<Vec<f64>> {
        let Some((_, grid)) = self.cells.iter().find(|(w, _)| *w == wheel) else {
            return vec![vec![f64::NAN; self.y_bins.count()]; self.x_bins.count()];
        };
        grid.iter()
            .map(|col| {
                col.iter()
                    .map(|c| if c.enough(min_count) { c.p() } else { f64::NAN })
                    .collect()
            })
            .collect()
    }
}

/// Edges for drawing: bin edges, or cells centred on grid levels.
pub(crate) fn draw_edges(b: &Bins) -> Vec<f64> {
    if !b.levels {
        return b.edges.clone();
    }
    let l = &b.edges;
    if l.len() == 1 {
        let w = (l[0].abs() * 0.05).max(1e-9);
        return vec![l[0] - w, l[0] + w];
    }
    let mut e = vec![l[0] - 0.5 * (l[1] - l[0])];
    e.extend(b.midpoints());
    e.push(l[l.len() - 1] + 0.5 * (l[l.len() - 1] - l[l.len() - 2]));
    e
}

/// Risk maps of every variant over the axes `x` × `y` (without their nominal curves).
pub(crate) fn risk_maps(
    rows: &Rows,
    (x, xb): (ParamId, &Bins),
    (y, yb): (ParamId, &Bins),
) -> Result<Vec<RiskMap>, AnalysisError> {
    let ny = yb.count() as i64;
    let empty = || vec![vec![ClassCounts::default(); yb.count()]; xb.count()];
    let mut maps: BTreeMap<Variant, BTreeMap<Wheel, CountGrid>> = BTreeMap::new();
    for g in rows.class_counts(&[GroupKey::Cell(x.name(), xb, y.name(), yb)])? {
        let grid = maps
            .entry(g.variant)
            .or_default()
            .entry(g.wheel)
            .or_insert_with(empty);
        let cell = g.bins[0];
        if let (Ok(ix), Ok(iy)) = (usize::try_from(cell / ny), usize::try_from(cell % ny)) {
            if ix < xb.count() && iy < yb.count() {
                grid[ix][iy].merge(&g.counts);
            }
        }
    }
    Ok(maps
        .into_iter()
        .map(|(variant, wheels)| RiskMap {
            variant,
            x,
            y,
            x_bins: xb.clone(),
            y_bins: yb.clone(),
            cells: Wheel::BOTH
                .iter()
                .map(|w| (*w, wheels.get(w).cloned().unwrap_or_else(empty)))
                .collect(),
            nominal: None,
        })
        .collect())
}
