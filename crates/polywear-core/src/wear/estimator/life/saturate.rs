//! The print saturated (MODEL.md#the-forced-response-saturates): each speed's part of an
//! order's rate bounded by the most of the zone's power a polygon can make its own order print,
//! as a piecewise-linear rate in the depth, and the walk of each order over the tread's life
//! under it, step by step of a drive cycle or leg by leg of a speed spread.

use super::depth_lock::{LockedInterval, OrderLocks};
use super::profile::LifeProfile;
use super::LifeAnswer;
use crate::params::Params;
use crate::wear::estimator::{print_log_ratio, tread_life_km};
use crate::wear::physics::fitted::FittedConstants;
use crate::wear::physics::law::MM_PER_1000KM_PER_M_PER_M;

mod walk;
pub(super) use walk::saturated_walk_substeps;

/// The largest first harmonic of a sliding power at a constant friction force, as a share of
/// its mean: max over a of 2⟨P cos θ⟩/⟨P⟩ for P ∝ |1 + a cos θ|, the sliding speed's mean
/// plus an oscillation a times it (MODEL.md#the-forced-response-saturates). Below a = 1 the
/// share is a; past it the sliding reverses for part of each period and the power's
/// harmonic turns to 2θ: the maximum, 1.0528 at a ≈ 1.18, is the most of the zone's mean
/// power a deep polygon can make its own order print (a test computes it).
pub const SLIDING_MODULATION_MAX: f64 = 1.0528;

/// One speed's part of an order's rate at depth u: share · (base · u + min(growth · u +
/// floor, bound)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedTerm {
    /// The speed's share of the distance.
    pub share: f64,
    /// The order's rate there with no transfer through the tread (its levelling) \[1/m\].
    pub base_per_m: f64,
    /// Its growth through the tread \[1/m\].
    pub growth_per_m: f64,
    /// The bound on that growth's print, in seeds 2R⁰ per metre.
    pub bound_per_m: f64,
    /// A print that does not grow with u, at most the bound, in seeds 2R⁰ per metre: 0 in the
    /// walk; in its upper bound, the most a locked cycle can print (MODEL.md#the-locked-print).
    pub floor_per_m: f64,
}

impl SpeedTerm {
    /// Its line below its knot, slope a(b + r) and value a L at u = 0 (L the floor, at most
    /// the cap), and where r > 0 the knot u* = (cap − L)/r (at least 0), with what crossing it
    /// takes off the slope (a r) and adds to the value (a (cap − L)).
    fn line_and_knot(&self) -> (f64, f64, Option<(f64, f64, f64)>) {
        let (a, b, r, cap) = (
            self.share,
            self.base_per_m,
            self.growth_per_m,
            self.bound_per_m,
        );
        let floor = self.floor_per_m.min(cap);
        let knot = (r > 0.0).then(|| (((cap - floor) / r).max(0.0), a * r, a * (cap - floor)));
        (a * (b + r), a * floor, knot)
    }
}

/// du/ds = F(u) with F continuous and linear on each piece: slope·u + offset on
/// \[`knots[i]`, `knots[i + 1]`), the last piece to +inf (u = D/2R⁰, s in metres).
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseRate {
    /// The pieces' lower ends, from 0, rising.
    pub knots: Vec<f64>,
    /// F's slope on each piece \[1/m\].
    pub slope: Vec<f64>,
    /// F's value at u = 0 of each piece's line \[1/m\].
    pub offset: Vec<f64>,
}

impl PiecewiseRate {
    /// Σ_k a_k (b_k u + min(r_k u + L_k, cap_k)) over `terms` (L_k ≤ cap_k the floor): each
    /// term linear below its knot u*_k = (cap_k − L_k)/r_k (r_k > 0) and b_k u + cap_k above
    /// it.
    pub fn of_terms(terms: &[SpeedTerm]) -> Self {
        let mut rate = PiecewiseRate {
            knots: Vec::new(),
            slope: Vec::new(),
            offset: Vec::new(),
        };
        rate.refill(terms, &mut Vec::new());
        rate
    }

    /// [`PiecewiseRate::of_terms`] into `self`, its buffers and `knots` (scratch) reused: an
    /// order's walk forms one rate for every interval of the depth grid.
    pub fn refill(&mut self, terms: &[SpeedTerm], knots: &mut Vec<(f64, f64, f64)>) {
        let (mut slope, mut offset) = (0.0, 0.0);
        knots.clear();
        for t in terms {
            let (line_slope, line_offset, knot) = t.line_and_knot();
            slope += line_slope;
            offset += line_offset;
            knots.extend(knot);
        }
        knots.sort_by(|x, y| x.0.total_cmp(&y.0));
        self.first_piece(slope, offset);
        for &(at, dr, dc) in knots.iter() {
            slope -= dr;
            offset += dc;
            if at > *self.knots.last().unwrap_or(&0.0) {
                self.knots.push(at);
                self.slope.push(slope);
                self.offset.push(offset);
            } else {
                *self.slope.last_mut().unwrap() = slope;
                *self.offset.last_mut().unwrap() = offset;
            }
        }
    }

    /// Empties the rate down to its first piece, from u = 0: slope·u + offset.
    fn first_piece(&mut self, slope: f64, offset: f64) {
        self.knots.clear();
        self.slope.clear();
        self.offset.clear();
        self.knots.push(0.0);
        self.slope.push(slope);
        self.offset.push(offset);
    }

    /// [`PiecewiseRate::refill`] then [`PiecewiseRate::evolve`], bit for bit, but laying out
    /// only the first piece where the path from `u` stays below every knot (the usual case: a
    /// print saturates far above the seed), without sorting the knots: a drive cycle's
    /// hundreds of speed bins are each a term, and sorting them on every interval of every
    /// order was a third of `polywear cycle`'s time.
    pub fn refill_evolve(
        &mut self,
        terms: &[SpeedTerm],
        knots: &mut Vec<(f64, f64, f64)>,
        u: f64,
        ds: f64,
        visible: f64,
    ) -> (f64, Option<f64>) {
        // The first piece as `refill` sums it: every term's line, then (in the terms' order,
        // as the stable sort leaves them) the terms whose knot is at 0.
        let (mut slope, mut offset, mut least, mut at_zero) = (0.0, 0.0, f64::INFINITY, false);
        for t in terms {
            let (line_slope, line_offset, knot) = t.line_and_knot();
            slope += line_slope;
            offset += line_offset;
            match knot {
                Some((at, _, _)) if at > 0.0 => least = least.min(at),
                Some(_) => at_zero = true,
                None => {}
            }
        }
        if at_zero {
            for (_, dr, dc) in terms
                .iter()
                .filter_map(|t| t.line_and_knot().2)
                .filter(|&(at, _, _)| at <= 0.0)
            {
                slope -= dr;
                offset += dc;
            }
        }
        if u < least {
            self.first_piece(slope, offset);
            if least.is_finite() {
                self.knots.push(least);
            }
            if let Some(done) = self.evolve_within(u, ds, visible, 1) {
                return done;
            }
        }
        self.refill(terms, knots);
        self.evolve(u, ds, visible)
    }

    /// u after `ds` from `u` (u > 0), exactly on each piece, and the distance at which u
    /// first reaches `visible` (None: not within `ds`).
    pub fn evolve(&self, u: f64, ds: f64, visible: f64) -> (f64, Option<f64>) {
        self.evolve_within(u, ds, visible, usize::MAX)
            .expect("every piece is laid out")
    }

    /// [`PiecewiseRate::evolve`] on the first `known` pieces (None: the path leaves them).
    pub(super) fn evolve_within(
        &self,
        mut u: f64,
        ds: f64,
        visible: f64,
        known: usize,
    ) -> Option<(f64, Option<f64>)> {
        let mut i = self.knots.partition_point(|&k| k <= u).saturating_sub(1);
        if i >= known {
            return None;
        }
        let (mut t, mut left) = (0.0, ds);
        for _ in 0..2 * self.knots.len() + 4 {
            if left <= 0.0 {
                break;
            }
            let (alpha, beta) = (self.slope[i], self.offset[i]);
            let f = alpha * u + beta;
            if f == 0.0 {
                break;
            }
            // The distance from u to the level `to` on this piece's line (+inf: never).
            let reach = |to: f64| {
                let s = if alpha == 0.0 {
                    (to - u) / beta
                } else {
                    let ratio = (alpha * to + beta) / f;
                    if ratio <= 0.0 {
                        return f64::INFINITY;
                    }
                    ratio.ln() / alpha
                };
                if s >= 0.0 {
                    s
                } else {
                    f64::INFINITY
                }
            };
            let rising = f > 0.0;
            let to_visible = match (rising, visible > u) {
                (true, true) => reach(visible),
                (true, false) => 0.0,
                (false, _) => f64::INFINITY,
            };
            let edge = if rising {
                self.knots.get(i + 1).copied()
            } else {
                (i > 0).then(|| self.knots[i])
            };
            let to_edge = edge.map_or(f64::INFINITY, reach);
            if to_visible <= left.min(to_edge) {
                return Some((visible, Some(t + to_visible)));
            }
            if let Some(at) = edge.filter(|_| to_edge <= left) {
                u = at;
                i = if rising { i + 1 } else { i - 1 };
                if i >= known {
                    return None;
                }
                t += to_edge;
                left -= to_edge;
                continue;
            }
            u = if alpha == 0.0 {
                u + beta * left
            } else {
                (u + beta / alpha) * (alpha * left).exp() - beta / alpha
            };
            break;
        }
        Some((u, None))
    }
}

/// The answer over the tread's life of a cycle's steps, each a profile weighed by its share
/// of the distance, with every step's print saturated on its own: each order's depth obeys
/// dD/ds = Σ_k a_k (b_k D + min(r_k D, m_max · φ_s 2 w′_k |H_w|)), b_k the step's levelling
/// and r_k its growth through the tread on the interval (read off its integrals), solved
/// exactly on each interval of the depth grid (MODEL.md#the-forced-response-saturates). A
/// vibrating step's order locks at depth (its [`super::DepthLock`]): where u R⁰ reaches the radius at
/// which the step's cycle locks at the interval's detuning, or at any depth where the tread's
/// drift carries ν through the order, the step prints the locked cycle's in-phase share of its
/// free print, at most the bound, each share held over short stretches at their predicted
/// middles (MODEL.md#the-locked-print). The steps must share one grid. With `modulation_max` = +inf
/// (no bound, and no lock at depth: the unsaturated reading) it is the summed profile's
/// [`LifeProfile::answer`]. [`SaturatedSteps`] prepares the steps once for many sets.
pub fn answer_saturated_per_step(
    steps: &[(f64, &LifeProfile)],
    c: &FittedConstants,
    p: &Params,
    modulation_max: f64,
) -> LifeAnswer {
    let mean = steps_mean(steps);
    saturated_walk(steps, &mean, c, p, modulation_max)
}

/// A wheel's steps (a cycle's speed bins, a spread's legs), each a profile with its share of
/// the distance, and their share-weighted mean, prepared once: what every set of fitted
/// constants reads ([`SaturatedSteps::answer`] is [`answer_saturated_per_step`] of the steps,
/// bit for bit, without summing the mean again for each set).
#[derive(Debug, Clone, PartialEq)]
pub struct SaturatedSteps {
    steps: Vec<(f64, LifeProfile)>,
    /// The steps' mean, weighed by their shares ([`steps_mean`]).
    mean: LifeProfile,
}

impl SaturatedSteps {
    /// The steps `steps` (share, profile), all on one grid.
    pub fn new(steps: Vec<(f64, LifeProfile)>) -> Self {
        let mean = steps_mean(&Self::refs(&steps));
        SaturatedSteps { steps, mean }
    }

    /// [`answer_saturated_per_step`] of the steps under `c`.
    pub fn answer(&self, c: &FittedConstants, p: &Params, modulation_max: f64) -> LifeAnswer {
        saturated_walk(&Self::refs(&self.steps), &self.mean, c, p, modulation_max)
    }

    /// The steps as [`answer_saturated_per_step`] takes them.
    fn refs(steps: &[(f64, LifeProfile)]) -> Vec<(f64, &LifeProfile)> {
        steps.iter().map(|(a, pr)| (*a, pr)).collect()
    }
}

impl LifeProfile {
    /// [`LifeProfile::answer`] with the zone's power modulation held to at most
    /// `modulation_max` of its mean: [`answer_saturated_per_step`] of this profile alone.
    pub fn answer_saturated(
        &self,
        c: &FittedConstants,
        p: &Params,
        modulation_max: f64,
    ) -> LifeAnswer {
        answer_saturated_per_step(&[(1.0, self)], c, p, modulation_max)
    }
}

/// The steps' mean profile, each weighed by its share of their total (the grid of the first;
/// an empty profile of no orders without steps).
pub(super) fn steps_mean(steps: &[(f64, &LifeProfile)]) -> LifeProfile {
    let total: f64 = steps.iter().map(|(a, _)| a).sum();
    let Some(&(_, like)) = steps.first() else {
        return LifeProfile::zero(0, 1, 0.0);
    };
    let mut mean = LifeProfile::zero(like.max_order, like.intervals, like.usable_m);
    for &(a, profile) in steps {
        mean.add(profile, a / total);
    }
    mean
}

/// [`answer_saturated_per_step`] of `steps` whose mean is `mean` ([`steps_mean`]).
fn saturated_walk(
    steps: &[(f64, &LifeProfile)],
    mean: &LifeProfile,
    c: &FittedConstants,
    p: &Params,
    modulation_max: f64,
) -> LifeAnswer {
    saturated_walk_substeps(steps, mean, c, p, modulation_max, None, true)
}
