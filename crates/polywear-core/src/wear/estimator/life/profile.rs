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

use super::{DepthLock, LifeAnswer, Nodes, TransferNodes, TreadDrift, WORN_DEGREE};
use crate::params::Params;
use crate::wear::estimator::{print_log_ratio, tread_life_km, Complex64, OrderLoop, WheelGrowth};
use crate::wear::physics::fitted::FittedConstants;
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
                tread_life_km: tread_life,
                ..LifeAnswer::UNKNOWN
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
        let (drift, intervals) = (&grid.drift, grid.intervals);
        let usable = drift.usable_m;
        let points = intervals + 1;
        let leg = ProfileLeg {
            g: self,
            grid,
            transfer,
            q,
            slope: drift.slope_coefficients(),
            end: drift.at_end(),
            nu: self.nu() / q,
            v: self.speed_mps * q,
            resonances: self.resonance_orders().map(|r| r / q).collect(),
            coarse,
        };
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
            let order_loop = self.order_loop(zone, forcing, 1.0, 0.0);
            base_per_share.push(order_loop.base_per_m);
            full_print_per_share.push(2.0 * self.even_per_share * zone.norm_sqr().sqrt());
            leg.lay_order(n, forcing, order_loop, &mut integrals);
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
            lock: DepthLock::of(self, q, &grid.ratios, from_order..=max_order, profiled),
        }
    }
}

/// What every order's profile on one leg shares: the wheel read at `q` times its speed, the
/// grid, the leg's transfer nodes, and the drift's slope, end, ν, speed and resonances there.
struct ProfileLeg<'a> {
    g: &'a WheelGrowth,
    grid: &'a DepthGrid,
    transfer: &'a TransferNodes,
    q: f64,
    slope: [f64; WORN_DEGREE],
    /// f₀/f of the worn-out tire.
    end: f64,
    nu: f64,
    /// The leg's speed \[m/s\].
    v: f64,
    /// Where each pole of the transfer resonates, in orders.
    resonances: Vec<f64>,
    /// Orders far from every resonance by their cubic between every [`COARSE`]-th point.
    coarse: bool,
}

/// One order's integral of the linear loop over the worn depth, from the transfer's moments.
struct OrderIntegral<'a> {
    order_loop: OrderLoop,
    /// The weights of the moments: ∫_x^n Ḡ (−dw/dx′) dx′ = Σ_m −e_m/n^{m+1} (M_m(n) − M_m(x)).
    weight: [Complex64; WORN_DEGREE],
    at_start: f64,
    transfer: &'a TransferNodes,
    q: f64,
}

impl OrderIntegral<'_> {
    fn weigh(&self, m: &[Complex64; WORN_DEGREE]) -> f64 {
        self.weight
            .iter()
            .zip(m)
            .fold(0.0, |acc, (c, m)| acc + (c * m).re)
    }

    /// ∫₀^w of the linear loop, from the moments `m` at x = n·f₀/f at w.
    fn linear_from(&self, w: f64, m: &[Complex64; WORN_DEGREE]) -> f64 {
        self.order_loop.base_per_m * w + self.at_start - self.weigh(m)
    }

    /// ∫₀^w of the linear loop, x = n·f₀/f at w.
    fn linear(&self, w: f64, x: f64) -> f64 {
        self.linear_from(w, &self.transfer.point(x * self.q).1)
    }
}

impl ProfileLeg<'_> {
    /// Lays order `n`'s cumulative integrals of β at φ_s = 1 at the grid's points onto
    /// `integrals`, its forcing `forcing` and loop `order_loop`.
    fn lay_order(
        &self,
        n: u32,
        forcing: Complex64,
        order_loop: OrderLoop,
        integrals: &mut Vec<f64>,
    ) {
        let order = n as f64;
        let (transfer, q) = (self.transfer, self.q);
        let mut weight = [Complex64::new(0.0, 0.0); WORN_DEGREE];
        let scaled = order * q;
        let mut power = 1.0 / scaled;
        for (c, &e) in weight.iter_mut().zip(&self.slope) {
            *c = order_loop.through_per_m * (-e * power);
            power /= scaled;
        }
        let mut integral = OrderIntegral {
            order_loop,
            weight,
            at_start: 0.0,
            transfer,
            q,
        };
        integral.at_start = integral.weigh(&transfer.point(scaled).1);
        let tongue = self.tongue_in_depth(order, forcing);
        let in_tongue = tongue.is_some_and(|((w_in, _), (w_out, _))| w_out > w_in);
        // An order whose x stays away from every resonance of the transfer (and from the
        // tongue) has a smooth integral: it is taken exactly at every COARSE-th point and
        // by its cubic through the values and slopes (dI/dw = β at x) between them.
        let (end, intervals) = (self.end, self.grid.intervals);
        let margin = FAR_MARGIN_ORDERS + FAR_MARGIN_SHARE * order;
        let far = self.coarse
            && !in_tongue
            && intervals % COARSE == 0
            && self
                .resonances
                .iter()
                .all(|&at| at < order * end - margin || at > order + margin);
        if far {
            self.lay_far(order, &integral, integrals);
            return;
        }
        // The grid's points fall in x: their segments are found walking down.
        let mut hint = transfer.x.len();
        let locked = order_loop.locked_per_m;
        for (j, &r) in self.grid.ratios.iter().enumerate() {
            let (w, x) = (self.depth(j), order * r);
            let mut total = integral.linear_from(w, &transfer.point_below(x * q, &mut hint).1);
            if let Some(((w_in, x_in), (w_out, x_out))) = tongue {
                if w > w_in && w_out > w_in {
                    let (w_to, x_to) = if w < w_out { (w, x) } else { (w_out, x_out) };
                    total += locked * (w_to - w_in)
                        - (integral.linear(w_to, x_to) - integral.linear(w_in, x_in));
                }
            }
            integrals.push(total);
        }
    }

    /// The worn depth of the grid's point `j` \[m\].
    fn depth(&self, j: usize) -> f64 {
        self.grid.drift.usable_m * j as f64 / self.grid.intervals as f64
    }

    /// The tongue in depth: where |x − ν| ≤ δ_n (x falls as w grows), as (depth, x) where x
    /// enters and where it leaves; none for a stable tread.
    fn tongue_in_depth(&self, order: f64, forcing: Complex64) -> Option<((f64, f64), (f64, f64))> {
        let (drift, end) = (&self.grid.drift, self.end);
        let usable = drift.usable_m;
        let (_, half_mps) = self.g.tongue_mps(order, forcing, self.g.seed_m);
        (half_mps > 0.0).then(|| {
            let delta = half_mps * order / self.v;
            let (x_top, x_bottom) = (self.nu + delta, self.nu - delta);
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
        })
    }

    /// An order far from every resonance: exactly at every [`COARSE`]-th point, by the cubic
    /// through the values and slopes between them.
    fn lay_far(&self, order: f64, integral: &OrderIntegral, integrals: &mut Vec<f64>) {
        let (transfer, q) = (self.transfer, self.q);
        let mut hint = transfer.x.len();
        let mut before: Option<(f64, f64)> = None;
        for (j, &r) in self.grid.ratios.iter().enumerate().step_by(COARSE) {
            let (w, x) = (self.depth(j), order * r);
            let (g, moments) = transfer.point_below(x * q, &mut hint);
            let value = integral.linear_from(w, &moments);
            let slope = integral.order_loop.linear_per_m(g);
            if let Some((value_before, slope_before)) = before {
                let h = self.depth(j) - self.depth(j - COARSE);
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
    }
}

#[cfg(test)]
pub(super) mod tests;
