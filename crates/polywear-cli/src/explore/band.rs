//! `explore`'s calibration band: `--calibration-band` and `--band-samples` resolved into the
//! sets before any work (the band's pass is the session's, `ExploreSession::run`).

use super::super::common::{CliError, CliResult};
use super::ExploreArgs;
use polywear_study::calibration_band::CalibrationBand;
use polywear_study::explore::{BandChoice, RunPlan};

/// The band the flags ask for: the shipped sets by default, a file's, or none (`off`, or a run
/// without the wear stage). A file that cannot be read or is refused stops the run here.
pub(crate) fn choose(args: &ExploreArgs, plan: &RunPlan) -> CliResult<Option<BandChoice>> {
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
    let Some((band, source)) = CalibrationBand::asked(asked)? else {
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
