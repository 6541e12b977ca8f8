//! The Poincaré section y = y_eq crossed upwards (v > 0), shared by shooting and by the
//! long-integration classifiers. State index 1 is y in every system used here.

use crate::numeric::brent;
use crate::solver::{integrate, Control, OdeSystem, SolverOptions, Step};

/// Locates an upward crossing of y = `y_sec` inside an accepted step, if there is one.
#[inline]
pub fn crossing_in_step<const N: usize>(step: &Step<'_, N>, y_sec: f64) -> Option<(f64, [f64; N])> {
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

/// One return to the section: time of flight, state there, and the RHS evaluations spent.
pub struct Return<const N: usize> {
    pub period_s: f64,
    pub state: [f64; N],
    pub rhs_evals: usize,
    pub h_last: f64,
}

/// Integrates from a point on the section until the next upward crossing after `t_min`.
pub fn first_return<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    start: [f64; N],
    y_sec: f64,
    t_min: f64,
    t_max: f64,
    opts: &SolverOptions<N>,
) -> Result<Return<N>, String> {
    let mut hit = None;
    let out = integrate(sys, 0.0, start, t_max, opts, |step| {
        if step.t1 > t_min {
            if let Some(c) = crossing_in_step(step, y_sec) {
                if c.0 > t_min {
                    hit = Some(c);
                    return Control::Stop;
                }
            }
        }
        Control::Continue
    })
    .map_err(|e| e.to_string())?;
    match hit {
        Some((t, x)) => Ok(Return {
            period_s: t,
            state: x,
            rhs_evals: out.rhs_evals,
            h_last: out.h_last,
        }),
        None => Err(format!(
            "no return to the section within {t_max:.4} s (motion not oscillatory)"
        )),
    }
}
