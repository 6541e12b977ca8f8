//! Uniform random bits from a vetted, stream-addressable generator: ChaCha12 (Bernstein's ChaCha
//! stream cipher with 12 rounds, the generator behind `rand`'s `StdRng`): the `chacha20` crate's
//! [`ChaCha12Rng`], which `rand` re-exports as `rand::rngs::ChaCha12Rng`. Its 64-bit stream
//! number and 68-bit word position address any value directly, so each value is a pure function
//! of (seed, stream, position): results never depend on thread count, chunking or sharding.
//!
//! Layout (recorded as [`RNG_NAME`] in every chunk's `rng` metadata and in the manifest):
//! - key: `ChaCha12Rng::seed_from_u64(seed)` (rand_core's documented PCG32 expansion of the
//!   study seed into the 256-bit key);
//! - sample `i` (a sample index, below 2^62) reads stream `i`; its axis `a` starts at word
//!   `2^32·a` (2^32 words of its own, so a rejection sampler may take as many as it needs);
//!   the row a sample draws from a study's measured operating points reads its last axis,
//!   2^36 − 1 (`ROW_AXIS` of polywear-study's `operating_points`), so the drawn parameters keep their values
//!   with and without the file;
//! - streams from `LHS_STREAMS` up hold the round functions of the Latin-hypercube permutation,
//!   stream `SOBOL_SCRAMBLE_STREAM` the per-axis Sobol scrambling seeds.

pub use chacha20::ChaCha12Rng;
use rand::{Rng, RngExt, SeedableRng};

/// The generator and its layout, as recorded in the output (`rng` key).
pub const RNG_NAME: &str =
    "ChaCha12Rng (chacha20 0.10, rand 0.10); key = seed_from_u64(seed); stream = sample index; word position = 2^32 * axis";

/// First stream of the Latin-hypercube permutations (one stream per axis).
pub(crate) const LHS_STREAMS: u64 = 1 << 62;
/// Stream of the Sobol scrambling seeds (word = axis).
pub(crate) const SOBOL_SCRAMBLE_STREAM: u64 = 1 << 63;

/// Words (32-bit) reserved for each axis of a sample.
const AXIS_WORDS: u32 = 32;

/// The random streams of one seed.
#[derive(Clone, Debug)]
pub struct Streams {
    /// The 256-bit ChaCha key.
    key: [u8; 32],
}

impl Streams {
    /// The streams of `seed`.
    pub fn new(seed: u64) -> Self {
        Streams {
            key: ChaCha12Rng::seed_from_u64(seed).get_seed(),
        }
    }

    /// The generator positioned at word `word` of stream `stream`.
    #[inline]
    pub fn at_word(&self, stream: u64, word: u128) -> ChaCha12Rng {
        let mut rng = ChaCha12Rng::from_seed(self.key);
        rng.set_stream(stream);
        rng.set_word_pos(word);
        rng
    }

    /// The generator of axis `axis` of sample (or stream) `index`: stream `index`, word
    /// 2^32·axis. Draw as many values from it as needed.
    #[inline]
    pub fn at(&self, index: u64, axis: u64) -> ChaCha12Rng {
        self.at_word(index, u128::from(axis) << AXIS_WORDS)
    }

    /// The first 64 bits of (index, axis).
    #[inline]
    pub fn bits(&self, index: u64, axis: u64) -> u64 {
        self.at(index, axis).next_u64()
    }

    /// The first uniform in [0, 1) of (index, axis): rand's `StandardUniform` (53 random bits).
    #[inline]
    pub fn uniform01(&self, index: u64, axis: u64) -> f64 {
        self.at(index, axis).random::<f64>()
    }
}

/// 64 random bits for (seed, index, stream): the first word pair of axis `stream` of sample
/// `index` (see [`Streams::at`]). Keys the generator on every call; hold a [`Streams`] where
/// one seed serves many draws.
#[inline]
pub fn bits(seed: u64, index: u64, stream: u64) -> u64 {
    Streams::new(seed).bits(index, stream)
}

/// Uniform in [0, 1) with 53 random bits, for (seed, index, stream).
#[inline]
pub fn uniform01(seed: u64, index: u64, stream: u64) -> f64 {
    Streams::new(seed).uniform01(index, stream)
}

/// Uniform in [lo, hi), for (seed, index, stream).
#[inline]
pub fn uniform(seed: u64, index: u64, stream: u64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * uniform01(seed, index, stream)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_addressed_not_sequenced() {
        let s = Streams::new(7);
        // Axis 3 of sample 10 is the same value however it is reached.
        let direct = s.bits(10, 3);
        let mut r = s.at(10, 0);
        r.set_word_pos(3u128 << 32);
        assert_eq!(r.next_u64(), direct);
        assert_eq!(bits(7, 10, 3), direct);
        // Distinct seeds, streams and axes give distinct values.
        assert_ne!(bits(8, 10, 3), direct);
        assert_ne!(bits(7, 11, 3), direct);
        assert_ne!(bits(7, 10, 4), direct);
        // Drawing more from one axis never reaches the next axis's words.
        let mut r = s.at(0, 0);
        let first: Vec<u64> = (0..1000).map(|_| r.next_u64()).collect();
        assert!(!first.contains(&s.bits(0, 1)));
    }

    #[test]
    fn uniform_stays_in_range() {
        let s = Streams::new(1);
        for i in 0..10_000 {
            let u = s.uniform01(i, 0);
            assert!((0.0..1.0).contains(&u));
            let x = uniform(1, i, 0, -2.0, 3.0);
            assert!((-2.0..3.0).contains(&x));
        }
    }
}
