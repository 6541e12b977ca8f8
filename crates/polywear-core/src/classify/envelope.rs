//! Long integration with envelope tracking: the fallback when shooting fails, the hard-excitation
//! check, and the brute-force reference that the fast classifier is tested against.

use super::budget::Meter;
use super::section::{crossing_in_step, metered};
use super::{ClassifyError, Scales, MIN_CYCLE_V_REL};
use crate::model::{State, TreadOde};
use crate::solver::{integrate, Control, Method, SolverOptions};

/// Where a trajectory was heading when envelope tracking stopped.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Envelope {
    /// Section amplitudes decay geometrically to zero.
    Decays,
    /// Section amplitudes converge to a positive value: a point near the cycle on the section.
    Settles {
        /// Extrapolated z where the cycle crosses the section \[m\].
        z: f64,
        /// Extrapolated v where the cycle crosses the section [m/s].
        v: f64,
    },
    /// No verdict within the time limit.
    Undecided {
        /// The last section velocity seen [m/s].
        last_v: f64,
    },
}

/// Follows the trajectory from `start`, recording the velocity at each upward section crossing,
/// and extrapolates the sequence (Aitken Δ²) to decide early where it goes.
pub(crate) fn track(
    ode: &TreadOde,
    scales: &Scales,
    start: State,
    max_time_s: f64,
    rtol: f64,
    meter: &Meter,
) -> Result<Envelope, ClassifyError> {
    let opts = SolverOptions::transient(rtol, scales.atol(rtol), 50_000_000);
    let mut hist: Vec<(f64, f64)> = Vec::new(); // (z, v) at crossings
    let mut verdict = None;
    let mut steady = 0;
    // The fallback stays on DOPRI5, with which its verdicts near the Hopf point were set.
    let dopri5 = Method::Dopri5;
    metered(dopri5, ode, start, max_time_s, &opts, meter, |step| {
        let Some((_, x)) = crossing_in_step(step, scales.y_eq) else {
            return Control::Continue;
        };
        hist.push((x[0], x[2]));
        let n = hist.len();
        // Below this the "oscillation" is integration noise around the equilibrium.
        if x[2] < MIN_CYCLE_V_REL * scales.v {
            verdict = Some(Envelope::Decays);
            return Control::Stop;
        }
        if n < 4 {
            return Control::Continue;
        }
        let (v0, v1, v2) = (hist[n - 3].1, hist[n - 2].1, hist[n - 1].1);
        let (d1, d2) = (v1 - v0, v2 - v1);
        if d2.abs() <= 1e-10 * v2 {
            verdict = Some(Envelope::Settles { z: x[0], v: v2 });
            return Control::Stop;
        }
        let ratio = d2 / d1;
        let prev_ratio = {
            let d0 = v0 - hist[n - 4].1;
            d1 / d0
        };
        // A steady contraction ratio in (0, 1) means geometric convergence: extrapolate.
        if ratio > 0.0 && ratio < 1.0 && (ratio - prev_ratio).abs() < 1e-3 {
            steady += 1;
        } else {
            steady = 0;
        }
        if steady >= 3 {
            let limit_v = v2 + d2 * ratio / (1.0 - ratio);
            if limit_v <= MIN_CYCLE_V_REL * scales.v {
                verdict = Some(Envelope::Decays);
            } else {
                let (z1, z2) = (hist[n - 2].0, hist[n - 1].0);
                let limit_z = z2 + (z2 - z1) * ratio / (1.0 - ratio);
                verdict = Some(Envelope::Settles {
                    z: limit_z,
                    v: limit_v,
                });
            }
            return Control::Stop;
        }
        Control::Continue
    })?;
    Ok(verdict.unwrap_or(Envelope::Undecided {
        last_v: hist.last().map_or(0.0, |h| h.1),
    }))
}

/// Amplitudes and frequency measured on a trajectory window, the way MODEL.md#reference-data does.
#[derive(Debug, Clone, Copy, Default)]
pub struct WindowMeasure {
    /// Half peak-to-peak of y over the window \[m\].
    pub amp_y_m: f64,
    /// Half peak-to-peak of v over the window [m/s].
    pub amp_v_mps: f64,
    /// Frequency from upward crossings of v's mid-range level \[Hz\]; 0 with fewer than two.
    pub freq_hz: f64,
}

/// Brute-force reference (MODEL.md#reference-data, `tests/data/points.csv`): integrate `duration_s`
/// from the equilibrium plus `disturbance_m` in y at `rtol`, and measure amplitudes (half
/// peak-to-peak) and frequency over the last `window_s`. Also returns the same measure on the
/// window before it, so callers can tell a settled cycle from a slow transient.
pub fn brute_force(
    ode: &TreadOde,
    scales: &Scales,
    disturbance_m: f64,
    duration_s: f64,
    window_s: f64,
    rtol: f64,
) -> Result<(WindowMeasure, WindowMeasure, usize), ClassifyError> {
    let opts = SolverOptions::transient(rtol, scales.atol(rtol), 500_000_000);
    let start = [scales.z_eq, scales.y_eq + disturbance_m, 0.0];
    measure_windows(ode, start, duration_s, window_s, &opts)
}

/// Integrates `duration_s` from `start` and measures the last two windows of `window_s` each
/// (see [`brute_force`]); also returns the RHS evaluations spent.
pub(crate) fn measure_windows(
    ode: &TreadOde,
    start: State,
    duration_s: f64,
    window_s: f64,
    opts: &SolverOptions<3>,
) -> Result<(WindowMeasure, WindowMeasure, usize), ClassifyError> {
    let mut windows = [WindowStats::new(), WindowStats::new()];
    let w_prev = duration_s - 2.0 * window_s;
    let w_last = duration_s - window_s;
    let out = integrate(ode, 0.0, start, duration_s, opts, |step| {
        if step.t1 <= w_prev {
            return Control::Continue;
        }
        const SUB: usize = 8;
        for j in 0..=SUB {
            let t = step.t0 + (step.t1 - step.t0) * j as f64 / SUB as f64;
            let idx = if t >= w_last {
                1
            } else if t >= w_prev {
                0
            } else {
                continue;
            };
            let x = if j == SUB {
                *step.x1
            } else {
                step.interpolate(t)
            };
            windows[idx].add(t, x);
        }
        Control::Continue
    })?;
    let [prev, last] = windows;
    Ok((prev.finish(), last.finish(), out.rhs_evals))
}

/// Running extremes and mean-level crossings of one window.
struct WindowStats {
    y: (f64, f64),
    v: (f64, f64),
    prev: Option<(f64, f64)>,
    crossings: Vec<f64>,
    samples: Vec<(f64, f64)>,
}

impl WindowStats {
    fn new() -> Self {
        WindowStats {
            y: (f64::INFINITY, f64::NEG_INFINITY),
            v: (f64::INFINITY, f64::NEG_INFINITY),
            prev: None,
            crossings: Vec::new(),
            samples: Vec::new(),
        }
    }

    fn add(&mut self, t: f64, x: State) {
        self.y = (self.y.0.min(x[1]), self.y.1.max(x[1]));
        self.v = (self.v.0.min(x[2]), self.v.1.max(x[2]));
        self.samples.push((t, x[2]));
    }

    fn finish(mut self) -> WindowMeasure {
        if self.samples.is_empty() {
            return WindowMeasure::default();
        }
        // Frequency from upward crossings of the velocity's mid-range level, linearly interpolated.
        let mid = 0.5 * (self.v.0 + self.v.1);
        for &(t, v) in &self.samples {
            if let Some((tp, vp)) = self.prev {
                if vp < mid && v >= mid {
                    self.crossings.push(tp + (t - tp) * (mid - vp) / (v - vp));
                }
            }
            self.prev = Some((t, v));
        }
        let n = self.crossings.len();
        let freq_hz = if n >= 2 {
            (n - 1) as f64 / (self.crossings[n - 1] - self.crossings[0])
        } else {
            0.0
        };
        WindowMeasure {
            amp_y_m: 0.5 * (self.y.1 - self.y.0),
            amp_v_mps: 0.5 * (self.v.1 - self.v.0),
            freq_hz,
        }
    }
}

/// Relative tolerance of the brute-force reference (as in `tests/data/points.csv`).
pub(crate) const REFERENCE_RTOL: f64 = 1e-10;

/// The brute-force verdict used to test the fast classifier: the method of MODEL.md#reference-data
/// (a long trajectory at rtol 1e-10 from the disturbed equilibrium, amplitudes over its last 0.5 s,
/// `limit_cycle` where the velocity amplitude exceeds 1e-4 m/s), with the horizon stretched to
/// 24 s + 10/|Re λ| (at most 224 s) so that transients have died by a factor e^10 at its end.
pub fn reference_verdict(ode: &TreadOde, rotation_hz: f64) -> super::WheelVerdict {
    use super::{Class, Method, WheelVerdict};
    let lin = ode.linear_stability();
    let scales = Scales::new(ode);
    let duration = 24.0 + 10.0 / lin.eig_re_max.abs().max(0.05);
    let mut v = WheelVerdict::without_cycle(
        Class::Stable,
        lin.eig_re_max,
        lin.eig_freq_hz,
        Method::Reference,
    );
    match brute_force(ode, &scales, 1e-5, duration, 0.5, REFERENCE_RTOL) {
        Ok((_, last, evals)) => {
            v.rhs_evals = evals as u64;
            if last.amp_v_mps > 1e-4 {
                v.class = Class::LimitCycle;
                v.amp_y_m = last.amp_y_m;
                v.amp_v_mps = last.amp_v_mps;
                v.freq_hz = last.freq_hz;
                v.polygon_order = last.freq_hz / rotation_hz;
            }
        }
        Err(reason) => {
            v.class = Class::Failed;
            v.reason = reason.to_string();
        }
    }
    v
}
