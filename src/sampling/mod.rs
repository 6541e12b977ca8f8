//! Sampling stage: turns (study, seed, sample index) into a parameter set. Every value is a pure
//! function of those three, so results never depend on thread count, chunking or sharding.
//!
//! Designs give points in the unit cube ([`design`]); distributions map each coordinate to a
//! parameter value by their inverse CDF ([`distribution`]), which keeps the stratification of
//! Latin hypercube and Sobol designs (rejection samplers such as `rand_distr`'s would not).

pub mod design;
pub mod distribution;
pub mod rng;
pub mod sobol;

pub use rng::{bits, uniform, uniform01};
