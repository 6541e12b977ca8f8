//! The lock at depth and the drift's capture in the walk over the tread's life
//! (MODEL.md#the-lock-at-depth-in-the-estimator).
//!
//! A profile's tongue is the seed's: the cycle locks to an order only while ν stays within the
//! first-order band of a polygon 2R⁰ deep. But the band widens with the polygon: a vibrating
//! wheel's order that has grown to radius R locks wherever the cycle's forced Hopf normal form
//! has a stable fixed point at the detuning Ω − ω_γ, and a locked cycle prints its power
//! harmonic at the phase where it locks, of which only the in-phase part deepens the polygon.
//! Where the tread's drift carries ν through an order the detuning passes zero, where any depth
//! locks: the order is captured. [`DepthLock`] is what a profile carries for that, plain data
//! read off the wheel's cycle; the saturated walk asks it, order by order and interval by
//! interval, at which radius the order locks and what share of the free print it then lays.

use super::super::{unit, Complex64, WheelGrowth};
use crate::wear::response::normal_form::{largest_real_root, ForcedHopf};

/// A vibrating wheel's lock at depth at one speed: its normal form, where its ν is and how the
/// locked cycle's print lies on each order.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthLock {
    /// The cycle's forced Hopf normal form (None: Adler's first-order lock at the free
    /// amplitude).
    pub hopf: Option<ForcedHopf>,
    /// ν = f/f_rot of the new tread at this profile's speed (a leg's ν₀/q).
    pub nu: f64,
    /// 2π f_rot at this profile's speed \[rad/s\]: the detuning per order.
    pub rotation_rad_s: f64,
    /// |P₁|/P̄ of the free cycle: its print as a share of the zone's mean power.
    pub power_harmonic_rel: f64,
    /// f₀/f at the profile's grid of worn depth (its points 0..=intervals).
    pub ratios: Vec<f64>,
    /// Per order 1..=max_order: the first-order half-width Δ₁ per metre of radius \[rad/s/m\]
    /// (0: the order is not profiled), and c_n, with which the in-phase share of the free
    /// print is Re(c_n a) for the locked cycle a of [`ForcedHopf::locked_cycle`].
    pub orders: Vec<(f64, Complex64)>,
}

impl DepthLock {
    /// The lock of `g`'s cycle at `speed_scale` times its speed, for the `orders` that
    /// `profiled` accepts, on the grid of f₀/f `ratios`; None for a stable tread. The normal
    /// form, the band per metre and the print's direction are the wheel's (a leg of a spread
    /// reads the wheel's own model, MODEL.md#the-speed-spread): Δ₁ ∝ V ν is the same at every
    /// leg, ν moves to ν₀/q and f_rot to q f_rot.
    pub(super) fn of(
        g: &WheelGrowth,
        speed_scale: f64,
        ratios: &[f64],
        orders: std::ops::RangeInclusive<u32>,
        profiled: impl Fn(u32) -> bool,
    ) -> Option<Self> {
        let r = &g.response;
        if r.phase_coupling_s <= 0.0 {
            return None;
        }
        let mut lock_orders = vec![(0.0, Complex64::new(0.0, 0.0)); *orders.end() as usize];
        for n in orders.filter(|&n| n >= 1 && profiled(n)) {
            let (per_m_rad_s, _) = g.first_order_lock(n, 1.0);
            // Re(c a) = in_phase_print(p₀ a), p₀ = print_direction · unit(e_n): c from the
            // print's two real directions.
            let order = n as f64;
            let p0 = r.print_direction * unit(g.feedback.forcing_per_radius(order));
            let c = Complex64::new(
                g.feedback.in_phase_print(order, p0),
                -g.feedback
                    .in_phase_print(order, p0 * Complex64::new(0.0, 1.0)),
            );
            lock_orders[n as usize - 1] = (per_m_rad_s, c);
        }
        Some(DepthLock {
            hopf: r.hopf,
            nu: r.nu / speed_scale,
            rotation_rad_s: g.speed_mps * speed_scale / g.r_b,
            power_harmonic_rel: r.power_harmonic_rel,
            ratios: ratios.to_vec(),
            orders: lock_orders,
        })
    }

    /// The detuning Ω − ω_γ \[rad/s\] of order `n` where the tread's f₀/f is `ratio`: the worn
    /// tread's ν is ν₀ f/f₀.
    pub fn detuning_rad_s(&self, n: u32, ratio: f64) -> f64 {
        self.rotation_rad_s * (n as f64 - self.nu / ratio)
    }

    /// Whether ν passes order `n` within interval `j` (1-based) of the grid: the detuning
    /// changes sign there, and the order locks at any depth (the capture).
    pub fn captures(&self, n: u32, j: usize) -> bool {
        let (a, b) = (
            self.detuning_rad_s(n, self.ratios[j - 1]),
            self.detuning_rad_s(n, self.ratios[j]),
        );
        a * b <= 0.0
    }

    /// The detuning of order `n` on interval `j`: zero where it is captured, else at the
    /// interval's middle f₀/f.
    pub fn interval_detuning_rad_s(&self, n: u32, j: usize) -> f64 {
        if self.captures(n, j) {
            0.0
        } else {
            self.detuning_rad_s(n, 0.5 * (self.ratios[j - 1] + self.ratios[j]))
        }
    }

    /// The radius \[m\] at which order `n` locks at `detuning_rad_s` (the normal form's least
    /// locking forcing in closed form, Adler's |Ω − ω_γ| = Δ₁ without one); +inf where the order
    /// is not profiled.
    pub fn lock_radius_m(&self, n: u32, detuning_rad_s: f64) -> f64 {
        let per_m = self.per_m(n);
        if per_m <= 0.0 {
            return f64::INFINITY;
        }
        let needed = match self.hopf {
            Some(hopf) => hopf.locking_first_order_rad_s(detuning_rad_s),
            None => detuning_rad_s.abs(),
        };
        needed / per_m
    }

    /// A radius \[m\] below which order `n` cannot lock at `detuning_rad_s`: the normal form
    /// locks only where Δ₁ ≥ |Ω − ω_γ|/√2 (G(R) ≥ R y²/(1 + c²) on R ≥ ½), Adler's where
    /// Δ₁ ≥ |Ω − ω_γ|; +inf where the order is not profiled.
    pub fn least_lock_radius_m(&self, n: u32, detuning_rad_s: f64) -> f64 {
        let per_m = self.per_m(n);
        if per_m <= 0.0 {
            return f64::INFINITY;
        }
        detuning_rad_s.abs() * std::f64::consts::FRAC_1_SQRT_2 / per_m
    }

    /// The share of the free cycle's full print that the cycle locked to order `n` at radius
    /// `radius_m` and `detuning_rad_s` lays in the polygon's valleys: Re(c_n a), a the locked
    /// cycle (MODEL.md#the-locked-print); None where it does not lock.
    pub fn print_share(&self, n: u32, radius_m: f64, detuning_rad_s: f64) -> Option<f64> {
        let (per_m, c) = *self.orders.get(n as usize - 1)?;
        if per_m <= 0.0 {
            return None;
        }
        let first = per_m * radius_m;
        let locked = match self.hopf {
            Some(hopf) => hopf.locked_cycle(first, detuning_rad_s)?,
            None => {
                let s = detuning_rad_s / first;
                (s.abs() <= 1.0).then(|| Complex64::from_polar(1.0, s.acos()))?
            }
        };
        Some((c * locked).re)
    }

    /// The most |a| of the cycle locked to order `n` at any radius up to `radius_m`, at any
    /// detuning: |a|² ≤ the largest root of R(R − 1)² = 4x², x the normal form's forcing at
    /// `radius_m` (its G(R) = x² is at least R(1 − R)²/4); 1 without a normal form (Adler's
    /// cycle keeps its amplitude).
    pub fn most_amplitude(&self, n: u32, radius_m: f64) -> f64 {
        match self.hopf {
            Some(hopf) => {
                let x = hopf.forcing(self.per_m(n) * radius_m);
                largest_real_root(-2.0, 1.0, -4.0 * x * x).max(1.0).sqrt()
            }
            None => 1.0,
        }
    }

    /// Δ₁ per metre of radius of order `n` (0: not profiled).
    pub(super) fn per_m(&self, n: u32) -> f64 {
        self.orders.get(n as usize - 1).map_or(0.0, |o| o.0)
    }
}

/// A locked stretch ends where u has grown by this factor: the share, held at the stretch's
/// predicted middle, moves with the radius (at 1.2 the cruising points of
/// MODEL.md#the-locked-print are within 0.5% of the midpoint rule on 256 steps per interval;
/// tested).
const STRETCH_GROWTH: f64 = 1.2;

/// The most stretches of one interval beyond one per step's lock radius (u would grow by
/// 1.2¹²⁸ ≈ 10¹⁰ in them).
const MOST_STRETCHES: usize = 128;

/// One interval of one order's walk, as [`OrderLocks::evolve`] follows it.
#[derive(Debug, Clone, Copy)]
pub(super) struct LockedInterval<'t> {
    /// The order.
    pub n: u32,
    /// The interval of the grid (1-based).
    pub j: usize,
    /// The steps' shares, levelling, growth on the interval and bounds.
    pub terms: &'t [super::SpeedTerm],
    /// Each step's free print, in seeds 2R⁰ per metre: what it prints locked, times its share.
    pub locked: &'t [f64],
    /// The interval's distance \[m\].
    pub ds: f64,
    /// u = D/2R⁰ at the visible depth.
    pub visible: f64,
    /// R⁰ \[m\]: u R⁰ is the polygon's radius.
    pub r0: f64,
}

/// One order's lock across a walk's steps: per step and interval of the grid, the detuning and
/// the radii at which the order can and does lock, the exact one taken only where the cheap
/// bound leaves it within reach.
#[derive(Debug)]
pub(super) struct OrderLocks<'a> {
    /// Where given, each locked interval is taken by the midpoint rule on this many steps
    /// instead (the reference the shipped stretches are tested against).
    midpoint_steps: Option<usize>,
    /// Each step's lock (None: a stable tread, or the order not profiled there).
    locks: Vec<Option<&'a DepthLock>>,
    intervals: usize,
    /// Per step and interval (step-major, interval j at j − 1): Ω − ω_γ \[rad/s\].
    detuning: Vec<f64>,
    /// The radius below which the step cannot lock \[m\] (+inf: not before the visible depth).
    least_m: Vec<f64>,
    /// The radius at which it locks \[m\] (NaN: not taken yet).
    lock_m: Vec<f64>,
    /// Per step, the most |a| of its locked cycle up to the visible radius.
    most_amplitude: Vec<f64>,
}

impl<'a> OrderLocks<'a> {
    /// Empty, to be laid out by [`OrderLocks::gather`]; with `midpoint_steps`, each locked
    /// interval by the midpoint rule on that many steps.
    pub(super) fn new(midpoint_steps: Option<usize>) -> Self {
        OrderLocks {
            midpoint_steps: midpoint_steps.map(|k| k.max(1)),
            locks: Vec::new(),
            intervals: 0,
            detuning: Vec::new(),
            least_m: Vec::new(),
            lock_m: Vec::new(),
            most_amplitude: Vec::new(),
        }
    }

    /// Lays out order `n` across `steps` on `intervals` intervals; whether some step can lock
    /// it before its radius reaches `visible_radius_m`.
    pub(super) fn gather(
        &mut self,
        steps: &[(f64, &'a super::LifeProfile)],
        n: u32,
        intervals: usize,
        visible_radius_m: f64,
    ) -> bool {
        self.intervals = intervals;
        self.locks.clear();
        self.detuning.clear();
        self.least_m.clear();
        self.lock_m.clear();
        self.most_amplitude.clear();
        if !steps
            .iter()
            .any(|(_, pr)| pr.lock.as_ref().is_some_and(|l| l.per_m(n) > 0.0))
        {
            return false;
        }
        let mut any = false;
        for &(_, profile) in steps {
            let lock = profile.lock.as_ref().filter(|l| l.per_m(n) > 0.0);
            self.locks.push(lock);
            self.most_amplitude
                .push(lock.map_or(0.0, |l| l.most_amplitude(n, visible_radius_m)));
            for j in 1..=intervals {
                let (detuning, least) = match lock {
                    Some(l) => {
                        let d = l.interval_detuning_rad_s(n, j);
                        (d, l.least_lock_radius_m(n, d))
                    }
                    None => (0.0, f64::INFINITY),
                };
                let least = if least < visible_radius_m {
                    any = true;
                    least
                } else {
                    f64::INFINITY
                };
                self.detuning.push(detuning);
                self.least_m.push(least);
                self.lock_m.push(f64::NAN);
            }
        }
        any
    }

    /// The radius \[m\] at which step `i` locks order `n` on interval `j` (+inf: not before
    /// the visible depth).
    fn lock_radius_m(&mut self, i: usize, n: u32, j: usize) -> f64 {
        let at = i * self.intervals + j - 1;
        if self.least_m[at].is_infinite() {
            return f64::INFINITY;
        }
        if self.lock_m[at].is_nan() {
            let l = self.locks[i].expect("a finite least radius has a lock");
            self.lock_m[at] = l.lock_radius_m(n, self.detuning[at]);
        }
        self.lock_m[at]
    }

    /// The distance \[m\] at which the gathered order reaches u = `visible` from u = 1 on a
    /// path that is never below the walk's (None: it does not, over the grid): each step that
    /// can lock the order on an interval prints there at least its free growth (max(r, 0) u)
    /// and at most the most a locked cycle can print, `locked[i]` |a|_max, within its bound,
    /// and every other at most max(r, 0) u and its bound: summed over the steps, one term
    /// min(B u + R⁺ u + C, B u + Cap), cheap where a cycle has hundreds of speed bins.
    /// `terms` are the steps' shares, levelling and bounds, `growth` sets their growth on an
    /// interval. |a|² ≤ R_max, the largest root of R(R − 1)² = 4x² at the visible radius's
    /// forcing x: G(R) ≥ R(1 − R)²/4 at every detuning (Adler's |a| = 1).
    pub(super) fn upper_reach_m(
        &self,
        terms: &[super::SpeedTerm],
        locked: &[f64],
        growth: impl Fn(usize, &mut [super::SpeedTerm]),
        ds: f64,
        visible: f64,
    ) -> Option<f64> {
        let mut steps = terms.to_vec();
        let (mut rate, mut knots) = (super::PiecewiseRate::of_terms(&[]), Vec::new());
        let (mut u, mut s) = (1.0_f64, 0.0);
        for j in 1..=self.intervals {
            growth(j, &mut steps);
            // Σ a (b u + min(r⁺ u + L, cap)) ≤ min(B u + R⁺ u + C, B u + Cap): one term.
            let mut upper = super::SpeedTerm {
                share: 1.0,
                base_per_m: 0.0,
                growth_per_m: 0.0,
                bound_per_m: 0.0,
                floor_per_m: 0.0,
            };
            for (i, t) in steps.iter().enumerate() {
                let lockable = self.least_m[i * self.intervals + j - 1].is_finite();
                let floor = if lockable {
                    (locked[i] * self.most_amplitude[i]).min(t.bound_per_m)
                } else {
                    0.0
                };
                upper.base_per_m += t.share * t.base_per_m;
                upper.growth_per_m += t.share * t.growth_per_m.max(0.0);
                upper.floor_per_m += t.share * floor;
                upper.bound_per_m += t.share * t.bound_per_m;
            }
            rate.refill(std::slice::from_ref(&upper), &mut knots);
            let (end, cross) = rate.evolve(u, ds, visible);
            if let Some(t) = cross {
                return Some(s + t);
            }
            u = end;
            s += ds;
        }
        None
    }

    /// Whether some step locks order `n` on interval `j` at a depth u = R/R⁰ up to `top`
    /// (`r0` = R⁰ \[m\]): a path that stays below every step's lock there is the unlocked one.
    pub(super) fn reached(&mut self, n: u32, j: usize, top: f64, r0: f64) -> bool {
        let radius = top * r0;
        (0..self.locks.len()).any(|i| {
            self.least_m[i * self.intervals + j - 1] <= radius
                && self.lock_radius_m(i, n, j) <= radius
        })
    }

    /// u after `at.ds` \[m\] from `u` and the distance at which it first reaches `at.visible`
    /// (None: not within the interval), with each step's print locked where u R⁰ is at least
    /// its lock radius: there the step prints `at.locked[i]` (its free print, seeds per metre)
    /// times its in-phase share (MODEL.md#the-locked-print), at most its bound; below,
    /// min(growth u, bound) as [`super::PiecewiseRate`] has it. The share turns slowly with the
    /// radius, so it is held over each stretch, read at its start and again at the predicted
    /// stretch's middle (a predictor–corrector, second order), and the rate is then piecewise
    /// linear and followed exactly; a stretch ends where u reaches the next step's lock radius
    /// or has grown by [`STRETCH_GROWTH`].
    pub(super) fn evolve(&mut self, at: &LockedInterval, mut u: f64) -> (f64, Option<f64>) {
        if let Some(steps) = self.midpoint_steps {
            return self.evolve_midpoint(at, u, steps);
        }
        let LockedInterval {
            n,
            j,
            terms,
            locked,
            ds,
            visible,
            r0,
        } = *at;
        let radii: Vec<f64> = (0..self.locks.len())
            .map(|i| self.lock_radius_m(i, n, j) / r0)
            .collect();
        let mut frozen = terms.to_vec();
        let (mut rate, mut knots) = (super::PiecewiseRate::of_terms(&[]), Vec::new());
        // Holds each locked step's print at its share at `at`, the others free.
        let hold = |at: f64, below: f64, frozen: &mut [super::SpeedTerm]| {
            for (i, (t, free)) in frozen.iter_mut().zip(terms).enumerate() {
                *t = *free;
                let Some(lock) = self.locks[i].filter(|_| below >= radii[i]) else {
                    continue;
                };
                let detuning = self.detuning[i * self.intervals + j - 1];
                if let Some(share) = lock.print_share(n, at * r0, detuning) {
                    t.growth_per_m = 0.0;
                    t.floor_per_m = (locked[i] * share).min(t.bound_per_m);
                }
            }
        };
        let (mut t, mut left) = (0.0, ds);
        for _ in 0..=2 * radii.len() + MOST_STRETCHES {
            if left <= 0.0 {
                break;
            }
            // The next lock radius above u ends the stretch.
            let next = radii
                .iter()
                .copied()
                .filter(|&r| r > u)
                .fold(f64::INFINITY, f64::min);
            let to = visible.min(next).min(u * STRETCH_GROWTH);
            hold(u, u, &mut frozen);
            rate.refill(&frozen, &mut knots);
            let (end, cross) = rate.evolve(u, left, to);
            // Corrector: the shares at the stretch's middle.
            hold(0.5 * (u + end), u, &mut frozen);
            rate.refill(&frozen, &mut knots);
            let (end, cross_again) = rate.evolve(u, left, to);
            match cross_again.or(cross.filter(|_| end >= to)) {
                Some(at) if to == visible => return (visible, Some(t + at)),
                Some(at) => {
                    // A step locks here, or u has grown by the stretch's most: on with the
                    // rest of the interval.
                    u = to;
                    t += at;
                    left -= at;
                }
                None => return (end, None),
            }
        }
        (u, None)
    }

    /// [`OrderLocks::evolve`] by the midpoint rule on `steps` steps, the share read afresh at
    /// every evaluation: the reference.
    fn evolve_midpoint(
        &mut self,
        at: &LockedInterval,
        mut u: f64,
        steps: usize,
    ) -> (f64, Option<f64>) {
        let (n, j, visible, r0) = (at.n, at.j, at.visible, at.r0);
        let radii: Vec<f64> = (0..self.locks.len())
            .map(|i| self.lock_radius_m(i, n, j))
            .collect();
        let rate = |u: f64| -> f64 {
            let mut sum = 0.0;
            for (i, t) in at.terms.iter().enumerate() {
                let free = (t.growth_per_m * u).min(t.bound_per_m);
                let detuning = self.detuning[i * self.intervals + j - 1];
                let print = match self.locks[i].filter(|_| u * r0 >= radii[i]) {
                    Some(l) => l
                        .print_share(n, u * r0, detuning)
                        .map_or(free, |share| (at.locked[i] * share).min(t.bound_per_m)),
                    None => free,
                };
                sum += t.share * (t.base_per_m * u + print);
            }
            sum
        };
        let h = at.ds / steps as f64;
        for step in 0..steps {
            let mid = (u + 0.5 * h * rate(u)).max(f64::MIN_POSITIVE);
            let next = (u + h * rate(mid)).max(f64::MIN_POSITIVE);
            if next >= visible && u < visible {
                return (
                    visible,
                    Some((step as f64 + (visible - u) / (next - u)) * h),
                );
            }
            u = next;
        }
        (u, None)
    }
}

#[cfg(test)]
mod tests {
    use super::super::profile::tests::growth_at;
    use super::*;
    use crate::classify::ClassifierOptions;
    use crate::evaluate::calibrate_wear;
    use crate::model::{Variant, Wheel};
    use crate::params::Params;

    /// The profile's lock is the wheel's own: at the new tread (f₀/f = 1) and the sample's
    /// speed, its lock radius and in-phase share are `WheelGrowth::lock_radius_m` and
    /// `WheelGrowth::locked_print_share` at the same detuning, and a leg at q moves ν to ν₀/q.
    #[test]
    fn the_profile_s_lock_is_the_wheel_s() {
        let p = Params {
            speed_kmh: 100.0,
            toe_deg: 0.3,
            wear_share_straight: 1.0,
            ..Params::default()
        };
        let cal = calibrate_wear(
            &Params::default(),
            Variant::SlidingShare,
            &ClassifierOptions::default(),
        )
        .unwrap();
        let (g, vibrates) = growth_at(&p, &cal, Wheel::Follower);
        assert!(vibrates);
        let nu = g.nu();
        let n = nu.floor() as u32;
        let lock = DepthLock::of(&g, 1.0, &[1.0, 1.0], 1..=n + 2, |_| true).unwrap();
        let v_kmh = p.speed_kmh;
        let mut compared = 0;
        for offset_kmh in [-3.0, -1.0, -0.2, 0.0, 0.4, 1.5, 4.0] {
            // V − V_n = offset: Ω − ω_γ = n (V − V_n)/r_B.
            let detuning = n as f64 * offset_kmh / 3.6 / g.r_b;
            let want = g.lock_radius_m(n, offset_kmh).unwrap();
            let got = lock.lock_radius_m(n, detuning);
            assert!(
                (got - want).abs() <= 1e-9 * want,
                "{offset_kmh}: {got} vs {want}"
            );
            assert!(lock.least_lock_radius_m(n, detuning) <= got * (1.0 + 1e-12));
            for radius_um in [2.0, 8.0, 30.0, 90.0] {
                let r = radius_um * 1e-6;
                let want = g.locked_print_share(n, r, offset_kmh);
                let got = lock.print_share(n, r, detuning);
                assert_eq!(
                    want.is_some(),
                    got.is_some(),
                    "{offset_kmh} km/h, {radius_um} um"
                );
                if let (Some(w), Some(s)) = (want, got) {
                    assert!((w - s).abs() < 1e-9, "{offset_kmh} km/h, {radius_um} um");
                    compared += 1;
                }
            }
        }
        assert!(compared >= 8, "only {compared} locked points compared");
        // At V_n itself (offset 0) the detuning from ν is zero.
        let v_n = v_kmh * nu / n as f64;
        let at_v_n = DepthLock::of(&g, v_n / v_kmh, &[1.0, 1.0], 1..=n + 2, |_| true).unwrap();
        assert!(at_v_n.detuning_rad_s(n, 1.0).abs() < 1e-9 * at_v_n.rotation_rad_s);
        // The tread's drift (f₀/f falling) carries ν = ν₀ f/f₀ up through n + 1.
        let drifting =
            DepthLock::of(&g, 1.0, &[1.0, nu / (n as f64 + 1.5)], 1..=n + 2, |_| true).unwrap();
        assert!(drifting.captures(n + 1, 1) && !drifting.captures(n, 1));
        assert_eq!(drifting.interval_detuning_rad_s(n + 1, 1), 0.0);
    }
}
