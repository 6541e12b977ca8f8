//! The search on the unit box [0, 1]^d: a coarse grid, then refinement where it matters. At
//! each level the step halves and the neighbours (at the new step, diagonals included) of the
//! best settings are evaluated: the best feasible one and those whose value lies within its
//! 95% interval, the best `keep` of them. Refining inside the best's interval, not only at the
//! best, is what a noisy objective asks: any of those settings may be the true minimum.
//!
//! The objective is a mean over the same samples at every setting (common random numbers), so
//! it is a deterministic, piecewise constant function of the setting; a local method with
//! gradients would see steps, a grid does not. Every setting lies on the lattice of the finest
//! step, so none is evaluated twice.

use std::collections::BTreeSet;

/// How far the search refines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SearchOptions {
    /// Points per axis of the coarse grid (at least 2).
    pub grid: usize,
    /// Refinement levels after the coarse grid (each halves the step).
    pub levels: usize,
    /// Settings refined per level, at most.
    pub keep: usize,
}

impl SearchOptions {
    /// The default: a 7-point grid per axis refined three times around the best four.
    pub const DEFAULT: SearchOptions = SearchOptions {
        grid: 7,
        levels: 3,
        keep: 4,
    };

    /// Lattice steps per unit at the finest level.
    pub fn lattice(&self) -> u64 {
        (self.grid as u64 - 1) << self.levels
    }

    /// The finest step, as a share of each axis.
    pub fn finest_step(&self) -> f64 {
        1.0 / self.lattice() as f64
    }
}

/// What an evaluation says of one setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Value {
    /// The objective (NaN: unknown).
    pub value: f64,
    /// The upper end of its 95% interval.
    pub high: f64,
    /// Whether the setting meets the constraints.
    pub feasible: bool,
}

/// One evaluated setting.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluated {
    /// Its coordinates in the unit box.
    pub unit: Vec<f64>,
    /// The level it was added at (0: the coarse grid).
    pub level: usize,
    /// What the evaluation said.
    pub value: Value,
}

/// Evaluates a batch of settings (unit coordinates) of one level, returning their values in
/// order.
pub type Evaluate<'a> = dyn FnMut(&[Vec<f64>], usize) -> Vec<Value> + 'a;

/// Maps a lattice key to the first key with the same setting (the identity where every lattice
/// point is a setting of its own).
pub(crate) type Canonical<'a> = dyn Fn(&[i64]) -> Vec<i64> + 'a;

/// Runs the search in `dims` dimensions; `eval` evaluates a batch of settings (unit
/// coordinates) of one level and returns their values in order; `canonical` names the lattice
/// points that are one setting (a whole-number axis), so that each is evaluated once. Returns
/// every setting evaluated, in order of evaluation.
pub fn search(
    dims: usize,
    opts: SearchOptions,
    eval: &mut Evaluate<'_>,
    canonical: &Canonical<'_>,
) -> Vec<Evaluated> {
    let m = opts.lattice() as i64;
    let to_unit = |k: &[i64]| k.iter().map(|&k| k as f64 / m as f64).collect::<Vec<f64>>();
    let mut seen: BTreeSet<Vec<i64>> = BTreeSet::new();
    let mut keys: Vec<Vec<i64>> = Vec::new();
    let mut out: Vec<Evaluated> = Vec::new();
    let coarse = m / (opts.grid as i64 - 1);
    let mut batch: Vec<Vec<i64>> = grid_keys(dims, opts.grid, coarse);
    for level in 0..=opts.levels {
        for k in batch.iter_mut() {
            *k = canonical(k);
        }
        batch.sort();
        batch.dedup();
        batch.retain(|k| seen.insert(k.clone()));
        if batch.is_empty() {
            break;
        }
        let units: Vec<Vec<f64>> = batch.iter().map(|k| to_unit(k)).collect();
        let values = eval(&units, level);
        for ((k, unit), value) in batch.drain(..).zip(units).zip(values) {
            keys.push(k);
            out.push(Evaluated { unit, level, value });
        }
        if level == opts.levels {
            break;
        }
        let step = coarse >> (level + 1);
        for c in candidates(&out, opts.keep) {
            for offset in offsets(dims) {
                let k: Vec<i64> = keys[c]
                    .iter()
                    .zip(&offset)
                    .map(|(k, o)| k + o * step)
                    .collect();
                if k.iter().all(|&x| (0..=m).contains(&x)) {
                    let k = canonical(&k);
                    if !seen.contains(&k) {
                        batch.push(k);
                    }
                }
            }
        }
        batch.sort();
        batch.dedup();
    }
    out
}

/// The coarse grid's lattice keys: `points` per axis, `spacing` lattice steps apart.
fn grid_keys(dims: usize, points: usize, spacing: i64) -> Vec<Vec<i64>> {
    let mut keys: Vec<Vec<i64>> = vec![Vec::new()];
    for _ in 0..dims {
        keys = keys
            .into_iter()
            .flat_map(|k| {
                (0..points as i64).map(move |i| {
                    let mut k = k.clone();
                    k.push(i * spacing);
                    k
                })
            })
            .collect();
    }
    keys
}

/// Every offset in {-1, 0, 1}^dims but zero.
fn offsets(dims: usize) -> Vec<Vec<i64>> {
    let all = grid_keys(dims, 3, 1);
    all.into_iter()
        .map(|k| k.iter().map(|x| x - 1).collect::<Vec<i64>>())
        .filter(|k| k.iter().any(|x| *x != 0))
        .collect()
}

/// The settings to refine around: the best feasible one and those whose value lies within its
/// interval, best first, at most `keep`.
fn candidates(points: &[Evaluated], keep: usize) -> Vec<usize> {
    let Some(best) = best(points) else {
        return Vec::new();
    };
    let high = points[best].value.high;
    let mut within: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let v = points[i].value;
            v.feasible && v.value.is_finite() && v.value <= high
        })
        .collect();
    within.sort_by(|&a, &b| {
        points[a]
            .value
            .value
            .total_cmp(&points[b].value.value)
            .then(a.cmp(&b))
    });
    within.truncate(keep.max(1));
    within
}

/// The feasible setting with the smallest value (the first evaluated among equals).
pub fn best(points: &[Evaluated]) -> Option<usize> {
    (0..points.len())
        .filter(|&i| points[i].value.feasible && points[i].value.value.is_finite())
        .min_by(|&a, &b| {
            points[a]
                .value
                .value
                .total_cmp(&points[b].value.value)
                .then(a.cmp(&b))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hidden bowl with small ripples, its minimum at `at`; the interval ±0.002.
    fn bowl(at: [f64; 2]) -> impl FnMut(&[Vec<f64>], usize) -> Vec<Value> {
        move |units: &[Vec<f64>], _| {
            units
                .iter()
                .map(|u| {
                    let (dx, dy) = (u[0] - at[0], u[1] - at[1]);
                    let ripple = 0.001 * ((40.0 * u[0]).sin() * (31.0 * u[1]).cos());
                    let value = 0.2 + dx * dx + 2.0 * dy * dy + ripple * (dx * dx + dy * dy);
                    Value {
                        value,
                        high: value + 0.002,
                        feasible: true,
                    }
                })
                .collect()
        }
    }

    #[test]
    fn the_search_finds_a_hidden_minimum_to_the_finest_step() {
        let opts = SearchOptions::DEFAULT;
        for at in [[0.37, 0.71], [0.05, 0.93], [0.0, 0.5], [0.62, 1.0]] {
            let points = search(2, opts, &mut bowl(at), &|k| k.to_vec());
            let b = &points[best(&points).unwrap()];
            let err = (b.unit[0] - at[0]).abs().max((b.unit[1] - at[1]).abs());
            assert!(
                err <= opts.finest_step(),
                "minimum at {at:?}, found {:?} (error {err}, step {})",
                b.unit,
                opts.finest_step()
            );
            // Far fewer settings than the finest grid would take.
            let full = (opts.lattice() + 1).pow(2) as usize;
            assert!(points.len() * 10 < full, "{} of {full}", points.len());
            // No setting twice.
            let mut seen: Vec<&Vec<f64>> = points.iter().map(|p| &p.unit).collect();
            seen.sort_by(|a, b| a.partial_cmp(b).unwrap());
            seen.dedup();
            assert_eq!(seen.len(), points.len());
        }
    }

    #[test]
    fn infeasible_settings_are_never_the_best() {
        let mut inner = bowl([0.5, 0.5]);
        let mut eval = |u: &[Vec<f64>], l: usize| {
            let mut v = inner(u, l);
            for (x, v) in u.iter().zip(&mut v) {
                v.feasible = x[0] >= 0.75;
            }
            v
        };
        let points = search(2, SearchOptions::DEFAULT, &mut eval, &|k| k.to_vec());
        let b = &points[best(&points).unwrap()];
        assert!((b.unit[0] - 0.75).abs() < 1e-12, "{:?}", b.unit);
        assert!((b.unit[1] - 0.5).abs() <= SearchOptions::DEFAULT.finest_step());
    }

    #[test]
    fn one_dimension_works_too() {
        let mut eval = |u: &[Vec<f64>], _l: usize| {
            u.iter()
                .map(|x| Value {
                    value: (x[0] - 0.123).abs(),
                    high: (x[0] - 0.123).abs() + 1e-3,
                    feasible: true,
                })
                .collect()
        };
        let points = search(1, SearchOptions::DEFAULT, &mut eval, &|k| k.to_vec());
        let b = &points[best(&points).unwrap()];
        assert!((b.unit[0] - 0.123).abs() <= SearchOptions::DEFAULT.finest_step());
    }
}
