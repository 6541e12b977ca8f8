//! Drawing one of n rows with probability proportional to its weight in constant time: Walker's
//! alias method, built by Vose's algorithm (M. D. Vose, "A linear algorithm for generating random
//! numbers with a given distribution", IEEE TSE 17(9), 1991).
//!
//! Only the rows of positive weight enter the table, so a row of weight zero is never drawn, not
//! even through rounding in the table's construction.

use rand::{Rng, RngExt};

/// An alias table over the rows of positive weight.
#[derive(Debug, Clone, PartialEq)]
pub struct AliasTable {
    /// Acceptance probability of each slot.
    prob: Vec<f64>,
    /// The slot's other row (index into `rows`) when the draw is not accepted.
    alias: Vec<u32>,
    /// The row index (into the caller's weights) of each slot.
    rows: Vec<u32>,
}

impl AliasTable {
    /// The table of `weights` (finite, non-negative, fewer than 2^32); None when no weight is
    /// positive.
    pub fn new(weights: &[f64]) -> Option<AliasTable> {
        let rows: Vec<u32> = (0..weights.len())
            .filter(|&i| weights[i] > 0.0)
            .map(|i| u32::try_from(i).expect("fewer than 2^32 rows"))
            .collect();
        let n = rows.len();
        if n == 0 {
            return None;
        }
        // Relative to the largest first, so that weights near the largest float (1e308 each)
        // sum without overflow.
        let largest = rows.iter().fold(0.0f64, |m, &r| m.max(weights[r as usize]));
        let relative = |r: u32| weights[r as usize] / largest;
        let total: f64 = rows.iter().map(|&r| relative(r)).sum();
        // Scaled so that the mean is 1: a slot holds exactly one unit of probability.
        let mut scaled: Vec<f64> = rows
            .iter()
            .map(|&r| relative(r) * n as f64 / total)
            .collect();
        let mut prob = vec![1.0; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            prob[s] = scaled[s];
            alias[s] = l as u32;
            scaled[l] = (scaled[l] + scaled[s]) - 1.0;
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What is left holds probability 1 up to rounding (every slot here has positive weight).
        Some(AliasTable { prob, alias, rows })
    }

    /// Rows of positive weight.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether no row has a positive weight.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// One row index, drawn with probability weight / total weight: a uniform slot, then that
    /// slot's row or its alias.
    pub fn draw<R: Rng>(&self, rng: &mut R) -> usize {
        let slot = rng.random_range(0..self.rows.len());
        let u: f64 = rng.random();
        let k = if u < self.prob[slot] {
            slot
        } else {
            self.alias[slot] as usize
        };
        self.rows[k] as usize
    }

    /// The probability that [`AliasTable::draw`] gives `row`: the table's exact distribution,
    /// for checks against the weights.
    pub fn probability(&self, row: usize) -> f64 {
        let n = self.rows.len() as f64;
        let mut p = 0.0;
        for (slot, &r) in self.rows.iter().enumerate() {
            if r as usize == row {
                p += self.prob[slot] / n;
            }
            if self.rows[self.alias[slot] as usize] as usize == row {
                p += (1.0 - self.prob[slot]) / n;
            }
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Streams;

    #[test]
    fn table_probabilities_equal_the_weights() {
        let w = [3.0, 0.0, 1.0, 0.5, 10.0, 0.0, 2.5];
        let t = AliasTable::new(&w).unwrap();
        let total: f64 = w.iter().sum();
        for (i, wi) in w.iter().enumerate() {
            assert!((t.probability(i) - wi / total).abs() < 1e-12, "row {i}");
        }
        assert_eq!(t.len(), 5);
    }

    #[test]
    fn zero_weight_rows_are_never_drawn_and_all_zero_has_no_table() {
        assert!(AliasTable::new(&[0.0, 0.0]).is_none());
        // Weights near the largest float: half and half, not an overflowed total.
        let t = AliasTable::new(&[1e308, 1e308]).unwrap();
        assert_eq!((t.probability(0), t.probability(1)), (0.5, 0.5));
        let t = AliasTable::new(&[f64::MAX, 1e-300, f64::MAX]).unwrap();
        assert!(
            (t.probability(0) - 0.5).abs() < 1e-15,
            "{}",
            t.probability(0)
        );
        assert!(AliasTable::new(&[]).is_none());
        let w = [0.0, 1e-300, 0.0, 1.0, 0.0];
        let t = AliasTable::new(&w).unwrap();
        let s = Streams::new(3);
        for i in 0..20_000 {
            let r = t.draw(&mut s.at(i, 0));
            assert!(r == 1 || r == 3, "drew row {r}");
        }
    }
}
