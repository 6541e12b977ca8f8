//! MODEL.md#step-12-feedback: how the worn profile acts back on the tread. A radius deviation
//! r(θ) (a high spot, r > 0, is less worn) raises the pressure under the tread and so both
//! friction levels, F_{m,s} → F_{m,s}·(1 + ε(t)), by two paths:
//!
//! - **local** (F-local): the tread blocks are a compression foundation of stiffness
//!   k_t = factor·G/h over the mean pressure p₀ = F_Z/(a b), so the sliding zone's friction
//!   rises by ε_loc(t) = (k_t/p₀)·\[K_w ∗ r\](t);
//! - **load** (F-global): the belt envelopes the profile under the parabolic patch pressure, so
//!   the load changes by ΔF_Z(t) = k_r·\[K_p ∗ r\](t), k_r the radial stiffness; F_m and F_s
//!   both scale with F_Z·L (step 5), so ΔF_Z is one more relative change of the friction
//!   levels, ε_glob = ∂ln(F_Z L)/∂F_Z · ΔF_Z, at the wheel's slip ratio.
//!
//! The radius path (the rolling radius varying at n·f_rot, reaching the tread only through
//! V_sx and at second order) is left out. Neither path changes K_s or m: the tread's own
//! stiffness and mass stay those of the mean patch.

use super::zone::{pressure_transfer, WearZone, ZoneGeometry};
use crate::model::{brush, tire, State, TreadOde, WheelModel};
use crate::numeric::Complex64;
use crate::params::Params;
use crate::solver::OdeSystem;

/// Profile orders that act back through ε and that the long-term loop's history records, 1 ..= this (the seed's
/// band is 1..=64; the zone filters what lies beyond).
pub const FEEDBACK_ORDERS: usize = 128;

/// The two feedback paths at one wheel and operating point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Feedback {
    /// κ = k_t/p₀ \[1/m\]: the relative pressure change per metre of radius under the tread.
    pub local_per_m: f64,
    /// k_r \[N/m\]: the load change per metre of radius under the belt.
    pub radial_stiffness_n_per_m: f64,
    /// ∂ln(F_Z L)/∂F_Z \[1/N\]: the relative change of both friction levels per newton of load.
    pub load_sensitivity_per_n: f64,
    /// Where the friction power is deposited, and the local path samples the profile.
    pub zone: ZoneGeometry,
    /// The whole patch under its parabolic pressure (the load path's kernel K_p).
    pub patch: ZoneGeometry,
    /// Tire radius r_B \[m\].
    pub r_b: f64,
}

impl Feedback {
    /// Both paths for `model` at `p`, the wear zone `zone` laid on its patch.
    pub fn new(p: &Params, model: &WheelModel, zone: WearZone) -> Self {
        let a = model.patch.length_m;
        let p0_pa = p.load_n / (a * model.patch.width_m);
        Feedback {
            local_per_m: foundation_stiffness_pa_per_m(p) / p0_pa,
            radial_stiffness_n_per_m: p.radial_stiffness_factor * model_radial_stiffness_n_per_m(p),
            load_sensitivity_per_n: load_sensitivity_per_n(p, model.slip_ratio),
            zone: ZoneGeometry::new(zone, a, model.friction.q),
            patch: ZoneGeometry::new(WearZone::WholePatch, a, 1.0),
            r_b: p.r_b,
        }
    }

    /// e_n \[1/m\]: ε = Re\[e_n R e^{inΩt}\] for the profile harmonic r = Re\[R e^{inθ}\]:
    /// κ H_w(n) + ∂ln(F_Z L)/∂F_Z · k_r H_p(n).
    pub fn forcing_per_radius(&self, order: f64) -> Complex64 {
        self.forcing_of(
            self.zone.transfer(order, self.r_b),
            pressure_transfer(order, self.patch.length_m, self.r_b),
        )
    }

    /// (H_w(n), e_n) at the consecutive orders `first`, `first` + 1, …: the zone's transfer and
    /// [`Feedback::forcing_per_radius`], their sines by rotation ([`ZoneGeometry::gains`]).
    pub fn zones_and_forcings(
        &self,
        first: u32,
    ) -> impl Iterator<Item = (Complex64, Complex64)> + '_ {
        self.zone
            .transfers(first, self.r_b)
            .zip(self.patch.gains(first, self.r_b))
            .map(|(zone, pressure)| (zone, self.forcing_of(zone, pressure)))
    }

    /// e_n from the zone's transfer H_w(n) and the pressure's H_p(n).
    fn forcing_of(&self, zone: Complex64, pressure: f64) -> Complex64 {
        zone * self.local_per_m
            + self.radial_stiffness_n_per_m * pressure * self.load_sensitivity_per_n
    }

    /// The part of a print p on order `order` (the power P̄(1 + Re\[p e^{inθ}\]) at the
    /// order's frequency) that deepens a polygon whose crests lie at tyre angle 0, over |p|'s
    /// full print: the wear zone lays dR/ds = −w′ conj(H_w) p, so Re(−conj(H_w) p)/|H_w|
    /// (MODEL.md#the-locked-print).
    pub fn in_phase_print(&self, order: f64, print: Complex64) -> f64 {
        let zone = self.zone.transfer(order, self.r_b);
        (-zone.conj() * print).re / zone.norm()
    }

    /// ΔF_Z per metre of radius of the harmonic of `order` under the belt, k_r H_p(n) \[N/m\].
    pub fn load_per_radius(&self, order: f64) -> f64 {
        self.radial_stiffness_n_per_m * pressure_transfer(order, self.patch.length_m, self.r_b)
    }

    /// ε at the moment the element at the patch centre is at tyre angle `centre_angle_rad`,
    /// for a radius deviation `radius_m` held on equal cells of tyre angle (its mean is
    /// removed first: uniform wear changes neither pressure nor load).
    pub fn epsilon_on_cells(&self, radius_m: &[f64], centre_angle_rad: f64) -> f64 {
        let mean = radius_m.iter().sum::<f64>() / radius_m.len() as f64;
        let local = self
            .zone
            .average_on_cells(radius_m, centre_angle_rad, self.r_b)
            - mean;
        let load = self
            .patch
            .average_on_cells(radius_m, centre_angle_rad, self.r_b)
            - mean;
        self.local_per_m * local
            + self.load_sensitivity_per_n * self.radial_stiffness_n_per_m * load
    }
}

/// The tread foundation stiffness k_t = factor·G/h \[Pa/m\] (incompressible blocks, no bulging
/// or belt: judgement, MODEL.md#wear-constants).
pub(crate) fn foundation_stiffness_pa_per_m(p: &Params) -> f64 {
    p.foundation_stiffness_factor * p.g_mod / p.tread_height
}

/// The model's own tangent radial stiffness (dδ/dF_Z)⁻¹ \[N/m\] of step 1's deflection
/// δ = t + √(t² + α2 F_Z), t = α1 F_Z/(2P) (MODEL.md#step-1-deflection).
pub(crate) fn model_radial_stiffness_n_per_m(p: &Params) -> f64 {
    let alpha1 = 1.0 / (std::f64::consts::TAU * (p.r_b * p.r_w).sqrt());
    let f = p.load_n;
    let t = alpha1 * f / (2.0 * p.pressure_pa());
    let root = (t * t + p.alpha2 * f).sqrt();
    let d_delta = t / f + (2.0 * t * t / f + p.alpha2) / (2.0 * root);
    1.0 / d_delta
}

/// ∂ln(F_Z L)/∂F_Z \[1/N\] by central differences of steps 1, 2 and 5 at slip ratio
/// `slip_ratio` (the drive force does not follow the load at the tread frequency). F_m and F_s
/// share the factor F_Z·L, so this one number is the relative change of both.
pub(crate) fn load_sensitivity_per_n(p: &Params, slip_ratio: f64) -> f64 {
    let h = 1e-4 * p.load_n;
    let f_m = |load_n: f64| {
        let q = Params { load_n, ..*p };
        match tire::contact_patch(&q) {
            Ok(patch) => brush::friction_levels(&q, &patch, slip_ratio).f_m,
            Err(_) => f64::NAN,
        }
    };
    let (up, down, mid) = (f_m(p.load_n + h), f_m(p.load_n - h), f_m(p.load_n));
    (up - down) / (2.0 * h * mid)
}

/// The tread ODE with both friction levels scaled by 1 + `epsilon`.
pub fn with_friction_scale(ode: &TreadOde, epsilon: f64) -> TreadOde {
    TreadOde {
        f_m: ode.f_m * (1.0 + epsilon),
        f_s: ode.f_s * (1.0 + epsilon),
        ..*ode
    }
}

/// The tread forced by ε(t): state (z, y, v, t), the friction levels scaled by 1 + ε(t) at
/// every evaluation. Time is the fourth state so that the autonomous integrators carry it.
pub struct ForcedTread<F: Fn(f64) -> f64> {
    /// The unforced tread.
    pub ode: TreadOde,
    /// ε as a function of time \[s\].
    pub epsilon: F,
}

impl<F: Fn(f64) -> f64> ForcedTread<F> {
    /// The tread ODE at time `t_s`.
    pub fn at(&self, t_s: f64) -> TreadOde {
        with_friction_scale(&self.ode, (self.epsilon)(t_s))
    }

    /// P = F·w \[W\] at state `s` = (z, y, v, t).
    pub fn power_w(&self, s: &[f64; 4]) -> f64 {
        super::law::friction_power_w(&self.at(s[3]), &[s[0], s[1], s[2]])
    }
}

impl<F: Fn(f64) -> f64> OdeSystem<4> for ForcedTread<F> {
    fn rhs(&self, s: &[f64; 4]) -> [f64; 4] {
        let x: State = [s[0], s[1], s[2]];
        let [dz, dy, dv] = self.at(s[3]).rhs(&x);
        [dz, dy, dv, 1.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Variant, Wheel};

    /// The analytic tangent stiffness is the central difference of step 1, and the load
    /// sensitivity is that of F_s as well as F_m.
    #[test]
    fn radial_stiffness_and_load_sensitivity() {
        let p = Params::default();
        let delta = |load_n: f64| {
            tire::contact_patch(&Params { load_n, ..p })
                .unwrap()
                .deflection_m
        };
        let h = 0.1;
        let numeric = 2.0 * h / (delta(p.load_n + h) - delta(p.load_n - h));
        let k = model_radial_stiffness_n_per_m(&p);
        assert!((k / numeric - 1.0).abs() < 1e-7, "{k} vs {numeric}");
        for wheel in Wheel::BOTH {
            let m = WheelModel::build(&p, wheel, Variant::SlidingShare).unwrap();
            let c = load_sensitivity_per_n(&p, m.slip_ratio);
            let f_s = |load_n: f64| {
                let q = Params { load_n, ..p };
                brush::friction_levels(&q, &tire::contact_patch(&q).unwrap(), m.slip_ratio).f_s
            };
            let cs = (f_s(p.load_n + 0.4) - f_s(p.load_n - 0.4)) / (0.8 * f_s(p.load_n));
            assert!((c / cs - 1.0).abs() < 1e-5, "{wheel}: {c} vs {cs}");
            assert!(c > 0.0);
        }
    }

    /// A sampled harmonic gives the forcing e_n R (mean removal included) on both paths.
    #[test]
    fn epsilon_on_cells_is_the_forcing_of_the_harmonic() {
        let p = Params::default();
        let m = WheelModel::build(&p, Wheel::Follower, Variant::SlidingShare).unwrap();
        let fb = Feedback::new(&p, &m, WearZone::Trailing);
        let cells = 8192;
        let d_theta = std::f64::consts::TAU / cells as f64;
        for order in [2.0, 19.0] {
            let r = Complex64::new(2e-6, 1e-6);
            let profile: Vec<f64> = (0..cells)
                .map(|i| {
                    5e-6 + (r * Complex64::from_polar(1.0, order * (i as f64 + 0.5) * d_theta)).re
                })
                .collect();
            for c in [0.3, 2.0] {
                let eps = fb.epsilon_on_cells(&profile, c);
                let want =
                    (fb.forcing_per_radius(order) * r * Complex64::from_polar(1.0, order * c)).re;
                assert!(
                    (eps - want).abs() < 2e-3 * (fb.local_per_m * r.norm()),
                    "{order} {c}: {eps} vs {want}"
                );
            }
        }
    }
}
