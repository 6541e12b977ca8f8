//! An explore run as one call: the rows of every owned chunk, the calibration band's pass over
//! its subsample (MODEL.md#the-calibration-band), then the closing report of the whole output
//! folder ([`ExploreRun`] → [`ExploreRun::solve`] → [`ExploreOutcome`]). The command line and a
//! Python layer both call it: they build the session (the plan, its locked folder, the band),
//! say what they show while it runs ([`ExploreRunObserver`]) and word how it ended. The call
//! lives here, not beside the session in `polywear_study::explore`, because the report is the
//! analysis's, and the study crate comes before the analysis in the data flow.

use std::path::PathBuf;
use std::time::Instant;

use crate::analysis::{AnalysisOptions, Step};
use crate::plot::FigureFormat;
use crate::render::RenderOptions;
use crate::run_report::{write_report, ReportError, RunReport};
use polywear_study::explore::{
    empty_shard_report, ExploreEnd, ExploreError, ExploreObserver, ExploreSession,
    ExploreSessionError, RunSummary,
};

/// The folder inside a run's output folder that its closing report goes to: where `analyze`
/// looks by default, and where an empty shard's page goes.
const REPORT_DIR: &str = "_report";

/// What a running explore reports and asks, from any thread: the session's progress and stop
/// ([`ExploreObserver`]), and the two moments after it.
pub trait ExploreRunObserver: ExploreObserver {
    /// Every owned sample's rows and the band are saved, in `secs`; the closing report comes
    /// next. From here on nothing is lost by ending the process (the command line lets a
    /// signal end it at once), and the run's own summary can be shown before the report's.
    fn saved(&self, _summary: &RunSummary, _secs: f64) {}
    /// The closing analysis finished `step`.
    fn report_step(&self, _step: Step) {}
}

/// A run ready to go: its session and the closing report asked for.
#[non_exhaustive]
pub struct ExploreRun<'a> {
    /// The plan, its checked and locked output folder, the band and its subsample size.
    pub session: ExploreSession<'a>,
    /// The figures' format of the closing report, written to `DIR/_report`; `None`: no report
    /// (`--no-report`).
    pub report: Option<FigureFormat>,
    /// The thread pool the rows and the band run on; `None`: the caller's (rayon's global pool
    /// unless the call is inside another's `install`). The report runs outside it, on the
    /// caller's threads, as `analyze` does.
    pub pool: Option<&'a rayon::ThreadPool>,
}

/// A run whose rows and band are saved: its counts, how long they took, and its report.
#[derive(Debug)]
pub struct FinishedRun {
    /// Counts of the samples this session evaluated and kept.
    pub summary: RunSummary,
    /// Seconds the rows and the band took.
    pub secs: f64,
    /// The closing report.
    pub report: ClosingReport,
}

/// The closing report of a finished run.
#[derive(Debug)]
pub enum ClosingReport {
    /// None was asked for.
    NotAsked,
    /// The shard owns no chunk (fewer chunks than shards): it did all it had to. The page
    /// saying so, `DIR/_report/report.md`, where a report was asked for.
    EmptyShard(Option<PathBuf>),
    /// The analysis of the whole output folder (this shard's files, those of an earlier
    /// session included): its summary is the run's one summary.
    Written(Box<RunReport>),
}

/// How a run ended.
#[derive(Debug)]
pub enum ExploreOutcome {
    /// Every owned sample's rows and the band are saved, and the report is as asked.
    Finished(FinishedRun),
    /// Stopped while the rows were evaluated: the chunks in flight were dropped and are redone
    /// on resume.
    StoppedInRows(RunSummary),
    /// Stopped during the band's pass: every sample's rows are saved, the band is pending
    /// (`analyze` refuses the run until a resume finishes it).
    StoppedInBand(RunSummary),
}

/// Why a run gave no outcome.
#[derive(Debug, thiserror::Error)]
pub enum ExploreRunError {
    /// The rows or the band could not be evaluated or written.
    #[error(transparent)]
    Session(#[from] ExploreSessionError),
    /// An empty shard's page could not be written (its rows, none, are all there).
    #[error(transparent)]
    EmptyShard(ExploreError),
    /// The rows and the band are saved, but the report could not be written.
    #[error(transparent)]
    Report(#[from] ReportError),
}

impl<'a> ExploreRun<'a> {
    /// The run of `session`, with the closing report in `report`'s figure format (`None`: no
    /// report), its rows on the caller's thread pool.
    pub fn new(session: ExploreSession<'a>, report: Option<FigureFormat>) -> Self {
        ExploreRun {
            session,
            report,
            pool: None,
        }
    }

    /// The same run, its rows and band on `pool`.
    pub fn on_pool(self, pool: &'a rayon::ThreadPool) -> Self {
        ExploreRun {
            pool: Some(pool),
            ..self
        }
    }

    /// Runs the rows and the band ([`ExploreSession::run`]), then, unless a stop came first,
    /// tells `observer` they are saved and writes the closing report.
    pub fn solve<O: ExploreRunObserver>(
        &self,
        observer: &O,
    ) -> Result<ExploreOutcome, ExploreRunError> {
        let start = Instant::now();
        let end = match self.pool {
            Some(pool) => pool.install(|| self.session.run(observer)),
            None => self.session.run(observer),
        }?;
        let secs = start.elapsed().as_secs_f64();
        let summary = match end {
            ExploreEnd::Finished(summary) => summary,
            ExploreEnd::StoppedInRows(s) => return Ok(ExploreOutcome::StoppedInRows(s)),
            ExploreEnd::StoppedInBand(s) => return Ok(ExploreOutcome::StoppedInBand(s)),
        };
        observer.saved(&summary, secs);
        let report = self.closing_report(observer)?;
        Ok(ExploreOutcome::Finished(FinishedRun {
            summary,
            secs,
            report,
        }))
    }

    /// The report of the whole output folder, with `analyze`'s default options; an empty
    /// shard's page instead where the shard owns no chunk.
    fn closing_report<O: ExploreRunObserver>(
        &self,
        observer: &O,
    ) -> Result<ClosingReport, ExploreRunError> {
        let plan = self.session.plan;
        if plan.owned_chunks().next().is_none() {
            let page = match self.report {
                Some(_) => Some(empty_shard_report(plan).map_err(ExploreRunError::EmptyShard)?),
                None => None,
            };
            return Ok(ClosingReport::EmptyShard(page));
        }
        let Some(figure_format) = self.report else {
            return Ok(ClosingReport::NotAsked);
        };
        let render = RenderOptions {
            out_dir: plan.out_dir.join(REPORT_DIR),
            figure_format,
        };
        let report = write_report(
            std::slice::from_ref(&plan.out_dir),
            &AnalysisOptions::default(),
            &render,
            &mut |step| observer.report_step(step),
        )?;
        Ok(ClosingReport::Written(Box::new(report)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_study::explore::{ExploreRequest, RunPlan, Shard};
    use polywear_study::refusal::Refusal;
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

    /// Counts what a run tells it; asks to stop when `stop` is set.
    #[derive(Default)]
    struct Seen {
        stop: AtomicBool,
        samples: AtomicUsize,
        saved: AtomicUsize,
        steps: AtomicUsize,
    }

    impl ExploreObserver for Seen {
        fn samples_done(&self, n: u64) {
            self.samples.fetch_add(n as usize, Ordering::SeqCst);
        }
        fn should_stop(&self) -> bool {
            self.stop.load(Ordering::SeqCst)
        }
    }

    impl ExploreRunObserver for Seen {
        fn saved(&self, _summary: &RunSummary, _secs: f64) {
            self.saved.fetch_add(1, Ordering::SeqCst);
        }
        fn report_step(&self, _step: Step) {
            self.steps.fetch_add(1, Ordering::SeqCst);
        }
    }

    /// A tiny run without the wear stage or a band: 12 samples in one chunk, in a fresh
    /// folder named after `name`.
    fn tiny_plan(name: &str, shard: Option<Shard>) -> RunPlan {
        let dir = std::env::temp_dir().join(format!(
            "polywear-explore-run-{name}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let study = dir.join("tiny.toml");
        std::fs::write(
            &study,
            "name = \"tiny\"\nseed = 5\nsamples = 12\n[params]\n\
             speed_kmh = { dist = \"uniform\", min = 90, max = 130 }\n\
             toe_deg = { dist = \"uniform\", min = 0.2, max = 0.5 }\n",
        )
        .unwrap();
        let request = ExploreRequest {
            study: Some(study),
            out: Some(dir.join("out")),
            shard,
            no_wear: true,
            ..ExploreRequest::default()
        };
        request.plan(&|b| Ok::<_, Refusal>(b)).unwrap().0
    }

    fn run(plan: &RunPlan, report: Option<FigureFormat>, seen: &Seen) -> ExploreOutcome {
        let prepared = plan.prepare_output().unwrap();
        let session = ExploreSession {
            plan,
            prepared: &prepared,
            band: None,
            band_samples: 100,
        };
        ExploreRun::new(session, report).solve(seen).unwrap()
    }

    fn clean(plan: &RunPlan) {
        let _ = std::fs::remove_dir_all(plan.out_dir.parent().unwrap());
    }

    /// One call runs the rows, says they are saved, then writes the report of the folder.
    #[test]
    fn a_finished_run_is_saved_then_reported() {
        let plan = tiny_plan("report", None);
        let seen = Seen::default();
        let outcome = run(&plan, Some(FigureFormat::Svg), &seen);
        let ExploreOutcome::Finished(run) = outcome else {
            panic!("{outcome:?}");
        };
        assert_eq!(run.summary.samples_evaluated, 12);
        assert_eq!(seen.samples.load(Ordering::SeqCst), 12);
        assert_eq!(seen.saved.load(Ordering::SeqCst), 1);
        assert!(seen.steps.load(Ordering::SeqCst) > 0);
        let ClosingReport::Written(report) = &run.report else {
            panic!("{:?}", run.report);
        };
        assert_eq!(
            report.analysis.info.rows,
            12 * 2 * plan.study.variants.len() as u64
        );
        assert_eq!(
            report.rendered.report,
            plan.out_dir.join("_report/report.md")
        );
        assert!(report.rendered.report.exists());
        clean(&plan);
    }

    /// A shard that owns no chunk did all it had to: its page says so; without a report, not
    /// even that.
    #[test]
    fn an_empty_shard_gets_its_page_or_nothing() {
        let plan = tiny_plan("empty-shard", Some(Shard::new(1, 2).unwrap()));
        let seen = Seen::default();
        let outcome = run(&plan, Some(FigureFormat::Png), &seen);
        let ExploreOutcome::Finished(FinishedRun {
            report: ClosingReport::EmptyShard(Some(page)),
            ..
        }) = &outcome
        else {
            panic!("{outcome:?}");
        };
        assert!(std::fs::read_to_string(page)
            .unwrap()
            .contains("This shard holds no rows"));
        clean(&plan);
        let plan = tiny_plan("empty-shard-no-report", Some(Shard::new(1, 2).unwrap()));
        let outcome = run(&plan, None, &seen);
        assert!(
            matches!(
                outcome,
                ExploreOutcome::Finished(FinishedRun {
                    report: ClosingReport::EmptyShard(None),
                    ..
                })
            ),
            "{outcome:?}"
        );
        assert!(!plan.out_dir.join("_report").exists());
        clean(&plan);
    }

    /// A stop before the first chunk ends the run in its rows: nothing is said saved, no
    /// report is written.
    #[test]
    fn a_stop_ends_in_the_rows_without_a_report() {
        let plan = tiny_plan("stop", None);
        let seen = Seen::default();
        seen.stop.store(true, Ordering::SeqCst);
        let outcome = run(&plan, Some(FigureFormat::Png), &seen);
        assert!(
            matches!(outcome, ExploreOutcome::StoppedInRows(_)),
            "{outcome:?}"
        );
        assert_eq!(seen.saved.load(Ordering::SeqCst), 0);
        assert!(!plan.out_dir.join("_report").exists());
        clean(&plan);
    }
}
