//! What the wear answer over the tread's life (MODEL.md#the-estimator-over-the-treads-life)
//! costs explore, side by side on the same samples of the shipped default study: samples/s of
//! classifying both wheels (A), with the plain answer over the tread's life (B: each speed's
//! print not saturated, the walk the shipped answer screens its orders with), and with the
//! shipped answer (C: each speed's print saturated), the three interleaved twice on all
//! threads. Explore's bar for its wear stage is half of A. A study file given after the sample
//! count replaces the default study (`studies/excess_toe.toml`: one where polygons are common,
//! and C builds its legs).
//!
//! Run: `cargo bench --bench wear_life -- [SAMPLES=4000] [STUDY.toml]`.

use std::time::Instant;

use rayon::prelude::*;

use polywear::classify::budget::Meter;
use polywear::classify::ClassifierOptions;
use polywear::evaluate::{self, PointProblem, WearStage};
use polywear::study::{Study, DEFAULT_STUDY};
use polywear_core::wear::{FittedConstants, LifeAnswer, WheelGrowth};

const LEVELS: u8 = 3;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let samples: u64 = args
        .iter()
        .filter_map(|a| a.parse().ok())
        .next()
        .unwrap_or(4_000);
    let study_file = args.iter().find(|a| a.ends_with(".toml"));
    let study = match study_file {
        Some(path) => {
            let text = std::fs::read_to_string(path).expect("the study file reads");
            Study::parse(&text).expect("the study file parses")
        }
        None => Study::parse(DEFAULT_STUDY).expect("the shipped default study parses"),
    };
    let study_name = study_file.map_or("default study", |p| p.as_str());
    let sampler = study.sampler(study.seed, samples);
    let opts = ClassifierOptions::default();
    let variants = [study.variants[0]];
    let stage = WearStage::for_run(
        &study.base,
        variants[0],
        study.wear.unwrap_or_default(),
        &opts,
    )
    .expect("the reference point calibrates");
    // 0: classify; 1: and the plain answer over the tread's life; 2: and the shipped
    // (saturated) one instead. Returns how many wheels saw a visible polygon within 60,000 km
    // (before the tire is worn out), plain and saturated.
    let run = |level: u8| -> (usize, usize) {
        (0..samples)
            .into_par_iter()
            .map(|i| {
                let (p, _) = sampler.sample(i);
                let point = evaluate::solve(&PointProblem::new(p, &variants, &opts));
                let mut seen = (0, 0);
                if level == 0 {
                    return seen;
                }
                let c = FittedConstants::of(&p);
                for w in &point.wheels {
                    let Ok(g) = WheelGrowth::new(&stage.problem(&p, w), &Meter::new(opts.budget))
                    else {
                        continue;
                    };
                    // Visible within 60,000 km and before the tire is worn out, as the analysis
                    // counts.
                    let visible =
                        |a: LifeAnswer| usize::from(a.visible_within(60_000.0) == Some(true));
                    if level == 1 {
                        seen.0 += visible(g.life_answer(&c));
                    } else {
                        seen.1 += visible(g.saturated_answer(&c));
                    }
                }
                seen
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    };
    let mut rates = [0.0_f64; LEVELS as usize];
    let mut seen = (0, 0);
    for _round in 0..2 {
        for level in 0..LEVELS {
            let t0 = Instant::now();
            let s = run(level);
            let rate = samples as f64 / t0.elapsed().as_secs_f64();
            rates[level as usize] = rates[level as usize].max(rate);
            match level {
                1 => seen.0 = s.0,
                2 => seen.1 = s.1,
                _ => {}
            }
        }
    }
    println!(
        "{study_name}, {samples} samples on {} threads (best of 2): classify {:.0} samples/s; with the plain answer over the tread's life {:.0} ({:.0}% kept); with the shipped (saturated) answer instead {:.0} ({:.0}% kept)",
        rayon::current_num_threads(),
        rates[0],
        rates[1],
        100.0 * rates[1] / rates[0],
        rates[2],
        100.0 * rates[2] / rates[0]
    );
    println!(
        "  wheels with a visible polygon within 60,000 km, before the tire is worn out: plain {}, saturated (shipped) {} (of {})",
        seen.0,
        seen.1,
        2 * samples
    );
}
