//! explore's `--resume` on the command line: the command that continues a stopped run (the
//! resume rules themselves are `polywear_study::explore::ExploreRequest`'s).
use super::ExploreArgs;
use polywear_study::explore::recorded_run::shell_word;
use polywear_study::explore::RunPlan;

/// The command that continues `plan`'s run: `--resume --out DIR`, and the flags the manifest
/// does not record (work budget, threads, the calibration band).
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
    if let Some(b) = &args.calibration_band {
        words.extend(["--calibration-band".into(), b.clone()]);
    }
    if let Some(n) = args.band_samples {
        words.extend(["--band-samples".into(), n.to_string()]);
    }
    words
        .iter()
        .map(|w| shell_word(w))
        .collect::<Vec<_>>()
        .join(" ")
}
