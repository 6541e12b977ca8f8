//! The loop's first step (MODEL.md#the-long-term-loop): how many revolutions it integrates at
//! each leg before the first measured window, and the slowest usage it accepts for that.

use super::lock::WINDOW_REVS;
use crate::wear::response::legs::Leg;

/// Most seconds of tread time the loop's first step may integrate over all its legs \[s\]. The
/// first step integrates [`FIRST_STEP_REVS`] revolutions at every leg whatever the distance,
/// and below a few km/h the tread's integration takes 5,700 to 7,900 RHS evaluations per
/// second of tread time (measured at 0.3 and 1 km/h, where the step is set by the tread's
/// stiffness, not its period): an hour of it is about 30 million evaluations, a few seconds.
/// A slower usage is refused before any work instead of running for minutes
/// (MODEL.md#the-long-term-loop).
pub const MAX_FIRST_STEP_TREAD_S: f64 = 3600.0;

/// Revolutions integrated before a leg's first measured window (onto its cycle).
pub(crate) const FIRST_SKIP_REVS: usize = 30;

/// Revolutions the loop's first step integrates at each leg: the transient onto its cycle and
/// the longest measured window.
pub const FIRST_STEP_REVS: usize = FIRST_SKIP_REVS + WINDOW_REVS.1;

/// The tread time \[s\] the loop's first step integrates over `legs` on a wheel of rolling
/// radius `r_b_m`: [`FIRST_STEP_REVS`] revolutions of 2π r_B / V at each leg.
pub fn first_step_tread_s(legs: &[Leg], r_b_m: f64) -> f64 {
    legs.iter()
        .map(|l| FIRST_STEP_REVS as f64 * std::f64::consts::TAU * r_b_m / (l.speed_kmh / 3.6))
        .sum()
}

/// The slowest speed \[km/h\] a single-speed usage may cruise at within
/// [`MAX_FIRST_STEP_TREAD_S`] with `legs` legs of rolling radius `r_b_m`.
pub fn slowest_cruise_kmh(legs: usize, r_b_m: f64) -> f64 {
    3.6 * legs as f64 * FIRST_STEP_REVS as f64 * std::f64::consts::TAU * r_b_m
        / MAX_FIRST_STEP_TREAD_S
}
