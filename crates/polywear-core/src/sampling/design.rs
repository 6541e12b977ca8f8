//! Experimental designs: the coordinate in [0, 1) of sample `index` along axis `dim`, and the
//! value a distribution takes there.

use rand::Rng;

use super::distribution::Distribution;
use super::rng::{Streams, LHS_STREAMS, SOBOL_SCRAMBLE_STREAM};
use super::sobol::{direction_numbers, owen_scramble, sobol_u32, MAX_DIMENSIONS, MAX_POINTS};

named_enum! {
    /// How sample points fill the unit cube.
    pub enum Design: "design" {
        /// Independent uniform draws.
        Random,
        /// Latin hypercube: each axis split into `samples` strata, one point per stratum.
        #[strum(to_string = "lhs", serialize = "latin_hypercube")]
        LatinHypercube,
        /// Scrambled Sobol quasi-random points.
        Sobol,
        /// Full factorial grid of each axis's levels.
        Grid,
        /// Saltelli's design for Sobol indices: per base point j, the rows A_j, B_j and A_j with
        /// axis m taken from B_j (m = 0..k), at sample indices j·(k+2) + 0, 1, 2 + m.
        Saltelli,
    }
}

impl Design {
    /// Every design, in the order of the declaration.
    pub const ALL: [Design; 5] = [
        Design::Random,
        Design::LatinHypercube,
        Design::Sobol,
        Design::Grid,
        Design::Saltelli,
    ];

    /// The design of a name (`as_str`, or `latin_hypercube` for `lhs`).
    pub fn parse(s: &str) -> Option<Self> {
        s.parse().ok()
    }
}

/// Largest number of drawn axes a Sobol design supports (one Sobol dimension each).
pub const SOBOL_MAX_AXES: usize = MAX_DIMENSIONS;

/// Largest number of drawn axes a Saltelli design supports (two Sobol dimensions each: the A
/// and B matrices).
pub const SALTELLI_MAX_AXES: usize = MAX_DIMENSIONS / 2;

/// Largest sample count of a Sobol design, and of base points of a Saltelli design.
pub const SOBOL_MAX_SAMPLES: u64 = MAX_POINTS;

/// Unit-cube coordinates for `n_axes` axes (Random, LatinHypercube, Sobol; Grid is indexed
/// separately by [`grid_digits`]).
pub struct Coordinates {
    design: Design,
    streams: Streams,
    samples: u64,
    n_axes: usize,
    sobol_dirs: Vec<[u32; 32]>,
    /// Owen-scrambling seed of each Sobol dimension.
    sobol_seeds: Vec<u32>,
}

impl Coordinates {
    /// Panics beyond [`SOBOL_MAX_AXES`] or [`SALTELLI_MAX_AXES`], which a study refuses.
    pub fn new(design: Design, seed: u64, samples: u64, n_axes: usize) -> Self {
        let sobol_dims = match design {
            Design::Sobol => n_axes,
            // The A and B matrices of a Saltelli design are two halves of one Sobol point set.
            Design::Saltelli => 2 * n_axes,
            _ => 0,
        };
        assert!(
            sobol_dims <= MAX_DIMENSIONS,
            "{} axes exceed the {MAX_DIMENSIONS} Sobol dimensions of a {} design",
            n_axes,
            design.as_str()
        );
        let sobol_dirs = (0..sobol_dims).map(direction_numbers).collect();
        let streams = Streams::new(seed);
        let sobol_seeds = (0..sobol_dims as u64)
            .map(|d| streams.at_word(SOBOL_SCRAMBLE_STREAM, d.into()).next_u32())
            .collect();
        Coordinates {
            design,
            streams,
            samples,
            n_axes,
            sobol_dirs,
            sobol_seeds,
        }
    }

    /// Value of `dist` for sample `index` on axis `dim`: a direct draw from the sample's stream
    /// of that axis in the random design ([`Distribution::draw`]), the inverse CDF at the
    /// design's coordinate in the stratified ones.
    pub fn value(&self, index: u64, dim: usize, dist: &Distribution) -> f64 {
        match self.design {
            Design::Random => dist.draw(&mut self.streams.at(index, dim as u64)),
            _ => dist.quantile(self.coordinate(index, dim)),
        }
    }

    /// Coordinate of sample `index` on axis `dim`, in [0, 1).
    pub fn coordinate(&self, index: u64, dim: usize) -> f64 {
        match self.design {
            Design::Random | Design::Grid => self.streams.uniform01(index, dim as u64),
            Design::LatinHypercube => {
                let stratum = permute(index, self.samples, &self.streams, dim as u64);
                (stratum as f64 + self.streams.uniform01(index, dim as u64)) / self.samples as f64
            }
            Design::Sobol => self.sobol(index, dim),
            Design::Saltelli => {
                let k = self.n_axes;
                let (j, block) = (index / (k as u64 + 2), (index % (k as u64 + 2)) as usize);
                let source = match block {
                    0 => dim,
                    1 => k + dim,
                    b if b - 2 == dim => k + dim,
                    _ => dim,
                };
                self.sobol(j, source)
            }
        }
    }

    /// Scrambled Sobol coordinate of point `index` (below [`SOBOL_MAX_SAMPLES`], which a
    /// study's sample count is checked against) in dimension `dim`.
    fn sobol(&self, index: u64, dim: usize) -> f64 {
        let index = u32::try_from(index).expect("Sobol index beyond 2^32, refused by the study");
        let x = sobol_u32(index, &self.sobol_dirs[dim]);
        (owen_scramble(x, self.sobol_seeds[dim]) as f64 + 0.5) / 4_294_967_296.0
    }
}

/// A pseudo-random permutation of [0, n), evaluated pointwise: a 4-round Feistel network on the
/// next even power of two, with cycle walking back into range. Round `k`'s function of the right
/// half `r` is the ChaCha word pair at position 2^36·k + 2r of stream [`LHS_STREAMS`] + `axis`.
pub(crate) fn permute(index: u64, n: u64, streams: &Streams, axis: u64) -> u64 {
    if n <= 1 {
        return 0;
    }
    let bits_total = (64 - (n - 1).leading_zeros()).max(2);
    let half = bits_total.div_ceil(2);
    let mask = (1u64 << half) - 1;
    let mut x = index;
    loop {
        let (mut l, mut r) = (x >> half, x & mask);
        for round in 0..4u64 {
            let word = (u128::from(round) << 36) | (u128::from(r) << 1);
            let f = streams.at_word(LHS_STREAMS + axis, word).next_u64() & mask;
            let nl = r;
            r = l ^ f;
            l = nl;
        }
        x = (l << half) | r;
        if x < n {
            return x;
        }
    }
}

/// Mixed-radix digits of a grid index: the last axis varies fastest.
pub fn grid_digits(mut index: u64, sizes: &[usize]) -> Vec<usize> {
    let mut digits = vec![0; sizes.len()];
    for (d, size) in sizes.iter().enumerate().rev() {
        digits[d] = (index % *size as u64) as usize;
        index /= *size as u64;
    }
    digits
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_is_a_bijection() {
        let streams = Streams::new(42);
        for n in [1u64, 2, 3, 10, 1000, 4097] {
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let p = permute(i, n, &streams, 0);
                assert!(!seen[p as usize]);
                seen[p as usize] = true;
            }
        }
    }

    #[test]
    fn latin_hypercube_has_one_point_per_stratum() {
        let n = 500u64;
        let c = Coordinates::new(Design::LatinHypercube, 7, n, 3);
        for dim in 0..3 {
            let mut strata = vec![0; n as usize];
            for i in 0..n {
                strata[(c.coordinate(i, dim) * n as f64) as usize] += 1;
            }
            assert!(strata.iter().all(|k| *k == 1));
        }
    }

    #[test]
    fn saltelli_rows_share_columns_as_designed() {
        let k = 3;
        let c = Coordinates::new(Design::Saltelli, 5, 100, k);
        for j in 0..20u64 {
            let row = |b: u64| -> Vec<f64> {
                (0..k)
                    .map(|d| c.coordinate(j * (k as u64 + 2) + b, d))
                    .collect()
            };
            let (a, b) = (row(0), row(1));
            assert!((0..k).all(|d| a[d] != b[d]));
            for m in 0..k {
                let ab = row(2 + m as u64);
                for d in 0..k {
                    assert_eq!(ab[d], if d == m { b[d] } else { a[d] });
                }
            }
        }
    }

    #[test]
    fn design_names_round_trip() {
        for d in Design::ALL {
            assert_eq!(d.as_str().parse::<Design>(), Ok(d));
        }
        assert_eq!("latin_hypercube".parse(), Ok(Design::LatinHypercube));
        assert!("halton"
            .parse::<Design>()
            .unwrap_err()
            .to_string()
            .contains("saltelli"));
    }

    #[test]
    fn grid_digits_enumerate_the_grid() {
        let sizes = [2, 3, 4];
        let all: Vec<Vec<usize>> = (0..24).map(|i| grid_digits(i, &sizes)).collect();
        assert_eq!(all[0], vec![0, 0, 0]);
        assert_eq!(all[1], vec![0, 0, 1]);
        assert_eq!(all[23], vec![1, 2, 3]);
        let mut sorted = all.clone();
        sorted.dedup();
        assert_eq!(sorted.len(), 24);
    }
}
