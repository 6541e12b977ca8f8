//! The saturated answer's legs and its screened walk against the full one.

use super::super::profile::tests::growth_at;
use super::super::saturate::{saturated_walk_substeps, steps_mean};
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
        let level = g.saturated_answer(&c);
        assert_eq!(level.polygon_order_wear, 18.0, "{here}: {level:?}");
        let ratio = level.distance_to_visible_km / loop_km;
        assert!((0.75..=1.25).contains(&ratio), "{here}: {level:?}");
        let mut legs = g.spread_leg_profiles(0.0);
        for (_, profile) in legs.iter_mut() {
            profile.lock = None;
        }
        let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
        let unlocked = answer_saturated_per_step(&steps, &c, &p, SLIDING_MODULATION_MAX);
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
            saturated_walk_substeps(&steps, &mean, &c, &p, m, midpoint, screen)
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
        let plain = answer_saturated_per_step(&unlocked, &c, &p, m);
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
                let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
                let mean = steps_mean(&steps);
                let m = SLIDING_MODULATION_MAX;
                let got = saturated_walk_substeps(&steps, &mean, &c, &p, m, None, true);
                let every = saturated_walk_substeps(&steps, &mean, &c, &p, m, None, false);
                assert_eq!(got.bits(), every.bits(), "{here}");
                if got.distance_to_visible_km.is_infinite() {
                    none += 1;
                    if got.peak_share_of_visible == (-print_log_ratio(&p)).exp() {
                        assert!(got.polygon_order_wear.is_nan(), "{here}");
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
    let cal = calibrate_wear(&base, Variant::SlidingShare, &ClassifierOptions::default()).unwrap();
    let mut out = Vec::new();
    for (speed_kmh, toe_deg, share) in [(110.0, 0.45, 1.0), (130.0, 0.5, 0.25), (93.0, 0.6, 0.5)] {
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
        let plain = g.life_answer(&c);
        let legs = g.spread_leg_profiles(5.0 / 3.6);
        let steps: Vec<(f64, &LifeProfile)> = legs.iter().map(|(a, pr)| (*a, pr)).collect();
        let unbounded = answer_saturated_per_step(&steps, &c, &p, f64::INFINITY);
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
    let (mut first, mut deepest): (Option<(f64, u32)>, (f64, u32)) = (None, (f64::NEG_INFINITY, 1));
    for n in 1..=like.max_order {
        let k = n as usize - 1;
        let (mut u, mut peak, mut s) = (1.0_f64, 1.0_f64, 0.0);
        for j in 1..=like.intervals {
            let terms: Vec<SpeedTerm> = steps
                .iter()
                .map(|&(a, pr)| {
                    let other = (1.0 - phi)
                        * (pr.other_per_share.0 + c.wear_rate_driven_factor * pr.other_per_share.1);
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
                got.polygon_order_wear, want.polygon_order_wear,
                "{here} sigma {spread_kmh}"
            );
            let (a, b) = (got.distance_to_visible_km, want.distance_to_visible_km);
            assert!(
                a == b || (a - b).abs() <= 1e-9 * b,
                "{here} sigma {spread_kmh}: {a} {b}"
            );
            let (x, y) = (got.peak_share_of_visible, want.peak_share_of_visible);
            assert!((x - y).abs() <= 1e-9, "{here} sigma {spread_kmh}: {x} {y}");
            let unbounded = answer_saturated_per_step(&steps, &c, &p, f64::INFINITY);
            assert!(
                a >= unbounded.distance_to_visible_km,
                "{here} sigma {spread_kmh}"
            );
            let level = g.saturated_answer(&c);
            let plain = g.life_answer(&c);
            if plain.distance_to_visible_km.is_finite() {
                // The tread's life is the plain answer's, the legs' sum of one even wear.
                let life_km = plain.tread_life_km;
                let (x, y) = (got.tread_life_km, life_km);
                assert!((x - y).abs() <= 1e-9 * y, "{here} sigma {spread_kmh}");
                let mut got = got;
                got.tread_life_km = life_km;
                assert_eq!(level, got, "{here} sigma {spread_kmh}");
                if a > 1.2 * plain.distance_to_visible_km {
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
    let cal = calibrate_wear(&base, Variant::SlidingShare, &ClassifierOptions::default()).unwrap();
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
            polygons += usize::from(b.distance_to_visible_km.is_finite());
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
