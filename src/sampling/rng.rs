//! Counter-based random numbers: each value is a pure function of (seed, sample index, stream),
//! so results never depend on thread count, chunking or sharding (SplitMix64 finalizer, Steele et
//! al. 2014, applied to a mixed counter).

/// 64 random bits for (seed, index, stream).
#[inline]
pub fn bits(seed: u64, index: u64, stream: u64) -> u64 {
    let mut z = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_mul(0xD1B5_4A32_D192_ED03))
        .wrapping_add(stream.wrapping_mul(0x8CB9_2BA7_2F3D_8DD7))
        .wrapping_add(0x2545_F491_4F6C_DD1D);
    for _ in 0..2 {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
    }
    z
}

/// Uniform in [0, 1) with 53 random bits.
#[inline]
pub fn uniform01(seed: u64, index: u64, stream: u64) -> f64 {
    (bits(seed, index, stream) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Uniform in [lo, hi).
#[inline]
pub fn uniform(seed: u64, index: u64, stream: u64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * uniform01(seed, index, stream)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_moments_and_independence_of_streams() {
        let n = 200_000u64;
        let xs: Vec<f64> = (0..n).map(|i| uniform01(7, i, 0)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 3e-3, "{mean}");
        assert!((var - 1.0 / 12.0).abs() < 2e-3, "{var}");
        let ys: Vec<f64> = (0..n).map(|i| uniform01(7, i, 1)).collect();
        let cov = xs
            .iter()
            .zip(&ys)
            .map(|(x, y)| (x - 0.5) * (y - 0.5))
            .sum::<f64>()
            / n as f64;
        assert!(cov.abs() < 2e-3, "{cov}");
        assert!(xs.iter().all(|x| (0.0..1.0).contains(x)));
        assert_ne!(uniform01(7, 0, 0), uniform01(8, 0, 0));
    }
}
