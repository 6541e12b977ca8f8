//! The lock band in speed by the forced orbit (`polywear_lab::forced_orbit`), against the forced Hopf
//! normal form (`WheelGrowth::lock_band_kmh`): the default point's follower (φ_s = 1) near V_19,
//! forced by one order-19 harmonic of radius R, the model rebuilt at each speed. The locked orbit
//! is found at V_19 (Newton from 30 revolutions settled) and continued outward in speed, each
//! step's Newton starting from the last orbit, until it is lost or stops attracting; the last
//! step is bisected. This follows the locked branch as a deepening polygon carries it
//! (MODEL.md#the-locked-print).
//!
//! ```sh
//! cargo run --release -p polywear-lab --example orbit_tongue -- R_UM...
//! cargo run --release -p polywear-lab --example orbit_tongue -- 0.25 0.5 1 2 4 8 16 32 64 125
//! ```
#[path = "common/near_v19.rs"]
mod near_v19;

use near_v19::{at, NearV19, ORDER, VARIANT};
use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear::model::{Wheel, WheelModel};
use polywear_core::numeric::Complex64;
use polywear_core::wear::{Feedback, WearSettings};
use polywear_lab::forced_orbit::{self, ForcedOrbit};

/// Steps outward, each this share of the normal form's half-width (at least 0.01 km/h).
const STEP_SHARE: f64 = 0.05;
const MOST_STEPS: usize = 2000;
const BISECTIONS: usize = 8;
/// The lowest speed continued to \[km/h\].
const LOWEST_KMH: f64 = 20.0;

fn main() {
    let radii_um = near_v19::radii_um();
    let settings = WearSettings::default();
    let near = NearV19::new();
    let (g, centre) = (&near.growth, near.centre_kmh);
    let free_start = near.free_start();
    let n = ORDER as f64;
    println!("follower, V_19 = {centre:.3} km/h");
    for r_um in radii_um {
        let r_m = r_um * 1e-6;
        // The orbit at `offset` from `start` (None: lost), and its evaluations.
        let orbit_at = |offset: f64, start: [f64; 3]| -> Option<ForcedOrbit> {
            let p = at(centre + offset);
            let model = WheelModel::build(&p, Wheel::Follower, VARIANT).ok()?;
            let fb = Feedback::new(&p, &model, settings.zone);
            let omega = std::f64::consts::TAU * n * WheelModel::rotation_hz(&p);
            forced_orbit::solve(
                &model.ode,
                fb.forcing_per_radius(n) * r_m,
                omega,
                start,
                1e-10,
            )
            .ok()
        };
        // At V_19, from 30 revolutions settled.
        let settled = {
            let model = WheelModel::build(&at(centre), Wheel::Follower, VARIANT).unwrap();
            let fb = Feedback::new(&at(centre), &model, settings.zone);
            let mut h = vec![Complex64::new(0.0, 0.0); ORDER as usize];
            h[ORDER as usize - 1] = Complex64::new(r_m, 0.0);
            let rotation_hz = WheelModel::rotation_hz(&at(centre));
            integrate_window(&WindowRequest {
                ode: &model.ode,
                epsilon: &EpsilonTable::new(&fb, &h, 2048),
                rotation_hz,
                start: free_start,
                skip_revs: 0,
                revs: 30,
                samples_per_rev: 16,
                rtol: 1e-8,
                period_s: 1.0 / (g.nu() * rotation_hz),
                max_steps: 50_000_000,
            })
            .unwrap()
            .end
        };
        let Some(first) = orbit_at(0.0, settled).filter(ForcedOrbit::locks) else {
            println!("R {r_um:6.2} um: no locked orbit at V_19");
            continue;
        };
        let nf_band = g.lock_band_kmh(ORDER, r_m).unwrap_or((0.0, 0.0));
        let step = (STEP_SHARE * 0.5 * (nf_band.1 - nf_band.0)).max(0.01);
        let mut evals = first.rhs_evals;
        let mut edges = [0.0; 2];
        let mut bound = [false; 2];
        for (side, sign) in [(0, -1.0), (1, 1.0)] {
            let (mut inside, mut last) = (0.0, first.clone());
            let mut outside = f64::NAN;
            for k in 1..=MOST_STEPS {
                let d = k as f64 * step;
                if centre + sign * d < LOWEST_KMH {
                    break;
                }
                match orbit_at(sign * d, last.start) {
                    Some(o) if o.locks() => {
                        evals += o.rhs_evals;
                        inside = d;
                        last = o;
                    }
                    _ => {
                        outside = d;
                        break;
                    }
                }
            }
            if outside.is_nan() {
                // Still locked at the lowest speed (or after the most steps): at least this.
                edges[side] = sign * inside;
                bound[side] = true;
                continue;
            }
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (inside + outside);
                match orbit_at(sign * mid, last.start) {
                    Some(o) if o.locks() => {
                        evals += o.rhs_evals;
                        inside = mid;
                        last = o;
                    }
                    _ => outside = mid,
                }
            }
            edges[side] = sign * inside;
        }
        let mark = |side: usize| if bound[side] { " (at least)" } else { "" };
        println!(
            "R {r_um:6.2} um: orbit {:+.3}{} … {:+.3}{} km/h   normal form {:+.3} … {:+.3} km/h   ({evals} evals)",
            edges[0],
            mark(0),
            edges[1],
            mark(1),
            nf_band.0,
            nf_band.1
        );
    }
}
