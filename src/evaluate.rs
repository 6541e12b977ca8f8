//! The one road for an operating point: a [`PointProblem`] (the parameters, which variants and
//! wheels, the classifier's options, the cycles of a neighbouring point) goes to [`solve`] and
//! comes back as a [`PointSolution`], per wheel the static model (MODEL.md#the-physics-step-by-step,
//! steps 1–8), the verdict (step 9) and the output row. Every command that evaluates operating
//! points calls [`solve`]; a stage after the classifier is added here, and in no other place
//! (ARCHITECTURE.md#how-to-add-a-stage-after-the-classifier).
//!
//! Two cases are the evaluator's own, not its callers': a parameter set that breaks a rule tying
//! parameters together (μ_s ≤ μ_m, n_d ≤ n_w) is a `failed` row per wheel with the reason, and a
//! speed of 0 is a standstill row per wheel (no sliding, no tread dynamics).

use crate::classify::WheelVerdict;
use crate::classify::{classify_point_hinted, Class, ClassifierOptions, CycleHint, Method};
use crate::model::{ModelFailure, Variant, Wheel, WheelModel};
use crate::params::Params;
use crate::records::WheelRecord;

/// One operating point to evaluate.
#[derive(Debug, Clone, Copy)]
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
}

impl<'a> PointProblem<'a> {
    /// The point for every variant and both wheels, without neighbouring cycles.
    pub fn new(params: Params, variants: &'a [Variant], options: &'a ClassifierOptions) -> Self {
        PointProblem {
            params,
            variants,
            wheels: &Wheel::BOTH,
            options,
            previous: &[],
        }
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
    let order: Vec<(Variant, Wheel)> = problem.wheel_order().collect();
    if p.speed_kmh == 0.0 {
        let wheels = order
            .into_iter()
            .map(|(variant, wheel)| standstill(p, wheel, variant))
            .collect();
        return PointSolution { wheels };
    }
    if let Err(e) = p.validate() {
        let failure = ModelFailure::Invalid(format!("invalid parameter set: {e}"));
        let wheels = order
            .into_iter()
            .map(|(variant, wheel)| {
                let verdict = WheelVerdict::from_model_failure(&failure);
                let model = Err(failure.clone());
                without_ode(p, wheel, variant, model, verdict)
            })
            .collect();
        return PointSolution { wheels };
    }
    let mut latest_found: Option<CycleHint> = None;
    let wheels = order
        .into_iter()
        .enumerate()
        .map(|(k, (variant, wheel))| {
            let own = problem.previous.get(k).copied().flatten();
            let (model, verdict, hint) =
                classify_point_hinted(p, wheel, variant, problem.options, own.or(latest_found));
            latest_found = hint.or(latest_found);
            let record = WheelRecord::new(p, wheel, variant, &model, &verdict);
            WheelSolution {
                model,
                verdict,
                record,
                hint,
            }
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
