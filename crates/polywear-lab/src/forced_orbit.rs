//! The tread forced by one polygon harmonic, solved as the forced system's periodic orbit
//! (MODEL.md#the-locked-print). A cycle locked to order n runs at the forcing's period
//! T = 2π/Ω exactly, so it is a fixed point of the map over one period, x₀ ↦ φ_T(x₀), which
//! Newton finds with the monodromy matrix M = ∂φ_T/∂x₀ from the variational equations. The
//! orbit locks (attracts) where every eigenvalue of M lies inside the unit circle, and its
//! power's harmonic at Ω is the print it lays on the polygon. Unlike brute force, nothing is
//! settled, and unlike the forced Hopf normal form ([`polywear_core::wear::response::normal_form`]), nothing is
//! truncated: the lock and the print at any depth, where the normal form holds to some 8 µm.

use nalgebra::{Matrix3, Vector3};
use polywear_core::classify::Scales;
use polywear_core::model::TreadOde;
use polywear_core::numeric::Complex64;
use polywear_core::solver::{
    integrate_dop853, Control, IntegrationError, OdeSystem, SolverOptions,
};
use polywear_core::wear::physics::feedback::with_friction_scale;

/// Newton iterations before the orbit counts as not found.
const MOST_ITERATIONS: usize = 30;
/// The orbit is found when the return misses its start by less than this many times the
/// integration's absolute tolerance in every component.
const FOUND_WITHIN_ATOL: f64 = 10.0;
/// The friction levels never fall below this share of their unforced values (as
/// [`polywear_core::long_term::window`]'s integration holds them).
const MIN_FRICTION_SCALE: f64 = 0.05;

/// The forced tread with its variational equations, time and the power's integrals as
/// states: (z, y, v, Φ column by column, t, ∫P, ∫P cos Ωt, ∫P sin Ωt).
struct ForcedVariational<'a> {
    ode: &'a TreadOde,
    /// ε_n: ε(t) = Re\[ε_n e^{iΩt}\].
    forcing: Complex64,
    omega_rad_s: f64,
}

impl OdeSystem<16> for ForcedVariational<'_> {
    /// The step control is the tread's three states', as everywhere else.
    const ERROR_NORM_COMPONENTS: usize = 3;

    fn rhs(&self, s: &[f64; 16]) -> [f64; 16] {
        let t = s[12];
        let (sin, cos) = (self.omega_rad_s * t).sin_cos();
        let eps = (self.forcing.re * cos - self.forcing.im * sin).max(MIN_FRICTION_SCALE - 1.0);
        let ode = with_friction_scale(self.ode, eps);
        let x = [s[0], s[1], s[2]];
        let f = ode.rhs(&x);
        let j = ode.jacobian(&x);
        let phi = Matrix3::from_column_slice(&s[3..12]);
        let d_phi = j * phi;
        let power_w = (ode.sigma0 * x[0] + ode.sigma1 * f[0]) * (x[2] - ode.u_mps);
        let mut out = [0.0; 16];
        out[..3].copy_from_slice(&f);
        out[3..12].copy_from_slice(d_phi.as_slice());
        out[12] = 1.0;
        out[13] = power_w;
        out[14] = power_w * cos;
        out[15] = power_w * sin;
        out
    }
}

/// The forced orbit.
#[derive(Debug, Clone, PartialEq)]
pub struct ForcedOrbit {
    /// Its state (z, y, v) at t = 0 (the forcing's phase 0).
    pub start: [f64; 3],
    /// The eigenvalues of its monodromy matrix over one forcing period.
    pub multipliers: [Complex64; 3],
    /// Its print: the power's harmonic at Ω over its mean, p in P = P̄(1 + Re\[p e^{iΩt}\]).
    pub print: Complex64,
    /// Its mean power P̄ \[W\].
    pub mean_power_w: f64,
    /// Right-hand-side evaluations spent (of the 16-state system).
    pub rhs_evals: usize,
}

impl ForcedOrbit {
    /// Whether it attracts: every multiplier inside the unit circle (the cycle locked).
    pub fn locks(&self) -> bool {
        self.multipliers.iter().all(|m| m.norm() < 1.0)
    }
}

/// Why no orbit came out.
#[derive(Debug, Clone, PartialEq)]
pub enum OrbitError {
    /// The integration over one period failed.
    Integration(IntegrationError),
    /// Newton did not converge (no orbit near the start, or a singular step).
    NotFound,
}

/// The periodic orbit of `ode` forced by ε(t) = Re\[`forcing` e^{iΩt}\], Ω = `omega_rad_s`,
/// by Newton from `start` at relative tolerance `rtol`.
pub fn solve(
    ode: &TreadOde,
    forcing: Complex64,
    omega_rad_s: f64,
    start: [f64; 3],
    rtol: f64,
) -> Result<ForcedOrbit, OrbitError> {
    let sys = ForcedVariational {
        ode,
        forcing,
        omega_rad_s,
    };
    let period_s = std::f64::consts::TAU / omega_rad_s;
    let atol3 = Scales::new(ode).atol(rtol);
    let mut atol = [f64::INFINITY; 16];
    atol[..3].copy_from_slice(&atol3);
    let opts = SolverOptions::per_period(rtol, atol, period_s, 1_000_000);
    let mut x0 = Vector3::from(start);
    let mut rhs_evals = 0;
    for _ in 0..MOST_ITERATIONS {
        let mut s0 = [0.0; 16];
        s0[..3].copy_from_slice(x0.as_slice());
        s0[3..12].copy_from_slice(Matrix3::<f64>::identity().as_slice());
        let out = integrate_dop853(&sys, 0.0, s0, period_s, &opts, |_| Control::Continue)
            .map_err(OrbitError::Integration)?;
        rhs_evals += out.rhs_evals;
        let s = out.x;
        let miss = Vector3::new(s[0], s[1], s[2]) - x0;
        let monodromy = Matrix3::from_column_slice(&s[3..12]);
        let found = (0..3).all(|i| miss[i].abs() <= FOUND_WITHIN_ATOL * atol3[i]);
        if found {
            let multipliers = match monodromy.try_schur(f64::EPSILON, 10_000) {
                Some(schur) => {
                    let e = schur.complex_eigenvalues();
                    [e[0], e[1], e[2]]
                }
                None => return Err(OrbitError::NotFound),
            };
            return Ok(ForcedOrbit {
                start: [x0[0], x0[1], x0[2]],
                multipliers,
                print: 2.0 * Complex64::new(s[14], -s[15]) / s[13],
                mean_power_w: s[13] / period_s,
                rhs_evals,
            });
        }
        let step = (monodromy - Matrix3::identity())
            .lu()
            .solve(&(-miss))
            .ok_or(OrbitError::NotFound)?;
        x0 += step;
        if !x0.iter().all(|v| v.is_finite()) {
            return Err(OrbitError::NotFound);
        }
    }
    Err(OrbitError::NotFound)
}

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_core::model::{Variant, Wheel, WheelModel};
    use polywear_core::params::Params;
    use polywear_core::wear::response::transfer::Linearisation;

    /// A stable tread weakly forced runs on an attracting orbit near its equilibrium whose
    /// print is the linear transfer's, p = G(iΩ) ε_n (MODEL.md#growth-of-an-order), within
    /// 10⁻⁴ of it, at frequencies below, near and above the tread's own; unforced, the orbit is
    /// the equilibrium itself and prints nothing.
    #[test]
    fn a_weakly_forced_stable_tread_prints_its_linear_transfer() {
        let p = Params {
            speed_kmh: 70.0,
            ..Params::default()
        };
        let m = WheelModel::build(&p, Wheel::Follower, Variant::SlidingShare).unwrap();
        let eq = m.ode.equilibrium();
        let lin = Linearisation::at(&m.ode, &eq);
        let forcing = Complex64::from_polar(1e-6, 0.3);
        for omega in [900.0, 1692.0, 2500.0] {
            let orbit = solve(&m.ode, forcing, omega, eq, 1e-11).unwrap();
            assert!(orbit.locks(), "{omega}: {:?}", orbit.multipliers);
            let linear = lin.transfer(omega) * forcing;
            assert!(
                (orbit.print - linear).norm() < 1e-4 * linear.norm(),
                "{omega}: {} against {linear}",
                orbit.print
            );
        }
        let still = solve(&m.ode, Complex64::new(0.0, 0.0), 1692.0, eq, 1e-11).unwrap();
        assert!(still.print.norm() < 1e-9, "{}", still.print);
    }
}
