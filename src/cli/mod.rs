//! The command line: one module per subcommand, all errors mapped to exit code 2.

pub mod analyze;
pub mod batch;
pub mod bifurcation;
pub mod calibrate;
pub mod chart;
pub mod classify;
pub mod common;
pub mod cycle;
pub mod explore;
pub mod optimize;
pub mod params;
pub mod reproduce;
pub mod simulate;
pub mod validate;
pub mod wear;
