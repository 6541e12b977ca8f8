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

use super::{LifeAnswer, Nodes, TransferNodes, TreadDrift, WORN_DEGREE};
use crate::params::Params;
use crate::wear::estimator::{print_log_ratio, tread_life_km, Complex64, WheelGrowth};
use crate::wear::fitted::{FittedConstants, WearAnswer};
use crate::wear::law::MM_PER_1000KM_PER_M_PER_M;

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
        }
    }

    /// Adds `weight` times `other` (a step's profile by its distance): every term is linear in
    /// the profiles, so the weighted mean of a cycle's steps is their sum over the total
    /// weight ([`LifeProfile::scale`]). Panics where the grids differ.
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
        let (distance_to_visible_km, order) = match first {
            _ if target <= 0.0 => (0.0, 1),
            Some((w, n)) => (w / wear * 1e-3, n),
            None => (f64::INFINITY, deepest.1),
        };
        LifeAnswer {
            answer: WearAnswer {
                polygon_order_wear: order as f64,
                distance_to_visible_km,
                tread_life_km: tread_life,
            },
            peak_share_of_visible: if first.is_some() || target <= 0.0 {
                1.0
            } else {
                (deepest.0 - target).exp()
            },
        }
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

impl WheelGrowth {
    /// The wheel's [`LifeProfile`] for orders 1..=`max_order` on `intervals` equal intervals of
    /// the usable depth. Each order's integral of the linear loop is closed-form from the
    /// moments of the transfer's nodes (Ḡ linear between them, as the answer over the tread's
    /// life takes it); where a vibrating wheel's cycle locks to the order (no spread: the
    /// tongue |x − ν| ≤ δ_n in orders), the locked print replaces the loop over the depths
    /// that put x there, exactly.
    pub fn life_profile(&self, max_order: u32, intervals: usize) -> LifeProfile {
        self.life_profile_with(max_order, intervals, true)
    }

    /// [`WheelGrowth::life_profile`], the orders far from every resonance by their cubic
    /// between every [`COARSE`]-th point where `coarse` (else every point exactly: what the
    /// cubic is tested against).
    fn life_profile_with(&self, max_order: u32, intervals: usize, coarse: bool) -> LifeProfile {
        let drift = TreadDrift::of(&self.params, &self.patch);
        let slope = drift.slope_coefficients();
        let end = drift.at_end();
        let usable = drift.usable_m;
        let points = intervals + 1;
        let depth = |j: usize| usable * j as f64 / intervals as f64;
        // f₀/f at each depth of the grid: the drift's polynomial inverted (it falls with the
        // depth), so that the depths and the integrals' weights are one function.
        let ratios: Vec<f64> = (0..points).map(|j| drift.ratio_at(depth(j))).collect();
        let transfer =
            TransferNodes::new(self, end.min(1.0), max_order as f64, 0.0, Nodes::Adaptive);
        let nu = self.nu();
        let v = self.speed_mps;
        let resonances: Vec<f64> = self.resonance_orders().collect();
        let mut integrals = Vec::with_capacity(max_order as usize * points);
        for (n, (zone, forcing)) in (1..=max_order).zip(self.feedback.zones_and_forcings(1)) {
            let order = n as f64;
            let order_loop = self.order_loop(zone, forcing, 1.0, 0.0);
            // The weights of the moments: ∫_x^n Ḡ (−dw/dx′) dx′ = Σ_m −e_m/n^{m+1} (M_m(n) −
            // M_m(x)).
            let mut weight = [Complex64::new(0.0, 0.0); WORN_DEGREE];
            let mut power = 1.0 / order;
            for (c, &e) in weight.iter_mut().zip(&slope) {
                *c = order_loop.through_per_m * (-e * power);
                power /= order;
            }
            let weigh = |m: &[Complex64; WORN_DEGREE]| {
                weight
                    .iter()
                    .zip(m)
                    .fold(0.0, |acc, (c, m)| acc + (c * m).re)
            };
            let at_start = weigh(&transfer.point(order).1);
            // ∫₀^w of the linear loop, from the moments at x = n·f₀/f at w.
            let linear_from = |w: f64, m: &[Complex64; WORN_DEGREE]| {
                order_loop.base_per_m * w + at_start - weigh(m)
            };
            let linear = |w: f64, x: f64| linear_from(w, &transfer.point(x).1);
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
                    let (g, moments) = transfer.point_below(x, &mut hint);
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
                let mut total = linear_from(w, &transfer.point_below(x, &mut hint).1);
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
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::budget::Meter;
    use crate::classify::ClassifierOptions;
    use crate::evaluate::{calibrate_wear, solve_wheel};
    use crate::model::{Variant, Wheel};
    use crate::wear::calibration::Calibration;
    use crate::wear::law::PER_1000KM_PER_PER_M;
    use crate::wear::{WearInputs, WearSettings};

    /// One wheel's closed loop at the point `p`, the wear stage calibrated as `cal`, and whether
    /// its tread vibrates.
    fn growth_at(p: &Params, cal: &Calibration, wheel: Wheel) -> (WheelGrowth, bool) {
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
            ..Params::default()
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
        let base = Params::default();
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        for (speed_kmh, toe_deg) in [(110.0, 0.45), (140.0, 0.35), (30.0, 0.3)] {
            let p = Params {
                speed_kmh,
                toe_deg,
                ..base
            };
            for wheel in Wheel::BOTH {
                let (g, vibrates) = growth_at(&p, &cal, wheel);
                let fast = g.life_profile_with(64, LIFE_PROFILE_INTERVALS, true);
                let exact = g.life_profile_with(64, LIFE_PROFILE_INTERVALS, false);
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
}
