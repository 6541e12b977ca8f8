//! The per-sample estimator over the tread's life (MODEL.md#the-estimator-over-the-treads-life).
//!
//! The new-tire estimator grows every order at the rate of the new tread for ever. The long-term
//! loop's tread wears: its height falls at the position's whole even wear, the block stiffens in
//! series with the carcass and loses mass (MODEL.md#the-ageing-tread), and the tread frequency
//! f rises by 40–60% before the tire is worn out. ν = f/f_rot sweeps past several orders, and each
//! grows only while ν is just above it. This reading follows that drift:
//!
//! ```text
//! ln D_n(s) = ln 2R⁰ + ∫₀^s β_n(x_n(s′)) ds′,      x_n(s) = n · f₀ / f(h₀ − ẇ s),
//! ```
//!
//! β_n(x) being the new tire's closed loop with the tread's transfer (and a vibrating wheel's
//! tongue) read at order x, the zone and the forcing at n: a tread whose stiffness and mass
//! scale its poles by f/f₀ answers at n·f_rot as the new one does at x·f_rot. The polygon is
//! visible where ln D_n first reaches ln d_visible, if that is before the tire is worn out.

use super::{band_share, tread_life_km, Complex64, WheelGrowth};
use crate::model::tire::worn_tread_block;
use crate::model::ContactPatch;
use crate::params::Params;
use crate::wear::fitted::{FittedConstants, WearAnswer};
use crate::wear::law::MM_PER_1000KM_PER_M_PER_M;

/// Points of the table of f₀/f over the usable depth.
const DRIFT_POINTS: usize = 33;

/// Points of its inverse, the worn depth at uniform f₀/f: within 10⁻⁵ of the usable depth of
/// the table's own inverse at carcass shares up to 0.7 (65 points were not).
const INVERSE_POINTS: usize = 129;

/// The finest spacing of the nodes in x, in orders: where the spread is narrow the resonance
/// is a few hundredths of an order wide; and the uniform grid the adaptive one is tested
/// against.
const FINE_STEP_ORDERS: f64 = 0.02;

/// The coarsest spacing near a resonance, in orders (a quarter of the spread's width, up to
/// this): a polygon seen late in the tire's life crosses the visible depth slowly, so its
/// distance magnifies the integral's error. At 0.1 the highway followers' median distance of
/// the fit over the tread's life is within 0.5% of a uniform grid of 0.02 order (0.15: 0.9%;
/// 0.25: 2.7%, enough to move a grid point across the field's 25,000 km).
const MAX_NEAR_STEP_ORDERS: f64 = 0.1;

/// Away from the transfer's resonances the nodes are spaced by this share of the distance to
/// the nearest one (Ḡ bends on that scale there: linear interpolation is within about
/// share²/8 of it) ...
const FAR_STEP_SHARE: f64 = 0.1;

/// ... up to this many orders.
const MAX_FAR_STEP_ORDERS: f64 = 0.5;

/// The change of ln D below which the locked print of an order is left out over its whole
/// life (its largest share of the spread times its growth over the life bounds it).
const NEGLIGIBLE_LOCKED_LOG: f64 = 1e-4;

/// How the nodes of Ḡ(x) are laid.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Nodes {
    /// A quarter of the spread's width in orders (within [`FINE_STEP_ORDERS`],
    /// [`MAX_NEAR_STEP_ORDERS`]) near the transfer's resonances, coarser away from them.
    Adaptive,
    /// [`FINE_STEP_ORDERS`] everywhere (what the adaptive nodes are tested against).
    #[cfg_attr(not(test), allow(dead_code))]
    UniformFine,
}

/// Ḡ(x), the tread's transfer averaged over the speed spread at order x, at nodes in x: a
/// function of x alone, so every order of a wheel reads the same nodes as ν drifts past it.
#[derive(Debug, Clone, PartialEq)]
struct TransferNodes {
    x: Vec<f64>,
    g: Vec<Complex64>,
}

impl TransferNodes {
    /// Nodes from `lo` to `hi` (both included) laid as `nodes` asks, for a spread of
    /// `spread_mps` \[m/s\].
    fn new(g: &WheelGrowth, lo: f64, hi: f64, spread_mps: f64, nodes: Nodes) -> Self {
        let transfer = &g.response.transfer;
        // Where each pole resonates, in orders: ω = x V / r_B at the pole's frequency.
        let resonances: Vec<f64> = transfer
            .terms
            .iter()
            .map(|t| t.pole.im.abs() * g.r_b / g.speed_mps)
            .collect();
        let spacing = |x: f64| match nodes {
            Nodes::UniformFine => FINE_STEP_ORDERS,
            Nodes::Adaptive => {
                // A quarter of the spread's width in orders at x near a resonance.
                let near = (0.25 * x * spread_mps / g.speed_mps)
                    .clamp(FINE_STEP_ORDERS, MAX_NEAR_STEP_ORDERS);
                let distance = resonances
                    .iter()
                    .map(|r| (x - r).abs())
                    .fold(f64::INFINITY, f64::min);
                (FAR_STEP_SHARE * distance).clamp(near, MAX_FAR_STEP_ORDERS)
            }
        };
        let mut x = vec![lo];
        while let Some(&last) = x.last() {
            if last >= hi {
                break;
            }
            x.push((last + spacing(last)).min(hi));
        }
        let g = x
            .iter()
            .map(|&x| transfer.mean_over_speed(x, g.r_b, g.speed_mps, spread_mps))
            .collect();
        TransferNodes { x, g }
    }

    /// Ḡ at `x`, linear between the nodes (held past the ends).
    fn at(&self, x: f64) -> Complex64 {
        let k = self
            .x
            .partition_point(|&n| n <= x)
            .clamp(1, self.x.len() - 1);
        let (a, b) = (self.x[k - 1], self.x[k]);
        let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
        self.g[k - 1] * (1.0 - t) + self.g[k] * t
    }
}

/// f₀/f(h₀ − w) over the worn depth w ∈ \[0, usable\]: the new tread's undamped frequency
/// √(K_s/m) over the worn one's (MODEL.md#the-ageing-tread; `worn_tread_block`).
#[derive(Debug, Clone, PartialEq)]
struct TreadDrift {
    usable_m: f64,
    ratio: Vec<f64>,
    /// The worn depth \[m\] at ratios uniform from 1 down to the end's ([`INVERSE_POINTS`]):
    /// the integral reads it at every node of every order.
    worn_m: Vec<f64>,
    /// (INVERSE_POINTS − 1)/(1 − the end's ratio): the inverse table's points per unit ratio.
    inverse_per_ratio: f64,
}

impl TreadDrift {
    fn of(p: &Params, patch: &ContactPatch) -> Self {
        let usable_m = p.usable_wear_m().clamp(0.0, p.tread_height);
        let frequency = |h: f64| {
            let b = worn_tread_block(p, patch, h);
            (b.stiffness_n_per_m / b.mass_kg).sqrt()
        };
        let new = frequency(p.tread_height);
        let ratio = (0..DRIFT_POINTS)
            .map(|k| {
                let w = usable_m * k as f64 / (DRIFT_POINTS - 1) as f64;
                if k == 0 {
                    1.0
                } else {
                    new / frequency(p.tread_height - w)
                }
            })
            .collect::<Vec<f64>>();
        let end = ratio[DRIFT_POINTS - 1];
        let span = 1.0 - end;
        // The piecewise-linear drift read backwards at uniform ratios (it falls monotonically).
        let mut segment = 0;
        let worn_m = (0..INVERSE_POINTS)
            .map(|k| {
                let r = 1.0 - span * k as f64 / (INVERSE_POINTS - 1) as f64;
                while segment + 2 < DRIFT_POINTS && ratio[segment + 1] > r {
                    segment += 1;
                }
                let (a, b) = (ratio[segment], ratio[segment + 1]);
                let t = if a > b {
                    ((a - r) / (a - b)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                usable_m * (segment as f64 + t) / (DRIFT_POINTS - 1) as f64
            })
            .collect();
        TreadDrift {
            usable_m,
            ratio,
            worn_m,
            inverse_per_ratio: if span > 0.0 {
                (INVERSE_POINTS - 1) as f64 / span
            } else {
                0.0
            },
        }
    }

    /// f₀/f at the worn depth `worn_m` (linear between the table's points, held past its ends).
    #[cfg(test)]
    fn at(&self, worn_m: f64) -> f64 {
        if self.usable_m <= 0.0 || worn_m <= 0.0 {
            return 1.0;
        }
        let u = (worn_m / self.usable_m).min(1.0) * (DRIFT_POINTS - 1) as f64;
        let k = (u.floor() as usize).min(DRIFT_POINTS - 2);
        let t = u - k as f64;
        self.ratio[k] * (1.0 - t) + self.ratio[k + 1] * t
    }

    /// The worn depth at which f₀/f is `ratio` \[m\]: [`TreadDrift::at`]'s inverse (the
    /// ratio falls as the tread wears), linear between its points at uniform ratios; 0 above 1
    /// and the usable depth below the end's.
    fn worn_at(&self, ratio: f64) -> f64 {
        let u = ((1.0 - ratio) * self.inverse_per_ratio).clamp(0.0, (INVERSE_POINTS - 1) as f64);
        let k = (u as usize).min(INVERSE_POINTS - 2);
        let t = u - k as f64;
        self.worn_m[k] * (1.0 - t) + self.worn_m[k + 1] * t
    }

    /// f₀/f of the worn-out tire.
    fn at_end(&self) -> f64 {
        self.ratio[DRIFT_POINTS - 1]
    }
}

/// The wear answer over the tread's life, with how near the deepest order came.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LifeAnswer {
    /// The order that becomes visible first, or (none visible) the one that got deepest; its
    /// distance to a visible polygon (+inf: none before the tire is worn out); the tread's life.
    pub answer: WearAnswer,
    /// The deepest order's largest depth over the life, as a share of d_visible (1 where a
    /// polygon is visible).
    pub peak_share_of_visible: f64,
}

impl WheelGrowth {
    /// The wheel's wear answer under `c` over the tread's life
    /// (MODEL.md#the-estimator-over-the-treads-life): every order that ν passes, integrated
    /// from the seed over the drifting tread frequency, until it is visible or the tire is worn
    /// out.
    pub fn life_answer(&self, c: &FittedConstants) -> LifeAnswer {
        self.life(c, Nodes::Adaptive)
    }

    /// [`WheelGrowth::life_answer`] with Ḡ(x) at the `nodes` given. Order n's x = n·f₀/f runs
    /// from n down to n·f₀/f_end; the trapezoid rule over the nodes it passes, in the distance
    /// s(x) = w(x/n)/ẇ, w the worn depth at which f₀/f = x/n.
    fn life(&self, c: &FittedConstants, nodes: Nodes) -> LifeAnswer {
        let share = c.wear_share_straight;
        let other_per_share =
            self.position_rate(c.wear_rate_driven_factor) * self.feedback.local_per_m;
        let wear_m_per_m = self.tread_wear_with(c);
        let tread_life = tread_life_km(&self.params, wear_m_per_m * MM_PER_1000KM_PER_M_PER_M);
        let target = self.print_log_ratio;
        let spread_mps = c.speed_spread_kmh / 3.6;
        let drift = TreadDrift::of(&self.params, &self.patch);
        let life_m = drift.usable_m / wear_m_per_m;
        let nu = self.nu();
        let end = drift.at_end();
        let lo = (nu.floor() - 2.0).max(1.0) as u32;
        let hi = ((nu / end).ceil() + 2.0).max(lo as f64) as u32;
        let transfer = TransferNodes::new(self, lo as f64 * end, hi as f64, spread_mps, nodes);
        let v = self.speed_mps;
        let mut first: Option<(f64, u32)> = None;
        let mut deepest = (f64::NEG_INFINITY, lo);
        for n in lo..=hi {
            let order = n as f64;
            let (zone, forcing) = (
                self.feedback.zone.transfer(order, self.r_b),
                self.feedback.forcing_per_radius(order),
            );
            let order_loop = self.order_loop(zone, forcing, share, other_per_share);
            // The tongue at x: a worn tread's ν is ν₀·f/f₀, so order n locks as the new tire's
            // order x does, in a band of speeds around V ν/x, ±V δ_L/x (δ_L of order n). The
            // uniform mean over it is the same at every x: the band of ω = x V/r_B it spans
            // does not move.
            let (centre_mps, half_mps) = self.tongue_mps(order, forcing, self.seed_m);
            let (centre_at_n, half_at_n) = (centre_mps * order, half_mps * order);
            let over_tongue = (half_mps > 0.0 && spread_mps > 0.0).then(|| {
                self.response.transfer.mean_over_band(
                    order,
                    self.r_b,
                    centre_mps - half_mps,
                    centre_mps + half_mps,
                )
            });
            // Where the band's nearest edge is t deviations from V, its share of the spread is
            // below its width times the density there, 2δ/(σ√2π)·e^{−t²/2}: the locked print is
            // left out beyond the t at which that, over the whole life, moves ln D by less than
            // NEGLIGIBLE_LOCKED_LOG (everywhere, if it does at t = 0 at the widest band).
            let lock_within_sd = match over_tongue {
                Some(g) => {
                    let widest = 2.0 * half_at_n / (order * end);
                    let bound = widest / (spread_mps * (2.0 * std::f64::consts::PI).sqrt())
                        * (order_loop.locked_per_m - order_loop.linear_per_m(g)).abs()
                        * life_m;
                    (bound >= NEGLIGIBLE_LOCKED_LOG)
                        .then(|| (2.0 * (bound / NEGLIGIBLE_LOCKED_LOG).ln()).sqrt())
                }
                None => (half_mps > 0.0).then_some(f64::INFINITY),
            };
            let beta_per_m = |x: f64, g: Complex64| {
                let (centre, half) = (centre_at_n / x, half_at_n / x);
                let locked_share = match lock_within_sd {
                    Some(t) if (centre - v).abs() - half <= t * spread_mps => {
                        band_share(centre, half, v, spread_mps)
                    }
                    _ => 0.0,
                };
                order_loop.growth_per_m(g, locked_share, over_tongue)
            };
            let (per_order, per_wear) = (1.0 / order, 1.0 / wear_m_per_m);
            let distance_m = |x: f64| drift.worn_at(x * per_order) * per_wear;
            let x_end = order * end;
            // The nodes strictly between n·f₀/f_end and n, from n down, then the end.
            let inside = transfer.x.partition_point(|&x| x <= x_end)
                ..transfer.x.partition_point(|&x| x < order);
            let path = inside
                .rev()
                .map(|j| (transfer.x[j], transfer.g[j]))
                .chain(std::iter::once((x_end, transfer.at(x_end))));
            let (mut log_growth, mut before, mut s_before) =
                (0.0, beta_per_m(order, transfer.at(order)), 0.0);
            let mut peak = 0.0_f64;
            for (x, g) in path {
                // Past an earlier order's polygon this one can only come later.
                if first.is_some_and(|(m, _)| s_before > m) {
                    break;
                }
                let s = if x == x_end { life_m } else { distance_m(x) };
                let beta = beta_per_m(x, g);
                let next = log_growth + 0.5 * (before + beta) * (s - s_before);
                if next >= target && target > 0.0 {
                    let at_m =
                        s_before + (s - s_before) * (target - log_growth) / (next - log_growth);
                    if first.is_none_or(|(m, _)| at_m < m) {
                        first = Some((at_m, n));
                    }
                    peak = peak.max(next);
                    break;
                }
                peak = peak.max(next);
                (log_growth, before, s_before) = (next, beta, s);
            }
            if peak > deepest.0 {
                deepest = (peak, n);
            }
        }
        let (distance_to_visible_km, order) = match first {
            _ if target <= 0.0 => (0.0, lo),
            Some((m, n)) => (m * 1e-3, n),
            None => (f64::INFINITY, deepest.1),
        };
        LifeAnswer {
            answer: WearAnswer {
                polygon_order_wear: order as f64,
                distance_to_visible_km,
                tread_life_km: tread_life,
            },
            peak_share_of_visible: if first.is_some() {
                1.0
            } else {
                (deepest.0 - target).exp()
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tire::contact_patch;

    /// The table's end is the ageing law's f/f₀ ≈ √((h₀/h)/(c + (1 − c) h/h₀)) (the bending
    /// term under 0.6%), for the carcass shares of its bound and the 1/h law (c = 0); a new
    /// tread does not drift.
    #[test]
    fn the_drift_follows_the_ageing_tread() {
        for c in [0.0, 0.3, 0.5, 0.7] {
            let p = Params {
                carcass_share: c,
                ..Params::default()
            };
            let drift = TreadDrift::of(&p, &contact_patch(&p).unwrap());
            let h = (p.tread_height - p.usable_wear_m()) / p.tread_height;
            let law = ((1.0 / h) / (c + (1.0 - c) * h)).sqrt();
            let end = 1.0 / drift.at_end();
            assert!(
                (end / law - 1.0).abs() < 0.01,
                "c = {c}: {end} against {law}"
            );
            assert_eq!(drift.at(0.0), 1.0);
            // Monotone: the tread only stiffens and lightens as it wears.
            assert!(drift.ratio.windows(2).all(|w| w[1] < w[0]), "c = {c}");
            assert_eq!(drift.at(2.0 * p.usable_wear_m()), drift.at_end());
            // The worn depth at a ratio is its inverse, held at the ends.
            for k in 0..=40 {
                let w = p.usable_wear_m() * k as f64 / 40.0;
                let back = drift.worn_at(drift.at(w));
                assert!(
                    (back - w).abs() < 1e-5 * p.usable_wear_m(),
                    "c = {c}: {w} {back}"
                );
            }
            assert_eq!(drift.worn_at(1.5), 0.0);
            assert_eq!(drift.worn_at(0.5 * drift.at_end()), p.usable_wear_m());
        }
    }
}

#[cfg(test)]
mod table_tests {
    use super::*;
    use crate::classify::budget::Meter;
    use crate::classify::ClassifierOptions;
    use crate::evaluate::{calibrate_wear, solve_wheel};
    use crate::model::{Variant, Wheel};
    use crate::wear::{WearInputs, WearSettings};

    /// The adaptive nodes of Ḡ(x) (and the locked print left out where it cannot count) give the
    /// integral over a uniform grid of 0.02 order: at highway points with stable and vibrating
    /// wheels, both positions, spreads of 0.5–10 km/h, the same polygon within 1.5% in
    /// distance, or the same peak within 2% where none is visible (a case on the edge,
    /// visible by one and not by the other, only where the other's peak is at least 0.9 of the
    /// visible depth). Measured: 0.6% and 0.8% at most.
    #[test]
    fn the_adaptive_nodes_give_the_fine_integral() {
        let opts = ClassifierOptions::default();
        let base = Params::default();
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        let settings = WearSettings::default();
        let (mut visible, mut vibrating) = (0, 0);
        for (speed_kmh, toe_deg) in [
            (80.0, 0.3),
            (100.0, 0.45),
            (110.0, 0.45),
            (125.0, 0.3),
            (140.0, 0.35),
            (115.0, 0.6),
        ] {
            for wheel in Wheel::BOTH {
                let p = Params {
                    speed_kmh,
                    toe_deg,
                    ..base
                };
                let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
                vibrating += usize::from(w.verdict.class.vibrates());
                let g = WheelGrowth::new(
                    &WearInputs {
                        params: &p,
                        model: &w.model,
                        verdict: &w.verdict,
                        settings: &settings,
                        calibration: &cal,
                    },
                    &Meter::new(opts.budget),
                )
                .unwrap();
                for (phi, spread) in [
                    (0.12, 5.0),
                    (0.25, 5.0),
                    (0.28, 10.0),
                    (0.25, 2.0),
                    (0.25, 0.5),
                ] {
                    let c = FittedConstants {
                        wear_share_straight: phi,
                        speed_spread_kmh: spread,
                        wear_rate_driven_factor: 1.75,
                    };
                    let (t, d) = (g.life(&c, Nodes::Adaptive), g.life(&c, Nodes::UniformFine));
                    let at = format!("{speed_kmh} km/h {toe_deg} deg {wheel} {c:?}: {t:?} {d:?}");
                    let (st, sd) = (
                        t.answer.distance_to_visible_km,
                        d.answer.distance_to_visible_km,
                    );
                    match (st.is_finite(), sd.is_finite()) {
                        (true, true) => {
                            visible += 1;
                            assert!((st / sd - 1.0).abs() < 0.015, "{at}");
                            assert_eq!(t.answer.polygon_order_wear, d.answer.polygon_order_wear);
                        }
                        (false, false) => assert!(
                            (t.peak_share_of_visible / d.peak_share_of_visible - 1.0).abs() < 0.02,
                            "{at}"
                        ),
                        _ => assert!(
                            t.peak_share_of_visible.min(d.peak_share_of_visible) >= 0.9,
                            "{at}"
                        ),
                    }
                }
            }
        }
        assert!(visible >= 5, "only {visible} visible cases");
        assert!(vibrating >= 2, "only {vibrating} vibrating wheels");
    }
}
