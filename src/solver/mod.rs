//! Time integration: adaptive Dormand–Prince Runge–Kutta methods with error control and dense
//! output, on fixed-size state (no allocation per step): 5(4) with 4th-order dense output for
//! loose and moderate tolerances, 8(5,3) with 7th-order dense output for tight ones.
//!
//! The split follows DifferentialEquations.jl: an [`OdeSystem`] is the problem, [`integrate`] is
//! the solver, and the caller sees each accepted [`Step`] through a callback (for section
//! crossings, envelope tracking or recording), which decides whether to go on.

mod dop853;
mod dop853_tableau;
mod dopri5;
mod driver;
mod types;

pub use dop853::integrate as integrate_dop853;
pub use dopri5::integrate;
pub use types::{Control, IntegrationError, Outcome, SolverOptions, Step};

/// Which Runge–Kutta pair integrates: both give the same [`Step`]s to the callback.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// DOPRI5, 6 evaluations per step: the cheaper one at loose and moderate tolerances.
    Dopri5,
    /// DOP853, 15 evaluations per step with its dense output: the cheaper one at tight
    /// tolerances, where its 8th order takes a fraction of DOPRI5's steps.
    Dop853,
}

impl Method {
    /// Right-hand-side evaluations one step costs (for charging steps that were not finished).
    pub fn evals_per_step(self) -> usize {
        match self {
            Method::Dopri5 => 6,
            Method::Dop853 => 15,
        }
    }
}

/// [`integrate`] or [`integrate_dop853`], as `method` says.
pub fn integrate_with<const N: usize, S: OdeSystem<N>>(
    method: Method,
    sys: &S,
    t0: f64,
    x0: [f64; N],
    t_end: f64,
    opts: &SolverOptions<N>,
    on_step: impl FnMut(&Step<'_, N>) -> Control,
) -> Result<Outcome<N>, IntegrationError> {
    match method {
        Method::Dopri5 => integrate(sys, t0, x0, t_end, opts, on_step),
        Method::Dop853 => integrate_dop853(sys, t0, x0, t_end, opts, on_step),
    }
}

/// The step controls the classifier, the trajectories and shooting integrate with, named by what
/// they integrate over. The tolerances themselves (`rtol`, and `atol` from the state scales,
/// `classify::Scales::atol`) come from the caller, which chooses them by the accuracy its verdict
/// needs; these presets fix only the step bounds, which follow from the motion.
impl<const N: usize> SolverOptions<N> {
    /// A run from a disturbed equilibrium through its transient, whose period is not known
    /// beforehand (envelope tracking, brute force, trajectories): the step stays at or below
    /// 1 ms, under the tread vibration's period (about 3.7 ms at 270 Hz, MODEL.md#step-9-attractor),
    /// so the callback sees every section crossing and peak even where a slow transient would
    /// let the error estimate alone take longer steps.
    pub fn transient(rtol: f64, atol: [f64; N], max_steps: usize) -> Self {
        SolverOptions {
            rtol,
            atol,
            h_max: 1e-3,
            h0: None,
            max_steps,
        }
    }

    /// A run over whole periods of a known linear period `period_s` (a settled cycle's
    /// windows): at least eight steps per period keep the crossings and the dense output's
    /// extremes resolved; the first step is chosen automatically.
    pub fn per_period(rtol: f64, atol: [f64; N], period_s: f64, max_steps: usize) -> Self {
        SolverOptions {
            rtol,
            atol,
            h_max: period_s / 8.0,
            h0: None,
            max_steps,
        }
    }

    /// One return to the Poincaré section y = y_eq (shooting's return map, a few periods of
    /// `period_s`): eight steps per period at most, a first step of a fortieth of the period
    /// (the start lies on the section, where the automatic choice sees only the slow drift), and
    /// 200,000 steps, far more than a few returns take, as a guard against a run that never
    /// returns.
    pub fn section_return(rtol: f64, atol: [f64; N], period_s: f64) -> Self {
        SolverOptions {
            h0: Some(period_s / 40.0),
            ..Self::per_period(rtol, atol, period_s, 200_000)
        }
    }

    /// The same options with at most `max_steps` steps (a budget's share).
    pub fn with_max_steps(self, max_steps: usize) -> Self {
        SolverOptions { max_steps, ..self }
    }
}

/// An autonomous ODE dx/dt = f(x) on N states.
pub trait OdeSystem<const N: usize> {
    /// Components the error norm averages over (the root mean square of the scaled errors):
    /// N, unless a reduced system keeps the step control of the larger one it stands for.
    const ERROR_NORM_COMPONENTS: usize = N;

    /// dx/dt at state `x`.
    fn rhs(&self, x: &[f64; N]) -> [f64; N];
}

impl OdeSystem<3> for crate::model::TreadOde {
    #[inline(always)]
    fn rhs(&self, x: &[f64; 3]) -> [f64; 3] {
        crate::model::TreadOde::rhs(self, x)
    }
}

/// The tread ODE together with its variational equations dΦ/dt = J(x) Φ (Φ stored column by
/// column after x), whose value after one period is the monodromy matrix. Shooting needs only
/// two of its columns and integrates [`SectionVariational`].
pub struct Variational<'a>(pub &'a crate::model::TreadOde);

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
pub struct SectionVariational<'a>(pub &'a crate::model::TreadOde);

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

/// Uniform samples of a trajectory and how the integration ended.
pub type SampledTrajectory<const N: usize> =
    (Vec<(f64, [f64; N])>, Result<Outcome<N>, IntegrationError>);

/// Samples a trajectory on a uniform time grid through the dense output (for plots and files).
/// Returns the samples and the outcome (whose error, if any, ends the series early).
pub fn sample_uniform<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    x0: [f64; N],
    duration_s: f64,
    sample_dt_s: f64,
    opts: &SolverOptions<N>,
) -> SampledTrajectory<N> {
    let mut samples = vec![(0.0, x0)];
    let mut next = 1usize;
    let out = integrate(sys, 0.0, x0, duration_s, opts, |step| {
        while (next as f64) * sample_dt_s <= step.t1 {
            let t = next as f64 * sample_dt_s;
            samples.push((t, step.interpolate(t)));
            next += 1;
        }
        Control::Continue
    });
    (samples, out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Variant, Wheel, WheelModel};
    use crate::params::Params;

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
