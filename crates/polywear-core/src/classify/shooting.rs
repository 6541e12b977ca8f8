//! The periodic orbit found directly: Newton's method on the Poincaré return map, with the
//! variational equations giving the monodromy matrix and so the Floquet multipliers.

use nalgebra::{Matrix2, Vector2};

use super::budget::Meter;
use super::peak::refined_peak;
use super::section::{first_return, Return};
use super::{Scales, ShootingError, MIN_CYCLE_V_REL};
use crate::model::SectionVariational;
use crate::model::{State, TreadOde};
use crate::solver::{DenseStep, Method, OdeSystem, SolverOptions, Step};

/// The last iteration of shooting that found a cycle, kept for what reads the cycle again (the
/// wear stage's periodic linearisation, MODEL.md#growth-of-a-vibrating-wheel): the return from a
/// start `start` on the section with the variational equations of [`SectionVariational`]
/// (the state, then Φ's z and v columns), whose Newton step `shift` = (dz, 0, dv) leads to the
/// cycle. The cycle is this trajectory shifted by Φ·shift, within |shift|², and Φ along it is
/// the path's, within |shift| (relative, below 10⁻³: `FINE_ACCEPT_REL`): the accuracy of the
/// classifier's own amplitudes and Floquet multiplier.
#[derive(Debug, Clone, PartialEq)]
pub struct CyclePath {
    /// The relative tolerance the return was integrated at (DOP853).
    pub rtol: f64,
    /// Where the return started, on the section.
    pub start: State,
    /// The last Newton step (dz, 0, dv) from `start` to the cycle.
    pub shift: State,
    /// The return's time \[s\] (the cycle's period less the Newton step's dT).
    pub return_s: f64,
    /// The accepted steps of the return, the last one past it.
    pub steps: Vec<DenseStep<9>>,
}

impl CyclePath {
    /// The variational state at `t` (s since the start), from the step holding it; up to a
    /// twentieth of the last step beyond its end by its polynomial (the cycle's period can end
    /// past the return by the Newton step's dT). None outside.
    pub fn at(&self, t: f64) -> Option<[f64; 9]> {
        let last = self.steps.last()?;
        if t < 0.0 || t > last.t1 + 0.05 * (last.t1 - last.t0) {
            return None;
        }
        let k = self
            .steps
            .partition_point(|s| s.t1 < t)
            .min(self.steps.len() - 1);
        Some(self.steps[k].interpolate(t))
    }
}

/// A converged limit cycle, represented by its point on the section y = y_eq, with what one
/// period along it measures.
#[derive(Debug, Clone)]
pub(crate) struct PeriodicOrbit {
    /// The orbit's point on the section y = y_eq.
    pub start: State,
    /// The period \[s\].
    pub period_s: f64,
    /// Modulus of the largest non-trivial Floquet multiplier (< 1: the cycle attracts).
    pub floquet_max: f64,
    /// Amplitudes and energy along one period.
    pub measure: CycleMeasure,
    /// The last iteration's trajectory, where it was integrated by DOP853 (a tolerance at or
    /// below [`DOP853_AT_OR_BELOW_RTOL`]).
    pub path: Option<CyclePath>,
}

/// Amplitudes (half peak-to-peak) and energy of one period (MODEL.md#step-9-attractor).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct CycleMeasure {
    /// Half peak-to-peak of y \[m\].
    pub amp_y_m: f64,
    /// Half peak-to-peak of v [m/s].
    pub amp_v_mps: f64,
    /// ∮ C_s v² dt over the period \[J\].
    pub energy_j: f64,
}

/// y, v and their sensitivities to the start point's z and v (rows y and v of the variational
/// matrix Φ, its y column left out: the start stays on the section) at one time along an orbit.
#[derive(Clone, Copy)]
struct Sample {
    y: f64,
    v: f64,
    dy: [f64; 3],
    dv: [f64; 3],
}

impl Sample {
    /// The components of a [`SectionVariational`] state (x, then Φ's z and v columns) that a
    /// sample reads.
    const COMPONENTS: [usize; 6] = [1, 2, 4, 5, 7, 8];

    /// From the state of [`SectionVariational`].
    fn of(s: &[f64; 9]) -> Self {
        Self::of_components(Self::COMPONENTS.map(|i| s[i]))
    }

    /// From the components [`Sample::COMPONENTS`].
    fn of_components([y, v, dy_z, dv_z, dy_v, dv_v]: [f64; 6]) -> Self {
        Sample {
            y,
            v,
            dy: [dy_z, 0.0, dy_v],
            dv: [dv_z, 0.0, dv_v],
        }
    }

    /// At time t inside an accepted step, through its dense output.
    fn at(s: &Step<'_, 9>, t: f64) -> Self {
        Self::of_components(s.interpolate_components(t, Self::COMPONENTS))
    }

    /// y and v on the trajectory started `d` away, to first order.
    fn shifted(&self, d: &[f64; 3]) -> (f64, f64) {
        let dot = |r: &[f64; 3]| r[0] * d[0] + r[1] * d[1] + r[2] * d[2];
        (self.y + dot(&self.dy), self.v + dot(&self.dv))
    }
}

/// Samples of one period of a variational trajectory, from which the amplitudes (half
/// peak-to-peak, 8 dense-output points per step, each extreme refined by the parabola through
/// its sample and the two next to it) and the damper's energy ∮ C_s v² dt (3-point
/// Gauss–Legendre per step) follow, also for a start point shifted by a small Newton step.
struct OrbitSamples {
    /// (time since the start \[s\], sample).
    extremes: Vec<(f64, Sample)>,
    /// (quadrature weight × step length, sample).
    quadrature: Vec<(f64, Sample)>,
}

impl OrbitSamples {
    fn new(start: &[f64; 9]) -> Self {
        OrbitSamples {
            extremes: vec![(0.0, Sample::of(start))],
            quadrature: Vec::new(),
        }
    }

    /// Adds the part [t0, t_hi] of an accepted step.
    fn add(&mut self, s: &Step<'_, 9>, t_hi: f64) {
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
            let t = s.t0 + h * j as f64 / 8.0;
            self.extremes.push((t, Sample::at(s, t)));
        }
        for (node, w) in GL {
            self.quadrature
                .push((w * h, Sample::at(s, s.t0 + h * node)));
        }
    }

    /// The measure of the orbit started `d` = (dz, 0, dv) away from the sampled one, whose
    /// period is longer by `dt_s`.
    fn measure(&self, d: &[f64; 3], dt_s: f64, c_s: f64) -> CycleMeasure {
        let times: Vec<f64> = self.extremes.iter().map(|(t, _)| *t).collect();
        let (ys, vs): (Vec<f64>, Vec<f64>) =
            self.extremes.iter().map(|(_, smp)| smp.shifted(d)).unzip();
        let (y_lo, y_hi) = (
            -refined_peak(&times, &ys, -1.0),
            refined_peak(&times, &ys, 1.0),
        );
        let (v_lo, v_hi) = (
            -refined_peak(&times, &vs, -1.0),
            refined_peak(&times, &vs, 1.0),
        );
        let mut energy = 0.0;
        for (wh, smp) in &self.quadrature {
            let v = smp.shifted(d).1;
            energy += wh * c_s * v * v;
        }
        // The stretch of the period beyond the sampled one (v there is the start's).
        let v0 = self.extremes[0].1.shifted(d).1;
        energy += dt_s * c_s * v0 * v0;
        CycleMeasure {
            amp_y_m: 0.5 * (y_hi - y_lo),
            amp_v_mps: 0.5 * (v_hi - v_lo),
            energy_j: energy,
        }
    }
}

/// The next return to the section, looked for between 0.3 and 30 linear periods.
#[allow(clippy::too_many_arguments)]
fn next_return<const N: usize, S: OdeSystem<N>>(
    method: Method,
    sys: &S,
    start: [f64; N],
    y_sec: f64,
    linear_period_s: f64,
    opts: &SolverOptions<N>,
    meter: &Meter,
    observe: impl FnMut(&Step<'_, N>, f64),
) -> Result<Return<N>, ShootingError> {
    first_return(
        method,
        sys,
        start,
        y_sec,
        (0.3 * linear_period_s, 30.0 * linear_period_s),
        opts,
        meter,
        observe,
    )
    .map_err(ShootingError::from)
}

/// Tolerances at or below which DOP853 integrates instead of DOPRI5: there its 8th order
/// takes so many fewer steps that 15 evaluations per step (dense output included) cost less
/// than DOPRI5's 6.
pub(crate) const DOP853_AT_OR_BELOW_RTOL: f64 = 1e-8;

/// The integrator that spends the fewest evaluations at tolerance `rtol`.
pub(crate) fn method_for(rtol: f64) -> Method {
    if rtol <= DOP853_AT_OR_BELOW_RTOL {
        Method::Dop853
    } else {
        Method::Dopri5
    }
}

/// Newton iterations before giving up.
const MAX_NEWTON: usize = 40;

/// Relative tolerance of the coarse Newton iterations (the final ones use the fine one), at most.
pub(crate) const COARSE_RTOL: f64 = 1e-6;

/// Relative tolerance of the amplitude guess, which only needs the growth to a few per cent,
/// at most.
pub(crate) const GUESS_RTOL: f64 = 1e-5;

/// The fine tolerance is at most this times growth^1.5 (growth = Re λ·T per period). The
/// cycle's fixed point moves by the map's integration error over 1 − its multiplier (≈ 2 ×
/// growth near onset), relative to an amplitude that shrinks like √growth: so the relative
/// error of the amplitude goes as rtol / growth^1.5. With the tolerance fixed at 1e-9, cycles
/// with Re λ ~ 1e-3 s⁻¹ came out 7% (energy 13%) below their value at rtol 1e-12, and those
/// with Re λ ~ 1e-4 s⁻¹ up to 69%; this bound keeps them near 1e-3 down to the floor below.
/// (The guess and the coarse iterations only need the cycle within reach of the next phase:
/// their tolerances stay proportional to the growth; the same law for them was looser at
/// typical growths and cost a fine iteration more, 856 against 813 evaluations per cycle.)
pub(crate) const FINE_RTOL_PER_GROWTH_1_5: f64 = 2e-3;

/// The fine tolerance is not tightened below this (double precision leaves little room).
pub(crate) const FINE_RTOL_FLOOR: f64 = 1e-12;

/// Integration tolerances of the three phases of shooting at one equilibrium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tolerances {
    /// The amplitude guess ([`amplitude_guess`]).
    pub guess: f64,
    /// Newton's first iteration. From a guess that is only known to a few per cent (the Hopf
    /// normal form's), the first step is large whatever the tolerance: [`Tolerances::looser_first`]
    /// spends the guess's tolerance on it.
    pub first: f64,
    /// Newton's other coarse iterations.
    pub coarse: f64,
    /// Newton's last iteration, which measures the cycle.
    pub fine: f64,
}

impl Tolerances {
    /// For an equilibrium whose oscillations grow by the factor 1 + `growth` per linear period
    /// (growth = Re λ · T) and the classifier's tolerance `rtol`. Near the Hopf point the growth,
    /// and so 1 − the cycle's Floquet multiplier, is small: the integration error must stay well
    /// below it, or the guess reads noise and Newton converges off the cycle.
    pub fn for_growth(growth: f64, rtol: f64) -> Self {
        let g = growth.abs();
        let fine = rtol.min((FINE_RTOL_PER_GROWTH_1_5 * g.powf(1.5)).max(FINE_RTOL_FLOOR));
        let coarse = (1e-4 * g).clamp(fine, COARSE_RTOL.max(fine));
        Tolerances {
            guess: (1e-3 * g).clamp(fine, GUESS_RTOL.max(fine)),
            first: coarse,
            coarse,
            fine,
        }
    }

    /// The same, with Newton's first iteration at the guess's tolerance.
    pub fn looser_first(self) -> Self {
        Tolerances {
            first: self.guess,
            ..self
        }
    }
}

/// Coarse iterations end once the Newton step is below this (z relative to |z_eq|, v to v).
/// Newton converges quadratically, so the first fine iteration's step is then about 1e-3 and
/// usually accepted at once; ending the coarse ones at 1e-3 instead cost one more coarse
/// iteration per cycle (946 against 825 RHS evaluations per limit-cycle wheel, default study).
const COARSE_STEP_REL: f64 = 3e-2;

/// A fine iteration whose Newton step is below this (relative) ends the search: the step is
/// applied to the start point, the period and the measured period to first order through the
/// variational matrix, leaving errors of order step². Measured against rtol 1e-12 on three
/// studies, amplitudes and energies stay within 1.3e-3 away from the Hopf point; 3e-3 let
/// strongly nonlinear cycles drift by 4e-3.
const FINE_ACCEPT_REL: f64 = 1e-3;

/// A fine iteration is accepted only if its Floquet multiplier ρ is expected to move by less
/// than this share of 1 − ρ over the last step (extrapolated from its move over the step
/// before). Some strongly nonlinear cycles have a multiplier that moves by 0.1 over a 1e-3
/// step: without the check one at 222 km/h and 0.05° reports 0.833 for a converged 0.927, and a
/// coarse phase that ends later reports 0.854 for another cycle's 0.924, even at rtol 1e-12. The
/// check costs nothing on the default study and 1–4% on the grid and wide-structure studies.
const FLOQUET_DRIFT_REL: f64 = 1e-2;

/// Newton gives up after this many damped steps in a row: its guess is outside the basin of
/// any cycle (typically it walks down onto the equilibrium, halving v each time), and the
/// caller's next guess is cheaper than the walk.
const MAX_DAMPED_STEPS: usize = 4;

/// Refines a guess `(z, v)` on the section into the periodic orbit through it. The first
/// iterations integrate at `tols.coarse`; once their steps are small, the last ones at
/// `tols.fine` until the return-map residual is below `newton_tol` or the Newton step below
/// `FINE_ACCEPT_REL`. The residual and step of v are relative to v itself, not to U: near the
/// Hopf point every small orbit returns to within U·`newton_tol` of its start, and would pass
/// for a cycle. The amplitudes, energy and period are measured along that final iteration's
/// period, corrected to first order for its last Newton step.
pub(crate) fn newton_orbit(
    ode: &TreadOde,
    scales: &Scales,
    (guess_z, guess_v): (f64, f64),
    linear_period_s: f64,
    tols: &Tolerances,
    newton_tol: f64,
    meter: &Meter,
) -> Result<PeriodicOrbit, ShootingError> {
    let y_sec = scales.y_eq;
    let options = |rtol: f64| {
        let mut atol = [f64::INFINITY; 9];
        atol[..3].copy_from_slice(&scales.atol(rtol));
        SolverOptions::section_return(rtol, atol, linear_period_s)
    };
    let (fine, coarse) = (options(tols.fine), options(tols.coarse.max(tols.fine)));
    let first = options(tols.first.max(tols.fine));
    let mut tight = tols.coarse <= tols.fine;
    let fine_method = method_for(tols.fine);
    let (mut z, mut v) = (guess_z, guess_v);
    let mut damped_in_a_row = 0;
    // The previous iteration's multiplier and relative step.
    let mut last: Option<(f64, f64)> = None;
    let keep_path = fine_method == Method::Dop853;
    let mut steps: Vec<DenseStep<9>> = Vec::new();
    for iter in 0..MAX_NEWTON {
        let start = [z, y_sec, v, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        let mut samples = OrbitSamples::new(&start);
        steps.clear();
        let opts = match (tight, iter) {
            (true, _) => &fine,
            (false, 0) => &first,
            (false, _) => &coarse,
        };
        let ret = next_return(
            if tight { fine_method } else { Method::Dopri5 },
            &SectionVariational(ode),
            start,
            y_sec,
            linear_period_s,
            opts,
            meter,
            |s, t_hi| {
                if tight {
                    samples.add(s, t_hi);
                    if keep_path {
                        steps.push(s.to_dense());
                    }
                }
            },
        )?;
        let NewtonStep {
            m_z,
            m_v,
            f_t,
            converged,
            mut dz,
            mut dv,
            step_rel,
            rho,
        } = newton_step(ode, scales, (z, v), &ret.state, newton_tol)?;
        // The multiplier still to move over the last step, extrapolated from how it moved over
        // the previous one.
        let rho_drift = last.map_or(0.0, |(rho_p, step_p): (f64, f64)| {
            (rho - rho_p).abs() * (step_rel / step_p).min(1.0)
        });
        let rho_settled = rho_drift <= FLOQUET_DRIFT_REL * (1.0 - rho).abs();
        last = Some((rho, step_rel));
        if tight && (converged || (step_rel < FINE_ACCEPT_REL && rho_settled)) {
            if v + dv <= MIN_CYCLE_V_REL * scales.v {
                return Err(ShootingError::FellOntoEquilibrium);
            }
            // The orbit through the corrected start returns later by dT = −(M d)_y / f_y.
            let d = [dz, 0.0, dv];
            let dt_s = -(m_z[1] * dz + m_v[1] * dv) / f_t[1];
            return Ok(PeriodicOrbit {
                start: [z + dz, y_sec, v + dv],
                period_s: ret.period_s + dt_s,
                floquet_max: rho,
                measure: samples.measure(&d, dt_s, ode.c_s),
                path: keep_path.then(|| CyclePath {
                    rtol: tols.fine,
                    start: [z, y_sec, v],
                    shift: d,
                    return_s: ret.period_s,
                    steps: std::mem::take(&mut steps),
                }),
            });
        }
        // Damp steps that would more than halve or double the amplitude.
        let limit = 0.5 * v;
        if dv.abs() > limit {
            let k = limit / dv.abs();
            (dz, dv) = (dz * k, dv * k);
            damped_in_a_row += 1;
            if damped_in_a_row >= MAX_DAMPED_STEPS {
                return Err(ShootingError::DampedSteps(MAX_DAMPED_STEPS));
            }
        } else {
            damped_in_a_row = 0;
        }
        if converged || step_rel < COARSE_STEP_REL || iter >= MAX_NEWTON / 2 {
            tight = true;
        }
        z += dz;
        v += dv;
        if v.is_nan() || v <= MIN_CYCLE_V_REL * scales.v || !z.is_finite() {
            return Err(ShootingError::FellOntoEquilibrium);
        }
    }
    Err(ShootingError::NoConvergence(MAX_NEWTON))
}

/// One Newton step of the return map from the section start (z, v), read off the variational
/// state `s` at the return: the monodromy matrix's z and v columns, the vector field there, the
/// convergence test, the step and the Floquet multiplier of the reduced map.
struct NewtonStep {
    m_z: [f64; 3],
    m_v: [f64; 3],
    f_t: [f64; 3],
    converged: bool,
    dz: f64,
    dv: f64,
    step_rel: f64,
    rho: f64,
}

fn newton_step(
    ode: &TreadOde,
    scales: &Scales,
    (z, v): (f64, f64),
    s: &[f64; 9],
    newton_tol: f64,
) -> Result<NewtonStep, ShootingError> {
    let x_t = [s[0], s[1], s[2]];
    let (m_z, m_v) = ([s[3], s[4], s[5]], [s[6], s[7], s[8]]);
    let f_t = ode.rhs(&x_t);
    // Derivative of the return map: project the flow's derivative along the vector field onto
    // the section (saltation-free: the section is crossed transversally, f_y = v > 0).
    let dp = |m: &[f64; 3], row: usize| m[row] - f_t[row] * m[1] / f_t[1];
    let reduced = Matrix2::new(dp(&m_z, 0), dp(&m_v, 0), dp(&m_z, 2), dp(&m_v, 2));
    let g = Vector2::new(x_t[0] - z, x_t[2] - v);
    let converged = (g[0] / scales.z).abs() < newton_tol && (g[1] / v).abs() < newton_tol;
    let jac = reduced - Matrix2::identity();
    let step = jac
        .lu()
        .solve(&(-g))
        .ok_or(ShootingError::SingularJacobian)?;
    let (dz, dv) = (step[0], step[1]);
    Ok(NewtonStep {
        m_z,
        m_v,
        f_t,
        converged,
        dz,
        dv,
        step_rel: (dz / scales.z).abs().max((dv / v).abs()),
        rho: spectral_radius(&reduced),
    })
}

/// Largest modulus of a 2×2 matrix's eigenvalues.
pub(crate) fn spectral_radius(m: &Matrix2<f64>) -> f64 {
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

/// One evaluation of the scalar return map along the Hopf direction.
struct MapPoint {
    /// s = a², with a the section velocity where the measured return starts [m²/s²].
    s: f64,
    /// Growth over that return, q = (P(a) − a) / a.
    q: f64,
    /// Where that return lands, (z, v).
    image: (f64, f64),
}

/// How close to the cycle the guess must be before Newton takes over: the predicted s* within
/// this share of the last evaluated s (|s* − s| < share · s*), the first share when the cycle's
/// amplitude is bracketed (the prediction then interpolates), the second while it is still
/// extrapolated. Near onset q is linear in s and this is |q| < share · q(0); judged by q/q(0)
/// itself, a large cycle just past onset, whose growth rises to 100 q(0) before it falls through
/// zero, never passed. Newton converges from well beyond these (one iteration costs one return,
/// a map evaluation two or three); the shares (1.0, 0.6) cost 813 evaluations per limit-cycle
/// wheel on 20,000 default-study samples against 827 for (0.6, 0.3), with no failures either way.
pub(crate) const HANDOFF: (f64, f64) = (1.0, 0.6);

/// A guess that needs Newton to start closer (the retry after a failed Newton).
pub(crate) const HANDOFF_CLOSE: (f64, f64) = (0.05, 0.05);

/// Growth per period below which the guess lets the fast mode settle over two returns.
const SETTLE_TWICE_BELOW_Q0: f64 = 1e-4;

/// Map evaluations before the guess gives up.
const MAX_GUESS_EVALS: usize = 10;

/// Amplitude guess for shooting from the growth per return q(a) = (P(a) − a)/a of the scalar
/// return map along the Hopf direction, where `q0` = q(0) = e^{Re λ T} − 1 is known from the
/// eigenvalue without integrating. Near onset the Hopf normal form gives q ≈ q0 + c·a², linear
/// in s = a², so regula falsi (Illinois) in s anchored at (0, q0) predicts the amplitude from
/// the first evaluation: `handoff` says when to stop (see [`HANDOFF`]). Returns the point on
/// the section predicted for the cycle, the last image scaled along the slow manifold to the
/// predicted amplitude.
#[allow(clippy::too_many_arguments)]
pub(crate) fn amplitude_guess(
    ode: &TreadOde,
    scales: &Scales,
    dz_per_v: f64,
    q0: f64,
    start_amplitude: f64,
    linear_period_s: f64,
    rtol: f64,
    handoff: (f64, f64),
    meter: &Meter,
) -> Result<(f64, f64), ShootingError> {
    let y_sec = scales.y_eq;
    let opts = SolverOptions::section_return(rtol, scales.atol(rtol), linear_period_s);
    // The first return lets the fast bristle mode (multiplier ~0.02 per period) die out; the
    // growth is read over the next one, which starts near the slow manifold. Near onset the
    // growth itself is that small (q0 = 2e-6 put a cycle at half its amplitude): one more.
    let method = method_for(rtol);
    let settling_returns = if q0 < SETTLE_TWICE_BELOW_Q0 { 2 } else { 1 };
    let state_after_return = |x: [f64; 3]| -> Result<[f64; 3], ShootingError> {
        let r = next_return(
            method,
            ode,
            x,
            y_sec,
            linear_period_s,
            &opts,
            meter,
            |_, _| {},
        )?;
        Ok(r.state)
    };
    let map = |a: f64| -> Result<MapPoint, ShootingError> {
        let mut x1 = [scales.z_eq + a * dz_per_v, y_sec, a];
        for _ in 0..settling_returns {
            x1 = state_after_return(x1)?;
        }
        let x2 = state_after_return(x1)?;
        if !(x1[2] > 0.0 && x2[2].is_finite()) {
            return Err(ShootingError::MapNotFinite);
        }
        Ok(MapPoint {
            s: x1[2] * x1[2],
            q: (x2[2] - x1[2]) / x1[2],
            image: (x2[0], x2[2]),
        })
    };
    // Regula falsi on the growing side `lo` and the decaying side `hi`, both (s, q).
    let mut lo = (0.0, q0);
    let mut hi: Option<(f64, f64)> = None;
    let mut a = start_amplitude;
    let mut last_side = 0;
    for _ in 0..MAX_GUESS_EVALS {
        let MapPoint { s, q, image } = map(a)?;
        if q > 0.0 {
            lo = (s, q);
            if let (Some(h), 1) = (hi.as_mut(), last_side) {
                h.1 *= 0.5; // Illinois: the other side has stayed twice
            }
            last_side = 1;
        } else {
            hi = Some((s, q));
            if last_side == -1 {
                lo.1 *= 0.5;
            }
            last_side = -1;
        }
        let (s_next, limit) = match hi {
            Some(h) => (lo.0 - lo.1 * (h.0 - lo.0) / (h.1 - lo.1), handoff.0),
            // Still growing: extrapolate the line through (0, q0) while q falls, else go out.
            None if q < 0.95 * q0 => ((s * q0 / (q0 - q)).min(16.0 * s), handoff.1),
            None => (4.0 * s, 0.0),
        };
        if (s_next - s).abs() < limit * s_next {
            let k = s_next.sqrt() / image.1;
            return Ok((scales.z_eq + k * (image.0 - scales.z_eq), k * image.1));
        }
        a = s_next.sqrt();
        if a > 50.0 * scales.v {
            return Err(ShootingError::Unbounded);
        }
        if a < 1e-7 * scales.v {
            return Err(ShootingError::DecayWhileUnstable);
        }
    }
    Err(ShootingError::NoGuess(MAX_GUESS_EVALS))
}

#[cfg(test)]
mod tests;
