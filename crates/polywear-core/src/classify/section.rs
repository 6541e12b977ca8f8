//! The Poincaré section y = y_eq crossed upwards (v > 0), shared by shooting and by the
//! long-integration classifiers. State index 1 is y in every system used here.

use super::budget::Meter;
use super::ClassifyError;
use crate::numeric::brent;
use crate::solver::{
    integrate_with, Control, IntegrationError, Method, OdeSystem, SolverOptions, Step,
};

/// Locates an upward crossing of y = `y_sec` inside an accepted step, if there is one.
#[inline]
pub(crate) fn crossing_in_step<const N: usize>(
    step: &Step<'_, N>,
    y_sec: f64,
) -> Option<(f64, [f64; N])> {
    if !(step.x0[1] < y_sec && step.x1[1] >= y_sec) {
        return None;
    }
    let t = brent(
        |t| step.interpolate(t)[1] - y_sec,
        step.t0,
        step.t1,
        1e-15 * step.t1.abs().max(1e-12),
        100,
    )
    .unwrap_or(step.t1);
    Some((t, step.interpolate(t)))
}

/// One return to the section: time of flight and the state there (the RHS evaluations spent
/// are charged to the meter).
pub(crate) struct Return<const N: usize> {
    /// Time of flight to the section \[s\].
    pub period_s: f64,
    /// The state on the section.
    pub state: [f64; N],
}

/// Runs `method` under the wheel's budget: the step limit shrinks to the evaluations left,
/// the step callback stops once the wall time is spent, and the work is charged to `meter`
/// (also when the integration fails).
pub(crate) fn metered<const N: usize, S: OdeSystem<N>>(
    method: Method,
    sys: &S,
    start: [f64; N],
    t_end: f64,
    opts: &SolverOptions<N>,
    meter: &Meter,
    mut on_step: impl FnMut(&Step<'_, N>) -> Control,
) -> Result<crate::solver::Outcome<N>, ClassifyError> {
    let opts = opts.with_max_steps(meter.max_steps(opts.max_steps, method.evals_per_step()));
    let out = integrate_with(method, sys, 0.0, start, t_end, &opts, |step| {
        if meter.out_of_time() {
            return Control::Stop;
        }
        on_step(step)
    });
    match out {
        Ok(o) => {
            meter.charge(o.rhs_evals);
            Ok(o)
        }
        Err(e) => {
            if let IntegrationError::TooManySteps { steps, .. } = e {
                meter.charge(method.evals_per_step() * steps + 1);
            }
            Err(e.into())
        }
    }
}

/// Integrates from a point on the section until the next upward crossing after `t_min`.
/// `observe(step, t_hi)` sees every accepted step up to the return, `t_hi` being the end of the
/// part of the step that belongs to the orbit (the return time in the last step).
#[allow(clippy::too_many_arguments)]
pub(crate) fn first_return<const N: usize, S: OdeSystem<N>>(
    method: Method,
    sys: &S,
    start: [f64; N],
    y_sec: f64,
    (t_min, t_max): (f64, f64),
    opts: &SolverOptions<N>,
    meter: &Meter,
    mut observe: impl FnMut(&Step<'_, N>, f64),
) -> Result<Return<N>, ClassifyError> {
    let mut hit = None;
    metered(method, sys, start, t_max, opts, meter, |step| {
        if step.t1 > t_min {
            if let Some(c) = crossing_in_step(step, y_sec) {
                if c.0 > t_min {
                    observe(step, c.0);
                    hit = Some(c);
                    return Control::Stop;
                }
            }
        }
        observe(step, step.t1);
        Control::Continue
    })?;
    match hit {
        Some((t, x)) => Ok(Return {
            period_s: t,
            state: x,
        }),
        None => Err(ClassifyError::NoReturn { t_max_s: t_max }),
    }
}
