//! A run's files into its report, as one call: the inputs checked (footers and manifests only,
//! so inputs that do not belong together stop here, before any work), the analysis, then the
//! tables, figures and `report.md` ([`write_report`]). `polywear analyze` calls it on the
//! folders it is given, and an explore run ([`crate::explore_run`]) on its own folder for its
//! closing report; each words the result and its errors its own way.

use std::path::PathBuf;
use std::time::Instant;

use crate::analysis::inputs::check_inputs;
use crate::analysis::{Analysis, AnalysisError, AnalysisOptions, Step};
use crate::render::{RenderError, RenderOptions, Rendered};

/// A written report: the analysis, the files it was written to, and how long both took.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// What the rows say.
    pub analysis: Analysis,
    /// The tables, figures and `report.md`.
    pub rendered: Rendered,
    /// Seconds from the inputs' check to the last file written.
    pub secs: f64,
}

impl RunReport {
    /// Why the report has no probability to give (every row failed or had no traction), in
    /// the words the summary prints; `None` where some row has a verdict. A report without a
    /// verdict is still written: a caller decides whether it is a failure (the command line
    /// says it is).
    pub fn no_verdict(&self) -> Option<String> {
        crate::render::summary::no_verdict(&self.analysis, &self.rendered.report)
    }
}

/// Why no report was written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The inputs cannot be read or do not belong together, or the analysis failed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// The inputs hold no rows.
    #[error("the inputs hold no rows")]
    NoRows,
    /// The analysis is done but its report cannot be written where asked (the rows are
    /// untouched: another folder may do).
    #[error("cannot write the report: {0}")]
    Write(RenderError),
}

/// Checks `inputs`, analyses them with `opts` and writes the report as `render` says.
/// `progress` is called after each [`Step`] of the analysis (the command line hands the memory
/// a finished query freed back to the system there).
pub fn write_report(
    inputs: &[PathBuf],
    opts: &AnalysisOptions,
    render: &RenderOptions,
    progress: &mut dyn FnMut(Step),
) -> Result<RunReport, ReportError> {
    let start = Instant::now();
    let info = check_inputs(inputs)?;
    if info.rows == 0 {
        return Err(ReportError::NoRows);
    }
    let analysis = crate::analysis::run_with_progress(info, opts, progress)?;
    let rendered = crate::render::write(&analysis, render).map_err(ReportError::Write)?;
    Ok(RunReport {
        analysis,
        rendered,
        secs: start.elapsed().as_secs_f64(),
    })
}
