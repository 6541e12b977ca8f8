//! The long-term loop's step rule (MODEL.md#the-long-term-loop): each order's depth, its rate
//! and its growth under a step's wear rate, and from them the next step's length.

use super::profile::{harmonics_of, Profile};

/// D_n, dD_n/ds and β_n of orders 1..=`orders` for the profile `profile` under the wear rate
/// `rate_m_per_m` per cell.
pub(super) fn harmonic_rates(
    profile: &Profile,
    rate_m_per_m: &[f64],
    orders: usize,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let r = profile.harmonics(orders);
    let mean = rate_m_per_m.iter().sum::<f64>() / rate_m_per_m.len() as f64;
    let dr_rate: Vec<f64> = rate_m_per_m.iter().map(|x| -(x - mean)).collect();
    let dr = harmonics_of(&dr_rate, orders);
    let mut depth = Vec::with_capacity(orders);
    let mut d_rate = Vec::with_capacity(orders);
    let mut beta = Vec::with_capacity(orders);
    for (rn, drn) in r.iter().zip(&dr) {
        let a = rn.norm();
        let along = (drn * rn.conj()).re;
        depth.push(2.0 * a);
        d_rate.push(if a > 0.0 {
            2.0 * along / a
        } else {
            2.0 * drn.norm()
        });
        beta.push(if a > 0.0 { along / (a * a) } else { 0.0 });
    }
    (depth, d_rate, beta)
}

/// Orders shallower than this share of the deepest take no part in the step rule: their β is
/// the ratio of two roundings.
const STEP_RULE_DEPTH_SHARE: f64 = 0.01;

/// The next step \[m\]: Δs_max, 0.1 |R|max/|dR/ds|max, 0.2/|β|max (over the orders at least
/// [`STEP_RULE_DEPTH_SHARE`] of the deepest) and 1 µm of profile change, never below Δs_min.
/// The orders' depths, depth rates and growth are a history point's (`depths_m`,
/// `depth_rate_m_per_m`, `growth_per_m`); the bounds are the loop settings' `min_step_km` and
/// `max_step_km`.
pub(super) fn next_step_m(
    (min_step_km, max_step_km): (f64, f64),
    (depths_m, depth_rate_m_per_m, growth_per_m): (&[f64], &[f64], &[f64]),
    rate_spread_m_per_m: f64,
) -> f64 {
    let depth = depths_m.iter().fold(0.0f64, |m, d| m.max(*d));
    let significant = |i: &usize| depths_m[*i] >= STEP_RULE_DEPTH_SHARE * depth;
    let max_abs = |v: &[f64]| {
        (0..v.len())
            .filter(significant)
            .fold(0.0f64, |m, i| m.max(v[i].abs()))
    };
    let d_rate = max_abs(depth_rate_m_per_m);
    let beta = max_abs(growth_per_m);
    let mut step = max_step_km * 1e3;
    if d_rate > 0.0 {
        step = step.min(0.1 * depth / d_rate);
    }
    if beta > 0.0 {
        step = step.min(0.2 / beta);
    }
    if rate_spread_m_per_m > 0.0 {
        step = step.min(1e-6 / rate_spread_m_per_m);
    }
    step.max(min_step_km * 1e3)
}
