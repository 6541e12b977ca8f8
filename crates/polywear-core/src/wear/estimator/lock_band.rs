//! The lock-in tongue of an order and the locked print (MODEL.md#growth-of-a-vibrating-wheel,
//! MODEL.md#the-tongue-at-depth, MODEL.md#the-locked-print): the speed band in which a vibrating
//! wheel's cycle locks to a polygon order, and what the locked cycle prints on it.

use super::*;

impl WheelGrowth {
    /// The speed band \[m/s\] (centre, half-width) in which the cycle locks to order `n` of
    /// depth |R_n| = `radius_m` and forcing e_n = `forcing`: |δ| ≤ δ_L = ν |e_n R_n| |ĝ₋₁|, the
    /// band ±V δ_L / n around V_n = V ν / n (ν ∝ 1/V at a fixed tread frequency); none for a
    /// stable wheel. A worn tread's ν is ν₀·f/f₀, which is n read at x = n·f₀/f.
    pub(super) fn tongue_mps(&self, n: f64, forcing: Complex64, radius_m: f64) -> (f64, f64) {
        let r = &self.response;
        let v = self.speed_mps;
        let lock_rev = r.nu * forcing.norm_sqr().sqrt() * radius_m * r.phase_coupling_s;
        (v * r.nu / n, v * lock_rev / n)
    }

    /// The speed band \[km/h\] in which the cycle locks to an order-`order` polygon of radius
    /// |R_n| = `radius_m`, as offsets (below ≤ 0 ≤ above) from V_n = V ν/n, from the cycle's
    /// forced Hopf normal form (MODEL.md#the-tongue-at-depth): the first-order ±V δ_L/n while
    /// δ_L is small beside the amplitude mode's rate, narrower and lopsided as the polygon
    /// deepens. A cycle whose amplitude mode relaxes within a small part of its period (no
    /// normal form read) keeps the first-order band, the normal form's limit there. None for a
    /// stable tread.
    pub fn lock_band_kmh(&self, order: u32, radius_m: f64) -> Option<(f64, f64)> {
        if self.response.phase_coupling_s <= 0.0 {
            return None;
        }
        let (first_rad_s, kmh_per_rad_s) = self.first_order_lock(order, radius_m);
        let (below, above) = match self.response.hopf {
            Some(hopf) => hopf.lock_edges_rad_s(first_rad_s),
            None => (-first_rad_s, first_rad_s),
        };
        Some((below * kmh_per_rad_s, above * kmh_per_rad_s))
    }

    /// The radius |R_n| \[m\] of an order-`order` polygon at which the cycle locks to it at the
    /// speed `offset_kmh` from V_n = V ν/n (as [`WheelGrowth::lock_band_kmh`]'s edges): the
    /// normal form's least locking forcing in closed form
    /// ([`ForcedHopf::locking_first_order_rad_s`]), Adler's |Ω − ω_γ| = Δ₁ without a normal
    /// form. None for a stable tread.
    pub fn lock_radius_m(&self, order: u32, offset_kmh: f64) -> Option<f64> {
        if self.response.phase_coupling_s <= 0.0 {
            return None;
        }
        let (per_m_rad_s, kmh_per_rad_s) = self.first_order_lock(order, 1.0);
        let detuning_rad_s = offset_kmh / kmh_per_rad_s;
        let needed = match self.response.hopf {
            Some(hopf) => hopf.locking_first_order_rad_s(detuning_rad_s),
            None => detuning_rad_s.abs(),
        };
        Some(needed / per_m_rad_s)
    }

    /// The locked cycle's amplitude over the free cycle's, at a polygon of order `order` and
    /// radius `radius_m` with the speed `offset_kmh` from V_n = V ν/n (as
    /// [`WheelGrowth::lock_band_kmh`]'s edges), from the forced Hopf normal form; None outside
    /// the band, for a stable tread, or without a normal form.
    pub fn locked_amplitude(&self, order: u32, radius_m: f64, offset_kmh: f64) -> Option<f64> {
        let hopf = self.response.hopf?;
        let (first_rad_s, kmh_per_rad_s) = self.first_order_lock(order, radius_m);
        hopf.locked_amplitude(first_rad_s, offset_kmh / kmh_per_rad_s)
    }

    /// The locked cycle's print onto an order-`order` polygon of radius `radius_m`, at the
    /// speed `offset_kmh` from V_n (as [`WheelGrowth::locked_amplitude`]), as a share of the free
    /// cycle's full print 2w′|H_w||P₁|/P̄ (MODEL.md#the-locked-print): the part of it that deepens
    /// the polygon, its amplitude over the free cycle's times the cosine of its phase against
    /// the polygon's. The cycle locks at a phase that turns across the tongue (Adler's arccos,
    /// the normal form's fixed point at depth), and the power harmonic it carries turns with
    /// it, so that only part of the print lies in the polygon's valleys; negative, it fills
    /// them. A cycle without a normal form takes Adler's phase at the free amplitude. None
    /// outside the band or for a stable tread.
    pub fn locked_print_share(&self, order: u32, radius_m: f64, offset_kmh: f64) -> Option<f64> {
        if self.response.phase_coupling_s <= 0.0 {
            return None;
        }
        let n = order as f64;
        let (first_rad_s, kmh_per_rad_s) = self.first_order_lock(order, radius_m);
        let detuning_rad_s = offset_kmh / kmh_per_rad_s;
        let locked = match self.response.hopf {
            Some(hopf) => hopf.locked_cycle(first_rad_s, detuning_rad_s)?,
            None => {
                let s = detuning_rad_s / first_rad_s;
                (s.abs() <= 1.0).then(|| Complex64::from_polar(1.0, s.acos()))?
            }
        };
        // The print p = (2P̂₁/P̄) e^{iψ}, ψ − arg(ĝ₋₁e_n) = arg(locked), in units of |p|.
        let forcing = self.feedback.forcing_per_radius(n);
        let print = self.response.print_direction * unit(forcing) * locked;
        Some(self.feedback.in_phase_print(n, print))
    }

    /// The first-order lock half-width Δ₁ = δ_L·2πf_rot \[rad/s\] of an order-`order` polygon
    /// of radius `radius_m`, and the speed per unit of detuning around V_n \[km/h per rad/s\]:
    /// the forcing's frequency Ω = n V/r_B moves with V, so ΔV = (Ω − ω_γ) r_B/n.
    pub(super) fn first_order_lock(&self, order: u32, radius_m: f64) -> (f64, f64) {
        let n = order as f64;
        let (_, half_mps) = self.tongue_mps(n, self.feedback.forcing_per_radius(n), radius_m);
        let mps_per_rad_s = self.r_b / n;
        (half_mps / mps_per_rad_s, mps_per_rad_s * 3.6)
    }

    /// The locked print as a growth rate \[1/m\]: a cycle locked to the order prints its power
    /// harmonic on it every revolution, D_n rising by 2 w′ |H_w| |P₁|/P̄ per metre from the seed
    /// 2R⁰; the rate that reaches d_visible at the same distance.
    pub(super) fn locked_print_per_m(&self, even: f64, gain: f64) -> f64 {
        let rise = 2.0 * even * gain * self.response.power_harmonic_rel;
        let (seed, visible) = (2.0 * self.seed_m, self.visible_m);
        if rise <= 0.0 || seed <= 0.0 {
            return 0.0;
        }
        if visible <= seed {
            return f64::INFINITY;
        }
        self.print_log_ratio * rise / (visible - seed)
    }
}
