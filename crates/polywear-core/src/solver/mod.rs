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
pub use types::{Control, DenseStep, IntegrationError, Outcome, SolverOptions, Step};

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
pub(crate) fn integrate_with<const N: usize, S: OdeSystem<N>>(
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

/// Uniform samples of a trajectory and how the integration ended.
pub(crate) type SampledTrajectory<const N: usize> =
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
