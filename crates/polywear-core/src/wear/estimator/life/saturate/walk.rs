//! The saturated walk of every order over the tread's life (MODEL.md#the-forced-response-saturates):
//! screened by each order's sliding bound and unsaturated path, then driven interval by interval
//! on the piecewise-linear rate, locked where a step's cycle locks it.

use super::*;

/// The path of order k (index `k`) of `steps` under the most any print can give: every
/// step's print, free or locked, is at most its bound cap, so that du/ds ≤ B u + C with
/// B = Σ a b the steps' levelling and C = Σ a cap, from u = 1. The walk's u is never above
/// it: where it reaches a depth and how deep it gets screen an order before it is walked.
#[derive(Debug, Clone, Copy)]
struct BoundPath {
    /// B \[1/m\].
    levelling_per_m: f64,
    /// C \[1/m\].
    cap_per_m: f64,
}

impl BoundPath {
    fn of(
        steps: &[(f64, &LifeProfile)],
        others: &[f64],
        k: usize,
        phi: f64,
        modulation_max: f64,
        seed_m: f64,
    ) -> Self {
        let total: f64 = steps.iter().map(|(a, _)| a).sum();
        let (mut b, mut c) = (0.0, 0.0);
        for (&(a, pr), &other) in steps.iter().zip(others) {
            b += a / total * (phi * pr.base_per_share[k] - other);
            c += a / total * phi * pr.full_print_per_share[k] * modulation_max / seed_m;
        }
        BoundPath {
            levelling_per_m: b,
            cap_per_m: c,
        }
    }

    /// The least distance \[m\] at which it reaches u = `visible` (+inf: never).
    fn reach_m(&self, visible: f64) -> f64 {
        let (b, c) = (self.levelling_per_m, self.cap_per_m);
        let (from, to) = (b + c, b * visible + c);
        if from <= 0.0 || to <= 0.0 {
            f64::INFINITY
        } else if b == 0.0 {
            (visible - 1.0) / c
        } else {
            (to / from).ln() / b
        }
    }

    /// Its largest ln u over the first `distance_m` metres (the path is monotone: its start
    /// or its end).
    fn log_peak(&self, distance_m: f64) -> f64 {
        let (b, c) = (self.levelling_per_m, self.cap_per_m);
        let end = if b == 0.0 {
            1.0 + c * distance_m
        } else {
            (1.0 + c / b) * (b * distance_m).exp() - c / b
        };
        end.max(1.0).ln()
    }
}

/// [`saturated_walk`], each interval where an order is locked by the midpoint rule on
/// `midpoint_steps` steps where given (the reference), leaving out the orders that cannot beat
/// the answer so far where `screen` (else driving every order: what the screen is tested
/// against).
pub(in crate::wear::estimator::life) fn saturated_walk_substeps(
    steps: &[(f64, &LifeProfile)],
    mean: &LifeProfile,
    c: &FittedConstants,
    p: &Params,
    modulation_max: f64,
    midpoint_steps: Option<usize>,
    screen: bool,
) -> LifeAnswer {
    let Some(&(_, like)) = steps.first() else {
        return mean.answer(c, p);
    };
    let wear = mean.tread_wear_m_per_m(c);
    let target = print_log_ratio(p);
    if wear.is_nan() || wear <= 0.0 || like.max_order == 0 || target <= 0.0 {
        return mean.answer(c, p);
    }
    let tread_life = tread_life_km(p, wear * MM_PER_1000KM_PER_M_PER_M);
    let walk = SaturatedWalk::new(steps, like, c, p, modulation_max, wear, target);
    // Each order unsaturated, from the mean profile: where it first reaches the visible depth
    // (in metres) and its largest ln(D/2R⁰). The saturated order is never earlier or deeper,
    // so an order that cannot beat the answer so far is not driven, and the order visible
    // first unsaturated is driven first; the answer is that of driving every order in turn.
    let unsaturated = walk.unsaturated(mean, like.max_order, c, wear, target);
    let leader = (1..=like.max_order)
        .filter_map(|n| unsaturated[n as usize - 1].0.map(|at| (at, n)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n);
    let mut reach = Reach {
        first: None,
        deepest: (f64::NEG_INFINITY, 1),
    };
    let mut scratch = Scratch {
        terms: Vec::with_capacity(steps.len()),
        rate: PiecewiseRate::of_terms(&[]),
        knots: Vec::with_capacity(steps.len()),
        locked: Vec::with_capacity(steps.len()),
        locks: OrderLocks::new(midpoint_steps),
    };
    // (Within a relative 10⁻⁹: where no knot is reached the two are one value, rounded twice.)
    let rest = (1..=like.max_order).filter(|&n| Some(n) != leader);
    for n in leader.into_iter().chain(rest) {
        let unsaturated = unsaturated[n as usize - 1];
        let Some(lockable) = walk.to_drive(n, unsaturated, &reach, &mut scratch, screen) else {
            continue;
        };
        let log_peak = walk.drive(n, lockable, &mut reach.first, &mut scratch);
        if log_peak > reach.deepest.0 || (log_peak == reach.deepest.0 && n < reach.deepest.1) {
            reach.deepest = (log_peak, n);
        }
    }
    LifeAnswer::of_walk(
        reach.first.map(|(at, n)| (at * 1e-3, n)),
        reach.deepest,
        target,
        tread_life,
        1,
    )
}

/// The answer so far of a saturated walk: the first polygon (distance \[m\], order) and the
/// deepest order (its largest ln(D/2R⁰), order).
struct Reach {
    first: Option<(f64, u32)>,
    deepest: (f64, u32),
}

/// What each order's drive reuses: the steps' terms, the piecewise rate and its knots, the
/// steps' locked prints and the locks laid out.
struct Scratch<'a> {
    terms: Vec<SpeedTerm>,
    rate: PiecewiseRate,
    knots: Vec<(f64, f64, f64)>,
    locked: Vec<f64>,
    locks: OrderLocks<'a>,
}

/// What every order's saturated walk shares under one set of constants.
struct SaturatedWalk<'a> {
    steps: &'a [(f64, &'a LifeProfile)],
    /// Each step's (1 − φ_s)(O₀ + k_d O₁) \[1/m\].
    others: Vec<f64>,
    /// The steps' shares' sum.
    total: f64,
    phi: f64,
    modulation_max: f64,
    intervals: usize,
    /// The grid's step in worn depth \[m\] and in distance \[m\], and the whole grid \[m\].
    dw: f64,
    ds: f64,
    grid_m: f64,
    /// u = D/2R⁰ at the visible depth.
    visible: f64,
    /// 2R⁰ \[m\].
    seed_m: f64,
}

impl<'a> SaturatedWalk<'a> {
    fn new(
        steps: &'a [(f64, &'a LifeProfile)],
        like: &LifeProfile,
        c: &FittedConstants,
        p: &Params,
        modulation_max: f64,
        wear: f64,
        target: f64,
    ) -> Self {
        let phi = c.wear_share_straight;
        let others: Vec<f64> = steps
            .iter()
            .map(|(_, pr)| {
                (1.0 - phi)
                    * (pr.other_per_share.0 + c.wear_rate_driven_factor * pr.other_per_share.1)
            })
            .collect();
        let intervals = like.intervals;
        let dw = like.usable_m / intervals as f64;
        let ds = dw / wear;
        SaturatedWalk {
            steps,
            others,
            total: steps.iter().map(|(a, _)| a).sum(),
            phi,
            modulation_max,
            intervals,
            dw,
            ds,
            grid_m: ds * intervals as f64,
            visible: target.exp(),
            seed_m: 2.0 * p.seed_runout_um * 1e-6,
        }
    }

    /// Each order of the mean profile unsaturated: where it first reaches the visible depth
    /// \[m\] (none: never) and its largest ln(D/2R⁰).
    fn unsaturated(
        &self,
        mean: &LifeProfile,
        max_order: u32,
        c: &FittedConstants,
        wear: f64,
        target: f64,
    ) -> Vec<(Option<f64>, f64)> {
        let (phi, dw, ds) = (self.phi, self.dw, self.ds);
        let mean_other = (1.0 - phi)
            * (mean.other_per_share.0 + c.wear_rate_driven_factor * mean.other_per_share.1);
        (1..=max_order)
            .map(|n| {
                let log =
                    |j: usize| (phi * mean.integral(n, j) - mean_other * dw * j as f64) / wear;
                let (mut before, mut peak) = (0.0_f64, 0.0_f64);
                for j in 1..=self.intervals {
                    let now = log(j);
                    if now >= target {
                        let at = (j as f64 - 1.0 + (target - before) / (now - before)) * ds;
                        return (Some(at), target.max(peak));
                    }
                    peak = peak.max(now);
                    before = now;
                }
                (None, peak)
            })
            .collect()
    }

    /// Sets each step's growth through the tread on interval `j` of order `n` into `terms`.
    fn set_growth(&self, n: u32, j: usize, terms: &mut [SpeedTerm]) {
        let (phi, dw) = (self.phi, self.dw);
        for (t, (&(_, pr), &other)) in terms.iter_mut().zip(self.steps.iter().zip(&self.others)) {
            let rate = (phi * (pr.integral(n, j) - pr.integral(n, j - 1)) - other * dw) / dw;
            t.growth_per_m = rate - t.base_per_m;
        }
    }

    /// Whether order `n` is driven, and then whether its lock is laid out (`Some(lockable)`):
    /// none for an order no step profiled, or, where `screen`, for one that cannot beat the
    /// answer so far `reach` by its sliding bound, its `unsaturated` path or its locked walk's
    /// upper path. A driven order's steps' terms (and locked prints) are left in `scratch`.
    fn to_drive(
        &self,
        n: u32,
        unsaturated: (Option<f64>, f64),
        reach: &Reach,
        scratch: &mut Scratch<'a>,
        screen: bool,
    ) -> Option<bool> {
        let k = n as usize - 1;
        let (steps, phi, seed_m) = (self.steps, self.phi, self.seed_m);
        let (first, deepest) = (reach.first, reach.deepest);
        // An order no step profiled (the legs lay only the orders that can matter) has no
        // print: it only levels from the seed.
        if steps
            .iter()
            .all(|(_, pr)| pr.full_print_per_share[k] == 0.0)
        {
            return None;
        }
        // Every print, free or locked, keeps to the sliding bound: an order whose bound cannot
        // beat the answer so far is not driven, nor laid out for the lock (its peak does not
        // count once there is an answer).
        let bounded = self.modulation_max.is_finite();
        let bound = bounded
            .then(|| BoundPath::of(steps, &self.others, k, phi, self.modulation_max, seed_m));
        let bound_reach = bound.map_or(0.0, |b| b.reach_m(self.visible));
        let out_of_reach = match first {
            Some((m, _)) => bound_reach > m * (1.0 + 1e-9),
            None => bound.is_some_and(|b| b.log_peak(self.grid_m) + 1e-9 < deepest.0),
        };
        if screen && out_of_reach {
            return None;
        }
        // The unsaturated screen: the saturated, unlocked order is never earlier or deeper.
        let unsaturated_hopeless = match (first, unsaturated) {
            (Some((m, _)), (at, _)) => at.is_none_or(|at| at > m * (1.0 + 1e-9)),
            // Not deeper than the deepest so far; or never above its seed unsaturated, once an
            // order has been walked: at the seed no order is the wear's (without this, every
            // order of a levelling wheel was walked: most of `polywear cycle`'s time).
            (None, (None, peak)) => peak + 1e-9 < deepest.0 || (peak <= 0.0 && deepest.0 >= 0.0),
            (None, (Some(_), _)) => false,
        };
        // An order some step can lock before it is visible may outgrow its unsaturated path
        // (a locked cycle prints at once what the linear loop grows to); it is screened by the
        // bound above and by the locked walk's upper path below. One whose bound does not reach
        // the visible depth within the tread's life is walked unlocked without laying out its
        // lock: the upper path, never above the bound, would say the same.
        let lockable = bounded
            && bound_reach <= self.grid_m * (1.0 + 1e-9)
            && scratch
                .locks
                .gather(steps, n, self.intervals, self.visible * (0.5 * seed_m));
        if !lockable && unsaturated_hopeless && screen {
            return None;
        }
        self.lay_terms(k, lockable, scratch);
        if !lockable {
            return Some(false);
        }
        // An order that cannot reach the visible depth even with every step that can lock it
        // printing the most a locked cycle can (or not before the answer so far) is walked
        // without the lock: its answer is the same, and its peak the unlocked one.
        let growth = |j: usize, terms: &mut [SpeedTerm]| self.set_growth(n, j, terms);
        let upper = scratch.locks.upper_reach_m(
            &scratch.terms,
            &scratch.locked,
            growth,
            self.ds,
            self.visible,
        );
        match (upper, first) {
            // Walked unlocked, the unsaturated screen holds again.
            (None, _) if screen && unsaturated_hopeless => None,
            (None, _) => Some(false),
            (Some(at), Some((m, _))) if screen && at > m * (1.0 + 1e-9) => None,
            _ => Some(true),
        }
    }

    /// What each step gives order `k + 1` at every depth into `scratch.terms`: its share,
    /// levelling and bound (only the growth through the tread moves along the grid); and where
    /// `lockable`, each step's locked print at the free amplitude (seeds per metre).
    fn lay_terms(&self, k: usize, lockable: bool, scratch: &mut Scratch<'a>) {
        let (phi, seed_m) = (self.phi, self.seed_m);
        scratch.terms.clear();
        scratch.terms.extend(
            self.steps
                .iter()
                .zip(&self.others)
                .map(|(&(a, pr), &other)| SpeedTerm {
                    share: a / self.total,
                    base_per_m: phi * pr.base_per_share[k] - other,
                    growth_per_m: 0.0,
                    bound_per_m: phi * pr.full_print_per_share[k] * self.modulation_max / seed_m,
                    floor_per_m: 0.0,
                }),
        );
        if lockable {
            scratch.locked.clear();
            scratch.locked.extend(self.steps.iter().map(|&(_, pr)| {
                let ph = pr.lock.as_ref().map_or(0.0, |l| l.power_harmonic_rel);
                phi * pr.full_print_per_share[k] * ph / seed_m
            }));
        }
    }

    /// Drives order `n` over the grid from its seed with the steps' terms in `scratch`, its
    /// lock laid out where `lockable`, and sets `first` where it is visible before it. Returns
    /// its largest ln(D/2R⁰).
    fn drive(
        &self,
        n: u32,
        lockable: bool,
        first: &mut Option<(f64, u32)>,
        scratch: &mut Scratch<'a>,
    ) -> f64 {
        let (ds, visible, r0) = (self.ds, self.visible, 0.5 * self.seed_m);
        let Scratch {
            terms,
            rate,
            knots,
            locked,
            locks,
        } = scratch;
        let (mut u, mut peak, mut s) = (1.0_f64, 1.0_f64, 0.0);
        for j in 1..=self.intervals {
            self.set_growth(n, j, terms.as_mut_slice());
            let (mut end, mut cross) = rate.refill_evolve(terms.as_slice(), knots, u, ds, visible);
            // A step whose order locks within reach of this interval's path turns its print to
            // the locked one there: the rate is no longer piecewise linear in u.
            if lockable && locks.reached(n, j, u.max(end), r0) {
                let at = LockedInterval {
                    n,
                    j,
                    terms: terms.as_slice(),
                    locked: locked.as_slice(),
                    ds,
                    visible,
                    r0,
                };
                (end, cross) = locks.evolve(&at, u);
            }
            if let Some(t) = cross {
                let at = s + t;
                if first.is_none_or(|(m, o)| at < m || (at == m && n < o)) {
                    *first = Some((at, n));
                }
                peak = visible;
                break;
            }
            u = end;
            peak = peak.max(u);
            s += ds;
            if first.is_some_and(|(m, _)| s > m) {
                break;
            }
        }
        peak.ln()
    }
}
