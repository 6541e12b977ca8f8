//! polywear's studies, compute only: a study's TOML and the inputs it names, read safely; the
//! batch run (`explore`: run plans, chunks, shards, verified resume) streamed to Parquet; drive
//! cycles; calibration; optimisation over a study's samples; stability charts and sweeps; the
//! acceptance check. Figures and the analysis of the rows are `polywear-analysis`'s.

#![warn(missing_docs)]

pub mod bifurcation;
pub mod calibrate;
pub mod calibration_band;
pub mod chart;
pub mod cycle;
pub mod explore;
pub mod field_facts;
pub(crate) mod key_value;
pub mod long_term_request;
pub mod operating_points;
pub mod optimize;
pub mod output_dir;
pub mod param_sources;
pub mod parquet_out;
pub mod point_file;
pub mod provenance;
pub mod refusal;
pub mod safe_read;
pub mod safe_write;
pub mod stats;
pub mod study;
pub mod table_input;
pub mod toe_input;
pub(crate) mod toml_input;
pub mod trajectory;
pub mod validation;
