//! The calibration band's query ([`crate::analysis::band`]): per scenario, variant, wheel and
//! calibrated set, the weight of the wheels with a known wear answer and of those with a
//! visible polygon within each distance, before the tire is worn out, from the band's file
//! (`_calibration_band.parquet`, one row per sample, scenario, variant, wheel and set).

use std::path::Path;

use polars::prelude::*;

use super::{collect, ints, pl_err, strs, variant_wheel, SampleWeight, WEIGHT_UNITS_PER_KMH};
use crate::analysis::AnalysisError;
use polywear_core::model::{Variant, Wheel};

/// One group's weights.
#[derive(Debug, Clone, PartialEq)]
pub struct BandCount {
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

/// The band's counts at each of `within_km`, weighed as the run's rows are.
pub fn band_counts(
    file: &Path,
    within_km: &[f64],
    weight: SampleWeight,
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
    let d = col("distance_to_visible_km");
    let life = col("tread_life_km");
    let unknown = |e: Expr| e.clone().is_null().or(e.is_nan());
    let known = unknown(d.clone()).or(unknown(life.clone())).not();
    let mut aggs = vec![when(known.clone())
        .then(w.clone())
        .otherwise(lit(0i64))
        .sum()
        .alias("known")];
    for (k, km) in within_km.iter().enumerate() {
        let visible = known
            .clone()
            .and(d.clone().lt_eq(lit(*km)))
            .and(d.clone().lt_eq(life.clone()));
        aggs.push(
            when(visible)
                .then(w.clone())
                .otherwise(lit(0i64))
                .sum()
                .alias(format!("visible_{k}")),
        );
    }
    let keys = [col("scenario"), col("variant"), col("wheel"), col("set")];
    let df = collect(
        lf.group_by(keys.clone())
            .agg(aggs)
            .sort_by_exprs(keys, SortMultipleOptions::default()),
    )?;
    let (scenario, set) = (strs(&df, "scenario")?, strs(&df, "set")?);
    let vw = variant_wheel(&df)?;
    let known = ints(&df, "known")?;
    let visible: Vec<Vec<i64>> = (0..within_km.len())
        .map(|k| ints(&df, &format!("visible_{k}")))
        .collect::<Result<_, _>>()?;
    Ok((0..df.height())
        .map(|i| BandCount {
            scenario: scenario[i].clone(),
            variant: vw[i].0,
            wheel: vw[i].1,
            set: set[i].clone(),
            known: known[i],
            visible: visible.iter().map(|v| v[i]).collect(),
        })
        .collect())
}
