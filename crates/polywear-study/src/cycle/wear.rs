//! The distance to a visible polygon for a car that drives a cycle all its life
//! (MODEL.md#along-a-drive-cycle): each step's closed-loop growth of every order
//! 1..=[`CYCLE_ORDERS_MAX`], at the step's own speed (the cycle's speeds are its speed spread, so
//! no further spread is laid over a step), averaged over the distance the cycle covers at each
//! step. Repeating the cycle multiplies |R_n| by exp(Σ β_n(k) Δs_k) per lap, so the order whose
//! distance-weighted mean β̄_n is largest is the one that becomes visible, after
//! ln(d_visible / 2R⁰) / β̄_n.

use super::{DriveCycle, StepWheel};
use polywear_core::classify::budget::Meter;
use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::{WearStage, WheelSolution};
use polywear_core::params::Params;
use polywear_core::wear::estimator::distance_to_visible_km;
use polywear_core::wear::{WearInputs, WheelGrowth};

/// The highest order followed along a cycle: the seed's band (MODEL.md#step-12-feedback). A step
/// slower than about 25 km/h puts ν above it; its orders near ν are not followed (their
/// distance at such speeds is small).
pub const CYCLE_ORDERS_MAX: u32 = 64;

/// β_n \[1/1000 km\] of orders 1..=[`CYCLE_ORDERS_MAX`] of one wheel at one step, with no
/// speed spread; empty where the wheel has no figures (no model, failed, standstill).
pub fn step_growth(
    p: &Params,
    wheel: &WheelSolution,
    stage: &WearStage,
    options: &ClassifierOptions,
) -> Vec<f64> {
    let inputs = WearInputs {
        params: p,
        model: &wheel.model,
        verdict: &wheel.verdict,
        settings: &stage.settings,
        calibration: &stage.calibration,
    };
    let Ok(growth) = WheelGrowth::new(&inputs, &Meter::new(options.budget)) else {
        return Vec::new();
    };
    (1..=CYCLE_ORDERS_MAX)
        .map(|n| {
            growth
                .order_with(n, p.wear_share_straight, 0.0)
                .growth_rate_per_1000km
        })
        .collect()
}

/// One wheel's polygon over a lifetime of the cycle (one tire structure).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleWear {
    /// The order with the largest distance-weighted growth (NaN where no step has figures).
    pub dominant_order: f64,
    /// Its β̄ \[1/1000 km\].
    pub growth_rate_per_1000km: f64,
    /// Distance to a polygon `visible_depth_mm` deep \[km\]; +inf when every order levels out.
    pub distance_to_visible_km: f64,
    /// Share of the cycle's distance at steps without figures (failed, no traction): left out
    /// of the mean, and said.
    pub unknown_distance_share: f64,
}

/// The cycle's wear of wheel `w` (0 follower, 1 driving) on the structure `base`.
pub fn cycle_wear(
    cycle: &DriveCycle,
    steps: &[[StepWheel; 2]],
    w: usize,
    base: &Params,
) -> CycleWear {
    let dt = cycle.step_durations_s();
    let mut sum = vec![0.0; CYCLE_ORDERS_MAX as usize];
    let (mut known_km, mut unknown_km) = (0.0, 0.0);
    for (i, s) in steps.iter().enumerate() {
        let km = cycle.speed_kmh[i] * dt[i] / 3600.0;
        if km <= 0.0 {
            continue;
        }
        let g = &s[w].order_growth_per_1000km;
        if g.is_empty() {
            unknown_km += km;
            continue;
        }
        known_km += km;
        for (acc, b) in sum.iter_mut().zip(g) {
            *acc += km * b;
        }
    }
    let unknown_distance_share = if known_km + unknown_km > 0.0 {
        unknown_km / (known_km + unknown_km)
    } else {
        0.0
    };
    let best = (known_km > 0.0)
        .then(|| {
            sum.iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map(|(k, s)| (k as f64 + 1.0, s / known_km))
        })
        .flatten();
    match best {
        Some((order, beta)) => CycleWear {
            dominant_order: order,
            growth_rate_per_1000km: beta,
            distance_to_visible_km: distance_to_visible_km(base, beta),
            unknown_distance_share,
        },
        None => CycleWear {
            dominant_order: f64::NAN,
            growth_rate_per_1000km: f64::NAN,
            distance_to_visible_km: f64::NAN,
            unknown_distance_share,
        },
    }
}
