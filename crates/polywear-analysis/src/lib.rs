//! polywear's analysis and figures: an explore output read lazily with polars into occurrence,
//! driving against follower, risk maps, severity, sensitivity and the fleet's exposure
//! ([`analysis::run`] → [`analysis::Analysis`] → [`render::write`]); every figure and report
//! ([`plot`], [`figures`]); the paper's analyses ([`reproduce`]). A run's files into its report
//! in one call ([`run_report`]), and an explore run with its band and closing report in one
//! call ([`explore_run`]), as the command line and a Python layer both run it.

#![warn(missing_docs)]

pub mod analysis;
pub mod explore_run;
pub mod figures;
pub mod plot;
pub mod render;
pub mod reproduce;
pub mod run_report;
