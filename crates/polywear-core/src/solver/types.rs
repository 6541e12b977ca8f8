//! The types both Runge–Kutta pairs share: the options of one integration, what the step
//! callback sees and returns, how an integration ends, and the starting-step guess.

use super::OdeSystem;

/// Tolerances and limits of one integration.
#[derive(Debug, Clone, Copy)]
pub struct SolverOptions<const N: usize> {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance per state component (the states have very different scales).
    pub atol: [f64; N],
    /// Largest step \[s\].
    pub h_max: f64,
    /// First step \[s\]; chosen automatically when `None`.
    pub h0: Option<f64>,
    /// Accepted plus rejected steps before giving up.
    pub max_steps: usize,
}

/// What the step callback wants next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on integrating.
    Continue,
    /// Stop after this step (the outcome then holds the step's end).
    Stop,
}

/// Why an integration gave up.
#[derive(Debug, Clone, PartialEq)]
pub enum IntegrationError {
    /// The step size fell below what double precision resolves.
    StepSizeUnderflow {
        /// Where \[s\].
        t: f64,
    },
    /// The state became NaN or infinite.
    NonFinite {
        /// Where \[s\].
        t: f64,
    },
    /// The step limit was reached.
    TooManySteps {
        /// Where \[s\].
        t: f64,
        /// The limit.
        steps: usize,
    },
}

impl std::fmt::Display for IntegrationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            IntegrationError::StepSizeUnderflow { t } => {
                write!(f, "step size underflow at t = {t:.6} s")
            }
            IntegrationError::NonFinite { t } => write!(f, "non-finite state at t = {t:.6} s"),
            IntegrationError::TooManySteps { t, steps } => {
                write!(f, "step limit {steps} reached at t = {t:.6} s")
            }
        }
    }
}

/// One accepted step, with the dense-output polynomial over it.
pub struct Step<'a, const N: usize> {
    /// Start of the step \[s\].
    pub t0: f64,
    /// End of the step \[s\].
    pub t1: f64,
    /// State at `t0`.
    pub x0: &'a [f64; N],
    /// State at `t1`.
    pub x1: &'a [f64; N],
    pub(super) dense: Dense<'a, N>,
}

/// The dense-output polynomial of a step, in the integrator's own form.
pub(super) enum Dense<'a, const N: usize> {
    /// DOPRI5's 4th-order polynomial (Hairer's CONTD5 coefficients, x0 included).
    Dopri5(&'a [[f64; N]; 5]),
    /// DOP853's 7th-order polynomial (Hairer's CONTD8 coefficients, x0 excluded).
    Dop853(&'a [[f64; N]; 7]),
}

impl<const N: usize> Step<'_, N> {
    /// Component `i` at the relative position `theta` = (t − t0)/(t1 − t0).
    #[inline(always)]
    fn component(&self, theta: f64, i: usize) -> f64 {
        let theta1 = 1.0 - theta;
        match self.dense {
            Dense::Dopri5(c) => {
                c[0][i]
                    + theta * (c[1][i] + theta1 * (c[2][i] + theta * (c[3][i] + theta1 * c[4][i])))
            }
            Dense::Dop853(c) => {
                let inner = c[4][i] + theta1 * (c[5][i] + theta * c[6][i]);
                self.x0[i]
                    + theta
                        * (c[0][i]
                            + theta1
                                * (c[1][i]
                                    + theta * (c[2][i] + theta1 * (c[3][i] + theta * inner))))
            }
        }
    }

    /// State at any t in [t0, t1] (4th-order accurate for DOPRI5, 7th-order for DOP853).
    #[inline]
    pub fn interpolate(&self, t: f64) -> [f64; N] {
        let theta = (t - self.t0) / (self.t1 - self.t0);
        std::array::from_fn(|i| self.component(theta, i))
    }

    /// The components `idx` of the state at t in [t0, t1]: the same values as
    /// [`Step::interpolate`] gives them, for callers that read a few of many components.
    #[inline]
    pub fn interpolate_components<const K: usize>(&self, t: f64, idx: [usize; K]) -> [f64; K] {
        let theta = (t - self.t0) / (self.t1 - self.t0);
        idx.map(|i| self.component(theta, i))
    }
}

/// An accepted step kept after the integration: its ends and its dense-output polynomial,
/// owned ([`Step::to_dense`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DenseStep<const N: usize> {
    /// Start of the step \[s\].
    pub t0: f64,
    /// End of the step \[s\].
    pub t1: f64,
    x0: [f64; N],
    coefficients: DenseCoefficients<N>,
}

#[derive(Debug, Clone, PartialEq)]
enum DenseCoefficients<const N: usize> {
    Dopri5([[f64; N]; 5]),
    Dop853([[f64; N]; 7]),
}

impl<const N: usize> Step<'_, N> {
    /// The step with its dense output, owned.
    pub fn to_dense(&self) -> DenseStep<N> {
        DenseStep {
            t0: self.t0,
            t1: self.t1,
            x0: *self.x0,
            coefficients: match self.dense {
                Dense::Dopri5(c) => DenseCoefficients::Dopri5(*c),
                Dense::Dop853(c) => DenseCoefficients::Dop853(*c),
            },
        }
    }
}

impl<const N: usize> DenseStep<N> {
    /// The state at `t` through the step's polynomial, as [`Step::interpolate`] gives it inside
    /// [t0, t1] (outside, the polynomial extrapolated).
    pub fn interpolate(&self, t: f64) -> [f64; N] {
        let step = Step {
            t0: self.t0,
            t1: self.t1,
            x0: &self.x0,
            // The polynomial does not read the end.
            x1: &self.x0,
            dense: match &self.coefficients {
                DenseCoefficients::Dopri5(c) => Dense::Dopri5(c),
                DenseCoefficients::Dop853(c) => Dense::Dop853(c),
            },
        };
        step.interpolate(t)
    }
}

/// Where an integration ended and what it cost.
#[derive(Debug, Clone, Copy)]
pub struct Outcome<const N: usize> {
    /// Time reached \[s\].
    pub t: f64,
    /// State there.
    pub x: [f64; N],
    /// Steps accepted.
    pub accepted_steps: usize,
    /// Steps rejected by the error control.
    pub rejected_steps: usize,
    /// Right-hand-side evaluations.
    pub rhs_evals: usize,
    /// True when the callback stopped the integration before `t_end`.
    pub stopped: bool,
    /// Last step size tried, a good first step for a continuation.
    pub h_last: f64,
}

#[inline(always)]
pub(super) fn axpy<const N: usize>(x: &[f64; N], h: f64, terms: &[(f64, &[f64; N])]) -> [f64; N] {
    std::array::from_fn(|i| {
        let mut s = 0.0;
        for (c, k) in terms {
            s += c * k[i];
        }
        x[i] + h * s
    })
}

#[inline(always)]
pub(super) fn error_norm<const N: usize>(
    err: &[f64; N],
    x0: &[f64; N],
    x1: &[f64; N],
    opts: &SolverOptions<N>,
    components: usize,
) -> f64 {
    let mut s = 0.0;
    for i in 0..N {
        let sc = opts.atol[i] + opts.rtol * x0[i].abs().max(x1[i].abs());
        let r = err[i] / sc;
        s += r * r;
    }
    (s / components as f64).sqrt()
}

/// Hairer's starting step guess for a method of order `order`.
pub(super) fn initial_step<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    x0: &[f64; N],
    f0: &[f64; N],
    opts: &SolverOptions<N>,
    order: i32,
) -> (f64, usize) {
    let sc: [f64; N] = std::array::from_fn(|i| opts.atol[i] + opts.rtol * x0[i].abs());
    let norm = |v: &[f64; N]| {
        (v.iter().zip(&sc).map(|(a, s)| (a / s).powi(2)).sum::<f64>()
            / S::ERROR_NORM_COMPONENTS as f64)
            .sqrt()
    };
    let d0 = norm(x0);
    let d1 = norm(f0);
    let mut h = if d0 < 1e-10 || d1 < 1e-10 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    h = h.min(opts.h_max);
    let x1 = axpy(x0, h, &[(1.0, f0)]);
    let f1 = sys.rhs(&x1);
    let df: [f64; N] = std::array::from_fn(|i| f1[i] - f0[i]);
    let d2 = norm(&df) / h;
    let h1 = if d1.max(d2) <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / d1.max(d2)).powf(1.0 / order as f64)
    };
    ((100.0 * h).min(h1).min(opts.h_max), 1)
}
