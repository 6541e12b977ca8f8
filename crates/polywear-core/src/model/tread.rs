//! The tread's lateral dynamics with LuGre friction (MODEL.md#step-6-tread-ode to
//! #step-8-linear-stability; paper Eqs. 18–26):
//! right-hand side, equilibrium, analytic Jacobian and its eigenvalues.

use nalgebra::{Complex, Matrix3};

use super::Variant;

/// State x = (z, y, v): mean bristle deflection z \[m\], lateral tread displacement y \[m\] and
/// lateral tread velocity v = dy/dt [m/s].
pub type State = [f64; 3];

/// Coefficients of the 3-state tread ODE for one wheel at one operating point. Plain numbers,
/// built once per wheel by [`super::WheelModel::build`], evaluated millions of times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreadOde {
    /// LuGre bristle stiffness σ0 = K_s [N/m].
    pub sigma0: f64,
    /// Tread lateral stiffness K_s [N/m].
    pub k_s: f64,
    /// Tread mass m \[kg\].
    pub mass_kg: f64,
    /// Tread lateral damping C_s [N s/m].
    pub c_s: f64,
    /// LuGre bristle damping σ1 [N s/m].
    pub sigma1: f64,
    /// Maximum static friction level F_m \[N\].
    pub f_m: f64,
    /// Sliding friction level F_s \[N\].
    pub f_s: f64,
    /// Stribeck speed [m/s].
    pub v_s: f64,
    /// Stribeck index.
    pub phi: f64,
    /// Road lateral speed under the tread, U = V sin α [m/s].
    pub u_mps: f64,
    /// Longitudinal sliding speed seen by the Stribeck curve [m/s]: 0 under `paper`, see
    /// [`super::longitudinal_sliding_mps`].
    pub v_sx_mps: f64,
    /// The friction variant (how w_t is formed).
    pub variant: Variant,
}

/// Largest |w| and V_sx for which w² + V_sx² neither overflows nor loses V_sx to underflow, so
/// that the plain square root equals `hypot` to within an ulp.
const PLAIN_SQRT_MAX: f64 = 1e150;
const PLAIN_SQRT_MIN: f64 = 1e-150;

/// The pieces of one evaluation at a state that the RHS and the Jacobian share: the sliding
/// speed, its slope, and the Stribeck curve's level and slope there.
#[derive(Debug, Clone, Copy)]
struct Friction {
    w: f64,
    w_t: f64,
    dwt_dw: f64,
    g: f64,
    dg: f64,
}

impl TreadOde {
    /// Sliding speed seen by the Stribeck curve w_t and its derivative d w_t / d w (step 6).
    /// With no longitudinal sliding (the follower, S = 0, and the `paper` variant) w_t = |w|;
    /// otherwise w_t = √(w² + V_sx²), as a plain square root where the squares can neither
    /// overflow nor underflow (speeds in m/s are far from both), else through `hypot`.
    #[inline(always)]
    pub fn sliding_speed(&self, w: f64) -> (f64, f64) {
        let b = self.v_sx_mps;
        if self.variant == Variant::Paper || b == 0.0 {
            return (w.abs(), if w >= 0.0 { 1.0 } else { -1.0 });
        }
        let wt = if w.abs() < PLAIN_SQRT_MAX && (PLAIN_SQRT_MIN..PLAIN_SQRT_MAX).contains(&b.abs())
        {
            (w * w + b * b).sqrt()
        } else {
            w.hypot(b)
        };
        (wt, if wt > 0.0 { w / wt } else { 1.0 })
    }

    /// (w_t/V_s)^φ as exp(φ ln(w_t/V_s)): one `ln` and one `exp`, cheaper than `powf`; its
    /// relative error is about |φ ln(w_t/V_s)| ulp, within 1e-14 over the speeds the tread
    /// sees (tested against `powf`). 0 at w_t = 0 (φ > 0).
    #[inline(always)]
    fn stribeck_power(&self, w_t: f64) -> f64 {
        (self.phi * (w_t / self.v_s).ln()).exp()
    }

    /// Stribeck curve g(w_t) = F_s + (F_m − F_s) exp(−(w_t/V_s)^φ) (Eq. 20).
    #[inline(always)]
    pub fn stribeck(&self, w_t: f64) -> f64 {
        self.f_s + (self.f_m - self.f_s) * (-self.stribeck_power(w_t)).exp()
    }

    /// g and dg/dw_t together from one evaluation of the curve's exponential: dg/dw_t =
    /// −(F_m − F_s) e^{−x^φ} φ x^φ / w_t with x = w_t/V_s.
    #[inline(always)]
    fn stribeck_with_slope(&self, w_t: f64) -> (f64, f64) {
        if w_t == 0.0 {
            // The slope is unbounded at rest for φ < 1; the Jacobian uses the one-sided value 0
            // there (it is only reached on a measure-zero set of trajectories).
            return (self.f_m, 0.0);
        }
        let xp = self.stribeck_power(w_t);
        let e = (self.f_m - self.f_s) * (-xp).exp();
        (self.f_s + e, -e * self.phi * xp / w_t)
    }

    #[inline(always)]
    fn friction(&self, v: f64) -> Friction {
        let w = v - self.u_mps;
        let (w_t, dwt_dw) = self.sliding_speed(w);
        let (g, dg) = self.stribeck_with_slope(w_t);
        Friction {
            w,
            w_t,
            dwt_dw,
            g,
            dg,
        }
    }

    /// Right-hand side of Eq. 21: (dz/dt, dy/dt, dv/dt).
    #[inline(always)]
    pub fn rhs(&self, x: &State) -> State {
        let w = x[2] - self.u_mps;
        let (w_t, _) = self.sliding_speed(w);
        let g = self.stribeck(w_t);
        self.rhs_with(x, w, w_t, g)
    }

    #[inline(always)]
    fn rhs_with(&self, x: &State, w: f64, w_t: f64, g: f64) -> State {
        let [z, y, v] = *x;
        let dz = w - self.sigma0 * w_t * z / g;
        let dv = -(self.c_s * v + self.k_s * y + self.sigma0 * z + self.sigma1 * dz) / self.mass_kg;
        [dz, v, dv]
    }

    /// The right-hand side and the Jacobian at one state from one evaluation of the sliding
    /// speed and the Stribeck curve (what the variational equations need at every stage).
    #[inline(always)]
    pub fn rhs_and_jacobian(&self, x: &State) -> (State, Matrix3<f64>) {
        let fr = self.friction(x[2]);
        (
            self.rhs_with(x, fr.w, fr.w_t, fr.g),
            self.jacobian_with(x, &fr),
        )
    }

    /// Analytic Jacobian ∂f/∂x (Eqs. 23–25). At w = 0 (paper variant) the right derivative is used.
    #[inline]
    pub fn jacobian(&self, x: &State) -> Matrix3<f64> {
        self.jacobian_with(x, &self.friction(x[2]))
    }

    #[inline(always)]
    fn jacobian_with(&self, x: &State, fr: &Friction) -> Matrix3<f64> {
        let z = x[0];
        let Friction {
            w_t, dwt_dw, g, dg, ..
        } = *fr;
        let dfz_dz = -self.sigma0 * w_t / g;
        let dfz_dv = 1.0 - self.sigma0 * z * dwt_dw * (g - w_t * dg) / (g * g);
        let m = self.mass_kg;
        Matrix3::new(
            dfz_dz,
            0.0,
            dfz_dv,
            0.0,
            0.0,
            1.0,
            -(self.sigma0 + self.sigma1 * dfz_dz) / m,
            -self.k_s / m,
            -(self.c_s + self.sigma1 * dfz_dv) / m,
        )
    }

    /// Equilibrium of Eq. 22: v = 0, z0 = −(U / w_t0) g(w_t0) / σ0, y0 = −σ0 z0 / K_s.
    pub fn equilibrium(&self) -> State {
        let (w_t0, _) = self.sliding_speed(-self.u_mps);
        let z0 = -(self.u_mps / w_t0) * self.stribeck(w_t0) / self.sigma0;
        [z0, -self.sigma0 * z0 / self.k_s, 0.0]
    }

    /// Eigenvalues of the Jacobian at the equilibrium (step 8), largest real part first.
    pub fn eigenvalues(&self) -> [Complex<f64>; 3] {
        let jac = self.jacobian(&self.equilibrium());
        // Bounded QR iterations: the unbounded ones never return for some degenerate Jacobians
        // (toe-in 1e-200°). Without convergence the eigenvalues are NaN, and the
        // classifier says so in a `failed` row.
        let Some(schur) = jac.try_schur(f64::EPSILON, 10_000) else {
            return [Complex::new(f64::NAN, f64::NAN); 3];
        };
        let ev = schur.complex_eigenvalues();
        let mut out = [ev[0], ev[1], ev[2]];
        // Leading first; within a complex pair the one with positive imaginary part first.
        out.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
        out
    }
}

/// The leading eigenvalue in the units people read: growth rate and linear frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearStability {
    /// Largest real part [1/s]; positive means the equilibrium is unstable.
    pub eig_re_max: f64,
    /// |Im|/2π of that eigenvalue \[Hz\]; 0 when it is real.
    pub eig_freq_hz: f64,
    /// The leading eigenvalue itself.
    pub leading: Complex<f64>,
}

impl TreadOde {
    /// The leading eigenvalue at the equilibrium as growth rate and frequency.
    pub fn linear_stability(&self) -> LinearStability {
        let ev = self.eigenvalues();
        let leading = ev[0];
        LinearStability {
            eig_re_max: leading.re,
            eig_freq_hz: leading.im.abs() / (2.0 * std::f64::consts::PI),
            leading,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Wheel, WheelModel};
    use crate::params::Params;

    fn driving_sliding_share() -> TreadOde {
        let m = WheelModel::build(&Params::default(), Wheel::Driving, Variant::SlidingShare);
        let ode = m.unwrap().ode;
        assert!(ode.v_sx_mps > 0.0, "{ode:?}");
        ode
    }

    /// The curve g and its slope through exp(φ ln x) against the `powf` form of Eq. 20, over
    /// x = w_t/V_s from 1e-12 to 1e3 and Stribeck indices from 0.3 to 3, stay within 1e-13
    /// relative: g everywhere, the slope wherever x^φ ≤ 30 (beyond, the exponential term is
    /// below 1e-13 of the curve, and the slope's relative error grows like x^φ ulp on a
    /// slope below e^−30 of its scale).
    #[test]
    fn stribeck_through_ln_and_exp_matches_powf() {
        let base = driving_sliding_share();
        let mut worst: (f64, f64) = (0.0, 0.0);
        for phi in [0.3, 0.5, 0.9, 0.94, 1.0, 1.7, 3.0] {
            let ode = TreadOde { phi, ..base };
            let df = ode.f_m - ode.f_s;
            for k in 0..=3000 {
                let x = 10f64.powf(-12.0 + 15.0 * k as f64 / 3000.0);
                let w_t = x * ode.v_s;
                let xp = x.powf(phi);
                let e = df * (-xp).exp();
                let (g_ref, dg_ref) = (ode.f_s + e, -e * phi * xp / w_t);
                let (g, dg) = ode.stribeck_with_slope(w_t);
                assert_eq!(g, ode.stribeck(w_t));
                worst.0 = worst.0.max((g / g_ref - 1.0).abs());
                if xp <= 30.0 {
                    worst.1 = worst.1.max((dg / dg_ref - 1.0).abs());
                }
            }
        }
        assert!(worst.0 < 1e-13 && worst.1 < 1e-13, "{worst:?}");
    }

    /// The plain square root gives hypot's sliding speed to within an ulp, and the shared
    /// evaluation gives the same RHS and Jacobian as the separate ones.
    #[test]
    fn shared_evaluation_matches_the_separate_ones() {
        let ode = driving_sliding_share();
        let eq = ode.equilibrium();
        for k in -200..=200 {
            let w = k as f64 * 1e-3 * ode.u_mps.abs().max(1e-3) + 1e-9;
            let (wt, slope) = ode.sliding_speed(w);
            let h = w.hypot(ode.v_sx_mps);
            assert!((wt / h - 1.0).abs() <= f64::EPSILON, "{w}: {wt} vs {h}");
            assert!((slope - w / h).abs() <= 2.0 * f64::EPSILON, "{w}");
            let x = [eq[0] * (1.0 + 1e-3 * k as f64), eq[1], w + ode.u_mps];
            let (f, j) = ode.rhs_and_jacobian(&x);
            assert_eq!(f, ode.rhs(&x));
            assert_eq!(j, ode.jacobian(&x));
        }
        // Speeds whose squares would overflow fall back to hypot.
        let (wt, _) = ode.sliding_speed(1e200);
        assert_eq!(wt, 1e200f64.hypot(ode.v_sx_mps));
    }
}
