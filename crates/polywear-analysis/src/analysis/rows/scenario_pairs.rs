//! The paired outcomes of a run with scenarios: per sample, variant and wheel, the outcome under
//! each scenario's reference (the baseline, or the scenario its `compare_to` names) beside the
//! outcome under the scenario, counted by pair of outcomes.

use std::collections::BTreeMap;
use std::path::PathBuf;

use polars::prelude::*;

use super::{collect, file_rows, ints, outcome_expr, strs, Rows};
use crate::analysis::AnalysisError;
use polywear_core::model::{Variant, Wheel};
use polywear_core::records::WearColumn;
use polywear_core::text_enum::UnknownName;
use polywear_study::study::BASELINE;

/// Samples per (scenario index, variant, wheel, reference code, scenario code), the codes those
/// of [`crate::analysis::counts::outcome_code`]: 0 no, 1 yes, 2 unclassified; the scenario
/// index counts the scenarios from 0, the baseline not included. The reference is the baseline
/// unless [`scenario_pairs`] is given another.
pub(crate) type ScenarioPairCounts = BTreeMap<(usize, Variant, Wheel, i64, i64), u64>;

/// What a row's outcome is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutcomeColumn<'a> {
    /// The wheel vibrates (class limit cycle or bistable).
    Vibration,
    /// The wheel's value of `column` (a distance in km: +inf where never) is at most `km`;
    /// unclassified where the row failed, had no traction, or the value is NaN.
    WithinKm {
        /// The distance column.
        column: &'a str,
        /// The distance \[km\].
        km: f64,
    },
}

impl OutcomeColumn<'_> {
    /// The outcome's name in tables: `vibration`, `wear_within_40000_km`.
    pub fn name(&self) -> String {
        match self {
            OutcomeColumn::Vibration => "vibration".into(),
            OutcomeColumn::WithinKm { km, .. } => {
                format!("wear_within_{}_km", polywear_core::wording::plain(*km, 9))
            }
        }
    }
}

/// The row's outcome code as a polars expression.
pub(super) fn code_expr(outcome: OutcomeColumn<'_>) -> Expr {
    match outcome {
        OutcomeColumn::Vibration => outcome_expr(),
        OutcomeColumn::WithinKm { column, km } => {
            let x = col(column).cast(DataType::Float64);
            let unknown = |e: Expr| e.clone().is_null().or(e.is_nan());
            // A polygon counts only if it comes before the tire is worn out (the row's
            // wear_outcome "visible"): a tire replaced first never shows it.
            let life = col(WearColumn::TreadLifeKm.name()).cast(DataType::Float64);
            when(outcome_expr().eq(lit(2i64)))
                .then(lit(2i64))
                .when(unknown(x.clone()).or(unknown(life.clone())))
                .then(lit(2i64))
                .when(x.clone().lt_eq(lit(km)).and(x.lt_eq(life)))
                .then(lit(1i64))
                .otherwise(lit(0i64))
        }
    }
}

/// Counts every sample's pair of outcomes (reference, scenario) for each of `scenarios` (the
/// names after the baseline, in row order), variant and wheel: `references[k]` is the row block
/// scenario k is compared with (0 the baseline, j + 1 scenario j). A sample's rows all lie in
/// one chunk file, so the files are grouped in batches of about `batch_rows` rows and the
/// group-by never holds more than one batch's samples; each sample's blocks are then in one
/// group, so any reference costs the same query. A sample missing a row counts as unclassified
/// under its block.
pub(crate) fn scenario_pairs(
    files: &[PathBuf],
    batch_rows: u64,
    scenarios: &[&str],
    references: &[usize],
    outcome: OutcomeColumn<'_>,
) -> Result<ScenarioPairCounts, AnalysisError> {
    assert_eq!(
        scenarios.len(),
        references.len(),
        "one reference per scenario"
    );
    assert!(
        references.iter().all(|&r| r <= scenarios.len()),
        "a reference names a block of the rows"
    );
    let names: Vec<&str> = std::iter::once(BASELINE)
        .chain(scenarios.iter().copied())
        .collect();
    let code_cols: Vec<String> = (0..names.len()).map(|k| format!("c{k}")).collect();
    let mut counts = ScenarioPairCounts::new();
    let mut start = 0;
    while start < files.len() {
        let mut end = start;
        let mut rows = 0u64;
        while end < files.len() && (end == start || rows < batch_rows) {
            rows += file_rows(&files[end]);
            end += 1;
        }
        let lf = Rows::scan(&files[start..end])?.lf;
        // Per sample: each block's code + 1 (0 where the block has no row).
        let per_block: Vec<Expr> = names
            .iter()
            .zip(&code_cols)
            .map(|(name, c)| {
                (col("code") + lit(1i64))
                    .filter(col("scenario").eq(lit(*name)))
                    .sum()
                    .alias(c.as_str())
            })
            .collect();
        let mut keys = vec![col("variant"), col("wheel")];
        keys.extend(code_cols.iter().map(|c| col(c.as_str())));
        let df = collect(
            lf.select([
                col("variant"),
                col("wheel"),
                col("sample_id"),
                col("scenario"),
                code_expr(outcome).alias("code"),
            ])
            .group_by([col("variant"), col("wheel"), col("sample_id")])
            .agg(per_block)
            .group_by(keys)
            .agg([len().cast(DataType::Int64).alias("n")]),
        )?;
        let (v, w, n) = (strs(&df, "variant")?, strs(&df, "wheel")?, ints(&df, "n")?);
        let codes: Vec<Vec<i64>> = code_cols
            .iter()
            .map(|c| ints(&df, c))
            .collect::<Result<_, _>>()?;
        // Code + 1 back to the code; a missing row (0) is unclassified.
        let code = |x: i64| if (1..=3).contains(&x) { x - 1 } else { 2 };
        for i in 0..df.height() {
            let err = |e: UnknownName| AnalysisError::Row(e.to_string());
            let variant: Variant = v[i].parse().map_err(err)?;
            let wheel: Wheel = w[i].parse().map_err(err)?;
            for (k, c) in codes.iter().enumerate().skip(1) {
                let reference = code(codes[references[k - 1]][i]);
                *counts
                    .entry((k - 1, variant, wheel, reference, code(c[i])))
                    .or_default() += n[i] as u64;
            }
        }
        start = end;
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The wear comparison counts a visible polygon within the distance, from the rows' distance
    /// column: synthetic rows with known outcomes (moved from the integration tests, scenarios.rs).
    #[test]
    fn the_wear_comparison_reads_the_distance_column() {
        use polywear_study::parquet_out::{write_table, Column};
        let dir =
            std::env::temp_dir().join(format!("polywear-scenario-pairs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("chunk-0000000.parquet");
        // Samples 0..4, follower only; (baseline distance, scenario distance, scenario class).
        let cases = [
            (10_000.0, 90_000.0, "stable"),           // 1 -> 0
            (50_000.0, 20_000.0, "limit_cycle"),      // 0 -> 1
            (f64::INFINITY, f64::INFINITY, "stable"), // 0 -> 0
            (30_000.0, f64::NAN, "stable"),           // 1 -> unclassified (NaN)
            (30_000.0, 30_000.0, "failed"),           // 1 -> unclassified (failed)
        ];
        let mut cols = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (i, (b, s, class)) in cases.iter().enumerate() {
            for (scenario, d, c) in [("baseline", *b, "stable"), ("s", *s, *class)] {
                cols.0.push(i as i64);
                cols.1.push(scenario.to_string());
                cols.2.push(d);
                cols.3.push(c.to_string());
            }
        }
        let n = cols.0.len();
        let columns = [
            Column::i64("sample_id", "", cols.0),
            Column::str("scenario", cols.1),
            Column::str("variant", vec!["sliding_share".into(); n]),
            Column::str("wheel", vec!["follower".into(); n]),
            Column::str("class", cols.3),
            Column::f64("distance_to_visible_km", "km", cols.2),
        ];
        write_table(&file, &columns, &[]).unwrap();
        let outcome = OutcomeColumn::WithinKm {
            column: "distance_to_visible_km",
            km: 40_000.0,
        };
        let counts = scenario_pairs(&[file], 1000, &["s"], &[0], outcome).unwrap();
        let key = |b, s| (0usize, Variant::SlidingShare, Wheel::Follower, b, s);
        let expected: BTreeMap<_, u64> = [
            (key(1, 0), 1),
            (key(0, 1), 1),
            (key(0, 0), 1),
            (key(1, 2), 2),
        ]
        .into();
        assert_eq!(counts, expected);
        std::fs::remove_dir_all(&dir).ok();
    }
}
