//! How severe the vibration is: the distribution of each cycle quantity among the vibrating
//! rows, from a fine histogram (exact to 1/4000 of the range, in memory independent of the row
//! count).

use std::collections::BTreeMap;

use super::bins::Bins;
use super::rows::{Rows, FIXED_POINT_SCALE};
use super::AnalysisError;
use polywear_core::model::{Variant, Wheel};

pub(crate) use super::quantities::{quantity, SEVERITY_QUANTITIES};

/// Fine histogram bins behind the severity quantiles.
pub(crate) const SEVERITY_FINE_BINS: usize = 4000;

/// Distribution of one cycle quantity among the vibrating rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Severity {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The cycle quantity (a column of `SEVERITY_QUANTITIES`).
    pub quantity: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// Vibrating rows with a finite value of the quantity.
    pub n: u64,
    /// Mean of the quantity over those rows.
    pub mean: f64,
    /// 5, 25, 50, 75, 95 %, read from the fine histogram (linear within a bin).
    pub quantiles: [f64; 5],
    /// The fine histogram: equal-width bins over the quantity's range among all vibrating rows.
    pub hist: Bins,
    /// Rows in each bin of `hist`.
    pub counts: Vec<u64>,
}

/// Severity quantiles from a `SEVERITY_FINE_BINS`-bin histogram per variant and wheel, over
/// each quantity's range among the vibrating rows (`ranges`); a quantity without a finite
/// range (no vibrating row) is left out.
pub(crate) fn severity(
    rows: &Rows,
    ranges: &BTreeMap<String, (f64, f64)>,
) -> Result<Vec<Severity>, AnalysisError> {
    let mut out = Vec::new();
    for q in SEVERITY_QUANTITIES {
        let (quantity, unit) = (q.name(), q.unit());
        let (lo, hi) = ranges
            .get(quantity)
            .copied()
            .unwrap_or((f64::NAN, f64::NAN));
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        let bins = Bins::equal_width(lo, hi, SEVERITY_FINE_BINS);
        let mut groups: BTreeMap<(Variant, Wheel), (Vec<u64>, i128)> = BTreeMap::new();
        for h in rows.histogram(quantity, &bins, (lo, hi))? {
            let g = groups
                .entry((h.variant, h.wheel))
                .or_insert_with(|| (vec![0; bins.count()], 0));
            if let Ok(k) = usize::try_from(h.bin) {
                g.0[k.min(bins.count() - 1)] += h.n as u64;
            }
            g.1 += i128::from(h.fixed_sum);
        }
        for ((variant, wheel), (counts, sum)) in groups {
            let n: u64 = counts.iter().sum();
            let mean_fixed = sum as f64 / n.max(1) as f64;
            out.push(Severity {
                variant,
                wheel,
                quantity,
                unit,
                n,
                mean: if n == 0 {
                    f64::NAN
                } else {
                    lo + (hi - lo) * mean_fixed / FIXED_POINT_SCALE
                },
                quantiles: [0.05, 0.25, 0.5, 0.75, 0.95].map(|q| hist_quantile(&bins, &counts, q)),
                hist: bins.clone(),
                counts,
            });
        }
    }
    Ok(out)
}

/// The q-quantile of a histogram, linear within the bin that holds it.
pub(crate) fn hist_quantile(bins: &Bins, counts: &[u64], q: f64) -> f64 {
    let n: u64 = counts.iter().sum();
    if n == 0 {
        return f64::NAN;
    }
    let target = q * n as f64;
    let mut below = 0.0;
    for (i, c) in counts.iter().enumerate() {
        let c = *c as f64;
        if c > 0.0 && below + c >= target {
            let (a, b, _) = bins.range(i);
            return a + (b - a) * ((target - below) / c).clamp(0.0, 1.0);
        }
        below += c;
    }
    *bins.edges.last().unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_quantiles_are_within_a_bin() {
        let values: Vec<f64> = (0..10_000).map(|i| (i as f64 / 9999.0).powi(2)).collect();
        let bins = Bins::equal_width(0.0, 1.0, SEVERITY_FINE_BINS);
        let mut counts = vec![0u64; bins.count()];
        for v in &values {
            counts[bins.index(*v).unwrap()] += 1;
        }
        for q in [0.05f64, 0.5, 0.95] {
            let exact = q.powi(2);
            assert!(
                (hist_quantile(&bins, &counts, q) - exact).abs() < 2.0 / SEVERITY_FINE_BINS as f64,
                "q = {q}"
            );
        }
    }
}
