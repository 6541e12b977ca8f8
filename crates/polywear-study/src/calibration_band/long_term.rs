//! `wear`'s verdict under the calibrated sets: the long-term loop (MODEL.md#the-long-term-loop)
//! run again with each chosen set's constants, on the same point, legs and seed.
//!
//! The loop cannot take a set in closed form (its profile feeds back on itself over the whole
//! distance), so every set costs one more run. By default the sets run are the band's ends *at
//! this point* as the per-sample estimator ranks them (for each wheel the set with the shortest
//! and the one with the longest distance, or tread life where no polygon grows), a few runs;
//! [`LoopSets::All`] runs every set. The estimator and the loop agree within their measured
//! error, not exactly, so the loop's own extremes may lie at other sets: `All` is the check.

use polywear_core::classify::budget::Meter;
use polywear_core::evaluate::WearStage;
use polywear_core::long_term::wheel_loop::Leg;
use polywear_core::long_term::{self, LongTermError, LongTermProblem, LongTermSolution};
use polywear_core::params::Params;
use polywear_core::wear::estimator::{SaturatedSteps, SLIDING_MODULATION_MAX};
use polywear_core::wear::{FittedConstants, LifeAnswer, WearSettings, WheelGrowth};

use rayon::prelude::*;

use super::CalibrationBand;

/// Which sets the loop runs under.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoopSets {
    /// For each wheel, the sets at the two ends of the estimator's band at this point.
    Ends,
    /// Every set.
    All,
}

impl LoopSets {
    /// Its name, as `--band-sets` takes it.
    pub fn as_str(self) -> &'static str {
        match self {
            LoopSets::Ends => "ends",
            LoopSets::All => "all",
        }
    }
}

/// One set's run.
#[derive(Debug, Clone)]
pub struct SetRun {
    /// The set's index in the band.
    pub set: usize,
    /// Why it was run: "every set", or the wheel and end of the estimator's band it holds.
    pub chosen_as: String,
    /// Both wheels' loops under it.
    pub solution: LongTermSolution,
}

/// The sets `which` asks for at the point of `run` (the loop under the run's own constants),
/// in band order, each with why it was chosen.
pub fn chosen(
    band: &CalibrationBand,
    which: LoopSets,
    problem: &LongTermProblem,
    run: &LongTermSolution,
) -> Result<Vec<(usize, String)>, LongTermError> {
    if which == LoopSets::All {
        return Ok((0..band.sets.len())
            .map(|k| (k, "every set".to_string()))
            .collect());
    }
    let p = &problem.params;
    let stage = WearStage::for_run(
        p,
        problem.variant,
        WearSettings {
            zone: problem.settings.zone,
            power: problem.settings.power,
        },
        &problem.classifier,
    )?;
    let constants: Vec<FittedConstants> = band
        .sets
        .iter()
        .map(|s| FittedConstants::of(&s.constants().applied_to(p)))
        .collect();
    let mut picked: Vec<(usize, String)> = Vec::new();
    for w in &run.wheels {
        // A cruise's sets are ranked by the point's answer; a drive cycle's by its legs'
        // answers (each leg saturating on its own), since the point is not what it drives.
        let answers: Vec<LifeAnswer> = if problem.is_cruise() {
            let Ok(growth) = WheelGrowth::new(
                &stage.problem(p, &w.solution),
                &Meter::new(problem.classifier.budget),
            ) else {
                continue;
            };
            growth.answers_on(&constants)
        } else {
            let legs = long_term::leg_profiles(
                p,
                problem.variant,
                w.wheel,
                &problem.legs,
                &stage,
                &problem.classifier,
            );
            if legs.is_empty() {
                continue;
            }
            let steps = SaturatedSteps::new(legs);
            constants
                .iter()
                .map(|c| steps.answer(c, p, SLIDING_MODULATION_MAX))
                .collect()
        };
        // Ranked by the distance to a visible polygon, then (where none grows, as at most
        // points) by the tread's life: the band's ends are then the tire's shortest and
        // longest life.
        let order = |a: &usize, b: &usize| {
            let (x, y) = (&answers[*a], &answers[*b]);
            x.distance_to_visible_km
                .total_cmp(&y.distance_to_visible_km)
                .then(x.tread_life_km.total_cmp(&y.tread_life_km))
        };
        let valid: Vec<usize> = (0..answers.len())
            .filter(|&k| !answers[k].distance_to_visible_km.is_nan())
            .collect();
        let lowest = valid.iter().copied().min_by(order);
        let highest = valid.iter().copied().max_by(order);
        for (k, end) in [(lowest, "shortest"), (highest, "longest")] {
            let Some(k) = k else { continue };
            let why = format!("{}'s {end} estimate", w.wheel);
            match picked.iter_mut().find(|(j, _)| *j == k) {
                Some((_, said)) => {
                    said.push_str(", ");
                    said.push_str(&why);
                }
                None => picked.push((k, why)),
            }
        }
    }
    picked.sort_by_key(|(k, _)| *k);
    Ok(picked)
}

/// Runs the loop under each of `sets` (from [`chosen`]), the point's constants replaced by the
/// set's and its legs from `legs` (a cruise's follow the set's speed spread; a cycle's do not);
/// `progress` is called with the kilometres run.
pub fn run(
    band: &CalibrationBand,
    sets: &[(usize, String)],
    problem: &LongTermProblem,
    legs: &(dyn Fn(&Params) -> Vec<Leg> + Sync),
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Vec<SetRun>, LongTermError> {
    // The sets in parallel (each runs its two wheels in parallel too); the order is the band's.
    sets.par_iter()
        .map(|(k, why)| {
            let p = band.sets[*k].constants().applied_to(&problem.params);
            let set_problem = LongTermProblem::new(
                p,
                problem.variant,
                legs(&p),
                problem.settings.clone(),
                problem.classifier,
            )?;
            Ok(SetRun {
                set: *k,
                chosen_as: why.clone(),
                solution: long_term::solve(&set_problem, progress)?,
            })
        })
        .collect()
}
