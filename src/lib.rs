//! polywear: how likely a tire is to develop polygonal wear through lateral self-excited
//! vibration of the tread (Zuo, Duan, Li 2014).
//!
//! This crate is the front door of a workspace laid along the data flow
//! (docs/book/src/maintainers/architecture.md):
//!
//! | crate | stages |
//! |---|---|
//! | `polywear-core` | [`params`], [`sampling`], [`model`], [`solver`], [`continuation`], [`classify`], [`wear`], [`evaluate`], [`ensemble`], [`records`] |
//! | `polywear-study` | [`study`], [`explore`], [`parquet_out`], [`cycle`], [`calibrate`], [`optimize`], [`chart`], [`bifurcation`], [`validation`] |
//! | `polywear-analysis` | [`analysis`], [`render`], [`plot`], [`figures`], [`reproduce`] |
//! | `polywear-cli` | the `polywear` program |
//!
//! [`prelude`] holds what a user of the engine needs for one point, a study and its analysis.
//!
//! One operating point, both wheels, through the evaluator:
//!
//! ```
//! use polywear::prelude::*;
//!
//! let params = Params::default();
//! let options = ClassifierOptions::default();
//! let problem = PointProblem::new(params, &[Variant::DEFAULT], &options);
//! let solution = solve(&problem);
//! for wheel in &solution.wheels {
//!     let r = &wheel.record;
//!     assert_eq!(r.speed_kmh, params.speed_kmh);
//!     println!("{} {}: {}", r.variant, r.wheel, r.class);
//!     assert!(r.class != Class::Failed, "{}", r.reason);
//! }
//! assert_eq!(solution.wheels.len(), 2);
//! ```

#![warn(missing_docs)]

pub use polywear_analysis::{analysis, figures, plot, render, reproduce};
pub use polywear_core::{
    classify, columns, continuation, ensemble, evaluate, model, numeric, params, records, sampling,
    solver, text_enum, wear, wording,
};
pub use polywear_study::{
    bifurcation, calibrate, chart, cycle, explore, key_value, operating_points, optimize,
    output_dir, parquet_out, safe_read, safe_write, stats, study, table_input, toml_input,
    trajectory, validation,
};

/// What a user of the engine needs: one point (problem → solve → solution), a study (in memory
/// or to Parquet) and its analysis.
pub mod prelude {
    pub use polywear_core::classify::{Class, ClassifierOptions, WheelVerdict};
    pub use polywear_core::evaluate::{solve, PointProblem, PointSolution};
    pub use polywear_core::model::{Variant, Wheel, WheelModel};
    pub use polywear_core::params::{ParamId, Params};
    pub use polywear_core::records::WheelRecord;
}
