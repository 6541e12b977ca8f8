//! The one road for an operating point: a [`PointProblem`] (the parameters, which variants and
//! wheels, the classifier's options, the cycles of a neighbouring point) goes to [`solve`] and
//! comes back as a [`PointSolution`], per wheel the static model (MODEL.md#the-physics-step-by-step,
//! steps 1–8), the verdict (step 9) and the output row. Every command that evaluates operating
//! points calls [`solve`]; a stage after the classifier is added here, and in no other place
//! (docs/book/src/maintainers/architecture.md#how-to-add-a-stage-after-the-classifier).
//!
//! The wear stage (MODEL.md#the-per-sample-estimator) runs after the classifier when the problem
//! carries a [`WearStage`]: the run's calibration and settings, computed once per run by
//! [`WearStage::for_run`] from the reference follower, itself evaluated here.
//!
//! Two cases are the evaluator's own, not its callers': a parameter set that breaks a rule tying
//! parameters together (μ_s ≤ μ_m, n_d ≤ n_w) is a `failed` row per wheel with the reason, and a
//! speed of 0 is a standstill row per wheel (no sliding, no tread dynamics).

use crate::classify::budget::Meter;
use crate::classify::WheelVerdict;
use crate::classify::{classify_point_hinted, Class, ClassifierOptions, CycleHint, Method};
use crate::model::{ModelFailure, Variant, Wheel, WheelModel};
use crate::params::Params;
use crate::records::{WearRecord, WheelRecord};
use crate::wear::{self, Calibration, WearAnswer, WearError, WearProblem, WearSettings};

/// One operating point to evaluate. Built by [`PointProblem::new`] (or
/// [`PointProblem::checked`], which refuses invalid parameters first) and its `with_…`
/// builders, so fields can be added without breaking callers.
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub struct PointProblem<'a> {
    /// Every parameter of the point.
    pub params: Params,
    /// The friction variants, in the order the wheels are evaluated.
    pub variants: &'a [Variant],
    /// The wheels evaluated for each variant, in order.
    pub wheels: &'a [Wheel],
    /// The classifier's settings.
    pub options: &'a ClassifierOptions,
    /// Each wheel's own cycle at a neighbouring point (the previous step of a drive cycle), in
    /// the order of [`PointProblem::wheel_order`]; empty for none. A wheel without one starts
    /// its shooting from the last cycle found at this point (the follower's for the driving
    /// wheel), which saves Newton iterations.
    pub previous: &'a [Option<CycleHint>],
    /// The wear stage after the classifier; `None` leaves it out (no wear columns).
    pub wear: Option<&'a WearStage>,
}

/// The wear stage of a run: its settings and the abradability calibrated once for the run's
/// nominal tire (MODEL.md#step-10-wear-law).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WearStage {
    /// The wear zone.
    #[serde(flatten)]
    pub settings: WearSettings,
    /// γ from the reference follower.
    pub calibration: Calibration,
}

impl WearStage {
    /// The wear problem of wheel `w` at parameters `p`: its model and verdict, with
    /// this stage's settings and calibration.
    pub fn problem<'a>(&'a self, p: &'a Params, w: &'a WheelSolution) -> WearProblem<'a> {
        WearProblem {
            // Its axle's values, whatever the caller passed (MODEL.md#the-car-axles-and-drivetrain).
            params: p.at_wheel(w.record.wheel),
            model: &w.model,
            verdict: &w.verdict,
            settings: &self.settings,
            calibration: &self.calibration,
        }
    }

    /// The stage of a run whose nominal tire is `base`: the reference follower evaluated on the
    /// one road under `variant`, then its calibration.
    pub fn for_run(
        base: &Params,
        variant: Variant,
        settings: WearSettings,
        options: &ClassifierOptions,
    ) -> Result<Self, WearError> {
        Ok(WearStage {
            settings,
            calibration: calibrate_wear(base, variant, options)?,
        })
    }
}

/// The wear calibration of a run whose nominal tire is `base`: its reference follower
/// ([`wear::physics::calibration::reference_params`]) evaluated on the one road, without a wear stage.
pub fn calibrate_wear(
    base: &Params,
    variant: Variant,
    options: &ClassifierOptions,
) -> Result<Calibration, WearError> {
    let reference = wear::physics::calibration::reference_params(base);
    let w = solve_wheel(reference, variant, Wheel::Follower, options);
    Calibration::of_reference(base, &w.model, &w.verdict, options.budget)
}

impl<'a> PointProblem<'a> {
    /// The point for every variant and both wheels, without neighbouring cycles. The
    /// parameters are not checked: a point the model cannot evaluate comes back as a `failed`
    /// wheel with its reason, never dropped (the explore engine checks its study before any
    /// work); [`PointProblem::checked`] refuses them instead.
    pub fn new(params: Params, variants: &'a [Variant], options: &'a ClassifierOptions) -> Self {
        PointProblem {
            params,
            variants,
            wheels: &Wheel::BOTH,
            options,
            previous: &[],
            wear: None,
        }
    }

    /// [`PointProblem::new`] after [`Params::validate`]: every value in its accepted range and
    /// the rules that tie several together, the first broken one named in the error.
    pub fn checked(
        params: Params,
        variants: &'a [Variant],
        options: &'a ClassifierOptions,
    ) -> Result<Self, crate::params::ParamError> {
        params.validate()?;
        Ok(Self::new(params, variants, options))
    }

    /// The same point with each wheel's cycle at a neighbouring point
    /// ([`PointProblem::previous`]), in the order of [`PointProblem::wheel_order`].
    pub fn with_previous(self, previous: &'a [Option<CycleHint>]) -> Self {
        PointProblem { previous, ..self }
    }

    /// The same point with the wear stage after the classifier (or without it, for `None`).
    pub fn with_wear(self, wear: Option<&'a WearStage>) -> Self {
        PointProblem { wear, ..self }
    }

    /// The point for one variant and one wheel.
    pub fn one_wheel(
        params: Params,
        variant: &'a Variant,
        wheel: &'a Wheel,
        options: &'a ClassifierOptions,
    ) -> Self {
        PointProblem {
            params,
            variants: std::slice::from_ref(variant),
            wheels: std::slice::from_ref(wheel),
            options,
            previous: &[],
            wear: None,
        }
    }

    /// The (variant, wheel) pairs in the order they are evaluated and returned.
    pub fn wheel_order(&self) -> impl Iterator<Item = (Variant, Wheel)> + '_ {
        self.variants
            .iter()
            .flat_map(move |&v| self.wheels.iter().map(move |&w| (v, w)))
    }
}

/// What one wheel of one point came to.
#[derive(Debug, Clone)]
pub struct WheelSolution {
    /// The static model (steps 1–8), or why there is none.
    pub model: Result<WheelModel, ModelFailure>,
    /// The classifier's verdict (step 9).
    pub verdict: WheelVerdict,
    /// The output row.
    pub record: WheelRecord,
    /// This wheel's cycle as a starting guess for a neighbouring point (none without a cycle).
    pub hint: Option<CycleHint>,
    /// The wear stage's estimate, when the problem has the stage (also in `record.wear`).
    pub wear: Option<WearAnswer>,
}

/// What a point came to: one [`WheelSolution`] per (variant, wheel), in
/// [`PointProblem::wheel_order`].
#[derive(Debug, Clone)]
pub struct PointSolution {
    /// One per (variant, wheel).
    pub wheels: Vec<WheelSolution>,
}

impl PointSolution {
    /// The output rows, in order.
    pub fn into_records(self) -> Vec<WheelRecord> {
        self.wheels.into_iter().map(|w| w.record).collect()
    }

    /// Each wheel's cycle as a hint for a neighbouring point, in order.
    pub fn hints(&self) -> Vec<Option<CycleHint>> {
        self.wheels.iter().map(|w| w.hint).collect()
    }
}

/// Evaluates a point: every requested variant and wheel, in order (see [`PointProblem`]).
pub fn solve(problem: &PointProblem<'_>) -> PointSolution {
    let p = &problem.params;
    // Each wheel reads its own axle's toe-in, load and pressure, and its row carries them
    // (MODEL.md#the-car-axles-and-drivetrain).
    let order: Vec<(Variant, Wheel, Params)> = problem
        .wheel_order()
        .map(|(v, w)| (v, w, p.at_wheel(w)))
        .collect();
    if p.speed_kmh == 0.0 {
        let wheels = order
            .into_iter()
            .map(|(variant, wheel, p)| {
                standstill(&p, wheel, variant).with_wear_estimate(problem.wear, &p, problem.options)
            })
            .collect();
        return PointSolution { wheels };
    }
    if let Err(e) = p.validate() {
        let failure = ModelFailure::Invalid(format!("invalid parameter set: {e}"));
        let wheels = order
            .into_iter()
            .map(|(variant, wheel, p)| {
                let verdict = WheelVerdict::from_model_failure(&failure);
                let model = Err(failure.clone());
                without_ode(&p, wheel, variant, model, verdict).with_wear_estimate(
                    problem.wear,
                    &p,
                    problem.options,
                )
            })
            .collect();
        return PointSolution { wheels };
    }
    let mut latest_found: Option<CycleHint> = None;
    let wheels = order
        .into_iter()
        .enumerate()
        .map(|(k, (variant, wheel, p))| {
            let own = problem.previous.get(k).copied().flatten();
            let (model, verdict, hint) =
                classify_point_hinted(&p, wheel, variant, problem.options, own.or(latest_found));
            latest_found = hint.or(latest_found);
            let record = WheelRecord::new(&p, wheel, variant, &model, &verdict);
            WheelSolution {
                model,
                verdict,
                record,
                hint,
                wear: None,
            }
            .with_wear_estimate(problem.wear, &p, problem.options)
        })
        .collect();
    PointSolution { wheels }
}

/// One wheel of one variant at a point, on its own (no neighbouring cycle): [`solve`] of
/// [`PointProblem::one_wheel`].
pub fn solve_wheel(
    params: Params,
    variant: Variant,
    wheel: Wheel,
    options: &ClassifierOptions,
) -> WheelSolution {
    let mut solution = solve(&PointProblem::one_wheel(params, &variant, &wheel, options));
    solution.wheels.pop().expect("one wheel")
}

/// Both wheels of every point in `points`, each on its own ([`solve_wheel`]), in parallel on
/// the current rayon pool: the (point index, wheel) jobs and their records, in the points'
/// order and independent of the number of threads (`polywear classify`'s batch).
pub fn solve_points(
    points: &[Params],
    variant: Variant,
    options: &ClassifierOptions,
) -> (Vec<(usize, Wheel)>, Vec<WheelRecord>) {
    let jobs: Vec<(usize, Wheel)> = (0..points.len())
        .flat_map(|i| Wheel::BOTH.map(|w| (i, w)))
        .collect();
    let record = |k: usize| {
        let (i, wheel) = jobs[k];
        solve_wheel(points[i], variant, wheel, options).record
    };
    let control = &crate::ensemble::Control::QUIET;
    let records = crate::ensemble::solve(jobs.len(), record, control).all();
    (jobs, records)
}

/// A wheel without a tread ODE: its row from the verdict alone.
fn without_ode(
    p: &Params,
    wheel: Wheel,
    variant: Variant,
    model: Result<WheelModel, ModelFailure>,
    verdict: WheelVerdict,
) -> WheelSolution {
    let record = WheelRecord::new(p, wheel, variant, &model, &verdict);
    WheelSolution {
        model,
        verdict,
        record,
        hint: None,
        wear: None,
    }
}

impl WheelSolution {
    /// Runs the wear stage on this wheel (nothing without a stage): the estimate, charged to a
    /// meter of its own within the classifier's budget, goes into the solution and its row. A
    /// standstill wheel runs no distance: its figures are NaN with the reason.
    fn with_wear_estimate(
        mut self,
        stage: Option<&WearStage>,
        p: &Params,
        options: &ClassifierOptions,
    ) -> Self {
        let Some(stage) = stage else { return self };
        let meter = Meter::new(options.budget);
        let estimate = if self.verdict.class == Class::Standstill {
            WearAnswer::undefined(p.wear_share_straight, self.verdict.reason.clone())
        } else {
            stage.problem(p, &self).solve(&meter)
        };
        self.record.wear = Some(WearRecord::of(&estimate, p, meter.used()));
        self.wear = Some(estimate);
        self
    }
}

/// A standstill wheel: the point's parameters at speed 0, no model, not vibrating.
fn standstill(p: &Params, wheel: Wheel, variant: Variant) -> WheelSolution {
    let mut verdict =
        WheelVerdict::without_cycle(Class::Standstill, f64::NAN, f64::NAN, Method::Linear);
    verdict.reason = "standstill (speed 0): no sliding, no tread dynamics".into();
    let model = Err(ModelFailure::Invalid(verdict.reason.clone()));
    without_ode(p, wheel, variant, model, verdict)
}
