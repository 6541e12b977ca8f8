//! The abradability γ of MODEL.md#step-10-wear-law, calibrated once per run at the reference
//! point: the shipped default operating point (100 km/h, 0.3°, 4000 N, 240 kPa), follower, on
//! the run's nominal tire. γ is a property of the compound, so it is computed from the base
//! parameters once, never per sample:
//!
//! ```text
//! γ = φ_s · w′₀ · b V 2π r_B / P̄_ref
//! ```
//!
//! so that the straight-running wear at the reference point is φ_s·w′₀. P̄_ref is the mean
//! friction power over the reference follower's cycle where it vibrates (as at the shipped
//! defaults), else at its equilibrium. φ_s and w′₀ are read per sample, so a study that draws
//! them scales γ with them.

use super::cycle::{SampledCycle, SAMPLES_PER_PERIOD};
use super::law::equilibrium_power_w;
use super::slip::WearPower;
use crate::classify::budget::Meter;
use crate::classify::{Class, WheelBudget, WheelVerdict};
use crate::model::{ModelFailure, Wheel, WheelModel};
use crate::params::{ParamId, Params, OPERATING_AXES};
use crate::wear::error::WearError;

/// The reference point's friction energy, from which γ follows for any φ_s and w′₀.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Calibration {
    /// Mean friction power of the reference follower P̄_ref \[W\].
    pub reference_power_w: f64,
    /// Its tread band swept per second, b·V·2π r_B \[m³/s per m/m\]: γ P̄_ref / this = w′.
    pub reference_band_m3_per_s: f64,
    /// The reference follower's class (`limit_cycle` at the shipped defaults).
    pub reference_class: Class,
    /// γ for the base parameters' φ_s and w′₀ \[m³/J\].
    pub gamma_m3_per_j: f64,
}

impl Calibration {
    /// The calibration of a run whose nominal tire is `base`, from its reference follower's
    /// model and verdict at [`reference_params`]`(base)` (the caller evaluates that point on the
    /// one road: `evaluate::calibrate_wear`). A vibrating reference spends one period of its
    /// cycle again, within `budget`.
    pub fn of_reference(
        base: &Params,
        model: &Result<WheelModel, ModelFailure>,
        verdict: &WheelVerdict,
        budget: WheelBudget,
    ) -> Result<Self, WearError> {
        let p = reference_params(base);
        let refused = |class: Class, reason: String| WearError::Reference {
            class,
            reason,
            speed_kmh: p.speed_kmh,
            toe_deg: p.toe_deg,
            load_n: p.load_n,
            pressure_kpa: p.pressure_kpa,
        };
        let model = match model {
            Ok(m) => m,
            Err(f) => return Err(refused(verdict.class, f.to_string())),
        };
        let power_w = match verdict.class {
            Class::Stable => equilibrium_power_w(&model.ode),
            Class::LimitCycle | Class::Bistable => {
                let meter = Meter::new(budget);
                SampledCycle::of(&model.ode, verdict, SAMPLES_PER_PERIOD, &meter)
                    .map_err(|e| refused(verdict.class, e.to_string()))?
                    .mean_power_w(&model.ode, &meter)
            }
            Class::NoTraction | Class::Failed | Class::Standstill => {
                return Err(refused(verdict.class, verdict.reason.clone()))
            }
        };
        let band = model.patch.width_m * p.speed_mps() * std::f64::consts::TAU * p.r_b;
        let c = Calibration {
            reference_power_w: power_w,
            reference_band_m3_per_s: band,
            reference_class: verdict.class,
            gamma_m3_per_j: 0.0,
        };
        Ok(Calibration {
            gamma_m3_per_j: c.gamma_m3_per_j(base),
            ..c
        })
    }

    /// γ \[m³/J\] for the φ_s and w′₀ of `p`.
    pub fn gamma_m3_per_j(&self, p: &Params) -> f64 {
        p.wear_share_straight * wear_rate_ref_m_per_m(p) * self.reference_band_m3_per_s
            / self.reference_power_w
    }
}

/// The even-wear rate at the reference point w′₀ in m/m.
pub(crate) fn wear_rate_ref_m_per_m(p: &Params) -> f64 {
    p.wear_rate_ref_mm_per_1000km / super::law::MM_PER_1000KM_PER_M_PER_M
}

/// The even-wear rate of a wheel's position \[m/m\]: w′₀, and for the driving wheel under
/// [`WearPower::WithSlip`] `wear_rate_driven_factor` times w′₀ (a driven axle's tyres wear
/// faster: MODEL.md#wear-constants). The share of it that is not straight running,
/// (1 − φ_s) of it, is the wheel's other wear.
pub fn position_rate_m_per_m(p: &Params, wheel: Wheel, power: WearPower) -> f64 {
    let factor = if driven_position(wheel, power) {
        p.wear_rate_driven_factor
    } else {
        1.0
    };
    factor * wear_rate_ref_m_per_m(p)
}

/// Whether a wheel's position wears at k_d w′₀ rather than w′₀: the driving wheel under
/// [`WearPower::WithSlip`].
pub(crate) fn driven_position(wheel: Wheel, power: WearPower) -> bool {
    matches!((wheel, power), (Wheel::Driving, WearPower::WithSlip))
}

/// `base` at the reference point: the operating axes at their shipped defaults, on both axles
/// (an axle's own value is cleared: the reference is one point, whatever the car).
pub fn reference_params(base: &Params) -> Params {
    let mut p = *base;
    for id in OPERATING_AXES {
        p[id] = id.spec().default;
    }
    for id in ParamId::ALL.iter().filter(|id| id.is_per_axle()) {
        p[*id] = f64::NAN;
    }
    debug_assert_eq!(p[ParamId::SpeedKmh], 100.0);
    p
}
