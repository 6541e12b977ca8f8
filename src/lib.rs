//! polywear: how likely a tire is to develop polygonal wear through lateral self-excited
//! vibration of the tread (Zuo, Duan, Li 2014). The library is one data flow; each stage takes
//! plain data and gives plain data (ARCHITECTURE.md lists every module):
//!
//! | stage | module | entry points |
//! |---|---|---|
//! | study | [`study`] | [`study::Study::parse`] (a study's TOML → `Study`), [`study::apply_param_file`] |
//! | sampling | [`sampling`] | [`study::Study::sampler`] → [`study::Sampler::sample`] (index → `Params`) |
//! | parameters | [`params`] | [`params::Params`] (SI fields, `Default` = the shipped tire), [`params::ParamId`] |
//! | model (MODEL.md#the-physics-step-by-step, steps 1–8) | [`model`] | [`model::WheelModel::build`] → the [`model::TreadOde`] |
//! | solver | [`solver`] | [`solver::integrate_with`] (Dormand–Prince pairs, dense output) |
//! | classification (step 9) | [`classify`] | [`classify::classify`] → [`classify::WheelVerdict`] |
//! | the one road | [`evaluate`] | [`evaluate::PointProblem`] → [`evaluate::solve`] → [`evaluate::PointSolution`] |
//! | ensembles | [`ensemble`] | [`ensemble::solve`] (an indexed family in parallel, in index order) |
//! | batch runs | [`explore`] | [`explore::RunPlan`] (chunks, shards, resume) → [`explore::RunSummary`] |
//! | records | [`records`] | [`records::WheelRecord`] (one row per wheel), [`records::record_columns`] |
//! | Parquet | [`parquet_out`] | [`parquet_out::write_table`], [`parquet_out::write_csv`] |
//! | analysis | [`analysis`], [`render`] | [`analysis::run`] → [`analysis::Analysis`] → [`render::write`] |
//!
//! Beside the flow: drive cycles ([`cycle`]), wear ([`wear`], after the classifier in
//! [`evaluate`]), optimisation ([`optimize`]), stability charts ([`chart`], over
//! [`continuation`]), sweeps ([`bifurcation`]), fits ([`calibrate`]), the paper's figures
//! ([`reproduce`], [`plot`] with its [`plot::FigureFormat`]) and the acceptance check
//! ([`validation`]).
//!
//! One operating point, both wheels, through the evaluator:
//!
//! ```
//! use polywear::classify::{Class, ClassifierOptions};
//! use polywear::evaluate::{solve, PointProblem};
//! use polywear::model::Variant;
//! use polywear::params::Params;
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

#[macro_use]
pub mod text_enum;

pub mod analysis;
pub mod bifurcation;
pub mod calibrate;
pub mod chart;
pub mod classify;
pub mod continuation;
pub mod cycle;
pub mod ensemble;
pub mod evaluate;
pub mod explore;
pub mod key_value;
pub mod model;
pub mod numeric;
pub mod operating_points;
pub mod optimize;
pub mod output_dir;
pub mod params;
pub mod parquet_out;
pub mod plot;
pub mod records;
pub mod render;
pub mod reproduce;
pub mod safe_read;
pub mod safe_write;
pub mod sampling;
pub mod solver;
pub mod study;
pub mod table_input;
pub mod toml_input;
pub mod trajectory;
pub mod validation;
pub mod wear;
pub mod wording;
