//! Analysis stage: reads explore output (Parquet) and answers what users ask of an overnight
//! run: how likely is self-excited vibration (and so polygonal wear) on driving and follower
//! wheels, where in the operating space does the risk live, how severe is it, and which
//! parameters drive it.

pub mod compute;
pub mod load;
pub mod report;
pub mod stats;
