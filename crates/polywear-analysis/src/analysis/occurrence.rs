//! How likely is self-excited vibration: rows per class for each variant and wheel.

use std::collections::BTreeMap;

use super::counts::ClassCounts;
use super::rows::Rows;
use super::AnalysisError;
use polywear_core::model::{Variant, Wheel};

/// Probability of self-excited vibration for one variant and wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct Occurrence {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// Rows per class.
    pub counts: ClassCounts,
}

impl Occurrence {
    /// P(vibration) over the classified rows; NaN when there are none.
    pub fn p(&self) -> f64 {
        self.counts.p()
    }
}

/// Rows per class for each variant and wheel, in (variant, wheel) order.
pub fn occurrence(rows: &Rows) -> Result<Vec<Occurrence>, AnalysisError> {
    let mut map: BTreeMap<(Variant, Wheel), ClassCounts> = BTreeMap::new();
    for g in rows.class_counts(&[])? {
        map.entry((g.variant, g.wheel))
            .or_default()
            .merge(&g.counts);
    }
    Ok(map
        .into_iter()
        .map(|((variant, wheel), counts)| Occurrence {
            variant,
            wheel,
            counts,
        })
        .collect())
}
