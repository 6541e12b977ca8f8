//! Physics invariants (steps 4–9 of MODEL.md#the-physics-step-by-step): equilibrium is a fixed
//! point, the analytic Jacobian matches finite differences, the slip ratio reproduces the drive
//! force, and the eigenvalue crosses zero where simulated oscillations start to grow.

use polywear::classify::Scales;
use polywear::model::{brush, tire, Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear_core::solver::{integrate, Control, SolverOptions};

/// A spread of operating points, including ones with large slip and sticking.
fn points() -> Vec<Params> {
    let mut out = Vec::new();
    for (speed, toe, load, pressure) in [
        (100.0, 0.3, 4000.0, 240.0),
        (60.0, 0.1, 2500.0, 200.0),
        (180.0, 0.8, 6500.0, 300.0),
        (250.0, 0.05, 3000.0, 420.0),
        (40.0, 1.0, 7000.0, 150.0),
    ] {
        out.push(Params {
            speed_kmh: speed,
            toe_deg: toe,
            load_n: load,
            pressure_kpa: pressure,
            ..Params::r0()
        });
    }
    out
}

fn models() -> Vec<WheelModel> {
    let mut out = Vec::new();
    for p in points() {
        for wheel in Wheel::BOTH {
            for variant in Variant::ALL {
                out.push(WheelModel::build(&p, wheel, variant).unwrap());
            }
        }
    }
    out
}

#[test]
fn equilibrium_is_a_fixed_point() {
    for m in models() {
        let eq = m.ode.equilibrium();
        let f = m.ode.rhs(&eq);
        let s = Scales::new(&m.ode);
        // Each rate relative to the natural rate scale of its state (|x| times ω ≈ 1700 1/s).
        assert!(f[0].abs() < 1e-12 * s.v, "dz/dt = {} for {m:?}", f[0]);
        assert_eq!(f[1], 0.0);
        assert!(f[2].abs() < 1e-9 * s.v * 1700.0, "dv/dt = {}", f[2]);
        // And a perturbed state is not (the test can fail).
        let g = m.ode.rhs(&[eq[0] * 1.01, eq[1], eq[2]]);
        assert!(g[0].abs() > 1e-6 * s.v);
    }
}

#[test]
fn analytic_jacobian_matches_central_differences() {
    for m in models() {
        let eq = m.ode.equilibrium();
        let s = Scales::new(&m.ode);
        // At the equilibrium and at two off-equilibrium states (w away from 0 for the kink).
        let states = [
            eq,
            [eq[0] * 0.9, eq[1] * 1.1, 0.3 * s.v],
            [eq[0] * 1.2, eq[1], -0.5 * s.v],
        ];
        let steps = [s.z * 1e-6, s.y * 1e-6, s.v * 1e-6];
        for x in states {
            let jac = m.ode.jacobian(&x);
            for col in 0..3 {
                let mut xp = x;
                let mut xm = x;
                xp[col] += steps[col];
                xm[col] -= steps[col];
                let (fp, fm) = (m.ode.rhs(&xp), m.ode.rhs(&xm));
                for row in 0..3 {
                    let fd = (fp[row] - fm[row]) / (2.0 * steps[col]);
                    let an = jac[(row, col)];
                    let scale = an.abs().max(fd.abs()).max(1e-6);
                    assert!(
                        (an - fd).abs() / scale < 1e-5,
                        "J[{row},{col}] analytic {an} vs FD {fd} at {x:?} ({:?} {:?})",
                        m.wheel,
                        m.variant
                    );
                }
            }
        }
    }
}

#[test]
fn slip_ratio_reproduces_the_drive_force() {
    for p in points() {
        let patch = tire::contact_patch(&p).unwrap();
        let m = WheelModel::build(&p, Wheel::Driving, Variant::Paper).unwrap();
        let want = brush::drive_force_n(&p);
        let got = brush::longitudinal_force_n(&p, &patch, m.slip_ratio);
        assert!(m.slip_ratio > 0.0);
        assert!(
            ((got - want) / want).abs() < 1e-10,
            "F_X(S) = {got}, F_drive = {want}"
        );
    }
}

#[test]
fn excessive_drive_force_is_no_traction_not_a_panic() {
    // A tiny car pushing a huge frontal area at top speed on one driven wheel of a light tire.
    let p = Params {
        area: 50.0,
        c_d: 5.0,
        speed_kmh: 300.0,
        n_driven: 1.0,
        load_n: 500.0,
        ..Params::r0()
    };
    match WheelModel::build(&p, Wheel::Driving, Variant::Paper) {
        Err(polywear::model::ModelFailure::NoTraction { limit, .. }) => {
            assert!(limit.drive_force_n > limit.max_force_n)
        }
        other => panic!("expected no traction, got {other:?}"),
    }
    // The follower at the same point is fine.
    assert!(WheelModel::build(&p, Wheel::Follower, Variant::Paper).is_ok());
}

/// Growth of the oscillation over 3 s from the disturbed equilibrium: the ratio of the velocity
/// amplitude in the last 0.1 s to that in the first 0.1 s.
fn growth(m: &WheelModel) -> f64 {
    let s = Scales::new(&m.ode);
    let opts = SolverOptions {
        rtol: 1e-9,
        atol: s.atol(1e-9),
        h_max: 1e-3,
        h0: None,
        max_steps: 10_000_000,
    };
    let (mut early, mut late) = (0.0f64, 0.0f64);
    integrate(
        &m.ode,
        0.0,
        [s.z_eq, s.y_eq + 1e-7, 0.0],
        3.0,
        &opts,
        |st| {
            if st.t1 < 0.1 {
                early = early.max(st.x1[2].abs());
            } else if st.t1 > 2.9 {
                late = late.max(st.x1[2].abs());
            }
            Control::Continue
        },
    )
    .unwrap();
    late / early
}

#[test]
fn eigenvalue_sign_change_is_where_oscillations_start_to_grow() {
    // Sweep speed across the lower Hopf point (≈ 93 km/h at defaults).
    let mut prev: Option<(f64, f64, f64)> = None;
    let mut crossings = 0;
    for speed in (80..=110).step_by(2) {
        let p = Params {
            speed_kmh: speed as f64,
            ..Params::r0()
        };
        let m = WheelModel::build(&p, Wheel::Follower, Variant::Paper).unwrap();
        let re = m.ode.linear_stability().eig_re_max;
        let g = growth(&m);
        // Small disturbances grow exactly where the real part is positive.
        assert_eq!(re > 0.0, g > 1.0, "speed {speed}: re {re}, growth {g}");
        if let Some((_, pre, _)) = prev {
            if pre <= 0.0 && re > 0.0 {
                crossings += 1;
            }
        }
        prev = Some((speed as f64, re, g));
    }
    assert_eq!(crossings, 1);
}

#[test]
fn hard_excitation_finds_no_cycle_where_the_hopf_points_are_supercritical() {
    use polywear::classify::{classify, Class, ClassifierOptions};
    // Both Hopf points of the default speed sweep are supercritical (the cycle is born at zero
    // amplitude), so a kick at a stable point must die out. Before MIN_CYCLE_V_REL the envelope
    // tracker took the noise floor around the equilibrium for a small "cycle" and said bistable.
    for speed in [85.0, 92.0, 224.0, 226.0, 235.0] {
        for kick in [0.05, 0.2] {
            let p = Params {
                speed_kmh: speed,
                ..Params::r0()
            };
            let m = WheelModel::build(&p, Wheel::Follower, Variant::Paper).unwrap();
            let opts = ClassifierOptions {
                kick_mps: Some(kick),
                ..ClassifierOptions::default()
            };
            let v = classify(&m.ode, WheelModel::rotation_hz(&p), &opts);
            assert_eq!(v.class, Class::Stable, "speed {speed}, kick {kick}: {v:?}");
            assert!(v.rhs_evals > 0, "the kick must have been integrated");
        }
    }
}
