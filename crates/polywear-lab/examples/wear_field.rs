//! The wear stage's field calibration (MODEL.md#calibration-to-the-field) and the measured error
//! of its speed-spread approximation (MODEL.md#the-speed-spread), reproducibly.
//!
//! ```sh
//! cargo run --release -p polywear-lab --example wear_field -- fit [SAMPLES]      # the (φ_s, σ_V) table
//! cargo run --release -p polywear-lab --example wear_field -- check [SAMPLES]    # the shipped constants
//! cargo run --release -p polywear-lab --example wear_field -- spread-error       # spread mean vs per-speed loops
//! ```
//!
//! These are the new tire's figures, a diagnostic: the shipped answer and its calibration are
//! over the tread's life (`cargo run --release --example calibrate_band`).
//!
//! `fit` evaluates each wheel's loop once (its response to ε does not depend on φ_s or σ_V) and
//! then every (φ_s, σ_V) of the grid: for the highway follower with excessive toe-in (0.40,
//! 0.45, 0.50° at 100, 110, 120 km/h, nominal tire, default load and pressure) the median
//! distance to a visible polygon, which the field puts at 25,000–40,000 km; over the default
//! study's samples (both wheels) the median distance, which must exceed 60,000 km, and the share
//! of 10–20 sides among the wheels with a visible polygon within 60,000 km.

use polywear::classify::ClassifierOptions;
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear::study::{Study, DEFAULT_STUDY};
use polywear_core::wear::estimator::{distance_to_visible_km, orders_around};
use polywear_core::wear::{Calibration, WearSettings, WheelGrowth};
use rayon::prelude::*;

/// One wheel's loop, or None where it has no figures.
fn growth(p: &Params, wheel: Wheel, cal: &Calibration) -> Option<WheelGrowth> {
    let stage = polywear::evaluate::WearStage {
        settings: WearSettings::default(),
        calibration: *cal,
    };
    polywear_study::calibration_band::fit::wheel_growth(p, wheel, &stage)
}

/// (s* \[km\], dominant order) of a wheel's loop at φ_s = `share`, σ_V = `spread_kmh`.
fn distance(g: &WheelGrowth, p: &Params, share: f64, spread_kmh: f64) -> (f64, u32) {
    let top = orders_around(g.nu())
        .map(|n| g.order_with(n, share, spread_kmh / 3.6))
        .max_by(|a, b| {
            a.growth_rate_per_1000km
                .total_cmp(&b.growth_rate_per_1000km)
        })
        .expect("at least one order");
    (
        distance_to_visible_km(p, top.growth_rate_per_1000km),
        top.order,
    )
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    if x.is_empty() {
        f64::NAN
    } else {
        x[x.len() / 2]
    }
}

/// A wheel of a sample with its loop.
type Loop = (Params, Wheel, WheelGrowth);

/// The highway followers with excessive toe-in, and the default study's wheels, with their loops.
fn populations(base: &Params, samples: u64) -> (Vec<Loop>, Vec<Loop>) {
    let cal = polywear::evaluate::calibrate_wear(
        base,
        Variant::SlidingShare,
        &ClassifierOptions::default(),
    )
    .expect("reference point");
    let highway: Vec<Loop> = [0.40, 0.45, 0.50]
        .iter()
        .flat_map(|&toe| [100.0, 110.0, 120.0].map(|v| (toe, v)))
        .filter_map(|(toe_deg, speed_kmh)| {
            let p = Params {
                toe_deg,
                speed_kmh,
                ..*base
            };
            growth(&p, Wheel::Follower, &cal).map(|g| (p, Wheel::Follower, g))
        })
        .collect();
    let study = Study::parse_with_base(DEFAULT_STUDY, *base).expect("default study");
    let sampler = study.sampler(study.seed, samples);
    let fleet: Vec<Loop> = (0..samples)
        .into_par_iter()
        .flat_map_iter(|i| {
            let (p, _) = sampler.sample(i);
            Wheel::BOTH
                .iter()
                .filter_map(move |&w| growth(&p, w, &cal).map(|g| (p, w, g)))
                .collect::<Vec<_>>()
        })
        .collect();
    (highway, fleet)
}

/// One row of the fit: highway median s*, fleet median s*, share visible within 60,000 km, share
/// of those with 10–20 sides.
fn row(
    highway: &[Loop],
    fleet: &[Loop],
    share: f64,
    spread: f64,
) -> (f64, f64, f64, f64, f64, f64) {
    let hw: Vec<f64> = highway
        .iter()
        .map(|(p, _, g)| distance(g, p, share, spread).0)
        .collect();
    let fl: Vec<(f64, u32)> = fleet
        .par_iter()
        .map(|(p, _, g)| distance(g, p, share, spread))
        .collect();
    let visible: Vec<&(f64, u32)> = fl.iter().filter(|(s, _)| *s <= 60_000.0).collect();
    let sides = visible
        .iter()
        .filter(|(_, n)| (10..=20).contains(n))
        .count();
    let (lo, hi) = (
        hw.iter().copied().fold(f64::INFINITY, f64::min),
        hw.iter().copied().fold(0.0, f64::max),
    );
    (
        median(hw),
        lo,
        hi,
        median(fl.iter().map(|x| x.0).collect()),
        visible.len() as f64 / fl.len() as f64,
        sides as f64 / visible.len().max(1) as f64,
    )
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().map(String::as_str).unwrap_or("check");
    let samples: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(2000);
    match mode {
        "fit" => {
            let (highway, fleet) = populations(&Params::default(), samples);
            println!(
                "{} highway followers, {} default-study wheels ({samples} samples)",
                highway.len(),
                fleet.len()
            );
            println!("phi_s sigma_V | highway s* median [min, max] km | fleet s* median km | visible <= 60k | 10-20 sides");
            let shares: Vec<f64> = match args.get(2).map(String::as_str) {
                Some("fine") => (8..=20).map(|k| k as f64 / 100.0).collect(),
                _ => vec![1.0, 0.5, 0.3, 0.2, 0.15, 0.1, 0.07, 0.05],
            };
            let spreads: Vec<f64> = match args.get(2).map(String::as_str) {
                Some("fine") => vec![3.0, 4.0, 5.0, 6.0, 7.0],
                _ => vec![0.0, 1.0, 2.0, 3.0, 5.0, 8.0],
            };
            for &share in &shares {
                for &spread in &spreads {
                    let (m, lo, hi, f, vis, sides) = row(&highway, &fleet, share, spread);
                    println!("{share:5} {spread:7} | {m:9.0} [{lo:.0}, {hi:.0}] | {f:9.0} | {:5.1}% | {:5.1}%", 100.0 * vis, 100.0 * sides);
                }
            }
        }
        "check" => {
            let base = Params::default();
            let (highway, fleet) = populations(&base, samples);
            for wheel in Wheel::BOTH {
                let d: Vec<(f64, u32)> = fleet
                    .iter()
                    .filter(|(_, w, _)| *w == wheel)
                    .map(|(p, _, g)| {
                        distance(g, p, base.wear_share_straight, base.speed_spread_kmh)
                    })
                    .collect();
                let visible = d.iter().filter(|x| x.0 <= 60_000.0).count();
                println!(
                    "{wheel}: median s* {:.0} km, visible within 40,000 km {:.1}%, within 60,000 km {:.1}%",
                    median(d.iter().map(|x| x.0).collect()),
                    100.0 * d.iter().filter(|x| x.0 <= 40_000.0).count() as f64 / d.len() as f64,
                    100.0 * visible as f64 / d.len() as f64
                );
            }
            let (m, lo, hi, f, vis, sides) = row(
                &highway,
                &fleet,
                base.wear_share_straight,
                base.speed_spread_kmh,
            );
            println!(
                "shipped phi_s = {}, sigma_V = {} km/h: highway follower s* median {m:.0} km [{lo:.0}, {hi:.0}]; default study ({} wheels) median {f:.0} km, visible within 60,000 km {:.1}%, of which 10-20 sides {:.1}%",
                base.wear_share_straight,
                base.speed_spread_kmh,
                fleet.len(),
                100.0 * vis,
                100.0 * sides
            );
        }
        "spread-error" => spread_error(),
        other => {
            eprintln!("unknown mode `{other}`; accepted: fit, check, spread-error");
        }
    }
}

/// The estimator's spread mean (the sample's linearisation kept, ω moved with the speed) against
/// the mean of the loops recomputed at 801 speeds across ±4σ (each speed classified again, with
/// its own class, cycle and linearisation), for the dominant orders of a stable and a vibrating
/// follower.
fn spread_error() {
    let base = Params {
        wear_share_straight: 1.0,
        ..Params::default()
    };
    let cal = polywear::evaluate::calibrate_wear(
        &base,
        Variant::SlidingShare,
        &ClassifierOptions::default(),
    )
    .expect("reference point");
    println!("point | sigma_V | order | estimator | per-speed mean | difference");
    for (speed, toe) in [(70.0, 0.3), (100.0, 0.3), (100.0, 0.45), (130.0, 0.3)] {
        let p0 = Params {
            speed_kmh: speed,
            toe_deg: toe,
            ..base
        };
        let g0 = growth(&p0, Wheel::Follower, &cal).expect("loop");
        let _ = &g0;
        for spread in [2.0, 5.0] {
            let nodes = 801;
            let sd = spread / 3.6;
            let orders: Vec<u32> = orders_around(g0.nu()).collect();
            let mut mean = vec![0.0; orders.len()];
            let mut weight = 0.0;
            for k in 0..nodes {
                let x = -4.0 + 8.0 * k as f64 / (nodes - 1) as f64;
                let w = (-0.5 * x * x).exp();
                let p = Params {
                    speed_kmh: speed + x * spread,
                    ..p0
                };
                let Some(g) = growth(&p, Wheel::Follower, &cal) else {
                    continue;
                };
                for (j, &n) in orders.iter().enumerate() {
                    mean[j] += w * g.order_with(n, 1.0, 0.0).growth_rate_per_1000km;
                }
                weight += w;
            }
            for (j, &n) in orders.iter().enumerate() {
                let est = g0.order_with(n, 1.0, sd).growth_rate_per_1000km;
                let brute = mean[j] / weight;
                println!(
                    "{speed} km/h {toe} deg | {spread} | {n} | {est:.4} | {brute:.4} | {:+.4}",
                    est - brute
                );
            }
        }
    }
}
