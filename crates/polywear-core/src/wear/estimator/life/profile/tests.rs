//! The drive cycle's profile over the tread's life against brute force, and the saturated
//! print's rate and walk.

use super::*;
use crate::classify::budget::Meter;
use crate::classify::ClassifierOptions;
use crate::evaluate::{calibrate_wear, solve_wheel};
use crate::model::{Variant, Wheel};
use crate::wear::estimator::life::saturate::*;
use crate::wear::physics::calibration::Calibration;
use crate::wear::physics::law::PER_1000KM_PER_PER_M;
use crate::wear::{WearProblem, WearSettings};

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
        &WearProblem {
            params: *p,
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
    let other = profile.other_per_share.0 + c.wear_rate_driven_factor * profile.other_per_share.1;
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
                    got.polygon_order_wear, want.polygon_order_wear,
                    "{here}: {got:?} {want:?}"
                );
            }
            let (a, b) = (got.distance_to_visible_km, want.distance_to_visible_km);
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
                assert_eq!(got.polygon_order_wear, brute_order as f64, "{here}");
            }
            let life = want.tread_life_km;
            assert!((got.tread_life_km - life).abs() <= 1e-9 * life, "{here}");
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
                let order = g.order_with(n, 1.0, 0.0).growth_rate_per_1000km / PER_1000KM_PER_PER_M;
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
            let unbounded = profile.answer_saturated(&c, &p, f64::INFINITY);
            assert_eq!(
                plain.polygon_order_wear, unbounded.polygon_order_wear,
                "{here}"
            );
            let (a, b) = (
                plain.distance_to_visible_km,
                unbounded.distance_to_visible_km,
            );
            assert!(a == b || (a - b).abs() <= 1e-9 * a, "{here}: {a} {b}");
            let bounded = profile.answer_saturated(&c, &p, SLIDING_MODULATION_MAX);
            let d = bounded.distance_to_visible_km;
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
            );
            let (d, e) = (d, twice.distance_to_visible_km);
            assert!(
                e == d || (e - d).abs() <= 1e-9 * d,
                "{here}: {e} against {d}"
            );
        }
    }
}
