//! The analysis' tables, each as CSV (RFC 4180) and Parquet with the run's metadata in its
//! footer: one row per variant and wheel (occurrence), reason (failures), variant (paired),
//! operating point (fleet rows), bin (conditional), cell (risk maps), quantity (severity),
//! parameter (first-order and Sobol indices) or decoding (robustness).

use std::path::{Path, PathBuf};

use super::columns::{count_col, f64_col, proportion_columns, str_col};
use super::RenderError;
use crate::analysis::conditional::BinStat;
use crate::analysis::counts::ClassCounts;
use crate::analysis::failures::Failures;
use crate::analysis::fleet::Fleet;
use crate::analysis::given_data::FirstOrder;
use crate::analysis::occurrence::Occurrence;
use crate::analysis::paired::Paired;
use crate::analysis::risk_map::RiskMap;
use crate::analysis::robustness::Robustness;
use crate::analysis::sensitivity::{Sensitivity, VIBRATION};
use crate::analysis::severity::Severity;
use crate::analysis::Analysis;
use polywear_core::classify::Class;
use polywear_core::model::{Variant, Wheel};
use polywear_core::wording::plain;
use polywear_study::parquet_out::{write_csv, write_table, Column};

/// Writes every table of `a` into `dir`; returns the files written, in order.
pub(crate) fn write_all(dir: &Path, a: &Analysis) -> Result<Vec<PathBuf>, RenderError> {
    let mut files = Vec::new();
    let min_count = a.options.min_count;
    let meta = table_metadata(a);
    write_tables(
        dir,
        "occurrence",
        &occurrence_columns(&a.occurrence),
        &meta,
        &mut files,
    )?;
    if a.failures.unclassified > 0 {
        let cols = failure_columns(&a.failures);
        write_tables(dir, "failures", &cols, &meta, &mut files)?;
    }
    write_tables(dir, "paired", &paired_columns(&a.paired), &meta, &mut files)?;
    if let Some(fleet) = &a.fleet {
        let cols = fleet_columns(fleet);
        write_tables(dir, "fleet_rows", &cols, &meta, &mut files)?;
    }
    write_tables(
        dir,
        "conditional",
        &conditional_columns(&a.conditional, min_count),
        &meta,
        &mut files,
    )?;
    for (x, y) in &a.options.pairs {
        let of_pair: Vec<&RiskMap> = a.maps.iter().filter(|m| m.x == *x && m.y == *y).collect();
        if !of_pair.is_empty() {
            write_tables(
                dir,
                &format!("riskmap_{x}_{y}"),
                &riskmap_columns(&of_pair, min_count),
                &meta,
                &mut files,
            )?;
        }
    }
    write_tables(
        dir,
        "severity",
        &severity_columns(&a.severity),
        &meta,
        &mut files,
    )?;
    let cols = first_order_columns(&a.first_order);
    write_tables(dir, "first_order", &cols, &meta, &mut files)?;
    if let Some(sens) = &a.sensitivity {
        write_tables(
            dir,
            "sensitivity",
            &sensitivity_columns(sens),
            &meta,
            &mut files,
        )?;
    }
    if !a.scenarios.is_empty() {
        let cols = super::scenarios::columns(&a.scenarios);
        write_tables(dir, "scenarios", &cols, &meta, &mut files)?;
    }
    if let Some(r) = &a.robustness {
        write_tables(
            dir,
            "robustness",
            &robustness_columns(r, min_count),
            &meta,
            &mut files,
        )?;
    }
    if let Some(w) = &a.wear {
        for (stem, cols) in super::wear_tables::tables(w, min_count) {
            write_tables(dir, &stem, &cols, &meta, &mut files)?;
        }
    }
    Ok(files)
}

/// Footer metadata of the Parquet tables: which run and settings they come from.
fn table_metadata(a: &Analysis) -> Vec<(String, String)> {
    let info = &a.info;
    let mut meta: Vec<(String, String)> = vec![
        ("study_name".into(), info.study_name.clone()),
        ("study_hash".into(), info.study_hash.clone()),
        ("seed".into(), info.seed.to_string()),
        ("variant".into(), info.variant_text()),
        ("samples".into(), info.samples.to_string()),
        ("samples_present".into(), info.samples_present.to_string()),
        ("min_count".into(), a.options.min_count.to_string()),
        (
            "polywear_version".into(),
            polywear_study::provenance::POLYWEAR_VERSION.to_string(),
        ),
    ];
    if let Some(w) = &a.wear {
        let within: Vec<String> = w.within_km.iter().map(|k| plain(*k, 9)).collect();
        meta.push(("within_km".into(), within.join(",")));
        meta.push(("wear_share_straight".into(), w.share_straight.to_string()));
        meta.push(("speed_spread_kmh".into(), w.speed_spread_kmh.to_string()));
        meta.push(("visible_depth_mm".into(), w.visible_depth_mm.to_string()));
    }
    meta
}

/// Writes one table as `stem.csv` (RFC 4180) and `stem.parquet`.
pub(super) fn write_tables(
    dir: &Path,
    stem: &str,
    cols: &[Column],
    meta: &[(String, String)],
    files: &mut Vec<PathBuf>,
) -> Result<(), RenderError> {
    let csv = dir.join(format!("{stem}.csv"));
    write_csv(&csv, cols).map_err(|e| RenderError::Write(e.to_string()))?;
    files.push(csv);
    let pq = dir.join(format!("{stem}.parquet"));
    write_table(&pq, cols, meta).map_err(|e| RenderError::Write(e.to_string()))?;
    files.push(pq);
    Ok(())
}

/// The class-count columns every probability table carries: classified rows (`samples`),
/// vibrating rows, p with its Wilson interval, and the unclassified rows on their own.
fn class_columns<T>(rows: &[T], counts: impl Fn(&T) -> ClassCounts, min_count: u64) -> Vec<Column> {
    let c = |r: &T| counts(r);
    let mut cols = vec![
        count_col("samples", rows, |r| c(r).classified()),
        count_col("vibrating", rows, |r| c(r).vibrating()),
    ];
    cols.extend(proportion_columns(rows, c, min_count));
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

fn occurrence_columns(o: &[Occurrence]) -> Vec<Column> {
    let mut cols = vec![
        str_col("variant", o, |x| x.variant.to_string()),
        str_col("wheel", o, |x| x.wheel.to_string()),
    ];
    cols.extend(class_columns(o, |x| x.counts, 1));
    cols
}

fn paired_columns(p: &[Paired]) -> Vec<Column> {
    vec![
        str_col("variant", p, |x| x.variant.to_string()),
        count_col("pairs", p, |x| x.pairs),
        count_col("only_follower", p, |x| x.only_follower),
        count_col("only_driving", p, |x| x.only_driving),
        count_col("both", p, |x| x.both),
        count_col("neither", p, |x| x.neither),
        count_col("unclassified_pairs", p, |x| x.unclassified),
        f64_col("mcnemar_chi2", p, |x| x.chi2),
        f64_col("p_value", p, |x| x.p_value),
        str_col("method", p, |x| x.method.to_string()),
    ]
}

fn conditional_columns(b: &[BinStat], min_count: u64) -> Vec<Column> {
    let mut cols = vec![
        str_col("variant", b, |x| x.variant.to_string()),
        str_col("wheel", b, |x| x.wheel.to_string()),
        str_col("axis", b, |x| x.axis.to_string()),
        f64_col("bin_lo", b, |x| x.lo),
        f64_col("bin_hi", b, |x| x.hi),
        f64_col("bin_mid", b, |x| x.mid),
    ];
    cols.extend(class_columns(b, |x| x.counts, min_count));
    cols
}

fn riskmap_columns(maps: &[&RiskMap], min_count: u64) -> Vec<Column> {
    // (variant, wheel, x_lo, x_hi, y_lo, y_hi, counts)
    type Cell = (Variant, Wheel, f64, f64, f64, f64, ClassCounts);
    let rows: Vec<Cell> = maps
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
    cols.extend(class_columns(&rows, |r| r.6, min_count));
    cols
}

fn severity_columns(s: &[Severity]) -> Vec<Column> {
    vec![
        str_col("variant", s, |x| x.variant.to_string()),
        str_col("wheel", s, |x| x.wheel.to_string()),
        str_col("quantity", s, |x| x.quantity.to_string()),
        str_col("unit", s, |x| x.unit.to_string()),
        count_col("limit_cycles", s, |x| x.n),
        f64_col("mean", s, |x| x.mean),
        f64_col("q05", s, |x| x.quantiles[0]),
        f64_col("q25", s, |x| x.quantiles[1]),
        f64_col("median", s, |x| x.quantiles[2]),
        f64_col("q75", s, |x| x.quantiles[3]),
        f64_col("q95", s, |x| x.quantiles[4]),
    ]
}

fn failure_columns(f: &Failures) -> Vec<Column> {
    let g = &f.groups;
    vec![
        str_col("class", g, |x| x.class.to_string()),
        count_col("rows", g, |x| x.rows),
        f64_col("share_of_rows", g, |x| x.rows as f64 / f.rows.max(1) as f64),
        str_col("reason_pattern", g, |x| x.pattern.clone()),
        str_col("example", g, |x| x.example.clone()),
    ]
}

/// One row per operating point and variant, in the report's order (largest share of the
/// fleet's risk first): its values, share of the weight, and per wheel the class counts,
/// P(vibration) with its Wilson interval and share of the risk.
fn fleet_columns(fleet: &Fleet) -> Vec<Column> {
    let r = &fleet.rows;
    let mut cols = vec![
        str_col("variant", r, |x| x.variant.to_string()),
        count_col(crate::analysis::fleet::ROW_COLUMN, r, |x| x.row),
    ];
    for (j, c) in fleet.columns.iter().enumerate() {
        let unit = polywear_core::params::spec(c).map_or("", |s| s.unit);
        cols.push(Column::f64(
            c.clone(),
            unit,
            r.iter()
                .map(|x| x.values.get(j).copied().unwrap_or(f64::NAN))
                .collect(),
        ));
    }
    cols.push(f64_col("weight_share", r, |x| x.weight_share));
    for wheel in Wheel::BOTH {
        let c = |x: &crate::analysis::fleet::FleetRow| *x.counts(wheel);
        cols.extend([
            count_col(&format!("{wheel}_samples"), r, |x| c(x).classified()),
            count_col(&format!("{wheel}_vibrating"), r, |x| c(x).vibrating()),
            count_col(&format!("{wheel}_unclassified"), r, |x| {
                c(x).total() - c(x).classified()
            }),
            f64_col(&format!("{wheel}_p"), r, |x| c(x).p()),
            f64_col(&format!("{wheel}_wilson95_lo"), r, |x| c(x).wilson().0),
            f64_col(&format!("{wheel}_wilson95_hi"), r, |x| c(x).wilson().1),
        ]);
    }
    cols.extend([
        f64_col("follower_risk_share", r, |x| x.risk_share[0]),
        f64_col("driving_risk_share", r, |x| x.risk_share[1]),
        f64_col("risk_share", r, |x| x.risk_share_both),
    ]);
    cols
}

fn first_order_columns(f: &[FirstOrder]) -> Vec<Column> {
    vec![
        str_col("variant", f, |x| x.variant.to_string()),
        str_col("wheel", f, |x| x.wheel.to_string()),
        str_col("output", f, |_| VIBRATION.to_string()),
        str_col("param", f, |x| x.param.to_string()),
        count_col("rows", f, |x| x.rows),
        count_col("classes", f, |x| x.classes as u64),
        f64_col("first_order", f, |x| x.s1),
        f64_col("first_order_conf", f, |x| x.conf),
        f64_col("noise", f, |x| x.noise),
    ]
}

fn sensitivity_columns(s: &[Sensitivity]) -> Vec<Column> {
    vec![
        str_col("variant", s, |x| x.variant.to_string()),
        str_col("wheel", s, |x| x.wheel.to_string()),
        str_col("output", s, |x| x.output.to_string()),
        str_col("param", s, |x| x.param.to_string()),
        count_col("base_samples", s, |x| x.base_samples),
        f64_col("first_order", s, |x| x.s.0),
        f64_col("first_order_lo", s, |x| x.s.1),
        f64_col("first_order_hi", s, |x| x.s.2),
        f64_col("total", s, |x| x.st.0),
        f64_col("total_lo", s, |x| x.st.1),
        f64_col("total_hi", s, |x| x.st.2),
        count_col("base_samples_left_out", s, |x| x.left_out),
    ]
}

fn robustness_columns(r: &Robustness, min_count: u64) -> Vec<Column> {
    let d = &r.decodings;
    let mut cols = vec![str_col("variant", d, |x| x.variant.to_string())];
    for (i, p) in r.params.iter().enumerate() {
        cols.push(f64_col(p.name(), d, |x| x.values[i]));
    }
    cols.extend([
        count_col("follower_samples", d, |x| x.follower.classified()),
        count_col("follower_vibrating", d, |x| x.follower.vibrating()),
        f64_col("follower_p", d, |x| x.follower.p()),
        count_col("driving_samples", d, |x| x.driving.classified()),
        count_col("driving_vibrating", d, |x| x.driving.vibrating()),
        f64_col("driving_p", d, |x| x.driving.p()),
        count_col("unclassified", d, |x| {
            x.follower.total() - x.follower.classified() + x.driving.total()
                - x.driving.classified()
        }),
        str_col("driving_less_exposed", d, |x| {
            if !x.comparable(min_count) {
                "too few samples".into()
            } else if x.driving_less_exposed() {
                "yes".into()
            } else {
                "no".into()
            }
        }),
    ]);
    cols
}
