//! polywear's lab (not published): what serves diagnostics and checks of the wear stage but no
//! shipped answer. The library crates keep what the shipped answer and the long-term loop use;
//! this crate holds the loop's accelerated oracle ([`accelerated`], the same wear by another
//! road, MODEL.md#the-long-term-loop), the forced orbit by Newton ([`forced_orbit`], brute
//! force's locked state), the probes under `examples/` that measured the estimator's nodes,
//! tongues and locks, and the tests that hold the oracle and the orbit against the loop.
//! Dated notes of what the probes found are under `docs/lab/`.

pub mod accelerated;
pub mod forced_orbit;
