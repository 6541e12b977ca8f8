//! One operating point's growth over the tread's life as a profile in the worn depth, with no
//! speed spread: what a drive cycle sums over its steps (MODEL.md#along-a-drive-cycle).
//!
//! Over the tread's life a step's order n grows at β_n(x) read at x = n·f₀/f(h₀ − w), w the
//! worn depth. A cycle's steps share the tread, so they share w, not the distance: the depth
//! falls at the cycle's mean whole even wear ẇ̄, and ln D_n(w) = ln 2R⁰ + (1/ẇ̄)·Σ_k a_k
//! ∫₀^w β_n,k dw′, a_k the step's share of the cycle's distance. β_n,k is affine in the fitted
//! constants, φ_s·B_n,k − (1 − φ_s)(O₀ + k_d O₁), and so is ẇ_k: the profile keeps the
//! cumulative integrals of B_n at φ_s = 1 on a grid of w, and the constant terms, so that a
//! cycle sums them once and every calibrated set reads its answer off the sums.

use super::depth_lock::{LockedInterval, OrderLocks};
use super::{DepthLock, LifeAnswer, Nodes, TransferNodes, TreadDrift, WORN_DEGREE};
use crate::params::Params;
use crate::wear::estimator::{print_log_ratio, tread_life_km, Complex64, WheelGrowth};
use crate::wear::physics::fitted::{FittedConstants, WearAnswer};
use crate::wear::physics::law::MM_PER_1000KM_PER_M_PER_M;

/// Intervals of the usable depth a drive cycle's profiles are laid on: the integrals are exact
/// at the grid's points, and the crossing of the visible depth is read linearly between them;
/// at 128 (50 µm of 6.4 mm) the distances are within 1% of the brute-force integral at highway
/// points, stable and vibrating (tested), at half the cost of 256.
pub const LIFE_PROFILE_INTERVALS: usize = 128;

/// An order far from every resonance is taken exactly at every this many points of the grid and
/// by the cubic through the values and slopes between them.
const COARSE: usize = 8;

/// "Far": no resonance within this many orders of the order's path x ∈ \[n·f₀/f_end, n\] ...
const FAR_MARGIN_ORDERS: f64 = 2.0;

/// ... plus this share of n.
const FAR_MARGIN_SHARE: f64 = 0.05;

/// One wheel's profile over the tread's life at one operating point, with no speed spread.
#[derive(Debug, Clone, PartialEq)]
pub struct LifeProfile {
    /// The orders profiled, 1..=`max_order`.
    pub max_order: u32,
    /// Intervals of the grid of worn depth: w_j = usable · j / `intervals`, j = 0..=intervals.
    pub intervals: usize,
    /// The usable depth \[m\] (the grid's last point).
    pub usable_m: f64,
    /// ∫₀^{w_j} B_n dw at φ_s = 1 (B_n \[1/m\] the growth over distance, w \[m\] the worn
    /// depth), order-major: `integrals[(n − 1)·(intervals + 1) + j]`.
    pub integrals: Vec<f64>,
    /// The tread's even wear per unit φ_s \[m/m\]: the lateral power's and the slip power's.
    pub even_per_share: f64,
    /// The position's even-wear rate w′_pos = P₀ + k_d P₁ \[m/m\].
    pub position_rate: (f64, f64),
    /// λ_other per unit (1 − φ_s) = O₀ + k_d O₁ \[1/m\].
    pub other_per_share: (f64, f64),
    /// Per order, β's part with no transfer through the tread at φ_s = 1 (its levelling, and
    /// the slip power's part) \[1/m\]: what the saturated print keeps linear in D_n.
    pub base_per_share: Vec<f64>,
    /// Per order, 2 w′ |H_w| per unit φ_s \[m/m\]: the rise of D_n per metre when the zone's
    /// power is modulated by its whole mean (|δP_n|/P̄ = 1), the lateral power's w′ alone.
    pub full_print_per_share: Vec<f64>,
    /// A vibrating wheel's lock at depth at the profile's speed (None: a stable tread, or a sum
    /// of steps without one): where its orders lock as they deepen and what the locked cycle
    /// then prints ([`DepthLock`], MODEL.md#the-locked-print).
    pub lock: Option<DepthLock>,
}

impl LifeProfile {
    /// A profile of nothing, to which weighted profiles are added ([`LifeProfile::add`]).
    pub fn zero(max_order: u32, intervals: usize, usable_m: f64) -> Self {
        LifeProfile {
            max_order,
            intervals,
            usable_m,
            integrals: vec![0.0; max_order as usize * (intervals + 1)],
            even_per_share: 0.0,
            position_rate: (0.0, 0.0),
            other_per_share: (0.0, 0.0),
            base_per_share: vec![0.0; max_order as usize],
            full_print_per_share: vec![0.0; max_order as usize],
            lock: None,
        }
    }

    /// Adds `weight` times `other` (a step's profile by its distance): every term is linear in
    /// the profiles, so the weighted mean of a cycle's steps is their sum over the total
    /// weight ([`LifeProfile::scale`]). The lock is not a sum: a profile without one takes
    /// `other`'s (a cycle's bin sums the steps of one speed, which share it). Panics where the
    /// grids differ.
    pub fn add(&mut self, other: &LifeProfile, weight: f64) {
        assert_eq!(
            (self.max_order, self.intervals),
            (other.max_order, other.intervals),
            "profiles on different grids"
        );
        for (a, b) in self.integrals.iter_mut().zip(&other.integrals) {
            *a += weight * b;
        }
        self.even_per_share += weight * other.even_per_share;
        self.position_rate.0 += weight * other.position_rate.0;
        self.position_rate.1 += weight * other.position_rate.1;
        self.other_per_share.0 += weight * other.other_per_share.0;
        self.other_per_share.1 += weight * other.other_per_share.1;
        for (a, b) in self.base_per_share.iter_mut().zip(&other.base_per_share) {
            *a += weight * b;
        }
        for (a, b) in self
            .full_print_per_share
            .iter_mut()
            .zip(&other.full_print_per_share)
        {
            *a += weight * b;
        }
        if self.lock.is_none() {
            self.lock.clone_from(&other.lock);
        }
    }

    /// Every term times `factor`.
    pub fn scale(&mut self, factor: f64) {
        let mut scaled = LifeProfile::zero(self.max_order, self.intervals, self.usable_m);
        scaled.add(self, factor);
        *self = scaled;
    }

    /// The answer over the tread's life under `c`, for the seed and visible depth of `p`: the
    /// depth falls at the whole even wear ẇ, ln D_n(w_j) = (φ_s I_n(w_j) − (1 − φ_s) λ_other
    /// w_j)/ẇ from the seed, the first order to reach ln(d_visible/2R⁰) (linear between the
    /// grid's points) is the polygon, at the distance w/ẇ; none before the usable depth: +inf,
    /// the order that got deepest and how deep. NaN where the tread does not wear.
    pub fn answer(&self, c: &FittedConstants, p: &Params) -> LifeAnswer {
        let wear = self.tread_wear_m_per_m(c);
        let tread_life = tread_life_km(p, wear * MM_PER_1000KM_PER_M_PER_M);
        if wear.is_nan() || wear <= 0.0 || self.max_order == 0 {
            return LifeAnswer {
                answer: WearAnswer {
                    polygon_order_wear: f64::NAN,
                    distance_to_visible_km: f64::NAN,
                    tread_life_km: tread_life,
                },
                peak_share_of_visible: f64::NAN,
            };
        }
        let target = print_log_ratio(p);
        let phi = c.wear_share_straight;
        let other = (1.0 - phi)
            * (self.other_per_share.0 + c.wear_rate_driven_factor * self.other_per_share.1);
        let depth = |j: usize| self.usable_m * j as f64 / self.intervals as f64;
        let mut first: Option<(f64, u32)> = None;
        let mut deepest = (f64::NEG_INFINITY, 1);
        for n in 1..=self.max_order {
            let log = |j: usize| (phi * self.integral(n, j) - other * depth(j)) / wear;
            let mut before = 0.0;
            let mut peak = 0.0_f64;
            for j in 1..=self.intervals {
                let now = log(j);
                if now >= target && target > 0.0 {
                    let w = depth(j - 1)
                        + (depth(j) - depth(j - 1)) * (target - before) / (now - before);
                    if first.is_none_or(|(m, _)| w < m) {
                        first = Some((w, n));
                    }
                    peak = peak.max(now);
                    break;
                }
                peak = peak.max(now);
                before = now;
            }
            if peak > deepest.0 {
                deepest = (peak, n);
            }
        }
        LifeAnswer::of_walk(
            first.map(|(w, n)| (w / wear * 1e-3, n)),
            deepest,
            target,
            tread_life,
            1,
        )
    }

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

    /// ∫₀^{w_j} B_n dw of order `n` at grid point `j`.
    pub fn integral(&self, n: u32, j: usize) -> f64 {
        self.integrals[(n as usize - 1) * (self.intervals + 1) + j]
    }

    /// The tread's whole even wear under `c` \[m/m\]: φ_s's share of the powers' and the
    /// rest of the position's, (1 − φ_s) w′_pos.
    pub fn tread_wear_m_per_m(&self, c: &FittedConstants) -> f64 {
        let phi = c.wear_share_straight;
        let (p0, p1) = self.position_rate;
        phi * self.even_per_share + (1.0 - phi) * (p0 + c.wear_rate_driven_factor * p1)
    }
}

/// The grid of worn depth a wheel's profiles are laid on: its tread's drift, and f₀/f at
/// each of the grid's depths w_j = usable · j/`intervals` (the drift's polynomial inverted, it
/// falls with the depth, so that the depths and the integrals' weights are one function).
/// Taken once per wheel: every leg of every spread reads the same.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct DepthGrid {
    pub(super) drift: TreadDrift,
    pub(super) intervals: usize,
    pub(super) ratios: Vec<f64>,
}

impl DepthGrid {
    /// The wheel's grid of `intervals` equal intervals of its usable depth.
    pub(super) fn of(g: &WheelGrowth, intervals: usize) -> Self {
        let drift = TreadDrift::of(&g.params, &g.patch);
        let usable = drift.usable_m;
        let ratios = (0..=intervals)
            .map(|j| drift.ratio_at(usable * j as f64 / intervals as f64))
            .collect();
        DepthGrid {
            drift,
            intervals,
            ratios,
        }
    }
}

impl WheelGrowth {
    /// f₀/f at the worn depths of [`WheelGrowth::life_profile`]'s grid of `intervals` equal
    /// intervals (the tread frequency's drift, MODEL.md#the-ageing-tread): order n reads the
    /// new tire's transfer at x = n·f₀/f there.
    pub fn worn_frequency_ratios(&self, intervals: usize) -> Vec<f64> {
        DepthGrid::of(self, intervals).ratios
    }

    /// The wheel's [`LifeProfile`] for orders 1..=`max_order` on `intervals` equal intervals of
    /// the usable depth. Each order's integral of the linear loop is closed-form from the
    /// moments of the transfer's nodes (Ḡ linear between them, as the answer over the tread's
    /// life takes it); where a vibrating wheel's cycle locks to the order (no spread: the
    /// tongue |x − ν| ≤ δ_n in orders), the locked print replaces the loop over the depths
    /// that put x there, exactly.
    pub fn life_profile(&self, max_order: u32, intervals: usize) -> LifeProfile {
        self.life_profile_with(1, max_order, intervals, true)
    }

    /// [`WheelGrowth::life_profile`], the orders far from every resonance by their cubic
    /// between every [`COARSE`]-th point where `coarse` (else every point exactly: what the
    /// cubic is tested against).
    fn life_profile_with(
        &self,
        from_order: u32,
        max_order: u32,
        intervals: usize,
        coarse: bool,
    ) -> LifeProfile {
        let grid = DepthGrid::of(self, intervals);
        let lo = from_order.max(1) as f64 * grid.drift.at_end().min(1.0);
        let transfer = TransferNodes::new(self, lo, max_order as f64, 0.0, Nodes::Adaptive);
        self.life_profile_on(
            &grid,
            &transfer,
            1.0,
            from_order,
            |_| true,
            max_order,
            coarse,
        )
    }

    /// [`WheelGrowth::life_profile_with`] of the wheel's own model read at `speed_scale` times
    /// its speed, from `transfer`, the nodes of its own transfer with no spread: the leg's
    /// transfer at order x is the wheel's at x·q (ω = x v/r_B), so it is read there, and the
    /// moments' weights take q^{−(m+1)} (∫ (y/q)^m G(y) dy/q); ν is ν₀/q, and the tongue's band
    /// of speeds is the wheel's. `transfer` must span \[`from_order`·f₀/f_end·q,
    /// `max_order`·q\]. With q = 1 it is the wheel's own profile, bit for bit. The orders
    /// `profiled` refuses are left at zero (each order's figures are those of the profile of
    /// every order from `from_order`, bit for bit).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn life_profile_on(
        &self,
        grid: &DepthGrid,
        transfer: &TransferNodes,
        speed_scale: f64,
        from_order: u32,
        profiled: impl Fn(u32) -> bool,
        max_order: u32,
        coarse: bool,
    ) -> LifeProfile {
        let q = speed_scale;
        let DepthGrid {
            drift,
            intervals,
            ratios,
        } = grid;
        let (drift, intervals) = (drift, *intervals);
        let slope = drift.slope_coefficients();
        let end = drift.at_end();
        let usable = drift.usable_m;
        let points = intervals + 1;
        let depth = |j: usize| usable * j as f64 / intervals as f64;
        let nu = self.nu() / q;
        let v = self.speed_mps * q;
        let resonances: Vec<f64> = self.resonance_orders().map(|r| r / q).collect();
        let mut integrals = Vec::with_capacity(max_order as usize * points);
        let mut base_per_share = Vec::with_capacity(max_order as usize);
        let mut full_print_per_share = Vec::with_capacity(max_order as usize);
        let from_order = from_order.clamp(1, max_order.max(1));
        for _ in 1..from_order.min(max_order + 1) {
            integrals.extend(std::iter::repeat_n(0.0, points));
            base_per_share.push(0.0);
            full_print_per_share.push(0.0);
        }
        for (n, (zone, forcing)) in
            (from_order..=max_order).zip(self.feedback.zones_and_forcings(from_order))
        {
            // (The zones are taken by rotation from `from_order` on, so an order's figures do
            // not depend on which orders are profiled.) Past the wheel's wall-clock limit no
            // order is laid out: the callers ask out_of_time and give no answer.
            if !profiled(n) || self.deadline.passed() {
                integrals.extend(std::iter::repeat_n(0.0, points));
                base_per_share.push(0.0);
                full_print_per_share.push(0.0);
                continue;
            }
            let order = n as f64;
            let order_loop = self.order_loop(zone, forcing, 1.0, 0.0);
            base_per_share.push(order_loop.base_per_m);
            full_print_per_share.push(2.0 * self.even_per_share * zone.norm_sqr().sqrt());
            // The weights of the moments: ∫_x^n Ḡ (−dw/dx′) dx′ = Σ_m −e_m/n^{m+1} (M_m(n) −
            // M_m(x)).
            let mut weight = [Complex64::new(0.0, 0.0); WORN_DEGREE];
            let scaled = order * q;
            let mut power = 1.0 / scaled;
            for (c, &e) in weight.iter_mut().zip(&slope) {
                *c = order_loop.through_per_m * (-e * power);
                power /= scaled;
            }
            let weigh = |m: &[Complex64; WORN_DEGREE]| {
                weight
                    .iter()
                    .zip(m)
                    .fold(0.0, |acc, (c, m)| acc + (c * m).re)
            };
            let at_start = weigh(&transfer.point(scaled).1);
            // ∫₀^w of the linear loop, from the moments at x = n·f₀/f at w.
            let linear_from = |w: f64, m: &[Complex64; WORN_DEGREE]| {
                order_loop.base_per_m * w + at_start - weigh(m)
            };
            let linear = |w: f64, x: f64| linear_from(w, &transfer.point(x * q).1);
            // The tongue in depth: where |x − ν| ≤ δ_n (x falls as w grows), and the locked
            // print's rate there.
            let (_, half_mps) = self.tongue_mps(order, forcing, self.seed_m);
            let tongue = (half_mps > 0.0).then(|| {
                let delta = half_mps * order / v;
                let (x_top, x_bottom) = (nu + delta, nu - delta);
                let at = |x: f64| -> (f64, f64) {
                    let r = x / order;
                    if r >= 1.0 {
                        (0.0, order)
                    } else if r <= end {
                        (usable, order * end)
                    } else {
                        (drift.worn_at(r), x)
                    }
                };
                (at(x_top), at(x_bottom))
            });
            let locked = order_loop.locked_per_m;
            let in_tongue = tongue.is_some_and(|((w_in, _), (w_out, _))| w_out > w_in);
            // An order whose x stays away from every resonance of the transfer (and from the
            // tongue) has a smooth integral: it is taken exactly at every COARSE-th point and
            // by its cubic through the values and slopes (dI/dw = β at x) between them.
            let margin = FAR_MARGIN_ORDERS + FAR_MARGIN_SHARE * order;
            let far = coarse
                && !in_tongue
                && intervals % COARSE == 0
                && resonances
                    .iter()
                    .all(|&at| at < order * end - margin || at > order + margin);
            // The grid's points fall in x: their segments are found walking down.
            let mut hint = transfer.x.len();
            if far {
                let mut before: Option<(f64, f64)> = None;
                for (j, &r) in ratios.iter().enumerate().step_by(COARSE) {
                    let (w, x) = (depth(j), order * r);
                    let (g, moments) = transfer.point_below(x * q, &mut hint);
                    let value = linear_from(w, &moments);
                    let slope = order_loop.linear_per_m(g);
                    if let Some((value_before, slope_before)) = before {
                        let h = depth(j) - depth(j - COARSE);
                        for k in 1..COARSE {
                            let t = k as f64 / COARSE as f64;
                            let (t2, t3) = (t * t, t * t * t);
                            integrals.push(
                                (2.0 * t3 - 3.0 * t2 + 1.0) * value_before
                                    + (t3 - 2.0 * t2 + t) * h * slope_before
                                    + (3.0 * t2 - 2.0 * t3) * value
                                    + (t3 - t2) * h * slope,
                            );
                        }
                    }
                    integrals.push(value);
                    before = Some((value, slope));
                }
                continue;
            }
            for (j, &r) in ratios.iter().enumerate() {
                let (w, x) = (depth(j), order * r);
                let mut total = linear_from(w, &transfer.point_below(x * q, &mut hint).1);
                if let Some(((w_in, x_in), (w_out, x_out))) = tongue {
                    if w > w_in && w_out > w_in {
                        let (w_to, x_to) = if w < w_out { (w, x) } else { (w_out, x_out) };
                        total += locked * (w_to - w_in) - (linear(w_to, x_to) - linear(w_in, x_in));
                    }
                }
                integrals.push(total);
            }
        }
        let position = |k_d: f64| self.position_rate(k_d);
        let other = |k_d: f64| position(k_d) * self.feedback.local_per_m;
        LifeProfile {
            max_order,
            intervals,
            usable_m: usable,
            integrals,
            even_per_share: self.even_per_share + self.slip_even_per_share,
            position_rate: (position(0.0), position(1.0) - position(0.0)),
            other_per_share: (other(0.0), other(1.0) - other(0.0)),
            base_per_share,
            full_print_per_share,
            lock: DepthLock::of(self, q, ratios, from_order..=max_order, profiled),
        }
    }
}

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
    fn evolve_within(
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
/// vibrating step's order locks at depth (its [`DepthLock`]): where u R⁰ reaches the radius at
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

/// [`saturated_walk`], each interval where an order is locked by the midpoint rule on
/// `midpoint_steps` steps where given (the reference), leaving out the orders that cannot beat
/// the answer so far where `screen` (else driving every order: what the screen is tested
/// against).
pub(super) fn saturated_walk_substeps(
    steps: &[(f64, &LifeProfile)],
    mean: &LifeProfile,
    c: &FittedConstants,
    p: &Params,
    modulation_max: f64,
    midpoint_steps: Option<usize>,
    screen: bool,
) -> LifeAnswer {
    let total: f64 = steps.iter().map(|(a, _)| a).sum();
    let Some(&(_, like)) = steps.first() else {
        return mean.answer(c, p);
    };
    let wear = mean.tread_wear_m_per_m(c);
    let target = print_log_ratio(p);
    if wear.is_nan() || wear <= 0.0 || like.max_order == 0 || target <= 0.0 {
        return mean.answer(c, p);
    }
    let tread_life = tread_life_km(p, wear * MM_PER_1000KM_PER_M_PER_M);
    let visible = target.exp();
    let seed_m = 2.0 * p.seed_runout_um * 1e-6;
    let phi = c.wear_share_straight;
    let others: Vec<f64> = steps
        .iter()
        .map(|(_, pr)| {
            (1.0 - phi) * (pr.other_per_share.0 + c.wear_rate_driven_factor * pr.other_per_share.1)
        })
        .collect();
    let intervals = like.intervals;
    let dw = like.usable_m / intervals as f64;
    let ds = dw / wear;
    let grid_m = ds * intervals as f64;
    // Each order unsaturated, from the mean profile: where it first reaches the visible depth
    // (in metres) and its largest ln(D/2R⁰). The saturated order is never earlier or deeper,
    // so an order that cannot beat the answer so far is not driven, and the order visible
    // first unsaturated is driven first; the answer is that of driving every order in turn.
    let mean_other =
        (1.0 - phi) * (mean.other_per_share.0 + c.wear_rate_driven_factor * mean.other_per_share.1);
    let unsaturated: Vec<(Option<f64>, f64)> = (1..=like.max_order)
        .map(|n| {
            let log = |j: usize| (phi * mean.integral(n, j) - mean_other * dw * j as f64) / wear;
            let (mut before, mut peak) = (0.0_f64, 0.0_f64);
            for j in 1..=intervals {
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
        .collect();
    let leader = (1..=like.max_order)
        .filter_map(|n| unsaturated[n as usize - 1].0.map(|at| (at, n)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n);
    let mut first: Option<(f64, u32)> = None;
    let mut deepest = (f64::NEG_INFINITY, 1);
    let mut terms = Vec::with_capacity(steps.len());
    let (mut rate, mut knots) = (
        PiecewiseRate::of_terms(&[]),
        Vec::with_capacity(steps.len()),
    );
    // (Within a relative 10⁻⁹: where no knot is reached the two are one value, rounded twice.)
    let rest = (1..=like.max_order).filter(|&n| Some(n) != leader);
    let r0 = 0.5 * seed_m;
    let mut locks = OrderLocks::new(midpoint_steps);
    let mut locked = Vec::with_capacity(steps.len());
    for n in leader.into_iter().chain(rest) {
        let k = n as usize - 1;
        // An order no step profiled (the legs lay only the orders that can matter) has no
        // print: it only levels from the seed.
        if steps
            .iter()
            .all(|(_, pr)| pr.full_print_per_share[k] == 0.0)
        {
            continue;
        }
        // Every print, free or locked, keeps to the sliding bound: an order whose bound cannot
        // beat the answer so far is not driven, nor laid out for the lock (its peak does not
        // count once there is an answer).
        let bounded = modulation_max.is_finite();
        let bound = bounded.then(|| BoundPath::of(steps, &others, k, phi, modulation_max, seed_m));
        let bound_reach = bound.map_or(0.0, |b| b.reach_m(visible));
        let out_of_reach = match first {
            Some((m, _)) => bound_reach > m * (1.0 + 1e-9),
            None => bound.is_some_and(|b| b.log_peak(grid_m) + 1e-9 < deepest.0),
        };
        if screen && out_of_reach {
            continue;
        }
        // The unsaturated screen: the saturated, unlocked order is never earlier or deeper.
        let unsaturated_hopeless = match (first, unsaturated[k]) {
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
            && bound_reach <= grid_m * (1.0 + 1e-9)
            && locks.gather(steps, n, intervals, visible * r0);
        if !lockable && unsaturated_hopeless && screen {
            continue;
        }
        // What each step gives this order at every depth: its share, levelling and bound;
        // only the growth through the tread moves along the grid.
        terms.clear();
        terms.extend(
            steps
                .iter()
                .zip(&others)
                .map(|(&(a, pr), &other)| SpeedTerm {
                    share: a / total,
                    base_per_m: phi * pr.base_per_share[k] - other,
                    growth_per_m: 0.0,
                    bound_per_m: phi * pr.full_print_per_share[k] * modulation_max / seed_m,
                    floor_per_m: 0.0,
                }),
        );
        // Each step's locked print at the free amplitude (seeds per metre).
        if lockable {
            locked.clear();
            locked.extend(steps.iter().map(|&(_, pr)| {
                let ph = pr.lock.as_ref().map_or(0.0, |l| l.power_harmonic_rel);
                phi * pr.full_print_per_share[k] * ph / seed_m
            }));
        }
        // An order that cannot reach the visible depth even with every step that can lock it
        // printing the most a locked cycle can (or not before the answer so far) is walked
        // without the lock: its answer is the same, and its peak the unlocked one.
        let lockable = lockable && {
            let growth = |j: usize, terms: &mut [SpeedTerm]| {
                for (t, (&(_, pr), &other)) in terms.iter_mut().zip(steps.iter().zip(&others)) {
                    let rate =
                        (phi * (pr.integral(n, j) - pr.integral(n, j - 1)) - other * dw) / dw;
                    t.growth_per_m = rate - t.base_per_m;
                }
            };
            let reach = locks.upper_reach_m(&terms, &locked, growth, ds, visible);
            match (reach, first) {
                // Walked unlocked, the unsaturated screen holds again.
                (None, _) if screen && unsaturated_hopeless => continue,
                (None, _) => false,
                (Some(at), Some((m, _))) if screen && at > m * (1.0 + 1e-9) => continue,
                _ => true,
            }
        };
        let (mut u, mut peak, mut s) = (1.0_f64, 1.0_f64, 0.0);
        for j in 1..=intervals {
            for (t, (&(_, pr), &other)) in terms.iter_mut().zip(steps.iter().zip(&others)) {
                let rate = (phi * (pr.integral(n, j) - pr.integral(n, j - 1)) - other * dw) / dw;
                t.growth_per_m = rate - t.base_per_m;
            }
            let (mut end, mut cross) = rate.refill_evolve(&terms, &mut knots, u, ds, visible);
            // A step whose order locks within reach of this interval's path turns its print to
            // the locked one there: the rate is no longer piecewise linear in u.
            if lockable && locks.reached(n, j, u.max(end), r0) {
                let at = LockedInterval {
                    n,
                    j,
                    terms: &terms,
                    locked: &locked,
                    ds,
                    visible,
                    r0,
                };
                (end, cross) = locks.evolve(&at, u);
            }
            if let Some(t) = cross {
                let at = s + t;
                if first.is_none_or(|(m, o)| at < m || (at == m && n < o)) {
                    first = Some((at, n));
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
        let log_peak = peak.ln();
        if log_peak > deepest.0 || (log_peak == deepest.0 && n < deepest.1) {
            deepest = (log_peak, n);
        }
    }
    LifeAnswer::of_walk(
        first.map(|(at, n)| (at * 1e-3, n)),
        deepest,
        target,
        tread_life,
        1,
    )
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::classify::budget::Meter;
    use crate::classify::ClassifierOptions;
    use crate::evaluate::{calibrate_wear, solve_wheel};
    use crate::model::{Variant, Wheel};
    use crate::wear::physics::calibration::Calibration;
    use crate::wear::physics::law::PER_1000KM_PER_PER_M;
    use crate::wear::{WearInputs, WearSettings};

    /// One wheel's closed loop at the point `p`, the wear stage calibrated as `cal`, and whether
    /// its tread vibrates.
    pub(in crate::wear::estimator::life) fn growth_at(
        p: &Params,
        cal: &Calibration,
        wheel: Wheel,
    ) -> (WheelGrowth, bool) {
        let opts = ClassifierOptions::default();
        let w = solve_wheel(*p, Variant::SlidingShare, wheel, &opts);
        let g = WheelGrowth::new(
            &WearInputs {
                params: p,
                model: &w.model,
                verdict: &w.verdict,
                settings: &WearSettings::default(),
                calibration: cal,
            },
            &Meter::new(opts.budget),
        )
        .unwrap();
        (g, w.verdict.class.vibrates())
    }

    /// ln D_n from the seed over the tread's life by brute force: β of order n at x = n·f₀/f(w)
    /// with the transfer summed exactly, the locked print inside the tongue, by the midpoint
    /// rule on `steps` equal steps of the worn depth; the first order to reach the visible
    /// depth and its distance \[km\] (+inf: none), among the orders ν passes (⌊ν₀⌋ − 2 …
    /// ⌈ν_end⌉ + 2; the rest level out).
    fn brute_force(g: &WheelGrowth, c: &FittedConstants, steps: usize) -> (u32, f64) {
        let drift = TreadDrift::of(&g.params, &g.patch);
        let profile = g.life_profile(1, 1);
        let wear = profile.tread_wear_m_per_m(c);
        let phi = c.wear_share_straight;
        let other =
            profile.other_per_share.0 + c.wear_rate_driven_factor * profile.other_per_share.1;
        let target = g.print_log_ratio;
        let dw = drift.usable_m / steps as f64;
        let mut first = (0, f64::INFINITY);
        let lo = (g.nu().floor() - 2.0).max(1.0) as u32;
        let hi = (g.nu() / drift.at_end()).ceil() as u32 + 2;
        for (n, (zone, forcing)) in (lo..=hi).zip(g.feedback.zones_and_forcings(lo)) {
            let order = n as f64;
            let order_loop = g.order_loop(zone, forcing, phi, other);
            let (_, half_mps) = g.tongue_mps(order, forcing, g.seed_m);
            let delta = half_mps * order / g.speed_mps;
            let mut log = 0.0;
            for k in 0..steps {
                let w = (k as f64 + 0.5) * dw;
                let x = order * drift.ratio_at(w);
                let beta = if half_mps > 0.0 && (x - g.nu()).abs() <= delta {
                    order_loop.locked_per_m
                } else {
                    let transfer = g.response.transfer.at(x * g.speed_mps / g.r_b);
                    order_loop.linear_per_m(transfer)
                };
                let next = log + beta * dw / wear;
                if next >= target {
                    let at = (k as f64 + (target - log) / (next - log)) * dw;
                    if at / wear * 1e-3 < first.1 {
                        first = (n, at / wear * 1e-3);
                    }
                    break;
                }
                log = next;
            }
        }
        first
    }

    /// One operating point's profile is the answer over the tread's life with no speed spread:
    /// the same order, the distance within 1% (the crossing read between the grid's points
    /// instead of the nodes'), the same tread life, at stable wheels; at every wheel, the
    /// brute-force integral's order and distance; at points where a polygon is visible and
    /// where none is, for a stable and a vibrating wheel (φ_s = 0.28, as the life answer's
    /// own test). Its slope at the new tire is the new tire's growth of each order.
    #[test]
    fn one_step_s_profile_is_the_answer_over_the_tread_s_life() {
        let opts = ClassifierOptions::default();
        let base = Params {
            wear_share_straight: 0.28,
            speed_spread_kmh: 0.0,
            ..crate::wear::physics::fitted::pinned_params()
        };
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        let (mut visible, mut none, mut vibrating) = (0, 0, 0);
        for (speed_kmh, toe_deg) in [(120.0, 0.45), (110.0, 0.6), (80.0, 0.3), (140.0, 0.35)] {
            let p = Params {
                speed_kmh,
                toe_deg,
                ..base
            };
            for wheel in Wheel::BOTH {
                let (g, vibrates) = growth_at(&p, &cal, wheel);
                let here = format!("{speed_kmh} km/h {toe_deg}° {wheel}");
                let c = FittedConstants::of(&p);
                let want = g.life_answer(&c);
                let profile = g.life_profile(64, LIFE_PROFILE_INTERVALS);
                let got = profile.answer(&c, &p);
                if !vibrates {
                    assert_eq!(
                        got.answer.polygon_order_wear, want.answer.polygon_order_wear,
                        "{here}: {got:?} {want:?}"
                    );
                }
                let (a, b) = (
                    got.answer.distance_to_visible_km,
                    want.answer.distance_to_visible_km,
                );
                // The life answer integrates the locked print by the trapezoid rule over its
                // nodes, which with no spread steps over a tongue a few nodes wide: the
                // vibrating wheels are held to the brute force alone, within 2% (Ḡ is linear
                // between nodes 0.02 order apart, next to the cycle's lightly damped poles).
                let (brute_order, brute_km) = brute_force(&g, &c, 40_000);
                let within = if vibrates { 0.02 } else { 0.01 };
                assert!(
                    a == brute_km || (a - brute_km).abs() <= within * brute_km,
                    "{here}: {a} km against {brute_km} km by brute force (order {brute_order})"
                );
                if !vibrates {
                    assert!(
                        a == b || (a - b).abs() <= 0.01 * b,
                        "{here}: {a} km against {b} km"
                    );
                }
                if a.is_finite() {
                    assert_eq!(got.answer.polygon_order_wear, brute_order as f64, "{here}");
                }
                let life = want.answer.tread_life_km;
                assert!(
                    (got.answer.tread_life_km - life).abs() <= 1e-9 * life,
                    "{here}"
                );
                if b.is_finite() {
                    visible += 1;
                } else {
                    none += 1;
                    let (x, y) = (got.peak_share_of_visible, want.peak_share_of_visible);
                    assert!((x - y).abs() <= 0.02 * y, "{here}: peak {x} against {y}");
                }
                vibrating += usize::from(vibrates);
                // The slope at the new tire, orders away from ν (the nodes' linear Ḡ is
                // exact at whole orders only where it bends little).
                let fine = g.life_profile(64, 2048);
                let step = fine.usable_m / fine.intervals as f64;
                for n in 1..=64u32 {
                    if (n as f64 - g.nu()).abs() < 3.0 {
                        continue;
                    }
                    let slope = fine.integral(n, 1) / step;
                    let order =
                        g.order_with(n, 1.0, 0.0).growth_rate_per_1000km / PER_1000KM_PER_PER_M;
                    assert!(
                        (slope - order).abs() <= 0.02 * order.abs() + 1e-9,
                        "{here} order {n}: {slope} against {order}"
                    );
                }
            }
        }
        assert!(
            visible >= 1 && none >= 1 && vibrating >= 1,
            "{visible} {none} {vibrating}"
        );
    }

    /// The orders far from every resonance, read by their cubic between every eighth point, are
    /// within 10⁻³ in ln D (0.1% of the depth; at φ_s = 1, over the tread's whole wear) of the
    /// exact integrals at every point, at a stable and a vibrating wheel and a slow step; most
    /// of a stable wheel's orders are far.
    #[test]
    fn far_orders_by_their_cubic_are_the_exact_integrals() {
        let opts = ClassifierOptions::default();
        let base = crate::wear::physics::fitted::pinned_params();
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        for (speed_kmh, toe_deg) in [(110.0, 0.45), (140.0, 0.35), (30.0, 0.3)] {
            let p = Params {
                speed_kmh,
                toe_deg,
                ..base
            };
            for wheel in Wheel::BOTH {
                let (g, vibrates) = growth_at(&p, &cal, wheel);
                let fast = g.life_profile_with(1, 64, LIFE_PROFILE_INTERVALS, true);
                let exact = g.life_profile_with(1, 64, LIFE_PROFILE_INTERVALS, false);
                let wear = fast.tread_wear_m_per_m(&FittedConstants {
                    wear_share_straight: 1.0,
                    ..FittedConstants::of(&p)
                });
                let worst = fast
                    .integrals
                    .iter()
                    .zip(&exact.integrals)
                    .map(|(a, b)| (a - b).abs() / wear)
                    .fold(0.0, f64::max);
                let moved = fast
                    .integrals
                    .iter()
                    .zip(&exact.integrals)
                    .filter(|(a, b)| a != b)
                    .count();
                let here = format!("{speed_kmh} km/h {toe_deg}° {wheel}");
                assert!(worst <= 1e-3, "{here}: {worst}");
                // A vibrating wheel's transfer resonates at the cycle's harmonics too: fewer of
                // its orders are far.
                let most = if vibrates { 20 } else { 2 };
                assert!(
                    moved > fast.integrals.len() / most,
                    "{here}: {moved} read by the cubic"
                );
            }
        }
    }

    /// The weighted sum of profiles, scaled by the total weight, answers as one profile does
    /// when all its terms are the same; and a profile added to a zero one is itself.
    #[test]
    fn weighted_profiles_add_as_their_mean() {
        let mut one = LifeProfile::zero(3, 4, 0.006);
        for (k, x) in one.integrals.iter_mut().enumerate() {
            *x = k as f64 * 1e-6;
        }
        one.even_per_share = 2e-9;
        one.position_rate = (1e-9, 0.5e-9);
        one.other_per_share = (1e-7, 2e-8);
        let mut sum = LifeProfile::zero(3, 4, 0.006);
        sum.add(&one, 2.0);
        sum.add(&one, 3.0);
        sum.scale(1.0 / 5.0);
        for (a, b) in sum.integrals.iter().zip(&one.integrals) {
            assert!((a - b).abs() <= 1e-15 * b.abs().max(1e-6));
        }
        assert!((sum.even_per_share - one.even_per_share).abs() < 1e-22);
    }

    /// The bound is the largest first harmonic of |1 + a cos θ| over its mean: a below 1 gives
    /// a itself, the maximum lies past it, and a fast oscillation prints little on its order.
    #[test]
    fn sliding_modulation_max_is_the_largest_harmonic_of_a_sliding_power() {
        let points = 20_000;
        let harmonic = |a: f64| {
            let (mut mean, mut first) = (0.0, 0.0);
            for i in 0..points {
                let theta = std::f64::consts::TAU * (i as f64 + 0.5) / points as f64;
                let power = (1.0 + a * theta.cos()).abs();
                mean += power;
                first += power * theta.cos();
            }
            2.0 * first / mean
        };
        assert!((harmonic(0.6) - 0.6).abs() < 1e-9);
        let (at, max) = (1000..3000)
            .map(|i| i as f64 * 1e-3)
            .map(|a| (a, harmonic(a)))
            .fold((0.0, 0.0), |best, x| if x.1 > best.1 { x } else { best });
        assert!(
            (max - SLIDING_MODULATION_MAX).abs() < 1e-4,
            "{max} at a = {at}"
        );
        assert!(at > 1.0 && at < 1.5, "{at}");
        assert!(harmonic(3.0) < 0.7);
    }

    /// The pieces' exact solution is the ODE's, integrated by RK4 on fine steps: rising
    /// through knots to the visible depth, settling where a levelling meets the bound, and
    /// falling back through a knot; and a rate of one linear piece is the exponential.
    #[test]
    fn piecewise_rate_evolves_as_its_ode() {
        let term = |share, base_per_m, growth_per_m, bound_per_m| SpeedTerm {
            floor_per_m: 0.0,
            share,
            base_per_m,
            growth_per_m,
            bound_per_m,
        };
        let rk4 = |terms: &[SpeedTerm], mut u: f64, ds: f64, visible: f64| {
            let f = |u: f64| -> f64 {
                terms
                    .iter()
                    .map(|t| {
                        let cap = if t.growth_per_m > 0.0 {
                            t.bound_per_m
                        } else {
                            f64::INFINITY
                        };
                        t.share * (t.base_per_m * u + (t.growth_per_m * u).min(cap))
                    })
                    .sum()
            };
            let steps = 200_000;
            let h = ds / steps as f64;
            for i in 0..steps {
                let k1 = f(u);
                let k2 = f(u + 0.5 * h * k1);
                let k3 = f(u + 0.5 * h * k2);
                let k4 = f(u + h * k3);
                let next = u + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                if next >= visible {
                    return (visible, Some((i as f64 + (visible - u) / (next - u)) * h));
                }
                u = next;
            }
            (u, None)
        };
        // (terms, u from, distance, visible)
        let cases = [
            // Two steps saturating one after the other, reaching the visible depth.
            (
                vec![term(0.5, -0.1, 3.0, 2.0), term(0.5, -0.1, 1.0, 4.0)],
                1.0,
                5.0,
                20.0,
            ),
            // Levelling against the bound: u settles at cap/|b| = 10 (below the visible 50).
            (vec![term(1.0, -0.2, 1.5, 2.0)], 1.0, 60.0, 50.0),
            // Above its equilibrium, falling back through the knot.
            (vec![term(1.0, -0.5, 0.8, 2.0)], 20.0, 10.0, 100.0),
            // One linear piece: the exponential.
            (vec![term(1.0, 0.1, 0.3, f64::INFINITY)], 1.0, 3.0, 1e3),
            // A levelling step and a saturating one.
            (
                vec![term(0.3, -0.4, -0.2, 1.0), term(0.7, 0.0, 2.0, 3.0)],
                1.0,
                8.0,
                30.0,
            ),
        ];
        for (terms, u, ds, visible) in &cases {
            let (u, ds, visible) = (*u, *ds, *visible);
            let (want, want_at) = rk4(terms, u, ds, visible);
            let (got, got_at) = PiecewiseRate::of_terms(terms).evolve(u, ds, visible);
            assert!(
                (got - want).abs() <= 1e-6 * want.abs().max(1.0),
                "{terms:?}: {got} against {want}"
            );
            match (got_at, want_at) {
                (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-5 * b, "{a} against {b}"),
                (None, None) => {}
                other => panic!("{terms:?}: {other:?}"),
            }
        }
        let (settled, _) = PiecewiseRate::of_terms(&cases[1].0).evolve(1.0, 200.0, 50.0);
        assert!((settled - 10.0).abs() < 1e-6, "{settled}");
    }

    /// The lazy first piece is the full rate, bit for bit: random terms (some with their knot
    /// at 0, a floor at the cap, an unbounded one), started below, between and above their
    /// knots, over distances that stay on the first piece and that leave it, both ways.
    #[test]
    fn refill_evolve_is_refill_then_evolve_bit_for_bit() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(40);
        let (mut lazy, mut full) = (PiecewiseRate::of_terms(&[]), PiecewiseRate::of_terms(&[]));
        let (mut knots, mut first_piece, mut left_it) = (Vec::new(), 0, 0);
        for case in 0..20_000 {
            let terms: Vec<SpeedTerm> = (0..rng.random_range(1..12))
                .map(|_| {
                    let cap = match rng.random_range(0..10) {
                        0 => f64::INFINITY,
                        _ => rng.random_range(0.0..5.0),
                    };
                    SpeedTerm {
                        share: rng.random_range(0.0..1.0),
                        base_per_m: rng.random_range(-1.0..0.5),
                        growth_per_m: rng.random_range(-0.5..2.0),
                        bound_per_m: cap,
                        floor_per_m: match rng.random_range(0..4) {
                            0 => cap,
                            1 => rng.random_range(0.0..3.0),
                            _ => 0.0,
                        },
                    }
                })
                .collect();
            let u = rng.random_range(0.05..6.0);
            let (ds, visible) = (rng.random_range(0.01..5.0), rng.random_range(1.0..60.0));
            full.refill(&terms, &mut knots);
            let want = full.evolve(u, ds, visible);
            let got = lazy.refill_evolve(&terms, &mut knots, u, ds, visible);
            assert_eq!(
                got.0.to_bits(),
                want.0.to_bits(),
                "case {case}: {terms:?} from {u}"
            );
            assert_eq!(
                got.1.map(f64::to_bits),
                want.1.map(f64::to_bits),
                "case {case}"
            );
            if full.knots.len() > 1 && u < full.knots[1] {
                match full.evolve_within(u, ds, visible, 1) {
                    Some(_) => first_piece += 1,
                    None => left_it += 1,
                }
            }
        }
        // Both branches taken often.
        assert!(
            first_piece > 1_000 && left_it > 1_000,
            "{first_piece} {left_it}"
        );
    }

    /// Unbounded, the saturated answer is the profile's own (the exact exponential on each
    /// interval is the log read linearly between the grid's points); at the bound it is never
    /// earlier and never deeper, comes a third later or more where an order grows fast through
    /// the resonance (φ_s = 1, 60, 93 and 110 km/h at 0.45°) and stays none at the shipped
    /// constants; two equal steps answer as one.
    #[test]
    fn saturation_slows_only_deep_orders() {
        let opts = ClassifierOptions::default();
        let base = Params {
            speed_spread_kmh: 0.0,
            toe_deg: 0.45,
            ..crate::wear::physics::fitted::pinned_params()
        };
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        for (speed_kmh, share) in [(60.0, 1.0), (93.0, 1.0), (110.0, 1.0), (110.0, 0.12)] {
            let p = Params {
                speed_kmh,
                wear_share_straight: share,
                ..base
            };
            let deep = share == 1.0;
            for wheel in Wheel::BOTH {
                let (g, _) = growth_at(&p, &cal, wheel);
                let profile = g.life_profile(64, LIFE_PROFILE_INTERVALS);
                let c = FittedConstants::of(&p);
                let here = format!("{speed_kmh} km/h phi_s {share} {wheel}");
                let plain = profile.answer(&c, &p);
                let unbounded = profile.answer_saturated(&c, &p, f64::INFINITY).answer;
                assert_eq!(
                    plain.answer.polygon_order_wear, unbounded.polygon_order_wear,
                    "{here}"
                );
                let (a, b) = (
                    plain.answer.distance_to_visible_km,
                    unbounded.distance_to_visible_km,
                );
                assert!(a == b || (a - b).abs() <= 1e-9 * a, "{here}: {a} {b}");
                let bounded = profile.answer_saturated(&c, &p, SLIDING_MODULATION_MAX);
                let d = bounded.answer.distance_to_visible_km;
                assert!(d >= a, "{here}: {d} against {a}");
                assert!(
                    bounded.peak_share_of_visible <= plain.peak_share_of_visible + 1e-12,
                    "{here}"
                );
                if deep {
                    assert!(a.is_finite() && d > 1.3 * a, "{here}: {d} against {a}");
                } else {
                    assert!(
                        a.is_infinite() && d.is_infinite(),
                        "{here}: {d} against {a}"
                    );
                }
                let twice = answer_saturated_per_step(
                    &[(0.3, &profile), (0.7, &profile)],
                    &c,
                    &p,
                    SLIDING_MODULATION_MAX,
                )
                .answer;
                let (d, e) = (d, twice.distance_to_visible_km);
                assert!(
                    e == d || (e - d).abs() <= 1e-9 * d,
                    "{here}: {e} against {d}"
                );
            }
        }
    }
}
