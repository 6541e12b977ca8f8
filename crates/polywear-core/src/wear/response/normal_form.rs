//! The lock-in tongue at any depth, from the cycle's forced Hopf normal form
//! (MODEL.md#the-tongue-at-depth). Phase reduction (Adler) gives the tongue's first-order
//! half-width Δ₁ = δ_lock·2πf_rot; it holds only while Δ₁ is small beside the rate λ at which
//! the cycle's amplitude mode relaxes. Beyond, the forcing also moves the amplitude, and the
//! amplitude moves the phase through the isochrons' twist (the shear c). The forced
//! Stuart–Landau oscillator keeps exactly those three numbers,
//!
//! ```text
//! da/dτ = ½(1 − |a|²)(1 + ic)a − iya + x,   τ = λt, y = (Ω − ω_γ)/λ, x = Δ₁/(λ√(1 + c²)),
//! ```
//!
//! a the cycle's complex amplitude (free: |a| = 1) in the frame of the forcing Ω, and it locks
//! where it has a stable fixed point. All three are read off the cycle's Floquet decomposition
//! ([`super::periodic::CycleResponse`]): λ = −μ of the amplitude mode, Δ₁ from the phase mode's
//! coupling ĝ₋₁, and c from the phase of ĝ₋₁ against the amplitude mode's coupling Î₋₁, since
//! in the normal form ĝ₋₁/Î₋₁ is a real multiple of c + i.

use super::periodic::CycleResponse;
use crate::numeric::Complex64;
use nalgebra::Matrix3;

/// Steps outward from the tongue's centre, each this share of the first-order half-width,
/// before the bisection of the last one.
const OUTWARD_STEP: f64 = 0.02;
/// The most steps outward: a tongue wider than this many first-order widths is cut there.
const MOST_STEPS: usize = 10_000;
/// Halvings of the bracket around each edge (2⁻⁴⁰ of a step).
const BISECTIONS: usize = 40;

/// A limit cycle's forced Hopf normal form: the amplitude mode's rate and the shear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForcedHopf {
    /// λ = −μ of the amplitude mode \[1/s\].
    pub amplitude_rate_per_s: f64,
    /// c: how far the isochrons twist, the cycle's frequency change per change of its squared
    /// amplitude in units of λ/2 (dimensionless; its sign says which side of the tongue widens:
    /// c < 0 widens the side below the cycle's frequency).
    pub shear: f64,
}

impl ForcedHopf {
    /// The normal form of the cycle whose response is `response` (None without an amplitude
    /// mode of real positive multiplier, or without coupling).
    pub fn of(response: &CycleResponse) -> Option<Self> {
        let (rate, iso) = response.amplitude_mode?;
        let ratio = response.phase_coupling / iso;
        (rate > 0.0 && ratio.im != 0.0 && ratio.is_finite()).then(|| ForcedHopf {
            amplitude_rate_per_s: rate,
            shear: ratio.re / ratio.im,
        })
    }

    /// The detunings Ω − ω_γ \[rad/s\] at which a cycle forced to a first-order half-width of
    /// `first_order_rad_s` stops being locked, below and above its own frequency (below ≤ 0 ≤
    /// above): from the centre outward to the first detuning without a stable fixed point.
    pub fn lock_edges_rad_s(&self, first_order_rad_s: f64) -> (f64, f64) {
        let lambda = self.amplitude_rate_per_s;
        let c = self.shear;
        let y1 = first_order_rad_s / lambda;
        if y1.is_nan() || y1 <= 0.0 || y1.is_infinite() {
            return (0.0, 0.0);
        }
        let x = self.forcing(first_order_rad_s);
        let edge = |sign: f64| {
            let locks = |y: f64| stable_fixed_point(c, x, sign * y);
            let step = OUTWARD_STEP * y1;
            let (mut inside, mut outside) = (0.0, f64::NAN);
            for k in 1..=MOST_STEPS {
                let y = k as f64 * step;
                if locks(y) {
                    inside = y;
                } else {
                    outside = y;
                    break;
                }
            }
            if outside.is_nan() {
                return inside;
            }
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (inside + outside);
                if locks(mid) {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            inside
        };
        (-edge(-1.0) * lambda, edge(1.0) * lambda)
    }

    /// x, the normal form's forcing for a first-order half-width of `first_order_rad_s`:
    /// Δ₁/(λ√(1 + c²)).
    pub(crate) fn forcing(&self, first_order_rad_s: f64) -> f64 {
        let c = self.shear;
        first_order_rad_s / self.amplitude_rate_per_s / (1.0 + c * c).sqrt()
    }

    /// The least first-order half-width Δ₁ \[rad/s\] at which the cycle locks at the detuning
    /// Ω − ω_γ = `detuning_rad_s`: x = Δ₁/(λ√(1 + c²)) with x² the least of G(½) and G at its
    /// local minimum above ½, in closed form (MODEL.md#the-tongue-at-depth). A forcing that
    /// deepens from zero locks the cycle there (it counts a detuning where the normal form
    /// locks apart from the tongue's centre too; the band of [`ForcedHopf::lock_edges_rad_s`]
    /// stops at the first detuning that does not).
    pub fn locking_first_order_rad_s(&self, detuning_rad_s: f64) -> f64 {
        let y = detuning_rad_s / self.amplitude_rate_per_s;
        let c = self.shear;
        least_locking_forcing_sq(c, y).sqrt() * self.amplitude_rate_per_s * (1.0 + c * c).sqrt()
    }

    /// |a| of the locked cycle, its amplitude over the free cycle's, forced to a first-order
    /// half-width of `first_order_rad_s` at the detuning Ω − ω_γ = `detuning_rad_s` (None where
    /// that is outside the tongue): the stable fixed point's, the largest where there are two.
    pub fn locked_amplitude(&self, first_order_rad_s: f64, detuning_rad_s: f64) -> Option<f64> {
        self.locked_cycle(first_order_rad_s, detuning_rad_s)
            .map(|a| a.norm())
    }

    /// The locked cycle against the forcing, forced as [`ForcedHopf::locked_amplitude`]: its
    /// amplitude over the free cycle's, turned by its phase lead over the direction of the phase
    /// coupling ĝ₋₁ε_n, so that a weak forcing gives Adler's e^{i arccos(δ/Δ₁)}, δ = Ω − ω_γ
    /// (MODEL.md#the-locked-print). In the normal form the stable fixed point is
    /// a = −x/(½(1 − |a|²)(1 + ic) − iy), and its phase reduction φ̇ = −y − x√(1 + c²) sin(φ +
    /// arctan c) puts the weakly forced cycle at φ = −arctan c − arcsin(δ/Δ₁): turned by
    /// i e^{i arctan c}, that is e^{i arccos(δ/Δ₁)}. None outside the tongue.
    pub fn locked_cycle(&self, first_order_rad_s: f64, detuning_rad_s: f64) -> Option<Complex64> {
        let (c, x) = (self.shear, self.forcing(first_order_rad_s));
        let y = detuning_rad_s / self.amplitude_rate_per_s;
        let big_r = largest_stable_fixed_point(c, x, y)?;
        let a = -x / Complex64::new(0.5 * (1.0 - big_r), 0.5 * (1.0 - big_r) * c - y);
        Some(a * Complex64::new(0.0, 1.0) * Complex64::from_polar(1.0, c.atan()))
    }
}

/// Whether da/dτ = ½(1 − |a|²)(1 + ic)a − iya + x has a stable fixed point: x² at least
/// [`least_locking_forcing_sq`].
fn stable_fixed_point(c: f64, x: f64, y: f64) -> bool {
    x * x >= least_locking_forcing_sq(c, y)
}

/// The least x² at which da/dτ = ½(1 − |a|²)(1 + ic)a − iya + x has a stable fixed point, in
/// closed form. Its |a|² = R solves G(R) = R(A(1 − R)² − cy(1 − R) + y²) = x², A = ¼(1 + c²);
/// one is stable where the trace 1 − 2R of the Jacobian is negative and its determinant
/// |½(1 + ic)(1 − 2R) − iy|² − AR², which is G′(R), positive. The largest root has G′ ≥ 0 (G
/// rises beyond its last turn), so a stable one exists exactly when some root lies above ½,
/// that is when x² ≥ min over R ≥ ½ of G: G(½) (the torus line) or G at its local minimum, the
/// larger root of G′(R) = 3AR² + (2cy − 4A)R + A − cy + y² (the saddle-node line).
fn least_locking_forcing_sq(c: f64, y: f64) -> f64 {
    let a = 0.25 * (1.0 + c * c);
    let g = |r: f64| r * (a * (1.0 - r) * (1.0 - r) - c * y * (1.0 - r) + y * y);
    let (qa, qb, qc) = (3.0 * a, 2.0 * c * y - 4.0 * a, a - c * y + y * y);
    let disc = qb * qb - 4.0 * qa * qc;
    let turn = (disc > 0.0).then(|| (-qb + disc.sqrt()) / (2.0 * qa));
    match turn {
        Some(r) if r > 0.5 => g(0.5).min(g(r)),
        _ => g(0.5),
    }
}

/// The largest |a|² among the stable fixed points of [`stable_fixed_point`]'s equation (None:
/// none is stable). The largest real root R₃ of the cubic G(R) = x² has G′ ≥ 0, so it is the
/// one wherever any is (a smaller stable root lies below it): taken in closed form and
/// polished by Newton, it is stable where R₃ > ½ and G′(R₃) > 0; only a near-double root (G′
/// within 10⁻⁶ of zero there, where the closed form keeps half the digits) falls back to all
/// three roots. The saturated walk asks this at every midpoint step
/// of a locked interval, where the companion matrix's Schur decomposition cost 90% of the
/// walk.
fn largest_stable_fixed_point(c: f64, x: f64, y: f64) -> Option<f64> {
    let a = 0.25 * (1.0 + c * c);
    let (p, q, r) = ((c * y - 2.0 * a) / a, (a - c * y + y * y) / a, -x * x / a);
    let big_r = largest_real_root(p, q, r);
    let slope = (3.0 * big_r + 2.0 * p) * big_r + q;
    let stable = |big_r: f64| {
        let d = Complex64::new(0.5 * (1.0 - 2.0 * big_r), 0.5 * c * (1.0 - 2.0 * big_r) - y);
        big_r > 0.5 && d.norm_sqr() - a * big_r * big_r > 0.0
    };
    if !big_r.is_finite() || slope.abs() <= 1e-6 * (q.abs() + big_r * big_r + 1.0) {
        return stable_fixed_points(c, x, y).fold(None, |best: Option<f64>, r| {
            Some(best.map_or(r, |b| b.max(r)))
        });
    }
    stable(big_r).then_some(big_r)
}

/// The largest real root of R³ + pR² + qR + r: Cardano's form where there is one real root
/// (or the double root beside it where rounding hides a pair), the trigonometric one where
/// there are three, then two Newton steps (each kept only where
/// it lowers the residual).
pub(crate) fn largest_real_root(p: f64, q: f64, r: f64) -> f64 {
    let shift = p / 3.0;
    // t = R + p/3: t³ + P t + Q = 0.
    let big_p = q - p * shift;
    let big_q = 2.0 * shift * shift * shift - shift * q + r;
    let disc = 0.25 * big_q * big_q + big_p * big_p * big_p / 27.0;
    let t = if disc > 0.0 {
        let s = disc.sqrt();
        let single = (-0.5 * big_q + s).cbrt() + (-0.5 * big_q - s).cbrt();
        // Near a double root (disc ≈ 0 by rounding) the other root, −3Q/2P, may be the
        // larger: take it where it is a root to within rounding.
        let double = -1.5 * big_q / big_p;
        let depressed = |t: f64| (t * t + big_p) * t + big_q;
        let scale = big_p.abs().powf(1.5) + big_q.abs();
        if big_p < 0.0 && double > single && depressed(double).abs() <= 1e-9 * scale {
            double
        } else {
            single
        }
    } else if big_p < 0.0 {
        let m = 2.0 * (-big_p / 3.0).sqrt();
        let cos3 = (1.5 * big_q / big_p * (-3.0 / big_p).sqrt()).clamp(-1.0, 1.0);
        m * (cos3.acos() / 3.0).cos()
    } else {
        0.0
    };
    let cubic = |x: f64| ((x + p) * x + q) * x + r;
    let mut root = t - shift;
    for _ in 0..2 {
        let slope = (3.0 * root + 2.0 * p) * root + q;
        if slope == 0.0 {
            break;
        }
        let next = root - cubic(root) / slope;
        if cubic(next).abs() < cubic(root).abs() {
            root = next;
        }
    }
    root
}

/// The |a|² of the stable fixed points of [`stable_fixed_point`]'s equation.
fn stable_fixed_points(c: f64, x: f64, y: f64) -> impl Iterator<Item = f64> {
    let a = 0.25 * (1.0 + c * c);
    // a R³ + (c y − 2a) R² + (a − c y + y²) R − x² = 0, monic.
    let (p, q, r) = ((c * y - 2.0 * a) / a, (a - c * y + y * y) / a, -x * x / a);
    let companion = Matrix3::new(-p, -q, -r, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let roots: Vec<Complex64> = companion
        .try_schur(f64::EPSILON, 10_000)
        .map(|schur| schur.complex_eigenvalues().iter().copied().collect())
        .unwrap_or_default();
    roots
        .into_iter()
        .filter(|root| root.im.abs() <= 1e-9 * root.re.abs().max(1.0))
        .map(|root| root.re)
        .filter(move |&big_r| {
            let d = Complex64::new(0.5 * (1.0 - 2.0 * big_r), 0.5 * c * (1.0 - 2.0 * big_r) - y);
            big_r > 0.5 && d.norm_sqr() - a * big_r * big_r > 0.0
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form largest stable fixed point is the largest of the companion matrix's
    /// stable roots, over shears, detunings and forcings on both sides of every edge.
    #[test]
    fn the_closed_form_root_is_the_companion_s() {
        let mut stable = 0;
        for c in [-3.0, -1.2, -0.3, 0.0, 0.4, 2.0] {
            for k in -40..=40 {
                let y = k as f64 * 0.1;
                for m in 0..=60 {
                    let x = m as f64 * 0.05;
                    let want = stable_fixed_points(c, x, y).fold(None, |best: Option<f64>, r| {
                        Some(best.map_or(r, |b: f64| b.max(r)))
                    });
                    let got = largest_stable_fixed_point(c, x, y);
                    match (want, got) {
                        (Some(w), Some(g)) => {
                            assert!((w - g).abs() <= 1e-9 * w.max(1.0), "{c} {y} {x}: {w} {g}");
                            stable += 1;
                        }
                        (None, None) => {}
                        // On the torus line R = ½ itself, rounding decides.
                        (Some(r), None) | (None, Some(r)) if (r - 0.5).abs() < 1e-9 => {}
                        _ => panic!("c {c}, y {y}, x {x}: {want:?} against {got:?}"),
                    }
                }
            }
        }
        assert!(stable > 5_000, "only {stable} stable points");
    }

    /// At small forcing the tongue is Adler's, ±Δ₁, whatever the shear; the shear only bends it
    /// once Δ₁ is near λ.
    #[test]
    fn weak_forcing_gives_the_first_order_tongue() {
        for c in [0.0, 1.0, -2.8] {
            let form = ForcedHopf {
                amplitude_rate_per_s: 4.0,
                shear: c,
            };
            let first = 0.004;
            let (below, above) = form.lock_edges_rad_s(first);
            assert!((below / first + 1.0).abs() < 0.01, "c {c}: {below}");
            assert!((above / first - 1.0).abs() < 0.01, "c {c}: {above}");
        }
    }

    /// The locked cycle is the free one under weak forcing (|a| → 1), grows with the forcing at
    /// the tongue's centre (the forcing in phase with it), and is absent outside the tongue.
    #[test]
    fn the_locked_amplitude_grows_with_the_forcing() {
        let form = ForcedHopf {
            amplitude_rate_per_s: 4.0,
            shear: -2.8,
        };
        let weak = form.locked_amplitude(0.004, 0.0).unwrap();
        assert!((weak - 1.0).abs() < 1e-3, "{weak}");
        let (mid, strong) = (
            form.locked_amplitude(4.0, 0.0).unwrap(),
            form.locked_amplitude(40.0, 0.0).unwrap(),
        );
        assert!(1.0 < mid && mid < strong, "{mid} {strong}");
        let (below, above) = form.lock_edges_rad_s(4.0);
        assert!(form.locked_amplitude(4.0, 1.01 * above).is_none());
        assert!(form.locked_amplitude(4.0, 1.01 * below).is_none());
        assert!(form.locked_amplitude(4.0, 0.99 * above).is_some());
    }

    /// The closed-form test for a stable fixed point is the fixed points' own (the cubic's roots
    /// by the companion matrix, each's trace and determinant) on a grid of shears, forcings and
    /// detunings, and the least locking forcing is on the edge: the band's edges at a forcing
    /// lock at it, and 0.1% beyond them they need more.
    #[test]
    fn the_closed_form_lock_is_the_fixed_points() {
        let (mut differ, mut locked) = (0, 0);
        for c in [-3.0, -1.0, 0.0, 0.5, 2.8] {
            for ix in 0..40 {
                let x = 0.02 * 1.2f64.powi(ix);
                for iy in -60..=60 {
                    let y = 0.05 * iy as f64 * (1.0 + x);
                    let by_roots = stable_fixed_points(c, x, y).next().is_some();
                    locked += usize::from(by_roots);
                    if by_roots != stable_fixed_point(c, x, y) {
                        // Only on the boundary itself, within the roots' rounding.
                        let m = least_locking_forcing_sq(c, y);
                        assert!((x * x / m - 1.0).abs() < 1e-6, "c {c} x {x} y {y}: {m}");
                        differ += 1;
                    }
                }
            }
        }
        // Of the 24,200 points, both kinds in numbers.
        assert!(
            differ < 5 && (5_000..19_200).contains(&locked),
            "{differ} {locked}"
        );
        for c in [0.0, -2.86] {
            let form = ForcedHopf {
                amplitude_rate_per_s: 3.6,
                shear: c,
            };
            for first in [0.5, 4.0, 40.0] {
                let (below, above) = form.lock_edges_rad_s(first);
                for edge in [below, above] {
                    let need = form.locking_first_order_rad_s(edge);
                    assert!(need <= first * (1.0 + 1e-9), "c {c}: {need} > {first}");
                    let beyond = form.locking_first_order_rad_s(1.001 * edge);
                    assert!(beyond > first, "c {c}, {first}: {beyond} at {edge}");
                }
            }
        }
    }

    /// Weakly forced, the locked cycle is Adler's whatever the shear: the free amplitude, at
    /// the phase e^{i arccos(δ/Δ₁)} (along the coupling at the upper edge, a quarter turn ahead
    /// at the centre, half a turn at the lower edge).
    #[test]
    fn the_weakly_locked_cycle_is_adlers() {
        for c in [0.0, 1.0, -2.8] {
            let form = ForcedHopf {
                amplitude_rate_per_s: 4.0,
                shear: c,
            };
            let first = 0.004;
            for s in [-0.9, -0.5, 0.0, 0.3, 0.8] {
                let a = form.locked_cycle(first, s * first).unwrap();
                let adler = Complex64::from_polar(1.0, f64::acos(s));
                assert!(
                    (a - adler).norm() < 0.01,
                    "c {c}, δ/Δ₁ {s}: {a} against {adler}"
                );
            }
            assert!(form.locked_cycle(first, 1.05 * first).is_none());
        }
    }

    /// Without shear the amplitude's response moves no phase, and the tongue stays at least
    /// the first order's; with the default point's shear, forced at 16 times λ, it narrows to
    /// about half of it (0.47; MODEL.md#the-tongue-at-depth).
    #[test]
    fn the_shear_narrows_a_strongly_forced_tongue() {
        let strong = |c: f64| {
            let form = ForcedHopf {
                amplitude_rate_per_s: 1.0,
                shear: c,
            };
            let (below, above) = form.lock_edges_rad_s(16.0);
            0.5 * (above - below) / 16.0
        };
        assert!(strong(0.0) >= 0.99, "{}", strong(0.0));
        let sheared = strong(-2.839);
        assert!((0.4..0.6).contains(&sheared), "{sheared}");
        // The shear's sign mirrors the tongue.
        let mirror = |c: f64| {
            ForcedHopf {
                amplitude_rate_per_s: 1.0,
                shear: c,
            }
            .lock_edges_rad_s(0.5)
        };
        let (b, a) = mirror(2.0);
        let (b2, a2) = mirror(-2.0);
        assert!(
            (b + a2).abs() < 1e-9 && (a + b2).abs() < 1e-9,
            "{b} {a} {b2} {a2}"
        );
        assert!(a2 < -b2, "c < 0 widens the side below: {b2} {a2}");
    }
}
