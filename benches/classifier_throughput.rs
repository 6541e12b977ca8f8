//! Classifier throughput on the shipped default study (`studies/default.toml`, read at run
//! time through `polywear::study::DEFAULT_STUDY`, so the figures follow the study and the model
//! defaults): samples/s, and the mean and 95th-percentile RHS evaluations per wheel, class and
//! method. RHS counts are deterministic; samples/s depends on the machine and its load.
//!
//! Run: `cargo bench --bench classifier_throughput -- [SAMPLES=20000] [SEED=2014] [--peers]`.
//! `--peers` also runs the Python peers of `benches/peers` (SciPy solve_ivp and numba) on the
//! first samples of the same study and prints their rates and RHS counts in the same table
//! (needs python3 with scipy, numba, pandas; `benches/peers/compare.sh` installs them).

use std::collections::BTreeMap;
use std::time::Instant;

use rayon::prelude::*;

use polywear::classify::{Class, ClassifierOptions};
use polywear::explore::evaluate_sample;
use polywear::study::{Study, DEFAULT_STUDY};

fn percentile(sorted: &[u64], q: f64) -> u64 {
    if sorted.is_empty() {
        return 0;
    }
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--bench"))
        .collect();
    let peers = args.iter().any(|a| a == "--peers");
    let nums: Vec<u64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let samples = nums.first().copied().unwrap_or(20_000);
    let study = Study::parse(DEFAULT_STUDY).expect("the shipped default study parses");
    let seed = nums.get(1).copied().unwrap_or(study.seed);
    let sampler = study.sampler(seed, samples);
    let opts = ClassifierOptions::default();
    let threads = rayon::current_num_threads();

    let t0 = Instant::now();
    let rows: Vec<_> = (0..samples)
        .into_par_iter()
        .map(|i| evaluate_sample(&study, &sampler, i, &opts, None))
        .collect();
    let secs = t0.elapsed().as_secs_f64();

    // (variant, wheel, class, method) -> RHS evaluations of each wheel.
    let mut groups: BTreeMap<(String, String, String, String), Vec<u64>> = BTreeMap::new();
    let mut per_sample = 0u64;
    let mut per_wheel: Vec<u64> = Vec::new();
    for r in rows.iter().flat_map(|s| &s.records) {
        per_sample += r.rhs_evals;
        if r.class != Class::NoTraction {
            per_wheel.push(r.rhs_evals);
        }
        for wheel in [r.wheel.to_string(), "both".to_string()] {
            groups
                .entry((
                    r.variant.to_string(),
                    wheel,
                    r.class.to_string(),
                    r.method.to_string(),
                ))
                .or_default()
                .push(r.rhs_evals);
        }
    }
    println!(
        "polywear classifier, study `{}` seed {seed}: {samples} samples on {threads} threads in {secs:.2} s = {:.0} samples/s; {:.0} RHS evaluations per sample",
        study.name,
        samples as f64 / secs,
        per_sample as f64 / samples as f64
    );
    println!(
        "\n{:<10} {:<9} {:<12} {:<9} {:>8} {:>10} {:>8} {:>8}",
        "variant", "wheel", "class", "method", "wheels", "mean RHS", "p95 RHS", "max RHS"
    );
    for ((variant, wheel, class, method), mut evals) in groups {
        evals.sort_unstable();
        let mean = evals.iter().sum::<u64>() as f64 / evals.len() as f64;
        println!(
            "{variant:<10} {wheel:<9} {class:<12} {method:<9} {:>8} {mean:>10.0} {:>8} {:>8}",
            evals.len(),
            percentile(&evals, 0.95),
            evals.last().copied().unwrap_or(0)
        );
    }

    if peers {
        per_wheel.sort_unstable();
        let mean = per_wheel.iter().sum::<u64>() as f64 / per_wheel.len().max(1) as f64;
        let rhs = format!("{mean:.0} (p95 {})", percentile(&per_wheel, 0.95));
        run_peers(
            samples.min(2000),
            seed,
            samples as f64 / secs,
            threads,
            &rhs,
        );
    }
}

/// Runs `benches/peers/bench_peers.py` on the first `n` samples of the same study and prints
/// its table beside polywear's rate.
fn run_peers(n: u64, seed: u64, poly_rate: f64, threads: usize, poly_rhs: &str) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let bin = dir.join("target/release/polywear");
    println!("\npeers on the first {n} samples (seed {seed}) of the same study:");
    println!(
        "{:<28} {:>9} {:>7} {:>12} {:>16}",
        "tool", "samples", "cores", "samples/s", "mean RHS/wheel (every wheel with an ODE)"
    );
    println!(
        "{:<28} {:>9} {:>7} {:>12.0} {:>16}",
        "polywear (this run)", "all", threads, poly_rate, poly_rhs
    );
    let status = std::process::Command::new("python3")
        .arg(dir.join("benches/peers/bench_peers.py"))
        .arg(&bin)
        .arg(n.to_string())
        .arg(seed.to_string())
        .status();
    match status {
        Ok(s) if s.success() => {}
        other => eprintln!(
            "peers not run ({other:?}); install them with `python3 -m pip install scipy numba pandas pyarrow` and build `cargo build --release`"
        ),
    }
}
