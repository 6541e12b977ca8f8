//! explore's errors in the words of the command line: the output directory as `--out`, a
//! resume's refusals as `--resume`'s, a failed write with what is saved and how to go on, and a
//! closing report that cannot be written with how to write it elsewhere.

use super::resume::resume_command;
use super::ExploreArgs;
use crate::analyze::report_error;
use crate::common::CliError;
use polywear_analysis::explore_run::ExploreRunError;
use polywear_analysis::render::run_words::analyze_command;
use polywear_study::explore::recorded_run::{shell_word, DirState, RecordedRun};
use polywear_study::explore::{ExploreError, ExploreSessionError, RunPlan};

/// An explore error in the words of the command line: the output directory as `--out`, a
/// resume's refusals as `--resume`'s, each with the flags that get on.
pub(super) fn explore_error(e: ExploreError) -> CliError {
    let dir = match &e {
        ExploreError::Write(_) | ExploreError::Wear(_) => return CliError(e.to_string()),
        ExploreError::OutputDir { dir, .. }
        | ExploreError::Raced { dir }
        | ExploreError::Occupied { dir, .. }
        | ExploreError::NothingToResume { dir, .. }
        | ExploreError::UnreadableManifest { dir, .. }
        | ExploreError::OtherGenerator { dir, .. }
        | ExploreError::OtherVersion { dir, .. }
        | ExploreError::OtherStudy { dir, .. }
        | ExploreError::OperatingPointsChanged { dir, .. }
        | ExploreError::DifferentRun { dir, .. }
        | ExploreError::ForeignChunk { dir, .. } => dir.clone(),
    };
    let text = e.to_string();
    let prefix = format!("{}: ", dir.display());
    let what = text.strip_prefix(&prefix).unwrap_or(&text);
    let d = shell_word(&dir.display().to_string());
    let another = "or choose another --out for a new run";
    let message = match &e {
        ExploreError::Occupied { state, .. } => match state {
            DirState::Finished { .. } => {
                format!("{what}; analyse it with `polywear analyze {d}`, {another}")
            }
            DirState::Unfinished { .. } => format!(
                "{what}; continue it with `polywear explore --resume --out {d}`, {another}"
            ),
            DirState::Foreign => format!(
                "{what}; accepted: an empty or absent directory (for a new run), or a run's directory with --resume"
            ),
            DirState::Unreadable(_) => format!("{what}; choose another --out"),
        },
        ExploreError::OtherGenerator { .. }
        | ExploreError::OtherVersion { .. }
        | ExploreError::OperatingPointsChanged { .. } => {
            format!("--resume: {what}")
        }
        ExploreError::OtherStudy { .. } => format!(
            "--resume: {what}\nleave the study file out to continue the run with its own study, or choose another --out"
        ),
        ExploreError::DifferentRun { .. } => format!(
            "--resume: {what}; continue it with `--resume --out {d}` alone, or choose another --out"
        ),
        ExploreError::OutputDir { .. } if what.contains("read-only") => {
            format!("{what}; choose another directory with --out")
        }
        _ => what.to_string(),
    };
    CliError(format!("--out {}: {message}", dir.display()))
}

/// A chunk or the journal that cannot be written (a full disk, a folder made read-only): what
/// is saved, as the journal records it, and the exact command that continues the run once the
/// cause is fixed.
pub(super) fn write_failure(args: &ExploreArgs, plan: &RunPlan, e: &ExploreError) -> CliError {
    let saved = RecordedRun::read(&plan.out_dir)
        .ok()
        .flatten()
        .map(|run| run.saved(&plan.out_dir));
    let saved = match saved {
        Some(s) => format!(
            "{} of {} samples are saved in {} ({} of {} chunks)",
            s.samples,
            s.samples_owned,
            plan.out_dir.display(),
            s.chunks,
            s.chunks_owned
        ),
        None => format!("nothing is saved in {}", plan.out_dir.display()),
    };
    let text = e.to_string();
    let cause = if text.contains("No space left") || text.contains("full disk") {
        "the disk is full: "
    } else {
        ""
    };
    CliError(format!(
        "{cause}{text}\n{saved}; free space or fix the folder, then resume with: {}",
        resume_command(args, plan)
    ))
}

/// The session's failure in the command line's words: a chunk that cannot be written, or the
/// band's file, with what is saved and the command that goes on.
fn session_error(args: &ExploreArgs, plan: &RunPlan, e: ExploreSessionError) -> CliError {
    match e {
        ExploreSessionError::Rows(e @ ExploreError::Write(_)) => write_failure(args, plan, &e),
        ExploreSessionError::Rows(e) => explore_error(e),
        ExploreSessionError::BandWrite(e) => {
            let cause = if e.contains("No space left") {
                "the disk is full: "
            } else {
                ""
            };
            CliError(format!(
                "{cause}cannot write the calibration band: {e}
every sample's rows are saved in {}; the band is not finished: free space or fix the folder, then finish it with: {}",
                plan.out_dir.display(),
                resume_command(args, plan)
            ))
        }
        e => CliError(e.to_string()),
    }
}

/// A run's failure in the command line's words: the rows or the band as [`session_error`]
/// words them, an empty shard's page, or the closing report, with the command that writes it
/// elsewhere (the rows are saved).
pub(super) fn run_error(args: &ExploreArgs, plan: &RunPlan, e: ExploreRunError) -> CliError {
    match e {
        ExploreRunError::Session(e) => session_error(args, plan, e),
        ExploreRunError::EmptyShard(e) => CliError(e.to_string()),
        ExploreRunError::Report(e) => {
            let elsewhere = format!(
                "the rows are saved: write the report elsewhere with `{}`",
                analyze_command(plan, true)
            );
            report_error(e, &elsewhere)
        }
    }
}
