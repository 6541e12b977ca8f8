use super::*;

/// The normal-form read-out of a drifting envelope agrees with shooting where both work:
/// just past the follower's Hopf point at R0, started at three times the cycle's amplitude.
#[test]
fn settled_cycle_extrapolates_to_the_shooting_amplitude() {
    let opts = ClassifierOptions::default();
    for speed in [93.35, 93.6] {
        let p = Params {
            speed_kmh: speed,
            ..Params::r0()
        };
        let m = WheelModel::build(&p, Wheel::Follower, Variant::Paper).unwrap();
        let rot = WheelModel::rotation_hz(&p);
        let shot = classify(&m.ode, rot, &opts);
        assert_eq!(shot.method, Method::Shooting, "{shot:?}");
        let lin = m.ode.linear_stability();
        assert!(lin.eig_re_max > 0.0 && lin.eig_re_max < 0.5, "{lin:?}");
        let scales = Scales::new(&m.ode);
        let k = 3.0;
        let start = [
            scales.z_eq + k * (shot.section_z_m - scales.z_eq),
            scales.y_eq,
            k * shot.section_v_mps,
        ];
        let meter = Meter::new(opts.budget);
        let est = settled_cycle(&m.ode, &scales, &lin, rot, start, opts.rtol, &meter).unwrap();
        let rel = (est.amp_v_mps / shot.amp_v_mps - 1.0).abs();
        assert!(
            rel < 0.1,
            "speed {speed}: {} vs {} ({rel:.3})",
            est.amp_v_mps,
            shot.amp_v_mps
        );
        assert!((est.freq_hz / shot.freq_hz - 1.0).abs() < 0.01);
    }
}
