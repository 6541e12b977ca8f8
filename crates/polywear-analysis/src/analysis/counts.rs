//! Rows per class, and a row's outcome in the paired comparison: the plain counts every query
//! returns.
//!
//! Classes: a wheel *vibrates* when it settles on a limit cycle or is bistable. Rows that
//! `failed` or have `no_traction` are counted on their own and never folded in: probabilities
//! are over the classified rows (stable, limit cycle, bistable).

use super::stats::wilson;
use polywear_core::classify::Class;

/// Rows per class.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ClassCounts(pub [u64; Class::ALL.len()]);

impl ClassCounts {
    /// Counts `n` more rows of `class`.
    pub fn add(&mut self, class: Class, n: u64) {
        self.0[class as usize] += n;
    }
    /// Rows of `class`.
    pub fn get(&self, class: Class) -> u64 {
        self.0[class as usize]
    }
    /// Adds another set of counts to this one.
    pub fn merge(&mut self, other: &ClassCounts) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += b;
        }
    }
    /// Rows that vibrate (limit cycle or bistable).
    pub fn vibrating(&self) -> u64 {
        self.get(Class::LimitCycle) + self.get(Class::Bistable)
    }
    /// Rows with a verdict: stable, limit cycle or bistable (the denominator of probabilities).
    pub fn classified(&self) -> u64 {
        self.vibrating() + self.get(Class::Stable)
    }
    /// Rows whose model or numerics failed.
    pub fn failed(&self) -> u64 {
        self.get(Class::Failed)
    }
    /// Driving-wheel rows that cannot transmit the drive force.
    pub fn no_traction(&self) -> u64 {
        self.get(Class::NoTraction)
    }
    /// All rows, whatever their class.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }
    /// All rows, whatever their class ([`ClassCounts::total`]).
    pub fn rows(&self) -> u64 {
        self.total()
    }
    /// P(vibration) over the classified rows; NaN when there are none.
    pub fn p(&self) -> f64 {
        let n = self.classified();
        if n == 0 {
            f64::NAN
        } else {
            self.vibrating() as f64 / n as f64
        }
    }
    /// 95% Wilson interval of [`ClassCounts::p`].
    pub fn wilson(&self) -> (f64, f64) {
        wilson(self.vibrating(), self.classified())
    }
    /// Whether there are at least `min_count` (and at least one) classified rows: enough to show
    /// a probability.
    pub fn enough(&self, min_count: u64) -> bool {
        self.classified() >= min_count.max(1)
    }
}

pub(crate) use polywear_core::classify::outcome_code;

/// Wheels of one group that reach a visible polygon within a distance, beside those whose
/// distance is unknown (NaN: failed, no traction, standstill; or a row without a verdict), with
/// the same counts weighted (see [`crate::analysis::rows::SampleWeight`]). The weights are whole
/// numbers, so their sums are exact whatever the order the rows are added in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WithinCounts {
    /// Wheels with a known distance at most the limit.
    pub within: u64,
    /// Wheels with a known distance (finite or +inf): the denominator.
    pub known: u64,
    /// Wheels whose distance is unknown: left out of numerator and denominator.
    pub unknown: u64,
    /// Weight of the wheels within the limit.
    pub w_within: i64,
    /// Weight of the wheels with a known distance.
    pub w_known: i64,
    /// Sum of the squared weights of the wheels with a known distance (for the effective count).
    pub w2_known: i64,
}

impl WithinCounts {
    /// Adds another group's counts.
    pub fn merge(&mut self, o: &WithinCounts) {
        self.within += o.within;
        self.known += o.known;
        self.unknown += o.unknown;
        self.w_within += o.w_within;
        self.w_known += o.w_known;
        self.w2_known += o.w2_known;
    }

    /// Every wheel counted: with a known distance or not.
    pub fn rows(&self) -> u64 {
        self.known + self.unknown
    }

    /// Whether every weight is 1 (the probability is the plain share of wheels).
    pub fn unweighted(&self) -> bool {
        self.w_known == self.known as i64 && self.w2_known == self.known as i64
    }

    /// P(visible polygon within the limit) over the wheels with a known distance, weighted;
    /// NaN without any.
    pub fn p(&self) -> f64 {
        if self.w_known <= 0 {
            f64::NAN
        } else {
            self.w_within as f64 / self.w_known as f64
        }
    }

    /// 95% Wilson interval of [`WithinCounts::p`]: on the counts when unweighted, else on Kish's
    /// effective count (Σw)² / Σw² at the weighted share.
    pub fn wilson(&self) -> (f64, f64) {
        if self.unweighted() {
            return wilson(self.within, self.known);
        }
        if self.w2_known <= 0 {
            return (f64::NAN, f64::NAN);
        }
        let n_eff = (self.w_known as f64).powi(2) / self.w2_known as f64;
        super::stats::wilson_share(self.p(), n_eff)
    }

    /// Whether at least `min_count` (and at least one) wheels have a known distance.
    pub fn enough(&self, min_count: u64) -> bool {
        self.known >= min_count.max(1)
    }
}

/// What a group of rows counts for an `crate::analysis::outcome::Outcome`: rows per class
/// for vibration ([`ClassCounts`]), wheels within a distance for wear ([`WithinCounts`]).
/// Each estimates one proportion with its Wilson interval, so the maps, bins, tables and
/// figures that show it are written once for both.
pub trait RiskCounts: Copy + Default {
    /// Adds another group's counts.
    fn merge(&mut self, other: &Self);
    /// The proportion; NaN without a denominator.
    fn p(&self) -> f64;
    /// 95% Wilson interval of [`RiskCounts::p`].
    fn wilson(&self) -> (f64, f64);
    /// Whether the denominator is at least `min_count` (and at least one): enough to show
    /// [`RiskCounts::p`].
    fn enough(&self, min_count: u64) -> bool;
    /// Every row counted, whatever its outcome (those counted apart included).
    fn rows(&self) -> u64;
}

/// [`RiskCounts`] of a type by its own methods of the same names.
macro_rules! risk_counts_by_own_methods {
    ($($t:ty),*) => {$(
        impl RiskCounts for $t {
            fn merge(&mut self, other: &Self) {
                <$t>::merge(self, other);
            }
            fn p(&self) -> f64 {
                <$t>::p(self)
            }
            fn wilson(&self) -> (f64, f64) {
                <$t>::wilson(self)
            }
            fn enough(&self, min_count: u64) -> bool {
                <$t>::enough(self, min_count)
            }
            fn rows(&self) -> u64 {
                <$t>::rows(self)
            }
        }
    )*};
}

risk_counts_by_own_methods!(ClassCounts, WithinCounts);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_weights_give_the_plain_share_and_interval_and_unequal_ones_widen_it() {
        let plain = WithinCounts {
            within: 30,
            known: 200,
            unknown: 7,
            w_within: 30,
            w_known: 200,
            w2_known: 200,
        };
        assert!(plain.unweighted());
        assert_eq!(plain.wilson(), wilson(30, 200));
        // Every weight 1000 (100 km/h): the same share, and Kish's count is the count.
        let tenfold = WithinCounts {
            w_within: 30_000,
            w_known: 200_000,
            w2_known: 200 * 1_000_000,
            ..plain
        };
        assert!(!tenfold.unweighted());
        assert_eq!(tenfold.p(), plain.p());
        let (a, b) = (tenfold.wilson(), plain.wilson());
        assert!((a.0 - b.0).abs() < 1e-14 && (a.1 - b.1).abs() < 1e-14);
        // Half the wheels at 3× the weight: fewer effective samples, a wider interval.
        let mixed = WithinCounts {
            w_within: 30 * 2000,
            w_known: 100 * 1000 + 100 * 3000,
            w2_known: 100 * 1_000_000 + 100 * 9_000_000,
            ..plain
        };
        let (lo, hi) = mixed.wilson();
        assert!((mixed.p() - 0.15).abs() < 1e-12);
        assert!(hi - lo > b.1 - b.0, "{lo} {hi}");
    }
}
