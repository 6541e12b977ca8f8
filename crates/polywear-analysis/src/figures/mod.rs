//! Figures of the compute stages: stability charts, drive cycles, optimisation, sweeps and time
//! series, drawn from their solutions.

pub mod bifurcation;
pub mod chart;
pub mod cycle;
pub mod optimize;
mod optimize_figure;
pub mod trajectory;
pub mod wear;

use std::path::PathBuf;

use crate::plot::PlotError;
use polywear_study::parquet_out::WriteError;

/// Why a command's files (tables and figure) were not written.
#[derive(Debug, thiserror::Error)]
pub enum FilesError {
    /// The output directory cannot be created.
    #[error("{}: {source}", dir.display())]
    CreateDir {
        /// The output directory.
        dir: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A table could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// The figure could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}
