//! The answer over the tread's life with the zone's power modulation saturated, against the
//! plain one (MODEL.md#the-forced-response-saturates), at the bound M_MAX (1.0528) and φ_s:
//!
//! - `cargo run --release -p polywear-lab --example saturation_probe -- M_MAX PHI_S`: steady points at 0.45°,
//!   60, 93 and 110 km/h, no spread;
//! - `... -- M_MAX PHI_S CYCLE.csv TOE`: a drive cycle's steps, each on its own and summed by
//!   speed bins of 0.1, 0.25, 0.5 and 1 km/h (as `cycle` gives it);
//! - `... -- M_MAX PHI_S spread V SIGMA K [TOE]`: a cruising spread as K equal-distance legs at
//!   its quantiles, each with its own model, as the long-term loop drives it;
//! - `... -- M_MAX PHI_S rows CSV SIGMA K`: every follower row of a CSV (explore's columns) so.
//!
//! Each prints the summed profile's plain answer, the one saturated on the sum, and the one
//! saturated per step (the reading MODEL.md#the-forced-response-saturates measures).
use polywear::classify::ClassifierOptions;
use polywear::evaluate::{solve_wheel, WearStage};
use polywear::long_term::leg_profiles;
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear_core::wear::estimator::answer_saturated_per_step;
use polywear_core::wear::{FittedConstants, LifeProfile, WearSettings};
use polywear_study::cycle::wear::step_life;
use polywear_study::cycle::DriveCycle;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let m_max: f64 = a.get(1).map_or(1.0, |s| s.parse().unwrap());
    let phi: f64 = a.get(2).map_or(1.0, |s| s.parse().unwrap());
    let opts = ClassifierOptions::default();
    let report = |here: &str, profile: &LifeProfile, p: &Params| {
        let c = FittedConstants::of(p);
        let plain = profile.answer(&c, p);
        let sat = profile.answer_saturated(&c, p, m_max);
        println!(
            "{here}: plain order {} at {:.0} km; saturated (m_max {m_max}) order {} at {:.0} km",
            plain.polygon_order_wear,
            plain.distance_to_visible_km,
            sat.polygon_order_wear,
            sat.distance_to_visible_km
        );
    };
    if a.get(3).map(String::as_str) == Some("rows") {
        rows(
            &a[4],
            a[5].parse().unwrap(),
            a[6].parse().unwrap(),
            m_max,
            phi,
        );
        return;
    }
    if a.get(3).map(String::as_str) == Some("spread") {
        // spread SPEED SIGMA K
        let speed: f64 = a[4].parse().unwrap();
        let sigma: f64 = a[5].parse().unwrap();
        let k: usize = a[6].parse().unwrap();
        let toe: f64 = a.get(7).map_or(0.45, |s| s.parse().unwrap());
        let base = Params {
            speed_kmh: speed,
            toe_deg: toe,
            wear_share_straight: phi,
            speed_spread_kmh: 0.0,
            ..Params::default()
        };
        let stage =
            WearStage::for_run(&base, Variant::SlidingShare, WearSettings::default(), &opts)
                .unwrap();
        let legs = polywear::long_term::wheel_loop::cruise_legs(speed, sigma, k);
        for wheel in Wheel::BOTH {
            let steps = leg_profiles(&base, Variant::SlidingShare, wheel, &legs, &stage, &opts);
            let (_, like) = &steps[0];
            let mut mean = LifeProfile::zero(like.max_order, like.intervals, like.usable_m);
            for (share, life) in &steps {
                mean.add(life, *share);
            }
            report(
                &format!("{speed} km/h {toe}° sigma {sigma} K {k} {wheel}"),
                &mean,
                &base,
            );
            per_step(&steps, &base, m_max);
        }
        return;
    }
    if let Some(path) = a.get(3) {
        let toe: f64 = a.get(4).map_or(0.45, |s| s.parse().unwrap());
        let base = Params {
            toe_deg: toe,
            wear_share_straight: phi,
            ..Params::default()
        };
        let stage =
            WearStage::for_run(&base, Variant::SlidingShare, WearSettings::default(), &opts)
                .unwrap();
        let cycle = DriveCycle::read(std::path::Path::new(path)).unwrap();
        let km = cycle.step_km();
        for wheel in Wheel::BOTH {
            let mut sum: Option<LifeProfile> = None;
            let mut total = 0.0;
            let mut steps: Vec<(f64, LifeProfile)> = Vec::new();
            let mut speeds: Vec<f64> = Vec::new();
            for (i, &d) in km.iter().enumerate() {
                if cycle.standstill(i) || d <= 0.0 {
                    continue;
                }
                let p = cycle.step_params(&base, i);
                let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
                let Some(life) = step_life(&p, &w, &stage, &opts) else {
                    continue;
                };
                sum.get_or_insert_with(|| {
                    LifeProfile::zero(life.max_order, life.intervals, life.usable_m)
                })
                .add(&life, d);
                total += d;
                speeds.push(p.speed_kmh);
                steps.push((d, life));
            }
            let mut mean = sum.unwrap();
            mean.scale(1.0 / total);
            report(&format!("{path} {toe}° {wheel}"), &mean, &base);
            per_step(&steps, &base, m_max);
            for width in [0.1, 0.25, 0.5, 1.0] {
                let binned = by_speed(&steps, &speeds, width);
                print!("  bins of {width} km/h ({}):", binned.len());
                per_step(&binned, &base, m_max);
            }
        }
        return;
    }
    for speed_kmh in [60.0, 93.0, 110.0] {
        let p = Params {
            speed_kmh,
            toe_deg: 0.45,
            wear_share_straight: phi,
            speed_spread_kmh: 0.0,
            ..Params::default()
        };
        let stage =
            WearStage::for_run(&p, Variant::SlidingShare, WearSettings::default(), &opts).unwrap();
        for wheel in Wheel::BOTH {
            let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
            let life = step_life(&p, &w, &stage, &opts).unwrap();
            report(&format!("{speed_kmh} km/h 0.45° {wheel}"), &life, &p);
            let n = if speed_kmh < 70.0 {
                32
            } else if speed_kmh < 100.0 {
                21
            } else {
                18
            };
            println!(
                "  2 w' |H_w| of order {n} at phi_s {phi}: {:.3} mm/1000 km",
                phi * life.full_print_per_share[n - 1] * 1e9
            );
        }
    }
}

/// The steps summed by speed bin of `width` km/h: each bin's distance and mean profile.
fn by_speed(steps: &[(f64, LifeProfile)], speeds: &[f64], width: f64) -> Vec<(f64, LifeProfile)> {
    let mut bins: std::collections::BTreeMap<i64, (f64, LifeProfile)> = Default::default();
    for ((d, life), v) in steps.iter().zip(speeds) {
        let bin = bins.entry((v / width).round() as i64).or_insert_with(|| {
            (
                0.0,
                LifeProfile::zero(life.max_order, life.intervals, life.usable_m),
            )
        });
        bin.0 += d;
        bin.1.add(life, *d);
    }
    bins.into_values()
        .map(|(d, mut sum)| {
            sum.scale(1.0 / d);
            (d, sum)
        })
        .collect()
}

/// Each step saturated on its own (MODEL.md#the-forced-response-saturates).
fn per_step(steps: &[(f64, LifeProfile)], p: &Params, m_max: f64) {
    let c = FittedConstants::of(p);
    let refs: Vec<(f64, &LifeProfile)> = steps.iter().map(|(a, pr)| (*a, pr)).collect();
    let exact = answer_saturated_per_step(&refs, &c, p, m_max);
    println!(
        "  saturated per step: order {} at {:.0} km",
        exact.polygon_order_wear, exact.distance_to_visible_km
    );
}

/// rows CSV SIGMA K: each row's follower (sample_id, tread_height, rho, g_mod, c_brush,
/// speed_kmh, toe_deg, load_n, pressure_kpa first, then anything) on K quantile speeds of its
/// spread, each leg its own model: the summed profile's answer and the per-step saturated one,
/// one CSV line per row on stdout.
fn rows(path: &str, sigma: f64, k: usize, m_max: f64, phi: f64) {
    use rayon::prelude::*;
    let opts = ClassifierOptions::default();
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let names = [
        "sample_id",
        "tread_height",
        "rho",
        "g_mod",
        "c_brush",
        "speed_kmh",
        "toe_deg",
        "load_n",
        "pressure_kpa",
        "distance_to_visible_km",
    ];
    let at: Vec<usize> = names.iter().map(|n| col(n)).collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            at.iter().map(|&i| f[i].parse().unwrap()).collect()
        })
        .collect();
    let nominal = Params {
        wear_share_straight: phi,
        ..Params::default()
    };
    let stage = WearStage::for_run(
        &nominal,
        Variant::SlidingShare,
        WearSettings::default(),
        &opts,
    )
    .unwrap();
    println!("sample_id,explore_km,legs_order,legs_km,saturated_order,saturated_km");
    let out: Vec<String> = rows
        .par_iter()
        .map(|r| {
            let base = Params {
                tread_height: r[1],
                rho: r[2],
                g_mod: r[3],
                c_brush: r[4],
                speed_kmh: r[5],
                toe_deg: r[6],
                load_n: r[7],
                pressure_kpa: r[8],
                speed_spread_kmh: 0.0,
                ..nominal
            };
            let legs = polywear::long_term::wheel_loop::cruise_legs(base.speed_kmh, sigma, k);
            let steps = leg_profiles(
                &base,
                Variant::SlidingShare,
                Wheel::Follower,
                &legs,
                &stage,
                &opts,
            );
            let refs: Vec<(f64, &LifeProfile)> = steps.iter().map(|(a, pr)| (*a, pr)).collect();
            let c = FittedConstants::of(&base);
            let plain = answer_saturated_per_step(&refs, &c, &base, f64::INFINITY);
            let sat = answer_saturated_per_step(&refs, &c, &base, m_max);
            format!(
                "{},{},{},{},{},{}",
                r[0],
                r[9],
                plain.polygon_order_wear,
                plain.distance_to_visible_km,
                sat.polygon_order_wear,
                sat.distance_to_visible_km
            )
        })
        .collect();
    for line in out {
        println!("{line}");
    }
}
