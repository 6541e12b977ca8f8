//! Laying friction energy onto the worn profile, element by element (MODEL.md#step-11-wear-zone,
//! MODEL.md#step-12-feedback): the energy dissipated while the element at the patch centre is at
//! angle θ_c goes to the cells the wear zone covers then, by the kernel's exact integral over
//! each cell, and within the zone each element takes its share of the friction force in
//! proportion to its own pressure, (1 + κ r(θ))/(1 + ε_loc). The shares of one instant add up to
//! 1, so the volume worn is γ times the energy to rounding.
//!
//! Each sample interval's energy is laid at its centre angle θ_k, so an even power lays the comb
//! Σ_k K_w(θ − θ_k), whose harmonics p·N (N samples per revolution) are 2|H_w(pN)| of the even
//! wear (Poisson's sum). On M cells they vanish only if every θ_k sits at the same place in its
//! cell, N a whole multiple of M ([`check_samples`]); N = M/4 printed orders M/4 and M/2
//! (MODEL.md#the-long-term-loop).

use crate::wear::physics::zone::ZoneGeometry;

/// Where the energy of each sample instant of a revolution goes: for sample k, the cells and
/// the shares (summing to 1) of the energy they take.
#[derive(Debug, Clone)]
pub struct DepositPlan {
    cells: usize,
    /// (cell, share) of every sample, sample after sample.
    entries: Vec<(u32, f64)>,
    /// Sample k's entries are `entries[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    /// b·r_B·Δθ: the tread area of one cell \[m²\].
    cell_area_m2: f64,
}

/// Refuses `samples` energy samples per revolution on `cells` cells unless `samples` is a whole
/// multiple of `cells`: only then is the plan the same for every cell, shifted, so that an even
/// power wears every cell alike (the sample comb's harmonics, multiples of M, integrate to 0
/// over each cell).
pub fn check_samples(samples: usize, cells: usize) -> Result<(), SampleCombError> {
    if cells > 0 && samples > 0 && samples % cells == 0 {
        Ok(())
    } else {
        Err(SampleCombError { samples, cells })
    }
}

/// Energy samples per revolution that are not a whole multiple of the profile's cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "{samples} energy samples per revolution are not a whole multiple of the {cells} cells: the samples' comb would print orders the cells resolve"
)]
pub struct SampleCombError {
    /// Energy samples per revolution.
    pub samples: usize,
    /// Cells of the profile.
    pub cells: usize,
}

impl DepositPlan {
    /// The plan for `samples` instants per revolution, sample k at centre angle
    /// 2π(k + `offset`)/`samples` (offset ½: the middle of the k-th interval), on the profile
    /// `radius_m` (r per cell, mean removed) under the zone `zone` of a tread `width_m` wide on
    /// radius `r_b`; `local_per_m` is κ = k_t/p₀. A cell whose pressure would be negative
    /// (κ r < −1, out of contact) takes nothing; if the whole zone is out of contact the
    /// kernel alone shares the energy.
    pub fn new(
        zone: &ZoneGeometry,
        r_b: f64,
        width_m: f64,
        radius_m: &[f64],
        local_per_m: f64,
        samples: usize,
        offset: f64,
    ) -> Self {
        let cells = radius_m.len();
        let mut entries = Vec::new();
        let mut offsets = Vec::with_capacity(samples + 1);
        for k in 0..samples {
            offsets.push(entries.len());
            let centre = std::f64::consts::TAU * (k as f64 + offset) / samples as f64;
            let start = entries.len();
            let mut total = 0.0;
            for (cell, w) in zone.cell_weights(centre, r_b, cells) {
                let share = w * (1.0 + local_per_m * radius_m[cell]).max(0.0);
                total += share;
                entries.push((cell as u32, share));
            }
            if total > 0.0 {
                for e in &mut entries[start..] {
                    e.1 /= total;
                }
            } else {
                entries.truncate(start);
                entries.extend(
                    zone.cell_weights(centre, r_b, cells)
                        .map(|(c, w)| (c as u32, w)),
                );
            }
        }
        offsets.push(entries.len());
        DepositPlan {
            cells,
            entries,
            offsets,
            cell_area_m2: width_m * r_b * std::f64::consts::TAU / cells as f64,
        }
    }

    /// The number of sample instants per revolution.
    pub fn samples(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The depth \[m\] each cell loses when sample k dissipates `energy_j[k]` \[J\] at
    /// abradability `gamma_m3_per_j` (the volume γE over the cell's tread area).
    pub fn lay(&self, gamma_m3_per_j: f64, energy_j: &[f64]) -> Vec<f64> {
        let mut depth = vec![0.0; self.cells];
        for (k, e) in energy_j.iter().enumerate() {
            let volume = gamma_m3_per_j * e / self.cell_area_m2;
            for &(cell, share) in &self.entries[self.offsets[k]..self.offsets[k + 1]] {
                depth[cell as usize] += volume * share;
            }
        }
        depth
    }
}

/// The wear per metre \[m/m\] of the share of a tyre's wear that does not come from straight
/// running, (1 − φ_s)·w′₀, at each cell: pressure-proportional like all wear, each element by
/// its own pressure 1 + κ r (never negative), not coupled to the vibration
/// (MODEL.md#growth-of-an-order: it adds λ_other = (1 − φ_s) w′₀ κ to every order's levelling).
pub fn other_wear_m_per_m(radius_m: &[f64], local_per_m: f64, rate_m_per_m: f64) -> Vec<f64> {
    radius_m
        .iter()
        .map(|r| rate_m_per_m * (1.0 + local_per_m * r).max(0.0))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::long_term::profile::{harmonics_of, Profile};
    use crate::wear::physics::law::deposit_revolution;
    use crate::wear::physics::zone::WearZone;

    /// An even power laid from N = M or 2M samples wears every cell alike, for any
    /// zone length; from N = M/4 it prints 2|H_w(pN)| of the even wear at orders M/4 and M/2
    /// (over 30% and 15% for the 4.9-cell zone of the driving wheel at 110 km/h and 0.45°).
    #[test]
    fn an_even_power_wears_every_cell_alike_when_the_samples_step_by_cells() {
        let (r_b, b, cells) = (0.317, 0.134, 1024);
        let flat = vec![0.0; cells];
        let comb = |q: f64, samples: usize| {
            let g = ZoneGeometry::new(WearZone::Trailing, 0.1551, q);
            let plan = DepositPlan::new(&g, r_b, b, &flat, 891.0, samples, 0.5);
            let depth = plan.lay(1.0, &vec![1.0; samples]);
            let mean = depth.iter().sum::<f64>() / cells as f64;
            let rel: Vec<f64> = depth.iter().map(|d| d / mean - 1.0).collect();
            let h = harmonics_of(&rel, cells / 2);
            (g, h[cells / 4 - 1].norm(), h[cells / 2 - 1].norm() / 2.0)
        };
        for q in [0.0328, 0.0614, 0.2, 1.0] {
            for samples in [cells, 2 * cells] {
                assert!(check_samples(samples, cells).is_ok());
                let (_, a, b) = comb(q, samples);
                assert!(a < 1e-13 && b < 1e-13, "q {q}, {samples}: {a:e} {b:e}");
            }
            let (g, quarter, half) = comb(q, cells / 4);
            assert!(check_samples(cells / 4, cells).is_err());
            // Order M/4 is the comb's 2|H_w(M/4)| through the cells' box sinc(nΔθ/2), give or
            // take its aliases, the odd multiples of M/4.
            let m = cells as f64;
            let h = |p: f64| {
                let n = p * m / 4.0;
                2.0 * (g.gain(n, r_b)
                    * crate::wear::physics::zone::sinc(n * std::f64::consts::PI / m))
                .abs()
            };
            let aliases: f64 = (1..100).map(|k| h((2 * k + 1) as f64)).sum();
            assert!(
                (quarter - h(1.0)).abs() <= aliases + 1e-12,
                "q {q}: {quarter}"
            );
            if q == 0.0614 {
                assert!(quarter > 0.3 && half > 0.15, "q {q}: {quarter} {half}");
            }
        }
    }

    /// Without pressure feedback (κ = 0) the plan is the core's own deposit; with it, the
    /// volume is still γ times the energy to rounding, and a high spot (r > 0) takes more.
    #[test]
    fn plan_is_the_kernel_deposit_plus_the_pressure_share() {
        let (gamma, b, v, r_b) = (2.4e-11, 0.134, 27.8, 0.317);
        let profile = Profile::seeded(1024, 20e-6, 3).radius_m();
        for zone in WearZone::ALL {
            let g = ZoneGeometry::new(zone, 0.155, 0.033);
            let samples = 997;
            let power: Vec<f64> = (0..samples)
                .map(|j| 37.0 + 16.0 * (0.37 * j as f64).sin())
                .collect();
            let t_rev = std::f64::consts::TAU * r_b / v;
            let energy: Vec<f64> = power.iter().map(|p| p * t_rev / samples as f64).collect();
            let core = deposit_revolution(gamma, b, v, r_b, &g, &power, 1024);
            let flat = DepositPlan::new(&g, r_b, b, &profile, 0.0, samples, 0.0);
            for (a, c) in flat.lay(gamma, &energy).iter().zip(&core) {
                assert!((a - c).abs() <= 1e-12 * c.abs(), "{zone}: {a} vs {c}");
            }
            let pressed = DepositPlan::new(&g, r_b, b, &profile, 891.0, samples, 0.0);
            let depth = pressed.lay(gamma, &energy);
            let volume = depth.iter().sum::<f64>() * b * r_b * std::f64::consts::TAU / 1024.0;
            let e_total: f64 = energy.iter().sum();
            assert!((volume / (gamma * e_total) - 1.0).abs() < 1e-12, "{zone}");
            // A uniform power wears the high spots more: the depth correlates with r.
            let even = pressed.lay(gamma, &vec![1.0; samples]);
            let corr: f64 = even.iter().zip(&profile).map(|(d, r)| d * r).sum();
            assert!(corr > 0.0, "{zone}: {corr}");
        }
    }
}
