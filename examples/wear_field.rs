//! The wear stage's field calibration (MODEL.md#calibration-to-the-field) and the measured error
//! of its speed-spread approximation (MODEL.md#the-speed-spread), reproducibly.
//!
//! ```sh
//! cargo run --release --example wear_field -- fit [SAMPLES]      # the (φ_s, σ_V) table
//! cargo run --release --example wear_field -- check [SAMPLES]    # the shipped constants
//! cargo run --release --example wear_field -- spread-error       # spread mean vs per-speed loops
//! cargo run --release --example wear_field -- band [SAMPLES] [OUT] # the calibrated sets
//! cargo run --release --example wear_field -- band-life [SAMPLES] [PHIS] [SIGMAS] # the fit over the tread's life
//! cargo run --release --example wear_field -- exposure [SAMPLES] # which wheel, on both levels
//! ```
//!
//! `exposure` is issue 40's question on both levels of the model: over the default study's
//! samples at the shipped φ_s and k_d, with the speed spread at 2, 5 and 10 km/h, the share of
//! follower and driving wheels with a visible polygon within 25,000, 40,000 and 60,000 km
//! (before the tire is worn out), by the new tire's estimate (explore's answer) and over the
//! tread's life (the reading that agrees with the long-term loop), with the samples where only
//! one of the two wheels has one.
//!
//! `band` is the calibration with its uncertainty (MODEL.md#the-calibration-band): history
//! matching over φ_s, σ_V and k_d against the field facts' targets
//! (`polywear::calibration_band::fit`), every grid point printed with what it gives, the
//! accepted ones written as the file of calibrated sets (`data/calibration_band.toml` when OUT
//! is not given).
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
use polywear::wear::estimator::{distance_to_visible_km, orders_around};
use polywear::wear::{Calibration, WearSettings, WheelGrowth};
use rayon::prelude::*;

/// One wheel's loop, or None where it has no figures.
fn growth(p: &Params, wheel: Wheel, cal: &Calibration) -> Option<WheelGrowth> {
    let stage = polywear::evaluate::WearStage {
        settings: WearSettings::default(),
        calibration: *cal,
    };
    polywear::calibration_band::fit::wheel_growth(p, wheel, &stage)
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
        "band" => band(
            samples,
            args.get(2)
                .map_or("data/calibration_band.toml", String::as_str),
        ),
        "band-life" => band_life(samples, args.get(2), args.get(3)),
        "exposure" => exposure(samples),
        other => {
            eprintln!(
                "unknown mode `{other}`; accepted: fit, check, spread-error, band, band-life, exposure"
            )
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

/// The calibrated sets: the grid with each target's figure, then the accepted sets written.
/// The history matching of `band` on the level over the tread's life
/// (MODEL.md#the-estimator-over-the-treads-life), on a coarser grid (each grid point integrates
/// every wheel's orders over its life): what every grid point gives, and which are accepted.
fn band_life(samples: u64, shares: Option<&String>, spreads: Option<&String>) {
    use polywear::calibration_band::fit::{fit, FitOptions};
    use polywear::field_facts::FieldFacts;
    use polywear::wear::EstimateLevel;
    let facts = FieldFacts::shipped();
    let base = Params::default();
    let list = |given: Option<&String>, default: &str| -> Vec<f64> {
        given
            .map_or(default, String::as_str)
            .split(',')
            .map(|x| x.parse().expect("a comma-separated list of numbers"))
            .collect()
    };
    let opts = FitOptions {
        shares: list(shares, "0.08,0.12,0.16,0.2,0.25,0.3,0.4,0.5"),
        spreads_kmh: list(spreads, "2,5,10"),
        driven_factors: vec![1.75],
        level: EstimateLevel::TreadLife,
        ..FitOptions::shipped(samples, &facts)
    };
    let f = fit(&base, &facts, &opts).expect("fit");
    print_grid(&f, samples);
    println!(
        "{} of {} grid points accepted",
        f.accepted().count(),
        f.points.len()
    );
}

fn print_grid(f: &polywear::calibration_band::fit::Fit, samples: u64) {
    println!(
        "{} highway followers, {} default-study wheels ({samples} samples)",
        f.highway_wheels, f.fleet_wheels
    );
    println!("phi_s sigma_V k_d | highway median km | fleet median km | visible <= 60k | 10-20 sides | accepted");
    for g in &f.points {
        let c = g.constants;
        println!(
            "{:.3} {:4} {:4} | {:9.0} | {:9.0} | {:5.1}% | {:5.1}% | {}",
            c.wear_share_straight,
            c.speed_spread_kmh,
            c.wear_rate_driven_factor,
            g.highway_median_km,
            g.fleet_median_km,
            100.0 * g.fleet_visible_share,
            100.0 * g.sides_share,
            if g.accepted { "yes" } else { "" }
        );
    }
}

fn band(samples: u64, out: &str) {
    use polywear::calibration_band::fit::{fit, FitOptions};
    use polywear::field_facts::FieldFacts;
    use polywear::wear::FittedConstants;
    let facts = FieldFacts::shipped();
    let base = Params::default();
    let f = fit(&base, &facts, &FitOptions::shipped(samples, &facts)).expect("fit");
    print_grid(&f, samples);
    let generated_by = format!("cargo run --release --example wear_field -- band {samples}");
    let band = f
        .band(&FittedConstants::of(&base), &generated_by)
        .expect("the shipped defaults meet the targets");
    std::fs::write(out, band.to_toml()).expect("write the sets");
    println!("{} accepted sets written to {out}", band.sets.len());
}

/// Which wheel wears polygonal, on both levels (see the module's documentation).
fn exposure(samples: u64) {
    use polywear::wear::{FittedConstants, WearAnswer};
    let base = Params::default();
    let cal = polywear::evaluate::calibrate_wear(
        &base,
        Variant::SlidingShare,
        &ClassifierOptions::default(),
    )
    .expect("reference point");
    let study = Study::parse_with_base(DEFAULT_STUDY, base).expect("default study");
    let sampler = study.sampler(study.seed, samples);
    let pairs: Vec<(Params, Option<WheelGrowth>, Option<WheelGrowth>)> = (0..samples)
        .into_par_iter()
        .map(|i| {
            let (p, _) = sampler.sample(i);
            let follower = growth(&p, Wheel::Follower, &cal);
            let driving = growth(&p, Wheel::Driving, &cal);
            (p, follower, driving)
        })
        .collect();
    let distances = [25_000.0, 40_000.0, 60_000.0];
    println!(
        "default study, {samples} samples (both wheels), shipped phi_s and k_d; visible within X km before the tire is worn out"
    );
    println!("sigma_V level     X km | follower | driving | only follower | only driving");
    for spread_kmh in [2.0, 5.0, 10.0] {
        for life in [false, true] {
            let answer = |p: &Params, g: &Option<WheelGrowth>| -> Option<WearAnswer> {
                let c = FittedConstants {
                    speed_spread_kmh: spread_kmh,
                    ..FittedConstants::of(p)
                };
                g.as_ref().map(|g| {
                    if life {
                        g.life_answer(&c).answer
                    } else {
                        g.answer_with(&c)
                    }
                })
            };
            let answers: Vec<(Option<WearAnswer>, Option<WearAnswer>)> = pairs
                .par_iter()
                .map(|(p, f, d)| (answer(p, f), answer(p, d)))
                .collect();
            for x in distances {
                let seen =
                    |a: &Option<WearAnswer>| a.is_some_and(|a| a.visible_within(x) == Some(true));
                let (mut f, mut d, mut only_f, mut only_d) = (0, 0, 0, 0);
                for (a, b) in &answers {
                    let (sf, sd) = (seen(a), seen(b));
                    f += usize::from(sf);
                    d += usize::from(sd);
                    only_f += usize::from(sf && !sd);
                    only_d += usize::from(sd && !sf);
                }
                let pct = |k: usize| 100.0 * k as f64 / samples as f64;
                println!(
                    "{spread_kmh:4} {:9} {x:6.0} | {:7.3}% | {:6.3}% | {only_f:13} | {only_d:12}",
                    if life { "life" } else { "new tire" },
                    pct(f),
                    pct(d)
                );
            }
        }
    }
}
