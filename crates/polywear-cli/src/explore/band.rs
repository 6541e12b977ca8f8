//! `explore`'s calibration band: `--calibration-band` and `--band-samples` resolved into the
//! sets and the subsample before any work, then the band's pass after the run's chunks.

use std::time::Duration;

use super::super::batch::Progress;
use super::super::common::{CliError, CliResult};
use super::ExploreArgs;
use polywear_study::calibration_band::evaluate::BandPlan;
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
    let choice = super::super::common::calibration_band(asked)?
        .map(|(band, source)| BandChoice { band, source });
    Ok(choice)
}

/// The band's pass after a finished run: the subsample re-evaluated under every set, written
/// to the output directory. Only the shard that owns chunk 0 writes it (every shard would
/// write the same rows).
pub fn run(
    args: &ExploreArgs,
    plan: &RunPlan,
    choice: &BandChoice,
    pool: &rayon::ThreadPool,
) -> CliResult {
    let Some(stage) = plan.wear.as_ref() else {
        return Ok(());
    };
    if !plan.shard.owns(0) {
        return Ok(());
    }
    let band_plan = BandPlan {
        study: &plan.study,
        seed: plan.seed,
        samples: plan.samples,
        band_samples: args.band_samples,
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
        )
    });
    progress.finish();
    written.map_err(|e| CliError(format!("cannot write the calibration band: {e}")))?;
    Ok(())
}

/// A run without a band (`--calibration-band off`) leaves no band of an earlier session of it
/// in its directory, so that its report is the answer asked for.
pub fn clear(plan: &RunPlan) -> CliResult {
    use polywear_study::calibration_band::evaluate::{BAND_DIGEST, BAND_FILE};
    if !plan.shard.owns(0) {
        return Ok(());
    }
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
