//! The inner integration of the long-term loop (MODEL.md#the-long-term-loop): the tread ODE
//! forced by the friction change ε(t) of a fixed worn profile (MODEL.md#step-12-feedback), over
//! a whole number of revolutions, with the friction energy carried as a state so that what is
//! laid onto the profile is exactly what the integration dissipated. The window returns, for
//! each measured revolution, the energy dissipated in each of its equal sample intervals, the
//! upward crossings of v = 0 (from which the rotation number follows) and the state at its end,
//! which the next window starts from.

use crate::classify::Scales;
use crate::model::TreadOde;
use crate::numeric::Complex64;
use crate::solver::{integrate_dop853, Control, IntegrationError, OdeSystem, SolverOptions};
use crate::wear::physics::feedback::{with_friction_scale, Feedback};
use crate::wear::physics::slip::SlipPower;

/// ε as a function of the tyre angle of the element at the patch centre, tabulated on equal
/// angles over one revolution and read by linear interpolation. The profile enters through its
/// harmonics, ε = Σ_n Re\[e_n R_n e^{inθ}\] (MODEL.md#step-12-feedback), so that ε is as smooth
/// as the trigonometric interpolant of the cells: the cells' own steps, fed back as they are,
/// put a kink in ε at every cell boundary the zone's edges cross, and the integrator would
/// take twenty times the steps to follow them.
#[derive(Debug, Clone)]
pub struct EpsilonTable {
    values: Vec<f64>,
    /// dε/dθ at the same points \[1/rad\].
    slopes: Vec<f64>,
    per_rad: f64,
}

impl EpsilonTable {
    /// The table of `points` values for the profile with harmonics `harmonics` (R_1, R_2, ...)
    /// under `feedback`.
    pub fn new(feedback: &Feedback, harmonics: &[Complex64], points: usize) -> Self {
        let forced: Vec<Complex64> = harmonics
            .iter()
            .enumerate()
            .map(|(k, r)| feedback.forcing_per_radius((k + 1) as f64) * r)
            .collect();
        let d = std::f64::consts::TAU / points as f64;
        let mut values = vec![0.0; points];
        let mut slopes = vec![0.0; points];
        for (i, c) in forced.iter().enumerate() {
            let order = (i + 1) as f64;
            // One complex product per point, renormalised every 64 points.
            let step = Complex64::from_polar(1.0, order * d);
            let mut phasor = Complex64::new(1.0, 0.0);
            for k in 0..points {
                if k % 64 == 0 {
                    phasor = Complex64::from_polar(1.0, order * k as f64 * d);
                }
                let z = c * phasor;
                values[k] += z.re;
                slopes[k] -= order * z.im;
                phasor *= step;
            }
        }
        EpsilonTable {
            values,
            slopes,
            per_rad: points as f64 / std::f64::consts::TAU,
        }
    }

    /// A table of ε = 0 (no feedback).
    pub fn zero() -> Self {
        EpsilonTable {
            values: vec![0.0],
            slopes: vec![0.0],
            per_rad: 1.0 / std::f64::consts::TAU,
        }
    }

    /// ε at tyre angle `angle_rad` (any real angle: the table is periodic), by cubic Hermite
    /// interpolation of the values and slopes: ε and dε/dθ are continuous, so the integrator's
    /// steps are set by the tread, not by the table.
    #[inline(always)]
    pub fn at(&self, angle_rad: f64) -> f64 {
        let n = self.values.len();
        let x = wrap(angle_rad * self.per_rad, n as f64);
        let i = (x as usize).min(n - 1);
        let t = x - i as f64;
        let j = if i + 1 == n { 0 } else { i + 1 };
        let h = 1.0 / self.per_rad;
        let (y0, y1) = (self.values[i], self.values[j]);
        let (m0, m1) = (self.slopes[i] * h, self.slopes[j] * h);
        let t2 = t * t;
        let t3 = t2 * t;
        (2.0 * t3 - 3.0 * t2 + 1.0) * y0
            + (t3 - 2.0 * t2 + t) * m0
            + (-2.0 * t3 + 3.0 * t2) * y1
            + (t3 - t2) * m1
    }

    /// The largest |ε| of the table.
    pub fn max_abs(&self) -> f64 {
        self.values.iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// `y` reduced into \[0, `n`) for a whole `n` > 0: the same value as `y.rem_euclid(n)`, bit for
/// bit for y ≥ 0 (the angles of a window; below 0 a zero may come out +0 where it gives −0),
/// without its general remainder (a software loop that took a twentieth of a window's
/// time). The quotient truncated to a whole k, y − k·n is exact (k·n is a whole number below
/// 2⁵³, and Sterbenz's lemma holds for the subtraction), so a quotient rounded up to the next
/// whole number only leaves a negative remainder, which adding `n` brings back exactly as
/// `rem_euclid` does.
#[inline(always)]
fn wrap(y: f64, n: f64) -> f64 {
    let k = (y / n) as i64 as f64;
    let x = y - k * n;
    if x < 0.0 {
        x + n
    } else {
        x
    }
}

/// The friction levels never fall below this share of their unforced values: a profile deep
/// enough to lift the patch off (κ r → −1) is outside what the foundation model describes.
const MIN_FRICTION_SCALE: f64 = 0.05;

/// The forced tread with its angle and friction energy as states: (z, y, v, Ω t, E).
struct ForcedWithEnergy<'a> {
    ode: TreadOde,
    epsilon: &'a EpsilonTable,
    omega_rad_per_s: f64,
}

impl OdeSystem<5> for ForcedWithEnergy<'_> {
    /// The angle and the energy take no part in the step control: the tread's three states
    /// keep the tolerance they have everywhere else.
    const ERROR_NORM_COMPONENTS: usize = 3;

    #[inline(always)]
    fn rhs(&self, s: &[f64; 5]) -> [f64; 5] {
        let eps = self.epsilon.at(s[3]).max(MIN_FRICTION_SCALE - 1.0);
        let ode = with_friction_scale(&self.ode, eps);
        let x = [s[0], s[1], s[2]];
        let f = ode.rhs(&x);
        let force_n = ode.sigma0 * x[0] + ode.sigma1 * f[0];
        let power_w = force_n * (x[2] - ode.u_mps);
        [f[0], f[1], f[2], self.omega_rad_per_s, power_w]
    }
}

/// What one window integrates.
#[derive(Debug, Clone, Copy)]
pub struct WindowRequest<'a> {
    /// The unforced tread.
    pub ode: &'a TreadOde,
    /// ε of the profile.
    pub epsilon: &'a EpsilonTable,
    /// The wheel's rotation frequency f_rot \[Hz\].
    pub rotation_hz: f64,
    /// The state (z, y, v) at the start, with the element at the patch centre at angle 0.
    pub start: [f64; 3],
    /// Revolutions integrated first and not measured (the transient after a profile update).
    pub skip_revs: usize,
    /// Revolutions measured.
    pub revs: usize,
    /// Sample intervals per revolution.
    pub samples_per_rev: usize,
    /// Relative tolerance of the integration.
    pub rtol: f64,
    /// The tread's period \[s\] (the cycle's, or the linear one): steps stay under an eighth.
    pub period_s: f64,
    /// Most steps the window may take.
    pub max_steps: usize,
}

/// What one window gives.
#[derive(Debug, Clone)]
pub struct Window {
    /// `energy_j[j][k]`: the energy \[J\] dissipated in sample interval k of measured
    /// revolution j (centre angles from 2πk/N to 2π(k+1)/N).
    pub energy_j: Vec<Vec<f64>>,
    /// Times \[s\] of the upward crossings of v = 0 in the measured revolutions, from the
    /// window's start.
    pub crossings_s: Vec<f64>,
    /// Start and end \[s\] of the measured revolutions.
    pub measured_s: (f64, f64),
    /// The state (z, y, v) at the end (angle 0 again).
    pub end: [f64; 3],
    /// The largest |v| \[m/s\] at the ends of the measured steps (a cycle or a forced wobble).
    pub peak_v_mps: f64,
    /// Right-hand-side evaluations spent.
    pub rhs_evals: usize,
}

impl Window {
    /// The print of order `order`: the harmonic of the energy laid per sample interval over the
    /// measured revolutions, over its mean, with the intervals' averaging (sinc(πn/N)) taken
    /// out, so that the power's stationary part P̄(1 + Re\[p e^{inθ}\]) gives p
    /// (MODEL.md#the-locked-print).
    pub fn print(&self, order: u32) -> Complex64 {
        let Some(first) = self.energy_j.first() else {
            return Complex64::new(0.0, 0.0);
        };
        let mut cells = vec![0.0; first.len()];
        for rev in &self.energy_j {
            cells.iter_mut().zip(rev).for_each(|(c, e)| *c += e);
        }
        let mean = cells.iter().sum::<f64>() / cells.len() as f64;
        let x = std::f64::consts::PI * order as f64 / cells.len() as f64;
        let harmonic = super::profile::harmonics_of(&cells, order as usize)[order as usize - 1];
        harmonic / mean / (x.sin() / x)
    }
}

/// Integrates one window (see [`WindowRequest`]).
pub fn integrate_window(req: &WindowRequest<'_>) -> Result<Window, IntegrationError> {
    let t_rev = 1.0 / req.rotation_hz;
    let sys = ForcedWithEnergy {
        ode: *req.ode,
        epsilon: req.epsilon,
        omega_rad_per_s: std::f64::consts::TAU * req.rotation_hz,
    };
    let scales = Scales::new(req.ode);
    let [az, ay, av] = scales.atol(req.rtol);
    let opts = SolverOptions::per_period(
        req.rtol,
        [az, ay, av, f64::INFINITY, f64::INFINITY],
        req.period_s,
        req.max_steps,
    );
    let n = req.samples_per_rev;
    let t_measured = req.skip_revs as f64 * t_rev;
    let t_end = (req.skip_revs + req.revs) as f64 * t_rev;
    let dt = t_rev / n as f64;
    let sample_time = |i: usize| t_measured + i as f64 * dt;
    let total_samples = req.revs * n;
    let mut energies = Vec::with_capacity(total_samples);
    let mut last_energy = f64::NAN;
    let mut next = 0usize;
    let mut crossings = Vec::new();
    let mut peak_v_mps = 0.0f64;
    let x0 = [req.start[0], req.start[1], req.start[2], 0.0, 0.0];
    let outcome = integrate_dop853(&sys, 0.0, x0, t_end, &opts, |step| {
        while next <= total_samples {
            // The last sample is the end of the window itself.
            let t = if next == total_samples {
                t_end
            } else {
                sample_time(next)
            };
            if t > step.t1 {
                break;
            }
            let [e] = step.interpolate_components(t, [4]);
            if next > 0 {
                energies.push(e - last_energy);
            }
            last_energy = e;
            next += 1;
        }
        if step.t1 > t_measured {
            peak_v_mps = peak_v_mps.max(step.x1[2].abs());
        }
        if step.t1 > t_measured && step.x0[2] < 0.0 && step.x1[2] >= 0.0 {
            let t = upward_zero(step.t0, step.t1, |t| step.interpolate_components(t, [2])[0]);
            if t >= t_measured {
                crossings.push(t);
            }
        }
        Control::Continue
    })?;
    let energy_j = energies.chunks(n).map(<[f64]>::to_vec).collect();
    Ok(Window {
        energy_j,
        crossings_s: crossings,
        measured_s: (t_measured, t_end),
        end: [outcome.x[0], outcome.x[1], outcome.x[2]],
        peak_v_mps,
        rhs_evals: outcome.rhs_evals,
    })
}

/// The time in \[t0, t1\] where `v` rises through 0 (v(t0) < 0 ≤ v(t1)), by bisection to
/// double precision in time.
fn upward_zero(t0: f64, t1: f64, v: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (t0, t1);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if v(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The slip power's share of a revolution's energy, laid as the loop lays the friction
/// power's: here, beside the ε table it follows, so that the wear physics needs no loop type.
impl SlipPower {
    /// Adds the slip power's energy to one revolution's energy samples \[J\] (`energy_j[k]` the
    /// interval k of N, centred on the angle 2π(k + ½)/N, as a `DepositPlan` with offset ½ lays
    /// it), the zone total following the profile's `epsilon` at that angle, for a revolution
    /// of `t_rev_s` seconds. Nothing for a wheel without slip power.
    pub fn add_to_revolution(&self, energy_j: &mut [f64], epsilon: &EpsilonTable, t_rev_s: f64) {
        if self.power_w <= 0.0 {
            return;
        }
        let n = energy_j.len() as f64;
        let dt = t_rev_s / n;
        for (k, e) in energy_j.iter_mut().enumerate() {
            let angle = std::f64::consts::TAU * (k as f64 + 0.5) / n;
            *e += self.power_w * (1.0 + self.gain * epsilon.at(angle)) * dt;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Variant, Wheel, WheelModel};
    use crate::params::Params;

    /// The table of a harmonic profile is ε = Re\[e_n R e^{inθ}\] between its points and
    /// wraps around the revolution.
    #[test]
    fn epsilon_table_is_the_forcing_of_the_profile() {
        let p = Params::default();
        let m = WheelModel::build(&p, Wheel::Follower, Variant::SlidingShare).unwrap();
        let fb = Feedback::new(&p, &m, crate::wear::WearZone::Trailing);
        let mut h = vec![Complex64::new(0.0, 0.0); 40];
        let r = Complex64::new(3e-6, -1e-6);
        h[18] = r;
        let t = EpsilonTable::new(&fb, &h, 1024);
        let e = fb.forcing_per_radius(19.0) * r;
        for theta in [0.0, 0.3, 1.234, 6.0, -2.0, 9.0] {
            let want = (e * Complex64::from_polar(1.0, 19.0 * theta)).re;
            assert!((t.at(theta) - want).abs() < 1e-4 * e.norm(), "{theta}");
        }
        assert!((t.max_abs() - e.norm()).abs() < 1e-3 * e.norm());
        assert_eq!(EpsilonTable::zero().at(1.0), 0.0);
    }

    /// The reduction of the table's angle is `rem_euclid` bit for bit at the whole numbers, an
    /// ulp either side of them and over the angles a window reaches; below 0 the same value.
    #[test]
    fn wrap_is_rem_euclid_bit_for_bit() {
        let n = 1024.0;
        let mut ys = vec![
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            n,
            -n,
            3.0 * n,
            40.0 * n,
            -7.5 * n,
        ];
        for k in -50..=50 {
            let y = k as f64 * n;
            let b = y.to_bits();
            ys.push(y);
            if k != 0 {
                ys.extend([f64::from_bits(b + 1), f64::from_bits(b - 1)]);
            }
        }
        let mut y = -3.0 * n;
        while y < 60.0 * n {
            ys.push(y);
            y += 0.618_033_988_749_895 * 37.0;
        }
        for y in ys {
            let (got, want) = (wrap(y, n), y.rem_euclid(n));
            assert_eq!(got, want, "{y:e}");
            if y >= 0.0 {
                assert_eq!(got.to_bits(), want.to_bits(), "{y:e}");
            }
        }
    }

    /// Unforced, the energy of a window at the equilibrium is P₀ times the time, sample by
    /// sample, and the state stays at the equilibrium.
    #[test]
    fn the_equilibrium_dissipates_its_power_in_every_sample() {
        let p = Params {
            speed_kmh: 60.0,
            ..Params::default()
        };
        let m = WheelModel::build(&p, Wheel::Follower, Variant::SlidingShare).unwrap();
        let eq = m.ode.equilibrium();
        let f_rot = WheelModel::rotation_hz(&p);
        let w = integrate_window(&WindowRequest {
            ode: &m.ode,
            epsilon: &EpsilonTable::zero(),
            rotation_hz: f_rot,
            start: eq,
            skip_revs: 1,
            revs: 2,
            samples_per_rev: 64,
            rtol: 1e-9,
            period_s: 1.0 / m.ode.linear_stability().eig_freq_hz,
            max_steps: 1_000_000,
        })
        .unwrap();
        let p0 = crate::wear::physics::law::equilibrium_power_w(&m.ode);
        let de = p0 / f_rot / 64.0;
        assert_eq!(w.energy_j.len(), 2);
        for rev in &w.energy_j {
            assert_eq!(rev.len(), 64);
            for e in rev {
                assert!((e / de - 1.0).abs() < 1e-9, "{e} vs {de}");
            }
        }
        assert!(w.crossings_s.is_empty());
        assert!((w.end[1] / eq[1] - 1.0).abs() < 1e-9);
    }
}
