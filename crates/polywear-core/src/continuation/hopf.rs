//! The Hopf defining system in box-relative parameters s ∈ [0, 1]² and its Newton corrector, and
//! what is measured at a Hopf point: frequency, first Lyapunov coefficient, and the flags.
//!
//! Unknowns u = (x, s) ∈ ℝⁿ⁺²; equations f(x, p(s)) = 0 (n), g(x, p(s)) = det(2A⊙I) = 0 (1), and
//! one linear constraint c·s = r that picks the point (a pseudo-arclength hyperplane, or a fixed
//! edge or scan line). ∂f/∂x is the system's exact Jacobian; ∂g/∂x is exact through the
//! adjugate and the second derivative B (∂A/∂x_k · v = B(e_k, v)); derivatives in s are central
//! differences, which only slow Newton down, never move the solution.

use nalgebra::{Complex, DMatrix, DVector};

use super::linalg::{adjugate, bialternate, dot, eigenvalues, null_vector, solve_equilibrated};
use super::{complexify, CVector, OdeWithJacobian, ParamBox, TwoParameterFamily};

/// Step of the central differences in s (box-relative).
const DS: f64 = 1e-7;
/// Newton stops when the correction in s is below this (box-relative) ...
const S_TOL: f64 = 1e-12;
/// ... and the correction of each state below this times (|x_i| + scale_i).
const X_RTOL: f64 = 1e-10;
const MAX_NEWTON: usize = 12;
/// A solution counts as a Hopf point when its critical pair has |Re λ| ≤ this × |λ|; converged
/// solutions are near 1e-12.
pub(crate) const CRITICAL_RE: f64 = 1e-9;

/// The Hopf test function g = det(2A⊙I).
pub(crate) fn test_function(a: &DMatrix<f64>) -> f64 {
    bialternate(a).determinant()
}

/// The equilibrium of `sys` by Newton's method from its guess, or `None` without convergence.
pub fn equilibrium<S: OdeWithJacobian>(sys: &S, scale: &DVector<f64>) -> Option<DVector<f64>> {
    let mut x = sys.equilibrium_guess();
    for _ in 0..30 {
        let dx = sys.jacobian(&x).lu().solve(&sys.rhs(&x))?;
        x -= &dx;
        if !x.iter().all(|v| v.is_finite()) {
            return None;
        }
        if dx
            .iter()
            .zip(x.iter().zip(scale.iter()))
            .all(|(d, (xi, si))| d.abs() <= X_RTOL * (xi.abs() + si))
        {
            return Some(x);
        }
    }
    None
}

/// A converged solution of the Hopf system (before its analysis).
#[derive(Debug, Clone)]
pub struct Solution {
    /// Box-relative parameters.
    pub s: [f64; 2],
    /// The equilibrium state.
    pub x: DVector<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// The Hopf system of one family in one box.
pub(crate) struct HopfSystem<'a, F: TwoParameterFamily> {
    /// The two-parameter family.
    pub family: &'a F,
    /// The box; the unknowns s are relative to it.
    pub bounds: ParamBox,
    /// Size per state below which a component counts as zero (the family's `state_scale`).
    pub scale: DVector<f64>,
}

impl<'a, F: TwoParameterFamily> HopfSystem<'a, F> {
    /// The Hopf system of `family` in the box `bounds`.
    pub fn new(family: &'a F, bounds: ParamBox) -> Self {
        HopfSystem {
            family,
            bounds,
            scale: family.state_scale(),
        }
    }

    /// The system at box-relative parameters s, or `None` where the model does not exist.
    pub fn system(&self, s: [f64; 2]) -> Option<F::System> {
        self.family.at(self.bounds.to_param(s))
    }

    /// g at the equilibrium for parameters s (NaN where there is none): its sign changes mark
    /// Hopf points and neutral saddles on the scan lines.
    pub fn scan_value(&self, s: [f64; 2]) -> f64 {
        let Some(sys) = self.system(s) else {
            return f64::NAN;
        };
        equilibrium(&sys, &self.scale).map_or(f64::NAN, |x| test_function(&sys.jacobian(&x)))
    }

    /// Residual (f, g) and the (n+1)×(n+2) Jacobian of the defining system at (x, s).
    fn linearise(&self, x: &DVector<f64>, s: [f64; 2]) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let sys = self.system(s)?;
        let n = sys.dim();
        let a = sys.jacobian(x);
        let mut res = DVector::zeros(n + 1);
        res.rows_mut(0, n).copy_from(&sys.rhs(x));
        let m = bialternate(&a);
        res[n] = m.determinant();
        let mut jac = DMatrix::zeros(n + 1, n + 2);
        jac.view_mut((0, 0), (n, n)).copy_from(&a);
        // ∂g/∂x_k = tr(adj(2A⊙I) · (2 ∂A/∂x_k ⊙ I)), with ∂A/∂x_k e_j = B(e_k, e_j).
        let adj = adjugate(&m);
        let unit = |k: usize| complexify(&DVector::from_fn(n, |i, _| (i == k) as u8 as f64));
        for k in 0..n {
            let ek = unit(k);
            let da = DMatrix::from_fn(n, n, |i, j| sys.second(x, &ek, &unit(j))[i].re);
            jac[(n, k)] = (&adj * bialternate(&da)).trace();
        }
        for j in 0..2 {
            let mut sp = s;
            let mut sm = s;
            sp[j] += DS;
            sm[j] -= DS;
            let (fp, fm) = (self.system(sp)?, self.system(sm)?);
            let df = (fp.rhs(x) - fm.rhs(x)) / (2.0 * DS);
            let dg = (test_function(&fp.jacobian(x)) - test_function(&fm.jacobian(x))) / (2.0 * DS);
            jac.view_mut((0, n + j), (n, 1)).copy_from(&df);
            jac[(n, n + j)] = dg;
        }
        Some((res, jac))
    }

    /// Newton's method on the Hopf system with the constraint c·s = r, from (x, s).
    pub fn correct(&self, x: DVector<f64>, s: [f64; 2], c: [f64; 2], r: f64) -> Option<Solution> {
        let (mut x, mut s) = (x, s);
        let n = x.len();
        for it in 1..=MAX_NEWTON {
            let (res, jac) = self.linearise(&x, s)?;
            let mut full = DMatrix::zeros(n + 2, n + 2);
            full.view_mut((0, 0), (n + 1, n + 2)).copy_from(&jac);
            full[(n + 1, n)] = c[0];
            full[(n + 1, n + 1)] = c[1];
            let mut rhs = DVector::zeros(n + 2);
            rhs.rows_mut(0, n + 1).copy_from(&res);
            rhs[n + 1] = c[0] * s[0] + c[1] * s[1] - r;
            let du = solve_equilibrated(full, rhs)?;
            let ds = [du[n], du[n + 1]];
            if ds[0].abs().max(ds[1].abs()) > 0.25 {
                return None;
            }
            for i in 0..n {
                x[i] -= du[i];
            }
            s = [s[0] - ds[0], s[1] - ds[1]];
            let x_done = (0..n).all(|i| du[i].abs() <= X_RTOL * (x[i].abs() + self.scale[i]));
            if ds[0].abs().max(ds[1].abs()) <= S_TOL && x_done {
                return Some(Solution {
                    s,
                    x,
                    iterations: it,
                });
            }
        }
        None
    }

    /// Unit tangent of the curve in s at a solution (x, s): the reduced gradient
    /// G = g_s − g_x A⁻¹ f_s turned by 90°. Also returns the state's derivative along it.
    pub fn tangent(&self, sol: &Solution) -> Option<([f64; 2], DVector<f64>)> {
        let (_, jac) = self.linearise(&sol.x, sol.s)?;
        let n = sol.x.len();
        let a = jac.view((0, 0), (n, n)).clone_owned();
        let lu = a.lu();
        let mut grad = [0.0; 2];
        let mut dx = Vec::new();
        for j in 0..2 {
            let fs = DVector::from_fn(n, |i, _| jac[(i, n + j)]);
            let xs = lu.solve(&fs)?;
            grad[j] = jac[(n, n + j)] - (0..n).map(|k| jac[(n, k)] * xs[k]).sum::<f64>();
            dx.push(-xs);
        }
        let norm = grad[0].hypot(grad[1]);
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        let t = [-grad[1] / norm, grad[0] / norm];
        let dxdt = &dx[0] * t[0] + &dx[1] * t[1];
        Some((t, dxdt))
    }
}

/// What is measured at one Hopf point.
#[derive(Debug, Clone, PartialEq)]
pub struct HopfData {
    /// The parameters in their own units.
    pub p: [f64; 2],
    /// The equilibrium.
    pub x: Vec<f64>,
    /// Angular frequency ω = Im λ of the critical pair [1/s].
    pub omega: f64,
    /// Re λ of the critical pair [1/s] (zero up to the corrector's tolerance).
    pub re_lambda: f64,
    /// First Lyapunov coefficient (Kuznetsov eq. 3.20, MODEL.md#first-lyapunov-coefficient);
    /// negative: supercritical (soft onset), positive: subcritical (hard onset).
    pub l1: f64,
    /// det A: its sign changes where a real eigenvalue crosses zero.
    pub det_a: f64,
}

/// Why a solution of the Hopf system is no Hopf point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NotHopf {
    /// The eigenvalues summing to zero are real (±κ): a neutral saddle, where the complex pair
    /// of a Hopf curve has turned real.
    NeutralSaddle,
    /// The eigenvalues or eigenvectors could not be computed.
    Numerics,
}

/// Analyses a solution: the critical pair, its eigenvectors and l1.
pub fn analyse<S: OdeWithJacobian>(
    sys: &S,
    x: &DVector<f64>,
    p: [f64; 2],
) -> Result<HopfData, NotHopf> {
    let a = sys.jacobian(x);
    let ev = eigenvalues(&a).ok_or(NotHopf::Numerics)?;
    let scale = ev.iter().map(|e| e.norm()).fold(0.0, f64::max);
    // The critical eigenvalue: positive imaginary part, smallest |Re|.
    let lambda = ev
        .iter()
        .filter(|e| e.im > 1e-9 * scale)
        .min_by(|a, b| a.re.abs().total_cmp(&b.re.abs()))
        .copied();
    let Some(lambda) = lambda.filter(|l| l.re.abs() <= CRITICAL_RE * l.norm()) else {
        // No pair on the imaginary axis: a neutral saddle if two real eigenvalues sum to zero,
        // otherwise Newton stopped on a false solution (e.g. where the model's coefficients
        // have a square-root edge in the parameters and the differences mislead it).
        let real: Vec<f64> = ev
            .iter()
            .filter(|e| e.im.abs() <= 1e-9 * scale)
            .map(|e| e.re)
            .collect();
        let saddle =
            (0..real.len()).any(|i| (0..i).any(|j| (real[i] + real[j]).abs() <= 1e-6 * scale));
        return Err(if saddle {
            NotHopf::NeutralSaddle
        } else {
            NotHopf::Numerics
        });
    };
    let l1 = first_lyapunov(sys, x, &a, lambda.im).ok_or(NotHopf::Numerics)?;
    Ok(HopfData {
        p,
        x: x.iter().copied().collect(),
        omega: lambda.im,
        re_lambda: lambda.re,
        l1,
        det_a: a.determinant(),
    })
}

/// First Lyapunov coefficient at a Hopf point with critical pair ±iω (Kuznetsov eq. 3.20):
/// l1 = Re(⟨p, C(q,q,q̄)⟩ − 2⟨p, B(q, A⁻¹B(q,q̄))⟩ + ⟨p, B(q̄, (2iωI − A)⁻¹B(q,q))⟩) / (2ω),
/// with A q = iω q, Aᵀ p = −iω p, ⟨q, q⟩ = 1, ⟨p, q⟩ = 1. Its value depends on the state's units
/// through the normalisation ⟨q, q⟩ = 1; its sign does not (MODEL.md#first-lyapunov-coefficient).
pub fn first_lyapunov<S: OdeWithJacobian>(
    sys: &S,
    x: &DVector<f64>,
    a: &DMatrix<f64>,
    omega: f64,
) -> Option<f64> {
    let n = a.nrows();
    let ac: DMatrix<Complex<f64>> = a.map(|v| Complex::new(v, 0.0));
    let iw = Complex::new(0.0, omega);
    let eye = DMatrix::<Complex<f64>>::identity(n, n);
    let q = null_vector(&(&ac - &eye * iw))?;
    let p0 = null_vector(&(ac.transpose() + &eye * iw))?;
    let pq = dot(&p0, &q);
    if pq.norm() < 1e-12 {
        return None;
    }
    let p: CVector = p0 / pq.conj();
    let qb = q.map(|c| c.conj());
    let b_qqb = sys.second(x, &q, &qb);
    let b_qq = sys.second(x, &q, &q);
    let a_inv_b = ac.clone().lu().solve(&b_qqb)?;
    let two_iw = &eye * Complex::new(0.0, 2.0 * omega) - &ac;
    let r_inv_b = two_iw.lu().solve(&b_qq)?;
    let c_qqqb = sys.third(x, &q, &q, &qb);
    let sum = dot(&p, &c_qqqb) - dot(&p, &sys.second(x, &q, &a_inv_b)) * 2.0
        + dot(&p, &sys.second(x, &qb, &r_inv_b));
    let l1 = sum.re / (2.0 * omega);
    l1.is_finite().then_some(l1)
}
