//! The periodic orbit found directly: Newton's method on the Poincaré return map, with the
//! variational equations giving the monodromy matrix and so the Floquet multipliers.

use nalgebra::{Matrix2, Matrix3, Vector2};

use super::section::{first_return, Return};
use super::{Scales, MIN_CYCLE_V_REL};
use crate::model::{State, TreadOde};
use crate::solver::{OdeSystem, SolverOptions, Variational};

/// A converged limit cycle, represented by its point on the section y = y_eq.
#[derive(Debug, Clone, Copy)]
pub struct PeriodicOrbit {
    pub start: State,
    pub period_s: f64,
    /// Modulus of the largest non-trivial Floquet multiplier (< 1: the cycle attracts).
    pub floquet_max: f64,
    pub rhs_evals: usize,
}

/// The next return to the section, looked for between 0.3 and 30 linear periods.
fn next_return<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    start: [f64; N],
    y_sec: f64,
    linear_period_s: f64,
    opts: &SolverOptions<N>,
) -> Result<Return<N>, String> {
    first_return(
        sys,
        start,
        y_sec,
        0.3 * linear_period_s,
        30.0 * linear_period_s,
        opts,
    )
}

/// Newton iterations before giving up.
const MAX_NEWTON: usize = 40;

/// Refines a guess `(z, v)` on the section into the periodic orbit through it.
pub fn newton_orbit(
    ode: &TreadOde,
    scales: &Scales,
    guess_z: f64,
    guess_v: f64,
    linear_period_s: f64,
    rtol: f64,
    newton_tol: f64,
) -> Result<PeriodicOrbit, String> {
    let y_sec = scales.y_eq;
    let mut atol = [f64::INFINITY; 12];
    atol[..3].copy_from_slice(&scales.atol(rtol));
    let opts = SolverOptions {
        rtol,
        atol,
        h_max: linear_period_s / 8.0,
        h0: Some(linear_period_s / 40.0),
        max_steps: 200_000,
    };
    let (mut z, mut v) = (guess_z, guess_v);
    let mut evals = 0;
    for _ in 0..MAX_NEWTON {
        let start = [z, y_sec, v, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let ret = next_return(&Variational(ode), start, y_sec, linear_period_s, &opts)?;
        evals += ret.rhs_evals;
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
        if converged {
            return Ok(PeriodicOrbit {
                start: [z, y_sec, v],
                period_s: ret.period_s,
                floquet_max: spectral_radius(&reduced),
                rhs_evals: evals,
            });
        }
        let jac = reduced - Matrix2::identity();
        let step = jac
            .lu()
            .solve(&(-g))
            .ok_or_else(|| "shooting: singular return-map Jacobian".to_string())?;
        let (mut dz, mut dv) = (step[0], step[1]);
        // Damp steps that would more than halve or double the amplitude.
        let limit = 0.5 * v;
        if dv.abs() > limit {
            let k = limit / dv.abs();
            dz *= k;
            dv *= k;
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
) -> Result<((f64, f64), usize), String> {
    let y_sec = scales.y_eq;
    let opts = SolverOptions {
        rtol,
        atol: scales.atol(rtol),
        h_max: linear_period_s / 8.0,
        h0: Some(linear_period_s / 40.0),
        max_steps: 200_000,
    };
    let mut evals = 0;
    let mut map = |a: f64| -> Result<(f64, (f64, f64)), String> {
        // The first return lets the fast bristle mode (multiplier ~0.02 per period) die out; the
        // growth is read over the second return, which starts near the slow manifold.
        let mut x = [scales.z_eq + a * dz_per_v, y_sec, a];
        let mut growth = 0.0;
        for _ in 0..2 {
            let ret = next_return(ode, x, y_sec, linear_period_s, &opts)?;
            evals += ret.rhs_evals;
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
    Ok((best.2, evals))
}
