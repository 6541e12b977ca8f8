//! The calibration (MODEL.md#the-calibration-band): a space-filling design over the calibrated
//! constants' prior ranges with a hard cut on the field facts' targets, the answers those of the
//! shipped level (over the tread's life, each speed's print saturated). This is history matching
//! without an emulator (Craig et al. 1997; Vernon, Goldstein and Bower 2010): every point of a
//! scrambled Sobol design over the five constants is kept that no fitting target rules out, each
//! target's stated range taken as the region a match must reach (no model-discrepancy
//! allowance). The kept points are the calibrated sets.
//!
//! Each wheel's closed loop is solved once ([`WheelGrowth`]): none of the five constants enters
//! the new tire's loop, so a design point costs the walk over the tread's life of every wheel
//! ([`WheelGrowth::saturated_answer`]). The targets (MODEL.md#calibration-to-the-field):
//!
//! - `highway_follower_distance`: the highway followers with excessive toe-in (0.40, 0.45,
//!   0.50° at 100, 110, 120 km/h, the nominal tire at the default load and pressure) reach a
//!   visible polygon after a median distance within the fact's range;
//! - `fleet_median_never`: the default study's median wheel (both wheels) has none within the
//!   fact's distance;
//! - `polygon_sides`: of the default study's wheels with a visible polygon within that
//!   distance, at least `SIDES_SHARE_MIN` have a number of sides within the fact's range.

use polywear_core::classify::budget::Meter;
use polywear_core::classify::{classify_point, ClassifierOptions};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::{Coordinates, Design};
use polywear_core::wear::{FittedConstants, LifeAnswer, WearProblem, WearSettings, WheelGrowth};
use rayon::prelude::*;

use super::{ConstantRange, FitError};
use crate::field_facts::FieldFacts;
use crate::study::{Study, DEFAULT_STUDY};

/// The share of the visible polygons that must have the field's number of sides: "most", read
/// as four in five (the bar the calibration's test has held since the wear stage shipped).
pub(crate) const SIDES_SHARE_MIN: f64 = 0.8;

/// The method, named, as the file and the report give it.
pub(crate) const METHOD: &str = "history matching on a scrambled Sobol design over the five calibrated constants' prior ranges (hard cut: every fitting target of data/field_facts.toml within its stated range), on the shipped level";

/// The most sets a file ships: more accepted points are thinned to this many, space-filling.
pub(crate) const SHIPPED_SETS_MAX: usize = 100;

/// Fewer accepted points than this are shipped all, and the file says so.
pub(crate) const FEW_SETS: usize = 20;

/// The design's points and what they are evaluated on.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// Points of the Sobol design.
    pub points: u64,
    /// Samples of the default study (each gives both wheels).
    pub fleet_samples: u64,
    /// Each calibrated constant's prior range, in [`FittedConstants::PARAMS`] order.
    pub ranges: Vec<ConstantRange>,
    /// Evaluate only these points of the design (a reduced design: CI checks it against the
    /// full fit at the same points); None for every point.
    pub only: Option<Vec<u64>>,
}

/// The seed of the design's scrambling (fixed: the design is part of the method).
const DESIGN_SEED: u64 = 2014;

impl FitOptions {
    /// The shipped design: 1024 points over the prior ranges of `facts` (each constant's
    /// provenance), 2000 samples of the default study.
    pub fn shipped(facts: &FieldFacts) -> Self {
        let fact = |id: &str, lo: f64, hi: f64| {
            facts
                .get(id)
                .and_then(|f| f.min.zip(f.max))
                .unwrap_or((lo, hi))
        };
        let (kd, c, mu) = (
            fact("driven_axle_wear_ratio", 1.5, 2.0),
            fact("carcass_share", 0.3, 0.7),
            fact("belt_mass_share", 0.0, 0.7),
        );
        let range = |param: ParamId, (min, max): (f64, f64), provenance: &str| ConstantRange {
            param: param.name().to_string(),
            min,
            max,
            provenance: provenance.to_string(),
        };
        FitOptions {
            points: 1024,
            fleet_samples: 2000,
            ranges: vec![
                range(ParamId::WearShareStraight, (0.02, 1.0), "no measurement: the share of the even wear that the vibration couples to, searched log-uniformly from a fiftieth to all of it"),
                range(ParamId::SpeedSpreadKmh, (2.0, 10.0), "judgement: the spread of a highway cruise, from steady cruise control (2 km/h) to dense traffic (10 km/h)"),
                range(ParamId::WearRateDrivenFactor, kd, "field fact driven_axle_wear_ratio (tire-rotation guidance for front-wheel-drive cars)"),
                range(ParamId::CarcassShare, c, "field fact carcass_share (no figure found: a judgement, MODEL.md#the-ageing-tread)"),
                range(ParamId::BeltMassShare, mu, "field fact belt_mass_share (no measurement found: a judgement from the tire's mass split, MODEL.md#the-ageing-tread)"),
            ],
            only: None,
        }
    }

    /// Point `k` of the design: a scrambled Sobol point of five coordinates mapped onto the
    /// prior ranges (φ_s log-uniformly, the rest uniformly).
    pub fn point(&self, k: u64) -> FittedConstants {
        let coords = Coordinates::new(Design::Sobol, DESIGN_SEED, self.points, 5);
        let mut v = [0.0; 5];
        for (axis, (x, r)) in v.iter_mut().zip(&self.ranges).enumerate() {
            let u = coords.coordinate(k, axis);
            *x = if r.param == ParamId::WearShareStraight.name() {
                (r.min.ln() + u * (r.max.ln() - r.min.ln())).exp()
            } else {
                r.min + u * (r.max - r.min)
            };
        }
        FittedConstants::from_values(v)
    }
}

/// What the fit found at one design point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridPoint {
    /// Its index in the design.
    pub index: u64,
    /// The constants.
    pub constants: FittedConstants,
    /// The highway followers' median distance to a visible polygon \[km\].
    pub highway_median_km: f64,
    /// The default study's wheels' median distance \[km\].
    pub fleet_median_km: f64,
    /// The share of the default study's wheels with a visible polygon within the fleet
    /// target's distance.
    pub fleet_visible_share: f64,
    /// Of those, the share with the field's number of sides.
    pub sides_share: f64,
    /// Every target met.
    pub accepted: bool,
}

/// The fit over the design.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The options it ran with.
    pub options: FitOptions,
    /// Every design point evaluated, in design order.
    pub points: Vec<GridPoint>,
    /// Highway followers with a loop.
    pub highway_wheels: usize,
    /// Default-study wheels with a loop.
    pub fleet_wheels: usize,
}

/// One wheel's closed loop at `p` (the sliding-share variant, as the field calibration's
/// wheels), or None where it has no figures.
pub fn wheel_growth(
    p: &Params,
    wheel: Wheel,
    stage: &polywear_core::evaluate::WearStage,
) -> Option<WheelGrowth> {
    let opts = ClassifierOptions::default();
    let (m, v) = classify_point(p, wheel, Variant::SlidingShare, &opts);
    let inputs = WearProblem {
        params: p.at_wheel(wheel),
        model: &m,
        verdict: &v,
        settings: &stage.settings,
        calibration: &stage.calibration,
    };
    // Kept and asked for every point of the design over minutes: no wall-clock limit.
    WheelGrowth::new(&inputs, &Meter::new(opts.budget))
        .ok()
        .map(WheelGrowth::untimed)
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x.get(x.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The wheels the targets are read on: the highway followers and the default study's wheels.
struct Population {
    highway: Vec<WheelGrowth>,
    fleet: Vec<WheelGrowth>,
}

impl Population {
    /// Each wheel's closed loop on the nominal tire `base`, once.
    fn of(base: &Params, fleet_samples: u64) -> Result<Self, FitError> {
        let stage = polywear_core::evaluate::WearStage::for_run(
            base,
            Variant::SlidingShare,
            WearSettings::default(),
            &ClassifierOptions::default(),
        )?;
        let highway: Vec<WheelGrowth> = [0.40, 0.45, 0.50]
            .iter()
            .flat_map(|&toe_deg| [100.0, 110.0, 120.0].map(|speed_kmh| (toe_deg, speed_kmh)))
            .collect::<Vec<_>>()
            .into_par_iter()
            .filter_map(|(toe_deg, speed_kmh)| {
                let p = Params {
                    toe_deg,
                    speed_kmh,
                    ..*base
                };
                wheel_growth(&p, Wheel::Follower, &stage)
            })
            .collect();
        let study = Study::parse_with_base(DEFAULT_STUDY, *base)?;
        let sampler = study.sampler(study.seed, fleet_samples);
        let fleet: Vec<WheelGrowth> = (0..fleet_samples)
            .into_par_iter()
            .flat_map_iter(|i| {
                let (p, _) = sampler.sample(i);
                Wheel::BOTH
                    .iter()
                    .filter_map(|&w| wheel_growth(&p, w, &stage))
                    .collect::<Vec<_>>()
            })
            .collect();
        if highway.is_empty() || fleet.is_empty() {
            return Err(FitError::NoWheels);
        }
        Ok(Population { highway, fleet })
    }
}

/// The targets a point is held to.
struct Targets<'a> {
    highway: &'a crate::field_facts::Fact,
    fleet: &'a crate::field_facts::Fact,
    sides: &'a crate::field_facts::Fact,
    fleet_km: f64,
}

impl<'a> Targets<'a> {
    fn of(facts: &'a FieldFacts) -> Result<Self, FitError> {
        let target = |id: &'static str| facts.get(id).ok_or(FitError::MissingFact(id));
        let fleet = target("fleet_median_never")?;
        Ok(Targets {
            highway: target("highway_follower_distance")?,
            sides: target("polygon_sides")?,
            fleet_km: fleet.min.ok_or(FitError::NoFleetMin)?,
            fleet,
        })
    }

    /// Design point `index` at the constants `c`, on the population's wheels.
    fn point(&self, pop: &Population, index: u64, c: &FittedConstants) -> GridPoint {
        let answer = |g: &WheelGrowth| g.saturated_answer(c);
        let highway_median_km = median(
            pop.highway
                .iter()
                .map(|g| answer(g).distance_to_visible_km)
                .collect(),
        );
        let answers: Vec<LifeAnswer> = pop.fleet.iter().map(answer).collect();
        let fleet_median_km = median(answers.iter().map(|a| a.distance_to_visible_km).collect());
        let visible: Vec<&LifeAnswer> = answers
            .iter()
            .filter(|a| a.distance_to_visible_km <= self.fleet_km)
            .collect();
        let sides = visible
            .iter()
            .filter(|a| self.sides.holds_for(a.polygon_order_wear))
            .count();
        let sides_share = sides as f64 / visible.len().max(1) as f64;
        let accepted = self.highway.holds_for(highway_median_km)
            && self.fleet.holds_for(fleet_median_km)
            && !visible.is_empty()
            && sides_share >= SIDES_SHARE_MIN;
        GridPoint {
            index,
            constants: *c,
            highway_median_km,
            fleet_median_km,
            fleet_visible_share: visible.len() as f64 / answers.len() as f64,
            sides_share,
            accepted,
        }
    }
}

/// Fits the design of `opts` to the targets of `facts`, on the nominal tire `base` and the
/// default study drawn on it; `progress` hears each point evaluated.
pub fn fit(
    base: &Params,
    facts: &FieldFacts,
    opts: &FitOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Fit, FitError> {
    let targets = Targets::of(facts)?;
    let pop = Population::of(base, opts.fleet_samples)?;
    let indices: Vec<u64> = opts
        .only
        .clone()
        .unwrap_or_else(|| (0..opts.points).collect());
    let points = indices
        .par_iter()
        .map(|&k| {
            let p = targets.point(&pop, k, &opts.point(k));
            progress(1);
            p
        })
        .collect();
    Ok(Fit {
        options: opts.clone(),
        points,
        highway_wheels: pop.highway.len(),
        fleet_wheels: pop.fleet.len(),
    })
}

#[path = "fit_sets.rs"]
mod sets;
pub use sets::design_columns;
