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

use super::{
    band_share, per_spread, tread_life_km, Complex64, NarrowBand, WheelGrowth,
    NARROW_BAND_DEVIATIONS, NEGLIGIBLE_LOCKED_SHARE,
};
use crate::model::tire::worn_tread_block;
use crate::model::ContactPatch;
use crate::params::Params;
use crate::wear::physics::feedback::FEEDBACK_ORDERS;
use crate::wear::physics::fitted::{FittedConstants, LifeAnswer};
use crate::wear::physics::law::MM_PER_1000KM_PER_M_PER_M;
use crate::wear::response::spread::NormalSpeeds;
use crate::wear::response::transfer::PoleExpansion;

mod depth_lock;
mod drift;
mod nodes;
mod profile;
mod saturate;
mod saturated;
mod walk;
pub use depth_lock::DepthLock;
use drift::TreadDrift;
use nodes::{Moments, Nodes, TransferNodes};
pub use profile::{LifeProfile, LIFE_PROFILE_INTERVALS};
pub use saturate::{
    answer_saturated_per_step, PiecewiseRate, SaturatedSteps, SpeedTerm, SLIDING_MODULATION_MAX,
};
pub use saturated::SATURATED_SPEED_LEGS;

/// Points of the table of f₀/f over the usable depth the worn depth's polynomial is fitted
/// through (17 give it within 2.5·10⁻⁷ of the usable depth of the ageing law, as 33 do).
const DRIFT_POINTS: usize = 17;

/// Degree of the polynomial in f₀/f − 1 that gives the worn depth (its derivative weighs Ḡ in
/// the distance, so that every order's integral of Ḡ is read from a few moments of it shared by
/// all orders): within 2.5·10⁻⁷ of the usable depth of the ageing law at carcass shares of
/// 0–0.7 (tested).
const WORN_DEGREE: usize = 5;

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

/// Poles resonating within this share of the nodes' span outside it are summed at every node;
/// the rest through [`Chebyshev`].
const FAR_POLE_MARGIN: f64 = 0.25;

/// The fewest far poles worth a Chebyshev fit: its sum at a node costs about what three poles'
/// series do (a stable wheel has two far poles, a vibrating one 15 or so).
const CHEBYSHEV_FAR_POLES: usize = 4;

/// Points of the Chebyshev fit of the far poles' sum: for a pole resonating a quarter of the
/// span beyond its end the coefficients fall as 2.6^{−j} (the Bernstein ellipse through it),
/// and that pole's share is at most a few % of Ḡ there; the fit's tail is checked
/// ([`CHEBYSHEV_TOLERANCE`]), and on the default study a vibrating wheel falls back to the sum
/// at every node about once in 500.
const CHEBYSHEV_POINTS: usize = 12;

/// The fit's last two coefficients, against the largest |Ḡ| at the nodes, above which the far
/// poles are summed at every node after all (far inside [`faddeeva_fast`]'s 10⁻⁴; against the
/// smallest |Ḡ| every wheel fell back, Ḡ passing near zero).
///
/// [`faddeeva_fast`]: crate::wear::response::spread
const CHEBYSHEV_TOLERANCE: f64 = 1e-7;

/// The orders ν passes over the tread's life, ⌊ν₀⌋ − 2 (at least 1) … ⌈ν₀ f_end/f₀⌉ + 2, for a
/// new tire's `nu_new` and f₀/f_end = `end_ratio`; the last no higher than the orders the
/// long-term loop resolves ([`FEEDBACK_ORDERS`]: its profile feeds back no higher order, the
/// zone filtering what lies beyond) or, where ν₀ itself lies beyond them, than ⌈ν₀⌉ + 2
/// (MODEL.md#the-estimator-over-the-treads-life). The ceiling bounds the walk's work whatever
/// the depths: a tread worn to nothing has f_end = ∞ (its mass ρabh is gone), and ν would
/// pass every order.
pub(in crate::wear::estimator) fn passed_orders(nu_new: f64, end_ratio: f64) -> (u32, u32) {
    let lo = (nu_new.floor() - 2.0).max(1.0);
    let ceiling = (FEEDBACK_ORDERS as f64).max(nu_new.ceil() + 2.0);
    let hi = ((nu_new / end_ratio).ceil() + 2.0).min(ceiling).max(lo);
    (lo as u32, hi as u32)
}

/// What [`WheelGrowth::life_answer`] takes from the wheel alone, whatever the fitted constants.
struct LifeOrders {
    drift: TreadDrift,
    /// The worn depth's slope along an order's path ([`TreadDrift::slope_coefficients`]).
    slope: [f64; WORN_DEGREE],
    /// f₀/f of the worn-out tire.
    end: f64,
    /// The orders ν passes, ⌊ν₀⌋ − 2 … ⌈ν₀ f_end/f₀⌉ + 2.
    lo: u32,
    hi: u32,
    /// Each order's zone transfer, forcing, and tongue (centre and half-width at x = 1, m/s).
    fixed: Vec<(Complex64, Complex64, (f64, f64))>,
    /// The transfer's uniform means over the widest tongue, once an order asks.
    tongue_means: std::cell::OnceCell<crate::wear::response::transfer::TongueMeans>,
}

/// ... and what it takes from the speed spread: the nodes of Ḡ(x).
struct LifeNodes {
    spread_mps: f64,
    transfer: TransferNodes,
    /// 1/x at the nodes.
    per_x: Vec<f64>,
    /// The narrow tongue's share of the spread at each node, once an order needs it.
    tongue_nodes: std::cell::OnceCell<Vec<NarrowBand>>,
}

impl LifeAnswer {
    /// Its figures' bits, to compare answers exactly (NaN, an order where every order
    /// levels, equal to itself).
    #[cfg(test)]
    pub(crate) fn bits(&self) -> [u64; 4] {
        [
            self.polygon_order_wear.to_bits(),
            self.distance_to_visible_km.to_bits(),
            self.tread_life_km.to_bits(),
            self.peak_share_of_visible.to_bits(),
        ]
    }

    /// The answer of a walk over a wheel's orders: the first polygon `first` (distance \[km\],
    /// order) if any, else none and the order that got deepest, `deepest` (its largest
    /// ln(D/2R⁰), order), NaN where no order rose above its seed (every order levels: which
    /// one "got deepest" would be only the lowest walked); a seed already visible (`target` =
    /// ln(d_visible/2R⁰) ≤ 0) is visible at once, as order `lowest`.
    pub(crate) fn of_walk(
        first: Option<(f64, u32)>,
        deepest: (f64, u32),
        target: f64,
        tread_life_km: f64,
        lowest: u32,
    ) -> Self {
        let (distance_to_visible_km, order) = match first {
            _ if target <= 0.0 => (0.0, lowest as f64),
            Some((km, n)) => (km, n as f64),
            None if deepest.0 <= 0.0 => (f64::INFINITY, f64::NAN),
            None => (f64::INFINITY, deepest.1 as f64),
        };
        LifeAnswer {
            polygon_order_wear: order,
            distance_to_visible_km,
            tread_life_km,
            peak_share_of_visible: if first.is_some() || target <= 0.0 {
                1.0
            } else {
                (deepest.0 - target).exp()
            },
        }
    }
}

impl WheelGrowth {
    /// Where each pole of the tread's transfer resonates, in orders: ω = x V/r_B at the pole's
    /// frequency |Im s|.
    fn resonance_orders(&self) -> impl Iterator<Item = f64> + '_ {
        self.response
            .transfer
            .terms
            .iter()
            .map(|t| t.pole.im.abs() * self.r_b / self.speed_mps)
    }

    /// The wheel's wear answer under `c` over the tread's life
    /// (MODEL.md#the-estimator-over-the-treads-life): every order that ν passes, integrated
    /// from the seed over the drifting tread frequency, until it is visible or the tire is worn
    /// out.
    pub fn life_answer(&self, c: &FittedConstants) -> LifeAnswer {
        let answer = self.aged(c).life(c, Nodes::Adaptive);
        self.in_time(vec![answer]).remove(0)
    }

    /// [`WheelGrowth::life_answer`] with Ḡ(x) at the `nodes` given. Order n's x = n·f₀/f runs
    /// from n down to n·f₀/f_end, at the distance s(x) = w(x/n)/ẇ (w the worn depth at which
    /// f₀/f = x/n). Ḡ is linear between the nodes and the linear loop is affine in it, so
    /// ln D_n at a node is closed-form: base·s + Re(through · ∫Ḡ ds), the integral from the
    /// nodes' moments ([`TransferNodes`]); the locked print by the trapezoid rule in s. ln D is
    /// taken only on the segments where it can rise.
    fn life(&self, c: &FittedConstants, nodes: Nodes) -> LifeAnswer {
        let orders = self.life_orders();
        let at = self.life_nodes(&orders, c.speed_spread_kmh / 3.6, nodes);
        self.life_from(&orders, &at, c)
    }

    /// `answers`, or unknown ones where the wheel's wall-clock limit passed while they were
    /// walked (a walk that finds it passed stops: what it gives is not an answer).
    pub(super) fn in_time(&self, answers: Vec<LifeAnswer>) -> Vec<LifeAnswer> {
        match self.out_of_time() {
            None => answers,
            Some(_) => vec![LifeAnswer::UNKNOWN; answers.len()],
        }
    }

    /// [`WheelGrowth::life_answer`] under each set of `sets`, each answer with every order's
    /// largest ln(D/2R⁰)
    /// over the life (orders from `.0`; [`WheelGrowth::life_walk`]): what the saturated level
    /// screens its orders with.
    pub(super) fn life_answers_and_peaks(
        &self,
        sets: &[FittedConstants],
    ) -> (u32, Vec<(LifeAnswer, Vec<f64>)>) {
        let orders = self.life_orders();
        let answers = per_spread(
            sets,
            |spread_mps| self.life_nodes(&orders, spread_mps, Nodes::Adaptive),
            |at, c| {
                let mut peaks = Vec::with_capacity(orders.fixed.len());
                let answer = self.life_walk(&orders, at, c, Some(&mut peaks));
                (answer, peaks)
            },
        );
        (orders.lo, answers)
    }

    /// What the answer over the tread's life takes from the wheel alone: the tread's drift, the
    /// orders ν passes, each with its zone transfer H_w(n), forcing e_n and tongue.
    fn life_orders(&self) -> LifeOrders {
        let drift = TreadDrift::of(&self.params, &self.patch);
        let (lo, hi) = passed_orders(self.nu(), drift.at_end());
        self.life_orders_over(drift, lo, hi)
    }

    /// Each order's largest ln(D/2R⁰) over the life on the plain walk
    /// ([`WheelGrowth::life_answers_and_peaks`]), for the orders `lo..=hi` alone (any orders,
    /// not only those ν passes) under each set of `sets`, all of the speed spread
    /// `spread_mps` \[m/s\]: what screens the saturated level's legs of orders beyond the plain
    /// walk's (the nodes of Ḡ laid over these orders alone).
    pub(super) fn life_peaks_over(
        &self,
        lo: u32,
        hi: u32,
        spread_mps: f64,
        sets: &[&FittedConstants],
    ) -> Vec<Vec<f64>> {
        let orders = self.life_orders_over(TreadDrift::of(&self.params, &self.patch), lo, hi);
        let at = self.life_nodes(&orders, spread_mps, Nodes::Adaptive);
        sets.iter()
            .map(|c| {
                let mut peaks = Vec::with_capacity(orders.fixed.len());
                self.life_walk(&orders, &at, c, Some(&mut peaks));
                peaks
            })
            .collect()
    }

    /// [`WheelGrowth::life_orders`] of the orders `lo..=hi` on the tread's `drift`.
    fn life_orders_over(&self, drift: TreadDrift, lo: u32, hi: u32) -> LifeOrders {
        let end = drift.at_end();
        // Each order's zone transfer H_w(n), forcing e_n, and tongue (centre and half-width,
        // m/s): the tongue at x: a worn tread's ν is ν₀·f/f₀, so order n locks as the new
        // tire's order x does, in a band of speeds around V ν/x, ±V δ_L/x (δ_L of order n). The
        // uniform mean over it is the same at every x: the band of ω = x V/r_B it spans does not
        // move.
        let fixed = (lo..=hi)
            .zip(self.feedback.zones_and_forcings(lo))
            .map(|(n, (zone, forcing))| {
                (
                    zone,
                    forcing,
                    self.tongue_mps(n as f64, forcing, self.seed_m),
                )
            })
            .collect();
        LifeOrders {
            slope: drift.slope_coefficients(),
            drift,
            end,
            lo,
            hi,
            fixed,
            tongue_means: std::cell::OnceCell::new(),
        }
    }

    /// The nodes of Ḡ(x) over `orders`' span for a spread of `spread_mps` \[m/s\], laid as
    /// `nodes` asks.
    fn life_nodes(&self, orders: &LifeOrders, spread_mps: f64, nodes: Nodes) -> LifeNodes {
        let transfer = TransferNodes::new(
            self,
            orders.lo as f64 * orders.end,
            orders.hi as f64,
            spread_mps,
            nodes,
        );
        LifeNodes {
            spread_mps,
            // 1/x at the nodes (every order's tongue is read there).
            per_x: transfer.x.iter().map(|x| 1.0 / x).collect(),
            transfer,
            tongue_nodes: std::cell::OnceCell::new(),
        }
    }

    /// The answer under `c` from the wheel's `orders` and the nodes `at` of its spread.
    fn life_from(&self, orders: &LifeOrders, at: &LifeNodes, c: &FittedConstants) -> LifeAnswer {
        self.life_walk(orders, at, c, None)
    }
}

#[cfg(test)]
mod table_tests;
