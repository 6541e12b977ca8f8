//! The long-term loop, the wear stage's brute-force check, in its one home
//! (MODEL.md#the-long-term-loop): one operating point driven over a distance on both wheels,
//! `LongTermProblem` → [`solve`] → [`LongTermSolution`], above [`crate::evaluate`] (each wheel
//! starts from its verdict). One file per job: [`wheel_loop`] (the loop of one wheel),
//! [`profile`] (the worn depth on cells, the seed), [`window`] (a few revolutions at a fixed
//! profile), [`lock`] (the rotation number and the weights of the mean revolution), [`deposit`]
//! (the energy laid element by element), [`edge`] (how finely a lock edge is placed),
//! [`first_step`] (the revolutions the first step integrates), [`wheel_wear`] (what the loop
//! found for one wheel), [`tongue`] (the lock-in tongue at the end of a run), and the columns
//! and figures of a solution. Built on the wear physics and response
//! ([`crate::wear::physics`], [`crate::wear::response`]).

use crate::classify::budget::Meter;
use crate::classify::{Class, ClassifierOptions};
use crate::ensemble::{self, Control};
use crate::evaluate::{self, PointProblem, WearStage, WheelSolution};
use crate::long_term::profile::SEED_ORDERS;
use crate::long_term::wheel_loop::{
    cruise_legs, first_step_tread_s, run_wheel, slowest_cruise_kmh, Leg, LoopInputs, LoopSettings,
    WheelWear, FEEDBACK_ORDERS, FIRST_STEP_REVS, MAX_FIRST_STEP_TREAD_S,
};
use crate::model::{ModelFailure, Variant, Wheel};
use crate::params::{ParamId, Params};
use crate::wear::estimator::{answer_saturated_per_step, SLIDING_MODULATION_MAX};
use crate::wear::{
    FittedConstants, LifeAnswer, LifeProfile, WearError, WearSettings, WheelGrowth,
    LIFE_PROFILE_INTERVALS,
};
use tongue::{Tongue, TongueRequest};

mod columns;
pub mod deposit;
pub mod edge;
mod figures;
pub mod first_step;
pub mod lock;
pub mod profile;
mod step_rule;
pub mod tongue;
pub mod wheel_loop;
pub mod wheel_wear;
pub mod window;
pub use figures::LongTermFigures;

/// The largest distance a long-term problem accepts \[km\].
pub(crate) const MAX_DISTANCE_KM: f64 = 1e6;

/// Why a long-term problem was refused before any work.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LongTermError {
    /// The distance is outside (0, `MAX_DISTANCE_KM`].
    #[error("distance_km = {0} is outside its accepted range (0, 1e6] km")]
    Distance(f64),
    /// No leg to drive, or a leg whose speed or share is not positive and finite.
    #[error("the usage has no legs, or a leg without a positive speed and share")]
    Legs,
    /// A leg's speed outside the accepted range of `speed_kmh` (a speed spread too wide for
    /// the speed).
    #[error(
        "a leg drives at {speed_kmh} km/h, outside the accepted range of speed_kmh {range} km/h"
    )]
    LegSpeed {
        /// The leg's speed \[km/h\].
        speed_kmh: f64,
        /// The accepted range, as `polywear params` writes it.
        range: String,
    },
    /// A usage so slow that the loop's first step alone would integrate more tread time than
    /// [`MAX_FIRST_STEP_TREAD_S`] (each revolution of 2π r_B / V is integrated, at any
    /// distance).
    #[error(
        "the slowest leg drives at {slowest} km/h: the wear loop's first step integrates {revs} revolutions at each of its {legs} legs, {tread_s:.3e} s of tread time, over the {limit_s} s it accepts; accepted: speeds whose first step fits, a single speed of at least {min} km/h",
        slowest = crate::wording::plain(*slowest_kmh, 6),
        min = crate::wording::plain(*min_kmh, 3),
        revs = FIRST_STEP_REVS,
        limit_s = MAX_FIRST_STEP_TREAD_S
    )]
    TooSlow {
        /// The slowest leg's speed \[km/h\].
        slowest_kmh: f64,
        /// The number of legs.
        legs: usize,
        /// The tread time the first step integrates \[s\].
        tread_s: f64,
        /// The slowest speed a cruise with one leg is accepted at \[km/h\].
        min_kmh: f64,
    },
    /// The wear stage could not be calibrated (MODEL.md#step-10-wear-law).
    #[error(transparent)]
    Stage(#[from] WearError),
}

/// One operating point and its usage, both wheels, over a distance.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct LongTermProblem {
    /// The point's parameters (each leg drives its own speed).
    pub params: Params,
    /// The friction variant of both wheels.
    pub variant: Variant,
    /// The speeds driven and their shares of the distance.
    pub legs: Vec<Leg>,
    /// The loop's steps, cells, seed, wear zone and distance.
    pub settings: LoopSettings,
    /// The classifier that gives each wheel its start (its cycle where it vibrates).
    pub classifier: ClassifierOptions,
}

impl LongTermProblem {
    /// A problem whose distance and legs are checked.
    pub fn new(
        params: Params,
        variant: Variant,
        legs: Vec<Leg>,
        settings: LoopSettings,
        classifier: ClassifierOptions,
    ) -> Result<Self, LongTermError> {
        check_distance_km(settings.distance_km)?;
        let good = |x: f64| x.is_finite() && x > 0.0;
        if legs.is_empty() || !legs.iter().all(|l| good(l.share)) {
            return Err(LongTermError::Legs);
        }
        let spec = ParamId::SpeedKmh.spec();
        if let Some(l) = legs.iter().find(|l| spec.check(l.speed_kmh).is_err()) {
            return Err(LongTermError::LegSpeed {
                speed_kmh: l.speed_kmh,
                range: spec.range_text(),
            });
        }
        // The work the first step needs is known from the speeds alone: refused before any work
        // (MODEL.md#the-long-term-loop).
        let tread_s = first_step_tread_s(&legs, params.r_b);
        if tread_s.is_nan() || tread_s > MAX_FIRST_STEP_TREAD_S {
            return Err(LongTermError::TooSlow {
                slowest_kmh: legs.iter().fold(f64::INFINITY, |m, l| m.min(l.speed_kmh)),
                legs: legs.len(),
                tread_s,
                min_kmh: slowest_cruise_kmh(1, params.r_b),
            });
        }
        Ok(LongTermProblem {
            params,
            variant,
            legs,
            settings,
            classifier,
        })
    }

    /// Whether the legs are a cruise at the point's speed with its speed spread (the point's
    /// per-sample estimates answer for it), not a drive cycle's speeds (whose estimates are
    /// the legs' own, MODEL.md#along-a-drive-cycle).
    pub fn is_cruise(&self) -> bool {
        let p = &self.params;
        self.legs == cruise_legs(p.speed_kmh, p.speed_spread_kmh, self.legs.len())
    }
}

/// The distance rule of [`LongTermProblem::new`] on its own, for a caller that refuses a bad
/// distance before it builds the legs: (0, `MAX_DISTANCE_KM`] km.
pub fn check_distance_km(km: f64) -> Result<(), LongTermError> {
    if km > 0.0 && km <= MAX_DISTANCE_KM {
        Ok(())
    } else {
        Err(LongTermError::Distance(km))
    }
}

/// Why a wheel has no long-term run, or no tongue.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WheelRunFailure {
    /// The wheel has no tread ODE.
    #[error("{0}")]
    Model(ModelFailure),
    /// The wheel has an ODE but no traction or no verdict to start from.
    #[error("{class}: {reason}")]
    Verdict {
        /// Its class.
        class: Class,
        /// Why.
        reason: String,
    },
    /// The loop, or the tongue's measurement, could not integrate.
    #[error("{0}")]
    Loop(WearError),
    /// No run, so no tongue to measure.
    #[error("no run")]
    NoRun,
}

/// One wheel's verdict, its estimate and its loop.
#[derive(Debug, Clone)]
pub struct WheelLongTerm {
    /// Which wheel.
    pub wheel: Wheel,
    /// The point's evaluation of this wheel: its verdict and the per-sample estimate.
    pub solution: WheelSolution,
    /// The loop's history and profiles, or why there is none.
    pub run: Result<WheelWear, WheelRunFailure>,
    /// The lock-in tongue measured at the end where a leg is locked (`None` where none is),
    /// or why it could not be.
    pub tongue: Result<Option<Tongue>, WheelRunFailure>,
    /// The one wear answer (MODEL.md#the-forced-response-saturates): for a cruise the point's,
    /// its speed spread on the estimator's own legs; for a drive cycle the cycle's legs', each
    /// saturating on its own; `None` where the wheel has no wear figures.
    pub estimate: Option<LifeAnswer>,
    /// The same reading on the loop's own legs, each leg's print saturating on its own: for a
    /// cruise the check that the estimator's legs stand for the loop's; `None` where no leg has
    /// wear figures.
    pub on_legs: Option<LifeAnswer>,
}

/// Both wheels' runs, in [`Wheel::BOTH`] order.
#[derive(Debug, Clone)]
pub struct LongTermSolution {
    /// The point's parameters.
    pub params: Params,
    /// Whether the legs are a cruise at the point ([`LongTermProblem::is_cruise`]), not a drive
    /// cycle's speeds.
    pub cruise: bool,
    /// One per wheel.
    pub wheels: Vec<WheelLongTerm>,
}

/// Runs both wheels in parallel, each from its verdict's cycle where it vibrates; `progress`
/// is called with the kilometres just run. The wear stage is calibrated first (a refused
/// calibration is the one error: a wheel that cannot run is an answer, not an error).
pub fn solve(
    problem: &LongTermProblem,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<LongTermSolution, LongTermError> {
    let p = problem.params;
    let settings = &problem.settings;
    let stage = WearStage::for_run(
        &p,
        problem.variant,
        WearSettings {
            zone: settings.zone,
            power: settings.power,
        },
        &problem.classifier,
    )?;
    let gamma = stage.calibration.gamma_m3_per_j(&p);
    let variants = [problem.variant];
    let point = evaluate::solve(
        &PointProblem::new(p, &variants, &problem.classifier).with_wear(Some(&stage)),
    );
    // Each wheel runs at its own axle's values (MODEL.md#the-car-axles-and-drivetrain).
    let at_wheel = Wheel::BOTH.map(|w| p.at_wheel(w));
    let runs = ensemble::solve(
        2,
        |i| {
            let w = &point.wheels[i];
            let inputs = LoopInputs {
                params: &at_wheel[i],
                wheel: Wheel::BOTH[i],
                variant: problem.variant,
                gamma_m3_per_j: gamma,
                legs: &problem.legs,
                start: start_of(w),
            };
            match &w.model {
                Ok(_) if !matches!(w.verdict.class, Class::NoTraction | Class::Failed) => {
                    run_wheel(&inputs, settings, progress)
                        .map(|run| {
                            let tongue = measured_tongue(&run, &inputs, settings);
                            (run, tongue)
                        })
                        .map_err(WheelRunFailure::Loop)
                }
                Ok(_) => Err(WheelRunFailure::Verdict {
                    class: w.verdict.class,
                    reason: w.verdict.reason.clone(),
                }),
                Err(e) => Err(WheelRunFailure::Model(e.clone())),
            }
        },
        &Control {
            progress: &|_| {},
            stop: &|| false,
        },
    )
    .all();
    let wheels = point
        .wheels
        .into_iter()
        .zip(runs)
        .enumerate()
        .map(|(i, (solution, outcome))| {
            let (run, tongue) = match outcome {
                Ok((run, tongue)) => (Ok(run), tongue),
                Err(e) => (Err(e), Err(WheelRunFailure::NoRun)),
            };
            let growth = WheelGrowth::new(
                &stage.problem(&at_wheel[i], &solution),
                &Meter::new(problem.classifier.budget),
            )
            .ok();
            let c = FittedConstants::of(&p);
            let on_legs = saturated_on_legs(problem, &stage, Wheel::BOTH[i]);
            let estimate = if problem.is_cruise() {
                // Past the wheel's wall-clock limit the answer is unknown (NaN), never partial.
                growth.as_ref().map(|g| g.saturated_answer(&c))
            } else {
                // A drive cycle's answer is its speeds', not the point's.
                on_legs
            };
            WheelLongTerm {
                wheel: Wheel::BOTH[i],
                solution,
                run,
                tongue,
                estimate,
                on_legs,
            }
        })
        .collect();
    Ok(LongTermSolution {
        params: p,
        cruise: problem.is_cruise(),
        wheels,
    })
}

/// The answer over the tread's life of `wheel` on the problem's legs, each leg's print
/// saturating on its own (MODEL.md#the-forced-response-saturates); `None` where no leg has wear
/// figures.
fn saturated_on_legs(
    problem: &LongTermProblem,
    stage: &WearStage,
    wheel: Wheel,
) -> Option<LifeAnswer> {
    let p = problem.params;
    let profiles = leg_profiles(
        &p,
        problem.variant,
        wheel,
        &problem.legs,
        stage,
        &problem.classifier,
    );
    if profiles.is_empty() {
        return None;
    }
    let steps: Vec<(f64, &LifeProfile)> = profiles.iter().map(|(a, pr)| (*a, pr)).collect();
    Some(answer_saturated_per_step(
        &steps,
        &FittedConstants::of(&p),
        &p,
        SLIDING_MODULATION_MAX,
    ))
}

/// Each leg's share and the life profile of `wheel` at the leg's own speed with no further
/// spread, orders 1..=`SEED_ORDERS` (the point `p` solved there, with its own work budget, as
/// each point of a run has); legs without wear figures are left out. What a reading per leg,
/// such as [`answer_saturated_per_step`], sums.
pub fn leg_profiles(
    p: &Params,
    variant: Variant,
    wheel: Wheel,
    legs: &[Leg],
    stage: &WearStage,
    classifier: &ClassifierOptions,
) -> Vec<(f64, LifeProfile)> {
    legs.iter()
        .filter_map(|leg| {
            let at = Params {
                speed_kmh: leg.speed_kmh,
                speed_spread_kmh: 0.0,
                ..p.at_wheel(wheel)
            };
            let w = evaluate::solve_wheel(at, variant, wheel, classifier);
            let growth =
                WheelGrowth::new(&stage.problem(&at, &w), &Meter::new(classifier.budget)).ok()?;
            let profile = growth.life_profile(SEED_ORDERS as u32, LIFE_PROFILE_INTERVALS);
            // Past the wheel's wall-clock limit the leg has no figures.
            growth
                .out_of_time()
                .is_none()
                .then_some((leg.share, profile))
        })
        .collect()
}

/// The state the loop starts a wheel from: on the classifier's cycle where it vibrates.
fn start_of(w: &WheelSolution) -> Option<[f64; 3]> {
    let m = w.model.as_ref().ok()?;
    let v = &w.verdict;
    (v.class.vibrates() && v.section_v_mps > 0.0)
        .then(|| [v.section_z_m, m.ode.equilibrium()[1], v.section_v_mps])
}

/// The lock-in tongue at the run's end, measured at its final profile around its locked leg
/// ([`tongue`]); `None` where no leg is locked at the end.
fn measured_tongue(
    run: &WheelWear,
    inputs: &LoopInputs<'_>,
    settings: &LoopSettings,
) -> Result<Option<Tongue>, WheelRunFailure> {
    let Some((leg, speed_kmh, order)) = run.locked_leg() else {
        return Ok(None);
    };
    let (Some(start), Some((_, depth_m))) = (run.end_states[leg], run.profiles.last()) else {
        return Ok(None);
    };
    tongue::measure(&TongueRequest {
        params: inputs.params,
        wheel: inputs.wheel,
        variant: inputs.variant,
        zone: settings.zone,
        depth_m,
        tread_height_m: run.end().tread_height_m,
        start,
        locked: (speed_kmh, order),
        orders: FEEDBACK_ORDERS,
        rtol: settings.rtol,
    })
    .map_err(WheelRunFailure::Loop)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_problem_refuses_a_distance_or_legs_it_cannot_drive() {
        let leg = |speed_kmh, share| Leg { speed_kmh, share };
        let new = |km: f64, legs: Vec<Leg>| {
            let settings = LoopSettings {
                distance_km: km,
                ..LoopSettings::default()
            };
            LongTermProblem::new(
                Params::default(),
                Variant::DEFAULT,
                legs,
                settings,
                ClassifierOptions::default(),
            )
        };
        assert!(new(60_000.0, vec![leg(110.0, 1.0)]).is_ok());
        for km in [0.0, -1.0, f64::NAN, 2e6] {
            let e = new(km, vec![leg(110.0, 1.0)]).unwrap_err();
            assert!(matches!(e, LongTermError::Distance(_)), "{km}: {e}");
            assert!(e.to_string().contains("(0, 1e6]"), "{e}");
        }
        for legs in [vec![], vec![leg(110.0, f64::NAN)], vec![leg(110.0, 0.0)]] {
            assert_eq!(new(1e3, legs).unwrap_err(), LongTermError::Legs);
        }
        // A leg outside the speed's accepted range, as a too wide spread gives.
        for speed in [0.0, -5.0, 401.0, f64::NAN] {
            let e = new(1e3, vec![leg(100.0, 0.5), leg(speed, 0.5)]).unwrap_err();
            assert!(matches!(e, LongTermError::LegSpeed { .. }), "{speed}: {e}");
            assert!(e.to_string().contains("(0, 400]"), "{e}");
        }
        // A usage whose first step alone integrates over an hour of tread time.
        for speed in [0.01, 1e-300] {
            let e = new(1.0, vec![leg(speed, 1.0)]).unwrap_err();
            assert!(matches!(e, LongTermError::TooSlow { .. }), "{speed}: {e}");
            assert!(e.to_string().contains("3600 s"), "{e}");
        }
        let min = slowest_cruise_kmh(1, Params::default().r_b);
        assert!(new(1.0, vec![leg(min * 1.001, 1.0)]).is_ok());
        assert!(new(1.0, vec![leg(min * 0.999, 1.0)]).is_err());
    }
}
