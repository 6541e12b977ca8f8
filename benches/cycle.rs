//! `polywear cycle`'s classification of the 1,800-step WLTC class 3b with both wheels
//! (`data/cycles/wltc_class3b.csv`, default parameters, `sliding_share`): wall time on one
//! thread and on all cores, best and median of several repeats, with the RHS evaluations spent
//! (deterministic) and the classes found; beside it, the same steps classified independently
//! (no neighbouring-step hint, no reuse of repeated steps: as `polywear classify` does), run
//! alternately with it so that both see the same machine load. Wall times depend on the machine
//! and its load.
//!
//! Run: `cargo bench --bench cycle -- [REPEATS=7]`.

use std::time::Instant;

use rayon::prelude::*;

use polywear::classify::{classify_point, ClassifierOptions};
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear_study::cycle::{classify_cycle, DriveCycle};

fn main() {
    let repeats: usize = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .find_map(|a| a.parse().ok())
        .unwrap_or(7);
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/cycles/wltc_class3b.csv");
    let cycle = DriveCycle::read(&path).expect("the shipped WLTC reads");
    let base = Params::default();
    let opts = ClassifierOptions::default();
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "WLTC class 3b: {} steps x 2 wheels, variant sliding_share, {repeats} repeats",
        cycle.len()
    );
    for threads in [1, all] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let (mut times, mut plain_times) = (Vec::new(), Vec::new());
        let mut steps = Vec::new();
        let mut plain_rhs = 0;
        for _ in 0..repeats {
            let t = Instant::now();
            steps = pool
                .install(|| classify_cycle(&cycle, &base, Variant::SlidingShare, &opts, None))
                .steps;
            times.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            plain_rhs = pool.install(|| independent_steps(&cycle, &base, &opts));
            plain_times.push(t.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        plain_times.sort_by(f64::total_cmp);
        let rhs: u64 = steps
            .iter()
            .flat_map(|s| s.iter())
            .map(|w| w.record.rhs_evals)
            .sum();
        let vib = |w: usize| steps.iter().filter(|s| s[w].vibrates()).count();
        println!(
            "  {threads} thread(s): cycle best {:.3} s, median {:.3} s, {rhs} RHS evaluations; independent steps best {:.3} s, median {:.3} s, {plain_rhs} RHS evaluations; vibrating steps: follower {}, driving {}",
            times[0],
            times[times.len() / 2],
            plain_times[0],
            plain_times[plain_times.len() / 2],
            vib(0),
            vib(1)
        );
    }
}

/// Every moving step and wheel classified on its own; returns the RHS evaluations spent.
fn independent_steps(cycle: &DriveCycle, base: &Params, opts: &ClassifierOptions) -> u64 {
    (0..cycle.len())
        .into_par_iter()
        .filter(|&i| !cycle.standstill(i))
        .map(|i| {
            let p = cycle.step_params(base, i);
            Wheel::BOTH
                .iter()
                .map(|&w| {
                    classify_point(&p, w, Variant::SlidingShare, opts)
                        .1
                        .rhs_evals
                })
                .sum::<u64>()
        })
        .sum()
}
