//! Why the wear stage has no figure for a wheel, or no calibration for a run.

use crate::classify::{Class, ClassifyError};

/// A wear figure that could not be computed; the estimator turns it into NaN columns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WearError {
    /// The integration along the classifier's cycle failed.
    #[error("integrating the cycle for the wear stage: {0}")]
    Cycle(#[from] ClassifyError),
    /// The verdict carries no cycle to integrate (a vibrating class without a section point).
    #[error("the verdict has no cycle to integrate (section velocity {section_v_mps:.3e} m/s)")]
    NoCycle {
        /// The verdict's section velocity \[m/s\].
        section_v_mps: f64,
    },
    /// The integrated period does not close on itself: the cycle is not the classifier's.
    #[error("the cycle does not close over one period (relative miss {miss:.2e})")]
    NotClosed {
        /// |x(T) − x(0)| relative to the state scales.
        miss: f64,
    },
    /// The cycle's monodromy matrix has no basis of eigenvectors (a defective or degenerate
    /// cycle): its Floquet modes, and so its response, are not defined.
    #[error("the cycle's monodromy matrix has no basis of Floquet modes")]
    NoFloquetBasis,
    /// The equilibrium's Jacobian has no basis of eigenvectors.
    #[error("the equilibrium's Jacobian has no basis of eigenvectors")]
    NoEigenbasis,
    /// The long-term loop or the accelerated oracle could not integrate a window.
    #[error("the wear loop at {speed_kmh} km/h after {distance_km:.0} km: {reason}")]
    Loop {
        /// The speed of the window \[km/h\].
        speed_kmh: f64,
        /// The distance run when it failed \[km\].
        distance_km: f64,
        /// What failed.
        reason: String,
    },
    /// The wheel has no tread ODE, or no verdict to work from.
    #[error("no wear figures without a model: {0}")]
    NoModel(String),
    /// The reference follower of the calibration has no verdict to calibrate on.
    #[error("the wear calibration's reference point (follower, {speed_kmh} km/h, {toe_deg} deg, {load_n} N, {pressure_kpa} kPa) is {class}: {reason}")]
    Reference {
        /// Its class.
        class: Class,
        /// Why.
        reason: String,
        /// Its speed \[km/h\].
        speed_kmh: f64,
        /// Its toe-in \[deg\].
        toe_deg: f64,
        /// Its load \[N\].
        load_n: f64,
        /// Its pressure \[kPa\].
        pressure_kpa: f64,
    },
}
