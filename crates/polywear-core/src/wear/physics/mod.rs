//! The wear physics (MODEL.md#step-10-wear-law, #step-11-wear-zone, #step-12-feedback): what
//! the friction power wears and where, the driving wheel's slip power, the profile's action back
//! on the friction levels, the abradability γ, the calibrated constants, and one sampled period
//! of a limit cycle as the wear stage reads it. Nothing here knows the estimator or the loop.

pub mod calibration;
pub mod cycle;
pub mod feedback;
pub mod fitted;
pub mod law;
pub mod slip;
pub mod zone;
