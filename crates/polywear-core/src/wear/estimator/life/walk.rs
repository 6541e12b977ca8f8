//! The walk of each order over the tread's life (MODEL.md#the-estimator-over-the-treads-life):
//! ln D_n node by node along the drift, taken only where it can rise, to the first visible
//! polygon or the tire's end. [`WalkOfLife`] holds what every order's walk shares under one set
//! of constants; [`OrderWalk`] one order's loop, its locked print and its path of nodes.

use std::ops::Range;

use super::*;
use crate::wear::estimator::OrderLoop;

/// The previous node of an order's walk in [`WheelGrowth::life`]: its distance and ln D where
/// they were taken.
struct Prev {
    x: f64,
    /// Its index among the nodes (none: the start, whose ln D is 0, or the end).
    j: Option<usize>,
    s: Option<f64>,
    log: Option<f64>,
    /// β of the linear loop there, and the locked print's part.
    linear: f64,
    locked: f64,
    /// The locked print's part of ln D there.
    locked_log: f64,
}

/// What every order's walk shares: the wheel, its orders and nodes, and the set's constants.
struct WalkOfLife<'a> {
    g: &'a WheelGrowth,
    orders: &'a LifeOrders,
    at: &'a LifeNodes,
    share: f64,
    other_per_share: f64,
    /// The tread's whole even wear under the set \[m/m\].
    wear_m_per_m: f64,
    /// ln(d_visible/2R⁰).
    target: f64,
    /// The distance to the worn-out tire \[m\].
    life_m: f64,
}

/// The walk's span over the nodes: the nodes' index range (walked from the top), the node it
/// resumes at (none: the order itself), and whether it goes on to the tire's end.
struct Span {
    inside: Range<usize>,
    resume: Option<usize>,
    to_end: bool,
}

impl WheelGrowth {
    /// [`WheelGrowth::life_from`], and where `peaks` is given, each order's largest
    /// ln(D/2R⁰) over the life into it (from `orders.lo`; at least the target where it is
    /// visible): every order is then walked to its own polygon or the tire's end, not only to
    /// an earlier order's polygon. The answer is the same.
    pub(super) fn life_walk(
        &self,
        orders: &LifeOrders,
        at: &LifeNodes,
        c: &FittedConstants,
        mut peaks: Option<&mut Vec<f64>>,
    ) -> LifeAnswer {
        let share = c.wear_share_straight;
        let other_per_share =
            self.position_rate(c.wear_rate_driven_factor) * self.feedback.local_per_m;
        let wear_m_per_m = self.tread_wear_with(c);
        let tread_life = tread_life_km(&self.params, wear_m_per_m * MM_PER_1000KM_PER_M_PER_M);
        let life = WalkOfLife {
            g: self,
            orders,
            at,
            share,
            other_per_share,
            wear_m_per_m,
            target: self.print_log_ratio,
            life_m: orders.drift.usable_m / wear_m_per_m,
        };
        let (lo, hi) = (orders.lo, orders.hi);
        let mut first: Option<(f64, u32)> = None;
        let mut deepest = (f64::NEG_INFINITY, lo);
        for (n, fixed) in (lo..=hi).zip(&orders.fixed) {
            // Past the wheel's wall-clock limit no answer is given (the callers ask
            // out_of_time): the walk stops.
            if self.deadline.passed() {
                break;
            }
            let walk = OrderWalk::new(&life, n, fixed);
            // An order with no rising point has no walk (its peak stays at the seed).
            let peak = match walk.span() {
                Some(span) => walk.peak(span, &mut first, peaks.is_some()),
                None => 0.0,
            };
            if peak > deepest.0 {
                deepest = (peak, n);
            }
            if let Some(peaks) = peaks.as_deref_mut() {
                peaks.push(peak);
            }
        }
        LifeAnswer::of_walk(
            first.map(|(m, n)| (m * 1e-3, n)),
            deepest,
            life.target,
            tread_life,
            lo,
        )
    }
}

impl WalkOfLife<'_> {
    /// The tongue's uniform means, for the widest tongue of these orders (a vibrating wheel
    /// under a spread).
    fn tongue_mean(&self, order: f64, centre_mps: f64, half_mps: f64) -> Complex64 {
        let (g, orders) = (self.g, self.orders);
        let v = g.speed_mps;
        orders
            .tongue_means
            .get_or_init(|| {
                let widest = (orders.lo..=orders.hi)
                    .zip(&orders.fixed)
                    .map(|(n, &(_, _, (_, half_mps)))| half_mps * n as f64 / v)
                    .fold(0.0, f64::max);
                g.response
                    .transfer
                    .tongue_means(g.r_b, v, g.response.nu, widest)
            })
            .at(order, centre_mps, half_mps)
    }
}

/// One order's walk: its loop, its tongue, where its locked print counts, and ln D along the
/// nodes.
struct OrderWalk<'a> {
    life: &'a WalkOfLife<'a>,
    n: u32,
    order: f64,
    /// 1/n, and 1/ẇ \[m/m\]⁻¹: the distance at x is w(x/n)/ẇ.
    per_order: f64,
    per_wear: f64,
    order_loop: OrderLoop,
    /// The tongue's centre and half-width at x = n \[m/s\].
    centre_at_n: f64,
    half_at_n: f64,
    /// The transfer's uniform mean over the tongue, where the spread reaches into it.
    over_tongue: Option<Complex64>,
    /// The deviations from V beyond which the locked print is left out (none: nowhere counts).
    lock_within_sd: Option<f64>,
    /// c_m of the loop through the tread's moments.
    weight: [Complex64; WORN_DEGREE],
    g_start: Complex64,
    at_start: f64,
    x_end: f64,
    g_end: Complex64,
    moments_end: Moments,
}

impl<'a> OrderWalk<'a> {
    /// Order `n`'s walk with its zone transfer, forcing and tongue `fixed`.
    fn new(
        life: &'a WalkOfLife<'a>,
        n: u32,
        &(zone, forcing, (centre_mps, half_mps)): &(Complex64, Complex64, (f64, f64)),
    ) -> Self {
        let order = n as f64;
        let (g, spread_mps) = (life.g, life.at.spread_mps);
        let order_loop = g.order_loop(zone, forcing, life.share, life.other_per_share);
        let (centre_at_n, half_at_n) = (centre_mps * order, half_mps * order);
        let over_tongue = (half_mps > 0.0 && spread_mps > 0.0)
            .then(|| life.tongue_mean(order, centre_mps, half_mps));
        // Where the band's nearest edge is t deviations from V, its share of the spread is
        // below its width times the density there, 2δ/(σ√2π)·e^{−t²/2}: the locked print is
        // left out beyond the t at which that, over the whole life, moves ln D by less than
        // NEGLIGIBLE_LOCKED_LOG (everywhere, if it does at t = 0 at the widest band).
        let lock_within_sd = match over_tongue {
            Some(gt) => {
                let widest = 2.0 * half_at_n / (order * life.orders.end);
                let bound = widest / (spread_mps * (2.0 * std::f64::consts::PI).sqrt())
                    * (order_loop.locked_per_m - order_loop.linear_per_m(gt)).abs()
                    * life.life_m;
                (bound >= NEGLIGIBLE_LOCKED_LOG)
                    .then(|| (2.0 * (bound / NEGLIGIBLE_LOCKED_LOG).ln()).sqrt())
            }
            None => (half_mps > 0.0).then_some(f64::INFINITY),
        };
        // The loop through the tread, ∫ Re(through · Ḡ) ds from x back to n, is
        // Re(through · ∫_x^n Ḡ(x′) (−dw/dx′) dx′)/ẇ = Re(Σ_m c_m (M_m(n) − M_m(x))), with
        // dw/dx = Σ_m e_m x^m/n^{m+1}: c_m = −through · e_m/(n^{m+1} ẇ).
        let (per_order, per_wear) = (1.0 / order, 1.0 / life.wear_m_per_m);
        let mut weight = [Complex64::new(0.0, 0.0); WORN_DEGREE];
        let mut power = per_order;
        for (c, &e) in weight.iter_mut().zip(&life.orders.slope) {
            *c = order_loop.through_per_m * (-e * power * per_wear);
            power *= per_order;
        }
        let transfer = &life.at.transfer;
        let (g_start, moments_start) = transfer.point(order);
        let x_end = order * life.orders.end;
        let (g_end, moments_end) = transfer.point(x_end);
        let mut walk = OrderWalk {
            life,
            n,
            order,
            per_order,
            per_wear,
            order_loop,
            centre_at_n,
            half_at_n,
            over_tongue,
            lock_within_sd,
            weight,
            g_start,
            at_start: 0.0,
            x_end,
            g_end,
            moments_end,
        };
        walk.at_start = walk.weighted(&moments_start);
        walk
    }

    /// Re(Σ_m c_m M_m) of the moments `m`.
    fn weighted(&self, m: &Moments) -> f64 {
        self.weight
            .iter()
            .zip(m)
            .fold(0.0, |acc, (c, m)| acc + (c * m).re)
    }

    /// The locked print's part of β at x: over the share of the spread in the tongue, the
    /// locked print instead of the loop's own mean over the band.
    fn locked_per_m(&self, x: f64, g: Complex64, j: Option<usize>) -> f64 {
        let Some(t) = self.lock_within_sd else {
            return 0.0;
        };
        let (at, v) = (self.life.at, self.life.g.speed_mps);
        let spread_mps = at.spread_mps;
        let per_x = j.map_or_else(|| 1.0 / x, |j| at.per_x[j]);
        let (centre, half) = (self.centre_at_n * per_x, self.half_at_n * per_x);
        if (centre - v).abs() - half > t * spread_mps {
            return 0.0;
        }
        let eta = half / spread_mps;
        let locked_share = match j {
            // At a node, the spread's density at the tongue's centre is the same for every
            // order.
            Some(j) if spread_mps > 0.0 && eta <= NARROW_BAND_DEVIATIONS => {
                let nu = self.life.g.nu();
                at.tongue_nodes.get_or_init(|| {
                    at.transfer
                        .x
                        .iter()
                        .map(|&x| NarrowBand::at((v * nu / x - v) / spread_mps))
                        .collect()
                })[j]
                    .share(eta)
            }
            _ => band_share(centre, half, v, spread_mps),
        };
        if locked_share > NEGLIGIBLE_LOCKED_SHARE {
            let in_band = self.order_loop.linear_per_m(self.over_tongue.unwrap_or(g));
            locked_share * (self.order_loop.locked_per_m - in_band)
        } else {
            0.0
        }
    }

    /// The distance at which order n's path reaches x \[m\] (the tire's life at its end).
    fn distance_of(&self, x: f64) -> f64 {
        if x == self.x_end {
            self.life.life_m
        } else {
            self.life.orders.drift.worn_at(x * self.per_order) * self.per_wear
        }
    }

    /// ln D at a node where the distance is `s`, the locked print's part `locked_log`.
    fn log_at(&self, s: f64, j: Option<usize>, locked_log: f64) -> f64 {
        let moments = j.map_or(self.moments_end, |j| self.life.at.transfer.moments[j]);
        self.order_loop.base_per_m * s + (self.at_start - self.weighted(&moments)) + locked_log
    }

    /// The nodes strictly between n·f₀/f_end and n, from n down, then the end. With no locked
    /// print on this order, ln D can rise only on a segment with an end where the linear
    /// loop's rate is not negative (a rising one): the walk starts at the node above the
    /// highest rising node and stops at the node below the lowest; outside them ln D falls,
    /// and neither peaks nor reaches the visible depth. None: no rising point, no walk. (Where
    /// the print counts, its part of ln D is summed node by node: every node is walked.)
    fn span(&self) -> Option<Span> {
        let transfer = &self.life.at.transfer;
        let mut inside = transfer.x.partition_point(|&x| x <= self.x_end)
            ..transfer.x.partition_point(|&x| x < self.order);
        let mut resume = None;
        let mut to_end = true;
        if self.lock_within_sd.is_some() {
            return Some(Span {
                inside,
                resume,
                to_end,
            });
        }
        let rises = |g: Complex64| self.order_loop.linear_per_m(g) >= 0.0;
        let (start_rises, end_rises) = (rises(self.g_start), rises(self.g_end));
        let highest = inside.clone().rev().find(|&j| rises(transfer.g[j]));
        let lowest = highest.and_then(|top| (inside.start..=top).find(|&j| rises(transfer.g[j])));
        if !start_rises && !end_rises && highest.is_none() {
            return None;
        }
        if !start_rises {
            resume = match highest {
                Some(top) => (top + 1 < inside.end).then_some(top + 1),
                // Only the end rises: the walk's one segment is from the lowest node.
                None => (!inside.is_empty()).then_some(inside.start),
            };
        }
        if let Some(j) = resume {
            inside.end = j;
        }
        if !end_rises {
            match lowest {
                Some(bottom) if bottom > inside.start => {
                    inside.start = bottom - 1;
                    to_end = false;
                }
                Some(_) => {}
                // Only the start rises: the walk's one segment is to the highest node.
                None => {
                    if let Some(top) = inside.clone().next_back() {
                        inside.start = top;
                        to_end = false;
                    }
                }
            }
        }
        Some(Span {
            inside,
            resume,
            to_end,
        })
    }

    /// Where the walk starts: at the node it resumes at, or at the order itself (ln D = 0).
    fn start(&self, resume: Option<usize>) -> Prev {
        let transfer = &self.life.at.transfer;
        match resume {
            Some(j) => Prev {
                x: transfer.x[j],
                j: Some(j),
                s: None,
                log: None,
                linear: self.order_loop.linear_per_m(transfer.g[j]),
                locked: 0.0,
                locked_log: 0.0,
            },
            None => Prev {
                x: self.order,
                j: None,
                s: Some(0.0),
                log: Some(0.0),
                linear: self.order_loop.linear_per_m(self.g_start),
                locked: self.locked_per_m(self.order, self.g_start, None),
                locked_log: 0.0,
            },
        }
    }

    /// Walks the span's nodes, taking ln D only where it can rise: on a segment where the
    /// linear loop's rate (linear in x between the nodes, Ḡ being so) and the locked print's
    /// (by the trapezoid rule) are both negative at the ends, ln D falls, so it neither peaks
    /// nor reaches the visible depth there. The distance is read where it is needed (lazily at
    /// the previous node). Sets `first` where this order is visible before it; past an earlier
    /// order's polygon it stops unless `every_peak` (the order can only come later). Returns
    /// the largest ln(D/2R⁰) reached.
    fn peak(&self, span: Span, first: &mut Option<(f64, u32)>, every_peak: bool) -> f64 {
        let transfer = &self.life.at.transfer;
        let target = self.life.target;
        let path = span
            .inside
            .rev()
            .map(|j| (transfer.x[j], transfer.g[j], Some(j)))
            .chain(span.to_end.then_some((self.x_end, self.g_end, None)));
        let mut prev = self.start(span.resume);
        let mut peak = 0.0_f64;
        for (x, g, j) in path {
            let linear = self.order_loop.linear_per_m(g);
            let locked = self.locked_per_m(x, g, j);
            let may_rise = linear.max(prev.linear) + locked.max(prev.locked) >= 0.0;
            let locks = locked != 0.0 || prev.locked != 0.0;
            let mut s = None;
            if may_rise || locks || first.is_some() {
                let s_before = *prev.s.get_or_insert_with(|| self.distance_of(prev.x));
                // Past an earlier order's polygon this one can only come later.
                if !every_peak && first.is_some_and(|(m, _)| s_before > m) {
                    break;
                }
                s = Some(self.distance_of(x));
            }
            let mut locked_log = prev.locked_log;
            if let (true, Some(s), Some(s_before)) = (locks, s, prev.s) {
                locked_log += 0.5 * (prev.locked + locked) * (s - s_before);
            }
            let mut log = None;
            if let (true, Some(s), Some(s_before)) = (may_rise, s, prev.s) {
                let next = self.log_at(s, j, locked_log);
                let before = *prev
                    .log
                    .get_or_insert_with(|| self.log_at(s_before, prev.j, prev.locked_log));
                if next >= target && target > 0.0 {
                    let at_m = s_before + (s - s_before) * (target - before) / (next - before);
                    if first.is_none_or(|(m, _)| at_m < m) {
                        *first = Some((at_m, self.n));
                    }
                    peak = peak.max(next);
                    break;
                }
                peak = peak.max(next);
                log = Some(next);
            }
            prev = Prev {
                x,
                j,
                s,
                log,
                linear,
                locked,
                locked_log,
            };
        }
        peak
    }
}
