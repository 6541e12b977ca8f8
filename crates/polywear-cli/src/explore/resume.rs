//! explore's `--resume`: what a resumed run takes from the run recorded in its directory, what
//! it refuses to change, and the command that continues a stopped run.

use std::path::Path;

use super::ExploreArgs;
use crate::common::{CliError, CliResult};
use polywear_core::wear::{WearSettings, WearZone};
use polywear_study::explore::recorded_run::{
    changed_lines, param_changes, shell_word, RecordedRun,
};
use polywear_study::explore::RunPlan;
use polywear_study::study::Study;

/// The run's wear stage: `--no-wear` or `--wear-zone` over the study's `wear`/`wear_zone`; a
/// resumed run keeps the stage it started with, and a flag that contradicts it is refused.
pub(super) fn wear_settings(
    args: &ExploreArgs,
    study: &Study,
    recorded: Option<&RecordedRun>,
) -> CliResult<Option<WearSettings>> {
    let asked = match (args.no_wear, args.wear_zone) {
        (true, _) => Some(None),
        (false, Some(zone)) if study.wear.is_none() && recorded.is_none() => {
            return Err(CliError(format!(
                "--wear-zone {zone}: the study sets `wear = false`, which leaves the wear stage out; remove it from the study, or leave --wear-zone out"
            )))
        }
        (false, Some(zone)) => Some(Some(WearSettings { zone })),
        (false, None) => None,
    };
    let Some(run) = recorded else {
        return Ok(asked.unwrap_or(study.wear));
    };
    match asked {
        Some(w) if w != run.wear => {
            let was = run
                .wear
                .map_or("no wear stage (--no-wear)".to_string(), |w| {
                    format!("the wear stage with --wear-zone {}", w.zone)
                });
            let flag = if args.no_wear {
                "--no-wear".to_string()
            } else {
                format!("--wear-zone {}", args.wear_zone.expect("asked"))
            };
            Err(CliError(format!(
                "--resume: {flag} contradicts the run, which started with {was}; leave it out to continue the run as it started, or choose another --out for a new run"
            )))
        }
        _ => Ok(run.wear),
    }
}

pub(super) fn parse_wear_zone(s: &str) -> Result<WearZone, String> {
    s.parse::<WearZone>().map_err(|e| e.to_string())
}

/// Refuses a flag of `--resume --out DIR` that contradicts the run recorded in DIR, showing
/// both values; repeating the recorded value is accepted.
pub(super) fn check_against_recorded(
    args: &ExploreArgs,
    study: &Study,
    dir: &Path,
    run: &RecordedRun,
) -> CliResult {
    let d = shell_word(&dir.display().to_string());
    let refuse = |what: String| {
        let sep = if what.ends_with('\n') { "" } else { "; " };
        CliError(format!(
            "--resume --out {d}: {what}{sep}leave it out to continue the run as it started (`polywear explore --resume --out {d}`), or choose another --out for a new run"
        ))
    };
    if let Some(path) = &args.study {
        if study.source != run.study {
            let lines = changed_lines(&run.study, &study.source);
            return Err(refuse(format!(
                "{} differs from the run's study in these lines (- the run's, + the file's):\n    {}\n",
                path.display(),
                lines.join("\n    ")
            )));
        }
    }
    if let Some(seed) = args.seed.filter(|s| *s != run.seed) {
        return Err(refuse(format!(
            "--seed {seed} contradicts the run's seed {}",
            run.seed
        )));
    }
    if let Some(n) = args
        .samples
        .filter(|n| study.evaluations(*n) != run.samples)
    {
        return Err(refuse(format!(
            "--samples {n} contradicts the run's {} samples",
            run.samples / study.evaluations(1)
        )));
    }
    if let Some(s) = args.shard.filter(|s| *s != run.shard) {
        return Err(refuse(format!(
            "--shard {s} contradicts the run's shard {}",
            run.shard
        )));
    }
    if let Some(path) = &args.params {
        if study.base != run.params {
            return Err(refuse(format!(
                "--params {} contradicts the run's values ({}, now from the file)",
                path.display(),
                param_changes(&run.params, &study.base)
            )));
        }
    }
    Ok(())
}

/// The command that continues `plan`'s run: `--resume --out DIR`, and the flags the manifest
/// does not record (work budget, threads).
pub(super) fn resume_command(args: &ExploreArgs, plan: &RunPlan) -> String {
    let mut words = vec![
        std::env::args().next().unwrap_or_else(|| "polywear".into()),
        "explore".into(),
        "--resume".into(),
        "--out".into(),
        plan.out_dir.display().to_string(),
    ];
    if let Some(n) = args.budget.max_rhs_evals {
        words.extend(["--max-rhs-evals".into(), n.to_string()]);
    }
    if let Some(s) = args.budget.max_wheel_seconds {
        words.extend(["--max-wheel-seconds".into(), s.to_string()]);
    }
    if let Some(t) = args.threads {
        words.extend(["--threads".into(), t.to_string()]);
    }
    if args.no_report {
        words.push("--no-report".into());
    }
    words
        .iter()
        .map(|w| shell_word(w))
        .collect::<Vec<_>>()
        .join(" ")
}
