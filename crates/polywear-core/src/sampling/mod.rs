//! Sampling stage: turns (study, seed, sample index) into a parameter set. Every value is a pure
//! function of those three, so results never depend on thread count, chunking or sharding.
//!
//! Random bits come from `rand`'s ChaCha12 generator, addressed by stream (sample index) and word
//! position (axis) ([`rng`]). The random design draws each value directly with `rand_distr`
//! ([`distribution::Distribution::draw`]); the stratified designs give points in the unit cube
//! ([`design`]) that distributions map to parameter values by their inverse CDF
//! ([`distribution`]), which keeps the stratification of Latin hypercube and Sobol designs
//! (rejection samplers such as `rand_distr`'s would not).

pub mod alias;
pub mod design;
pub mod distribution;
pub mod rng;
pub mod sobol;

pub use rng::{bits, uniform, uniform01, Streams, RNG_NAME};
