//! Rows per class, and a row's outcome in the paired comparison: the plain counts every query
//! returns.
//!
//! Classes: a wheel *vibrates* when it settles on a limit cycle or is bistable. Rows that
//! `failed` or have `no_traction` are counted on their own and never folded in: probabilities
//! are over the classified rows (stable, limit cycle, bistable).

use super::stats::wilson;
use crate::classify::Class;

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

/// A wheel's outcome in the paired comparison, as a code: 0 not vibrating, 1 vibrating, 2
/// unclassified (failed or no traction). A sample's pair is `follower + 3 × driving`.
pub fn outcome_code(class: Class) -> i64 {
    if class.vibrates() {
        1
    } else if class == Class::Stable {
        0
    } else {
        2
    }
}
