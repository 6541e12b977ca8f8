//! The speeds a wheel drives in the long-term loop (MODEL.md#the-long-term-loop): a steady
//! speed, a normal spread of the cruising speed, or a drive cycle, each as a few legs of equal
//! shares of the distance (`--speed-nodes` of them; five settle the distance to a visible
//! polygon within 15% of forty on a cruising spread and on HWFET, MODEL.md#the-long-term-loop;
//! WLTC's widely spread speeds need about forty, MODEL.md#along-a-drive-cycle).

use crate::sampling::distribution::normal_quantile;

/// Equal-share speeds a drive cycle is visited at unless told otherwise.
pub const SPEED_NODES: usize = 5;

/// One speed of the usage and its share of the distance.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Leg {
    /// Speed \[km/h\].
    pub speed_kmh: f64,
    /// Share of the distance (the legs' shares add up to 1).
    pub share: f64,
}

/// Cruising at `speed_kmh` with a normal spread of `spread_kmh`: the speed itself without a
/// spread, else `nodes` equal shares at the spread's quantiles (k + ½)/K. A spread too wide for
/// the speed gives legs outside the speed's accepted range, which `LongTermProblem::new`
/// refuses (they are not clamped: a leg driven at another speed than the spread's would be
/// an answer to another question).
pub fn cruise_legs(speed_kmh: f64, spread_kmh: f64, nodes: usize) -> Vec<Leg> {
    if spread_kmh <= 0.0 || nodes <= 1 {
        return vec![Leg {
            speed_kmh,
            share: 1.0,
        }];
    }
    (0..nodes)
        .map(|i| Leg {
            speed_kmh: speed_kmh + spread_kmh * normal_quantile((i as f64 + 0.5) / nodes as f64),
            share: 1.0 / nodes as f64,
        })
        .collect()
}

/// A drive cycle's speeds `speeds_kmh[i]`, each driven `distances_m[i]`, as `nodes`
/// equal shares of distance at the distance-weighted quantiles (k + ½)/K of speed (standstill
/// rows carry no distance and drop out). Empty when the cycle covers no distance.
pub fn cycle_legs(speeds_kmh: &[f64], distances_m: &[f64], nodes: usize) -> Vec<Leg> {
    let mut rows: Vec<(f64, f64)> = speeds_kmh
        .iter()
        .zip(distances_m)
        .filter(|(v, d)| **v > 0.0 && **d > 0.0)
        .map(|(v, d)| (*v, *d))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = rows.iter().map(|r| r.1).sum();
    if total.is_nan() || total <= 0.0 {
        return Vec::new();
    }
    let k = nodes.max(1);
    let mut legs = Vec::with_capacity(k);
    let (mut acc, mut row) = (0.0, 0usize);
    for i in 0..k {
        let target = (i as f64 + 0.5) / k as f64 * total;
        while row + 1 < rows.len() && acc + rows[row].1 < target {
            acc += rows[row].1;
            row += 1;
        }
        legs.push(Leg {
            speed_kmh: rows[row].0,
            share: 1.0 / k as f64,
        });
    }
    legs
}

/// Most seconds of tread time the loop's first step may integrate over all its legs \[s\]. The
/// first step integrates [`FIRST_STEP_REVS`] revolutions at every leg whatever the distance,
/// and below a few km/h the tread's integration takes 5,700 to 7,900 RHS evaluations per
/// second of tread time (measured at 0.3 and 1 km/h, where the step is set by the tread's
/// stiffness, not its period): an hour of it is about 30 million evaluations, a few seconds.
/// A slower usage is refused before any work instead of running for minutes
/// (MODEL.md#the-long-term-loop).
pub const MAX_FIRST_STEP_TREAD_S: f64 = 3600.0;

/// Revolutions integrated before a leg's first measured window (onto its cycle).
pub(crate) const FIRST_SKIP_REVS: usize = 30;

/// Revolutions the loop's first step integrates at each leg: the transient onto its cycle and
/// the longest measured window.
pub const FIRST_STEP_REVS: usize = FIRST_SKIP_REVS + super::lock::WINDOW_REVS.1;

/// The tread time \[s\] the loop's first step integrates over `legs` on a wheel of rolling
/// radius `r_b_m`: [`FIRST_STEP_REVS`] revolutions of 2π r_B / V at each leg.
pub fn first_step_tread_s(legs: &[Leg], r_b_m: f64) -> f64 {
    legs.iter()
        .map(|l| FIRST_STEP_REVS as f64 * std::f64::consts::TAU * r_b_m / (l.speed_kmh / 3.6))
        .sum()
}

/// The slowest speed \[km/h\] a single-speed usage may cruise at within
/// [`MAX_FIRST_STEP_TREAD_S`] with `legs` legs of rolling radius `r_b_m`.
pub fn slowest_cruise_kmh(legs: usize, r_b_m: f64) -> f64 {
    3.6 * legs as f64 * FIRST_STEP_REVS as f64 * std::f64::consts::TAU * r_b_m
        / MAX_FIRST_STEP_TREAD_S
}
