//! Hot paths: one RHS evaluation (the shipped one beside the `powf`/`hypot` form that evaluates
//! the Stribeck curve again for the Jacobian, kept in `before` for the comparison), a 1-second
//! trajectory, and the classifier per wheel at the default point next to the brute-force
//! reference.
//! Run: `cargo bench --bench hot_paths`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};

use polywear::classify::{classify, envelope, ClassifierOptions, Scales};
use polywear::model::Variational;
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear_core::solver::{integrate, Control, OdeSystem, SolverOptions};

/// The right-hand side as first written: `powf` for (w_t/V_s)^φ, `hypot` for w_t, and the
/// Jacobian of the variational equations evaluating the sliding speed and the curve again.
mod before {
    use polywear::model::{TreadOde, Variant};

    fn sliding_speed(o: &TreadOde, w: f64) -> (f64, f64) {
        match o.variant {
            Variant::Paper => (w.abs(), if w >= 0.0 { 1.0 } else { -1.0 }),
            Variant::Combined | Variant::SlidingShare => {
                let wt = w.hypot(o.v_sx_mps);
                (wt, if wt > 0.0 { w / wt } else { 1.0 })
            }
        }
    }

    fn stribeck(o: &TreadOde, w_t: f64) -> f64 {
        o.f_s + (o.f_m - o.f_s) * (-(w_t / o.v_s).powf(o.phi)).exp()
    }

    fn stribeck_with_slope(o: &TreadOde, w_t: f64) -> (f64, f64) {
        let x = w_t / o.v_s;
        if x == 0.0 {
            return (o.f_m, 0.0);
        }
        let xp = x.powf(o.phi);
        let e = (o.f_m - o.f_s) * (-xp).exp();
        (o.f_s + e, -e * o.phi * xp / w_t)
    }

    pub fn rhs(o: &TreadOde, x: &[f64; 3]) -> [f64; 3] {
        let [z, y, v] = *x;
        let w = v - o.u_mps;
        let (w_t, _) = sliding_speed(o, w);
        let g = stribeck(o, w_t);
        let dz = w - o.sigma0 * w_t * z / g;
        let dv = -(o.c_s * v + o.k_s * y + o.sigma0 * z + o.sigma1 * dz) / o.mass_kg;
        [dz, v, dv]
    }

    pub fn jacobian(o: &TreadOde, x: &[f64; 3]) -> [[f64; 3]; 3] {
        let [z, _, v] = *x;
        let w = v - o.u_mps;
        let (w_t, dwt_dw) = sliding_speed(o, w);
        let (g, dg) = stribeck_with_slope(o, w_t);
        let dfz_dz = -o.sigma0 * w_t / g;
        let dfz_dv = 1.0 - o.sigma0 * z * dwt_dw * (g - w_t * dg) / (g * g);
        let m = o.mass_kg;
        [
            [dfz_dz, 0.0, dfz_dv],
            [0.0, 0.0, 1.0],
            [
                -(o.sigma0 + o.sigma1 * dfz_dz) / m,
                -o.k_s / m,
                -(o.c_s + o.sigma1 * dfz_dv) / m,
            ],
        ]
    }

    pub fn variational(o: &TreadOde, s: &[f64; 12]) -> [f64; 12] {
        let x = [s[0], s[1], s[2]];
        let f = rhs(o, &x);
        let j = jacobian(o, &x);
        let mut out = [0.0; 12];
        out[..3].copy_from_slice(&f);
        for col in 0..3 {
            let phi = [s[3 + 3 * col], s[4 + 3 * col], s[5 + 3 * col]];
            for row in 0..3 {
                out[3 + 3 * col + row] =
                    j[row][0] * phi[0] + j[row][1] * phi[1] + j[row][2] * phi[2];
            }
        }
        out
    }
}

fn default_model() -> WheelModel {
    WheelModel::build(&Params::default(), Wheel::Follower, Variant::Paper).unwrap()
}

fn bench_rhs(c: &mut Criterion) {
    let follower = default_model().ode;
    let driving = WheelModel::build(&Params::default(), Wheel::Driving, Variant::SlidingShare)
        .unwrap()
        .ode;
    for (name, ode) in [
        ("follower_paper", follower),
        ("driving_sliding_share", driving),
    ] {
        let eq = ode.equilibrium();
        let x = [eq[0] * 1.01, eq[1], 0.01];
        let s = [
            x[0], x[1], x[2], 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0,
        ];
        let mut g = c.benchmark_group(format!("rhs_{name}"));
        g.bench_function("rhs_before", |b| {
            b.iter(|| before::rhs(black_box(&ode), black_box(&x)))
        });
        g.bench_function("rhs", |b| b.iter(|| black_box(&ode).rhs(black_box(&x))));
        g.bench_function("variational_before", |b| {
            b.iter(|| before::variational(black_box(&ode), black_box(&s)))
        });
        g.bench_function("variational", |b| {
            b.iter(|| Variational(black_box(&ode)).rhs(black_box(&s)))
        });
        g.bench_function("jacobian", |b| {
            b.iter(|| black_box(&ode).jacobian(black_box(&x)))
        });
        g.finish();
        // The comparison is only fair if both compute the same thing.
        let (new, old) = (ode.rhs(&x), before::rhs(&ode, &x));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * a.abs().max(b.abs()).max(1e-300);
        assert!(
            new.iter().zip(&old).all(|(a, b)| close(*a, *b)),
            "{new:?} vs {old:?}"
        );
        let (new, old) = (Variational(&ode).rhs(&s), before::variational(&ode, &s));
        assert!(
            new.iter().zip(&old).all(|(a, b)| close(*a, *b)),
            "{new:?} vs {old:?}"
        );
    }
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
