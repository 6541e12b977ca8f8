//! The lock band in speed of the default point's follower (100 km/h, φ_s = 1, no spread) forced
//! by one order-19 harmonic of radius R: each speed around V_19 = V ν/19 with the whole model
//! rebuilt at it, as the long-term loop builds its legs and `long_term::tongue` measures, settled
//! SETTLE revolutions from the free cycle and ρ read over REVS
//! (MODEL.md#growth-of-a-vibrating-wheel):
//!
//! ```sh
//! # scan ±RANGE km/h in steps of STEP
//! cargo run --release -p polywear-lab --example tongue_speed -- R_M SETTLE REVS RANGE STEP [speed|fixed]
//! # both edges: outward in steps of STEP km/h (RANGE unused), then six halvings
//! cargo run --release -p polywear-lab --example tongue_speed -- 2e-6 300 40 0 0.08 speed edges
//! ```
//!
//! `fixed` holds the model (and the forcing's coupling) at V_19 and moves only the rotation, as
//! `tongue_scan` does in δ.
use polywear::classify::ClassifierOptions;
use polywear::evaluate::solve_wheel;
use polywear::long_term::lock::rotation_number;
use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear_core::numeric::Complex64;
use polywear_core::wear::{Feedback, WearZone};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let radius: f64 = a[1].parse().unwrap();
    let skip: usize = a[2].parse().unwrap();
    let revs: usize = a[3].parse().unwrap();
    let range_kmh: f64 = a[4].parse().unwrap();
    let step_kmh: f64 = a[5].parse().unwrap();
    let fixed = a.get(6).is_some_and(|s| s == "fixed");
    let p0 = Params {
        speed_kmh: 100.0,
        wear_share_straight: 1.0,
        speed_spread_kmh: 0.0,
        ..Params::default()
    };
    let opts = ClassifierOptions::default();
    let w = solve_wheel(p0, Variant::SlidingShare, Wheel::Follower, &opts);
    let v = &w.verdict;
    let m0 = w.model.as_ref().unwrap();
    let nu = v.polygon_order;
    let centre = p0.speed_kmh * nu / 19.0;
    let start = [v.section_z_m, m0.ode.equilibrium()[1], v.section_v_mps];
    println!("nu {nu:.4} centre {centre:.4} km/h");
    let mut h = vec![Complex64::new(0.0, 0.0); 64];
    h[18] = Complex64::new(radius, 0.0);
    let pc = Params {
        speed_kmh: centre,
        ..p0
    };
    let mc = WheelModel::build_worn(&pc, pc.tread_height, Wheel::Follower, Variant::SlidingShare)
        .unwrap();
    let fbc = Feedback::new(&pc, &mc, WearZone::Trailing);
    let tablec = EpsilonTable::new(&fbc, &h, 2048);
    let locked = |dv: f64| -> (bool, f64) {
        let p = Params {
            speed_kmh: centre + dv,
            ..p0
        };
        let rot = WheelModel::rotation_hz(&p);
        let (model, table);
        let (mref, tref) = if fixed {
            (&mc, &tablec)
        } else {
            model =
                WheelModel::build_worn(&p, p.tread_height, Wheel::Follower, Variant::SlidingShare)
                    .unwrap();
            let fb = Feedback::new(&p, &model, WearZone::Trailing);
            table = EpsilonTable::new(&fb, &h, 2048);
            (&model, &table)
        };
        let win = integrate_window(&WindowRequest {
            ode: &mref.ode,
            epsilon: tref,
            rotation_hz: rot,
            start,
            skip_revs: skip,
            revs,
            samples_per_rev: 64,
            rtol: 1e-8,
            period_s: 1.0 / (19.0 * rot),
            max_steps: 50_000_000,
        })
        .unwrap();
        let rho = rotation_number(&win.crossings_s, 1.0 / rot);
        ((rho - 19.0).abs() < 1e-3, rho)
    };
    if a.get(7).is_some_and(|s| s == "edges") {
        let step = step_kmh;
        let mut edges = [0.0; 2];
        for (side, sign) in [(0usize, -1.0), (1, 1.0)] {
            let (mut inside, mut outside) = (0.0, f64::NAN);
            for k in 1..=200 {
                let d = k as f64 * step;
                if locked(sign * d).0 {
                    inside = d
                } else {
                    outside = d;
                    break;
                }
            }
            for _ in 0..6 {
                let mid = 0.5 * (inside + outside);
                if locked(sign * mid).0 {
                    inside = mid
                } else {
                    outside = mid
                }
            }
            edges[side] = inside;
        }
        println!(
            "R {:.2} um  below -{:.3}  above +{:.3}  half {:.3} km/h",
            radius * 1e6,
            edges[0],
            edges[1],
            0.5 * (edges[0] + edges[1])
        );
        return;
    }
    let (lim_kmh, step_kmh) = (range_kmh, step_kmh);
    let mut dv = -lim_kmh;
    while dv <= lim_kmh + 1e-9 {
        let (l, rho) = locked(dv);
        println!(
            "dV {dv:+.3} km/h  delta_eq {:+.4}  rho {rho:.5} {}",
            -19.0 * dv / centre,
            if l { "LOCK" } else { "" }
        );
        dv += step_kmh;
    }
}
