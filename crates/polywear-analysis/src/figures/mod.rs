//! Figures of the compute stages: stability charts, drive cycles, optimisation, sweeps and time
//! series, drawn from their solutions.

pub mod bifurcation;
pub mod chart;
pub mod cycle;
pub mod optimize;
pub mod trajectory;
