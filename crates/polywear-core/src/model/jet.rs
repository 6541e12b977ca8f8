//! The tread ODE's jet: its Jacobian and exact second and third state derivatives (MODEL.md#step-6-tread-ode; paper Eq. 21),
//! for the first Lyapunov coefficient.
//!
//! The state enters nonlinearly only through h(z, w) = σ0 z φ(w), φ(w) = w_t(w) / g(w_t(w)),
//! w = v − U: dz/dt = w − h and dv/dt = −(C_s v + K_s y + σ0 z + σ1 (w − h)) / m. So
//! D²f = (−D²h, 0, σ1 D²h / m) and the same for D³f, with (u_z, u_v the z and v components)
//! D²h(u, v) = σ0 (φ'(u_z v_v + u_v v_z) + z φ'' u_v v_v) and
//! D³h(u, v, w) = σ0 (φ''(u_z v_v w_v + u_v v_z w_v + u_v v_v w_z) + z φ''' u_v v_v w_v).
//! φ', φ'', φ''' come from a third-order Taylor jet of the scalar φ (forward-mode
//! differentiation of one variable, exact to rounding): a few lines here beat a dependency.

use std::ops::{Add, Div, Mul, Sub};

use nalgebra::{Complex, DMatrix, DVector};

use crate::continuation::{CVector, OdeWithJacobian};
use crate::model::{TreadOde, Variant};

/// A truncated Taylor series c0 + c1 ε + c2 ε² + c3 ε³ (c_k = f⁽ᵏ⁾ / k!).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Jet(pub [f64; 4]);

impl Jet {
    /// The independent variable at x.
    pub fn var(x: f64) -> Jet {
        Jet([x, 1.0, 0.0, 0.0])
    }
    /// The constant c (all higher coefficients zero).
    pub fn constant(c: f64) -> Jet {
        Jet([c, 0.0, 0.0, 0.0])
    }
    /// The series multiplied by the constant k.
    pub fn scale(self, k: f64) -> Jet {
        Jet(self.0.map(|c| c * k))
    }
    /// exp of the series (coefficient recurrence of e' = a' e).
    pub fn exp(self) -> Jet {
        let a = self.0;
        let mut e = [a[0].exp(), 0.0, 0.0, 0.0];
        for k in 1..4 {
            e[k] = (1..=k).map(|j| j as f64 * a[j] * e[k - j]).sum::<f64>() / k as f64;
        }
        Jet(e)
    }
    /// ln of the series, for c0 > 0 (coefficient recurrence of l' = a' / a).
    pub fn ln(self) -> Jet {
        let a = self.0;
        let mut l = [a[0].ln(), 0.0, 0.0, 0.0];
        for k in 1..4 {
            let s: f64 = (1..k).map(|j| j as f64 * l[j] * a[k - j]).sum();
            l[k] = (a[k] - s / k as f64) / a[0];
        }
        Jet(l)
    }
    /// x^r for x > 0.
    pub fn powf(self, r: f64) -> Jet {
        self.ln().scale(r).exp()
    }
    /// |x| near c0 ≠ 0 (the series negated where c0 < 0).
    pub fn abs(self) -> Jet {
        if self.0[0] < 0.0 {
            self.scale(-1.0)
        } else {
            self
        }
    }
    /// The k-th derivative.
    pub fn derivative(&self, k: usize) -> f64 {
        self.0[k] * [1.0, 1.0, 2.0, 6.0][k]
    }
}

impl Add for Jet {
    type Output = Jet;
    fn add(self, b: Jet) -> Jet {
        Jet([0, 1, 2, 3].map(|k| self.0[k] + b.0[k]))
    }
}

impl Sub for Jet {
    type Output = Jet;
    fn sub(self, b: Jet) -> Jet {
        Jet([0, 1, 2, 3].map(|k| self.0[k] - b.0[k]))
    }
}

impl Mul for Jet {
    type Output = Jet;
    fn mul(self, b: Jet) -> Jet {
        Jet([0, 1, 2, 3].map(|k| (0..=k).map(|i| self.0[i] * b.0[k - i]).sum()))
    }
}

impl Div for Jet {
    type Output = Jet;
    fn div(self, b: Jet) -> Jet {
        let mut q = [0.0; 4];
        for k in 0..4 {
            let s: f64 = (1..=k).map(|i| b.0[i] * q[k - i]).sum();
            q[k] = (self.0[k] - s) / b.0[0];
        }
        Jet(q)
    }
}

/// φ(w) = w_t / g(w_t) as a jet in w (step 6: w_t = |w| under `paper`, √(w² + V_sx²) otherwise;
/// g the Stribeck curve, Eq. 20). Requires w_t > 0, which holds at every equilibrium with toe-in.
pub(crate) fn phi_jet(ode: &TreadOde, w: f64) -> Jet {
    let w = Jet::var(w);
    let w_t = match ode.variant {
        Variant::Paper => w.abs(),
        Variant::Combined | Variant::SlidingShare => {
            (w * w + Jet::constant(ode.v_sx_mps * ode.v_sx_mps)).powf(0.5)
        }
    };
    let decay = (w_t.scale(1.0 / ode.v_s).powf(ode.phi)).scale(-1.0).exp();
    let g = Jet::constant(ode.f_s) + decay.scale(ode.f_m - ode.f_s);
    w_t / g
}

/// The tread ODE of one wheel at one operating point, as the continuation sees it.
#[derive(Debug, Clone, Copy)]
pub struct TreadSystem(pub TreadOde);

const Z: usize = 0;
const V: usize = 2;

impl TreadSystem {
    /// (φ', φ'', φ''') at the state's w.
    fn slopes(&self, x: &DVector<f64>) -> [f64; 3] {
        let j = phi_jet(&self.0, x[V] - self.0.u_mps);
        [j.derivative(1), j.derivative(2), j.derivative(3)]
    }

    /// (−D, 0, σ1 D / m) for a derivative D of h.
    fn spread(&self, d: Complex<f64>) -> CVector {
        DVector::from_vec(vec![
            -d,
            Complex::new(0.0, 0.0),
            d * (self.0.sigma1 / self.0.mass_kg),
        ])
    }
}

impl OdeWithJacobian for TreadSystem {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&self, x: &DVector<f64>) -> DVector<f64> {
        DVector::from_column_slice(&self.0.rhs(&[x[0], x[1], x[2]]))
    }
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let j = self.0.jacobian(&[x[0], x[1], x[2]]);
        DMatrix::from_fn(3, 3, |r, c| j[(r, c)])
    }
    fn second(&self, x: &DVector<f64>, u: &CVector, v: &CVector) -> CVector {
        let [d1, d2, _] = self.slopes(x);
        let d = (u[Z] * v[V] + u[V] * v[Z]) * d1 + u[V] * v[V] * (x[Z] * d2);
        self.spread(d * self.0.sigma0)
    }
    fn third(&self, x: &DVector<f64>, u: &CVector, v: &CVector, w: &CVector) -> CVector {
        let [_, d2, d3] = self.slopes(x);
        let d = (u[Z] * v[V] * w[V] + u[V] * v[Z] * w[V] + u[V] * v[V] * w[Z]) * d2
            + u[V] * v[V] * w[V] * (x[Z] * d3);
        self.spread(d * self.0.sigma0)
    }
    fn equilibrium_guess(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.0.equilibrium())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::continuation::tests::check_derivatives;
    use crate::model::{Wheel, WheelModel};
    use crate::params::Params;

    #[test]
    fn jet_matches_closed_form_derivatives() {
        // f(x) = exp(x) / (1 + x²) ^ 0.7 at x = 0.4, against central differences of f'.
        let f = |x: Jet| x.exp() / (Jet::constant(1.0) + x * x).powf(0.7);
        let fx = |x: f64| x.exp() / (1.0 + x * x).powf(0.7);
        let j = f(Jet::var(0.4));
        let h = 1e-3;
        let d = |k: usize, x: f64| f(Jet::var(x)).derivative(k);
        assert!((j.0[0] - fx(0.4)).abs() < 1e-15);
        assert!((j.derivative(1) - (fx(0.4 + 1e-6) - fx(0.4 - 1e-6)) / 2e-6).abs() < 1e-8);
        assert!((j.derivative(2) - (d(1, 0.4 + h) - d(1, 0.4 - h)) / (2.0 * h)).abs() < 1e-5);
        assert!((j.derivative(3) - (d(2, 0.4 + h) - d(2, 0.4 - h)) / (2.0 * h)).abs() < 1e-5);
    }

    #[test]
    fn tread_derivatives_match_differences_for_every_variant_and_wheel() {
        for variant in Variant::ALL {
            for wheel in Wheel::BOTH {
                let m = WheelModel::build(&Params::default(), wheel, variant).unwrap();
                let sys = TreadSystem(m.ode);
                let e = m.ode.equilibrium();
                // Off the equilibrium too, so z ≠ z0 and w ≠ −U are exercised.
                let x = DVector::from_vec(vec![e[0] * 1.1, e[1] * 0.9, 0.02]);
                let h = DVector::from_vec(vec![1e-4, 1e-4, 1e-2]);
                check_derivatives(&sys, &x, &h, 1e-6);
                // The jet's φ' reproduces the model's own Jacobian entry ∂(dz/dt)/∂v.
                let jac = sys.jacobian(&x);
                let [d1, _, _] = sys.slopes(&x);
                let mine = 1.0 - m.ode.sigma0 * x[0] * d1;
                assert!((jac[(0, 2)] - mine).abs() < 1e-12 * mine.abs().max(1.0));
            }
        }
    }
}
