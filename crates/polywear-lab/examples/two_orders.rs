//! A cycle forced by two neighbouring polygon orders at once, brute force
//! (MODEL.md#the-locked-print): a wheel at 0.3° toe-in and φ_s = 1, forced by orders N and
//! N + 1 of radii R_N and R_N+1 (their crests at tyre angle 0), 300 revolutions settled from the
//! free cycle and 40 read. Prints the rotation number (N when locked to N) and each order's print
//! in phase with it, Re(−conj(H_w) p)/|H_w|, as a share of P̄.
//!
//! ```sh
//! cargo run --release -p polywear-lab --example two_orders -- SPEED N R_N_UM R_N1_UM [follower|driving]
//! cargo run --release -p polywear-lab --example two_orders -- 90 21 18 13 driving
//! ```
use polywear::classify::ClassifierOptions;
use polywear::evaluate::solve_wheel;
use polywear::long_term::lock::rotation_number;
use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear_core::numeric::Complex64;
use polywear_core::wear::{Feedback, WearSettings};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let speed_kmh: f64 = a[1].parse().unwrap();
    let order: usize = a[2].parse().unwrap();
    let (r_n, r_next): (f64, f64) = (a[3].parse().unwrap(), a[4].parse().unwrap());
    let wheel = match a.get(5).map(String::as_str) {
        Some("follower") => Wheel::Follower,
        _ => Wheel::Driving,
    };
    let p = Params {
        speed_kmh,
        toe_deg: 0.3,
        wear_share_straight: 1.0,
        speed_spread_kmh: 0.0,
        ..Params::default()
    };
    let w = solve_wheel(
        p,
        Variant::SlidingShare,
        wheel,
        &ClassifierOptions::default(),
    );
    let v = &w.verdict;
    let m = w.model.as_ref().unwrap();
    let fb = Feedback::new(&p, m, WearSettings::default().zone);
    let mut h = vec![Complex64::new(0.0, 0.0); order + 1];
    h[order - 1] = Complex64::new(r_n * 1e-6, 0.0);
    h[order] = Complex64::new(r_next * 1e-6, 0.0);
    let rotation_hz = WheelModel::rotation_hz(&p);
    let win = integrate_window(&WindowRequest {
        ode: &m.ode,
        epsilon: &EpsilonTable::new(&fb, &h, 4096),
        rotation_hz,
        start: [v.section_z_m, m.ode.equilibrium()[1], v.section_v_mps],
        skip_revs: 300,
        revs: 40,
        samples_per_rev: 256,
        rtol: 1e-8,
        period_s: 1.0 / (v.polygon_order * rotation_hz),
        max_steps: 50_000_000,
    })
    .unwrap();
    let rho = rotation_number(&win.crossings_s, 1.0 / rotation_hz);
    let in_phase = |n: usize| fb.in_phase_print(n as f64, win.print(n as u32));
    println!(
        "{wheel:?} at {speed_kmh} km/h, nu {:.3}: R_{order} {r_n} um, R_{} {r_next} um: rho {rho:.4}; in phase, order {order} {:+.4}, order {} {:+.4}",
        v.polygon_order,
        order + 1,
        in_phase(order),
        order + 1,
        in_phase(order + 1)
    );
}
