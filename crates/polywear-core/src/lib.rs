//! polywear's engine: how likely a tire is to develop polygonal wear through lateral
//! self-excited vibration of the tread (Zuo, Duan, Li 2014), from one operating point to an
//! indexed family of them. Each stage takes plain data and gives plain data:
//!
//! | stage | module | entry points |
//! |---|---|---|
//! | parameters | [`params`] | [`params::Params`] (SI fields, `Default` = the shipped tire), [`params::ParamId`] |
//! | sampling | [`sampling`] | designs, distributions and the per-sample random streams |
//! | model (MODEL.md#the-physics-step-by-step, steps 1–8) | [`model`] | [`model::WheelModel::build`] → the [`model::TreadOde`] with its derivatives ([`model::jet`]) |
//! | solver | [`solver`] | [`solver::integrate`] (Dormand–Prince pairs, dense output) over any [`solver::OdeSystem`] |
//! | continuation | [`continuation`] | Hopf curves of any [`continuation::OdeWithJacobian`] |
//! | classification (step 9) | [`classify`] | [`classify::classify`] → [`classify::WheelVerdict`] |
//! | wear | [`wear`] | the per-sample estimate and the long-term loop |
//! | the one road | [`evaluate`] | [`evaluate::PointProblem`] → [`evaluate::solve`] → [`evaluate::PointSolution`] |
//! | the long-term loop on both wheels | [`long_term`] | [`long_term::LongTermProblem`] → [`long_term::solve`] → [`long_term::LongTermSolution`] |
//! | ensembles | [`ensemble`] | [`ensemble::solve`] (an indexed family in parallel, in index order) |
//! | records | [`records`] | [`records::WheelRecord`] (one row per wheel), [`records::record_columns`] → [`columns::Column`] |
//!
//! No file formats and no frameworks: reading studies, Parquet and figures live in
//! `polywear-study` and `polywear-analysis`, the command line in `polywear-cli`.
//!
//! One operating point, both wheels, through the evaluator:
//!
//! ```
//! use polywear_core::classify::{Class, ClassifierOptions};
//! use polywear_core::evaluate::{solve, PointProblem};
//! use polywear_core::model::Variant;
//! use polywear_core::params::Params;
//!
//! let params = Params::default();
//! let options = ClassifierOptions::default();
//! let problem = PointProblem::new(params, &[Variant::DEFAULT], &options);
//! let solution = solve(&problem);
//! for wheel in &solution.wheels {
//!     let r = &wheel.record;
//!     assert_eq!(r.speed_kmh, params.speed_kmh);
//!     assert!(r.class != Class::Failed, "{}", r.reason);
//! }
//! assert_eq!(solution.wheels.len(), 2);
//! ```

#![warn(missing_docs)]

#[macro_use]
pub mod text_enum;

pub mod classify;
pub mod columns;
pub mod continuation;
pub mod ensemble;
pub mod evaluate;
pub mod long_term;
pub mod model;
pub mod numeric;
pub mod params;
pub mod records;
pub mod sampling;
pub mod solver;
pub mod wear;
pub mod wording;
