//! Where the risk lives along each axis: P(vibration | parameter in bin), per variant and wheel.

use std::collections::BTreeMap;

use super::bins::Bins;
use super::counts::ClassCounts;
use super::rows::{GroupKey, Rows};
use super::AnalysisError;
use crate::model::{Variant, Wheel};
use crate::params::ParamId;

/// Probability in one bin of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct BinStat {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The drawn parameter binned.
    pub axis: ParamId,
    /// Lower edge of the bin (the level itself for levels).
    pub lo: f64,
    /// Upper edge of the bin (the level itself for levels).
    pub hi: f64,
    /// Middle of the bin, where the figure plots it.
    pub mid: f64,
    /// Rows per class in the bin.
    pub counts: ClassCounts,
}

/// P(vibration | axis in bin), per variant, wheel and bin of one axis: every bin of every
/// (variant, wheel) present, empty bins included.
pub fn conditional(rows: &Rows, axis: ParamId, bins: &Bins) -> Result<Vec<BinStat>, AnalysisError> {
    let groups = rows.class_counts(&[GroupKey::Bin(axis.name(), bins)])?;
    let mut map: BTreeMap<(Variant, Wheel, i64), ClassCounts> = BTreeMap::new();
    for g in &groups {
        map.entry((g.variant, g.wheel, g.bins[0]))
            .or_default()
            .merge(&g.counts);
    }
    let mut keys: Vec<(Variant, Wheel)> = groups.iter().map(|g| (g.variant, g.wheel)).collect();
    keys.sort();
    keys.dedup();
    let mut out = Vec::new();
    for (variant, wheel) in keys {
        for i in 0..bins.count() {
            let (lo, hi, mid) = bins.range(i);
            out.push(BinStat {
                variant,
                wheel,
                axis,
                lo,
                hi,
                mid,
                counts: map
                    .get(&(variant, wheel, i as i64))
                    .copied()
                    .unwrap_or_default(),
            });
        }
    }
    Ok(out)
}
