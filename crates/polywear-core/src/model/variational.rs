//! The tread ODE as the solver sees it: [`TreadOde`] is a [`crate::solver::OdeSystem`], and
//! so are its variational equations ([`Variational`], [`SectionVariational`]) that shooting
//! integrates for the monodromy matrix (MODEL.md#shooting). The model owns these
//! impls, so the integrator stays generic and never names the tire.

use super::TreadOde;
use crate::solver::OdeSystem;

impl OdeSystem<3> for TreadOde {
    #[inline(always)]
    fn rhs(&self, x: &[f64; 3]) -> [f64; 3] {
        TreadOde::rhs(self, x)
    }
}

/// The tread ODE together with its variational equations dΦ/dt = J(x) Φ (Φ stored column by
/// column after x), whose value after one period is the monodromy matrix. Shooting needs only
/// two of its columns and integrates [`SectionVariational`].
pub struct Variational<'a>(pub &'a TreadOde);

impl OdeSystem<12> for Variational<'_> {
    #[inline(always)]
    fn rhs(&self, s: &[f64; 12]) -> [f64; 12] {
        let x = [s[0], s[1], s[2]];
        let (f, j) = self.0.rhs_and_jacobian(&x);
        let mut out = [0.0; 12];
        out[..3].copy_from_slice(&f);
        // J has the row (0, 0, 1) of dy/dt = v and zeros at (0, 1): those products are skipped.
        let (j00, j02) = (j[(0, 0)], j[(0, 2)]);
        let (j20, j21, j22) = (j[(2, 0)], j[(2, 1)], j[(2, 2)]);
        for col in 0..3 {
            let [p0, p1, p2] = [s[3 + 3 * col], s[4 + 3 * col], s[5 + 3 * col]];
            out[3 + 3 * col] = j00 * p0 + j02 * p2;
            out[4 + 3 * col] = p2;
            out[5 + 3 * col] = j20 * p0 + j21 * p1 + j22 * p2;
        }
        out
    }
}

/// The tread ODE with the variational equations of the two start directions that stay on the
/// section y = y_eq, z and v: Φ's first and third columns after x (states 3–5: ∂x/∂z0,
/// states 6–8: ∂x/∂v0). The return map's derivative and the Floquet multipliers need no other
/// column (the section fixes y), and each column evolves on its own, so these are exactly the
/// columns of [`Variational`] for three quarters of its work. The sensitivities carry no
/// tolerance (infinite atol), and the error norm averages over the 12 components of the full
/// system, so the steps are the full system's steps.
pub struct SectionVariational<'a>(pub &'a TreadOde);

impl OdeSystem<9> for SectionVariational<'_> {
    const ERROR_NORM_COMPONENTS: usize = 12;

    #[inline(always)]
    fn rhs(&self, s: &[f64; 9]) -> [f64; 9] {
        let x = [s[0], s[1], s[2]];
        let (f, j) = self.0.rhs_and_jacobian(&x);
        let (j00, j02) = (j[(0, 0)], j[(0, 2)]);
        let (j20, j21, j22) = (j[(2, 0)], j[(2, 1)], j[(2, 2)]);
        let column =
            |p0: f64, p1: f64, p2: f64| [j00 * p0 + j02 * p2, p2, j20 * p0 + j21 * p1 + j22 * p2];
        let [a0, a1, a2] = column(s[3], s[4], s[5]);
        let [b0, b1, b2] = column(s[6], s[7], s[8]);
        [f[0], f[1], f[2], a0, a1, a2, b0, b1, b2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Variant, Wheel, WheelModel};
    use crate::params::Params;
    use crate::solver::{integrate, Control, SolverOptions};

    /// The section system takes the full system's steps and gives its z and v columns bit for
    /// bit (the documented equivalence shooting relies on).
    #[test]
    fn section_variational_is_the_full_systems_z_and_v_columns() {
        for (wheel, variant) in [
            (Wheel::Follower, Variant::Paper),
            (Wheel::Driving, Variant::SlidingShare),
        ] {
            let ode = WheelModel::build(&Params::default(), wheel, variant)
                .unwrap()
                .ode;
            let eq = ode.equilibrium();
            let x = [eq[0] * 1.05, eq[1], 0.3 * ode.u_mps.abs()];
            let period = 1.0 / ode.linear_stability().eig_freq_hz;
            let atol_x = [
                1e-9 * eq[0].abs(),
                1e-9 * eq[1].abs(),
                1e-9 * ode.u_mps.abs(),
            ];
            let opts = |n: usize| {
                let mut atol = vec![f64::INFINITY; n];
                atol[..3].copy_from_slice(&atol_x);
                (1e-9, atol, period / 8.0)
            };
            let (rtol, atol12, h_max) = opts(12);
            let full = integrate(
                &Variational(&ode),
                0.0,
                [
                    x[0], x[1], x[2], 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0,
                ],
                3.0 * period,
                &SolverOptions {
                    rtol,
                    atol: atol12.try_into().unwrap(),
                    h_max,
                    h0: Some(period / 40.0),
                    max_steps: 100_000,
                },
                |_| Control::Continue,
            )
            .unwrap();
            let (_, atol9, _) = opts(9);
            let section = integrate(
                &SectionVariational(&ode),
                0.0,
                [x[0], x[1], x[2], 1.0, 0.0, 0.0, 0.0, 0.0, 1.0],
                3.0 * period,
                &SolverOptions {
                    rtol,
                    atol: atol9.try_into().unwrap(),
                    h_max,
                    h0: Some(period / 40.0),
                    max_steps: 100_000,
                },
                |_| Control::Continue,
            )
            .unwrap();
            assert_eq!(full.rhs_evals, section.rhs_evals);
            let f = full.x;
            let expected = [f[0], f[1], f[2], f[3], f[4], f[5], f[9], f[10], f[11]];
            assert_eq!(section.x, expected, "{wheel} {variant}");
        }
    }
}
