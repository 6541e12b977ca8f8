//! `polywear cycle`'s classification of the 1,800-step WLTC class 3b with both wheels
//! (`data/cycles/wltc_class3b.csv`, default parameters, `sliding_share`): wall time on one
//! thread and on all cores, best and median of several repeats, with the RHS evaluations spent
//! (deterministic) and the classes found. Wall times depend on the machine and its load.
//!
//! Run: `cargo bench --bench cycle -- [REPEATS=7]`.

use std::time::Instant;

use polywear::classify::ClassifierOptions;
use polywear::cycle::{classify_cycle, DriveCycle};
use polywear::model::Variant;
use polywear::params::Params;

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
        let mut times = Vec::new();
        let mut steps = Vec::new();
        for _ in 0..repeats {
            let t = Instant::now();
            steps = pool.install(|| classify_cycle(&cycle, &base, Variant::SlidingShare, &opts));
            times.push(t.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let rhs: u64 = steps
            .iter()
            .flat_map(|s| s.iter())
            .map(|w| w.record.rhs_evals)
            .sum();
        let vib = |w: usize| steps.iter().filter(|s| s[w].vibrates()).count();
        println!(
            "  {threads} thread(s): best {:.3} s, median {:.3} s; {rhs} RHS evaluations; vibrating steps: follower {}, driving {}",
            times[0],
            times[times.len() / 2],
            vib(0),
            vib(1)
        );
    }
}
