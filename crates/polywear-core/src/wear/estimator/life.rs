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

use super::{tread_life_km, Complex64, WheelGrowth, PER_1000KM_PER_PER_M};
use crate::model::tire::worn_tread_block;
use crate::model::ContactPatch;
use crate::params::Params;
use crate::wear::fitted::{FittedConstants, WearAnswer};
use crate::wear::law::MM_PER_1000KM_PER_M_PER_M;

/// Points of the table of f₀/f over the usable depth.
const DRIFT_POINTS: usize = 33;

/// The largest step in x, in orders, of the integral over the life where the spread does not
/// smooth the resonance enough for a table (it is a few hundredths of an order wide).
const STEP_ORDERS: f64 = 0.02;

/// The spread's width at ν, in orders, from which Ḡ(x) is tabulated: its grid and the
/// integral's steps are a quarter of that width (so at least 0.05 of an order), and at most
/// [`MAX_TABLE_STEP_ORDERS`].
const TABLE_FROM_SPREAD_ORDERS: f64 = 0.2;

/// The coarsest grid of the table, in orders: a polygon seen late in the tire's life crosses
/// the visible depth slowly, so its distance magnifies the integral's error.
const MAX_TABLE_STEP_ORDERS: f64 = 0.1;

/// Ḡ(x), the tread's transfer averaged over the speed spread at order x, on a uniform grid:
/// a function of x alone, so every order of a wheel reads the same table as ν drifts past it.
#[derive(Debug, Clone, PartialEq)]
struct TransferTable {
    first: f64,
    step: f64,
    values: Vec<Complex64>,
}

impl TransferTable {
    fn new(g: &WheelGrowth, lo: f64, hi: f64, step: f64, spread_mps: f64) -> Self {
        let count = ((hi - lo) / step).ceil() as usize + 2;
        let values = (0..count)
            .map(|j| {
                g.response.transfer.mean_over_speed(
                    lo + step * j as f64,
                    g.r_b,
                    g.speed_mps,
                    spread_mps,
                )
            })
            .collect();
        TransferTable {
            first: lo,
            step,
            values,
        }
    }

    /// Ḡ at `x`, linear between the grid's points (held past its ends).
    fn at(&self, x: f64) -> Complex64 {
        let last = self.values.len() - 1;
        let u = ((x - self.first) / self.step).clamp(0.0, last as f64);
        let k = (u.floor() as usize).min(last - 1);
        let t = u - k as f64;
        self.values[k] * (1.0 - t) + self.values[k + 1] * t
    }
}

/// f₀/f(h₀ − w) over the worn depth w ∈ \[0, usable\]: the new tread's undamped frequency
/// √(K_s/m) over the worn one's (MODEL.md#the-ageing-tread; `worn_tread_block`).
#[derive(Debug, Clone, PartialEq)]
struct TreadDrift {
    usable_m: f64,
    ratio: Vec<f64>,
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
            .collect();
        TreadDrift { usable_m, ratio }
    }

    /// f₀/f at the worn depth `worn_m` (linear between the table's points, held past its ends).
    fn at(&self, worn_m: f64) -> f64 {
        if self.usable_m <= 0.0 || worn_m <= 0.0 {
            return 1.0;
        }
        let u = (worn_m / self.usable_m).min(1.0) * (DRIFT_POINTS - 1) as f64;
        let k = (u.floor() as usize).min(DRIFT_POINTS - 2);
        let t = u - k as f64;
        self.ratio[k] * (1.0 - t) + self.ratio[k + 1] * t
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
        self.life(c, true)
    }

    /// [`WheelGrowth::life_answer`]; `tabulate`: Ḡ(x) read from a table where the spread is wide
    /// enough ([`TABLE_FROM_SPREAD_ORDERS`]), else evaluated at every step in steps of
    /// [`STEP_ORDERS`] (what the table is tested against).
    fn life(&self, c: &FittedConstants, tabulate: bool) -> LifeAnswer {
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
        // The spread's width in orders at ν: where it smooths the resonance over a few tenths
        // of an order, Ḡ(x) is tabulated once for all orders.
        let spread_orders = nu * spread_mps / self.speed_mps;
        let table = (tabulate && spread_orders >= TABLE_FROM_SPREAD_ORDERS).then(|| {
            let step = (0.25 * spread_orders).min(MAX_TABLE_STEP_ORDERS);
            TransferTable::new(
                self,
                (lo as f64 * end - step).max(0.5 * lo as f64 * end),
                hi as f64 + step,
                step,
                spread_mps,
            )
        });
        let step_orders = table.as_ref().map_or(STEP_ORDERS, |t| t.step);
        let mut first: Option<(f64, u32)> = None;
        let mut deepest = (f64::NEG_INFINITY, lo);
        for n in lo..=hi {
            let (zone, forcing) = (
                self.feedback.zone.transfer(n as f64, self.r_b),
                self.feedback.forcing_per_radius(n as f64),
            );
            let beta_per_m = |s_m: f64| {
                let x = n as f64 * drift.at(wear_m_per_m * s_m);
                let fixed = self.order_fixed_with(n, x, zone, forcing);
                let terms = match &table {
                    Some(t) => self.spread_terms_with(&fixed, spread_mps, t.at(x)),
                    None => self.spread_terms(&fixed, spread_mps),
                };
                self.order_from(&terms, share, other_per_share)
                    .growth_rate_per_1000km
                    / PER_1000KM_PER_PER_M
            };
            let steps = ((n as f64 * (1.0 - end) / step_orders).ceil() as usize).max(8);
            let ds = life_m / steps as f64;
            let (mut log_growth, mut before) = (0.0, beta_per_m(0.0));
            let mut peak = 0.0_f64;
            for k in 1..=steps {
                let s = ds * k as f64;
                // Past an earlier order's polygon this one can only come later.
                if first.is_some_and(|(m, _)| s - ds > m) {
                    break;
                }
                let beta = beta_per_m(s);
                let next = log_growth + 0.5 * (before + beta) * ds;
                if next >= target && target > 0.0 {
                    let at_m = s - ds + ds * (target - log_growth) / (next - log_growth);
                    if first.is_none_or(|(m, _)| at_m < m) {
                        first = Some((at_m, n));
                    }
                    peak = peak.max(next);
                    break;
                }
                peak = peak.max(next);
                (log_growth, before) = (next, beta);
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

    /// The table of Ḡ(x) gives the integral evaluated at every step: at highway points with
    /// stable and vibrating wheels, both positions, spreads of 2–10 km/h, the same polygon
    /// within 3% in distance, or the same peak within 5% where none is visible (a case on the
    /// edge, visible by one and not by the other, only where the other's peak is at least 0.9
    /// of the visible depth).
    #[test]
    fn the_tabulated_transfer_gives_the_direct_integral() {
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
                for (phi, spread) in [(0.12, 5.0), (0.25, 5.0), (0.28, 10.0), (0.25, 2.0)] {
                    let c = FittedConstants {
                        wear_share_straight: phi,
                        speed_spread_kmh: spread,
                        wear_rate_driven_factor: 1.75,
                    };
                    let (t, d) = (g.life(&c, true), g.life(&c, false));
                    let at = format!("{speed_kmh} km/h {toe_deg} deg {wheel} {c:?}: {t:?} {d:?}");
                    let (st, sd) = (
                        t.answer.distance_to_visible_km,
                        d.answer.distance_to_visible_km,
                    );
                    match (st.is_finite(), sd.is_finite()) {
                        (true, true) => {
                            visible += 1;
                            assert!((st / sd - 1.0).abs() < 0.03, "{at}");
                            assert_eq!(t.answer.polygon_order_wear, d.answer.polygon_order_wear);
                        }
                        (false, false) => assert!(
                            (t.peak_share_of_visible / d.peak_share_of_visible - 1.0).abs() < 0.05,
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
