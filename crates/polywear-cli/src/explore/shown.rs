//! What the command line shows of a running explore: a progress bar (or log lines) for the
//! samples, then one for the band's samples, and whether a signal asks it to stop; once the
//! rows and the band are saved, the run's summary, before the closing report's.

use std::sync::OnceLock;
use std::time::Duration;

use super::super::analyze::release_freed_memory;
use super::super::batch::{Interrupt, Progress};
use super::ExploreArgs;
use polywear_analysis::analysis::Step;
use polywear_analysis::explore_run::ExploreRunObserver;
use polywear_analysis::render::run_words::explore_done;
use polywear_study::explore::{ExploreObserver, RunPlan, RunSummary};

/// How often a progress line is logged when stderr is not a terminal.
pub(super) fn every(args: &ExploreArgs) -> Duration {
    Duration::from_secs_f64(args.log_every)
}

/// What the command line shows of a running explore: the samples' progress, then the band's.
pub(super) struct Shown<'a> {
    pub(super) args: &'a ExploreArgs,
    pub(super) plan: &'a RunPlan,
    pub(super) rows: Progress,
    pub(super) band: OnceLock<Progress>,
    pub(super) stop: &'a Interrupt,
}

impl ExploreObserver for Shown<'_> {
    fn samples_done(&self, n: u64) {
        self.rows.add(n);
    }

    fn rows_ended(&self) {
        self.rows.finish();
    }

    fn band_started(&self, sets: usize, source: &str, samples: u64) {
        if !self.args.quiet {
            eprintln!(
                "calibration band: {sets} calibrated sets ({source}) on {samples} of the samples"
            );
        }
        let progress = Progress::new(self.args.quiet, samples, "band samples", every(self.args));
        let _ = self.band.set(progress);
    }

    fn band_samples_done(&self, n: u64) {
        if let Some(progress) = self.band.get() {
            progress.add(n);
        }
    }

    fn band_ended(&self) {
        if let Some(progress) = self.band.get() {
            progress.finish();
        }
    }

    fn should_stop(&self) -> bool {
        self.stop.signal().is_some()
    }
}

impl ExploreRunObserver for Shown<'_> {
    fn saved(&self, summary: &RunSummary, secs: f64) {
        // From here on a signal ends the program at once: the rows and the band are saved.
        self.stop.disarm();
        if !self.args.quiet {
            println!("{}", explore_done(self.plan, summary, secs));
        }
    }

    fn report_step(&self, _step: Step) {
        release_freed_memory();
    }
}
