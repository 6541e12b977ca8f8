//! Step 9 of MODEL.md: where does the tread go after a small disturbance? The verdict for one
//! wheel: stable equilibrium, limit cycle (self-excited vibration), both (bistable), no traction,
//! or failed, with amplitude, frequency, polygon order, energy and the work it took.
//!
//! Route (fast and exact): linear stability at the equilibrium decides the onset; an unstable
//! equilibrium's limit cycle is found directly by shooting (Newton on the Poincaré return map),
//! started from the Hopf direction with a bracketed amplitude; long integration with envelope
//! tracking is the fallback when shooting fails, and the optional hard-excitation check looks for
//! a cycle coexisting with a stable equilibrium.

pub mod envelope;
pub mod section;
pub mod shooting;
pub mod validation;

use nalgebra::{Complex, Vector3};

use crate::model::{ModelFailure, State, TreadOde, Variant, Wheel, WheelModel};
use crate::params::Params;
use envelope::Envelope;

/// Smallest section velocity of a limit cycle, relative to the road's lateral speed U: smaller
/// "cycles" are the equilibrium seen through integration noise (a stable equilibrium has a
/// return map whose fixed point at v → 0 passes for a cycle with multiplier e^(Re λ·T) < 1).
pub const MIN_CYCLE_V_REL: f64 = 1e-5;

/// The verdict's class (the `class` column; written and read back by its name, see `as_str`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// The equilibrium attracts: no self-excited vibration.
    Stable,
    /// The tread settles on a limit cycle: self-excited vibration, polygonal wear likely.
    LimitCycle,
    /// A stable limit cycle coexists with a stable equilibrium (found by the hard-excitation check).
    Bistable,
    /// The driving wheel cannot transmit the drive force (MODEL.md step 4).
    NoTraction,
    /// The model or the numerics failed; `reason` says why.
    Failed,
}

serialize_as_str!(Class, Method);
display_and_parse!(Class, "class");
display_and_parse!(Method, "method");

impl Class {
    /// Every class, in the order of the declaration.
    pub const ALL: [Class; 5] = [
        Class::Stable,
        Class::LimitCycle,
        Class::Bistable,
        Class::NoTraction,
        Class::Failed,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Class::Stable => "stable",
            Class::LimitCycle => "limit_cycle",
            Class::Bistable => "bistable",
            Class::NoTraction => "no_traction",
            Class::Failed => "failed",
        }
    }

    /// Whether the tread vibrates (or can, after a hard enough disturbance).
    pub fn vibrates(self) -> bool {
        matches!(self, Class::LimitCycle | Class::Bistable)
    }
}

/// How the verdict was reached (the `method` column).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// Eigenvalues alone (stable equilibrium, or no model).
    Linear,
    /// Periodic orbit by Newton shooting.
    Shooting,
    /// Long integration with envelope tracking.
    Envelope,
    /// Brute-force fixed-horizon integration (the test reference).
    Reference,
}

impl Method {
    /// Every method, in the order of the declaration.
    pub const ALL: [Method; 4] = [
        Method::Linear,
        Method::Shooting,
        Method::Envelope,
        Method::Reference,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Method::Linear => "linear",
            Method::Shooting => "shooting",
            Method::Envelope => "envelope",
            Method::Reference => "reference",
        }
    }
}

/// Everything the classifier says about one wheel. Amplitudes are half peak-to-peak; all
/// cycle quantities are 0 when there is no cycle, and NaN where they are undefined.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelVerdict {
    pub class: Class,
    /// Largest real part of the Jacobian's eigenvalues at the equilibrium [1/s].
    pub eig_re_max: f64,
    /// Linear frequency |Im λ|/2π of that eigenvalue [Hz].
    pub eig_freq_hz: f64,
    pub amp_y_m: f64,
    pub amp_v_mps: f64,
    /// Limit-cycle frequency 1/T [Hz].
    pub freq_hz: f64,
    /// Wear facets n = f / f_rot (MODEL.md step 9).
    pub polygon_order: f64,
    /// Energy fed by friction into the tread per cycle, equal to what the tread damper
    /// dissipates: E = ∮ C_s v² dt [J].
    pub energy_per_cycle_j: f64,
    /// Modulus of the largest non-trivial Floquet multiplier of the cycle (NaN if none).
    pub floquet_max: f64,
    /// Right-hand-side evaluations spent (variational evaluations count as one).
    pub rhs_evals: u64,
    pub method: Method,
    /// Why the class is `failed` or `no_traction`; empty otherwise.
    pub reason: String,
}

impl WheelVerdict {
    pub(crate) fn without_cycle(
        class: Class,
        eig_re_max: f64,
        eig_freq_hz: f64,
        method: Method,
    ) -> Self {
        WheelVerdict {
            class,
            eig_re_max,
            eig_freq_hz,
            amp_y_m: 0.0,
            amp_v_mps: 0.0,
            freq_hz: 0.0,
            polygon_order: 0.0,
            energy_per_cycle_j: 0.0,
            floquet_max: f64::NAN,
            rhs_evals: 0,
            method,
            reason: String::new(),
        }
    }

    /// A verdict for a point where no ODE exists (no traction, invalid static model).
    pub fn from_model_failure(f: &ModelFailure) -> Self {
        let class = match f {
            ModelFailure::NoTraction { .. } => Class::NoTraction,
            ModelFailure::Invalid(_) => Class::Failed,
        };
        let mut v = Self::without_cycle(class, f64::NAN, f64::NAN, Method::Linear);
        v.reason = f.to_string();
        v
    }
}

/// Settings of the classifier; the defaults are what `simulate`, `bifurcation` and `explore` use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassifierOptions {
    /// Relative tolerance of the shooting integrations.
    pub rtol: f64,
    /// Newton converges when the return-map residual is below this, relative to the state scales.
    pub newton_tol: f64,
    /// Initial disturbance of y for trajectories started at the equilibrium [m] (MODEL.md step 9).
    pub disturbance_m: f64,
    /// Hard-excitation check: lateral velocity amplitude of the kick [m/s]; None to skip.
    pub kick_mps: Option<f64>,
    /// Simulated-time limit of the envelope-tracking fallback [s].
    pub fallback_max_s: f64,
}

impl Default for ClassifierOptions {
    fn default() -> Self {
        ClassifierOptions {
            rtol: 1e-9,
            newton_tol: 1e-8,
            disturbance_m: 1e-5,
            kick_mps: None,
            fallback_max_s: 60.0,
        }
    }
}

/// Scales of the three states at one equilibrium, for tolerances and convergence tests.
#[derive(Debug, Clone, Copy)]
pub struct Scales {
    pub z_eq: f64,
    pub y_eq: f64,
    /// |z0| [m].
    pub z: f64,
    /// |y0| [m].
    pub y: f64,
    /// Road lateral speed U [m/s].
    pub v: f64,
}

impl Scales {
    pub fn new(ode: &TreadOde) -> Self {
        let eq = ode.equilibrium();
        Scales {
            z_eq: eq[0],
            y_eq: eq[1],
            z: eq[0].abs(),
            y: eq[1].abs(),
            v: ode.u_mps.abs(),
        }
    }

    /// Absolute tolerances matching `rtol` at these scales.
    pub fn atol(&self, rtol: f64) -> [f64; 3] {
        [rtol * self.z, rtol * self.y, rtol * self.v]
    }
}

/// Classifies one wheel at one operating point: steps 1–9 of MODEL.md.
pub fn classify_point(
    p: &Params,
    wheel: Wheel,
    variant: Variant,
    opts: &ClassifierOptions,
) -> (Result<WheelModel, ModelFailure>, WheelVerdict) {
    match WheelModel::build(p, wheel, variant) {
        Ok(model) => {
            let verdict = classify(&model.ode, WheelModel::rotation_hz(p), opts);
            (Ok(model), verdict)
        }
        Err(f) => {
            let verdict = WheelVerdict::from_model_failure(&f);
            (Err(f), verdict)
        }
    }
}

/// The verdict for one tread ODE (step 9). `rotation_hz` converts frequency to polygon order.
pub fn classify(ode: &TreadOde, rotation_hz: f64, opts: &ClassifierOptions) -> WheelVerdict {
    let lin = ode.linear_stability();
    let scales = Scales::new(ode);
    let oscillatory = lin.eig_freq_hz > 0.0;
    let mut evals = 0usize;
    let fail = |reason: String, evals: usize| {
        let mut v = WheelVerdict::without_cycle(
            Class::Failed,
            lin.eig_re_max,
            lin.eig_freq_hz,
            Method::Envelope,
        );
        v.reason = reason;
        v.rhs_evals = evals as u64;
        v
    };
    if !lin.eig_re_max.is_finite() {
        return fail("non-finite Jacobian at the equilibrium".into(), 0);
    }

    if lin.eig_re_max < 0.0 {
        let mut verdict = WheelVerdict::without_cycle(
            Class::Stable,
            lin.eig_re_max,
            lin.eig_freq_hz,
            Method::Linear,
        );
        if let (Some(kick), true) = (opts.kick_mps, oscillatory) {
            // Hard excitation: does a cycle coexist with the stable equilibrium?
            let period = 1.0 / lin.eig_freq_hz;
            let dz = hopf_dz_per_v(ode, lin.leading);
            let start = [scales.z_eq + kick * dz, scales.y_eq, kick];
            match envelope::track(ode, &scales, start, opts.fallback_max_s, opts.rtol) {
                Ok((Envelope::Settles { z, v }, e)) => {
                    evals += e;
                    if let Ok(orbit) = shooting::newton_orbit(
                        ode,
                        &scales,
                        z,
                        v,
                        period,
                        opts.rtol,
                        opts.newton_tol,
                    ) {
                        evals += orbit.rhs_evals;
                        if orbit.floquet_max < 1.0 {
                            let mut v =
                                cycle_verdict(ode, &scales, &orbit, &lin, rotation_hz, opts, evals);
                            v.class = Class::Bistable;
                            return v;
                        }
                    }
                }
                Ok((_, e)) => evals += e,
                Err(reason) => return fail(format!("hard-excitation check: {reason}"), evals),
            }
        }
        verdict.rhs_evals = evals as u64;
        return verdict;
    }

    // Unstable equilibrium: find the limit cycle by shooting from the Hopf direction.
    if oscillatory {
        let period = 1.0 / lin.eig_freq_hz;
        let dz = hopf_dz_per_v(ode, lin.leading);
        let shot = shooting::amplitude_guess(ode, &scales, dz, 0.3 * scales.v, period, 1e-7)
            .and_then(|((z, v), e)| {
                evals += e;
                shooting::newton_orbit(ode, &scales, z, v, period, opts.rtol, opts.newton_tol)
            });
        if let Ok(orbit) = shot {
            evals += orbit.rhs_evals;
            if orbit.floquet_max < 1.0 {
                return cycle_verdict(ode, &scales, &orbit, &lin, rotation_hz, opts, evals);
            }
        }
    }

    // Fallback: follow the trajectory from the disturbed equilibrium.
    let start = [scales.z_eq, scales.y_eq + opts.disturbance_m, 0.0];
    match envelope::track(ode, &scales, start, opts.fallback_max_s, opts.rtol) {
        Ok((Envelope::Decays, e)) => {
            evals += e;
            let mut v = WheelVerdict::without_cycle(
                Class::Stable,
                lin.eig_re_max,
                lin.eig_freq_hz,
                Method::Envelope,
            );
            v.rhs_evals = evals as u64;
            v
        }
        Ok((Envelope::Settles { z, v }, e)) => {
            evals += e;
            let period = if oscillatory {
                1.0 / lin.eig_freq_hz
            } else {
                4e-3
            };
            match shooting::newton_orbit(ode, &scales, z, v, period, opts.rtol, opts.newton_tol) {
                Ok(orbit) => {
                    evals += orbit.rhs_evals;
                    let mut v = cycle_verdict(ode, &scales, &orbit, &lin, rotation_hz, opts, evals);
                    v.method = Method::Envelope;
                    v
                }
                Err(reason) => fail(format!("envelope settled but {reason}"), evals),
            }
        }
        Ok((Envelope::Undecided { last_v }, e)) => fail(
            format!(
                "not settled within {} s (last section velocity {last_v:.3e} m/s)",
                opts.fallback_max_s
            ),
            evals + e,
        ),
        Err(reason) => fail(reason, evals),
    }
}

/// Direction of the Hopf eigenvector on the section y = y_eq, as dz per unit v.
fn hopf_dz_per_v(ode: &TreadOde, lambda: Complex<f64>) -> f64 {
    let jac = ode.jacobian(&ode.equilibrium());
    let row = |i: usize| {
        Vector3::new(
            Complex::new(jac[(i, 0)], 0.0)
                - if i == 0 {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                },
            Complex::new(jac[(i, 1)], 0.0)
                - if i == 1 {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                },
            Complex::new(jac[(i, 2)], 0.0)
                - if i == 2 {
                    lambda
                } else {
                    Complex::new(0.0, 0.0)
                },
        )
    };
    // The eigenvector spans the null space of J − λI: cross product of two independent rows.
    let q = row(0).cross(&row(1));
    let q = if q.norm() > 0.0 {
        q
    } else {
        row(1).cross(&row(2))
    };
    // Rotate the phase so that the y component is purely imaginary: Re(q) then lies on y = 0.
    let rot = Complex::from_polar(1.0, std::f64::consts::FRAC_PI_2 - q[1].arg());
    let d = q.map(|c| (c * rot).re);
    if d[2] == 0.0 {
        0.0
    } else {
        d[0] / d[2]
    }
}

/// The limit-cycle verdict for a converged orbit: amplitudes, frequency, energy and polygon
/// order from one period integrated with dense output; `evals` is the work spent so far.
fn cycle_verdict(
    ode: &TreadOde,
    scales: &Scales,
    orbit: &shooting::PeriodicOrbit,
    lin: &crate::model::LinearStability,
    rotation_hz: f64,
    opts: &ClassifierOptions,
    evals: usize,
) -> WheelVerdict {
    let m = measure_cycle(ode, scales, orbit.start, orbit.period_s, opts.rtol);
    let freq_hz = 1.0 / orbit.period_s;
    WheelVerdict {
        class: Class::LimitCycle,
        eig_re_max: lin.eig_re_max,
        eig_freq_hz: lin.eig_freq_hz,
        amp_y_m: m.0,
        amp_v_mps: m.1,
        freq_hz,
        polygon_order: freq_hz / rotation_hz,
        energy_per_cycle_j: m.2,
        floquet_max: orbit.floquet_max,
        rhs_evals: (evals + m.3) as u64,
        method: Method::Shooting,
        reason: String::new(),
    }
}

/// Half peak-to-peak of y and v, and ∮ C_s v² dt (3-point Gauss–Legendre per step), over one
/// period from `start`. Returns (amp_y, amp_v, energy, rhs evaluations).
pub fn measure_cycle(
    ode: &TreadOde,
    scales: &Scales,
    start: State,
    period_s: f64,
    rtol: f64,
) -> (f64, f64, f64, usize) {
    use crate::solver::{integrate, Control, SolverOptions};
    let opts = SolverOptions {
        rtol,
        atol: scales.atol(rtol),
        h_max: period_s / 16.0,
        h0: Some(period_s / 40.0),
        max_steps: 1_000_000,
    };
    let (mut y_lo, mut y_hi) = (start[1], start[1]);
    let (mut v_lo, mut v_hi) = (start[2], start[2]);
    let mut energy = 0.0;
    const GL: [(f64, f64); 3] = [
        (0.112_701_665_379_258_3, 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.887_298_334_620_741_7, 5.0 / 18.0),
    ];
    let out = integrate(ode, 0.0, start, period_s, &opts, |s| {
        let h = s.t1 - s.t0;
        for j in 1..=8 {
            let x = s.interpolate(s.t0 + h * j as f64 / 8.0);
            y_lo = y_lo.min(x[1]);
            y_hi = y_hi.max(x[1]);
            v_lo = v_lo.min(x[2]);
            v_hi = v_hi.max(x[2]);
        }
        for (node, w) in GL {
            let v = s.interpolate(s.t0 + h * node)[2];
            energy += w * h * ode.c_s * v * v;
        }
        Control::Continue
    });
    let evals = out.map(|o| o.rhs_evals).unwrap_or(0);
    (0.5 * (y_hi - y_lo), 0.5 * (v_hi - v_lo), energy, evals)
}
