//! The tables of an [`OutcomeAnswer`], one writer for vibration and for wear: one row per
//! variant and wheel (`occurrence`), variant (`paired`), bin (`conditional`) and cell
//! (`riskmap_<x>_<y>`). The wear answer's tables are named `wear_…` and carry the distance
//! (`within_km`) as a key, one row per distance where it answers at several; the counts'
//! columns are the outcome's own ([`CountColumns`]).

use super::columns::{count_col, f64_col, proportion_columns, str_col};
use crate::analysis::conditional::BinStat;
use crate::analysis::counts::{ClassCounts, RiskCounts, WithinCounts};
use crate::analysis::outcome::Occurrence;
use crate::analysis::paired::Paired;
use crate::analysis::risk_map::RiskMap;
use polywear_core::classify::Class;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_study::parquet_out::Column;

/// The columns an outcome's counts give every probability table: the denominator
/// (`samples`), the numerator, p (NaN below `min_count`) with its Wilson interval, and the
/// rows counted apart.
pub(super) trait CountColumns: RiskCounts {
    /// The count columns of `rows`.
    fn columns<T>(rows: &[T], counts: impl Fn(&T) -> Self, min_count: u64) -> Vec<Column>;
}

impl CountColumns for ClassCounts {
    /// Classified rows, vibrating rows, p and its interval, then the rows per class.
    fn columns<T>(rows: &[T], c: impl Fn(&T) -> Self, min_count: u64) -> Vec<Column> {
        let mut cols = vec![
            count_col("samples", rows, |r| c(r).classified()),
            count_col("vibrating", rows, |r| c(r).vibrating()),
        ];
        cols.extend(proportion_columns(rows, &c, min_count));
        cols.extend([
            count_col(Class::Stable.as_str(), rows, |r| c(r).get(Class::Stable)),
            count_col(Class::LimitCycle.as_str(), rows, |r| {
                c(r).get(Class::LimitCycle)
            }),
            count_col(Class::Bistable.as_str(), rows, |r| {
                c(r).get(Class::Bistable)
            }),
            count_col(Class::NoTraction.as_str(), rows, |r| c(r).no_traction()),
            count_col(Class::Failed.as_str(), rows, |r| c(r).failed()),
        ]);
        cols
    }
}

impl CountColumns for WithinCounts {
    /// Wheels with a distance, those within, p and its interval, the unknown wheels.
    fn columns<T>(rows: &[T], c: impl Fn(&T) -> Self, min_count: u64) -> Vec<Column> {
        let mut cols = vec![
            count_col("samples", rows, |r| c(r).known),
            count_col("within", rows, |r| c(r).within),
        ];
        cols.extend(proportion_columns(rows, &c, min_count));
        cols.push(count_col("unknown", rows, |r| c(r).unknown));
        cols
    }
}

/// The key column before the counts: the distance of a wear table, where `km` gives one
/// (always or never: None for a vibration table, without it).
fn within_col<T>(cols: &mut Vec<Column>, rows: &[T], with: bool, km: impl Fn(&T) -> f64) {
    if with {
        cols.push(f64_col("within_km", rows, km));
    }
}

/// Rows keyed by a distance: (within_km, row); NaN for a vibration table's rows.
pub(super) type AtDistance<'a, T> = (f64, &'a T);

/// One row per variant, wheel (and distance): the outcome's counts, p and its interval.
pub(super) fn occurrence<C: CountColumns>(
    rows: &[AtDistance<'_, Occurrence<C>>],
    with_km: bool,
) -> Vec<Column> {
    let mut cols = vec![
        str_col("variant", rows, |r| r.1.variant.to_string()),
        str_col("wheel", rows, |r| r.1.wheel.to_string()),
    ];
    within_col(&mut cols, rows, with_km, |r| r.0);
    cols.extend(C::columns(rows, |r| r.1.counts, 1));
    cols
}

/// One row per variant (and distance): the samples by which wheel has the outcome, and
/// McNemar's test.
pub(super) fn paired(rows: &[AtDistance<'_, Paired>], with_km: bool) -> Vec<Column> {
    let mut cols = vec![str_col("variant", rows, |r| r.1.variant.to_string())];
    within_col(&mut cols, rows, with_km, |r| r.0);
    cols.extend([
        count_col("pairs", rows, |r| r.1.pairs),
        count_col("only_follower", rows, |r| r.1.only_follower),
        count_col("only_driving", rows, |r| r.1.only_driving),
        count_col("both", rows, |r| r.1.both),
        count_col("neither", rows, |r| r.1.neither),
        count_col("unclassified_pairs", rows, |r| r.1.unclassified),
        f64_col("mcnemar_chi2", rows, |r| r.1.chi2),
        f64_col("p_value", rows, |r| r.1.p_value),
        str_col("method", rows, |r| r.1.method.to_string()),
    ]);
    cols
}

/// One row per variant, wheel, axis and bin.
pub(super) fn conditional<C: CountColumns>(
    bins: &[BinStat<C>],
    within_km: Option<f64>,
    min_count: u64,
) -> Vec<Column> {
    let mut cols = vec![
        str_col("variant", bins, |x| x.variant.to_string()),
        str_col("wheel", bins, |x| x.wheel.to_string()),
        str_col("axis", bins, |x| x.axis.to_string()),
        f64_col("bin_lo", bins, |x| x.lo),
        f64_col("bin_hi", bins, |x| x.hi),
        f64_col("bin_mid", bins, |x| x.mid),
    ];
    within_col(&mut cols, bins, within_km.is_some(), |_| {
        within_km.unwrap_or(f64::NAN)
    });
    cols.extend(C::columns(bins, |x| x.counts, min_count));
    cols
}

/// The maps of each pair of axes, in the order of `maps`: (x, y, the maps of every variant).
pub(super) fn map_pairs<C>(maps: &[RiskMap<C>]) -> Vec<(ParamId, ParamId, Vec<&RiskMap<C>>)> {
    let mut out: Vec<(ParamId, ParamId, Vec<&RiskMap<C>>)> = Vec::new();
    for m in maps {
        match out.iter_mut().find(|(x, y, _)| (*x, *y) == (m.x, m.y)) {
            Some((_, _, of)) => of.push(m),
            None => out.push((m.x, m.y, vec![m])),
        }
    }
    out
}

/// One row per variant, wheel and cell of the maps of one pair of axes: the cell's edges on
/// both axes and its counts.
pub(super) fn risk_map<C: CountColumns>(
    maps: &[&RiskMap<C>],
    within_km: Option<f64>,
    min_count: u64,
) -> Vec<Column> {
    // (variant, wheel, x_lo, x_hi, y_lo, y_hi, counts)
    type Cell<C> = (Variant, Wheel, f64, f64, f64, f64, C);
    let rows: Vec<Cell<C>> = maps
        .iter()
        .flat_map(|map| {
            map.each_cell().map(|(wheel, ix, iy, c)| {
                let (xl, xh, _) = map.x_bins.range(ix);
                let (yl, yh, _) = map.y_bins.range(iy);
                (map.variant, wheel, xl, xh, yl, yh, c)
            })
        })
        .collect();
    let (x, y) = (&maps[0].x, &maps[0].y);
    let mut cols = vec![
        str_col("variant", &rows, |r| r.0.to_string()),
        str_col("wheel", &rows, |r| r.1.to_string()),
        f64_col(&format!("{x}_lo"), &rows, |r| r.2),
        f64_col(&format!("{x}_hi"), &rows, |r| r.3),
        f64_col(&format!("{y}_lo"), &rows, |r| r.4),
        f64_col(&format!("{y}_hi"), &rows, |r| r.5),
    ];
    within_col(&mut cols, &rows, within_km.is_some(), |_| {
        within_km.unwrap_or(f64::NAN)
    });
    cols.extend(C::columns(&rows, |r| r.6, min_count));
    cols
}
