//! One period of the classifier's limit cycle with its variational equations, sampled
//! uniformly: what the wear stage reads off a vibrating wheel (its mean friction power, and the
//! periodic linearisation of MODEL.md#growth-of-a-vibrating-wheel). It is read off shooting's
//! last iteration, shifted onto the cycle to first order, where the classifier kept that
//! iteration; otherwise integrated again.

use nalgebra::Matrix3;

use super::law::friction_power_w;
use crate::classify::budget::Meter;
use crate::classify::section::metered;
use crate::classify::{CyclePath, Scales, WheelVerdict};
use crate::model::SectionVariational;
use crate::model::{State, TreadOde};
use crate::solver::{Control, Method, SolverOptions};
use crate::wear::error::WearError;

/// Relative tolerance of the integration along the cycle: the growth rates agree with those at
/// 1e-9 to 1e-5 (default point, both wheels, and four more vibrating points), for 170–185
/// evaluations instead of 226–237. Shooting's last iteration stands in for it where it was
/// integrated at this tolerance or tighter.
pub(crate) const CYCLE_RTOL: f64 = 1e-8;

/// Samples of the cycle taken per period, for its mean power and its periodic linearisation. The
/// cycle's coefficients are smooth and their harmonics fall fast, so the trapezoidal sums over
/// these samples are spectrally accurate: 16 give the response at the orders near ν to the
/// digits of 64.
pub const SAMPLES_PER_PERIOD: usize = 16;

/// The largest miss |x(T) − x(0)| (relative to the state scales) accepted for a cycle.
const MAX_CLOSURE_MISS: f64 = 1e-4;

/// A point of the cycle: time since the section crossing, state and fundamental matrix Φ(t)
/// (Φ(0) = I).
#[derive(Debug, Clone, Copy)]
pub struct CycleSample {
    /// Time since the start on the section \[s\].
    pub t_s: f64,
    /// The state x_γ(t).
    pub x: State,
    /// The fundamental matrix Φ(t) of the variational equations.
    pub phi: Matrix3<f64>,
    /// The vector field f(x_γ(t)) and its Jacobian there (one evaluation, which both Φ's y
    /// column and the periodic linearisation read).
    pub field: State,
    /// ∂f/∂x at x_γ(t).
    pub jacobian: Matrix3<f64>,
}

/// Φ from the variational state `s` (the state, then Φ's z and v columns) with its y column
/// from Φ f(x₀) = f(x(t)): `f` the vector field at the sample, `f0` at the start.
fn full_phi(s: &[f64; 9], f: &State, f0: &State) -> Matrix3<f64> {
    let (cz, cv) = ([s[3], s[4], s[5]], [s[6], s[7], s[8]]);
    let cy: [f64; 3] = std::array::from_fn(|i| (f[i] - f0[0] * cz[i] - f0[2] * cv[i]) / f0[1]);
    Matrix3::new(
        cz[0], cy[0], cv[0], cz[1], cy[1], cv[1], cz[2], cy[2], cv[2],
    )
}

/// |x(T) − x(0)| relative to the state scales, the largest component.
fn closure_miss(scales: &Scales, x_t: &State, x0: &State) -> f64 {
    ((x_t[0] - x0[0]) / scales.z)
        .abs()
        .max(((x_t[1] - x0[1]) / scales.y).abs())
        .max(((x_t[2] - x0[2]) / scales.v).abs())
}

/// One period of a limit cycle, sampled at equal times.
#[derive(Debug, Clone)]
pub struct SampledCycle {
    /// The period T \[s\].
    pub period_s: f64,
    /// `SAMPLES_PER_PERIOD` samples at t = kT/N, k = 0..N.
    pub samples: Vec<CycleSample>,
    /// The monodromy matrix Φ(T).
    pub monodromy: Matrix3<f64>,
}

/// Where a verdict's cycle crosses the section, its period, and f there: what both ways of
/// sampling the cycle start from.
struct SectionStart {
    x0: State,
    period_s: f64,
    f0: State,
}

impl SectionStart {
    /// `verdict`'s cycle of `ode`, or why it has none.
    fn of(ode: &TreadOde, verdict: &WheelVerdict) -> Result<Self, WearError> {
        if !(verdict.section_v_mps > 0.0 && verdict.freq_hz > 0.0) {
            return Err(WearError::NoCycle {
                section_v_mps: verdict.section_v_mps,
            });
        }
        let x0 = [
            verdict.section_z_m,
            Scales::new(ode).y_eq,
            verdict.section_v_mps,
        ];
        Ok(SectionStart {
            x0,
            period_s: 1.0 / verdict.freq_hz,
            f0: ode.rhs(&x0),
        })
    }
}

impl SampledCycle {
    /// One period of `verdict`'s cycle of `ode` with `samples` samples: read off shooting's last
    /// iteration where the classifier kept it at `CYCLE_RTOL` or tighter
    /// ([`SampledCycle::from_path`]), else integrated ([`SampledCycle::integrate`]). Against the
    /// cycle integrated at 10⁻¹², the growth rates of the 1,824 vibrating wheels of the default
    /// study's first 2,000 samples are within 1% at the 99th percentile read off the path, 2.6%
    /// integrated at `CYCLE_RTOL` (near the Hopf point shooting's tolerance is the tighter).
    pub fn of(
        ode: &TreadOde,
        verdict: &WheelVerdict,
        samples: usize,
        meter: &Meter,
    ) -> Result<Self, WearError> {
        let start = SectionStart::of(ode, verdict)?;
        let read = verdict
            .cycle_path
            .as_deref()
            .filter(|path| path.rtol <= CYCLE_RTOL)
            .and_then(|path| Self::read_path(ode, path, &start, samples, meter));
        match read {
            Some(cycle) => Ok(cycle),
            None => Self::integrate_from(ode, &start, samples, meter),
        }
    }

    /// The samples read off shooting's last iteration, `verdict`'s cycle path, shifted onto the
    /// cycle to first order: the state by Φ·shift at each sample (within |shift|²), Φ as the
    /// path has it (within |shift|), the period's end by the polynomial of the return's last
    /// step. No integration: one evaluation of f and its Jacobian per sample and one of f at the
    /// end, charged to `meter`. None without a path, where the period ends beyond it, or where
    /// the shifted end misses the start by more than `MAX_CLOSURE_MISS`.
    pub fn from_path(
        ode: &TreadOde,
        verdict: &WheelVerdict,
        samples: usize,
        meter: &Meter,
    ) -> Result<Option<Self>, WearError> {
        let start = SectionStart::of(ode, verdict)?;
        Ok(verdict
            .cycle_path
            .as_deref()
            .and_then(|path| Self::read_path(ode, path, &start, samples, meter)))
    }

    /// [`SampledCycle::from_path`] from the cycle's `start` on the section.
    fn read_path(
        ode: &TreadOde,
        path: &CyclePath,
        start: &SectionStart,
        samples: usize,
        meter: &Meter,
    ) -> Option<Self> {
        let SectionStart { period_s, f0, .. } = *start;
        let scales = Scales::new(ode);
        let d = path.shift;
        // The cycle's state at t: the path's, shifted by its Φ (z and v columns; d_y = 0).
        let shifted = |s: &[f64; 9]| -> State {
            std::array::from_fn(|i| s[i] + s[3 + i] * d[0] + s[6 + i] * d[2])
        };
        // The period's end first: every sample lies before it, so none is evaluated for nothing.
        let end = path.at(period_s)?;
        let mut out = Vec::with_capacity(samples);
        for k in 0..samples {
            let t_s = k as f64 * period_s / samples as f64;
            let s = path.at(t_s)?;
            let x = shifted(&s);
            let (field, jacobian) = ode.rhs_and_jacobian(&x);
            out.push(CycleSample {
                t_s,
                x,
                phi: full_phi(&s, &field, &f0),
                field,
                jacobian,
            });
        }
        let x_t = shifted(&end);
        let x0: State = std::array::from_fn(|i| path.start[i] + d[i]);
        meter.charge(out.len() + 1);
        let miss = closure_miss(&scales, &x_t, &x0);
        if miss.is_nan() || miss > MAX_CLOSURE_MISS {
            return None;
        }
        Some(SampledCycle {
            period_s,
            samples: out,
            monodromy: full_phi(&end, &ode.rhs(&x_t), &f0),
        })
    }

    /// Integrates one period of `verdict`'s cycle of `ode` (start on the section
    /// [section_z_m, y_eq, section_v_mps], period 1/freq_hz) with its variational equations, at
    /// `CYCLE_RTOL`; the work is charged to `meter`. Only Φ's z and v columns are integrated
    /// ([`SectionVariational`]): the flow maps the vector field onto itself, Φ(t) f(x₀) =
    /// f(x(t)), and f_y = v₀ > 0 on the section, so the y column follows from the other two and
    /// f at each sample (one evaluation of f and its Jacobian per sample, charged, which the
    /// periodic linearisation reads too).
    pub fn integrate(
        ode: &TreadOde,
        verdict: &WheelVerdict,
        samples: usize,
        meter: &Meter,
    ) -> Result<Self, WearError> {
        Self::integrate_from(ode, &SectionStart::of(ode, verdict)?, samples, meter)
    }

    /// [`SampledCycle::integrate`] from the cycle's `start` on the section.
    fn integrate_from(
        ode: &TreadOde,
        start: &SectionStart,
        samples: usize,
        meter: &Meter,
    ) -> Result<Self, WearError> {
        let SectionStart { x0, period_s, f0 } = *start;
        let scales = Scales::new(ode);
        let start = [x0[0], x0[1], x0[2], 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        let mut atol = [f64::INFINITY; 9];
        atol[..3].copy_from_slice(&scales.atol(CYCLE_RTOL));
        let opts = SolverOptions::section_return(CYCLE_RTOL, atol, period_s);
        let full_phi = |s: &[f64; 9], f: &[f64; 3]| full_phi(s, f, &f0);
        let mut out = Vec::with_capacity(samples);
        let end = metered(
            Method::Dop853,
            &SectionVariational(ode),
            start,
            period_s,
            &opts,
            meter,
            |step| {
                while out.len() < samples {
                    let t_s = out.len() as f64 * period_s / samples as f64;
                    if t_s > step.t1 {
                        break;
                    }
                    let s = step.interpolate(t_s);
                    let x = [s[0], s[1], s[2]];
                    let (field, jacobian) = ode.rhs_and_jacobian(&x);
                    out.push(CycleSample {
                        t_s,
                        x,
                        phi: full_phi(&s, &field),
                        field,
                        jacobian,
                    });
                }
                Control::Continue
            },
        )?;
        meter.charge(out.len() + 2);
        let x_t = [end.x[0], end.x[1], end.x[2]];
        let miss = closure_miss(&scales, &x_t, &x0);
        if miss.is_nan() || miss > MAX_CLOSURE_MISS || out.len() != samples {
            return Err(WearError::NotClosed { miss });
        }
        Ok(SampledCycle {
            period_s,
            samples: out,
            monodromy: full_phi(&end.x, &ode.rhs(&x_t)),
        })
    }

    /// The mean friction power P̄ over the period \[W\] (trapezoidal sum of the periodic P, one
    /// RHS evaluation per sample, charged to `meter`).
    pub fn mean_power_w(&self, ode: &TreadOde, meter: &Meter) -> f64 {
        meter.charge(self.samples.len());
        self.samples
            .iter()
            .map(|s| friction_power_w(ode, &s.x))
            .sum::<f64>()
            / self.samples.len() as f64
    }
}
