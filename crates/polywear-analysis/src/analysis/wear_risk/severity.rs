//! How fast polygons grow and how far a tire runs before one is visible: the quantiles of
//! `growth_rate_per_1000km` and of the finite `distance_to_visible_km` per variant and wheel,
//! beside the share at +inf (every order levels out) and the unknown ones, from a fine
//! histogram (memory independent of the row count). Distances span four decades, so their
//! histogram is on log10 of the distance, exact to 1/4000 of that range.

use std::collections::BTreeMap;

use crate::analysis::bins::Bins;
use crate::analysis::rows::{decade_bins, decades, Rows, WearSpread};
use crate::analysis::severity::{hist_quantile, SEVERITY_FINE_BINS};
use crate::analysis::AnalysisError;
use polywear_core::model::{Variant, Wheel};
use polywear_core::records::WearColumn;

/// A wear quantity of the severity table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearQuantity {
    /// Its column.
    pub column: WearColumn,
    /// What it is, in words.
    pub title: &'static str,
    /// Whether its histogram has bins per decade (`crate::analysis::rows::decade_bins`).
    pub log: bool,
}

/// The wear quantities of the severity table.
pub(crate) const WEAR_QUANTITIES: [WearQuantity; 2] = [
    WearQuantity {
        column: WearColumn::GrowthRatePer1000km,
        title: "Growth rate of the dominant order (> 0 grows)",
        log: false,
    },
    WearQuantity {
        column: WearColumn::DistanceToVisibleKm,
        title: "Distance to a visible polygon (finite ones)",
        log: true,
    },
];

/// The spread of one wear quantity over one variant and wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct WearSeverity {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The quantity.
    pub quantity: WearQuantity,
    /// Rows finite, at +inf and unknown.
    pub spread: WearSpread,
    /// 5, 25, 50, 75, 95 % of the finite values (NaN without any).
    pub quantiles: [f64; 5],
}

impl WearSeverity {
    /// The share at +inf among the known rows (finite or +inf).
    pub fn share_inf(&self) -> f64 {
        let known = self.spread.finite + self.spread.pos_inf;
        self.spread.pos_inf as f64 / known as f64
    }
}

/// The severity table of every wear quantity, per variant and wheel.
pub(crate) fn wear_severity(rows: &Rows) -> Result<Vec<WearSeverity>, AnalysisError> {
    let mut out = Vec::new();
    for q in WEAR_QUANTITIES {
        let name = q.column.name();
        let (spread, (lo, hi)) = rows.wear_spread(name)?;
        let mut hists: BTreeMap<(Variant, Wheel), Vec<u64>> = BTreeMap::new();
        let span = decades(lo, hi);
        let bins = if q.log {
            decade_bins(span)
        } else {
            Bins::equal_width(lo, hi, SEVERITY_FINE_BINS)
        };
        if lo.is_finite() && hi.is_finite() {
            let d = q.log.then_some(span);
            for h in rows.finite_histogram(name, &bins, d)? {
                let counts = hists
                    .entry((h.variant, h.wheel))
                    .or_insert_with(|| vec![0; bins.count()]);
                if let Ok(k) = usize::try_from(h.bin) {
                    counts[k.min(bins.count() - 1)] += h.n as u64;
                }
            }
        }
        let mut spread = spread;
        spread.sort_by_key(|s| (s.variant, s.wheel));
        for s in spread {
            let quantiles = [0.05, 0.25, 0.5, 0.75, 0.95].map(|p| {
                let Some(counts) = hists.get(&(s.variant, s.wheel)) else {
                    return f64::NAN;
                };
                hist_quantile(&bins, counts, p)
            });
            out.push(WearSeverity {
                variant: s.variant,
                wheel: s.wheel,
                quantity: q,
                spread: s,
                quantiles,
            });
        }
    }
    Ok(out)
}
