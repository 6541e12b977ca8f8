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
        let visible = |a: &LifeAnswer| a.answer.distance_to_visible_km.is_finite();
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
                bounded.answer.tread_life_km = plain.answer.tread_life_km;
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
mod tests {
    use super::super::profile::tests::growth_at;
    use super::super::profile::{saturated_walk_substeps, steps_mean};
    use super::super::{answer_saturated_per_step, PiecewiseRate, SpeedTerm};
    use super::*;
    use crate::classify::ClassifierOptions;
    use crate::evaluate::calibrate_wear;
    use crate::model::{Variant, Wheel};
    use crate::params::Params;
    use crate::wear::estimator::print_log_ratio;

    /// Vibrating wheels at 0.3°, φ_s = 1 (the cruising points of MODEL.md#the-locked-print),
    /// with the default point's calibration: (where, parameters, growth) per wheel.
    fn vibrating_wheels(points: &[(f64, f64)]) -> Vec<(String, Params, WheelGrowth)> {
        let cal = calibrate_wear(
            &crate::wear::physics::fitted::pinned_params(),
            Variant::SlidingShare,
            &ClassifierOptions::default(),
        )
        .unwrap();
        let mut out = Vec::new();
        for &(speed_kmh, spread_kmh) in points {
            let p = Params {
                speed_kmh,
                toe_deg: 0.3,
                wear_share_straight: 1.0,
                speed_spread_kmh: spread_kmh,
                ..crate::wear::physics::fitted::pinned_params()
            };
            for wheel in Wheel::BOTH {
                let (g, vibrates) = growth_at(&p, &cal, wheel);
                assert!(vibrates, "{speed_kmh} km/h {wheel}");
                out.push((format!("{speed_kmh} km/h sigma {spread_kmh} {wheel}"), p, g));
            }
        }
        out
    }

    /// The drift's capture and the lock at depth (MODEL.md#the-locked-print): at 110 km/h,
    /// 0.3°, φ_s = 1, no spread, the long-term loop grows order 18 on both wheels, 5,712 /
    /// 4,138 km (`polywear wear --speed 110 --toe 0.3 --set wear_share_straight=1
    /// --speed-spread-kmh 0 --calibration-band off`), where the new tire's ν is 17.6 and rises
    /// through 18 as the tread wears. The level gives order 18 within 25% of the loop; without
    /// the lock at depth (the profiles' locks taken away) it gives order 17, and the driving
    /// wheel's polygon at more than twice the loop's distance.
    #[test]
    fn the_drift_captures_the_order_it_carries_nu_through() {
        for ((here, p, g), loop_km) in vibrating_wheels(&[(110.0, 0.0)])
            .into_iter()
            .zip([5_712.0, 4_138.0])
        {
            let c = FittedConstants::of(&p);
            let level = g.saturated_answer(&c).answer;
            assert_eq!(level.polygon_order_wear, 18.0, "{here}: {level:?}");
            let ratio = level.distance_to_visible_km / loop_km;
            assert!((0.75..=1.25).contains(&ratio), "{here}: {level:?}");
            let mut legs = g.spread_leg_profiles(0.0);
            for (_, profile) in legs.iter_mut() {
                profile.lock = None;
            }
            let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
            let unlocked = answer_saturated_per_step(&steps, &c, &p, SLIDING_MODULATION_MAX).answer;
            assert_eq!(unlocked.polygon_order_wear, 17.0, "{here}: {unlocked:?}");
            if here.contains("driving") {
                assert!(
                    unlocked.distance_to_visible_km > 2.0 * loop_km,
                    "{here}: {unlocked:?}"
                );
            }
        }
    }

    /// Where orders lock at depth, the walk that leaves out the orders that cannot beat its
    /// answer (by the unsaturated path where no step can lock, by the sliding bound where one
    /// can) gives the answer of driving every order; and the locked stretches, each share held
    /// at its predicted middle, give the distance within 0.5% of the midpoint rule on 256 steps
    /// per interval with the share read at every step.
    #[test]
    fn the_locked_walk_screens_soundly_and_settles() {
        let mut locked = 0;
        for (here, p, g) in vibrating_wheels(&[(90.0, 0.0), (100.0, 5.0), (110.0, 2.0)]) {
            let c = FittedConstants::of(&p);
            let legs = g.spread_leg_profiles(p.speed_spread_kmh / 3.6);
            let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
            let mean = steps_mean(&steps);
            let m = SLIDING_MODULATION_MAX;
            let walk = |midpoint: Option<usize>, screen: bool| {
                saturated_walk_substeps(&steps, &mean, &c, &p, m, midpoint, screen).answer
            };
            let (got, every, fine) = (walk(None, true), walk(None, false), walk(Some(256), true));
            assert_eq!(got.polygon_order_wear, every.polygon_order_wear, "{here}");
            assert_eq!(
                got.distance_to_visible_km, every.distance_to_visible_km,
                "{here}"
            );
            assert_eq!(got.polygon_order_wear, fine.polygon_order_wear, "{here}");
            let (a, b) = (got.distance_to_visible_km, fine.distance_to_visible_km);
            assert!(
                a.is_finite() && (a - b).abs() <= 0.005 * b,
                "{here}: {a} against {b}"
            );
            let mut unlocked_legs = legs.clone();
            for (_, profile) in unlocked_legs.iter_mut() {
                profile.lock = None;
            }
            let unlocked: Vec<(f64, &LifeProfile)> =
                unlocked_legs.iter().map(|(a, pr)| (*a, pr)).collect();
            let plain = answer_saturated_per_step(&unlocked, &c, &p, m).answer;
            if (plain.distance_to_visible_km - a).abs() > 0.05 * a {
                locked += 1;
            }
        }
        assert!(
            locked >= 4,
            "the lock at depth moved only {locked} of 6 wheels by 5%"
        );
    }

    /// Where no order becomes visible, the screens keep the whole answer, deepest order and
    /// its peak included: at the shipped constants (stable and vibrating treads, a speed
    /// spread of 0, 2 and 5 km/h, which lays several legs), the screened walk is the walk of
    /// every order, bit for bit. Among them are wheels whose every order levels from its seed
    /// (the deepest ln u is 0, so no order is the wear's: NaN), whose orders after the first
    /// the screens skip without walking them (on a drive cycle, four fifths of
    /// `polywear cycle`'s time).
    #[test]
    fn the_screens_keep_a_levelling_wheel_s_deepest_order() {
        let cal = calibrate_wear(
            &crate::wear::physics::fitted::pinned_params(),
            Variant::SlidingShare,
            &ClassifierOptions::default(),
        )
        .unwrap();
        let (mut none, mut at_seed) = (0, 0);
        for speed_kmh in [70.0, 90.0, 110.0, 130.0] {
            for spread_kmh in [0.0, 2.0, 5.0] {
                let p = Params {
                    speed_kmh,
                    speed_spread_kmh: spread_kmh,
                    ..crate::wear::physics::fitted::pinned_params()
                };
                let c = FittedConstants::of(&p);
                for wheel in Wheel::BOTH {
                    let here = format!("{speed_kmh} km/h sigma {spread_kmh} {wheel}");
                    let g = growth_at(&p, &cal, wheel).0;
                    let legs = g.spread_leg_profiles(spread_kmh / 3.6);
                    let steps: Vec<(f64, &LifeProfile)> =
                        legs.iter().map(|(a, pr)| (*a, pr)).collect();
                    let mean = steps_mean(&steps);
                    let m = SLIDING_MODULATION_MAX;
                    let got = saturated_walk_substeps(&steps, &mean, &c, &p, m, None, true);
                    let every = saturated_walk_substeps(&steps, &mean, &c, &p, m, None, false);
                    assert_eq!(got.bits(), every.bits(), "{here}");
                    if got.answer.distance_to_visible_km.is_infinite() {
                        none += 1;
                        if got.peak_share_of_visible == (-print_log_ratio(&p)).exp() {
                            assert!(got.answer.polygon_order_wear.is_nan(), "{here}");
                            at_seed += 1;
                        }
                    }
                }
            }
        }
        assert!(
            none >= 20 && at_seed >= 10,
            "{none} without a polygon, {at_seed} at the seed"
        );
    }

    /// Highway points at 0.45–0.6° toe-in with the calibration of the default point, both
    /// wheels (stable and vibrating among them), with a speed spread.
    fn highway_wheels(spread_kmh: f64) -> Vec<(String, Params, WheelGrowth)> {
        let base = Params {
            toe_deg: 0.45,
            speed_spread_kmh: spread_kmh,
            ..crate::wear::physics::fitted::pinned_params()
        };
        let cal =
            calibrate_wear(&base, Variant::SlidingShare, &ClassifierOptions::default()).unwrap();
        let mut out = Vec::new();
        for (speed_kmh, toe_deg, share) in
            [(110.0, 0.45, 1.0), (130.0, 0.5, 0.25), (93.0, 0.6, 0.5)]
        {
            let p = Params {
                speed_kmh,
                toe_deg,
                wear_share_straight: share,
                ..base
            };
            for wheel in Wheel::BOTH {
                let here = format!("{speed_kmh} km/h {toe_deg}° phi_s {share} {wheel}");
                out.push((here, p, growth_at(&p, &cal, wheel).0));
            }
        }
        out
    }

    /// A leg read off the wheel's nodes at q·V is the wheel's model rebuilt at that speed (ν
    /// and the speed set there, its own nodes laid afresh): the moments' q^{−(m+1)} and the
    /// reads at x·q are what the rebuilt one's integrals give.
    #[test]
    fn a_leg_read_at_its_speed_is_the_model_rebuilt_there() {
        for (here, _, g) in highway_wheels(5.0) {
            let legs = g.spread_leg_profiles(5.0 / 3.6);
            assert_eq!(legs.len(), SATURATED_SPEED_LEGS, "{here}");
            let shares: f64 = legs.iter().map(|(a, _)| a).sum();
            assert!((shares - 1.0).abs() < 1e-12, "{here}");
            let speeds = cruise_legs(g.speed_mps * 3.6, 5.0, SATURATED_SPEED_LEGS);
            for k in [0, 13, SATURATED_SPEED_LEGS - 1] {
                let v = speeds[k].speed_kmh / 3.6;
                let mut rebuilt = g.clone();
                rebuilt.response.nu *= g.speed_mps / v;
                rebuilt.speed_mps = v;
                let profile = &legs[k].1;
                let own = rebuilt.life_profile(profile.max_order, profile.intervals);
                let first = (1..=profile.max_order)
                    .find(|&n| profile.full_print_per_share[n as usize - 1] > 0.0)
                    .unwrap();
                let largest = (first..=profile.max_order)
                    .flat_map(|n| (0..=profile.intervals).map(move |j| (n, j)))
                    .map(|(n, j)| own.integral(n, j).abs())
                    .fold(0.0, f64::max);
                assert!(largest > 0.0, "{here}");
                // Both take Ḡ linear between nodes 0.02 order apart near a resonance, laid over
                // different spans: next to a vibrating wheel's lightly damped poles that is
                // good to about 1.5% of the largest integral (a leg's q^{−(m+1)} left out moves
                // them by q^{−5}, 0.6–1.7 over these legs).
                for n in first..=profile.max_order {
                    for j in 0..=profile.intervals {
                        let (a, b) = (profile.integral(n, j), own.integral(n, j));
                        assert!(
                            (a - b).abs() <= 0.02 * largest,
                            "{here} leg {k} order {n} point {j}: {a} against {b} (of {largest})"
                        );
                    }
                }
            }
        }
    }

    /// Unsaturated, the legs are a quadrature of the spread the answer over the tread's life
    /// takes in closed form (Ḡ): the same polygon, its distance within 6%.
    #[test]
    fn the_legs_unsaturated_are_the_spread_s_mean() {
        let mut compared = 0;
        for (here, p, g) in highway_wheels(5.0) {
            let c = FittedConstants::of(&p);
            let plain = g.life_answer(&c).answer;
            let legs = g.spread_leg_profiles(5.0 / 3.6);
            let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
            let unbounded = answer_saturated_per_step(&steps, &c, &p, f64::INFINITY).answer;
            let (a, b) = (
                unbounded.distance_to_visible_km,
                plain.distance_to_visible_km,
            );
            if b.is_finite() {
                compared += 1;
                assert!(
                    (unbounded.polygon_order_wear - plain.polygon_order_wear).abs() <= 1.0,
                    "{here}: {unbounded:?} against {plain:?}"
                );
                assert!((a - b).abs() <= 0.06 * b, "{here}: {a} km against {b} km");
            } else {
                assert!(
                    a.is_infinite() || a > 0.9 * plain.tread_life_km,
                    "{here}: {a} km"
                );
            }
        }
        assert!(compared >= 3, "only {compared} wheels with a polygon");
    }

    /// Every order driven in turn, as [`answer_saturated_per_step`] did before it left out
    /// the orders that cannot beat its answer: the reference it must equal.
    fn every_order(
        steps: &[(f64, &LifeProfile)],
        c: &FittedConstants,
        p: &Params,
        modulation_max: f64,
    ) -> LifeAnswer {
        let total: f64 = steps.iter().map(|(a, _)| a).sum();
        let like = steps[0].1;
        let mut mean = LifeProfile::zero(like.max_order, like.intervals, like.usable_m);
        for &(a, profile) in steps {
            mean.add(profile, a / total);
        }
        let wear = mean.tread_wear_m_per_m(c);
        let target = print_log_ratio(p);
        let tread_life = crate::wear::estimator::tread_life_km(
            p,
            wear * crate::wear::physics::law::MM_PER_1000KM_PER_M_PER_M,
        );
        let seed_m = 2.0 * p.seed_runout_um * 1e-6;
        let phi = c.wear_share_straight;
        let dw = like.usable_m / like.intervals as f64;
        let ds = dw / wear;
        let (mut first, mut deepest): (Option<(f64, u32)>, (f64, u32)) =
            (None, (f64::NEG_INFINITY, 1));
        for n in 1..=like.max_order {
            let k = n as usize - 1;
            let (mut u, mut peak, mut s) = (1.0_f64, 1.0_f64, 0.0);
            for j in 1..=like.intervals {
                let terms: Vec<SpeedTerm> = steps
                    .iter()
                    .map(|&(a, pr)| {
                        let other = (1.0 - phi)
                            * (pr.other_per_share.0
                                + c.wear_rate_driven_factor * pr.other_per_share.1);
                        let base = phi * pr.base_per_share[k] - other;
                        let rate =
                            (phi * (pr.integral(n, j) - pr.integral(n, j - 1)) - other * dw) / dw;
                        SpeedTerm {
                            share: a / total,
                            base_per_m: base,
                            growth_per_m: rate - base,
                            bound_per_m: phi * pr.full_print_per_share[k] * modulation_max / seed_m,
                            floor_per_m: 0.0,
                        }
                    })
                    .collect();
                let (end, cross) = PiecewiseRate::of_terms(&terms).evolve(u, ds, target.exp());
                if let Some(t) = cross {
                    if first.is_none_or(|(m, _)| s + t < m) {
                        first = Some((s + t, n));
                    }
                    peak = target.exp();
                    break;
                }
                u = end;
                peak = peak.max(u);
                s += ds;
            }
            if peak.ln() > deepest.0 {
                deepest = (peak.ln(), n);
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

    /// The saturated answer leaves out the orders that cannot beat it, and is that of driving
    /// every order; it is never earlier or deeper than the legs unsaturated; where the plain
    /// answer has no polygon the level keeps it.
    #[test]
    fn the_saturated_level_drives_only_what_can_change_its_answer() {
        let mut slowed = 0;
        for spread_kmh in [0.0, 5.0] {
            for (here, p, g) in highway_wheels(spread_kmh) {
                let c = FittedConstants::of(&p);
                let legs = g.spread_leg_profiles(spread_kmh / 3.6);
                let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
                let got = answer_saturated_per_step(&steps, &c, &p, SLIDING_MODULATION_MAX);
                let want = every_order(&steps, &c, &p, SLIDING_MODULATION_MAX);
                assert_eq!(
                    got.answer.polygon_order_wear, want.answer.polygon_order_wear,
                    "{here} sigma {spread_kmh}"
                );
                let (a, b) = (
                    got.answer.distance_to_visible_km,
                    want.answer.distance_to_visible_km,
                );
                assert!(
                    a == b || (a - b).abs() <= 1e-9 * b,
                    "{here} sigma {spread_kmh}: {a} {b}"
                );
                let (x, y) = (got.peak_share_of_visible, want.peak_share_of_visible);
                assert!((x - y).abs() <= 1e-9, "{here} sigma {spread_kmh}: {x} {y}");
                let unbounded = answer_saturated_per_step(&steps, &c, &p, f64::INFINITY);
                assert!(
                    a >= unbounded.answer.distance_to_visible_km,
                    "{here} sigma {spread_kmh}"
                );
                let level = g.saturated_answer(&c);
                let plain = g.life_answer(&c);
                if plain.answer.distance_to_visible_km.is_finite() {
                    // The tread's life is the plain answer's, the legs' sum of one even wear.
                    let life_km = plain.answer.tread_life_km;
                    let (x, y) = (got.answer.tread_life_km, life_km);
                    assert!((x - y).abs() <= 1e-9 * y, "{here} sigma {spread_kmh}");
                    let mut got = got;
                    got.answer.tread_life_km = life_km;
                    assert_eq!(level, got, "{here} sigma {spread_kmh}");
                    if a > 1.2 * plain.answer.distance_to_visible_km {
                        slowed += 1;
                    }
                } else {
                    assert_eq!(level, plain, "{here} sigma {spread_kmh}");
                }
            }
        }
        assert!(slowed >= 4, "saturation moved only {slowed} wheels by 20%");
    }

    /// The legs are built only for the orders the plain answer brings within
    /// [`SCREEN_LOG_MARGIN`] of the visible depth (the legs' orders beyond the plain answer's
    /// by their own plain walk), and the answer is that of every order's legs, bit for bit: at
    /// highway points, at 62 km/h with a spread wide enough for its fast legs to reach orders
    /// below the plain walk's, under a band of sets on several spreads. A screen that keeps
    /// none of the plain walk's orders changes answers, and so does one that leaves out the
    /// orders beyond them: the test can tell.
    #[test]
    fn the_screened_legs_give_every_order_s_answer() {
        let mut wheels = highway_wheels(5.0);
        let base = Params {
            toe_deg: 0.6,
            speed_kmh: 62.0,
            wear_share_straight: 0.25,
            speed_spread_kmh: 10.0,
            ..crate::wear::physics::fitted::pinned_params()
        };
        let cal =
            calibrate_wear(&base, Variant::SlidingShare, &ClassifierOptions::default()).unwrap();
        for wheel in Wheel::BOTH {
            wheels.push((
                format!("62 km/h 0.6° {wheel}"),
                base,
                growth_at(&base, &cal, wheel).0,
            ));
        }
        let sets: Vec<FittedConstants> = [0.12, 0.25, 0.5, 1.0]
            .into_iter()
            .flat_map(|phi| {
                [2.0, 5.0, 10.0].into_iter().flat_map(move |sigma| {
                    [1.5, 2.0].map(|k_d| FittedConstants {
                        wear_share_straight: phi,
                        speed_spread_kmh: sigma,
                        wear_rate_driven_factor: k_d,
                        ..FittedConstants::of(&crate::wear::physics::fitted::pinned_params())
                    })
                })
            })
            .collect();
        let (mut polygons, mut told) = (0, 0);
        for (here, _, g) in wheels {
            let every = g.saturated_answers_screened(&sets, f64::INFINITY);
            let screened = g.saturated_answers_screened(&sets, SCREEN_LOG_MARGIN);
            for ((c, a), b) in sets.iter().zip(&screened).zip(&every) {
                assert_eq!(a.bits(), b.bits(), "{here} under {c:?}");
                polygons += usize::from(b.answer.distance_to_visible_km.is_finite());
            }
            let none = g.saturated_answers_screened(&sets, -1e9);
            told += usize::from(none.iter().zip(&every).any(|(a, b)| a.bits() != b.bits()));
        }
        assert!(polygons >= 40, "only {polygons} answers with a polygon");
        assert!(
            told >= 3,
            "a screen of no orders changed only {told} wheels"
        );
    }
}
