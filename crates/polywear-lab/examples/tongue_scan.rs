//! The lock band of the default point's cycle (follower, 100 km/h, φ_s = 1, no spread) forced by
//! one order-19 harmonic of radius R, with only the rotation frequency moved so that δ = ν − 19
//! is scanned at a fixed model, beside the estimator's first-order half-width δ_lock
//! (MODEL.md#growth-of-a-vibrating-wheel):
//!
//! ```sh
//! cargo run --release -p polywear-lab --example tongue_scan -- R_M SETTLE_REVS HALF_RANGE STEP
//! cargo run --release -p polywear-lab --example tongue_scan -- 0.25e-6 300 0.04 0.0025
//! cargo run --release -p polywear-lab --example tongue_scan -- 2e-6 100 0.3 0.02
//! ```
use polywear::classify::budget::Meter;
use polywear::classify::ClassifierOptions;
use polywear::evaluate::{calibrate_wear, solve_wheel};
use polywear::long_term::lock::rotation_number;
use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear_core::numeric::Complex64;
use polywear_core::wear::{Feedback, WearProblem, WearSettings, WearZone, WheelGrowth};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let radius: f64 = a.get(1).map_or(2e-6, |s| s.parse().unwrap());
    let skip: usize = a.get(2).map_or(60, |s| s.parse().unwrap());
    let p = Params {
        speed_kmh: 100.0,
        wear_share_straight: 1.0,
        speed_spread_kmh: 0.0,
        ..Params::default()
    };
    let opts = ClassifierOptions::default();
    let cal = calibrate_wear(&p, Variant::SlidingShare, &opts).unwrap();
    let w = solve_wheel(p, Variant::SlidingShare, Wheel::Follower, &opts);
    let v = &w.verdict;
    let m = w.model.as_ref().unwrap();
    let nu = v.polygon_order;
    let f_rot = WheelModel::rotation_hz(&p);
    let f = nu * f_rot;
    let meter = Meter::new(Default::default());
    let g = WheelGrowth::new(
        &WearProblem {
            params: p,
            model: &w.model,
            verdict: v,
            settings: &WearSettings::default(),
            calibration: &cal,
        },
        &meter,
    )
    .unwrap();
    let est = g.order(19);
    let scale = radius / 2e-6;
    let dl_est = est.lock_halfwidth_kmh / 3.6 * 19.0 / (p.speed_kmh / 3.6) * scale;
    println!("class {} nu {nu:.4} f {f:.2} Hz; estimator delta_L {dl_est:.4} rev (first order; {:.3} km/h at 2 um)", v.class, est.lock_halfwidth_kmh);
    let fb = Feedback::new(&p, m, WearZone::Trailing);
    let mut h = vec![Complex64::new(0.0, 0.0); 64];
    h[18] = Complex64::new(radius, 0.0);
    let table = EpsilonTable::new(&fb, &h, 2048);
    println!(
        "|e_19| R = {:.4e}",
        fb.forcing_per_radius(19.0).norm() * radius
    );
    let start = [v.section_z_m, m.ode.equilibrium()[1], v.section_v_mps];
    let period = 1.0 / f;
    let lim: f64 = a.get(3).map_or(0.3, |s| s.parse().unwrap());
    let stepd: f64 = a.get(4).map_or(0.02, |s| s.parse().unwrap());
    let mut d = -lim;
    while d <= lim + 1e-9 {
        let fr = f / (19.0 + d);
        let win = integrate_window(&WindowRequest {
            ode: &m.ode,
            epsilon: &table,
            rotation_hz: fr,
            start,
            skip_revs: skip,
            revs: 20,
            samples_per_rev: 64,
            rtol: 1e-8,
            period_s: period,
            max_steps: 10_000_000,
        })
        .unwrap();
        let rho = rotation_number(&win.crossings_s, 1.0 / fr);
        println!(
            "delta {d:+.3} rho {rho:.5} {}",
            if (rho - 19.0).abs() < 1e-3 {
                "LOCK"
            } else {
                ""
            }
        );
        d += stepd;
    }
}
