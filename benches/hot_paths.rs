//! Hot paths: one RHS evaluation, a 1-second trajectory, and the classifier per wheel at the
//! default point next to the brute-force reference.
//! Run: `cargo bench --bench hot_paths`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};

use polywear::classify::{classify, envelope, ClassifierOptions, Scales};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear::solver::{integrate, Control, SolverOptions};

fn default_model() -> WheelModel {
    WheelModel::build(&Params::default(), Wheel::Follower, Variant::Paper).unwrap()
}

fn bench_rhs(c: &mut Criterion) {
    let m = default_model();
    let eq = m.ode.equilibrium();
    let x = [eq[0] * 1.01, eq[1], 0.01];
    c.bench_function("rhs_eval", |b| b.iter(|| m.ode.rhs(black_box(&x))));
    c.bench_function("jacobian_eval", |b| {
        b.iter(|| m.ode.jacobian(black_box(&x)))
    });
}

fn bench_trajectory(c: &mut Criterion) {
    let m = default_model();
    let s = Scales::new(&m.ode);
    let opts = SolverOptions {
        rtol: 1e-9,
        atol: s.atol(1e-9),
        h_max: 1e-3,
        h0: None,
        max_steps: 10_000_000,
    };
    c.bench_function("trajectory_1s_rtol1e-9", |b| {
        b.iter(|| {
            integrate(
                &m.ode,
                0.0,
                [s.z_eq, s.y_eq + 1e-5, 0.0],
                1.0,
                &opts,
                |_| Control::Continue,
            )
            .unwrap()
        })
    });
}

fn bench_classify(c: &mut Criterion) {
    let p = Params::default();
    let m = default_model();
    let opts = ClassifierOptions::default();
    let rot = WheelModel::rotation_hz(&p);
    let mut g = c.benchmark_group("classify_default_point");
    g.bench_function("polywear_classifier", |b| {
        b.iter(|| classify(black_box(&m.ode), rot, &opts))
    });
    // The same classifier at a looser shooting tolerance, for the speed/accuracy trade-off.
    let loose = ClassifierOptions { rtol: 1e-8, ..opts };
    g.bench_function("polywear_classifier_rtol1e-8", |b| {
        b.iter(|| classify(black_box(&m.ode), rot, &loose))
    });
    g.sample_size(10);
    let s = Scales::new(&m.ode);
    g.bench_function("brute_force_24s_rtol1e-10", |b| {
        b.iter(|| envelope::brute_force(&m.ode, &s, 1e-5, 24.0, 0.5, 1e-10).unwrap())
    });
    g.finish();
    let stable = WheelModel::build(
        &Params {
            speed_kmh: 70.0,
            ..p
        },
        Wheel::Follower,
        Variant::Paper,
    )
    .unwrap();
    c.bench_function("classify_stable_point", |b| {
        b.iter(|| classify(black_box(&stable.ode), rot, &opts))
    });
}

criterion_group!(benches, bench_rhs, bench_trajectory, bench_classify);
criterion_main!(benches);
