//! Why a classifier route gives no verdict: the integration failed, the motion never returned to
//! the section, or the settled trajectory holds no cycle to measure. The message becomes the
//! `reason` of a `failed` verdict (or the next route is tried), so it says what was seen.

use crate::solver::IntegrationError;

/// A classifier route that found no verdict, with what it saw.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClassifyError {
    /// The integrator gave up (step size underflow, non-finite state, step limit).
    #[error("{0}")]
    Integration(IntegrationError),
    /// No upward crossing of the section within the time searched.
    #[error("no return to the section within {t_max_s:.4} s (motion not oscillatory)")]
    NoReturn {
        /// The longest time of flight searched \[s\].
        t_max_s: f64,
    },
    /// The trajectory settled, but its last two windows show no oscillation.
    #[error(
        "the settled trajectory shows no cycle (amplitude of v {prev_mps:.3e} then {last_mps:.3e} m/s)"
    )]
    NoSettledCycle {
        /// Amplitude of v over the window before the last \[m/s\].
        prev_mps: f64,
        /// Amplitude of v over the last window \[m/s\].
        last_mps: f64,
    },
    /// The cycle's amplitude grows at least as fast as the linear rate: no supercritical
    /// cycle to extrapolate to.
    #[error(
        "the cycle's amplitude still grows ({drift_per_s:.3e} 1/s against Re λ = {re_per_s:.3e} 1/s): no supercritical cycle to extrapolate to"
    )]
    StillGrowing {
        /// Growth rate of the amplitude between the windows \[1/s\].
        drift_per_s: f64,
        /// Re λ of the equilibrium \[1/s\].
        re_per_s: f64,
    },
}

impl From<IntegrationError> for ClassifyError {
    fn from(e: IntegrationError) -> Self {
        ClassifyError::Integration(e)
    }
}

/// Why shooting found no periodic orbit from its guess (the caller then tries another guess
/// or the envelope; the message may end up as a `failed` row's reason).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShootingError {
    /// A return to the section failed.
    #[error("{0}")]
    Return(#[from] ClassifyError),
    /// The return map's derivative minus the identity is singular: no Newton step.
    #[error("shooting: singular return-map Jacobian")]
    SingularJacobian,
    /// Newton's orbit shrank onto the equilibrium's noise floor.
    #[error("shooting: Newton fell back onto the equilibrium")]
    FellOntoEquilibrium,
    /// Newton's steps were damped this many times in a row: no cycle near the guess.
    #[error("shooting: {0} damped Newton steps in a row (no cycle near the guess)")]
    DampedSteps(usize),
    /// Newton did not converge in this many iterations.
    #[error("shooting: Newton did not converge in {0} iterations")]
    NoConvergence(usize),
    /// The scalar return map along the Hopf direction gave a non-finite value.
    #[error("shooting: the return map along the Hopf direction is not finite")]
    MapNotFinite,
    /// The amplitude guess grew past 50 U without bracketing a cycle.
    #[error("shooting: amplitude grows beyond 50 U; no bounded cycle bracketed")]
    Unbounded,
    /// Small oscillations decayed although the equilibrium is unstable.
    #[error("shooting: small oscillations decay although the equilibrium is unstable")]
    DecayWhileUnstable,
    /// No amplitude guess in this many evaluations of the return map.
    #[error("shooting: no amplitude guess in {0} evaluations of the return map")]
    NoGuess(usize),
}
