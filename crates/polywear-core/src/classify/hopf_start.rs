//! Where shooting starts when no neighbouring wheel's cycle is known: on the Hopf eigenvector's
//! trace on the section (MODEL.md#step-9-attractor), at the amplitude the Hopf normal form
//! predicts from the growth of small oscillations.

use nalgebra::{Complex, Vector3};

use crate::model::TreadOde;

/// The cycle's section velocity per U that the Hopf normal form predicts for oscillations growing
/// by `growth` = Re λ·T per period: the amplitude grows as √growth (MODEL.md#step-9-attractor),
/// here with the factor 5.5 that the default study's 19,000 cycles share from growth 1e-5 to 0.1
/// (5th–95th percentile 4.8–6.7 above growth 1e-3, up to 9 below), capped short of U, where
/// the tread's sliding velocity w = v − U turns and the amplitude saturates. It only sets where
/// Newton starts: a guess 20% off costs an iteration more, not a different cycle.
pub(super) fn normal_form_section_v(growth: f64) -> f64 {
    (NORMAL_FORM_V_PER_SQRT_GROWTH * growth.sqrt()).min(0.9)
}

/// See [`normal_form_section_v`].
const NORMAL_FORM_V_PER_SQRT_GROWTH: f64 = 5.5;

/// Shooting starts from the normal form's cycle only where the growth is at least this times
/// Newton's tolerance; see [`normal_form_applies`].
const NORMAL_FORM_MIN_GROWTH_PER_NEWTON_TOL: f64 = 1e3;

/// Whether Newton may start from [`normal_form_section_v`]. Its residual test relative to v
/// passes an orbit whose amplitude is off by about newton_tol / (2·growth), since near the Hopf
/// point the return map moves every orbit by only ~growth: at growth 1.5e-8 a start 20% off
/// ended on an orbit 25% small. From 1e3·newton_tol up that error is below 5e-4; closer to
/// the Hopf point the return map along the Hopf direction brings the guess close first.
pub(super) fn normal_form_applies(growth: f64, newton_tol: f64) -> bool {
    growth >= NORMAL_FORM_MIN_GROWTH_PER_NEWTON_TOL * newton_tol
}

/// Section velocity per U where the return map's amplitude guess starts near the Hopf point.
pub(super) const GUESS_START_V_REL: f64 = 0.3;

/// Direction of the Hopf eigenvector on the section y = y_eq, as dz per unit v.
pub(super) fn hopf_dz_per_v(ode: &TreadOde, lambda: Complex<f64>) -> f64 {
    let jac = ode.jacobian(&ode.equilibrium());
    let row = |i: usize| {
        Vector3::new(
            Complex::new(jac[(i, 0)], 0.0)
                - if i == 0 {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                },
            Complex::new(jac[(i, 1)], 0.0)
                - if i == 1 {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                },
            Complex::new(jac[(i, 2)], 0.0)
                - if i == 2 {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                },
        )
    };
    // The eigenvector spans the null space of J − λI: cross product of two independent rows.
    let q = row(0).cross(&row(1));
    let q = if q.norm() > 0.0 {
        q
    } else {
        row(1).cross(&row(2))
    };
    // Rotate the phase so that the y component is purely imaginary: Re(q) then lies on y = 0.
    let rot = Complex::from_polar(1.0, std::f64::consts::FRAC_PI_2 - q[1].arg());
    let d = q.map(|c| (c * rot).re);
    if d[2] == 0.0 {
        0.0
    } else {
        d[0] / d[2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::budget::Meter;
    use crate::classify::{classify, shooting, ClassifierOptions, Scales};
    use crate::model::{Variant, Wheel, WheelModel};
    use crate::params::Params;

    /// R0 wheels past their Hopf point, from growth 1e-4 to 0.05 per period, with their
    /// growth Re λ·T.
    fn unstable_r0_wheels() -> Vec<(Wheel, Variant, Params, f64)> {
        let mut wheels = Vec::new();
        for (wheel, variant) in [
            (Wheel::Follower, Variant::Paper),
            (Wheel::Driving, Variant::SlidingShare),
        ] {
            for speed in (40..300).step_by(3) {
                let p = Params {
                    speed_kmh: f64::from(speed),
                    ..Params::r0()
                };
                let Ok(m) = WheelModel::build(&p, wheel, variant) else {
                    continue;
                };
                let lin = m.ode.linear_stability();
                let growth = lin.eig_re_max / lin.eig_freq_hz;
                if lin.eig_freq_hz > 0.0 && (1e-4..0.05).contains(&growth) {
                    wheels.push((wheel, variant, p, growth));
                }
            }
        }
        wheels
    }

    /// The premise of starting there: for most wheels the cycle's section velocity is within a
    /// factor 1.5 of the prediction, so that Newton starts inside its basin. (Near the
    /// follower's upper Hopf point, 211 km/h and up at R0, the cycle is up to 3 times larger:
    /// its growth first rises with the amplitude. Newton then gives up and the return map's
    /// guess takes over; every wheel still gets its cycle.)
    #[test]
    fn the_normal_form_puts_the_start_near_the_cycle() {
        let wheels = unstable_r0_wheels();
        assert!(wheels.len() >= 40, "{} wheels", wheels.len());
        let mut near = 0;
        for &(wheel, variant, p, growth) in &wheels {
            let m = WheelModel::build(&p, wheel, variant).unwrap();
            let v = classify(&m.ode, 1.0, &ClassifierOptions::default());
            assert!(
                v.class.vibrates(),
                "{wheel} {variant} {}: {v:?}",
                p.speed_kmh
            );
            let ratio = v.section_v_mps / Scales::new(&m.ode).v / normal_form_section_v(growth);
            assert!(
                ratio > 0.5,
                "{wheel} {variant} {} km/h: {ratio}",
                p.speed_kmh
            );
            near += usize::from(ratio < 1.5);
        }
        assert!(near * 10 >= wheels.len() * 9, "{near} of {}", wheels.len());
    }

    /// Newton from the normal form's start and Newton from the return map's amplitude guess
    /// end on the same cycle: the start only changes the work.
    #[test]
    fn newton_from_the_normal_form_finds_the_return_maps_cycle() {
        let opts = ClassifierOptions::default();
        let wheels = unstable_r0_wheels();
        let mut found = 0;
        for &(wheel, variant, p, growth) in &wheels {
            let m = WheelModel::build(&p, wheel, variant).unwrap();
            let lin = m.ode.linear_stability();
            let scales = Scales::new(&m.ode);
            let period = 1.0 / lin.eig_freq_hz;
            let tols = shooting::Tolerances::for_growth(growth, opts.rtol);
            let dz = hopf_dz_per_v(&m.ode, lin.leading);
            let meter = Meter::new(opts.budget);
            let a = normal_form_section_v(growth) * scales.v;
            let start = (scales.z_eq + a * dz, a);
            let newton = |guess, tols: &shooting::Tolerances| {
                shooting::newton_orbit(&m.ode, &scales, guess, period, tols, 1e-8, &meter)
            };
            let Ok(direct) = newton(start, &tols.looser_first()) else {
                continue;
            };
            found += 1;
            let guess = shooting::amplitude_guess(
                &m.ode,
                &scales,
                dz,
                growth.exp_m1(),
                GUESS_START_V_REL * scales.v,
                period,
                tols.guess,
                shooting::HANDOFF,
                &meter,
            )
            .expect("amplitude guess");
            let guessed = newton(guess, &tols).expect("from the amplitude guess");
            let what = format!(
                "{wheel} {variant} {} km/h: {direct:?} vs {guessed:?}",
                p.speed_kmh
            );
            let rel = |a: f64, b: f64| (a / b - 1.0).abs();
            assert!(
                rel(direct.measure.amp_v_mps, guessed.measure.amp_v_mps) < 2e-4,
                "{what}"
            );
            assert!(
                rel(direct.measure.energy_j, guessed.measure.energy_j) < 4e-4,
                "{what}"
            );
            assert!(rel(direct.period_s, guessed.period_s) < 1e-7, "{what}");
            assert!(
                (direct.floquet_max - guessed.floquet_max).abs() < 2e-3,
                "{what}"
            );
        }
        assert!(
            found * 10 >= wheels.len() * 9,
            "{found} of {}",
            wheels.len()
        );
    }
}
