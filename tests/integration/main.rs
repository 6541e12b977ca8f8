//! The integration tests, one module per area, in one test binary: each binary links
//! polars, so one binary instead of one per file saves CI most of its link time.
//! Run one area with `cargo test --release --test integration <module>::`.

mod common;
#[path = "common/parquet_rows.rs"]
mod parquet_rows;

mod analyze;
mod bad_inputs;
mod band_integrity;
mod both_wheels;
mod budget;
mod calibrate_reproduce;
mod calibration_band;
mod car;
mod chart;
mod classifier_vs_reference;
mod cli_bifurcation;
mod cli_simulate;
mod cycle_lifetime;
mod cycles;
mod docs;
mod explore;
mod fault_injection;
mod field_engineer;
mod figures;
mod fuzz_inputs;
mod inputs;
mod integrity;
mod invariants;
mod operating_points;
mod optimize;
mod plain_words;
mod python_interop;
mod reference_points;
mod sampling;
mod scenarios;
mod shooting_accuracy;
mod sobol_design;
mod talking;
mod tread_ageing;
mod wear;
mod wear_analysis;
mod wear_explore;
mod wear_loop;
