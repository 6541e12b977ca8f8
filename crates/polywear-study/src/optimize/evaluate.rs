//! Evaluating settings: each setting's changes applied to every one of the study's samples (the
//! same draws for every setting), both wheels classified as explore classifies a sample, and
//! each sample's outcomes kept for the objective, the constraints and the paired differences.

use polywear_core::ensemble::{self, Control};

use super::objective::{Estimate, Objective, Outcomes, Term, UNKNOWN};
use super::search::{search, Value};
use super::{collect, Problem, SetEstimate, Setting, Solution};
use crate::calibration_band::evaluate::subsample;
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
use polywear_core::wear::{FittedConstants, LifeAnswer, WheelGrowth};

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
    // The samples the sets are evaluated on: every one, or the band's subsample, the same for
    // every setting (MODEL.md#the-calibration-band).
    let band_samples = problem.band.as_ref().map_or(n as u64, |b| b.samples);
    let subsample: Vec<usize> = subsample(problem.seed, n as u64, band_samples)
        .into_iter()
        .map(|i| i as usize)
        .collect();
    let every = subsample.len() == n;
    let mut in_band = vec![false; n];
    for &i in &subsample {
        in_band[i] = true;
    }
    let set_count = sets.as_ref().map_or(0, Vec::len);
    let mut settings: Vec<Setting> = Vec::new();
    let mut eval = |units: &[Vec<f64>], level: usize| -> Vec<Value> {
        (progress.level)(level, (units.len() * n) as u64);
        let values = setting_values(problem, units);
        let changes = setting_changes(problem, &values);
        let outcome = |j: usize| {
            let sets = sets.as_deref().filter(|_| in_band[j % n]);
            sample_outcomes(problem, base[j % n], &changes[j / n], sets, wear)
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
            let band = set_estimates(problem, o, b, &subsample, every, set_count);
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

/// The value of each varied parameter at each setting of `units` (points of the unit box), in
/// axis order.
fn setting_values(problem: &Problem, units: &[Vec<f64>]) -> Vec<Vec<f64>> {
    units
        .iter()
        .map(|u| {
            problem
                .axes
                .iter()
                .zip(u)
                .map(|(a, &x)| a.value(x))
                .collect()
        })
        .collect()
}

/// The changes to a sample's parameters that make each setting of `values`.
fn setting_changes(problem: &Problem, values: &[Vec<f64>]) -> Vec<Vec<ParamChange>> {
    values
        .iter()
        .map(|v| {
            problem
                .axes
                .iter()
                .zip(v)
                .map(|(a, &x)| a.change(x))
                .collect()
        })
        .collect()
}

/// One sample `p` under one setting's `changes`: its outcomes, and under each calibrated set
/// of `sets` (where the sample is in the band's subsample and the run has a wear stage) its
/// outcomes under that set's constants; without them, no set's outcomes. `wear`: whether the
/// objective or a constraint reads the wear outcome.
fn sample_outcomes(
    problem: &Problem,
    mut p: Params,
    changes: &[ParamChange],
    sets: Option<&[FittedConstants]>,
    wear: bool,
) -> (Outcomes, Box<[Outcomes]>) {
    for c in changes {
        p[c.param] = c.change.apply(p[c.param]);
    }
    match (sets, problem.wear.as_ref()) {
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
}

/// A setting's objective and feasibility under each of the `set_count` calibrated sets, from
/// its samples' outcomes `o` and their outcomes under each set `b`: judged on the sets' own
/// outcomes where every sample is in the band (`every`), else the run's figure moved by each
/// set's difference from it on the `subsample` (a control variate).
fn set_estimates(
    problem: &Problem,
    o: &[Outcomes],
    b: &[Box<[Outcomes]>],
    subsample: &[usize],
    every: bool,
    set_count: usize,
) -> Vec<SetEstimate> {
    let run_sub: Vec<Outcomes> = if every {
        Vec::new()
    } else {
        subsample.iter().map(|&i| o[i]).collect()
    };
    (0..set_count)
        .map(|k| {
            if every {
                let under: Vec<Outcomes> = b.iter().map(|x| x[k]).collect();
                let (objective, _, feasible) = judged(problem, &under);
                return SetEstimate {
                    objective,
                    feasible,
                };
            }
            let set_sub: Vec<Outcomes> = subsample.iter().map(|&i| b[i][k]).collect();
            let shifted = |objective: &Objective| control_variate(objective, o, &run_sub, &set_sub);
            SetEstimate {
                objective: shifted(&problem.objective),
                feasible: problem
                    .constraints
                    .iter()
                    .all(|c| c.holds(&shifted(&c.objective()))),
            }
        })
        .collect()
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

/// An objective under a calibrated set from a subsample (a control variate): its value under
/// the run's own constants on every sample, `all`, plus the set's paired difference from them on
/// the subsample (`set_sub` against `run_sub`, the same samples in order), clamped to the
/// scores' range. Each end of the interval adds the two intervals' half-widths on its side in
/// quadrature. NaN where either part has no known score.
fn control_variate(
    objective: &Objective,
    all: &[Outcomes],
    run_sub: &[Outcomes],
    set_sub: &[Outcomes],
) -> Estimate {
    let e = objective.estimate(all);
    let (d, lo, hi) = objective.paired_difference(set_sub, run_sub);
    let top: f64 = objective.terms.iter().map(|t| t.0).sum();
    let value = (e.value + d).clamp(0.0, top);
    if value.is_nan() {
        return Estimate {
            value: f64::NAN,
            low: f64::NAN,
            high: f64::NAN,
            n: e.n,
        };
    }
    Estimate {
        value,
        low: (value - (e.value - e.low).hypot(d - lo)).max(0.0),
        high: (value + (e.high - e.value).hypot(hi - d)).min(top),
        n: e.n,
    }
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
            WheelGrowth::new(&stage.problem(p, w), &Meter::new(problem.classifier.budget)).ok();
        let answers = match &growth {
            Some(g) => g.answers_on(&constants),
            None => vec![LifeAnswer::UNKNOWN; constants.len()],
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::objective::{WheelChoice, NO, YES};
    use polywear_core::model::Wheel;

    fn wear(code: u8) -> Outcomes {
        Outcomes::default().with(Term::Wear, Wheel::Follower, code)
    }

    /// The control variate: a set that changes no sample is the run's own estimate on every
    /// sample; over a subsample of every sample it is the set's own value; its interval holds
    /// its value, and it stays in the scores' range.
    #[test]
    fn a_set_s_objective_is_the_run_s_plus_its_paired_difference() {
        let objective = Objective {
            terms: vec![(1.0, Term::Wear)],
            wheel: WheelChoice::Follower,
        };
        let all: Vec<Outcomes> = (0..1000).map(|i| wear(u8::from(i % 10 == 0))).collect();
        let sub: Vec<usize> = (0..1000).step_by(5).collect();
        let run_sub: Vec<Outcomes> = sub.iter().map(|&i| all[i]).collect();
        let same = control_variate(&objective, &all, &run_sub, &run_sub);
        assert_eq!(same.value, objective.estimate(&all).value);
        assert!(same.low <= same.value && same.value <= same.high);
        // A set that adds a polygon to every fourth sample.
        let every_fourth = |outcomes: &[Outcomes]| -> Vec<Outcomes> {
            outcomes
                .iter()
                .enumerate()
                .map(|(k, o)| if k % 4 == 0 { wear(YES) } else { *o })
                .collect()
        };
        let set_sub = every_fourth(&run_sub);
        let moved = control_variate(&objective, &all, &run_sub, &set_sub);
        let d = objective.paired_difference(&set_sub, &run_sub).0;
        assert!((moved.value - (0.1 + d)).abs() < 1e-12, "{moved:?}");
        assert!(moved.low < moved.value && moved.value < moved.high);
        // The subsample is every sample: the set's own value.
        let set_all = every_fourth(&all);
        let whole = control_variate(&objective, &all, &all, &set_all);
        assert!((whole.value - objective.estimate(&set_all).value).abs() < 1e-12);
        // Clamped to [0, 1]: a set that clears every polygon of a subsample richer in them.
        let rich: Vec<Outcomes> = (0..100).map(|_| wear(YES)).collect();
        let none: Vec<Outcomes> = (0..100).map(|_| wear(NO)).collect();
        let clamped = control_variate(&objective, &all, &rich, &none);
        assert_eq!(clamped.value, 0.0);
        assert_eq!(clamped.low, 0.0);
        // Nothing known: NaN.
        let unknown: Vec<Outcomes> = (0..10).map(|_| wear(UNKNOWN)).collect();
        assert!(control_variate(&objective, &all, &unknown, &unknown)
            .value
            .is_nan());
    }
}
