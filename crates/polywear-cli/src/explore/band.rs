//! `explore`'s calibration band: `--calibration-band` and `--band-samples` resolved into the
//! sets and the subsample before any work, then the band's pass after the run's chunks.

use std::time::Duration;

use super::super::batch::{Interrupt, Progress};
use super::super::common::{CliError, CliResult};
use super::ExploreArgs;
use polywear_study::calibration_band::evaluate::{BandPlan, BandWriteError, DEFAULT_BAND_SAMPLES};
use polywear_study::calibration_band::CalibrationBand;
use polywear_study::explore::RunPlan;

/// The sets a run's band uses, and where they come from.
pub struct BandChoice {
    /// The sets.
    pub band: CalibrationBand,
    /// The file's path, or [`SHIPPED_NAME`].
    pub source: String,
}

/// The band the flags ask for: the shipped sets by default, a file's, or none (`off`, or a run
/// without the wear stage). A file that cannot be read or is refused stops the run here.
pub fn choose(args: &ExploreArgs, plan: &RunPlan) -> CliResult<Option<BandChoice>> {
    let asked = args.calibration_band.as_deref();
    let unused = |why: &str| {
        CliError(format!(
            "--band-samples {}: {why}, so it would not be used; leave it out",
            args.band_samples.unwrap_or_default()
        ))
    };
    if args.band_samples.is_some() && asked == Some("off") {
        return Err(unused(
            "the calibration band is off (--calibration-band off)",
        ));
    }
    if args.band_samples.is_some() && plan.wear.is_none() {
        return Err(unused("the run has no wear stage, so no calibration band"));
    }
    if asked == Some("off") {
        if !args.quiet {
            eprintln!("calibration band: off (--calibration-band off): every wear figure is the nominal constants' alone, with its sampling interval only");
        }
        return Ok(None);
    }
    if plan.wear.is_none() {
        if asked.is_some() {
            return Err(CliError(
                "--calibration-band: the run has no wear stage (--no-wear or `wear = false`), so there is no wear answer to band; leave the flag out".into(),
            ));
        }
        return Ok(None);
    }
    let Some((band, source)) = super::super::common::calibration_band(asked)? else {
        return Ok(None);
    };
    // The band's sets replace the run's own fitted constants: where the run gives its own (a
    // study's or --params' φ_s = 1), the headline is its own and the band the sets', said once.
    let own = polywear_core::wear::FittedConstants::of(&plan.study.base);
    let given = own.departures_from(&band.nominal().constants());
    if !args.quiet && !given.is_empty() {
        let words: Vec<String> = given
            .iter()
            .map(|(id, v, _)| format!("{id} = {}", polywear_core::wording::plain(*v, 6)))
            .collect();
        eprintln!(
            "note: the run's own {} is not the fitted constants'; the calibration band's sets replace it with each set's, so the band is the fit's range, and the headline figures are the run's (--calibration-band off gives those alone)",
            words.join(", ")
        );
    }
    band.check_scenarios(&plan.study, &source)
        .map_err(|e| match asked {
            Some(_) => CliError(format!("--calibration-band {e}")),
            None => CliError(format!("the calibration band (by default) {e}")),
        })?;
    Ok(Some(BandChoice { band, source }))
}

/// How the band's pass ended.
pub enum BandEnd {
    /// Written (or nothing to write on this shard).
    Written,
    /// Stopped by this signal between batches: the band stays pending.
    Stopped(i32),
}

/// Marks the run's band as asked for and unfinished before any chunk is run, so that a run
/// stopped anywhere before the band is whole leaves a band `analyze` refuses with the command
/// that finishes it; a run without a band removes an earlier session's. Only the shard that
/// owns chunk 0 writes the band.
pub fn prepare(plan: &RunPlan, choice: Option<&BandChoice>) -> CliResult {
    if !plan.shard.owns(0) {
        return Ok(());
    }
    match (choice, plan.wear.as_ref()) {
        (Some(c), Some(_)) => {
            polywear_study::calibration_band::evaluate::mark_pending(&plan.out_dir, &c.source)
                .map_err(|e| CliError(format!("cannot write the calibration band: {e}")))
        }
        _ => clear(plan),
    }
}

/// The band's pass after a finished run: the subsample re-evaluated under every set, written
/// to the output directory. Only the shard that owns chunk 0 writes it (every shard would
/// write the same rows). A signal stops it between batches; a file that cannot be written ends
/// the run with the command that finishes the band.
pub fn run(
    args: &ExploreArgs,
    plan: &RunPlan,
    choice: &BandChoice,
    pool: &rayon::ThreadPool,
    stop: &Interrupt,
) -> CliResult<BandEnd> {
    let Some(stage) = plan.wear.as_ref() else {
        return Ok(BandEnd::Written);
    };
    if !plan.shard.owns(0) {
        return Ok(BandEnd::Written);
    }
    let band_plan = BandPlan {
        study: &plan.study,
        seed: plan.seed,
        samples: plan.samples,
        band_samples: args.band_samples.unwrap_or(DEFAULT_BAND_SAMPLES),
        stage,
        band: &choice.band,
        band_source: choice.source.clone(),
    };
    let n = band_plan.indices().len() as u64;
    if !args.quiet {
        eprintln!(
            "calibration band: {} calibrated sets ({}) on {n} of the samples",
            choice.band.sets.len(),
            choice.source
        );
    }
    let progress = Progress::new(
        args.quiet,
        n,
        "band samples",
        Duration::from_secs_f64(args.log_every),
    );
    let written = pool.install(|| {
        band_plan.write(
            &plan.out_dir,
            plan.chunk_metadata(0).to_key_values(),
            &|k| progress.add(k),
            &|| stop.signal().is_some(),
        )
    });
    progress.finish();
    match written {
        Ok(_) => Ok(BandEnd::Written),
        Err(BandWriteError::Stopped) => Ok(BandEnd::Stopped(stop.signal().unwrap_or(0))),
        Err(BandWriteError::Io(e)) => {
            let cause = if e.contains("No space left") {
                "the disk is full: "
            } else {
                ""
            };
            Err(CliError(format!(
                "{cause}cannot write the calibration band: {e}
every sample's rows are saved in {}; the band is not finished: free space or fix the folder, then finish it with: {}",
                plan.out_dir.display(),
                super::resume::resume_command(args, plan)
            )))
        }
    }
}

/// A run without a band (`--calibration-band off`) leaves no band of an earlier session of it
/// in its directory, so that its report is the answer asked for.
fn clear(plan: &RunPlan) -> CliResult {
    use polywear_study::calibration_band::evaluate::{BAND_DIGEST, BAND_FILE};
    for name in [BAND_DIGEST, BAND_FILE] {
        let path = plan.out_dir.join(name);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(CliError(format!("{}: {e}", path.display())))
            }
            _ => {}
        }
    }
    Ok(())
}
