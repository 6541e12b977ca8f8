//! One period of the classifier's limit cycle, integrated again with its variational equations
//! and sampled uniformly: what the wear stage reads off a vibrating wheel (its mean friction
//! power, and the periodic linearisation of MODEL.md#growth-of-a-vibrating-wheel).

use nalgebra::Matrix3;

use super::error::WearError;
use super::law::friction_power_w;
use crate::classify::budget::Meter;
use crate::classify::section::metered;
use crate::classify::{Scales, WheelVerdict};
use crate::model::{State, TreadOde};
use crate::solver::{Control, Method, SolverOptions, Variational};

/// Relative tolerance of the integration along the cycle: the classifier's fine tolerance.
pub const CYCLE_RTOL: f64 = 1e-9;

/// Samples of the cycle taken per period. The cycle's coefficients are smooth and their Fourier
/// coefficients fall fast, so the trapezoidal sums over these samples are spectrally accurate.
pub const SAMPLES_PER_PERIOD: usize = 32;

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

impl SampledCycle {
    /// Integrates one period of `verdict`'s cycle of `ode` (start on the section
    /// [section_z_m, y_eq, section_v_mps], period 1/freq_hz) with its variational equations, at
    /// the classifier's fine tolerance; the work is charged to `meter`.
    pub fn integrate(
        ode: &TreadOde,
        verdict: &WheelVerdict,
        samples: usize,
        meter: &Meter,
    ) -> Result<Self, WearError> {
        let scales = Scales::new(ode);
        if !(verdict.section_v_mps > 0.0 && verdict.freq_hz > 0.0) {
            return Err(WearError::NoCycle {
                section_v_mps: verdict.section_v_mps,
            });
        }
        let period_s = 1.0 / verdict.freq_hz;
        let x0 = [verdict.section_z_m, scales.y_eq, verdict.section_v_mps];
        let mut start = [0.0; 12];
        start[..3].copy_from_slice(&x0);
        (start[3], start[7], start[11]) = (1.0, 1.0, 1.0);
        let mut atol = [f64::INFINITY; 12];
        atol[..3].copy_from_slice(&scales.atol(CYCLE_RTOL));
        let opts = SolverOptions::section_return(CYCLE_RTOL, atol, period_s);
        let mut out = Vec::with_capacity(samples);
        let to_sample = |t_s: f64, s: &[f64; 12]| CycleSample {
            t_s,
            x: [s[0], s[1], s[2]],
            phi: Matrix3::from_column_slice(&s[3..12]),
        };
        let end = metered(
            Method::Dop853,
            &Variational(ode),
            start,
            period_s,
            &opts,
            meter,
            |step| {
                while out.len() < samples {
                    let t = out.len() as f64 * period_s / samples as f64;
                    if t > step.t1 {
                        break;
                    }
                    out.push(to_sample(t, &step.interpolate(t)));
                }
                Control::Continue
            },
        )?;
        let x_t = [end.x[0], end.x[1], end.x[2]];
        let miss = ((x_t[0] - x0[0]) / scales.z)
            .abs()
            .max(((x_t[1] - x0[1]) / scales.y).abs())
            .max(((x_t[2] - x0[2]) / scales.v).abs());
        if miss.is_nan() || miss > MAX_CLOSURE_MISS || out.len() != samples {
            return Err(WearError::NotClosed { miss });
        }
        Ok(SampledCycle {
            period_s,
            samples: out,
            monodromy: Matrix3::from_column_slice(&end.x[3..12]),
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
