//! A long run's opening lines, said before any work: what is evaluated, on how many samples
//! and threads, into which folder, under which calibration band (MODEL.md#the-calibration-band)
//! and scenarios. Words about a checked plan, so that a script that runs the same plan can say
//! what `polywear explore` and `polywear optimize` say.

use std::path::Path;

use polywear_core::wording::plain;
use polywear_study::explore::RunPlan;
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

/// Which scenarios every sample is also evaluated under, if any, each with its reference.
pub fn scenarios_line(study: &Study) -> Option<String> {
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
