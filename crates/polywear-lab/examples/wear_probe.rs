//! A quick look at the long-term loop at one point: `cargo run --release -p polywear-lab --example wear_probe
//! -- SPEED PHI_S SPREAD WHEEL(f|d) DISTANCE_KM`. Prints the time, the steps and the dominant
//! order's history. PW_SKIP sets the revolutions settled after each profile update (default 2).
use polywear::classify::ClassifierOptions;
use polywear::evaluate::{calibrate_wear, solve_wheel};
use polywear::long_term::wheel_loop::{cruise_legs, run_wheel, LoopInputs, LoopSettings};
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use std::time::Instant;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: f64| a.get(i).map(|s| s.parse().unwrap()).unwrap_or(d);
    let speed = arg(1, 100.0);
    let p = Params {
        speed_kmh: speed,
        wear_share_straight: arg(2, 1.0),
        speed_spread_kmh: arg(3, 0.0),
        toe_deg: std::env::var("PW_TOE").map_or(Params::default().toe_deg, |t| t.parse().unwrap()),
        ..Params::default()
    };
    let wheel = if a.get(4).map(String::as_str) == Some("d") {
        Wheel::Driving
    } else {
        Wheel::Follower
    };
    let opts = ClassifierOptions::default();
    let cal = calibrate_wear(&p, Variant::SlidingShare, &opts).unwrap();
    let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
    let v = &w.verdict;
    println!("class {} nu {:.3}", v.class, v.polygon_order);
    let start = v.class.vibrates().then(|| {
        let eq = w.model.as_ref().unwrap().ode.equilibrium();
        [v.section_z_m, eq[1], v.section_v_mps]
    });
    // PW_LEGS=K: K equal-share speeds of the spread (default 5); PW_TOE: the toe-in [deg].
    let nodes: usize = std::env::var("PW_LEGS")
        .ok()
        .map(|k| k.parse().unwrap())
        .unwrap_or(5);
    let legs = cruise_legs(speed, p.speed_spread_kmh, nodes);
    let settings = LoopSettings {
        distance_km: arg(5, 60_000.0),
        rtol: arg(6, 1e-8),
        // PW_FIXED_H: the tread height held at the new tyre's.
        update_tread_height: std::env::var("PW_FIXED_H").is_err(),
        // PW_MIN_STEP_KM: the loop's Δs_min (default 20 km).
        min_step_km: std::env::var("PW_MIN_STEP_KM").map_or(20.0, |s| s.parse().unwrap()),
        // PW_SKIP: revolutions settled after each profile update (default 2).
        skip_revs: std::env::var("PW_SKIP").map_or(2, |s| s.parse().unwrap()),
        ..LoopSettings::default()
    };
    let t0 = Instant::now();
    let r = run_wheel(
        &LoopInputs {
            params: &p,
            wheel,
            variant: Variant::SlidingShare,
            gamma_m3_per_j: cal.gamma_m3_per_j(&p),
            legs: &legs,
            start,
        },
        &settings,
        &|_| {},
    )
    .unwrap();
    println!(
        "{:?} steps {} redone {} rhs {} visible {:?} even {:.5} mm/1000km dominant {}",
        t0.elapsed(),
        r.steps,
        r.redone,
        r.rhs_evals,
        r.visible,
        r.even_wear_m_per_m * 1e9,
        r.dominant_order()
    );
    if std::env::var("PW_STEPS").is_ok() {
        let d: Vec<String> = r
            .history
            .windows(2)
            .map(|w| format!("{:.0}", w[1].distance_km - w[0].distance_km))
            .collect();
        println!("steps km: {}", d.join(" "));
    }
    // PW_ORDER: the order followed (default the dominant one).
    let n =
        std::env::var("PW_ORDER").map_or(r.dominant_order() as usize, |s| s.parse().unwrap()) - 1;
    for h in r.history.iter().step_by((r.history.len() / 15).max(1)) {
        println!(
            "  {:9.1} km h {:.3} mm D{} {:.3} um beta {:.3}/1000km rho {:?} D{} {:.3} D{} {:.3} D2 {:.3}",
            h.distance_km,
            h.tread_height_m * 1e3,
            n + 1,
            h.depths_m[n] * 1e6,
            h.growth_per_m[n] * 1e6,
            h.rho,
            n,
            h.depths_m[n - 1] * 1e6,
            n + 2,
            h.depths_m[n + 1] * 1e6,
            h.depths_m[1] * 1e6
        );
    }
}
