//! A long run's lines: the opening ones, said before any work (what is evaluated, on how many
//! samples and threads, into which folder, under which calibration band,
//! MODEL.md#the-calibration-band, and scenarios), and explore's closing ones (what was done,
//! and where the whole run's summary is). Words about a checked plan and its summary, so that a
//! script that runs the same plan can say what `polywear explore` and `polywear optimize` say.

use std::path::Path;

use polywear_core::wording::plain;
use polywear_study::explore::recorded_run::shell_word;
use polywear_study::explore::{RunPlan, RunSummary};
use polywear_study::optimize::Problem;
use polywear_study::study::Study;

/// `explore`'s opening: the study, samples, design, seed, variants, shard, `threads` and the
/// output folder; the scenarios every sample is also evaluated under; and, for a resumed run,
/// the `kept` samples already saved and the `todo` left.
pub fn explore_lines(plan: &RunPlan, kept: u64, todo: u64, threads: usize) -> Vec<String> {
    let variants: Vec<&str> = plan.study.variants.iter().map(|v| v.as_str()).collect();
    let mut lines = vec![format!(
        "{}: {} samples ({} design, seed {}, variants {}), shard {}, {threads} threads -> {}",
        plan.study.name,
        plan.samples,
        plan.study.design.as_str(),
        plan.seed,
        variants.join("+"),
        plan.shard,
        plan.out_dir.display()
    )];
    lines.extend(scenarios_line(&plan.study));
    if kept > 0 {
        lines.push(format!(
            "resume: {kept} of {} samples already saved; {todo} to do",
            plan.owned_samples()
        ));
    }
    lines
}

/// `explore`'s closing line: the samples this session evaluated in `secs`, their rate, those
/// already saved, and the chunk files written.
pub fn explore_done(plan: &RunPlan, summary: &RunSummary, secs: f64) -> String {
    format!(
        "{} samples evaluated in {} s ({} samples/s); {} already saved; {} chunk files written to {}",
        summary.samples_evaluated,
        plain(secs, 2),
        plain(summary.samples_evaluated as f64 / secs.max(1e-9), 3),
        summary.samples_skipped,
        summary.chunks_written,
        plan.out_dir.display()
    )
}

/// The line of a shard that owns no chunk (fewer chunks than shards): it did all it had to,
/// and its `report` says so.
pub fn empty_shard_line(plan: &RunPlan, report: &Path) -> String {
    format!(
        "shard {}/{} holds no rows ({} chunk(s) for {} shards); report: {}",
        plan.shard.index,
        plan.shard.count,
        plan.n_chunks(),
        plan.shard.count,
        report.display()
    )
}

/// The command that analyses the run's folder, quoted for a shell: the whole run's summary,
/// and a report written `elsewhere` (with `--out FOLDER`) when it cannot go in the folder.
pub fn analyze_command(plan: &RunPlan, elsewhere: bool) -> String {
    let dir = shell_word(&plan.out_dir.display().to_string());
    match elsewhere {
        false => format!("polywear analyze {dir}"),
        true => format!("polywear analyze {dir} --out FOLDER"),
    }
}

/// Which scenarios every sample is also evaluated under, if any, each with its reference.
pub(crate) fn scenarios_line(study: &Study) -> Option<String> {
    if study.scenarios.is_empty() {
        return None;
    }
    let each: Vec<String> = study
        .scenarios
        .iter()
        .map(|s| match &s.compare_to {
            None => format!("{} ({})", s.name, s.words()),
            Some(r) => format!("{} ({}; compared with `{r}`)", s.name, s.words()),
        })
        .collect();
    Some(format!(
        "  each sample also under {} scenario(s): {}",
        study.scenarios.len(),
        each.join("; ")
    ))
}

/// `optimize`'s opening: the band the search moves under (or why none: `band_off` when it was
/// turned off by name), then the objective, samples, seed, variant, box, `threads` and the
/// output folder.
pub fn optimize_lines(
    problem: &Problem,
    band_off: bool,
    threads: usize,
    out_dir: &Path,
) -> Vec<String> {
    let mut lines = Vec::new();
    match (&problem.band, &problem.band_note) {
        (Some(b), _) if b.samples < problem.samples => lines.push(format!(
            "calibration band: {} sets from {}, each setting's wear answer under every set on the same {} of its {} samples (--band-samples), moved by the nominal constants' answer on all of them",
            b.sets.sets.len(),
            b.source,
            b.samples,
            problem.samples
        )),
        (Some(b), _) => lines.push(format!(
            "calibration band: {} sets from {}, each setting's wear answer under every set on the same samples",
            b.sets.sets.len(),
            b.source
        )),
        (None, Some(note)) => lines.push(format!("note: {note}")),
        (None, None) if band_off => lines.push(
            "calibration band: off (--calibration-band off): the optimum is the nominal constants' alone, with its sampling interval only".into()
        ),
        (None, None) => {}
    }
    let axes: Vec<String> = problem
        .axes
        .iter()
        .map(|a| format!("{} {}..{}", a.param, plain(a.lo, 6), plain(a.hi, 6)))
        .collect();
    lines.push(format!(
        "{}: {} of {} samples (seed {}, variant {}), {}, {threads} threads -> {}",
        problem.study.name,
        problem.objective.text(),
        problem.samples,
        problem.seed,
        problem.variant,
        axes.join(", "),
        out_dir.display()
    ));
    lines
}
