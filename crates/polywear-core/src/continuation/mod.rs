//! Two-parameter continuation of Hopf points for any small ODE x' = f(x, p) with an exact
//! Jacobian and exact second and third derivatives (the data MatCont or BifurcationKit ask for).
//!
//! The code is generic over [`OdeWithJacobian`] and [`TwoParameterFamily`], so the textbook
//! systems of its tests' `textbook` (Brusselator, Bautin normal form) run the same code path as the tire:
//!
//! - [`hopf`]: the Hopf defining system (equilibrium equations plus the bialternate-product test
//!   function det(2A⊙I), Kuznetsov, *Elements of Applied Bifurcation Theory*, §10.2.2), Newton's
//!   corrector on it, and the first Lyapunov coefficient l1 (Kuznetsov eq. 3.20,
//!   MODEL.md#first-lyapunov-coefficient);
//! - [`trace`]: pseudo-arclength continuation with step control, seeds from scan lines, curve
//!   ends on the box, closed curves, Bautin points (l1 = 0) by Brent's method.

pub mod hopf;
pub mod linalg;
#[cfg(test)]
pub(crate) mod textbook;
pub mod trace;

use nalgebra::{Complex, DMatrix, DVector};

/// A complex vector (for the eigenvectors q, p and the multilinear forms B, C).
pub type CVector = DVector<Complex<f64>>;

/// One autonomous ODE x' = f(x) at fixed parameters, with its derivatives in the state.
pub trait OdeWithJacobian {
    /// Number of states n.
    fn dim(&self) -> usize;
    /// f(x).
    fn rhs(&self, x: &DVector<f64>) -> DVector<f64>;
    /// A = ∂f/∂x at x.
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64>;
    /// B(u, v)_i = Σ_jk ∂²f_i/∂x_j∂x_k u_j v_k at x, extended to complex arguments bilinearly.
    fn second(&self, x: &DVector<f64>, u: &CVector, v: &CVector) -> CVector;
    /// C(u, v, w)_i = Σ_jkl ∂³f_i/∂x_j∂x_k∂x_l u_j v_k w_l at x, trilinear.
    fn third(&self, x: &DVector<f64>, u: &CVector, v: &CVector, w: &CVector) -> CVector;
    /// A point from which Newton's method reaches the equilibrium (the equilibrium itself where
    /// it is known in closed form).
    fn equilibrium_guess(&self) -> DVector<f64>;
}

/// A two-parameter family of ODEs: the system at parameters p = (P, Q) in their own units.
pub trait TwoParameterFamily: Sync {
    /// The ODE at fixed parameters.
    type System: OdeWithJacobian;
    /// The system at p, or `None` where the model does not exist there.
    fn at(&self, p: [f64; 2]) -> Option<Self::System>;
    /// Size per state below which a component counts as zero in Newton's stopping test.
    fn state_scale(&self) -> DVector<f64>;
}

/// The rectangle [lo, hi] of the parameter plane in which curves are traced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamBox {
    /// Lower corner (P, Q) in the parameters' own units.
    pub lo: [f64; 2],
    /// Upper corner (P, Q) in the parameters' own units.
    pub hi: [f64; 2],
}

impl ParamBox {
    /// Parameters of the box-relative coordinates s ∈ [0, 1]².
    pub fn to_param(&self, s: [f64; 2]) -> [f64; 2] {
        [
            self.lo[0] + s[0] * (self.hi[0] - self.lo[0]),
            self.lo[1] + s[1] * (self.hi[1] - self.lo[1]),
        ]
    }

    /// Box-relative coordinates of parameters p.
    pub fn to_unit(&self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.lo[0]) / (self.hi[0] - self.lo[0]),
            (p[1] - self.lo[1]) / (self.hi[1] - self.lo[1]),
        ]
    }
}

/// Real vector as a complex one.
pub(crate) fn complexify(v: &DVector<f64>) -> CVector {
    v.map(|x| Complex::new(x, 0.0))
}

#[cfg(test)]
pub(crate) mod tests;
