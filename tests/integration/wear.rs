//! The wear stage (MODEL.md#step-10-wear-law to #step-12-feedback, #polygonal-wear) held to the
//! predictions of its specification: the sign and balance of the friction power, the even wear
//! equal to its calibration (P4), the patch filter's transfers (P5). Reference tests run on R0
//! with the wear constants they need set explicitly, so that shipped defaults can move.

use polywear::classify::budget::Meter;
use polywear::classify::{classify_point, ClassifierOptions, WheelVerdict};
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::Params;
use polywear::wear::calibration::reference_params;
use polywear::wear::cycle::SampledCycle;
use polywear::wear::law::{deposit_revolution, friction_force_n, friction_power_w};
use polywear::wear::zone::{parabolic_gain, pressure_transfer, sinc};
use polywear::wear::{Calibration, WearZone, ZoneGeometry};

/// R0 with the wear constants of these tests.
fn r0(share: f64) -> Params {
    Params {
        wear_share_straight: share,
        wear_rate_ref_mm_per_1000km: 0.12,
        speed_spread_kmh: 0.0,
        seed_runout_um: 2.0,
        visible_depth_mm: 0.5,
        foundation_stiffness_factor: 3.0,
        radial_stiffness_factor: 1.0,
        ..Params::r0()
    }
}

fn classified(p: &Params, wheel: Wheel) -> (WheelModel, WheelVerdict) {
    let (m, v) = classify_point(
        p,
        wheel,
        Variant::SlidingShare,
        &ClassifierOptions::default(),
    );
    (m.unwrap(), v)
}

/// P = F·w is positive at every instant of the reference cycle (both wheels, R0 and shipped),
/// and its mean is the energy balance −U F̄ − C_s⟨v²⟩, computed from other quantities.
#[test]
fn friction_power_is_positive_and_balances_on_the_reference_cycle() {
    for base in [r0(1.0), Params::default()] {
        for wheel in Wheel::BOTH {
            let (m, v) = classified(&base, wheel);
            assert!(v.class.vibrates(), "{wheel}: {v:?}");
            let meter = Meter::new(ClassifierOptions::default().budget);
            let cycle = SampledCycle::integrate(&m.ode, &v, 512, &meter).unwrap();
            let n = cycle.samples.len() as f64;
            let (mut p_mean, mut f_mean, mut v2_mean, mut p_min) = (0.0, 0.0, 0.0, f64::MAX);
            for s in &cycle.samples {
                let p = friction_power_w(&m.ode, &s.x);
                p_min = p_min.min(p);
                p_mean += p / n;
                f_mean += friction_force_n(&m.ode, &s.x) / n;
                v2_mean += s.x[2] * s.x[2] / n;
            }
            assert!(p_min > 0.0, "{wheel}: P reaches {p_min} W");
            let balance = -m.ode.u_mps * f_mean - m.ode.c_s * v2_mean;
            assert!(
                (p_mean / balance - 1.0).abs() < 1e-9,
                "{wheel}: P̄ = {p_mean} W, −U F̄ − C_s⟨v²⟩ = {balance} W"
            );
            // The damper's share is the classifier's energy per cycle.
            let damper = m.ode.c_s * v2_mean / v.freq_hz;
            assert!(
                (damper / v.energy_per_cycle_j - 1.0).abs() < 1e-4,
                "{wheel}"
            );
        }
    }
}

/// P4: at the reference point the even wear is φ_s·w′₀ (to 1e-9), for any φ_s; elsewhere it is
/// ∝ P̄/V, P̄ from an independent sampling of the cycle (vibrating) or U² g/w_t (stable).
#[test]
fn even_wear_reproduces_its_calibration() {
    use polywear::wear::law::{even_wear_m_per_m, MM_PER_1000KM_PER_M_PER_M};
    let opts = ClassifierOptions::default();
    let mean_power = |m: &WheelModel, v: &WheelVerdict, samples: usize| {
        if v.class.vibrates() {
            let meter = Meter::new(opts.budget);
            SampledCycle::integrate(&m.ode, v, samples, &meter)
                .unwrap()
                .mean_power_w(&m.ode, &meter)
        } else {
            let u = m.ode.u_mps;
            u * u * m.ode.stribeck(u) / u
        }
    };
    for share in [1.0, 0.37] {
        let base = r0(share);
        let cal = Calibration::at_reference(&base, Variant::SlidingShare, &opts).unwrap();
        let even_at = |p: &Params| {
            let (m, v) = classified(p, Wheel::Follower);
            let w = even_wear_m_per_m(
                cal.gamma_m3_per_j(p),
                mean_power(&m, &v, 32),
                m.patch.width_m,
                p.speed_mps(),
                p.r_b,
            );
            (w * MM_PER_1000KM_PER_M_PER_M, m, v)
        };
        let (at_ref, m_ref, v_ref) = even_at(&reference_params(&base));
        let want = share * 0.12;
        assert!(
            (at_ref / want - 1.0).abs() < 1e-9,
            "φ_s {share}: {at_ref} vs {want}"
        );
        let p_ref = mean_power(&m_ref, &v_ref, 64);
        for speed_kmh in [70.0, 130.0] {
            let p = Params {
                speed_kmh,
                ..reference_params(&base)
            };
            let (e, m, v) = even_at(&p);
            let expected = want
                * (mean_power(&m, &v, 64) / p_ref)
                * (100.0 / speed_kmh)
                * (m_ref.patch.width_m / m.patch.width_m);
            assert!(
                (e / expected - 1.0).abs() < 1e-6,
                "{speed_kmh} km/h ({}): {e} vs {expected}",
                v.class
            );
        }
    }
}

/// P4, energy conservation: laying one revolution of the reference cycle's power onto the
/// circumference wears the volume γ ∫P dt, to 1e-9, through every zone.
#[test]
fn wear_volume_is_gamma_times_the_energy() {
    let base = r0(1.0);
    let cal =
        Calibration::at_reference(&base, Variant::SlidingShare, &ClassifierOptions::default())
            .unwrap();
    let (m, v) = classified(&base, Wheel::Follower);
    let meter = Meter::new(ClassifierOptions::default().budget);
    let cycle = SampledCycle::integrate(&m.ode, &v, 64, &meter).unwrap();
    // P over one revolution: the cycle's samples repeated (the revolution is not a whole number
    // of periods, so the power at t is that at t mod T, read off the nearest sample).
    let t_rev = std::f64::consts::TAU * base.r_b / base.speed_mps();
    let per_rev = 20_000;
    let power: Vec<f64> = (0..per_rev)
        .map(|j| {
            let t = (j as f64 * t_rev / per_rev as f64) % cycle.period_s;
            let k = ((t / cycle.period_s * 64.0).round() as usize) % 64;
            friction_power_w(&m.ode, &cycle.samples[k].x)
        })
        .collect();
    let energy_j = power.iter().sum::<f64>() * t_rev / per_rev as f64;
    for zone in WearZone::ALL {
        let g = ZoneGeometry::new(zone, m.patch.length_m, m.friction.q);
        let cells = 1024;
        let gamma = cal.gamma_m3_per_j(&base);
        let depth = deposit_revolution(
            gamma,
            m.patch.width_m,
            base.speed_mps(),
            base.r_b,
            &g,
            &power,
            cells,
        );
        let volume = depth.iter().sum::<f64>() * m.patch.width_m * base.r_b * std::f64::consts::TAU
            / cells as f64;
        assert!((volume / (gamma * energy_j) - 1.0).abs() < 1e-9, "{zone}");
        // The mean depth is one revolution of even wear.
        let even = gamma * energy_j
            / t_rev
            / (m.patch.width_m * base.speed_mps() * std::f64::consts::TAU * base.r_b);
        let mean = depth.iter().sum::<f64>() / cells as f64;
        assert!((mean / (even * std::f64::consts::TAU * base.r_b) - 1.0).abs() < 1e-9);
    }
}

/// P5: the zones' transfers are the closed forms (sin u/u, 3(sin u − u cos u)/u³) for n = 5..30
/// to 1e-6, with the values at the default patch worked by hand: 0.9910, −0.0210, −0.2147 at
/// n = 19, and the whole patch's first zero at u = 4.4934 (n = 18.37).
#[test]
fn patch_filter_transfers() {
    let p = Params::default();
    let m = WheelModel::build(&p, Wheel::Follower, Variant::SlidingShare).unwrap();
    let a = m.patch.length_m;
    let lw = 0.05 * a; // q = 0.033 < q_min
    for n in 5..=30 {
        let nf = n as f64;
        let trailing = ZoneGeometry::new(WearZone::Trailing, a, m.friction.q);
        let whole = ZoneGeometry::new(WearZone::WholePatch, a, m.friction.q);
        let uniform = ZoneGeometry::new(WearZone::WholePatchUniform, a, m.friction.q);
        let u = |l: f64| nf * l / (2.0 * p.r_b);
        let closed = [
            (trailing, (u(lw)).sin() / u(lw)),
            (whole, 3.0 * (u(a).sin() - u(a) * u(a).cos()) / u(a).powi(3)),
            (uniform, u(a).sin() / u(a)),
        ];
        for (g, want) in closed {
            assert!(
                (g.transfer(nf, p.r_b).norm() - want.abs()).abs() < 1e-6,
                "{} n {n}",
                g.zone
            );
            assert!((g.gain(nf, p.r_b) - want).abs() < 1e-6);
        }
        assert!((pressure_transfer(nf, a, p.r_b) - closed[1].1).abs() < 1e-12);
    }
    let at19 = |z: WearZone| ZoneGeometry::new(z, a, m.friction.q).gain(19.0, p.r_b);
    assert!((at19(WearZone::Trailing) - 0.9910).abs() < 1e-4);
    assert!((at19(WearZone::WholePatch) + 0.0210).abs() < 1e-4);
    assert!((at19(WearZone::WholePatchUniform) + 0.2147).abs() < 1e-4);
    let zero_n = 4.493_409_457_909 * 2.0 * p.r_b / a;
    assert!(parabolic_gain(4.493_409_457_909).abs() < 1e-12);
    assert!((zero_n - 18.37).abs() < 0.01, "{zero_n}");
    assert!(sinc(std::f64::consts::PI).abs() < 1e-15);
}
