//! The tread's response to a worn profile (MODEL.md#the-per-sample-estimator): the response to
//! ε at a state and at the equilibrium as poles ([`transfer`]), the cycle's response through its
//! Floquet modes and harmonic balance ([`periodic`]), exact means of poles over a normal speed
//! spread ([`spread`]) and the speeds driven as legs ([`legs`]), and the forced Hopf normal
//! form ([`normal_form`]). Built on [`super::physics`]; used by the estimator and the loop.

pub mod legs;
pub mod normal_form;
pub mod periodic;
pub mod spread;
pub mod transfer;
