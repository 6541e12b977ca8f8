//! The calibration band's query ([`crate::analysis::band`]): per scenario, variant, wheel and
//! calibrated set, the weight of the wheels with a known wear answer and of those with a
//! visible polygon within each distance, before the tire is worn out, from the band's file
//! (`_calibration_band.parquet`: one row per sample, scenario, variant and wheel, a column of
//! distances per set).

use std::path::Path;

use polars::prelude::*;

use super::{collect, ints, pl_err, strs, variant_wheel, SampleWeight, WEIGHT_UNITS_PER_KMH};
use crate::analysis::AnalysisError;
use polywear_core::model::{Variant, Wheel};
use polywear_study::calibration_band::evaluate::set_column;

/// One group's weights.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BandCount {
    /// The scenario (`baseline` for the baseline).
    pub scenario: String,
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The calibrated set (`run`: the run's own constants).
    pub set: String,
    /// Weight of the wheels with a known answer.
    pub known: i64,
    /// Weight of those with a visible polygon within each distance asked, in that order.
    pub visible: Vec<i64>,
}

/// The band's counts at each of `within_km` under each of `sets` (their ids, [`RUN_SET`]
/// among them), weighed as the run's rows are. A set's column holds the distance to a visible
/// polygon before the tire is worn out (+inf: none; NaN: unknown).
///
/// [`RUN_SET`]: polywear_study::calibration_band::evaluate::RUN_SET
pub(crate) fn band_counts(
    file: &Path,
    within_km: &[f64],
    weight: SampleWeight,
    sets: &[&str],
) -> Result<Vec<BandCount>, AnalysisError> {
    let lf = LazyFrame::scan_parquet(
        PlRefPath::new(file.to_string_lossy().as_ref()),
        ScanArgsParquet::default(),
    )
    .map_err(pl_err)?;
    let w = match weight {
        SampleWeight::Equal => lit(1i64),
        SampleWeight::SpeedKmh => {
            (col("speed_kmh") * lit(WEIGHT_UNITS_PER_KMH) + lit(0.5)).cast(DataType::Int64)
        }
    };
    let mut aggs = Vec::new();
    for (j, set) in sets.iter().enumerate() {
        let d = col(set_column(set)).cast(DataType::Float64);
        let known = d.clone().is_null().or(d.clone().is_nan()).not();
        aggs.push(
            when(known.clone())
                .then(w.clone())
                .otherwise(lit(0i64))
                .sum()
                .alias(format!("known_{j}")),
        );
        for (k, km) in within_km.iter().enumerate() {
            let visible = known.clone().and(d.clone().lt_eq(lit(*km)));
            aggs.push(
                when(visible)
                    .then(w.clone())
                    .otherwise(lit(0i64))
                    .sum()
                    .alias(format!("visible_{j}_{k}")),
            );
        }
    }
    let keys = [col("scenario"), col("variant"), col("wheel")];
    let df = collect(
        lf.group_by(keys.clone())
            .agg(aggs)
            .sort_by_exprs(keys, SortMultipleOptions::default()),
    )?;
    let scenario = strs(&df, "scenario")?;
    let vw = variant_wheel(&df)?;
    let mut out = Vec::with_capacity(df.height() * sets.len());
    for (j, set) in sets.iter().enumerate() {
        let known = ints(&df, &format!("known_{j}"))?;
        let visible: Vec<Vec<i64>> = (0..within_km.len())
            .map(|k| ints(&df, &format!("visible_{j}_{k}")))
            .collect::<Result<_, _>>()?;
        for i in 0..df.height() {
            out.push(BandCount {
                scenario: scenario[i].clone(),
                variant: vw[i].0,
                wheel: vw[i].1,
                set: set.to_string(),
                known: known[i],
                visible: visible.iter().map(|v| v[i]).collect(),
            });
        }
    }
    Ok(out)
}
