//! Where the risk lives over two axes: an outcome's counts over a grid of bins, per variant and
//! wheel (`crate::analysis::outcome::answer` counts the cells).

use std::collections::BTreeMap;

use super::bins::Bins;
use super::counts::{ClassCounts, RiskCounts};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_study::chart::WheelCurves;

/// Counts per cell, indexed `[ix][iy]`.
pub(crate) type Grid<C> = Vec<Vec<C>>;

/// A risk map: counts over a 2-D grid of bins of two axes, per wheel. The vibration analysis
/// counts rows per class ([`ClassCounts`], the default); the wear analysis counts wheels within
/// a distance over the same cells ([`crate::analysis::counts::WithinCounts`]), so both maps
/// share their axes, bins and Hopf curves.
#[derive(Debug, Clone)]
pub struct RiskMap<C = ClassCounts> {
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
    pub cells: Vec<(Wheel, Grid<C>)>,
    /// The Hopf curves of the run's nominal tire over the map's box (the study's median values
    /// elsewhere), when they can be traced: the stability boundary the map should follow.
    pub nominal: Option<Vec<WheelCurves>>,
}

impl<C: RiskCounts> RiskMap<C> {
    /// (cells where some wheel has at least `min_count` samples counted, all cells).
    pub fn coverage(&self, min_count: u64) -> (usize, usize) {
        let cells = self.x_bins.count() * self.y_bins.count();
        let filled = (0..self.x_bins.count())
            .flat_map(|ix| (0..self.y_bins.count()).map(move |iy| (ix, iy)))
            .filter(|&(ix, iy)| self.cells.iter().any(|(_, g)| g[ix][iy].enough(min_count)))
            .count();
        (filled, cells)
    }

    /// Probability per cell, NaN where fewer than `min_count` samples are counted.
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

    /// Every cell of every wheel: (wheel, ix, iy, counts), wheel by wheel, `ix` then `iy`.
    pub fn each_cell(&self) -> impl Iterator<Item = (Wheel, usize, usize, C)> + '_ {
        self.cells.iter().flat_map(|(wheel, grid)| {
            grid.iter().enumerate().flat_map(move |(ix, col)| {
                col.iter()
                    .enumerate()
                    .map(move |(iy, c)| (*wheel, ix, iy, *c))
            })
        })
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

/// One map per variant present in `cells` (variant, wheel, cell index of a
/// [`GroupKey::Cell`](crate::analysis::rows::GroupKey::Cell) key, counts), both wheels each (a wheel without rows with empty cells),
/// without their nominal curves; a cell index outside the grid is left out.
pub(crate) fn maps_of_cells<'a, C: RiskCounts + 'a>(
    cells: impl IntoIterator<Item = (Variant, Wheel, i64, &'a C)>,
    (x, xb): (ParamId, &Bins),
    (y, yb): (ParamId, &Bins),
) -> Vec<RiskMap<C>> {
    let ny = yb.count() as i64;
    let empty = || vec![vec![C::default(); yb.count()]; xb.count()];
    let mut maps: BTreeMap<Variant, BTreeMap<Wheel, Grid<C>>> = BTreeMap::new();
    for (variant, wheel, cell, counts) in cells {
        let grid = maps
            .entry(variant)
            .or_default()
            .entry(wheel)
            .or_insert_with(empty);
        if let (Ok(ix), Ok(iy)) = (usize::try_from(cell / ny), usize::try_from(cell % ny)) {
            if ix < xb.count() && iy < yb.count() {
                grid[ix][iy].merge(counts);
            }
        }
    }
    maps.into_iter()
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
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::counts::WithinCounts;

    fn within(within: u64, known: u64) -> WithinCounts {
        WithinCounts {
            within,
            known,
            unknown: 0,
            w_within: within as i64,
            w_known: known as i64,
            w2_known: known as i64,
        }
    }

    #[test]
    fn cells_fold_into_one_map_per_variant_with_both_wheels_whatever_they_count() {
        let (xb, yb) = (
            Bins::equal_width(0.0, 1.0, 3),
            Bins::equal_width(0.0, 1.0, 2),
        );
        let (x, y) = (ParamId::SpeedKmh, ParamId::ToeDeg);
        // Cell 5 = (ix 2, iy 1), twice; cell 6 lies outside the 3 × 2 grid; the combined
        // variant has follower rows only.
        let a = within(1, 4);
        let b = within(2, 3);
        let cells = [
            (Variant::SlidingShare, Wheel::Driving, 5, &a),
            (Variant::SlidingShare, Wheel::Driving, 5, &b),
            (Variant::SlidingShare, Wheel::Driving, 6, &a),
            (Variant::Combined, Wheel::Follower, 0, &a),
        ];
        let maps = maps_of_cells(cells, (x, &xb), (y, &yb));
        let variants: Vec<Variant> = maps.iter().map(|m| m.variant).collect();
        assert_eq!(variants, [Variant::Combined, Variant::SlidingShare]);
        let share = &maps[1];
        let wheels: Vec<Wheel> = share.cells.iter().map(|(w, _)| *w).collect();
        assert_eq!(wheels, Wheel::BOTH);
        let driving = share.probability(Wheel::Driving, 1);
        assert_eq!(driving[2][1], 3.0 / 7.0);
        let counted: u64 = share.each_cell().map(|(_, _, _, c)| c.known).sum();
        assert_eq!(counted, 7, "the cell outside the grid is left out");
        assert!(share.probability(Wheel::Follower, 1)[0][0].is_nan());
        assert_eq!(share.coverage(1), (1, 6));
        // Cells in the tables' order: wheel by wheel, ix then iy.
        let order: Vec<(Wheel, usize, usize)> = share
            .each_cell()
            .map(|(w, ix, iy, _)| (w, ix, iy))
            .collect();
        assert_eq!(order.len(), 12);
        assert_eq!(order[1], (Wheel::Follower, 0, 1));
        assert_eq!(order[11], (Wheel::Driving, 2, 1));
        // Class counts fold the same way.
        let mut c = ClassCounts::default();
        c.add(polywear_core::classify::Class::LimitCycle, 3);
        c.add(polywear_core::classify::Class::Stable, 1);
        let class_maps = maps_of_cells(
            [(Variant::Paper, Wheel::Follower, 1, &c)],
            (x, &xb),
            (y, &yb),
        );
        assert_eq!(class_maps[0].probability(Wheel::Follower, 1)[0][1], 0.75);
    }
}
