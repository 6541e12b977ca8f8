//! The worn profile of the long-term loop (MODEL.md#the-long-term-loop): the depth d(θ) worn at
//! each of M equal cells of tyre angle, cell i covering \[iΔθ, (i+1)Δθ), Δθ = 2π/M. Only its
//! deviation from the mean acts back, the radius deviation r = −(d − d̄)
//! (MODEL.md#step-12-feedback), whose harmonics R_n (r = Σ Re\[R_n e^{inθ}\]) are read at the
//! cell centres θ_i = (i + ½)Δθ, so that a harmonic sampled there has exactly its amplitude
//! whatever M is.
//!
//! The seed of a new tyre, r(θ) = Σ_{n=1..64} R⁰ cos(nθ + φ_n), puts the same run-out R⁰ in each
//! order of a fixed band with a phase φ_n drawn for (seed, n): the band and the phases do not
//! depend on M.

use crate::numeric::Complex64;
use crate::sampling::rng::Streams;

/// The orders the seed puts run-out into: 1 ..= this.
pub(crate) const SEED_ORDERS: usize = 64;

/// The random stream of the seed's phases (sample index = the order).
const SEED_PHASE_AXIS: u64 = 0;

/// The worn depth on equal cells of tyre angle \[m\].
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Depth worn at each cell \[m\] (the seed's run-out counts as depth: d = −r at the start).
    pub depth_m: Vec<f64>,
}

impl Profile {
    /// A new tyre on `cells` cells: run-out `runout_m` in every order 1..=`SEED_ORDERS`, the
    /// phase of order n the first uniform of stream n of `seed`, times 2π.
    pub fn seeded(cells: usize, runout_m: f64, seed: u64) -> Profile {
        let streams = Streams::new(seed);
        let phases: Vec<f64> = (1..=SEED_ORDERS as u64)
            .map(|n| std::f64::consts::TAU * streams.uniform01(n, SEED_PHASE_AXIS))
            .collect();
        let d_theta = std::f64::consts::TAU / cells as f64;
        let depth_m = (0..cells)
            .map(|i| {
                let theta = (i as f64 + 0.5) * d_theta;
                let r: f64 = phases
                    .iter()
                    .enumerate()
                    .map(|(k, phase)| runout_m * ((k + 1) as f64 * theta + phase).cos())
                    .sum();
                -r
            })
            .collect();
        Profile { depth_m }
    }

    /// The number of cells M.
    pub fn cells(&self) -> usize {
        self.depth_m.len()
    }

    /// The mean depth d̄ \[m\].
    pub fn mean_depth_m(&self) -> f64 {
        self.depth_m.iter().sum::<f64>() / self.cells() as f64
    }

    /// The radius deviation r = −(d − d̄) per cell \[m\]: r > 0 a high spot.
    pub fn radius_m(&self) -> Vec<f64> {
        let mean = self.mean_depth_m();
        self.depth_m.iter().map(|d| -(d - mean)).collect()
    }

    /// The harmonics R_1 ..= R_`orders` of the radius deviation \[m\].
    pub fn harmonics(&self, orders: usize) -> Vec<Complex64> {
        harmonics_of(&self.radius_m(), orders)
    }

    /// The peak-to-valley depths D_n = 2|R_n| of orders 1 ..= `orders` \[m\].
    pub fn depths_m(&self, orders: usize) -> Vec<f64> {
        self.harmonics(orders)
            .iter()
            .map(|r| 2.0 * r.norm())
            .collect()
    }
}

/// The harmonics X_1 ..= X_`orders` of values `x` on equal cells, read at the cell centres:
/// X_n = (2/M) Σ_i x_i e^{−inθ_i}, so that x_i = Re\[X e^{inθ_i}\] gives X_n = X.
pub fn harmonics_of(x: &[f64], orders: usize) -> Vec<Complex64> {
    let cells = x.len();
    let d_theta = std::f64::consts::TAU / cells as f64;
    (1..=orders)
        .map(|n| {
            // The phasor steps by e^{−inΔθ} from cell to cell: one complex product per cell,
            // renormalised every 64 cells against the drift of repeated rounding.
            let step = Complex64::from_polar(1.0, -(n as f64) * d_theta);
            let mut sum = Complex64::new(0.0, 0.0);
            let mut phasor = Complex64::from_polar(1.0, -(n as f64) * 0.5 * d_theta);
            for (i, xi) in x.iter().enumerate() {
                if i % 64 == 0 {
                    phasor = Complex64::from_polar(1.0, -(n as f64) * (i as f64 + 0.5) * d_theta);
                }
                sum += phasor * *xi;
                phasor *= step;
            }
            sum * (2.0 / cells as f64)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The seed has run-out R⁰ in every order of its band, nothing beyond it, zero mean, and
    /// the same harmonics on 512 and 1024 cells.
    #[test]
    fn the_seed_is_the_same_band_on_any_grid() {
        let fine = Profile::seeded(1024, 2e-6, 7);
        let coarse = Profile::seeded(512, 2e-6, 7);
        assert!(fine.mean_depth_m().abs() < 1e-18);
        let (hf, hc) = (fine.harmonics(80), coarse.harmonics(80));
        for n in 1..=80 {
            let (a, b) = (hf[n - 1], hc[n - 1]);
            if n <= SEED_ORDERS {
                assert!((a.norm() - 2e-6).abs() < 1e-17, "{n}: {a}");
            } else {
                assert!(a.norm() < 1e-17, "{n}: {a}");
            }
            assert!((a - b).norm() < 1e-17, "{n}: {a} vs {b}");
        }
        // Another seed, other phases.
        let other = Profile::seeded(1024, 2e-6, 8).harmonics(3);
        assert!((other[2] - hf[2]).norm() > 1e-7);
    }

    /// A sampled harmonic with a known amplitude and phase is read back exactly.
    #[test]
    fn harmonics_read_back_a_sampled_cosine() {
        let cells = 1000;
        let d_theta = std::f64::consts::TAU / cells as f64;
        let want = Complex64::new(0.3, -1.2);
        let x: Vec<f64> = (0..cells)
            .map(|i| (want * Complex64::from_polar(1.0, 19.0 * (i as f64 + 0.5) * d_theta)).re)
            .collect();
        let h = harmonics_of(&x, 40);
        assert!((h[18] - want).norm() < 1e-13, "{}", h[18]);
        assert!(h[17].norm() < 1e-13 && h[19].norm() < 1e-13);
    }
}
