//! The report's answer to "which of my operating points are risky": for a study with
//! `[operating_points]`, the file's rows sorted by their share of the fleet's risk, with their
//! values, share of the weight and P(vibration) per wheel.

use std::fmt::Write as _;

use super::words::pct;
use crate::analysis::fleet::{Fleet, FleetRow};
use crate::analysis::Analysis;
use polywear_core::model::{Variant, Wheel};
use polywear_core::wording::plain;

/// Rows of the per-row table shown on the page; the CSV has them all.
pub(crate) const SHOWN_ROWS: usize = 40;

/// How many of the riskiest rows hold at least half of the fleet's risk (both wheels), and
/// their share of the weight.
pub(crate) fn half_the_risk(rows: &[&FleetRow]) -> Option<(usize, f64)> {
    let mut risk = 0.0;
    let mut weight = 0.0;
    for (k, r) in rows.iter().enumerate() {
        if !r.risk_share_both.is_finite() {
            return None;
        }
        risk += r.risk_share_both;
        weight += r.weight_share;
        if risk >= 0.5 {
            return Some((k + 1, weight));
        }
    }
    None
}

/// "P (lo – hi)" of one wheel of a row.
fn wheel_cell(r: &FleetRow, w: Wheel) -> String {
    let c = r.counts(w);
    let (lo, hi) = c.wilson();
    format!("{} ({} – {})", pct(c.p()), pct(lo), pct(hi))
}

/// The per-row section, for a fleet run.
pub(crate) fn fleet_section(s: &mut String, a: &Analysis) {
    let Some(fleet) = &a.fleet else {
        return;
    };
    let _ = writeln!(s, "## Which operating points carry the risk?\n");
    let _ = writeln!(
        s,
        "Each row of `{}` (numbered from 1 as in the file, the `operating_point_row` column of \
         the rows), with P(vibration) per wheel and its 95% Wilson interval over the samples \
         that drew it, its share of the {} and its share of the fleet's risk: its term \
         w·P of the weighted P(vibration), per wheel and for both wheels together. Sorted by \
         the share of both wheels. Tables: `fleet_rows.csv`, `fleet_rows.parquet`.\n",
        fleet.file,
        fleet.weight.short()
    );
    let variants: Vec<Variant> = a.variants();
    for &variant in &variants {
        let rows: Vec<&FleetRow> = fleet.rows.iter().filter(|r| r.variant == variant).collect();
        if variants.len() > 1 {
            let _ = writeln!(s, "### Variant `{variant}`\n");
        }
        if let Some((k, weight)) = half_the_risk(&rows) {
            let _ = writeln!(
                s,
                "**{k} of the {} operating points carry half of the fleet's risk**; they hold {} \
                 of the {}.\n",
                rows.len(),
                pct(weight),
                fleet.weight.short()
            );
        }
        fleet_table(s, fleet, &rows);
    }
    if fleet.never_drawn > 0 {
        let _ = writeln!(
            s,
            "{} rows of positive weight were drawn by no sample: more samples would reach them.\n",
            fleet.never_drawn
        );
    }
}

fn fleet_table(s: &mut String, fleet: &Fleet, rows: &[&FleetRow]) {
    let labels: Vec<String> = fleet
        .columns
        .iter()
        .map(|c| polywear_core::params::axis_label(c, ""))
        .collect();
    let _ = writeln!(
        s,
        "| rank | row | {} | share of {} | follower P(vibration) (95%) | driving P(vibration) (95%) | share of risk, both wheels | follower | driving |",
        labels.join(" | "),
        fleet.weight.short()
    );
    let _ = writeln!(
        s,
        "|---:|---:|{}---:|---:|---:|---:|---:|---:|",
        "---:|".repeat(labels.len())
    );
    for (k, r) in rows.iter().take(SHOWN_ROWS).enumerate() {
        let values: Vec<String> = (0..labels.len())
            .map(|j| r.values.get(j).map_or("n/a".into(), |v| plain(*v, 6)))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            k + 1,
            r.row,
            values.join(" | "),
            pct(r.weight_share),
            wheel_cell(r, Wheel::Follower),
            wheel_cell(r, Wheel::Driving),
            pct(r.risk_share_both),
            pct(r.risk_share[0]),
            pct(r.risk_share[1])
        );
    }
    if rows.len() > SHOWN_ROWS {
        let _ = writeln!(
            s,
            "\n({} more rows in `fleet_rows.csv`.)",
            rows.len() - SHOWN_ROWS
        );
    }
    let _ = writeln!(s);
}
