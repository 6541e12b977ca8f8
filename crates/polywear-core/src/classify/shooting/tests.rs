use super::*;
use crate::classify::{classify, ClassifierOptions};
use crate::model::{Variant, Wheel, WheelModel};
use crate::params::Params;

/// Near the Hopf point every small orbit returns to within U·`newton_tol` of its start.
/// Judged against U, Newton started at a tenth or a third of the cycle's amplitude, with
/// the map integrated at 1e-9, stopped on an orbit 2% or 0.2% of the cycle's size (its
/// multiplier 0.9999994 passing for attracting). Judged against the orbit's own amplitude,
/// Newton finds the cycle (7% off at this tolerance, hence the 10% bound) or gives up; from
/// near the cycle it must find it.
#[test]
fn newton_does_not_take_a_small_orbit_for_a_cycle() {
    // R0's follower under `paper`, where Re λ = 1e-3 s⁻¹.
    let p = Params {
        speed_kmh: 93.236_326_05,
        ..Params::r0()
    };
    let m = WheelModel::build(&p, Wheel::Follower, Variant::Paper).unwrap();
    let opts = ClassifierOptions::default();
    let cycle = classify(&m.ode, WheelModel::rotation_hz(&p), &opts);
    assert!(cycle.class.vibrates(), "{cycle:?}");
    let lin = m.ode.linear_stability();
    assert!((lin.eig_re_max / 1e-3 - 1.0).abs() < 1e-3, "{lin:?}");
    let scales = Scales::new(&m.ode);
    let meter = Meter::new(opts.budget);
    let period = 1.0 / lin.eig_freq_hz;
    let at_1e9 = Tolerances {
        guess: 1e-9,
        first: 1e-9,
        coarse: 1e-9,
        fine: 1e-9,
    };
    let shoot_from = |k: f64| {
        let guess = (
            scales.z_eq + k * (cycle.section_z_m - scales.z_eq),
            k * cycle.section_v_mps,
        );
        newton_orbit(&m.ode, &scales, guess, period, &at_1e9, 1e-8, &meter)
    };
    // From a tenth or a third of the cycle: the cycle, or giving up; never a small orbit.
    for k in [0.1, 0.3] {
        if let Ok(orbit) = shoot_from(k) {
            let rel = orbit.measure.amp_v_mps / cycle.amp_v_mps - 1.0;
            assert!(rel.abs() < 0.1, "from {k}: {orbit:?} vs {cycle:?}");
        }
    }
    // The same Newton does find the cycle from near it: the giving up above is a judgement
    // of the small orbits, not a Newton that never converges here.
    let near = shoot_from(0.9).expect("Newton from 90% of the cycle");
    let rel = near.measure.amp_v_mps / cycle.amp_v_mps - 1.0;
    assert!(rel.abs() < 0.1, "from 0.9: {near:?} vs {cycle:?}");
}

/// The tolerances are the fixed ones away from the Hopf point and tighten towards it, the
/// fine one as growth^1.5 down to the floor; the others never go below it.
#[test]
fn tolerances_tighten_towards_the_hopf_point() {
    let far = Tolerances::for_growth(1e-2, 1e-9);
    assert_eq!(far.fine, 1e-9);
    assert_eq!((far.guess, far.coarse), (GUESS_RTOL, COARSE_RTOL));
    let near = Tolerances::for_growth(1e-6, 1e-9);
    assert!((near.fine / (FINE_RTOL_PER_GROWTH_1_5 * 1e-9) - 1.0).abs() < 1e-12);
    assert!(near.coarse >= near.fine && near.guess >= near.coarse);
    let at = Tolerances::for_growth(0.0, 1e-9);
    assert_eq!(
        (at.fine, at.coarse, at.guess),
        (FINE_RTOL_FLOOR, FINE_RTOL_FLOOR, FINE_RTOL_FLOOR)
    );
    // A user asking for more than the floor gets it.
    assert_eq!(Tolerances::for_growth(0.0, 1e-13).fine, 1e-13);
    // A real unstable eigenvalue (no period): the fixed tolerances.
    let real = Tolerances::for_growth(f64::INFINITY, 1e-9);
    assert_eq!(
        (real.guess, real.coarse, real.fine),
        (GUESS_RTOL, COARSE_RTOL, 1e-9)
    );
}
