//! The adaptive step loop that DOPRI5 and DOP853 share (Hairer, Nørsett, Wanner, "Solving ODEs
//! I", Sec. II.4 and the codes DOPRI5/DOP853): step-size limits, the last step landing on
//! `t_end`, retries after a non-finite state, the callback after each accepted step and the
//! outcome. What differs between the two pairs (stages, error estimate, step-size factor, dense
//! output) is an [`EmbeddedPair`].

use super::types::{initial_step, Dense};
use super::{Control, IntegrationError, OdeSystem, Outcome, SolverOptions, Step};

/// One embedded Runge–Kutta pair as the step loop sees it.
pub(super) trait EmbeddedPair<const N: usize> {
    /// Order of the propagated solution (for the first-step guess).
    const ORDER: i32;

    /// The pair's stage storage, given f at the start.
    fn start(f0: [f64; N]) -> Self;

    /// f at the current state (the first stage of the next step).
    fn f0(&self) -> &[f64; N];

    /// Tries a step of size `h` from `x`: the new state, its error norm (≤ 1 accepts) and the
    /// evaluations spent.
    fn try_step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        x: &[f64; N],
        h: f64,
        opts: &SolverOptions<N>,
    ) -> ([f64; N], f64, usize);

    /// h is divided by this after an accepted step with error norm `err`.
    fn accepted_factor(&mut self, err: f64) -> f64;

    /// h is divided by this after a rejected step with error norm `err`.
    fn rejected_factor(&self, err: f64) -> f64;

    /// Completes an accepted step from `x` to `x_new`: its dense output, and f at `x_new` as the
    /// next step's first stage. Returns the evaluations spent.
    fn finish_step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        x: &[f64; N],
        x_new: &[f64; N],
        h: f64,
    ) -> usize;

    /// The dense output of the step [`EmbeddedPair::finish_step`] completed.
    fn dense(&self) -> Dense<'_, N>;
}

/// Integrates `sys` from (t0, x0) to `t_end` with the pair `P`, calling `on_step` after every
/// accepted step.
#[inline(always)]
pub(super) fn drive<const N: usize, S: OdeSystem<N>, P: EmbeddedPair<N>>(
    sys: &S,
    t0: f64,
    x0: [f64; N],
    t_end: f64,
    opts: &SolverOptions<N>,
    mut on_step: impl FnMut(&Step<'_, N>) -> Control,
) -> Result<Outcome<N>, IntegrationError> {
    let mut t = t0;
    let mut x = x0;
    let mut pair = P::start(sys.rhs(&x));
    let mut evals = 1;
    let (mut h, extra) = match opts.h0 {
        Some(h) => (h.min(opts.h_max), 0),
        None => initial_step(sys, &x, pair.f0(), opts, P::ORDER),
    };
    evals += extra;
    let mut accepted = 0;
    let mut rejected = 0;
    let mut last_rejected = false;
    let h_min_rel = 16.0 * f64::EPSILON;
    let outcome = |t, x, accepted, rejected, evals, stopped, h_last| Outcome {
        t,
        x,
        accepted_steps: accepted,
        rejected_steps: rejected,
        rhs_evals: evals,
        stopped,
        h_last,
    };
    while t < t_end {
        if accepted + rejected >= opts.max_steps {
            return Err(IntegrationError::TooManySteps {
                t,
                steps: accepted + rejected,
            });
        }
        if h < h_min_rel * t.abs().max(1e-300) {
            return Err(IntegrationError::StepSizeUnderflow { t });
        }
        let last = t + 1.01 * h >= t_end;
        if last {
            h = t_end - t;
        }
        let (x_new, err, spent) = pair.try_step(sys, &x, h, opts);
        evals += spent;
        if !err.is_finite() || x_new.iter().any(|v| !v.is_finite()) {
            // Retry with a much smaller step before declaring the state broken.
            if h > h_min_rel * t.abs().max(1e-12) * 1e3 {
                h *= 0.1;
                rejected += 1;
                last_rejected = true;
                continue;
            }
            return Err(IntegrationError::NonFinite { t });
        }
        if err <= 1.0 {
            let mut h_new = (h / pair.accepted_factor(err)).min(opts.h_max);
            if last_rejected {
                h_new = h_new.min(h);
            }
            evals += pair.finish_step(sys, &x, &x_new, h);
            let t_new = if last { t_end } else { t + h };
            accepted += 1;
            let control = on_step(&Step {
                t0: t,
                t1: t_new,
                x0: &x,
                x1: &x_new,
                dense: pair.dense(),
            });
            t = t_new;
            x = x_new;
            h = h_new;
            last_rejected = false;
            if control == Control::Stop {
                return Ok(outcome(t, x, accepted, rejected, evals, true, h));
            }
        } else {
            h /= pair.rejected_factor(err);
            rejected += 1;
            last_rejected = true;
        }
    }
    Ok(outcome(t, x, accepted, rejected, evals, false, h))
}
