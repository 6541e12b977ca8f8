//! The periodic orbit found directly: Newton's method on the Poincaré return map, with the
//! variational equations giving the monodromy matrix and so the Floquet multipliers.

use nalgebra::{Matrix2, Matrix3, Vector2};

use super::budget::Meter;
use super::section::{first_return, Return};
use super::{Scales, MIN_CYCLE_V_REL};
use crate::model::{State, TreadOde};
use crate::solver::{OdeSystem, SolverOptions, Step, Variational};

/// A converged limit cycle, represented by its point on the section y = y_eq, with what one
/// period along it measures.
#[derive(Debug, Clone, Copy)]
pub struct PeriodicOrbit {
    pub start: State,
    pub period_s: f64,
    /// Modulus of the largest non-trivial Floquet multiplier (< 1: the cycle attracts).
    pub floquet_max: f64,
    pub measure: CycleMeasure,
}

/// Amplitudes (half peak-to-peak) and energy of one period (MODEL.md step 9).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CycleMeasure {
    pub amp_y_m: f64,
    pub amp_v_mps: f64,
    /// ∮ C_s v² dt over the period [J].
    pub energy_j: f64,
}

/// y, v and their sensitivities to the start point (rows y and v of the variational matrix Φ)
/// at one time along an orbit.
#[derive(Clone, Copy)]
struct Sample {
    y: f64,
    v: f64,
    dy: [f64; 3],
    dv: [f64; 3],
}

impl Sample {
    /// From the variational state (x, Φ stored column by column).
    fn of(s: &[f64; 12]) -> Self {
        Sample {
            y: s[1],
            v: s[2],
            dy: [s[4], s[7], s[10]],
            dv: [s[5], s[8], s[11]],
        }
    }

    /// y and v on the trajectory started `d` away, to first order.
    fn shifted(&self, d: &[f64; 3]) -> (f64, f64) {
        let dot = |r: &[f64; 3]| r[0] * d[0] + r[1] * d[1] + r[2] * d[2];
        (self.y + dot(&self.dy), self.v + dot(&self.dv))
    }
}

/// Samples of one period of a variational trajectory, from which the amplitudes (half
/// peak-to-peak, 8 dense-output points per step) and the damper's energy ∮ C_s v² dt (3-point
/// Gauss–Legendre per step) follow, also for a start point shifted by a small Newton step.
struct OrbitSamples {
    extremes: Vec<Sample>,
    /// (quadrature weight × step length, sample).
    quadrature: Vec<(f64, Sample)>,
}

impl OrbitSamples {
    fn new(start: &[f64; 12]) -> Self {
        OrbitSamples {
            extremes: vec![Sample::of(start)],
            quadrature: Vec::new(),
        }
    }

    /// Adds the part [t0, t_hi] of an accepted step.
    fn add(&mut self, s: &Step<'_, 12>, t_hi: f64) {
        const GL: [(f64, f64); 3] = [
            (0.112_701_665_379_258_3, 5.0 / 18.0),
            (0.5, 8.0 / 18.0),
            (0.887_298_334_620_741_7, 5.0 / 18.0),
        ];
        let h = t_hi - s.t0;
        if h <= 0.0 {
            return;
        }
        for j in 1..=8 {
            let x = s.interpolate(s.t0 + h * j as f64 / 8.0);
            self.extremes.push(Sample::of(&x));
        }
        for (node, w) in GL {
            let x = s.interpolate(s.t0 + h * node);
            self.quadrature.push((w * h, Sample::of(&x)));
        }
    }

    /// The measure of the orbit started `d` = (dz, 0, dv) away from the sampled one, whose
    /// period is longer by `dt_s`.
    fn measure(&self, d: &[f64; 3], dt_s: f64, c_s: f64) -> CycleMeasure {
        let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut v_lo, mut v_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for smp in &self.extremes {
            let (y, v) = smp.shifted(d);
            (y_lo, y_hi) = (y_lo.min(y), y_hi.max(y));
            (v_lo, v_hi) = (v_lo.min(v), v_hi.max(v));
        }
        let mut energy = 0.0;
        for (wh, smp) in &self.quadrature {
            let v = smp.shifted(d).1;
            energy += wh * c_s * v * v;
        }
        // The stretch of the period beyond the sampled one (v there is the start's).
        let v0 = self.extremes[0].shifted(d).1;
        energy += dt_s * c_s * v0 * v0;
        CycleMeasure {
            amp_y_m: 0.5 * (y_hi - y_lo),
            amp_v_mps: 0.5 * (v_hi - v_lo),
            energy_j: energy,
        }
    }
}

/// The next return to the section, looked for between 0.3 and 30 linear periods.
fn next_return<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    start: [f64; N],
    y_sec: f64,
    linear_period_s: f64,
    opts: &SolverOptions<N>,
    meter: &Meter,
    observe: impl FnMut(&Step<'_, N>, f64),
) -> Result<Return<N>, String> {
    first_return(
        sys,
        start,
        y_sec,
        (0.3 * linear_period_s, 30.0 * linear_period_s),
        opts,
        meter,
        observe,
    )
}

/// Newton iterations before giving up.
const MAX_NEWTON: usize = 40;

/// Relative tolerance of the coarse Newton iterations (the final ones use the classifier's),
/// at most.
pub const COARSE_RTOL: f64 = 1e-6;

/// Relative tolerance of the amplitude bracketing, which only needs the sign of the growth,
/// at most.
pub const GUESS_RTOL: f64 = 1e-5;

/// Tolerances (amplitude bracketing, coarse Newton) for an equilibrium whose oscillations grow
/// by the factor 1 + `growth` per linear period (growth = Re λ · T). Near the Hopf point the
/// growth, and so 1 − the cycle's Floquet multiplier, is small: the integration error must stay
/// well below it, or the bracket reads noise and coarse Newton converges off the cycle.
pub fn coarse_tolerances(growth: f64, fine_rtol: f64) -> (f64, f64) {
    let g = growth.abs();
    (
        (1e-3 * g).clamp(fine_rtol, GUESS_RTOL),
        (1e-4 * g).clamp(fine_rtol, COARSE_RTOL),
    )
}

/// Coarse iterations end once the Newton step is below this, relative to the state scales: the
/// orbit is then known to the coarse integration's accuracy.
const COARSE_STEP_REL: f64 = 1e-3;

/// A fine iteration whose Newton step is below this (relative) ends the search: the step is
/// applied to the start point, the period and the measured period to first order through the
/// variational matrix, leaving errors of order step² (about 1e-6).
const FINE_ACCEPT_REL: f64 = 1e-3;

/// Refines a guess `(z, v)` on the section into the periodic orbit through it. The first
/// iterations integrate at `coarse_rtol`; once their steps are small, the last ones at `rtol`
/// until the return-map residual is below `newton_tol` or the Newton step below
/// [`FINE_ACCEPT_REL`]. The amplitudes, energy and period are measured along that final
/// iteration's period, corrected to first order for its last Newton step.
#[allow(clippy::too_many_arguments)]
pub fn newton_orbit(
    ode: &TreadOde,
    scales: &Scales,
    guess_z: f64,
    guess_v: f64,
    linear_period_s: f64,
    (coarse_rtol, rtol): (f64, f64),
    newton_tol: f64,
    meter: &Meter,
) -> Result<PeriodicOrbit, String> {
    let y_sec = scales.y_eq;
    let options = |rtol: f64| {
        let mut atol = [f64::INFINITY; 12];
        atol[..3].copy_from_slice(&scales.atol(rtol));
        SolverOptions {
            rtol,
            atol,
            h_max: linear_period_s / 8.0,
            h0: Some(linear_period_s / 40.0),
            max_steps: 200_000,
        }
    };
    let (fine, coarse) = (options(rtol), options(coarse_rtol.max(rtol)));
    let mut tight = coarse_rtol <= rtol;
    let (mut z, mut v) = (guess_z, guess_v);
    for iter in 0..MAX_NEWTON {
        let start = [z, y_sec, v, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut samples = OrbitSamples::new(&start);
        let opts = if tight { &fine } else { &coarse };
        let ret = next_return(
            &Variational(ode),
            start,
            y_sec,
            linear_period_s,
            opts,
            meter,
            |s, t_hi| {
                if tight {
                    samples.add(s, t_hi)
                }
            },
        )?;
        let s = ret.state;
        let x_t = [s[0], s[1], s[2]];
        let monodromy = Matrix3::from_column_slice(&s[3..12]);
        let f_t = ode.rhs(&x_t);
        // Derivative of the return map: project the flow's derivative along the vector field
        // onto the section (saltation-free: the section is crossed transversally, f_y = v > 0).
        let mut dp = monodromy;
        for col in 0..3 {
            let m_y = monodromy[(1, col)];
            for row in 0..3 {
                dp[(row, col)] -= f_t[row] * m_y / f_t[1];
            }
        }
        let reduced = Matrix2::new(dp[(0, 0)], dp[(0, 2)], dp[(2, 0)], dp[(2, 2)]);
        let g = Vector2::new(x_t[0] - z, x_t[2] - v);
        let converged =
            (g[0] / scales.z).abs() < newton_tol && (g[1] / scales.v).abs() < newton_tol;
        let jac = reduced - Matrix2::identity();
        let step = jac
            .lu()
            .solve(&(-g))
            .ok_or_else(|| "shooting: singular return-map Jacobian".to_string())?;
        let (mut dz, mut dv) = (step[0], step[1]);
        let step_rel = (dz / scales.z).abs().max((dv / v.max(scales.v)).abs());
        if tight && (converged || step_rel < FINE_ACCEPT_REL) {
            if v + dv <= MIN_CYCLE_V_REL * scales.v {
                return Err("shooting: Newton fell back onto the equilibrium".into());
            }
            // The orbit through the corrected start returns later by dT = −(M d)_y / f_y.
            let d = [dz, 0.0, dv];
            let dt_s = -(monodromy[(1, 0)] * dz + monodromy[(1, 2)] * dv) / f_t[1];
            return Ok(PeriodicOrbit {
                start: [z + dz, y_sec, v + dv],
                period_s: ret.period_s + dt_s,
                floquet_max: spectral_radius(&reduced),
                measure: samples.measure(&d, dt_s, ode.c_s),
            });
        }
        // Damp steps that would more than halve or double the amplitude.
        let limit = 0.5 * v;
        if dv.abs() > limit {
            let k = limit / dv.abs();
            dz *= k;
            dv *= k;
        }
        if converged || step_rel < COARSE_STEP_REL || iter >= MAX_NEWTON / 2 {
            tight = true;
        }
        z += dz;
        v += dv;
        if v.is_nan() || v <= MIN_CYCLE_V_REL * scales.v || !z.is_finite() {
            return Err("shooting: Newton fell back onto the equilibrium".into());
        }
    }
    Err(format!(
        "shooting: Newton did not converge in {MAX_NEWTON} iterations"
    ))
}

/// Largest modulus of a 2×2 matrix's eigenvalues.
pub fn spectral_radius(m: &Matrix2<f64>) -> f64 {
    let tr = m.trace();
    let det = m.determinant();
    let disc = tr * tr / 4.0 - det;
    if disc >= 0.0 {
        let r = disc.sqrt();
        (tr / 2.0 + r).abs().max((tr / 2.0 - r).abs())
    } else {
        det.abs().sqrt()
    }
}

/// Amplitude guess by bracketing the growth of the scalar return map v ↦ P_v(v) − v along the
/// Hopf direction, then a few Illinois (regula falsi) steps. Returns a point near the cycle.
pub fn amplitude_guess(
    ode: &TreadOde,
    scales: &Scales,
    dz_per_v: f64,
    start_amplitude: f64,
    linear_period_s: f64,
    rtol: f64,
    meter: &Meter,
) -> Result<(f64, f64), String> {
    let y_sec = scales.y_eq;
    let opts = SolverOptions {
        rtol,
        atol: scales.atol(rtol),
        h_max: linear_period_s / 8.0,
        h0: Some(linear_period_s / 40.0),
        max_steps: 200_000,
    };
    let map = |a: f64| -> Result<(f64, (f64, f64)), String> {
        // The first return lets the fast bristle mode (multiplier ~0.02 per period) die out; the
        // growth is read over the second return, which starts near the slow manifold.
        let mut x = [scales.z_eq + a * dz_per_v, y_sec, a];
        let mut growth = 0.0;
        for _ in 0..2 {
            let ret = next_return(ode, x, y_sec, linear_period_s, &opts, meter, |_, _| {})?;
            growth = ret.state[2] - x[2];
            x = ret.state;
        }
        Ok((growth, (x[0], x[2])))
    };
    let a_min = 1e-7 * scales.v;
    let a_max = 50.0 * scales.v;
    let mut a = start_amplitude;
    let (mut h, mut img) = map(a)?;
    let (mut lo, mut hi);
    if h > 0.0 {
        lo = (a, h, img);
        loop {
            a *= 2.0;
            if a > a_max {
                return Err(
                    "shooting: amplitude grows beyond 50 U; no bounded cycle bracketed".into(),
                );
            }
            (h, img) = map(a)?;
            if h <= 0.0 {
                hi = (a, h, img);
                break;
            }
            lo = (a, h, img);
        }
    } else {
        hi = (a, h, img);
        loop {
            a *= 0.25;
            if a < a_min {
                return Err(
                    "shooting: small oscillations decay although the equilibrium is unstable"
                        .into(),
                );
            }
            (h, img) = map(a)?;
            if h > 0.0 {
                lo = (a, h, img);
                break;
            }
            hi = (a, h, img);
        }
    }
    // Illinois steps on the bracket [lo (growing), hi (decaying)].
    let mut best = if lo.1.abs() < hi.1.abs() { lo } else { hi };
    let mut side = 0;
    for _ in 0..3 {
        let a_new = lo.0 - lo.1 * (hi.0 - lo.0) / (hi.1 - lo.1);
        let (h_new, img_new) = map(a_new)?;
        if h_new.abs() < best.1.abs() {
            best = (a_new, h_new, img_new);
        }
        if h_new > 0.0 {
            lo = (a_new, h_new, img_new);
            if side == 1 {
                hi.1 *= 0.5;
            }
            side = 1;
        } else {
            hi = (a_new, h_new, img_new);
            if side == -1 {
                lo.1 *= 0.5;
            }
            side = -1;
        }
        if (hi.0 - lo.0).abs() < 1e-3 * hi.0 {
            break;
        }
    }
    Ok(best.2)
}
