//! MODEL.md#step-9-attractor: where does the tread go after a small disturbance? The verdict for
//! one wheel: stable equilibrium, limit cycle (self-excited vibration), both (bistable), no
//! traction, or failed, with amplitude, frequency, polygon order, energy and the work it took.
//!
//! Route (fast and exact; MODEL.md#classes-and-verdicts): linear stability at the equilibrium
//! decides the onset; an unstable equilibrium's limit cycle is found directly by shooting (Newton
//! on the Poincaré return map), started from the Hopf direction with an amplitude predicted by the
//! normal form (or from the neighbouring wheel's cycle); long integration with envelope tracking is
//! the fallback when shooting fails, and the optional hard-excitation check looks for a cycle
//! coexisting with a stable equilibrium.

pub mod budget;
pub mod envelope;
mod error;
mod hopf_start;
mod peak;
mod scales;
pub mod section;
pub mod shooting;

use crate::model::{ModelFailure, TreadOde, Variant, Wheel, WheelModel};
use crate::params::Params;
use budget::Meter;
pub use budget::{BudgetError, WheelBudget};
use envelope::Envelope;
pub use error::{ClassifyError, ShootingError};
use hopf_start::{hopf_dz_per_v, normal_form_section_v};
pub use scales::Scales;
pub use shooting::CyclePath;

/// Smallest section velocity of a limit cycle, relative to the road's lateral speed U: smaller
/// "cycles" are the equilibrium seen through integration noise (a stable equilibrium has a
/// return map whose fixed point at v → 0 passes for a cycle with multiplier e^(Re λ·T) < 1).
pub const MIN_CYCLE_V_REL: f64 = 1e-5;

named_enum! {
    /// The verdict's class (the `class` column; written and read back by its name, see `as_str`).
    pub enum Class: "class" {
        /// The equilibrium attracts: no self-excited vibration.
        Stable,
        /// The tread settles on a limit cycle: self-excited vibration, polygonal wear likely.
        LimitCycle,
        /// A stable limit cycle coexists with a stable equilibrium (found by the hard-excitation check).
        Bistable,
        /// The driving wheel cannot transmit the drive force
        /// (MODEL.md#step-4-brush-model-and-slip-ratio).
        NoTraction,
        /// The model or the numerics failed; `reason` says why.
        Failed,
        /// The vehicle stands still (speed 0, a drive cycle's stop): no sliding, no tread
        /// dynamics, not vibrating.
        Standstill,
    }
}

impl Class {
    /// Every class, in the order of the declaration.
    pub const ALL: [Class; 6] = [
        Class::Stable,
        Class::LimitCycle,
        Class::Bistable,
        Class::NoTraction,
        Class::Failed,
        Class::Standstill,
    ];

    /// Whether the tread vibrates (or can, after a hard enough disturbance).
    pub fn vibrates(self) -> bool {
        matches!(self, Class::LimitCycle | Class::Bistable)
    }
}

/// A wheel's outcome in the paired comparison, as a code: 0 not vibrating, 1 vibrating, 2
/// unclassified (failed or no traction). A sample's pair is `follower + 3 × driving`.
pub fn outcome_code(class: Class) -> i64 {
    if class.vibrates() {
        1
    } else if class == Class::Stable {
        0
    } else {
        2
    }
}

named_enum! {
    /// How the verdict was reached (the `method` column).
    pub enum Method: "method" {
        /// Eigenvalues alone (stable equilibrium, or no model).
        Linear,
        /// Periodic orbit by Newton shooting.
        Shooting,
        /// Long integration with envelope tracking.
        Envelope,
        /// Brute-force fixed-horizon integration (the test reference).
        Reference,
    }
}

impl Method {
    /// Every method, in the order of the declaration.
    pub const ALL: [Method; 4] = [
        Method::Linear,
        Method::Shooting,
        Method::Envelope,
        Method::Reference,
    ];
}

/// Everything the classifier says about one wheel. Amplitudes are half peak-to-peak; all
/// cycle quantities are 0 when there is no cycle, and NaN where they are undefined.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelVerdict {
    /// The verdict.
    pub class: Class,
    /// Largest real part of the Jacobian's eigenvalues at the equilibrium [1/s].
    pub eig_re_max: f64,
    /// Linear frequency |Im λ|/2π of that eigenvalue \[Hz\].
    pub eig_freq_hz: f64,
    /// Half peak-to-peak of y over the cycle \[m\].
    pub amp_y_m: f64,
    /// Half peak-to-peak of v over the cycle [m/s].
    pub amp_v_mps: f64,
    /// Limit-cycle frequency 1/T \[Hz\].
    pub freq_hz: f64,
    /// Wear facets n = f / f_rot (MODEL.md#step-9-attractor).
    pub polygon_order: f64,
    /// Energy fed by friction into the tread per cycle, equal to what the tread damper
    /// dissipates: E = ∮ C_s v² dt \[J\].
    pub energy_per_cycle_j: f64,
    /// Modulus of the largest non-trivial Floquet multiplier of the cycle (NaN if none).
    pub floquet_max: f64,
    /// Right-hand-side evaluations spent (variational evaluations count as one).
    pub rhs_evals: u64,
    /// How the verdict was reached.
    pub method: Method,
    /// Why the class is `failed` or `no_traction`; empty otherwise.
    pub reason: String,
    /// Where the cycle crosses the section y = y_eq upwards: z \[m\] and v [m/s] (0 if no cycle).
    pub section_z_m: f64,
    /// The section velocity v \[m/s\] of the same crossing (see `section_z_m`).
    pub section_v_mps: f64,
    /// Shooting's last iteration, from which the cycle and its variational matrix follow to
    /// first order (none without a cycle, or where the cycle was found otherwise): what reads the
    /// cycle again need not integrate it again.
    pub cycle_path: Option<std::sync::Arc<CyclePath>>,
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
            section_z_m: 0.0,
            section_v_mps: 0.0,
            cycle_path: None,
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
    /// Initial disturbance of y for trajectories started at the equilibrium \[m\]
    /// (MODEL.md#step-9-attractor).
    pub disturbance_m: f64,
    /// Hard-excitation check: lateral velocity amplitude of the kick [m/s]; None to skip.
    pub kick_mps: Option<f64>,
    /// Simulated-time limit of the envelope-tracking fallback \[s\].
    pub fallback_max_s: f64,
    /// Work limits per wheel; beyond them the wheel is `failed` with `budget exceeded (...)`.
    pub budget: WheelBudget,
}

impl Default for ClassifierOptions {
    fn default() -> Self {
        ClassifierOptions {
            rtol: 1e-9,
            newton_tol: 1e-8,
            disturbance_m: 1e-5,
            kick_mps: None,
            fallback_max_s: 60.0,
            budget: WheelBudget::default(),
        }
    }
}

/// Classifies one wheel at one operating point: steps 1–9 of MODEL.md#the-physics-step-by-step.
pub fn classify_point(
    p: &Params,
    wheel: Wheel,
    variant: Variant,
    opts: &ClassifierOptions,
) -> (Result<WheelModel, ModelFailure>, WheelVerdict) {
    let (model, verdict, _) = classify_point_hinted(p, wheel, variant, opts, None);
    (model, verdict)
}

/// [`classify_point`] with a starting guess for shooting taken from a neighbouring wheel's
/// cycle (the other wheel or variant of the same sample); also returns this wheel's cycle as a
/// hint for the next.
pub(crate) fn classify_point_hinted(
    p: &Params,
    wheel: Wheel,
    variant: Variant,
    opts: &ClassifierOptions,
    hint: Option<CycleHint>,
) -> (
    Result<WheelModel, ModelFailure>,
    WheelVerdict,
    Option<CycleHint>,
) {
    match WheelModel::build(p, wheel, variant) {
        Ok(model) => {
            let (verdict, next) =
                classify_hinted(&model.ode, WheelModel::rotation_hz(p), opts, hint);
            (Ok(model), verdict, next)
        }
        Err(f) => {
            let verdict = WheelVerdict::from_model_failure(&f);
            (Err(f), verdict, None)
        }
    }
}

/// Where a limit cycle crosses the section, relative to its wheel's scales: a starting guess
/// for Newton shooting on a neighbouring wheel (same patch and stiffness, nearby friction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleHint {
    /// (z − z_eq) / |z_eq|.
    pub dz_rel: f64,
    /// v / U.
    pub v_rel: f64,
    /// That wheel's growth of small oscillations per period, e^{Re λ T} − 1.
    pub q0: f64,
}

impl CycleHint {
    /// The starting point on the section of a wheel whose small oscillations grow by `q0` per
    /// period. The Hopf normal form puts the cycle's amplitude at √(q0 / c): with the cubic
    /// coefficient c taken as the neighbour's, the amplitude scales by √(q0 / q0_neighbour)
    /// (bounded, for neighbours whose c differs a lot).
    pub fn guess(&self, scales: &Scales, q0: f64) -> (f64, f64) {
        let k = if q0 > 0.0 && self.q0 > 0.0 {
            (q0 / self.q0).sqrt().clamp(0.1, 10.0)
        } else {
            1.0
        };
        (
            scales.z_eq + k * self.dz_rel * scales.z,
            k * self.v_rel * scales.v,
        )
    }
}

/// The verdict for one tread ODE (step 9). `rotation_hz` converts frequency to polygon order.
pub fn classify(ode: &TreadOde, rotation_hz: f64, opts: &ClassifierOptions) -> WheelVerdict {
    classify_hinted(ode, rotation_hz, opts, None).0
}

/// [`classify`] with an optional shooting guess; returns the cycle's hint when there is one.
/// A wheel whose work exceeds `opts.budget` is `failed` with reason `budget exceeded (...)`.
pub fn classify_hinted(
    ode: &TreadOde,
    rotation_hz: f64,
    opts: &ClassifierOptions,
    hint: Option<CycleHint>,
) -> (WheelVerdict, Option<CycleHint>) {
    let meter = Meter::new(opts.budget);
    let mut v = classify_metered(ode, rotation_hz, opts, hint, &meter);
    v.rhs_evals = meter.used();
    if let Some(reason) = meter.exceeded() {
        if v.class == Class::Failed {
            v.reason = reason;
        }
    }
    let scales = Scales::new(ode);
    let next = (v.class.vibrates() && v.section_v_mps > 0.0).then(|| CycleHint {
        dz_rel: (v.section_z_m - scales.z_eq) / scales.z,
        v_rel: v.section_v_mps / scales.v,
        q0: (v.eig_re_max / v.eig_freq_hz).exp_m1(),
    });
    (v, next)
}

fn classify_metered(
    ode: &TreadOde,
    rotation_hz: f64,
    opts: &ClassifierOptions,
    hint: Option<CycleHint>,
    meter: &Meter,
) -> WheelVerdict {
    let lin = ode.linear_stability();
    let route = Route {
        ode,
        rotation_hz,
        opts,
        meter,
        lin,
        scales: Scales::new(ode),
        // Growth per linear period, Re λ·T; a real unstable eigenvalue has no period to shoot
        // over.
        growth: if lin.eig_freq_hz > 0.0 {
            lin.eig_re_max / lin.eig_freq_hz
        } else {
            f64::INFINITY
        },
    };
    if !lin.eig_re_max.is_finite() {
        return route.fail(
            "eigenvalues at the equilibrium are not finite (degenerate Jacobian, e.g. a toe-in \
             too small for double precision)"
                .into(),
        );
    }
    if lin.eig_re_max < 0.0 {
        return route.stable();
    }
    if let Some(v) = route.shoot(hint) {
        return v;
    }
    if meter.exceeded().is_some() {
        return route.fail(String::new());
    }
    route.follow()
}

/// One wheel's way to its verdict (MODEL.md#classes-and-verdicts): what every branch shares.
struct Route<'a> {
    ode: &'a TreadOde,
    rotation_hz: f64,
    opts: &'a ClassifierOptions,
    meter: &'a Meter,
    lin: crate::model::LinearStability,
    scales: Scales,
    /// Growth of small oscillations per linear period, Re λ·T (infinite without a period).
    growth: f64,
}

impl Route<'_> {
    fn oscillatory(&self) -> bool {
        self.lin.eig_freq_hz > 0.0
    }

    fn fail(&self, reason: String) -> WheelVerdict {
        let mut v = WheelVerdict::without_cycle(
            Class::Failed,
            self.lin.eig_re_max,
            self.lin.eig_freq_hz,
            Method::Envelope,
        );
        v.reason = reason;
        v
    }

    fn tols(&self) -> shooting::Tolerances {
        shooting::Tolerances::for_growth(self.growth, self.opts.rtol)
    }

    fn newton_with(
        &self,
        guess: (f64, f64),
        period: f64,
        tols: &shooting::Tolerances,
    ) -> Result<shooting::PeriodicOrbit, ShootingError> {
        let (ode, scales, meter) = (self.ode, &self.scales, self.meter);
        shooting::newton_orbit(
            ode,
            scales,
            guess,
            period,
            tols,
            self.opts.newton_tol,
            meter,
        )
    }

    fn newton(
        &self,
        guess: (f64, f64),
        period: f64,
    ) -> Result<shooting::PeriodicOrbit, ShootingError> {
        self.newton_with(guess, period, &self.tols())
    }

    fn cycle(&self, orbit: shooting::PeriodicOrbit) -> WheelVerdict {
        cycle_verdict(orbit, &self.lin, self.rotation_hz)
    }

    /// A stable equilibrium; with the hard-excitation check, is a cycle coexisting with it?
    fn stable(&self) -> WheelVerdict {
        let (lin, scales) = (&self.lin, &self.scales);
        let verdict = WheelVerdict::without_cycle(
            Class::Stable,
            lin.eig_re_max,
            lin.eig_freq_hz,
            Method::Linear,
        );
        let (Some(kick), true) = (self.opts.kick_mps, self.oscillatory()) else {
            return verdict;
        };
        let period = 1.0 / lin.eig_freq_hz;
        let dz = hopf_dz_per_v(self.ode, lin.leading);
        let start = [scales.z_eq + kick * dz, scales.y_eq, kick];
        let max_s = self.opts.fallback_max_s;
        match envelope::track(self.ode, scales, start, max_s, self.opts.rtol, self.meter) {
            Ok(Envelope::Settles { z, v }) => {
                if let Ok(orbit) = self.newton((z, v), period) {
                    if orbit.floquet_max < 1.0 {
                        let mut v = self.cycle(orbit);
                        v.class = Class::Bistable;
                        return v;
                    }
                }
            }
            Ok(_) => {}
            Err(reason) => return self.fail(format!("hard-excitation check: {reason}")),
        }
        if self.meter.exceeded().is_some() {
            return self.fail(String::new());
        }
        verdict
    }

    /// Unstable equilibrium: the limit cycle by shooting, from the neighbouring wheel's cycle
    /// when there is one, else from where the Hopf normal form puts it; failing that, from the
    /// amplitude the return map along the Hopf direction predicts, retried once closer. None
    /// when shooting finds no attracting cycle.
    fn shoot(&self, hint: Option<CycleHint>) -> Option<WheelVerdict> {
        if !self.oscillatory() {
            return None;
        }
        let (scales, tols) = (&self.scales, self.tols());
        let period = 1.0 / self.lin.eig_freq_hz;
        let q0 = self.growth.exp_m1();
        let attracting = |o: Result<shooting::PeriodicOrbit, ShootingError>| {
            o.ok().filter(|o| o.floquet_max < 1.0)
        };
        if let Some(orbit) = hint.and_then(|h| attracting(self.newton(h.guess(scales, q0), period)))
        {
            return Some(self.cycle(orbit));
        }
        let dz = hopf_dz_per_v(self.ode, self.lin.leading);
        // Newton's residual test passes an orbit whose amplitude is off by about newton_tol /
        // (2·growth): only well above the Hopf point can it start from a guess 20% off.
        let from_normal_form = hopf_start::normal_form_applies(self.growth, self.opts.newton_tol);
        let a = if from_normal_form {
            normal_form_section_v(self.growth)
        } else {
            hopf_start::GUESS_START_V_REL
        } * scales.v;
        if from_normal_form {
            let orbit = self.newton_with((scales.z_eq + a * dz, a), period, &tols.looser_first());
            if let Some(orbit) = attracting(orbit) {
                return Some(self.cycle(orbit));
            }
        }
        for handoff in [shooting::HANDOFF, shooting::HANDOFF_CLOSE] {
            if self.meter.exceeded().is_some() {
                break;
            }
            let guess = shooting::amplitude_guess(
                self.ode, scales, dz, q0, a, period, tols.guess, handoff, self.meter,
            );
            let Ok(guess) = guess else {
                break;
            };
            if let Some(orbit) = attracting(self.newton(guess, period)) {
                return Some(self.cycle(orbit));
            }
        }
        None
    }

    /// The fallback: the trajectory from the disturbed equilibrium, followed by its envelope.
    fn follow(&self) -> WheelVerdict {
        let (ode, scales, lin, opts) = (self.ode, &self.scales, &self.lin, self.opts);
        let start = [scales.z_eq, scales.y_eq + opts.disturbance_m, 0.0];
        match envelope::track(
            ode,
            scales,
            start,
            opts.fallback_max_s,
            opts.rtol,
            self.meter,
        ) {
            // Small oscillations cannot die out around an unstable equilibrium: the envelope has
            // mistaken the fast mode's decay, or a growth too slow to see, for the verdict.
            Ok(Envelope::Decays) if lin.eig_re_max > 0.0 => self.fail(format!(
                "the envelope decayed although the equilibrium is unstable (Re λ = {:.3e} 1/s)",
                lin.eig_re_max
            )),
            Ok(Envelope::Decays) => WheelVerdict::without_cycle(
                Class::Stable,
                lin.eig_re_max,
                lin.eig_freq_hz,
                Method::Envelope,
            ),
            Ok(Envelope::Settles { z, v }) => self.settled(z, v),
            Ok(Envelope::Undecided { last_v }) => self.fail(format!(
                "not settled within {} s (last section velocity {last_v:.3e} m/s)",
                opts.fallback_max_s
            )),
            Err(reason) => self.fail(reason.to_string()),
        }
    }

    /// The envelope settled at section state (z, v): the cycle by Newton from there, or read
    /// off the settled trajectory where Newton has nothing to hold on to.
    fn settled(&self, z: f64, v: f64) -> WheelVerdict {
        let period = if self.oscillatory() {
            1.0 / self.lin.eig_freq_hz
        } else {
            4e-3
        };
        match self.newton((z, v), period) {
            Ok(orbit) => {
                let mut v = self.cycle(orbit);
                v.method = Method::Envelope;
                v
            }
            // So close to the Hopf point (Re λ·T ~ 1e-7) the return map is the identity to
            // within the integration error and Newton has nothing to hold on to; the envelope
            // has settled, so the cycle is measured on the settled trajectory.
            Err(reason) => {
                let start = [z, self.scales.y_eq, v];
                let (ode, scales, lin) = (self.ode, &self.scales, &self.lin);
                let rtol = self.opts.rtol;
                settled_cycle(ode, scales, lin, self.rotation_hz, start, rtol, self.meter)
                    .unwrap_or_else(|e| self.fail(format!("envelope settled but {reason}; {e}")))
            }
        }
    }
}

/// The verdict of a cycle read off the trajectory from the envelope's settled section state
/// `start`, for when Newton cannot hold on (within about 1e-4 s⁻¹ of the Hopf point the return
/// map is the identity to within the integration error). 40 linear periods are integrated and
/// measured over two windows of 20 (as the brute force of MODEL.md#reference-data does). Where the
/// amplitude still drifts, the cycle is that of the Hopf normal form dA/dt = A (Re λ + l1 A²)
/// fitted to the drift: with r = d ln A/dt measured at Ā, l1 = (r − Re λ)/Ā² and A*² = −Re λ/l1 =
/// Ā² Re λ/(Re λ − r), supercritical (l1 < 0) only. Energy per cycle from the near-sinusoidal
/// velocity, C_s·A_v²/(2f).
fn settled_cycle(
    ode: &TreadOde,
    scales: &Scales,
    lin: &crate::model::LinearStability,
    rotation_hz: f64,
    start: crate::model::State,
    rtol: f64,
    meter: &Meter,
) -> Result<WheelVerdict, ClassifyError> {
    let period = 1.0 / lin.eig_freq_hz;
    let opts = crate::solver::SolverOptions::per_period(
        rtol,
        scales.atol(rtol),
        period,
        meter.max_steps(1_000_000, crate::solver::Method::Dopri5.evals_per_step()),
    );
    let window_s = 20.0 * period;
    let (prev, last, evals) =
        envelope::measure_windows(ode, start, 2.0 * window_s, window_s, &opts)?;
    meter.charge(evals);
    let ok =
        |m: &envelope::WindowMeasure| m.amp_v_mps > MIN_CYCLE_V_REL * scales.v && m.freq_hz > 0.0;
    if !(ok(&prev) && ok(&last)) {
        return Err(ClassifyError::NoSettledCycle {
            prev_mps: prev.amp_v_mps,
            last_mps: last.amp_v_mps,
        });
    }
    let re = lin.eig_re_max;
    let drift = (last.amp_v_mps / prev.amp_v_mps).ln() / window_s;
    let scale = if (last.amp_v_mps - prev.amp_v_mps).abs() <= 1e-4 * last.amp_v_mps {
        1.0
    } else if re > 0.0 && drift < re {
        let a_mid = (last.amp_v_mps * prev.amp_v_mps).sqrt();
        a_mid * (re / (re - drift)).sqrt() / last.amp_v_mps
    } else {
        return Err(ClassifyError::StillGrowing {
            drift_per_s: drift,
            re_per_s: re,
        });
    };
    let amp_v_mps = scale * last.amp_v_mps;
    Ok(WheelVerdict {
        class: Class::LimitCycle,
        eig_re_max: lin.eig_re_max,
        eig_freq_hz: lin.eig_freq_hz,
        amp_y_m: scale * last.amp_y_m,
        amp_v_mps,
        freq_hz: last.freq_hz,
        polygon_order: last.freq_hz / rotation_hz,
        energy_per_cycle_j: ode.c_s * amp_v_mps.powi(2) / (2.0 * last.freq_hz),
        floquet_max: f64::NAN,
        rhs_evals: 0,
        method: Method::Envelope,
        reason: String::new(),
        section_z_m: start[0],
        section_v_mps: start[2],
        cycle_path: None,
    })
}

/// The limit-cycle verdict for a converged orbit: frequency and polygon order from its period,
/// amplitudes and energy from the period integrated by its last Newton iteration.
fn cycle_verdict(
    orbit: shooting::PeriodicOrbit,
    lin: &crate::model::LinearStability,
    rotation_hz: f64,
) -> WheelVerdict {
    let m = orbit.measure;
    let freq_hz = 1.0 / orbit.period_s;
    WheelVerdict {
        class: Class::LimitCycle,
        eig_re_max: lin.eig_re_max,
        eig_freq_hz: lin.eig_freq_hz,
        amp_y_m: m.amp_y_m,
        amp_v_mps: m.amp_v_mps,
        freq_hz,
        polygon_order: freq_hz / rotation_hz,
        energy_per_cycle_j: m.energy_j,
        floquet_max: orbit.floquet_max,
        rhs_evals: 0,
        method: Method::Shooting,
        reason: String::new(),
        section_z_m: orbit.start[0],
        section_v_mps: orbit.start[2],
        cycle_path: orbit.path.map(std::sync::Arc::new),
    }
}

#[cfg(test)]
mod tests;
