//! An explore run's computing (MODEL.md#the-calibration-band): the rows of every owned chunk,
//! then the calibration band's pass over its subsample, with a stop between chunks or batches.
//! [`ExploreSession::run`] is the compute half of the one call the command line and a Python
//! layer both make, `polywear_analysis::explore_run`, which adds the closing report (the
//! analysis comes after this crate in the data flow); they only say what it reports
//! ([`ExploreObserver`]: progress and the band's start) and word how it ended.

use std::path::Path;

use super::{ExploreError, PreparedOutput, RunPlan, RunSummary};
use crate::calibration_band::evaluate::{
    mark_pending, remove_band_file, BandFileError, BandPlan, BandWriteError, BAND_DIGEST, BAND_FILE,
};
use crate::calibration_band::CalibrationBand;

/// The sets a run's band uses, and where they come from.
#[derive(Debug, Clone)]
pub struct BandChoice {
    /// The sets.
    pub band: CalibrationBand,
    /// The file's path, or the shipped band's name.
    pub source: String,
}

/// What a running explore reports and asks, from any thread.
pub trait ExploreObserver: Sync {
    /// `n` more samples' rows are saved.
    fn samples_done(&self, n: u64);
    /// Every owned chunk is saved (or the run stopped): the rows' progress ends.
    fn rows_ended(&self) {}
    /// The band's pass starts: `sets` sets from `source` on `samples` of the samples.
    fn band_started(&self, _sets: usize, _source: &str, _samples: u64) {}
    /// `n` more band samples are evaluated under every set.
    fn band_samples_done(&self, _n: u64) {}
    /// The band's pass ended.
    fn band_ended(&self) {}
    /// Whether to stop now (a signal): checked between chunks and between the band's batches.
    fn should_stop(&self) -> bool;
}

/// A run ready to go: its plan, its locked output directory, its band and the band's
/// subsample size.
pub struct ExploreSession<'a> {
    /// The run.
    pub plan: &'a RunPlan,
    /// Its output directory, checked and locked.
    pub prepared: &'a PreparedOutput,
    /// The calibration band (none: off, or no wear stage).
    pub band: Option<&'a BandChoice>,
    /// Samples the band is evaluated on.
    pub band_samples: u64,
}

/// How a run ended.
#[derive(Debug)]
pub enum ExploreEnd {
    /// Every owned sample's rows and the band are written.
    Finished(RunSummary),
    /// Stopped while the rows were evaluated: the chunks in flight were dropped.
    StoppedInRows(RunSummary),
    /// Stopped during the band's pass: every sample's rows are saved, the band is pending.
    StoppedInBand(RunSummary),
}

/// Why a run gave no answer.
#[derive(Debug, thiserror::Error)]
pub enum ExploreSessionError {
    /// The rows could not be evaluated or written.
    #[error(transparent)]
    Rows(#[from] ExploreError),
    /// The band could not be marked pending before the rows.
    #[error("cannot write the calibration band: {0}")]
    BandPending(BandFileError),
    /// An earlier session's band could not be removed.
    #[error("{0}")]
    BandClear(BandFileError),
    /// The band's pass could not write its file: every sample's rows are saved.
    #[error("cannot write the calibration band: {0}")]
    BandWrite(String),
}

impl ExploreSession<'_> {
    /// Marks the band pending (or clears an earlier session's), evaluates every owned chunk,
    /// then the band's pass.
    pub fn run(&self, observer: &dyn ExploreObserver) -> Result<ExploreEnd, ExploreSessionError> {
        self.prepare_band()?;
        let result = self
            .plan
            .run_until(self.prepared, &|n| observer.samples_done(n), &|| {
                observer.should_stop()
            });
        observer.rows_ended();
        let summary = result?;
        if observer.should_stop() {
            return Ok(ExploreEnd::StoppedInRows(summary));
        }
        match self.run_band(observer)? {
            true => Ok(ExploreEnd::Finished(summary)),
            false => Ok(ExploreEnd::StoppedInBand(summary)),
        }
    }

    /// Marks the run's band as asked for and unfinished before any chunk is run, so that a run
    /// stopped anywhere before the band is whole leaves a band `analyze` refuses with the
    /// command that finishes it; a run without a band removes an earlier session's. Only the
    /// shard that owns chunk 0 writes the band.
    fn prepare_band(&self) -> Result<(), ExploreSessionError> {
        let plan = self.plan;
        if !plan.shard.owns(0) {
            return Ok(());
        }
        match (self.band, plan.wear.as_ref()) {
            (Some(c), Some(_)) => {
                mark_pending(&plan.out_dir, &c.source).map_err(ExploreSessionError::BandPending)
            }
            _ => clear_band(&plan.out_dir).map_err(ExploreSessionError::BandClear),
        }
    }

    /// The band's pass after a finished run: the subsample re-evaluated under every set,
    /// written to the output directory by the shard that owns chunk 0 (every shard would
    /// write the same rows). False where a stop came between batches (the band stays pending).
    fn run_band(&self, observer: &dyn ExploreObserver) -> Result<bool, ExploreSessionError> {
        let plan = self.plan;
        let (Some(choice), Some(stage)) = (self.band, plan.wear.as_ref()) else {
            return Ok(true);
        };
        if !plan.shard.owns(0) {
            return Ok(true);
        }
        let band_plan = BandPlan {
            study: &plan.study,
            seed: plan.seed,
            samples: plan.samples,
            band_samples: self.band_samples,
            stage,
            band: &choice.band,
            band_source: choice.source.clone(),
        };
        let n = band_plan.indices().len() as u64;
        observer.band_started(choice.band.sets.len(), &choice.source, n);
        let written = band_plan.write(
            &plan.out_dir,
            plan.chunk_metadata(0).to_key_values(),
            &|k| observer.band_samples_done(k),
            &|| observer.should_stop(),
        );
        observer.band_ended();
        match written {
            Ok(_) => Ok(true),
            Err(BandWriteError::Stopped) => Ok(false),
            Err(BandWriteError::Io(e)) => Err(ExploreSessionError::BandWrite(e)),
        }
    }
}

/// A run without a band (`--calibration-band off`) leaves no band of an earlier session of it
/// in its directory `dir`, so that its report is the answer asked for.
fn clear_band(dir: &Path) -> Result<(), BandFileError> {
    for name in [BAND_DIGEST, BAND_FILE] {
        remove_band_file(&dir.join(name))?;
    }
    Ok(())
}
