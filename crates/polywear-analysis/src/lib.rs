//! polywear's analysis and figures: an explore output read lazily with polars into occurrence,
//! driving against follower, risk maps, severity, sensitivity and the fleet's exposure
//! ([`analysis::run`] → [`analysis::Analysis`] → [`render::write`]); every figure and report
//! ([`plot`], [`figures`]); the paper's analyses ([`reproduce`]).

#![warn(missing_docs)]

pub mod analysis;
pub mod figures;
pub mod plot;
pub mod render;
pub mod reproduce;
