//! The answer over the tread's life with each speed's forced response saturated
//! (MODEL.md#the-forced-response-saturates): the `saturated` estimate level.
//!
//! The answer over the tread's life averages the tread's transfer over the speed spread (Ḡ)
//! before it forms an order's growth, and lets that growth print without bound. A deep order
//! prints at most m_max · 2 w′ |H_w| at each speed, so the spread is driven here as the
//! long-term loop drives it: equal shares of the distance at the spread's quantiles, each leg
//! the sample's own model read at the leg's speed (its transfer at ω = x v/r_B and ν ∝ 1/v, as
//! Ḡ reads them), each order's print held to the bound at each leg on its own
//! ([`answer_saturated_per_step`]).
//!
//! The saturated answer of a stable tread is never earlier and never deeper than the
//! unsaturated one of the same legs (tested), so the plain answer screens: a set under which no
//! order is visible keeps the plain answer, and only the wheels with a polygon pay for the legs.
//! A vibrating tread's orders also lock at depth and are captured where the drift carries ν
//! through them ([`super::DepthLock`], MODEL.md#the-locked-print), which can outgrow the
//! unsaturated path; the same screen is kept for them, a measured approximation: walking every
//! vibrating wheel whose locked print could hold a visible polygon against its levelling (3.5%
//! of the vibrating wheels) cost explore five times its `--no-wear` time, and on 20,000 samples
//! of the default study it changed one wheel's answer of 40,000, to a polygon the long-term loop
//! does not give (MODEL.md#the-lock-at-depth-in-the-estimator).

#[cfg(doc)]
use super::answer_saturated_per_step;
use super::profile::DepthGrid;
use super::{
    passed_orders, LifeAnswer, LifeProfile, Nodes, SaturatedSteps, TransferNodes,
    LIFE_PROFILE_INTERVALS, SLIDING_MODULATION_MAX,
};
use crate::wear::estimator::{per_spread, WheelGrowth};
use crate::wear::physics::fitted::FittedConstants;
use crate::wear::response::legs::cruise_legs;

/// A spread's legs ([`WheelGrowth::spread_legs`]): each one's share of the distance and its
/// speed over the sample's, q; the slowest and fastest q; and the orders the legs lay, from the
/// lowest ν passes at the fastest leg to the highest at the slowest.
struct SpreadLegs {
    scales: Vec<(f64, f64)>,
    slowest: f64,
    fastest: f64,
    from: u32,
    to: u32,
}

/// Legs of the speed spread the saturated answer drives: the long-term loop's spreads settle
/// from about 40 (`polywear wear --speed-nodes 40`; at 110 km/h, σ_V = 5 km/h the loop moves
/// by 14% and 16% from 5 legs to 40).
pub const SATURATED_SPEED_LEGS: usize = 40;

/// The legs are built for the orders whose plain answer (the spread's mean transfer, no
/// saturation) comes within this much of the visible depth in ln D, a factor e² ≈ 7.4: the
/// saturated order is never deeper than the legs' unsaturated mean, which is the plain answer
/// within its quadrature (6% in distance, about 0.3 in ln D; tested). The orders left out
/// cannot reach the visible depth; the answer is that of every order's legs (tested).
const SCREEN_LOG_MARGIN: f64 = 2.0;

/// The lowest leg speed, as a share of the sample's: a spread wide enough to put a quantile
/// below it (σ_V above about 0.4 V at 40 legs) has those legs held there.
const LOWEST_LEG_SHARE: f64 = 0.05;

impl WheelGrowth {
    /// The legs of a spread of `spread_mps` \[m/s\]: [`SATURATED_SPEED_LEGS`] equal shares at
    /// its quantiles (the speed itself without a spread), each with its profile over the
    /// tread's life on one grid of orders, from the lowest order ν passes at the fastest leg to
    /// the highest at the slowest. Each leg is the wheel's own model read at the leg's speed
    /// v = q V: its transfer at ω = x v/r_B, ν = ν₀/q; the tongue's band of speeds, the
    /// powers and the zone's feedback are the sample's, as the spread's mean Ḡ takes them
    /// (MODEL.md#the-speed-spread). One set of nodes of the transfer serves every leg
    /// (`WheelGrowth::life_profile_on`).
    pub fn spread_leg_profiles(&self, spread_mps: f64) -> Vec<(f64, LifeProfile)> {
        let grid = DepthGrid::of(self, LIFE_PROFILE_INTERVALS);
        self.spread_leg_profiles_of(&grid, spread_mps, |_| true)
    }

    /// [`WheelGrowth::spread_leg_profiles`] on `grid` of the orders `profiled` accepts alone
    /// (the others' integrals left at zero): the same nodes of the transfer, so each order's
    /// integrals are those of every order's legs, bit for bit.
    fn spread_leg_profiles_of(
        &self,
        grid: &DepthGrid,
        spread_mps: f64,
        profiled: impl Fn(u32) -> bool + Copy,
    ) -> Vec<(f64, LifeProfile)> {
        let SpreadLegs {
            scales,
            slowest,
            fastest,
            from,
            to,
        } = self.spread_legs(grid, spread_mps);
        let end = grid.drift.at_end().min(1.0);
        let transfer = TransferNodes::new(
            self,
            from as f64 * end * slowest,
            to as f64 * fastest,
            0.0,
            Nodes::Adaptive,
        );
        scales
            .into_iter()
            .map(|(share, q)| {
                let profile = self.life_profile_on(grid, &transfer, q, from, profiled, to, true);
                (share, profile)
            })
            .collect()
    }

    /// The legs of a spread of `spread_mps` \[m/s\] and the orders they lay.
    fn spread_legs(&self, grid: &DepthGrid, spread_mps: f64) -> SpreadLegs {
        let v = self.speed_mps;
        let legs = cruise_legs(v * 3.6, spread_mps * 3.6, SATURATED_SPEED_LEGS);
        let scales: Vec<(f64, f64)> = legs
            .iter()
            .map(|l| (l.share, (l.speed_kmh / 3.6 / v).max(LOWEST_LEG_SHARE)))
            .collect();
        let (slowest, fastest) = scales
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(lo, hi), &(_, q)| {
                (lo.min(q), hi.max(q))
            });
        let end = grid.drift.at_end().min(1.0);
        let nu = self.nu();
        let from = passed_orders(nu / fastest, end).0;
        let to = passed_orders(nu / slowest, end).1.max(from);
        SpreadLegs {
            scales,
            slowest,
            fastest,
            from,
            to,
        }
    }

    /// [`WheelGrowth::life_answer`] under every set of `sets` with each leg's print saturated
    /// ([`answer_saturated_per_step`], m_max = [`SLIDING_MODULATION_MAX`]) under every set of
    /// `sets`: a set whose plain answer has no polygon keeps it (the saturated one is never
    /// earlier or deeper), the others are driven on the legs of their spread, built once per
    /// spread for the orders that come within a factor e² of the visible depth on the plain
    /// walk under some set of that spread with a polygon (the saturated answer is never deeper,
    /// and the legs' unsaturated mean is the plain answer's spread, by quadrature; the answer
    /// is that of every order's legs, tested). The legs' orders beyond the plain answer's are
    /// walked plainly on their own for that screen, for the sets with a polygon alone.
    pub fn saturated_answers_with(&self, sets: &[FittedConstants]) -> Vec<LifeAnswer> {
        let answers = self.per_ageing(sets, |g, sets| {
            g.saturated_answers_screened(sets, SCREEN_LOG_MARGIN)
        });
        self.in_time(answers)
    }

    /// [`WheelGrowth::saturated_answers_with`] with the legs built for the orders whose plain
    /// peak comes within `margin` (in ln D) of the visible depth (+inf: every order).
    fn saturated_answers_screened(&self, sets: &[FittedConstants], margin: f64) -> Vec<LifeAnswer> {
        let (lowest, walks) = self.life_answers_and_peaks(sets);
        let visible = |a: &LifeAnswer| a.distance_to_visible_km.is_finite();
        if walks.iter().all(|(a, _)| !visible(a)) {
            return walks.into_iter().map(|(a, _)| a).collect();
        }
        // Per spread with a polygon under some set, the orders of its legs (from ..= to) that
        // some such set brings within the margin of the visible depth on the plain walk: the
        // legs are laid for those alone, once per spread. The legs reach orders the plain walk
        // does not (it walks ⌊ν⌋ − 2 … ⌈ν f₀/f_end⌉ + 2 at the sample's own speed): those are
        // walked plainly on their own, for the spread's sets with a polygon.
        let target = self.print_log_ratio;
        let highest = lowest + walks.first().map_or(0, |(_, p)| p.len() as u32).max(1) - 1;
        let grid = DepthGrid::of(self, LIFE_PROFILE_INTERVALS);
        let mut near: Vec<(u64, u32, Vec<bool>)> = Vec::new();
        for (c, (answer, peaks)) in sets.iter().zip(&walks) {
            if !visible(answer) {
                continue;
            }
            let key = (c.speed_spread_kmh / 3.6).to_bits();
            let k = match near.iter().position(|(k, ..)| *k == key) {
                Some(k) => k,
                None => {
                    let legs = self.spread_legs(&grid, f64::from_bits(key));
                    let orders = (legs.to - legs.from + 1) as usize;
                    near.push((key, legs.from, vec![!margin.is_finite(); orders]));
                    near.len() - 1
                }
            };
            let (_, from, is_near) = &mut near[k];
            for (n, &peak) in (lowest..).zip(peaks) {
                if let Some(is_near) = n
                    .checked_sub(*from)
                    .and_then(|i| is_near.get_mut(i as usize))
                {
                    *is_near |= peak >= target - margin;
                }
            }
        }
        if margin.is_finite() {
            for (key, from, is_near) in &mut near {
                let to = *from + is_near.len() as u32 - 1;
                let with_polygon: Vec<&FittedConstants> = sets
                    .iter()
                    .zip(&walks)
                    .filter(|(c, (a, _))| {
                        (c.speed_spread_kmh / 3.6).to_bits() == *key && visible(a)
                    })
                    .map(|(c, _)| c)
                    .collect();
                let below = *from..=to.min(lowest.saturating_sub(1));
                let above = (*from).max(highest + 1)..=to;
                for orders in [below, above] {
                    if orders.is_empty() {
                        continue;
                    }
                    let (a, b) = (*orders.start(), *orders.end());
                    for peaks in self.life_peaks_over(a, b, f64::from_bits(*key), &with_polygon) {
                        for (n, peak) in (a..).zip(peaks) {
                            is_near[(n - *from) as usize] |= peak >= target - margin;
                        }
                    }
                }
            }
        }
        let mut next = walks.into_iter();
        per_spread(
            sets,
            |spread_mps| {
                let near = near
                    .iter()
                    .find(|(k, ..)| *k == spread_mps.to_bits())
                    .map(|(_, from, near)| (*from, near.as_slice()));
                (
                    spread_mps,
                    near,
                    std::cell::OnceCell::<SaturatedSteps>::new(),
                )
            },
            |(spread_mps, near, legs), c| {
                let (plain, _) = next.next().expect("one plain answer per set");
                if !visible(&plain) {
                    return plain;
                }
                // The legs and their mean are laid once per spread, for every set on it.
                let legs = legs.get_or_init(|| {
                    let profiled = |n: u32| {
                        near.is_none_or(|(from, near)| {
                            n.checked_sub(from)
                                .and_then(|i| near.get(i as usize))
                                .is_some_and(|&is_near| is_near)
                        })
                    };
                    SaturatedSteps::new(self.spread_leg_profiles_of(&grid, *spread_mps, profiled))
                });
                let mut bounded = legs.answer(c, &self.params, SLIDING_MODULATION_MAX);
                // The legs share the wheel's even wear: its tread's life is the plain answer's
                // (the same sum, taken once rather than over the legs' shares).
                bounded.tread_life_km = plain.tread_life_km;
                bounded
            },
        )
    }

    /// [`WheelGrowth::saturated_answers_with`] of one set.
    pub fn saturated_answer(&self, c: &FittedConstants) -> LifeAnswer {
        self.saturated_answers_with(std::slice::from_ref(c))
            .pop()
            .expect("one set, one answer")
    }
}

#[cfg(test)]
mod tests;
