//! The speeds a wheel drives, for the estimator and the long-term loop alike
//! (MODEL.md#the-long-term-loop): a steady speed, a normal spread of the cruising speed, or a
//! drive cycle, each as a few legs of equal shares of the distance (`--speed-nodes` of them; five settle the distance to a visible
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
