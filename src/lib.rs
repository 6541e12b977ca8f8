//! polywear: how likely a tire is to develop polygonal wear through lateral self-excited
//! vibration of the tread (Zuo, Duan, Li 2014).
//!
//! This crate is the front door of a workspace laid along the data flow
//! (docs/book/src/maintainers/architecture.md):
//!
//! | crate | stages |
//! |---|---|
//! | `polywear-core` | [`params`], `sampling`, [`model`], `solver`, `continuation`, [`classify`], `wear`, [`evaluate`], `ensemble`, [`records`] |
//! | `polywear-study` | [`study`], [`explore`], `parquet_out`, `cycle`, `calibrate`, `calibration_band`, `optimize`, `chart`, `bifurcation`, `validation` |
//! | `polywear-analysis` | [`analysis`], [`render`], `plot`, `figures`, `reproduce`, [`run_report`], [`explore_run`] |
//! | `polywear-cli` | the `polywear` program |
//!
//! **The public surface** is [`prelude`] and the modules re-exported here: one point ([`evaluate`]: `PointProblem` → `solve` → `PointSolution`),
//! a study in memory or to Parquet ([`study`], [`explore`]), the long-term loop
//! ([`long_term`]), an explore run with its closing report as the command line runs it
//! ([`explore_run`]), and the analysis of a run's files ([`analysis`], [`render`],
//! [`run_report`]), with the plain data they pass ([`params`], [`model`], [`classify`],
//! [`records`]). Every problem type is `#[non_exhaustive]` and built by a constructor that
//! checks it; every error is a `thiserror` enum naming the field and its accepted range; none holds a reference to global state. That
//! is the surface Python bindings (PyO3) would wrap: plain-data problems in, plain-data
//! solutions and Parquet files out (docs/book/src/reference/rust-api.md). The other stages
//! (the names without links above) are not re-exported: they are the workspace's inner stages,
//! reached by the command line, the tests and the benchmarks through their own crates, and free
//! to change.
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
//! // A problem built from Rust is checked like the command line's input.
//! let bad = Params { speed_kmh: -1.0, ..params };
//! let refused = PointProblem::checked(bad, &[Variant::DEFAULT], &options).unwrap_err();
//! assert!(refused.to_string().contains("speed_kmh"), "{refused}");
//! ```
//!
//! A study in memory: its samples drawn and evaluated one by one, as `explore` does before it
//! writes them to Parquet ([`explore::ExploreRequest::plan`] → [`explore::RunPlan::run`]):
//!
//! ```
//! use polywear::prelude::*;
//!
//! let study = Study::parse(polywear::study::DEFAULT_STUDY).unwrap();
//! let sampler = study.sampler(7, 4);
//! let options = ClassifierOptions { budget: study.budget, ..ClassifierOptions::default() };
//! let rows = polywear::explore::evaluate_sample(&study, &sampler, 0, &options, None);
//! assert_eq!(rows.records.len(), 2 * study.variants.len());
//! ```

#![warn(missing_docs)]

// The public surface.
pub use polywear_analysis::{analysis, explore_run, render, run_report};
pub use polywear_core::{classify, evaluate, long_term, model, params, records};
pub use polywear_study::{explore, study};

/// What a user of the engine needs: one point (problem → solve → solution), a study (in memory
/// or to Parquet), the long-term loop, and the analysis of a run.
pub mod prelude {
    pub use polywear_analysis::analysis::outcome::OutcomeAnswer;
    pub use polywear_analysis::analysis::{Analysis, AnalysisError, AnalysisOptions};
    pub use polywear_core::classify::{Class, ClassifierOptions, WheelVerdict};
    pub use polywear_core::evaluate::{solve, PointProblem, PointSolution};
    pub use polywear_core::long_term::{LongTermError, LongTermProblem, LongTermSolution};
    pub use polywear_core::model::{Variant, Wheel, WheelModel};
    pub use polywear_core::params::{ParamError, ParamId, Params};
    pub use polywear_core::records::WheelRecord;
    pub use polywear_study::explore::{ExploreError, ExploreRequest, RunPlan};
    pub use polywear_study::study::{Study, StudyError};
}
