//! The wear estimator's cost beside the classifier's, side by side on the same samples of the
//! shipped default study: samples/s of classifying both wheels without and with the estimator
//! (MODEL.md#the-per-sample-estimator), and the RHS evaluations the estimator adds per wheel by
//! class (counted by the classifier's meter), both through explore's evaluation of a sample
//! (`explore::evaluate_sample`). Explore also writes the rows, which this leaves out, so the
//! share kept here is a lower bound of explore's.
//!
//! Run: `cargo bench --bench wear -- [SAMPLES=20000]`.

use std::time::Instant;

use rayon::prelude::*;

use polywear::classify::{Class, ClassifierOptions};
use polywear::evaluate::WearStage;
use polywear::explore::evaluate_sample;
use polywear::study::{Study, DEFAULT_STUDY};

fn main() {
    let samples: u64 = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .next()
        .unwrap_or(20_000);
    let study = Study::parse(DEFAULT_STUDY).expect("the shipped default study parses");
    let sampler = study.sampler(study.seed, samples);
    let opts = ClassifierOptions::default();
    let stage = WearStage::for_run(
        &study.base,
        study.variants[0],
        study.wear.unwrap_or_default(),
        &opts,
    )
    .expect("the reference point calibrates");
    // Per sample and wheel: (class, RHS evaluations of the wear stage), through explore's own
    // evaluation of a sample.
    let run = |wear: bool| -> Vec<Vec<(Class, u64)>> {
        (0..samples)
            .into_par_iter()
            .map(|i| {
                let rows = evaluate_sample(&study, &sampler, i, &opts, wear.then_some(&stage));
                rows.records
                    .iter()
                    .map(|r| (r.class, r.wear.as_ref().map_or(0, |w| w.wear_rhs_evals)))
                    .collect()
            })
            .collect()
    };
    let mut rates = Vec::new();
    let mut last = Vec::new();
    // Interleaved, twice each, so that a change of load on a shared machine hits both.
    for round in 0..4 {
        let wear = round % 2 == 1;
        let t0 = Instant::now();
        let rows = run(wear);
        rates.push((wear, samples as f64 / t0.elapsed().as_secs_f64()));
        if wear {
            last = rows;
        }
    }
    let best = |w: bool| {
        rates
            .iter()
            .filter(|r| r.0 == w)
            .map(|r| r.1)
            .fold(0.0, f64::max)
    };
    let (without, with) = (best(false), best(true));
    println!(
        "default study, {samples} samples on {} threads (best of 2): classifier {without:.0} samples/s, with the wear estimator {with:.0} samples/s ({:.0}% kept)",
        rayon::current_num_threads(),
        100.0 * with / without
    );
    for class in [Class::Stable, Class::LimitCycle, Class::Bistable] {
        let mut evals: Vec<u64> = last
            .iter()
            .flatten()
            .filter(|(c, _)| *c == class)
            .map(|(_, e)| *e)
            .collect();
        if evals.is_empty() {
            continue;
        }
        evals.sort_unstable();
        println!(
            "  {class}: {} wheels, estimator RHS evaluations mean {:.0}, max {}",
            evals.len(),
            evals.iter().sum::<u64>() as f64 / evals.len() as f64,
            evals[evals.len() - 1]
        );
    }
}
