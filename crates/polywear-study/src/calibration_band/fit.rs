//! The calibration by history matching (Craig et al. 1997; Vernon, Goldstein and Bower 2010):
//! every point of a grid over the fitted constants is kept that is not ruled out by a fitting
//! target of the field facts, each target's stated range taken as the region a match must
//! reach (a hard cut, no model-discrepancy allowance). The kept points are the calibrated sets.
//!
//! Each wheel's closed loop is solved once ([`WheelGrowth`]); φ_s, σ_V and k_d then enter
//! without solving again ([`WheelGrowth::answer_with`]), so the whole grid costs little more
//! than one evaluation of the wheels. The targets (MODEL.md#calibration-to-the-field):
//!
//! - `highway_follower_distance`: the highway followers with excessive toe-in (0.40, 0.45,
//!   0.50° at 100, 110, 120 km/h, the nominal tire at the default load and pressure) reach a
//!   visible polygon after a median distance within the fact's range;
//! - `fleet_median_never`: the default study's median wheel (both wheels) has none within the
//!   fact's distance;
//! - `polygon_sides`: of the default study's wheels with a visible polygon within that
//!   distance, at least [`SIDES_SHARE_MIN`] have a number of sides within the fact's range.

use polywear_core::classify::budget::Meter;
use polywear_core::classify::{classify_point, ClassifierOptions};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::Params;
use polywear_core::wear::{
    EstimateLevel, FittedConstants, WearAnswer, WearInputs, WearSettings, WheelGrowth,
};
use rayon::prelude::*;

use super::{CalibratedSet, CalibrationBand};
use crate::field_facts::FieldFacts;
use crate::study::{Study, DEFAULT_STUDY};

/// The share of the visible polygons that must have the field's number of sides: "most", read
/// as four in five (the bar the calibration's test has held since the wear stage shipped).
pub const SIDES_SHARE_MIN: f64 = 0.8;

/// The method, named, as the file and the report give it.
pub const METHOD: &str = "history matching on a grid (hard cut: every fitting target of data/field_facts.toml within its stated range)";

/// The grid searched and the fleet's size.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// Samples of the default study (each gives both wheels).
    pub samples: u64,
    /// φ_s values.
    pub shares: Vec<f64>,
    /// σ_V values \[km/h\].
    pub spreads_kmh: Vec<f64>,
    /// k_d values.
    pub driven_factors: Vec<f64>,
    /// Which level of the per-sample estimator answers each grid point.
    pub level: EstimateLevel,
}

impl FitOptions {
    /// The shipped grid: σ_V from 2 to 10 km/h in steps of 1 (a cruising speed's plausible
    /// spread; without one the sides miss); φ_s from 0.03 to 0.30 in steps of 0.01, wide enough
    /// that the accepted ridge (more spread, more φ_s) ends inside it at every σ_V; k_d at the
    /// published range's ends and middle (`driven_axle_wear_ratio`, 1.5–2), which no target
    /// constrains much but the driving wheel's answer depends on.
    pub fn shipped(samples: u64, facts: &FieldFacts) -> Self {
        let kd = facts
            .get("driven_axle_wear_ratio")
            .and_then(|f| f.min.zip(f.max))
            .unwrap_or((1.5, 2.0));
        FitOptions {
            samples,
            shares: (3..=30).map(|k| k as f64 / 100.0).collect(),
            spreads_kmh: (2..=10).map(f64::from).collect(),
            driven_factors: vec![kd.0, 0.5 * (kd.0 + kd.1), kd.1],
            level: EstimateLevel::NewTire,
        }
    }
}

/// What the fit found at one grid point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridPoint {
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

/// The fit over the whole grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Every grid point, in grid order (φ_s, then σ_V, then k_d).
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
    let inputs = WearInputs {
        params: p,
        model: &m,
        verdict: &v,
        settings: &stage.settings,
        calibration: &stage.calibration,
    };
    WheelGrowth::new(&inputs, &Meter::new(opts.budget)).ok()
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x.get(x.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Fits the grid of `opts` to the targets of `facts`, on the nominal tire `base` and the
/// default study drawn on it.
pub fn fit(base: &Params, facts: &FieldFacts, opts: &FitOptions) -> Result<Fit, String> {
    let target = |id: &str| {
        facts
            .get(id)
            .ok_or(format!("the field facts have no `{id}`"))
    };
    let (highway_t, fleet_t, sides_t) = (
        target("highway_follower_distance")?,
        target("fleet_median_never")?,
        target("polygon_sides")?,
    );
    let fleet_km = fleet_t
        .min
        .ok_or("`fleet_median_never` has no `min` distance")?;
    let stage = polywear_core::evaluate::WearStage::for_run(
        base,
        Variant::SlidingShare,
        WearSettings::default(),
        &ClassifierOptions::default(),
    )
    .map_err(|e| e.to_string())?;
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
    let study = Study::parse_with_base(DEFAULT_STUDY, *base).map_err(|e| e.to_string())?;
    let sampler = study.sampler(study.seed, opts.samples);
    let fleet: Vec<WheelGrowth> = (0..opts.samples)
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
        return Err("no wheel with a loop to fit on".into());
    }
    let grid: Vec<FittedConstants> = opts
        .shares
        .iter()
        .flat_map(|&wear_share_straight| {
            opts.spreads_kmh.iter().flat_map(move |&speed_spread_kmh| {
                opts.driven_factors
                    .iter()
                    .map(move |&wear_rate_driven_factor| FittedConstants {
                        wear_share_straight,
                        speed_spread_kmh,
                        wear_rate_driven_factor,
                    })
            })
        })
        .collect();
    let answer =
        |g: &WheelGrowth, c: &FittedConstants| g.answers_on(opts.level, std::slice::from_ref(c))[0];
    let points = grid
        .par_iter()
        .map(|c| {
            let highway_median_km = median(
                highway
                    .iter()
                    .map(|g| answer(g, c).distance_to_visible_km)
                    .collect(),
            );
            let answers: Vec<WearAnswer> = fleet.iter().map(|g| answer(g, c)).collect();
            let fleet_median_km =
                median(answers.iter().map(|a| a.distance_to_visible_km).collect());
            let visible: Vec<&WearAnswer> = answers
                .iter()
                .filter(|a| a.distance_to_visible_km <= fleet_km)
                .collect();
            let sides = visible
                .iter()
                .filter(|a| sides_t.holds_for(a.polygon_order_wear))
                .count();
            let sides_share = sides as f64 / visible.len().max(1) as f64;
            let accepted = highway_t.holds_for(highway_median_km)
                && fleet_t.holds_for(fleet_median_km)
                && !visible.is_empty()
                && sides_share >= SIDES_SHARE_MIN;
            GridPoint {
                constants: *c,
                highway_median_km,
                fleet_median_km,
                fleet_visible_share: visible.len() as f64 / answers.len() as f64,
                sides_share,
                accepted,
            }
        })
        .collect();
    Ok(Fit {
        points,
        highway_wheels: highway.len(),
        fleet_wheels: fleet.len(),
    })
}

impl Fit {
    /// The accepted points.
    pub fn accepted(&self) -> impl Iterator<Item = &GridPoint> {
        self.points.iter().filter(|p| p.accepted)
    }

    /// The accepted points as a file of calibrated sets, `nominal` marked (an error when the
    /// nominal constants are not accepted: the shipped defaults must meet the targets).
    pub fn band(
        &self,
        nominal: &FittedConstants,
        generated_by: &str,
    ) -> Result<CalibrationBand, String> {
        let sets: Vec<CalibratedSet> = self
            .accepted()
            .map(|g| {
                let c = g.constants;
                let is_nominal = c == *nominal;
                CalibratedSet {
                    id: if is_nominal {
                        "nominal".to_string()
                    } else {
                        format!(
                            "phi{:.3}_sv{}_kd{}",
                            c.wear_share_straight, c.speed_spread_kmh, c.wear_rate_driven_factor
                        )
                    },
                    nominal: is_nominal,
                    wear_share_straight: c.wear_share_straight,
                    speed_spread_kmh: c.speed_spread_kmh,
                    wear_rate_driven_factor: c.wear_rate_driven_factor,
                    highway_median_km: Some(g.highway_median_km.round()),
                    fleet_median_km: Some(g.fleet_median_km.round()),
                    sides_share: Some((g.sides_share * 1000.0).round() / 1000.0),
                }
            })
            .collect();
        if !sets.iter().any(|s| s.nominal) {
            return Err(format!(
                "the nominal constants {nominal:?} are not accepted by the targets"
            ));
        }
        let band = CalibrationBand {
            method: METHOD.to_string(),
            generated_by: generated_by.to_string(),
            sets,
        };
        // The file must read back as it will be read.
        CalibrationBand::parse(&band.to_toml(), "the fit").map_err(|e| e.to_string())
    }
}
