//! The tread's response to a small relative change ε of both friction levels, as a transfer
//! from ε to δP/P̄ (MODEL.md#growth-of-a-stable-wheel): the linearisation at one state, and for
//! a stable wheel the transfer G_P(iω) = C(iωI − A)⁻¹B_ε + D_ε at the equilibrium, written as a
//! sum of poles so that its mean over a speed spread is exact ([`super::spread`]).

use nalgebra::{Matrix3, RowVector3, Vector3};

use super::spread::NormalSpeeds;
use crate::model::{State, TreadOde};
use crate::numeric::Complex64;

/// The linearisation of the tread forced by ε at one state x: δẋ = A δx + b ε and
/// δP = c·δx + d ε, with P = F·w the friction power (MODEL.md#step-10-wear-law).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearisation {
    /// A = ∂f/∂x, the analytic Jacobian of step 8.
    pub a: Matrix3<f64>,
    /// b = ∂f/∂ε: F_{m,s} → (1 + ε)F_{m,s} scales g, so ∂ż/∂ε = σ0 w_t z/g = w − ż and
    /// ∂v̇/∂ε = −σ1 ∂ż/∂ε / m.
    pub b: Vector3<f64>,
    /// c = ∂P/∂x = w ∂F/∂x + F ∂w/∂x \[W per unit state\].
    pub c: RowVector3<f64>,
    /// d = ∂P/∂ε = w σ1 ∂ż/∂ε \[W\].
    pub d: f64,
    /// P = F·w at x \[W\].
    pub power_w: f64,
}

impl Linearisation {
    /// At state `x` of `ode`: one evaluation of the right-hand side and Jacobian.
    pub fn at(ode: &TreadOde, x: &State) -> Self {
        let (f, a) = ode.rhs_and_jacobian(x);
        Self::from_field(ode, x, &f, a)
    }

    /// At state `x` whose vector field `f` and Jacobian `a` are known (a sampled cycle's).
    pub fn from_field(ode: &TreadOde, x: &State, f: &State, a: Matrix3<f64>) -> Self {
        let w = x[2] - ode.u_mps;
        let dz_de = w - f[0];
        let force = ode.sigma0 * x[0] + ode.sigma1 * f[0];
        let s1 = ode.sigma1;
        Linearisation {
            a,
            b: Vector3::new(dz_de, 0.0, -s1 * dz_de / ode.mass_kg),
            c: RowVector3::new(
                w * (ode.sigma0 + s1 * a[(0, 0)]),
                w * s1 * a[(0, 1)],
                w * s1 * a[(0, 2)] + force,
            ),
            d: w * s1 * dz_de,
            power_w: force * w,
        }
    }

    /// G_P(iω) = (c (iωI − A)⁻¹ b + d)/P by one 3×3 complex solve (NaN if singular).
    pub fn transfer(&self, omega: f64) -> Complex64 {
        let m = Matrix3::from_fn(|i, j| {
            let diag = if i == j {
                Complex64::new(0.0, omega)
            } else {
                Complex64::new(0.0, 0.0)
            };
            diag - Complex64::new(self.a[(i, j)], 0.0)
        });
        let b = self.b.map(|x| Complex64::new(x, 0.0));
        match m.lu().solve(&b) {
            Some(dx) => {
                let c = self.c.map(|x| Complex64::new(x, 0.0));
                ((c * dx)[0] + self.d) / self.power_w
            }
            None => Complex64::new(f64::NAN, f64::NAN),
        }
    }
}

/// One pole of a transfer: residue / (iω − pole).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoleTerm {
    /// The pole s \[1/s\].
    pub pole: Complex64,
    /// Its residue \[1/s\].
    pub residue: Complex64,
    /// Whether the pole belongs to a cycle's phase mode (on the imaginary axis: the resonance of
    /// the cycle's phase with the order, which locks it inside the tongue).
    pub phase: bool,
}

/// A transfer G(iω) = direct + Σ residue/(iω − pole).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PoleExpansion {
    /// The part without a pole.
    pub direct: Complex64,
    /// The poles.
    pub terms: Vec<PoleTerm>,
}

impl PoleExpansion {
    /// G at the angular frequency `omega` \[rad/s\].
    pub fn at(&self, omega: f64) -> Complex64 {
        let iw = Complex64::new(0.0, omega);
        self.terms
            .iter()
            .fold(self.direct, |g, t| g + t.residue / (iw - t.pole))
    }

    /// The mean of G(i n V/r_B) over speeds V normal around `speed_mps` with standard deviation
    /// `spread_mps`, at fixed order n: each pole is a pole in V, at z = −i s r_B/n, whose normal
    /// mean is exact. A phase-mode pole lies on the real V axis: its principal value.
    pub fn mean_over_speed(
        &self,
        order: f64,
        r_b: f64,
        speed_mps: f64,
        spread_mps: f64,
    ) -> Complex64 {
        self.mean_over_speeds(order, r_b, &NormalSpeeds::new(speed_mps, spread_mps))
    }

    /// [`PoleExpansion::mean_over_speed`] over `speeds`.
    pub(crate) fn mean_over_speeds(
        &self,
        order: f64,
        r_b: f64,
        speeds: &NormalSpeeds,
    ) -> Complex64 {
        let k = r_b / order;
        let sum = self.terms.iter().fold(Complex64::new(0.0, 0.0), |g, t| {
            let z = pole_in_speed(t, k);
            g + t.residue * speeds.mean_of_pole(z)
        });
        // residue/(iω − s) = residue · (r_B/(i n)) / (V − z).
        self.direct + sum * Complex64::new(0.0, -k)
    }

    /// The poles that resonate at an order inside \[`lo`, `hi`\] (ω = x V/r_B at a positive
    /// frequency Im s) with the part without a pole, and the rest: what the rest adds is smooth
    /// over those orders.
    pub fn split_at_orders(
        &self,
        lo: f64,
        hi: f64,
        r_b: f64,
        speed_mps: f64,
    ) -> (PoleExpansion, PoleExpansion) {
        let (near, far) = self.terms.iter().partition(|t| {
            let x = t.pole.im * r_b / speed_mps;
            (lo..=hi).contains(&x)
        });
        (
            PoleExpansion {
                direct: self.direct,
                terms: near,
            },
            PoleExpansion {
                direct: Complex64::new(0.0, 0.0),
                terms: far,
            },
        )
    }

    /// The mean of G(i n V/r_B) over speeds uniform on \[`lo_mps`, `hi_mps`\]: each pole
    /// integrates to a logarithm, (1/(b − a)) ln((b − z)/(a − z)); a phase-mode pole inside the
    /// band keeps its principal value.
    pub fn mean_over_band(&self, order: f64, r_b: f64, lo_mps: f64, hi_mps: f64) -> Complex64 {
        let k = r_b / order;
        let width = hi_mps - lo_mps;
        let (centre, half) = (0.5 * (lo_mps + hi_mps), 0.5 * width);
        self.terms.iter().fold(self.direct, |g, t| {
            let z = pole_in_speed(t, k);
            let to_centre = Complex64::new(centre, 0.0) - z;
            let q = half / to_centre;
            let mean = if q.norm_sqr() < FAR_FROM_BAND * FAR_FROM_BAND {
                // ln((c + h − z)/(c − h − z)) / 2h = artanh(q)/h, q = h/(c − z): its series
                // (1/(c − z)) Σ q^{2j}/(2j + 1), to q⁸ within q¹⁰/11 (a pole far from the
                // band: a cycle's harmonics, and the poles of most orders' tongues).
                let q2 = q * q;
                to_centre.inv()
                    * (Complex64::new(1.0, 0.0)
                        + q2 * (1.0 / 3.0 + q2 * (0.2 + q2 * (1.0 / 7.0 + q2 / 9.0))))
            } else {
                let ratio = (Complex64::new(hi_mps, 0.0) - z) / (Complex64::new(lo_mps, 0.0) - z);
                // ln|ratio| from its square (no hypot: the ratio is of order one).
                let log_norm = 0.5 * ratio.norm_sqr().ln();
                let log = if t.phase {
                    Complex64::new(log_norm, 0.0)
                } else {
                    Complex64::new(log_norm, ratio.im.atan2(ratio.re))
                };
                log / width
            };
            g + t.residue * Complex64::new(0.0, -k) * mean
        })
    }
}

/// [`PoleExpansion::mean_over_band`] over a cycle's tongue at every order of a wheel: at order
/// n the band of speeds is V ν/n ± V λ_n/n (λ_n the lock's half-width in revolutions), which
/// spans the same ω = ω_γ(1 ± λ_n/ν) at every n but for its width. A pole far from the band at
/// the widest λ adds residue·(−i r_B)/(Vν − z₁) · Σ_j (λ u)^{2j}/(2j + 1), u = V/(Vν − z₁) and
/// z₁ its pole in V at order 1 (the series the band's mean takes anyway): those poles are
/// summed once as a series in λ², the rest per order.
#[derive(Debug, Clone, PartialEq)]
pub struct TongueMeans {
    /// The poles near the band, with the part without a pole.
    near: PoleExpansion,
    /// Σ over the far poles of residue·(−i r_B)/(Vν − z₁) · u^{2j}/(2j + 1), j = 0 … 4.
    series: [Complex64; 5],
    r_b: f64,
    speed_mps: f64,
}

impl TongueMeans {
    /// The transfer's uniform mean over the band `centre_mps` ± `half_mps` at `order`, the
    /// band being the tongue's (centre V ν/n).
    pub fn at(&self, order: f64, centre_mps: f64, half_mps: f64) -> Complex64 {
        let lambda = half_mps * order / self.speed_mps;
        let l2 = lambda * lambda;
        let far = self
            .series
            .iter()
            .rev()
            .fold(Complex64::new(0.0, 0.0), |acc, &c| acc * l2 + c);
        self.near.mean_over_band(
            order,
            self.r_b,
            centre_mps - half_mps,
            centre_mps + half_mps,
        ) + far
    }
}

impl PoleExpansion {
    /// The means over a cycle's tongue ([`TongueMeans`]) of frequency ν = ω_γ r_B/V revolutions,
    /// for half-widths λ up to `widest` (revolutions).
    pub fn tongue_means(&self, r_b: f64, speed_mps: f64, nu: f64, widest: f64) -> TongueMeans {
        let mut near = PoleExpansion {
            direct: self.direct,
            terms: Vec::new(),
        };
        let mut series = [Complex64::new(0.0, 0.0); 5];
        let centre = Complex64::new(speed_mps * nu, 0.0);
        for t in &self.terms {
            let to_centre = centre - pole_in_speed(t, r_b);
            let u = Complex64::new(speed_mps, 0.0) / to_centre;
            if (u * widest).norm_sqr() < FAR_FROM_BAND * FAR_FROM_BAND {
                let u2 = u * u;
                let mut term = t.residue * Complex64::new(0.0, -r_b) / to_centre;
                for (j, s) in series.iter_mut().enumerate() {
                    *s += term / (2 * j + 1) as f64;
                    term *= u2;
                }
            } else {
                near.terms.push(*t);
            }
        }
        TongueMeans {
            near,
            series,
            r_b,
            speed_mps,
        }
    }
}

/// |h/(c − z)| below which a pole's mean over a band c ± h is taken from its series (the
/// series' first term left out is under 1e-11 of the mean).
const FAR_FROM_BAND: f64 = 0.1;

/// The pole of a term in the speed V for order n = r_B/`k`: z = −i s r_B/n (real for a phase
/// mode).
fn pole_in_speed(t: &PoleTerm, k: f64) -> Complex64 {
    let z = Complex64::new(0.0, -k) * t.pole;
    if t.phase {
        Complex64::new(z.re, 0.0)
    } else {
        z
    }
}

/// The null vector of a singular 3×3 complex matrix: the cross product of its two rows that
/// span the most (bilinear, so orthogonal to both rows without conjugation).
pub(crate) fn null_vector(n: &Matrix3<Complex64>) -> nalgebra::Vector3<Complex64> {
    let row = |i: usize| [n[(i, 0)], n[(i, 1)], n[(i, 2)]];
    let cross = |a: [Complex64; 3], b: [Complex64; 3]| {
        nalgebra::Vector3::new(
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        )
    };
    [(0, 1), (0, 2), (1, 2)]
        .iter()
        .map(|&(i, j)| cross(row(i), row(j)))
        .max_by(|a, b| a.norm_squared().total_cmp(&b.norm_squared()))
        .unwrap_or_default()
}

/// Right eigenvectors (columns) and left eigenvectors (rows of the inverse) of a real 3×3
/// matrix for its eigenvalues `ev`; None where they do not form a basis (a defective matrix).
pub(crate) fn eigenbasis(
    m: &Matrix3<f64>,
    ev: &[Complex64; 3],
) -> Option<(Matrix3<Complex64>, Matrix3<Complex64>)> {
    let mc = m.map(|x| Complex64::new(x, 0.0));
    let mut r = Matrix3::<Complex64>::zeros();
    for (j, lam) in ev.iter().enumerate() {
        let n = mc - Matrix3::from_diagonal_element(*lam);
        let v = null_vector(&n);
        let norm = v.norm();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        r.set_column(j, &(v / Complex64::new(norm, 0.0)));
    }
    let l = r.try_inverse()?;
    // A nearly defective basis (cond > 1e8) loses the residues to cancellation.
    let cond = r.norm() * l.norm();
    (cond.is_finite() && cond < 1e8).then_some((r, l))
}

/// The stable wheel's transfer at its equilibrium (MODEL.md#growth-of-a-stable-wheel) as poles at
/// the Jacobian's eigenvalues, residues (c r_j)(l_j b)/P̄; None where the Jacobian has no
/// eigenbasis (the caller then solves at each frequency).
pub(crate) fn equilibrium_expansion(ode: &TreadOde, lin: &Linearisation) -> Option<PoleExpansion> {
    let ev = ode.eigenvalues();
    if ev.iter().any(|e| !e.re.is_finite()) {
        return None;
    }
    let (r, l) = eigenbasis(&lin.a, &ev)?;
    let b = lin.b.map(|x| Complex64::new(x, 0.0));
    let c = lin.c.map(|x| Complex64::new(x, 0.0));
    let terms = (0..3)
        .map(|j| PoleTerm {
            pole: ev[j],
            residue: (c * r.column(j))[0] * (l.row(j) * b)[0] / lin.power_w,
            phase: false,
        })
        .collect();
    Some(PoleExpansion {
        direct: Complex64::new(lin.d / lin.power_w, 0.0),
        terms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Variant, Wheel, WheelModel};
    use crate::params::Params;

    /// The pole expansion equals the 3×3 solve at every frequency, for both wheels at a stable
    /// point and at an unstable one (the algebra does not care), and G_P(0) = 1: a static ε
    /// scales the equilibrium's friction force and so its power.
    #[test]
    fn pole_expansion_is_the_solve() {
        for speed_kmh in [70.0, 100.0] {
            for wheel in Wheel::BOTH {
                let p = Params {
                    speed_kmh,
                    ..Params::default()
                };
                let m = WheelModel::build(&p, wheel, Variant::SlidingShare).unwrap();
                let lin = Linearisation::at(&m.ode, &m.ode.equilibrium());
                let e = equilibrium_expansion(&m.ode, &lin).unwrap();
                for omega in [0.0, 100.0, 1500.0, 1692.0, 1700.0, 2500.0] {
                    let (a, b) = (e.at(omega), lin.transfer(omega));
                    assert!(
                        (a - b).norm() < 1e-9 * b.norm().max(1.0),
                        "{wheel} {omega}: {a} vs {b}"
                    );
                }
                let g0 = lin.transfer(0.0);
                assert!((g0 - 1.0).norm() < 1e-9, "{wheel}: G(0) = {g0}");
            }
        }
    }

    /// The linearisation's b is the derivative of the RHS with the friction levels scaled, and
    /// c, d those of the power (central differences).
    #[test]
    fn linearisation_is_the_derivative() {
        use crate::wear::physics::feedback::with_friction_scale;
        use crate::wear::physics::law::friction_power_w;
        let m =
            WheelModel::build(&Params::default(), Wheel::Driving, Variant::SlidingShare).unwrap();
        let eq = m.ode.equilibrium();
        let x = [eq[0] * 1.1, eq[1] * 0.9, 0.03];
        let lin = Linearisation::at(&m.ode, &x);
        let h = 1e-6;
        let (up, down) = (
            with_friction_scale(&m.ode, h),
            with_friction_scale(&m.ode, -h),
        );
        let (fu, fd) = (up.rhs(&x), down.rhs(&x));
        for i in 0..3 {
            let num = (fu[i] - fd[i]) / (2.0 * h);
            assert!(
                (num - lin.b[i]).abs() < 1e-6 * lin.b.norm(),
                "b[{i}]: {num} vs {}",
                lin.b[i]
            );
        }
        let d = (friction_power_w(&up, &x) - friction_power_w(&down, &x)) / (2.0 * h);
        assert!((d - lin.d).abs() < 1e-6 * lin.power_w, "{d} vs {}", lin.d);
        let scales = [eq[0].abs(), eq[1].abs(), m.ode.u_mps];
        for i in 0..3 {
            let hx = 1e-6 * scales[i];
            let (mut xu, mut xd) = (x, x);
            xu[i] += hx;
            xd[i] -= hx;
            let num = (friction_power_w(&m.ode, &xu) - friction_power_w(&m.ode, &xd)) / (2.0 * hx);
            assert!(
                (num - lin.c[i]).abs() < 1e-5 * lin.c[i].abs().max(1e-3 * lin.power_w / scales[i]),
                "c[{i}]: {num} vs {}",
                lin.c[i]
            );
        }
    }
}
