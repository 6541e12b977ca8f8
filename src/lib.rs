//! polywear: how likely a tire is to develop polygonal wear through lateral self-excited
//! vibration of the tread (Zuo, Duan, Li 2014). The modules follow the data flow:
//! [`params`] → [`model`] (steps 1–8 of MODEL.md#the-physics-step-by-step) → [`solver`] →
//! [`classify`] (step 9) → [`records`] → [`parquet_out`]; [`plot`] draws what people would rather
//! look at.

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
