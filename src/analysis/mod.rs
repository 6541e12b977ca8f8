//! Analysis stage: reads explore output (Parquet) and answers what users ask of an overnight
//! run: how likely is self-excited vibration (and so polygonal wear) on driving and follower
//! wheels, where in the operating space does the risk live, how severe is it, and which
//! parameters drive it.
//!
//! The stages of a report: [`inputs`] (footers checked before any row is read), [`queries`]
//! (polars lazy queries on the streaming engine, returning small tables), [`stats`] (intervals
//! and tests on those tables), then [`figures`] and [`markdown`]; [`report`] runs them in order
//! and writes the tables.

pub mod figures;
pub mod inputs;
pub mod markdown;
pub mod queries;
pub mod report;
pub mod stats;
