use polywear::classify::ClassifierOptions;
use polywear::evaluate::{calibrate_wear, solve_wheel};
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear::wear::estimator::{WearInputs, WearSettings, WheelGrowth};
use polywear::wear::long_term::{cruise_legs, run_wheel, LoopInputs, LoopSettings};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let speed: f64 = a[1].parse().unwrap();
    let spread: f64 = a[2].parse().unwrap();
    let p = Params {
        speed_kmh: speed,
        wear_share_straight: 1.0,
        speed_spread_kmh: spread,
        seed_runout_um: std::env::var("SEED")
            .map(|s| s.parse().unwrap())
            .unwrap_or(2.0),
        ..Params::default()
    };
    let opts = ClassifierOptions::default();
    let cal = calibrate_wear(&p, Variant::SlidingShare, &opts).unwrap();
    let w = solve_wheel(p, Variant::SlidingShare, Wheel::Follower, &opts);
    let v = &w.verdict;
    let start = v.class.vibrates().then(|| {
        [
            v.section_z_m,
            w.model.as_ref().unwrap().ode.equilibrium()[1],
            v.section_v_mps,
        ]
    });
    let legs = cruise_legs(speed, spread);
    let r = run_wheel(
        &LoopInputs {
            params: &p,
            wheel: Wheel::Follower,
            variant: Variant::SlidingShare,
            gamma_m3_per_j: cal.gamma_m3_per_j(&p),
            legs: &legs,
            start,
        },
        &LoopSettings {
            distance_km: 60.0,
            update_tread_height: false,
            stop_at_visible: false,
            skip_revs: std::env::var("SKIP")
                .map(|s| s.parse().unwrap())
                .unwrap_or(2),
            ..LoopSettings::default()
        },
        &|_| {},
    )
    .unwrap();
    let meter = polywear::classify::budget::Meter::new(Default::default());
    let g = WheelGrowth::new(
        &WearInputs {
            params: &p,
            model: &w.model,
            verdict: &w.verdict,
            settings: &WearSettings::default(),
            calibration: &cal,
        },
        &meter,
    )
    .unwrap();
    println!(
        "class {} nu {:.3} rho {:?}",
        v.class,
        g.nu(),
        r.history[1].rho
    );
    for n in a[3..].iter().map(|s| s.parse::<u32>().unwrap()) {
        println!(
            "  n {n}: loop {:.4} est {:.4}",
            r.history[1].growth_per_m[n as usize - 1] * 1e6,
            g.order(n).growth_rate_per_1000km
        );
    }
}
