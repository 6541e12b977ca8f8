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

/// Shooting's routes report their reasons as text; a section return's error joins them there.
impl From<ClassifyError> for String {
    fn from(e: ClassifyError) -> Self {
        e.to_string()
    }
}
