//! The lock band of a cycle forced by one order-19 harmonic of radius R, at a fixed model (only
//! the rotation moves, so that δ = ν − 19 is scanned), against the forced Hopf normal form read
//! off the cycle's Floquet modes (`wear::response::normal_form`) and the first-order (Adler) half-width
//! (MODEL.md#the-tongue-at-depth). The default point's follower, φ_s = 1, at SPEED km/h:
//!
//! ```sh
//! cargo run --release -p polywear-lab --example tongue_depth -- SPEED R_UM...
//! cargo run --release -p polywear-lab --example tongue_depth -- 100 0.25 0.5 1 2 4 8 16
//! ```
use polywear::classify::budget::Meter;
use polywear::classify::ClassifierOptions;
use polywear::evaluate::solve_wheel;
use polywear::long_term::lock::{is_locked, rotation_number};
use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear_core::numeric::Complex64;
use polywear_core::wear::physics::cycle::{SampledCycle, SAMPLES_PER_PERIOD};
use polywear_core::wear::response::normal_form::ForcedHopf;
use polywear_core::wear::response::periodic::CycleResponse;
use polywear_core::wear::{Feedback, WearZone};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let speed: f64 = a.get(1).map_or(100.0, |s| s.parse().unwrap());
    let radii_um: Vec<f64> = a.iter().skip(2).map(|s| s.parse().unwrap()).collect();
    let p = Params {
        speed_kmh: speed,
        wear_share_straight: 1.0,
        speed_spread_kmh: 0.0,
        ..Params::default()
    };
    let w = solve_wheel(
        p,
        Variant::SlidingShare,
        Wheel::Follower,
        &ClassifierOptions::default(),
    );
    let v = &w.verdict;
    let m = w.model.as_ref().unwrap();
    let cycle = SampledCycle::of(
        &m.ode,
        v,
        SAMPLES_PER_PERIOD,
        &Meter::new(Default::default()),
    )
    .unwrap();
    let response = CycleResponse::of(&m.ode, &cycle).unwrap();
    let form = ForcedHopf::of(&response).unwrap();
    let fb = Feedback::new(&p, m, WearZone::Trailing);
    let nu = v.polygon_order;
    let f_rot = WheelModel::rotation_hz(&p);
    let f_cycle = nu * f_rot;
    // δ_lock per metre of R (MODEL.md#growth-of-a-vibrating-wheel), and in rad/s.
    let delta_per_m = nu * fb.forcing_per_radius(19.0).norm() * response.phase_coupling_s;
    let rad_s_per_delta = std::f64::consts::TAU * f_cycle / 19.0;
    println!(
        "{speed} km/h: nu {nu:.4}, lambda {:.3} 1/s, shear {:.3}, first order {:.5} per um of R",
        form.amplitude_rate_per_s,
        form.shear,
        delta_per_m * 1e-6
    );
    let start = [v.section_z_m, m.ode.equilibrium()[1], v.section_v_mps];
    for r_um in radii_um {
        let mut h = vec![Complex64::new(0.0, 0.0); 64];
        h[18] = Complex64::new(r_um * 1e-6, 0.0);
        let table = EpsilonTable::new(&fb, &h, 2048);
        let locks = |delta: f64| {
            let rotation_hz = f_cycle / (19.0 + delta);
            let win = integrate_window(&WindowRequest {
                ode: &m.ode,
                epsilon: &table,
                rotation_hz,
                start,
                skip_revs: 300,
                revs: 40,
                samples_per_rev: 64,
                rtol: 1e-8,
                period_s: 1.0 / f_cycle,
                max_steps: 50_000_000,
            })
            .unwrap();
            is_locked(rotation_number(&win.crossings_s, 1.0 / rotation_hz))
        };
        let first = delta_per_m * r_um * 1e-6;
        let edge = |sign: f64| {
            let step = 0.05 * first;
            let (mut inside, mut outside) = (0.0, f64::NAN);
            for k in 1..=400 {
                let d = k as f64 * step;
                if locks(sign * d) {
                    inside = d;
                } else {
                    outside = d;
                    break;
                }
            }
            for _ in 0..6 {
                let mid = 0.5 * (inside + outside);
                if locks(sign * mid) {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            inside
        };
        // δ > 0 is a slower rotation: the forcing below the cycle's frequency.
        let (below, above) = (edge(1.0), edge(-1.0));
        let (nf_below, nf_above) = form.lock_edges_rad_s(first * rad_s_per_delta);
        println!(
            "R {r_um:5.2} um  first order ±{first:.4}  brute force -{:.3} +{:.3} (half {:.3})  normal form -{:.3} +{:.3} (half {:.3})  [of first order]",
            below / first,
            above / first,
            0.5 * (below + above) / first,
            -nf_below / rad_s_per_delta / first,
            nf_above / rad_s_per_delta / first,
            0.5 * (nf_above - nf_below) / rad_s_per_delta / first
        );
    }
}
