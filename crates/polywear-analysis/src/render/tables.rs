//! The analysis' tables, each as CSV (RFC 4180) and Parquet with the run's metadata in its
//! footer: one row per variant and wheel (occurrence), reason (failures), variant (paired),
//! operating point (fleet rows), bin (conditional), cell (risk maps), quantity (severity),
//! parameter (first-order and Sobol indices) or decoding (robustness).

use std::path::{Path, PathBuf};

use super::answer_tables;
use super::columns::{count_col, f64_col, str_col};
use super::RenderError;
use crate::analysis::failures::Failures;
use crate::analysis::fleet::Fleet;
use crate::analysis::given_data::FirstOrder;
use crate::analysis::robustness::Robustness;
use crate::analysis::sensitivity::{Sensitivity, VIBRATION};
use crate::analysis::severity::Severity;
use crate::analysis::Analysis;
use polywear_core::model::Wheel;
use polywear_core::wording::plain;
use polywear_study::parquet_out::{write_csv, write_table, Column};

/// Writes every table of `a` into `dir`; returns the files written, in order.
pub(crate) fn write_all(dir: &Path, a: &Analysis) -> Result<Vec<PathBuf>, RenderError> {
    let mut files = Vec::new();
    let min_count = a.options.min_count;
    let meta = table_metadata(a);
    let mut write = |stem: &str, cols: &[Column]| write_tables(dir, stem, cols, &meta, &mut files);
    let v = &a.vibration;
    let occurrence: Vec<_> = v.occurrence.iter().map(|o| (f64::NAN, o)).collect();
    write("occurrence", &answer_tables::occurrence(&occurrence, false))?;
    if a.failures.unclassified > 0 {
        write("failures", &failure_columns(&a.failures))?;
    }
    let paired: Vec<_> = v.paired.iter().map(|p| (f64::NAN, p)).collect();
    write("paired", &answer_tables::paired(&paired, false))?;
    if let Some(fleet) = &a.fleet {
        write("fleet_rows", &fleet_columns(fleet))?;
    }
    let cols = answer_tables::conditional(&v.conditional, None, min_count);
    write("conditional", &cols)?;
    for (x, y, of_pair) in answer_tables::map_pairs(&v.maps) {
        let cols = answer_tables::risk_map(&of_pair, None, min_count);
        write(&format!("riskmap_{x}_{y}"), &cols)?;
    }
    write("severity", &severity_columns(&a.severity))?;
    write("first_order", &first_order_columns(&a.first_order))?;
    if let Some(sens) = &a.sensitivity {
        write("sensitivity", &sensitivity_columns(sens))?;
    }
    if !a.scenarios.is_empty() {
        write("scenarios", &super::scenarios::columns(&a.scenarios))?;
    }
    if let Some(r) = &a.robustness {
        write("robustness", &robustness_columns(r, min_count))?;
    }
    if let Some(w) = &a.wear {
        for (stem, cols) in super::wear_tables::tables(w, min_count) {
            write(&stem, &cols)?;
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
        let within: Vec<String> = w.within_km().iter().map(|k| plain(*k, 9)).collect();
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
        count_col(polywear_core::records::OPERATING_POINT_ROW.name, r, |x| {
            x.row
        }),
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
