//! Scrambled Sobol points evaluated directly from the index (no sequential state), so any
//! sample of any shard is computed alone. Direction numbers follow Joe & Kuo's construction
//! (primitive polynomials over GF(2) with odd initial numbers m_k < 2^k); scrambling is a
//! nested uniform (Owen-style) scramble by a Laine–Karras hash, seeded per dimension.

/// (degree s, coefficients a, initial m_1..m_s) for dimensions 2, 3, ... (dimension 1 is the
/// van der Corput sequence).
const POLYS: &[(u32, u32, &[u32])] = &[
    (1, 0, &[1]),
    (2, 1, &[1, 3]),
    (3, 1, &[1, 3, 1]),
    (3, 2, &[1, 1, 1]),
    (4, 1, &[1, 1, 3, 3]),
    (4, 4, &[1, 3, 5, 13]),
    (5, 2, &[1, 1, 5, 5, 17]),
    (5, 4, &[1, 1, 5, 5, 5]),
    (5, 7, &[1, 1, 7, 11, 19]),
    (5, 11, &[1, 1, 5, 1, 1]),
    (5, 13, &[1, 1, 1, 3, 11]),
    (5, 14, &[1, 3, 5, 5, 31]),
    (6, 1, &[1, 3, 3, 9, 7, 49]),
    (6, 13, &[1, 1, 1, 15, 21, 21]),
    (6, 16, &[1, 3, 1, 13, 27, 49]),
    (6, 19, &[1, 1, 1, 15, 7, 5]),
    (6, 22, &[1, 3, 1, 15, 13, 25]),
    (6, 25, &[1, 1, 5, 5, 19, 61]),
    (7, 1, &[1, 3, 7, 11, 23, 15, 103]),
    (7, 4, &[1, 3, 7, 13, 13, 15, 69]),
    (7, 7, &[1, 1, 3, 13, 7, 35, 63]),
    (7, 8, &[1, 3, 5, 9, 1, 25, 53]),
    (7, 14, &[1, 3, 1, 13, 9, 35, 107]),
    (7, 19, &[1, 3, 1, 5, 27, 61, 31]),
    (7, 21, &[1, 1, 5, 11, 19, 41, 61]),
    (7, 28, &[1, 3, 5, 3, 3, 13, 69]),
    (7, 31, &[1, 1, 7, 13, 1, 19, 1]),
    (7, 32, &[1, 3, 7, 5, 13, 19, 59]),
    (7, 37, &[1, 1, 3, 9, 25, 29, 41]),
    (7, 41, &[1, 3, 5, 13, 23, 1, 55]),
    (7, 42, &[1, 3, 7, 3, 13, 59, 17]),
];

/// Dimensions available.
pub const MAX_DIMENSIONS: usize = POLYS.len() + 1;

/// 32 direction numbers v_k (as left-aligned 32-bit integers) of one dimension.
pub fn direction_numbers(dim: usize) -> [u32; 32] {
    let mut v = [0u32; 32];
    if dim == 0 {
        for (k, vk) in v.iter_mut().enumerate() {
            *vk = 1 << (31 - k);
        }
        return v;
    }
    let (s, a, m_init) = POLYS[dim - 1];
    let s = s as usize;
    let mut m = [0u32; 32];
    m[..s].copy_from_slice(m_init);
    for k in s..32 {
        // m_k = 2 a_1 m_{k-1} ^ 4 a_2 m_{k-2} ^ ... ^ 2^s m_{k-s} ^ m_{k-s}
        let mut mk = m[k - s] ^ (m[k - s] << s);
        for j in 1..s {
            let a_j = (a >> (s - 1 - j)) & 1;
            if a_j == 1 {
                mk ^= m[k - j] << j;
            }
        }
        m[k] = mk;
    }
    for k in 0..32 {
        v[k] = m[k] << (31 - k);
    }
    v
}

/// Unscrambled Sobol coordinate of point `index` (standard, non-Gray order).
#[inline]
pub fn sobol_u32(index: u32, directions: &[u32; 32]) -> u32 {
    let mut x = 0u32;
    let mut i = index;
    let mut k = 0;
    while i != 0 {
        if i & 1 == 1 {
            x ^= directions[k];
        }
        i >>= 1;
        k += 1;
    }
    x
}

/// Nested uniform scramble: each bit is flipped depending only on the bits above it.
#[inline]
pub fn owen_scramble(x: u32, seed: u32) -> u32 {
    let mut x = x.reverse_bits();
    x ^= x.wrapping_mul(0x3d20_adea);
    x = x.wrapping_add(seed);
    x = x.wrapping_mul((seed >> 16) | 1);
    x ^= x.wrapping_mul(0x0552_6c56);
    x ^= x.wrapping_mul(0x53a2_2864);
    x.reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether the GF(2) polynomial x^s + a_1 x^{s-1} + ... + a_{s-1} x + 1 is primitive: the
    /// powers of x must cycle through all 2^s - 1 non-zero residues.
    fn primitive(s: u32, a: u32) -> bool {
        let poly = (1u64 << s) | ((a as u64) << 1) | 1;
        let period = (1u64 << s) - 1;
        let mut r = 1u64;
        for k in 1..=period {
            r <<= 1;
            if r & (1 << s) != 0 {
                r ^= poly;
            }
            if r == 1 {
                return k == period;
            }
        }
        false
    }

    #[test]
    fn table_is_a_valid_sobol_construction() {
        for (d, (s, a, m)) in POLYS.iter().enumerate() {
            assert!(
                primitive(*s, *a),
                "dimension {} polynomial (s={s}, a={a}) not primitive",
                d + 2
            );
            assert!(*a < (1 << (s - 1)) || *s == 1);
            for (k, mk) in m.iter().enumerate() {
                assert!(
                    mk % 2 == 1 && *mk < (1 << (k + 1)),
                    "dimension {} m_{} = {mk}",
                    d + 2,
                    k + 1
                );
            }
        }
    }

    #[test]
    fn every_dimension_and_pair_is_stratified() {
        // First 2^m points: one per interval of length 2^-m in each dimension, and the 2-D
        // projections of the first 2^(2k) points fill every 2^k x 2^k cell at most 2^t times.
        let n = 1u32 << 10;
        let dirs: Vec<[u32; 32]> = (0..MAX_DIMENSIONS).map(direction_numbers).collect();
        for (d, dir) in dirs.iter().enumerate() {
            let mut seen = vec![0u32; n as usize];
            for i in 0..n {
                seen[(sobol_u32(i, dir) >> 22) as usize] += 1;
            }
            assert!(seen.iter().all(|c| *c == 1), "dimension {d}");
            // Scrambling keeps it.
            let mut seen = vec![0u32; n as usize];
            for i in 0..n {
                seen[(owen_scramble(sobol_u32(i, dir), 12345 + d as u32) >> 22) as usize] += 1;
            }
            assert!(seen.iter().all(|c| *c == 1), "scrambled dimension {d}");
        }
        for d1 in 0..8 {
            for d2 in d1 + 1..8 {
                let mut cells = [0u32; 32 * 32];
                for i in 0..n {
                    let x = sobol_u32(i, &dirs[d1]) >> 27;
                    let y = sobol_u32(i, &dirs[d2]) >> 27;
                    cells[(x * 32 + y) as usize] += 1;
                }
                assert!(
                    cells.iter().all(|c| *c <= 8),
                    "dims {d1},{d2}: {:?}",
                    cells.iter().max()
                );
            }
        }
    }
}
