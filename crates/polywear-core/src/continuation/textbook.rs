//! Textbook systems with known Hopf curves and Lyapunov coefficients, run through the same
//! continuation code as the tire to check it.
//!
//! - Brusselator x' = a − (b+1)x + x²y, y' = bx − x²y: equilibrium (a, b/a), Hopf curve
//!   b = 1 + a² with ω = a, and (with ⟨q,q⟩ = 1, ⟨p,q⟩ = 1) l1 = −(a² + 2) / (2a(2a² + 1)),
//!   derived from Kuznetsov's eqs. 3.18–3.19 in complex coordinates.
//! - Hopf normal form z' = (μ + i)z + c z|z|² − z|z|⁴ in x = (Re z, Im z): Hopf where μ = 0,
//!   ω = 1, and l1 = 2c (z = √2 w in the coordinate w of the normalised eigenvector
//!   q = (1, −i)/√2). With μ = β1, c = β2 it is the Bautin normal form (Kuznetsov eq. 8.20),
//!   whose Bautin point is the origin; with μ = 1/4 − β1² − β2², c = β1 its Hopf curve is a
//!   closed circle with two Bautin points (0, ±1/2).

use nalgebra::{Complex, DMatrix, DVector};

use super::{CVector, OdeWithJacobian, TwoParameterFamily};

type C = Complex<f64>;

/// The Brusselator at parameters (a, b).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Brusselator {
    /// The parameter a > 0 (the equilibrium is (a, b/a)).
    pub a: f64,
    /// The parameter b; the Hopf curve is b = 1 + a².
    pub b: f64,
}

impl Brusselator {
    /// The closed-form first Lyapunov coefficient on the Hopf curve b = 1 + a².
    pub fn l1_on_hopf_curve(a: f64) -> f64 {
        -(a * a + 2.0) / (2.0 * a * (2.0 * a * a + 1.0))
    }
}

impl OdeWithJacobian for Brusselator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, x: &DVector<f64>) -> DVector<f64> {
        let (u, v) = (x[0], x[1]);
        DVector::from_vec(vec![
            self.a - (self.b + 1.0) * u + u * u * v,
            self.b * u - u * u * v,
        ])
    }
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let (u, v) = (x[0], x[1]);
        DMatrix::from_row_slice(
            2,
            2,
            &[
                -(self.b + 1.0) + 2.0 * u * v,
                u * u,
                self.b - 2.0 * u * v,
                -u * u,
            ],
        )
    }
    fn second(&self, x: &DVector<f64>, p: &CVector, q: &CVector) -> CVector {
        // Only N = u²v is nonlinear: D²N[p, q] = 2v p_u q_u + 2u (p_u q_v + p_v q_u).
        let d2 = p[0] * q[0] * (2.0 * x[1]) + (p[0] * q[1] + p[1] * q[0]) * (2.0 * x[0]);
        DVector::from_vec(vec![d2, -d2])
    }
    fn third(&self, _x: &DVector<f64>, p: &CVector, q: &CVector, r: &CVector) -> CVector {
        let d3 = (p[0] * q[0] * r[1] + p[0] * q[1] * r[0] + p[1] * q[0] * r[0]) * 2.0;
        DVector::from_vec(vec![d3, -d3])
    }
    fn equilibrium_guess(&self) -> DVector<f64> {
        DVector::from_vec(vec![self.a, self.b / self.a])
    }
}

/// The Brusselator family in (a, b).
pub(crate) struct BrusselatorFamily;

impl TwoParameterFamily for BrusselatorFamily {
    type System = Brusselator;
    fn at(&self, p: [f64; 2]) -> Option<Brusselator> {
        (p[0] > 0.0).then_some(Brusselator { a: p[0], b: p[1] })
    }
    fn state_scale(&self) -> DVector<f64> {
        DVector::from_element(2, 1e-9)
    }
}

/// Hopf normal form z' = (μ + i)z + c z|z|² − z|z|⁴ in real coordinates.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NormalForm {
    /// The unfolding parameter μ: Hopf points at μ = 0.
    pub mu: f64,
    /// The cubic coefficient c: l1 = 2c at μ = 0 (with ⟨q, q⟩ = 1), a Bautin point at c = 0.
    pub cubic: f64,
}

/// Bilinear (not sesquilinear) dot product, so that the forms extend to complex arguments.
fn bdot(a: &CVector, b: &CVector) -> C {
    a.iter().zip(b.iter()).map(|(x, y)| x * y).sum()
}

impl OdeWithJacobian for NormalForm {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, x: &DVector<f64>) -> DVector<f64> {
        let rho = x.norm_squared();
        let k = self.mu + self.cubic * rho - rho * rho;
        DVector::from_vec(vec![k * x[0] - x[1], x[0] + k * x[1]])
    }
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let rho = x.norm_squared();
        let k = self.mu + self.cubic * rho - rho * rho;
        // ∂k/∂x_j = (2c − 4ρ) x_j.
        let dk = 2.0 * self.cubic - 4.0 * rho;
        DMatrix::from_row_slice(
            2,
            2,
            &[
                k + dk * x[0] * x[0],
                -1.0 + dk * x[0] * x[1],
                1.0 + dk * x[1] * x[0],
                k + dk * x[1] * x[1],
            ],
        )
    }
    fn second(&self, x: &DVector<f64>, u: &CVector, v: &CVector) -> CVector {
        // c·ρx − ρ²x, with ρ = x·x; the linear part has no second derivative.
        let xc = super::complexify(x);
        let (xu, xv, uv, xx) = (bdot(&xc, u), bdot(&xc, v), bdot(u, v), bdot(&xc, &xc));
        let cubic = (&xc * uv + v * xu + u * xv) * C::new(2.0, 0.0);
        let quintic =
            &xc * (xv * xu * 8.0 + xx * uv * 4.0) + v * (xx * xu * 4.0) + u * (xx * xv * 4.0);
        cubic * C::new(self.cubic, 0.0) - quintic
    }
    fn third(&self, x: &DVector<f64>, u: &CVector, v: &CVector, w: &CVector) -> CVector {
        let xc = super::complexify(x);
        let (xu, xv, xw, xx) = (bdot(&xc, u), bdot(&xc, v), bdot(&xc, w), bdot(&xc, &xc));
        let (uv, uw, vw) = (bdot(u, v), bdot(u, w), bdot(v, w));
        let cubic = (w * uv + v * uw + u * vw) * C::new(2.0, 0.0);
        let quintic = &xc * ((vw * xu + xv * uw + xw * uv) * 8.0)
            + w * (xv * xu * 8.0 + xx * uv * 4.0)
            + v * (xw * xu * 8.0 + xx * uw * 4.0)
            + u * (xw * xv * 8.0 + xx * vw * 4.0);
        cubic * C::new(self.cubic, 0.0) - quintic
    }
    fn equilibrium_guess(&self) -> DVector<f64> {
        DVector::zeros(2)
    }
}

/// The Bautin normal form: μ = β1, c = β2.
pub(crate) struct BautinFamily;

impl TwoParameterFamily for BautinFamily {
    type System = NormalForm;
    fn at(&self, p: [f64; 2]) -> Option<NormalForm> {
        Some(NormalForm {
            mu: p[0],
            cubic: p[1],
        })
    }
    fn state_scale(&self) -> DVector<f64> {
        DVector::from_element(2, 1e-9)
    }
}

/// A closed Hopf curve: μ = 1/4 − β1² − β2², c = β1.
pub(crate) struct RingFamily;

impl TwoParameterFamily for RingFamily {
    type System = NormalForm;
    fn at(&self, p: [f64; 2]) -> Option<NormalForm> {
        Some(NormalForm {
            mu: 0.25 - p[0] * p[0] - p[1] * p[1],
            cubic: p[0],
        })
    }
    fn state_scale(&self) -> DVector<f64> {
        DVector::from_element(2, 1e-9)
    }
}

/// Bogdanov–Takens normal form x' = y, y' = β1 + β2 x + x² − xy (Kuznetsov eq. 8.51, s = −1), on
/// the equilibrium branch through x = 0 at β1 = 0 (a neutral saddle for β2 > 0): its Hopf curve is β1 = 0, β2 < 0 with
/// ω = √(−β2), and at the Bogdanov–Takens point (0, 0) the complex pair turns real.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BogdanovTakens {
    /// The unfolding parameter β1.
    pub beta1: f64,
    /// The unfolding parameter β2.
    pub beta2: f64,
}

impl OdeWithJacobian for BogdanovTakens {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, x: &DVector<f64>) -> DVector<f64> {
        let (u, v) = (x[0], x[1]);
        DVector::from_vec(vec![v, self.beta1 + self.beta2 * u + u * u - u * v])
    }
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let (u, v) = (x[0], x[1]);
        DMatrix::from_row_slice(2, 2, &[0.0, 1.0, self.beta2 + 2.0 * u - v, -u])
    }
    fn second(&self, _x: &DVector<f64>, p: &CVector, q: &CVector) -> CVector {
        let d2 = p[0] * q[0] * 2.0 - (p[0] * q[1] + p[1] * q[0]);
        DVector::from_vec(vec![C::new(0.0, 0.0), d2])
    }
    fn third(&self, _x: &DVector<f64>, _p: &CVector, _q: &CVector, _r: &CVector) -> CVector {
        DVector::from_element(2, C::new(0.0, 0.0))
    }
    fn equilibrium_guess(&self) -> DVector<f64> {
        // Newton from the origin follows the branch through x = 0 at β1 = 0.
        DVector::zeros(2)
    }
}

/// The Bogdanov–Takens family in (β1, β2); no equilibrium where β2² < 4β1.
pub(crate) struct BogdanovTakensFamily;

impl TwoParameterFamily for BogdanovTakensFamily {
    type System = BogdanovTakens;
    fn at(&self, p: [f64; 2]) -> Option<BogdanovTakens> {
        (p[1] * p[1] >= 4.0 * p[0]).then_some(BogdanovTakens {
            beta1: p[0],
            beta2: p[1],
        })
    }
    fn state_scale(&self) -> DVector<f64> {
        DVector::from_element(2, 1e-9)
    }
}
