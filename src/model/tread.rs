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

impl TreadOde {
    /// Sliding speed seen by the Stribeck curve w_t and its derivative d w_t / d w (step 6).
    #[inline(always)]
    fn sliding_speed(&self, w: f64) -> (f64, f64) {
        match self.variant {
            Variant::Paper => (w.abs(), if w >= 0.0 { 1.0 } else { -1.0 }),
            Variant::Combined | Variant::SlidingShare => {
                let wt = w.hypot(self.v_sx_mps);
                (wt, if wt > 0.0 { w / wt } else { 1.0 })
            }
        }
    }

    /// Stribeck curve g(w_t) = F_s + (F_m − F_s) exp(−(w_t/V_s)^φ) (Eq. 20).
    #[inline(always)]
    pub fn stribeck(&self, w_t: f64) -> f64 {
        self.f_s + (self.f_m - self.f_s) * (-(w_t / self.v_s).powf(self.phi)).exp()
    }

    /// g and dg/dw_t together.
    #[inline(always)]
    fn stribeck_with_slope(&self, w_t: f64) -> (f64, f64) {
        let x = w_t / self.v_s;
        if x == 0.0 {
            // The slope is unbounded at rest for φ < 1; the Jacobian uses the one-sided value 0
            // there (it is only reached on a measure-zero set of trajectories).
            return (self.f_m, 0.0);
        }
        let xp = x.powf(self.phi);
        let e = (self.f_m - self.f_s) * (-xp).exp();
        (self.f_s + e, -e * self.phi * xp / w_t)
    }

    /// Right-hand side of Eq. 21: (dz/dt, dy/dt, dv/dt).
    #[inline(always)]
    pub fn rhs(&self, x: &State) -> State {
        let [z, y, v] = *x;
        let w = v - self.u_mps;
        let (w_t, _) = self.sliding_speed(w);
        let g = self.stribeck(w_t);
        let dz = w - self.sigma0 * w_t * z / g;
        let dv = -(self.c_s * v + self.k_s * y + self.sigma0 * z + self.sigma1 * dz) / self.mass_kg;
        [dz, v, dv]
    }

    /// Analytic Jacobian ∂f/∂x (Eqs. 23–25). At w = 0 (paper variant) the right derivative is used.
    #[inline]
    pub fn jacobian(&self, x: &State) -> Matrix3<f64> {
        let [z, _, v] = *x;
        let w = v - self.u_mps;
        let (w_t, dwt_dw) = self.sliding_speed(w);
        let (g, dg) = self.stribeck_with_slope(w_t);
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
