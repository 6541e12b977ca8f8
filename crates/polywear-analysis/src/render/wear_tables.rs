//! The wear answer's tables (CSV and Parquet, through [`super::tables`]): those it shares with
//! the vibration answer, written by [`super::answer_tables`] (`wear_occurrence` per distance,
//! `wear_paired`, `wear_conditional`, `wear_riskmap_<x>_<y>`), then its own: one row per
//! quantity (`wear_severity`), order (`wear_orders`), how near the deepest orders came over the
//! tread's life (`wear_near_misses`) and operating point (`wear_fleet_rows`).

use super::answer_tables::{self, CountColumns};
use super::columns::{count_col, f64_col, str_col};
use crate::analysis::counts::WithinCounts;
use crate::analysis::rows::NEAR_MISS_SHARES;
use crate::analysis::wear_risk::{WearAnalysis, HEADLINE_WITHIN_KM};
use polywear_core::model::Wheel;
use polywear_study::parquet_out::Column;

/// Every wear table: (file stem, columns).
pub(crate) fn tables(w: &WearAnalysis, min_count: u64) -> Vec<(String, Vec<Column>)> {
    let mut out = Vec::new();
    let occurrence = w.occurrence_rows();
    out.push((
        "wear_occurrence".to_string(),
        answer_tables::occurrence(&occurrence, true),
    ));
    out.push((
        "wear_paired".to_string(),
        answer_tables::paired(&w.paired_rows(), true),
    ));
    let h = w.headline_answer();
    let at = Some(HEADLINE_WITHIN_KM);
    out.push((
        "wear_conditional".to_string(),
        answer_tables::conditional(&h.conditional, at, min_count),
    ));
    for (x, y, of_pair) in answer_tables::map_pairs(&h.maps) {
        out.push((
            format!("wear_riskmap_{x}_{y}"),
            answer_tables::risk_map(&of_pair, at, min_count),
        ));
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
    let m = &w.near_misses;
    if !m.is_empty() {
        let mut cols = vec![
            str_col("variant", m, |r| r.variant.to_string()),
            str_col("wheel", m, |r| r.wheel.to_string()),
            count_col("wheels_with_peak", m, |r| r.known),
        ];
        cols.extend(
            NEAR_MISS_SHARES
                .iter()
                .enumerate()
                .map(|(k, t)| count_col(&near_miss_column(*t), m, |r| r.at_least[k])),
        );
        out.push(("wear_near_misses".to_string(), cols));
    }
    if !w.headline_answer().fleet.is_empty() {
        out.push(("wear_fleet_rows".to_string(), fleet_columns(w, min_count)));
    }
    out
}

/// The near-miss table's column of the wheels whose peak reached the share `t` of the visible
/// depth: `reached_10pct`, ..., `reached_visible` for 1.
pub(crate) fn near_miss_column(t: f64) -> String {
    if t >= 1.0 {
        "reached_visible".to_string()
    } else {
        format!("reached_{:.0}pct", 100.0 * t)
    }
}

/// One row per operating point of the file and wheel.
fn fleet_columns(w: &WearAnalysis, min_count: u64) -> Vec<Column> {
    let f = &w.headline_answer().fleet;
    let rows: Vec<(usize, Wheel)> = (0..f.len())
        .flat_map(|i| Wheel::BOTH.map(|wh| (i, wh)))
        .collect();
    let mut cols = vec![
        str_col("variant", &rows, |(i, _)| f[*i].variant.to_string()),
        count_col("row", &rows, |(i, _)| f[*i].row),
        str_col("wheel", &rows, |(_, wh)| wh.to_string()),
    ];
    cols.extend(WithinCounts::columns(
        &rows,
        |(i, wh)| *f[*i].of(*wh),
        min_count,
    ));
    cols
}
