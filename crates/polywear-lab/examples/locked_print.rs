//! The locked cycle's print onto a polygon, brute force against the estimator
//! (`WheelGrowth::locked_print_share`, MODEL.md#the-locked-print): the follower at the default
//! point (φ_s = 1) near V_19, forced by one order-19 harmonic of radius R (real: its crests at
//! tyre angle 0) at speeds across the lock band, the model rebuilt at each speed as the loop
//! builds it. After 300 revolutions of settling, the harmonic 19 of the energy laid per cell
//! over 40 revolutions, over its mean (`Window::print`), is the print p; what deepens
//! the polygon is Re(−conj(H_w) p)/|H_w|, here over the free cycle's |P₁|/P̄. Beside it, the
//! forced orbit's (`polywear_lab::forced_orbit`, by Newton from 30 revolutions settled), and whether
//! it attracts.
//!
//! ```sh
//! cargo run --release -p polywear-lab --example locked_print -- R_UM...
//! cargo run --release -p polywear-lab --example locked_print -- 0.25 1 2 4
//! ```
#[path = "common/near_v19.rs"]
mod near_v19;

use near_v19::{at, NearV19, ORDER, VARIANT};
use polywear::long_term::lock::{is_locked, rotation_number};
use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear::model::{Wheel, WheelModel};
use polywear_core::numeric::Complex64;
use polywear_core::wear::{Feedback, WearSettings};
use polywear_lab::forced_orbit;

const SAMPLES_PER_REV: usize = 256;

fn main() {
    let radii_um = near_v19::radii_um();
    let settings = WearSettings::default();
    let near = NearV19::new();
    let (g, centre) = (&near.growth, near.centre_kmh);
    let free = g.cycle_power_harmonic_rel();
    println!(
        "follower, V_19 = {centre:.3} km/h, nu {:.4}, free |P1|/P {free:.4}",
        g.nu()
    );
    let start = near.free_start();
    let n = ORDER as f64;
    for r_um in radii_um {
        let r_m = r_um * 1e-6;
        let Some((below, above)) = g.lock_band_kmh(ORDER, r_m) else {
            println!("R {r_um} um: no band");
            continue;
        };
        println!("R {r_um:5.2} um: band {below:+.4} … {above:+.4} km/h");
        for share in [-0.9, -0.6, -0.3, 0.0, 0.3, 0.6, 0.9] {
            let offset = if share < 0.0 {
                -share * below
            } else {
                share * above
            };
            let p = at(centre + offset);
            let model = WheelModel::build(&p, Wheel::Follower, VARIANT).unwrap();
            let fb = Feedback::new(&p, &model, settings.zone);
            let mut h = vec![Complex64::new(0.0, 0.0); ORDER as usize];
            h[ORDER as usize - 1] = Complex64::new(r_m, 0.0);
            let table = EpsilonTable::new(&fb, &h, 2048);
            let rotation_hz = WheelModel::rotation_hz(&p);
            let request = WindowRequest {
                ode: &model.ode,
                epsilon: &table,
                rotation_hz,
                start,
                skip_revs: 300,
                revs: 40,
                samples_per_rev: SAMPLES_PER_REV,
                rtol: 1e-8,
                period_s: 1.0 / (g.nu() * rotation_hz),
                max_steps: 50_000_000,
            };
            let win = integrate_window(&request).unwrap();
            let rho = rotation_number(&win.crossings_s, 1.0 / rotation_hz);
            let print = win.print(ORDER);
            let brute = fb.in_phase_print(n, print) / free;
            let estimated = g.locked_print_share(ORDER, r_m, offset);
            // The forced orbit by Newton, from 30 revolutions settled.
            let short = integrate_window(&WindowRequest {
                skip_revs: 0,
                revs: 30,
                samples_per_rev: 16,
                ..request
            })
            .unwrap();
            let omega = std::f64::consts::TAU * n * rotation_hz;
            let forcing = fb.forcing_per_radius(n) * r_m;
            let orbit = match forced_orbit::solve(&model.ode, forcing, omega, short.end, 1e-10) {
                Ok(o) => format!(
                    "orbit {:+.3}{} ({} evals)",
                    fb.in_phase_print(n, o.print) / free,
                    if o.locks() { "" } else { " (unstable)" },
                    o.rhs_evals
                ),
                Err(e) => format!("orbit: {e:?}"),
            };
            println!(
                "  {offset:+.4} km/h  rho {rho:.4}{}  |p|/free {:.3}  brute force {brute:+.3} ({} evals)  estimator {}  {orbit}",
                if is_locked(rho) { "" } else { " (unlocked)" },
                print.norm() / free,
                win.rhs_evals,
                estimated.map_or("none".into(), |e| format!("{e:+.3}"))
            );
        }
    }
}
