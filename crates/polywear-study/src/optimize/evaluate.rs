//! Evaluating settings: each setting's changes applied to every one of the study's samples (the
//! same draws for every setting), both wheels classified as explore classifies a sample, and
//! each sample's outcomes kept for the objective, the constraints and the paired differences.

use polywear_core::ensemble::{self, Control};

use super::objective::{Estimate, Outcomes, Term, UNKNOWN};
use super::search::{search, Value};
use super::{collect, Problem, SetEstimate, Setting, Solution};
use crate::explore::evaluate_params;
use crate::parquet_out::ColumnData;
use crate::study::ParamChange;
use polywear_core::classify::budget::Meter;
use polywear_core::classify::outcome_code;
use polywear_core::evaluate::{self, PointProblem, WearStage};
use polywear_core::model::Wheel;
use polywear_core::params::Params;
use polywear_core::records::DISTANCE_COLUMN;
use polywear_core::records::{record_columns, WheelRecord, WEAR_COLUMNS};
use polywear_core::wear::{FittedConstants, WearAnswer, WheelGrowth};

/// Whether this build's rows carry the wear stage's distance to a visible polygon.
pub fn wear_available() -> bool {
    WEAR_COLUMNS.iter().any(|c| c.name == DISTANCE_COLUMN)
}

/// What the search reports as it goes.
pub struct Progress<'a> {
    /// A level starts: (level, sample evaluations it takes).
    pub level: &'a dyn Fn(usize, u64),
    /// Sample evaluations done since the last call.
    pub done: &'a (dyn Fn(u64) + Sync),
}

/// Runs the search of `problem`.
pub fn solve(problem: &Problem, progress: &Progress<'_>) -> Solution {
    let n = problem.samples as usize;
    let sampler = problem.study.sampler(problem.seed, problem.samples);
    let draw = |i: usize| sampler.sample_with_row(i as u64).0;
    let base: Vec<Params> = ensemble::solve(n, draw, &Control::QUIET).all();
    let wear =
        problem.objective.uses_wear() || problem.constraints.iter().any(|c| c.term == Term::Wear);
    // Each set's constants; a setting's own are the sample's (FittedConstants::of).
    let sets: Option<Vec<FittedConstants>> = problem
        .band
        .as_ref()
        .filter(|_| wear)
        .map(|b| b.sets.sets.iter().map(|c| c.constants()).collect());
    let mut settings: Vec<Setting> = Vec::new();
    let mut eval = |units: &[Vec<f64>], level: usize| -> Vec<Value> {
        (progress.level)(level, (units.len() * n) as u64);
        let values: Vec<Vec<f64>> = units
            .iter()
            .map(|u| {
                problem
                    .axes
                    .iter()
                    .zip(u)
                    .map(|(a, &x)| a.value(x))
                    .collect()
            })
            .collect();
        let changes: Vec<Vec<ParamChange>> = values
            .iter()
            .map(|v| {
                problem
                    .axes
                    .iter()
                    .zip(v)
                    .map(|(a, &x)| a.change(x))
                    .collect()
            })
            .collect();
        let outcome = |j: usize| {
            let mut p = base[j % n];
            for c in &changes[j / n] {
                p[c.param] = c.change.apply(p[c.param]);
            }
            match (&sets, problem.wear.as_ref()) {
                (Some(sets), Some(stage)) => banded_outcomes(problem, stage, &p, sets),
                _ => {
                    let records = evaluate_params(
                        &p,
                        &[problem.variant],
                        &problem.classifier,
                        problem.wear.as_ref(),
                    );
                    let o = outcomes_of(&records, wear.then_some(problem.within_km));
                    (o, Box::default())
                }
            }
        };
        let control = Control {
            progress: progress.done,
            stop: &|| false,
        };
        let (outcomes, band): (Vec<Outcomes>, Vec<Box<[Outcomes]>>) =
            ensemble::solve(units.len() * n, outcome, &control)
                .all()
                .into_iter()
                .unzip();
        let mut out = Vec::with_capacity(units.len());
        for (((unit, values), o), b) in units
            .iter()
            .zip(values)
            .zip(outcomes.chunks(n))
            .zip(band.chunks(n))
        {
            let (objective, constrained, feasible) = judged(problem, o);
            let set_count = b.first().map_or(0, |x| x.len());
            let band: Vec<SetEstimate> = (0..set_count)
                .map(|k| {
                    let under: Vec<Outcomes> = b.iter().map(|x| x[k]).collect();
                    let (objective, _, feasible) = judged(problem, &under);
                    SetEstimate {
                        objective,
                        feasible,
                    }
                })
                .collect();
            out.push(Value {
                value: objective.value,
                high: objective.high,
                feasible,
            });
            settings.push(Setting {
                values,
                unit: unit.clone(),
                level,
                objective,
                constrained,
                feasible,
                outcomes: o.to_vec(),
                band,
            });
        }
        out
    };
    let m = problem.search.lattice() as i64;
    let canonical = |k: &[i64]| -> Vec<i64> {
        problem
            .axes
            .iter()
            .zip(k)
            .map(|(a, &k)| a.canonical_index(k, m))
            .collect()
    };
    let points = search(problem.axes.len(), problem.search, &mut eval, &canonical);
    collect(&points, settings, &problem.objective)
}

/// A setting's objective, its constraints' estimates and whether they all hold, from its
/// samples' outcomes.
fn judged(problem: &Problem, o: &[Outcomes]) -> (Estimate, Vec<Estimate>, bool) {
    let objective = problem.objective.estimate(o);
    let constrained: Vec<Estimate> = problem
        .constraints
        .iter()
        .map(|c| c.objective().estimate(o))
        .collect();
    let feasible = problem
        .constraints
        .iter()
        .zip(&constrained)
        .all(|(c, e)| c.holds(e));
    (objective, constrained, feasible)
}

/// A sample's outcomes under its own constants and under each set of the band: the point
/// classified once, each wheel's closed loop solved once ([`WheelGrowth`]), then its answer
/// under every set's constants ([`WheelGrowth::answers_on`] its estimate level). The first is
/// the outcome the rows give (the band's `run` answer equals the row's, tested).
fn banded_outcomes(
    problem: &Problem,
    stage: &WearStage,
    p: &Params,
    sets: &[FittedConstants],
) -> (Outcomes, Box<[Outcomes]>) {
    let variants = [problem.variant];
    let solution = evaluate::solve(&PointProblem::new(*p, &variants, &problem.classifier));
    let constants: Vec<FittedConstants> = std::iter::once(FittedConstants::of(p))
        .chain(sets.iter().map(|c| FittedConstants::of(&c.applied_to(p))))
        .collect();
    let mut under = vec![Outcomes::default(); constants.len()];
    for w in &solution.wheels {
        let wheel = w.record.wheel;
        let vib = outcome_code(w.record.class) as u8;
        let growth =
            WheelGrowth::new(&stage.inputs(p, w), &Meter::new(problem.classifier.budget)).ok();
        let answers = match &growth {
            Some(g) => g.answers_on(stage.settings.estimate, &constants),
            None => vec![WearAnswer::UNKNOWN; constants.len()],
        };
        for (o, a) in under.iter_mut().zip(&answers) {
            let d = a.distance_to_visible_km;
            let code = if vib != UNKNOWN && !d.is_nan() {
                u8::from(d <= problem.within_km)
            } else {
                UNKNOWN
            };
            *o = o
                .with(Term::Vibration, wheel, vib)
                .with(Term::Wear, wheel, code);
        }
    }
    let run = under[0];
    (run, under[1..].into())
}

/// A sample's outcomes from its follower and driving records: vibration from the class
/// (MODEL.md#classes: a limit cycle or bistable; failed and no traction unknown), and,
/// with `within_km`, a visible polygon within it from the rows' distance (unknown where the
/// wheel has no verdict or the distance is undefined).
pub(crate) fn outcomes_of(records: &[WheelRecord], within_km: Option<f64>) -> Outcomes {
    let distances: Option<Vec<f64>> = within_km.and_then(|_| {
        record_columns(records)
            .into_iter()
            .find(|c| c.name == DISTANCE_COLUMN)
            .and_then(|c| match c.data {
                ColumnData::F64(v) => Some(v),
                _ => None,
            })
    });
    let mut o = Outcomes::default();
    for (k, r) in records.iter().enumerate() {
        let wheel = r.wheel;
        let vib = outcome_code(r.class) as u8;
        o = o.with(Term::Vibration, wheel, vib);
        let wear = match (&distances, within_km) {
            (Some(d), Some(km)) if vib != UNKNOWN && !d[k].is_nan() => u8::from(d[k] <= km),
            _ => UNKNOWN,
        };
        o = o.with(Term::Wear, wheel, wear);
    }
    debug_assert!(records.iter().map(|r| r.wheel).eq(Wheel::BOTH));
    o
}
