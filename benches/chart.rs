//! One stability chart (speed x toe-in, both wheels, default tire) next to a 200x200
//! brute-force eigenvalue grid of the same box, which only says stable or unstable per cell.
//! Run: `cargo bench --bench chart` (set RAYON_NUM_THREADS to pin the thread count).

use criterion::{criterion_group, criterion_main, Criterion};

use polywear::model::{Variant, Wheel};
use polywear::params::{ParamId, Params};
use polywear_core::continuation::trace::TraceOptions;
use polywear_core::continuation::ParamBox;
use polywear_study::chart::ChartRequest;

fn speed_toe() -> ChartRequest {
    ChartRequest::new(
        Params::default(),
        Variant::SlidingShare,
        Wheel::BOTH.to_vec(),
        (ParamId::SpeedKmh, ParamId::ToeDeg),
        ParamBox {
            lo: [60.0, 0.05],
            hi: [250.0, 0.6],
        },
    )
    .unwrap()
}

fn bench_chart(c: &mut Criterion) {
    let req = speed_toe();
    let opts = TraceOptions::default();
    let mut g = c.benchmark_group("chart_speed_toe");
    g.sample_size(10);
    g.bench_function("hopf_curves_both_wheels", |b| b.iter(|| req.trace(&opts)));
    g.bench_function("eigen_grid_200x200_both_wheels", |b| {
        b.iter(|| Wheel::BOTH.map(|w| req.stability_grid(w, 200, 200)))
    });
    g.finish();
}

criterion_group!(benches, bench_chart);
criterion_main!(benches);
