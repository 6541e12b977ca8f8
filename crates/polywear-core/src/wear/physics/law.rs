//! MODEL.md#step-10-wear-law: rubber loses volume in proportion to the frictional energy it
//! dissipates, dV = γ dE (the energy form of Archard's law, Schallamach's abradability). The
//! lumped tread slides at w = v − U against the friction force F = σ0 z + σ1 ż (σ2 = 0), so the
//! power dissipated at the interface is P = F·w. With F the force the tread exerts on the road
//! (m v̇ = −C_s v − K_s y − F, MODEL.md#step-6-tread-ode), F and w have the same sign on every
//! cycle of the follower and P ≥ 0 as it stands; over a period P̄ = −U F̄ − C_s⟨v²⟩, since the
//! tread's spring stores nothing and its damper takes C_s⟨v²⟩ of what friction feeds in.
//!
//! Wear depth per revolution of an element is γ/(b V) times the power averaged over its passage
//! through the wear zone; the even-wear rate per distance is w′ = γ P̄ / (b V 2π r_B).

use super::zone::ZoneGeometry;
use crate::model::{State, TreadOde};

/// m/m (depth per distance) to mm per 1000 km.
pub const MM_PER_1000KM_PER_M_PER_M: f64 = 1e9;
/// 1/m (growth per distance) to 1 per 1000 km.
pub(crate) const PER_1000KM_PER_PER_M: f64 = 1e6;

/// The friction force F = σ0 z + σ1 ż \[N\] the tread exerts on the road at state `x`
/// (MODEL.md#step-6-tread-ode; σ2 = 0).
pub fn friction_force_n(ode: &TreadOde, x: &State) -> f64 {
    let dz = ode.rhs(x)[0];
    ode.sigma0 * x[0] + ode.sigma1 * dz
}

/// The friction power P = F·w \[W\] dissipated at the interface at state `x`, w = v − U the
/// tread's sliding speed.
pub fn friction_power_w(ode: &TreadOde, x: &State) -> f64 {
    friction_force_n(ode, x) * (x[2] - ode.u_mps)
}

/// P at the equilibrium, −U·F₀ = U² g(w_t0)/w_t0 \[W\] (MODEL.md#step-7-equilibrium).
pub(crate) fn equilibrium_power_w(ode: &TreadOde) -> f64 {
    friction_power_w(ode, &ode.equilibrium())
}

/// The even-wear rate w′ = γ P̄ / (b V 2π r_B) \[m/m\]: the volume γ P̄ worn per second spread
/// over the tread band b·2π r_B, which passes 1/(2π r_B) revolutions per metre.
pub fn even_wear_m_per_m(
    gamma_m3_per_j: f64,
    mean_power_w: f64,
    width_m: f64,
    speed_mps: f64,
    r_b: f64,
) -> f64 {
    gamma_m3_per_j * mean_power_w / (width_m * speed_mps * std::f64::consts::TAU * r_b)
}

/// Lays one revolution of friction power onto the circumference: `power_w[j]` is P at
/// t_j = j·T_rev/N (N = `power_w.len()`, T_rev = 2π r_B / V), each sample carries the energy
/// P_j T_rev/N, spread over the tyre angles the wear zone covers at t_j by the kernel's exact
/// integral over each of the `cells` cells of angle. Returns the depth worn per cell \[m\].
/// The volume is conserved to rounding: b r_B Δθ Σ depth = γ Σ P_j T_rev/N
/// (MODEL.md#step-11-wear-zone). The angle of the element at the patch centre is Ω t.
pub fn deposit_revolution(
    gamma_m3_per_j: f64,
    width_m: f64,
    speed_mps: f64,
    r_b: f64,
    zone: &ZoneGeometry,
    power_w: &[f64],
    cells: usize,
) -> Vec<f64> {
    let mut depth = vec![0.0; cells];
    let t_rev = std::f64::consts::TAU * r_b / speed_mps;
    let dt = t_rev / power_w.len() as f64;
    let cell_area = width_m * r_b * std::f64::consts::TAU / cells as f64;
    for (j, p) in power_w.iter().enumerate() {
        let centre_angle = std::f64::consts::TAU * j as f64 / power_w.len() as f64;
        let volume = gamma_m3_per_j * p * dt;
        for (cell, w) in zone.cell_weights(centre_angle, r_b, cells) {
            depth[cell] += volume * w / cell_area;
        }
    }
    depth
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Variant, Wheel, WheelModel};
    use crate::params::Params;
    use crate::wear::physics::zone::WearZone;

    /// At the equilibrium P = U² g / w_t, positive, for both wheels.
    #[test]
    fn equilibrium_power_is_the_sliding_friction_times_u() {
        for wheel in Wheel::BOTH {
            let m = WheelModel::build(&Params::default(), wheel, Variant::SlidingShare).unwrap();
            let ode = m.ode;
            let (wt, _) = ode.sliding_speed(-ode.u_mps);
            let expected = ode.u_mps * ode.u_mps * ode.stribeck(wt) / wt;
            let p = equilibrium_power_w(&ode);
            assert!(
                p > 0.0 && (p / expected - 1.0).abs() < 1e-12,
                "{p} vs {expected}"
            );
        }
    }

    /// The deposit conserves volume to rounding for every zone, and a constant power wears
    /// every cell by the even wear of one revolution.
    #[test]
    fn deposit_conserves_volume() {
        let (gamma, b, v, r_b) = (2.4e-11, 0.134, 27.8, 0.317);
        for zone in WearZone::ALL {
            let g = ZoneGeometry::new(zone, 0.155, 0.033);
            let power: Vec<f64> = (0..997)
                .map(|j| 37.0 + 16.0 * (0.37 * j as f64).sin())
                .collect();
            let cells = 1024;
            let depth = deposit_revolution(gamma, b, v, r_b, &g, &power, cells);
            let t_rev = std::f64::consts::TAU * r_b / v;
            let energy: f64 = power.iter().sum::<f64>() * t_rev / power.len() as f64;
            let volume: f64 =
                depth.iter().sum::<f64>() * b * r_b * std::f64::consts::TAU / cells as f64;
            assert!((volume / (gamma * energy) - 1.0).abs() < 1e-12, "{zone}");
            let even = deposit_revolution(gamma, b, v, r_b, &g, &vec![37.0; 4096], cells);
            let per_rev = even_wear_m_per_m(gamma, 37.0, b, v, r_b) * std::f64::consts::TAU * r_b;
            for d in even {
                assert!((d / per_rev - 1.0).abs() < 1e-3, "{zone}: {d} vs {per_rev}");
            }
        }
    }
}
