//! The wear answer's tables (CSV and Parquet, through [`super::tables`]): one row per variant,
//! wheel and distance (`wear_occurrence`), variant and distance (`wear_paired`), bin
//! (`wear_conditional`), cell (`wear_riskmap_<x>_<y>`), quantity (`wear_severity`), order
//! (`wear_orders`) and operating point (`wear_fleet_rows`).

use super::columns::{count_col, f64_col, proportion_columns, str_col};
use crate::analysis::counts::WithinCounts;
use crate::analysis::wear_risk::{WearAnalysis, WearMap, HEADLINE_WITHIN_KM};
use polywear_core::model::Wheel;
use polywear_study::parquet_out::Column;

/// The counts every wear probability table carries: wheels with a distance, those within, p
/// (NaN below `min_count`) with its Wilson interval, and the unknown wheels.
fn within_columns<T>(rows: &[T], c: impl Fn(&T) -> WithinCounts, min_count: u64) -> Vec<Column> {
    let mut cols = vec![
        count_col("samples", rows, |r| c(r).known),
        count_col("within", rows, |r| c(r).within),
    ];
    cols.extend(proportion_columns(rows, &c, min_count));
    cols.push(count_col("unknown", rows, |r| c(r).unknown));
    cols
}

/// Every wear table: (file stem, columns).
pub fn tables(w: &WearAnalysis, min_count: u64) -> Vec<(String, Vec<Column>)> {
    let mut out = Vec::new();
    let o = &w.occurrence;
    let mut cols = vec![
        str_col("variant", o, |r| r.variant.to_string()),
        str_col("wheel", o, |r| r.wheel.to_string()),
        f64_col("within_km", o, |r| r.within_km),
    ];
    cols.extend(within_columns(o, |r| r.counts, 1));
    out.push(("wear_occurrence".to_string(), cols));
    let p = &w.paired;
    out.push((
        "wear_paired".to_string(),
        vec![
            str_col("variant", p, |r| r.paired.variant.to_string()),
            f64_col("within_km", p, |r| r.within_km),
            count_col("pairs", p, |r| r.paired.pairs),
            count_col("only_follower", p, |r| r.paired.only_follower),
            count_col("only_driving", p, |r| r.paired.only_driving),
            count_col("both", p, |r| r.paired.both),
            count_col("neither", p, |r| r.paired.neither),
            count_col("unknown", p, |r| r.paired.unclassified),
            f64_col("mcnemar_chi2", p, |r| r.paired.chi2),
            f64_col("mcnemar_p", p, |r| r.paired.p_value),
            str_col("mcnemar_method", p, |r| r.paired.method.to_string()),
        ],
    ));
    let b = &w.conditional;
    let mut cols = vec![
        str_col("variant", b, |r| r.variant.to_string()),
        str_col("wheel", b, |r| r.wheel.to_string()),
        str_col("axis", b, |r| r.axis.to_string()),
        f64_col("lo", b, |r| r.lo),
        f64_col("hi", b, |r| r.hi),
        f64_col("mid", b, |r| r.mid),
    ];
    cols.extend(within_columns(b, |r| r.counts, min_count));
    out.push(("wear_conditional".to_string(), cols));
    let mut pairs: Vec<(String, String)> = w
        .maps
        .iter()
        .map(|m| (m.x.to_string(), m.y.to_string()))
        .collect();
    pairs.dedup();
    for (x, y) in pairs {
        let of: Vec<&WearMap> = w
            .maps
            .iter()
            .filter(|m| m.x.to_string() == x && m.y.to_string() == y)
            .collect();
        out.push((format!("wear_riskmap_{x}_{y}"), map_columns(&of, min_count)));
    }
    let s = &w.severity;
    out.push((
        "wear_severity".to_string(),
        vec![
            str_col("variant", s, |r| r.variant.to_string()),
            str_col("wheel", s, |r| r.wheel.to_string()),
            str_col("quantity", s, |r| r.quantity.column.name().to_string()),
            str_col("unit", s, |r| r.quantity.column.unit().to_string()),
            count_col("finite", s, |r| r.spread.finite),
            count_col("pos_inf", s, |r| r.spread.pos_inf),
            count_col("unknown", s, |r| r.spread.unknown),
            f64_col("q05", s, |r| r.quantiles[0]),
            f64_col("q25", s, |r| r.quantiles[1]),
            f64_col("q50", s, |r| r.quantiles[2]),
            f64_col("q75", s, |r| r.quantiles[3]),
            f64_col("q95", s, |r| r.quantiles[4]),
        ],
    ));
    let d = &w.orders;
    out.push((
        "wear_orders".to_string(),
        vec![
            str_col("variant", d, |r| r.variant.to_string()),
            str_col("wheel", d, |r| r.wheel.to_string()),
            count_col("order", d, |r| r.order as u64),
            count_col("wheels", d, |r| r.n),
        ],
    ));
    if !w.fleet.is_empty() {
        out.push(("wear_fleet_rows".to_string(), fleet_columns(w, min_count)));
    }
    out
}

/// One row per variant, wheel and cell of the wear risk maps of one pair of axes.
fn map_columns(maps: &[&WearMap], min_count: u64) -> Vec<Column> {
    let rows: Vec<(&WearMap, Wheel, usize, usize, WithinCounts)> = maps
        .iter()
        .flat_map(|m| m.each_cell().map(move |(w, ix, iy, c)| (*m, w, ix, iy, c)))
        .collect();
    let mut cols = vec![
        str_col("variant", &rows, |r| r.0.variant.to_string()),
        str_col("wheel", &rows, |r| r.1.to_string()),
        f64_col("x_mid", &rows, |r| r.0.x_bins.range(r.2).2),
        f64_col("y_mid", &rows, |r| r.0.y_bins.range(r.3).2),
        f64_col("within_km", &rows, |_| HEADLINE_WITHIN_KM),
    ];
    cols.extend(within_columns(&rows, |r| r.4, min_count));
    cols
}

/// One row per operating point of the file and wheel.
fn fleet_columns(w: &WearAnalysis, min_count: u64) -> Vec<Column> {
    let rows: Vec<(usize, Wheel)> = (0..w.fleet.len())
        .flat_map(|i| Wheel::BOTH.map(|wh| (i, wh)))
        .collect();
    let f = &w.fleet;
    let k = |wh: Wheel| usize::from(wh == Wheel::Driving);
    let mut cols = vec![
        str_col("variant", &rows, |(i, _)| f[*i].variant.to_string()),
        count_col("row", &rows, |(i, _)| f[*i].row),
        str_col("wheel", &rows, |(_, wh)| wh.to_string()),
    ];
    cols.extend(within_columns(
        &rows,
        |(i, wh)| f[*i].counts[k(*wh)],
        min_count,
    ));
    cols
}
