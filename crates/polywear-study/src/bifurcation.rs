//! One-parameter sweeps for both wheels (the paper's bifurcation diagrams, Figs. 6, 7, 12, 14,
//! 16, 18, 20, 22, 23): every value classified in parallel, and the Hopf points located by
//! Brent's method on the real part of the leading eigenvalue.

use polywear_core::classify::ClassifierOptions;
use polywear_core::columns::Column;
use polywear_core::ensemble::{self, Control};
use polywear_core::evaluate;
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::numeric::sign_change_roots;
use polywear_core::params::{ParamId, Params};
use polywear_core::records::{record_columns, WheelRecord};
use polywear_core::wording::plain;

/// The result of a sweep: one record per (value, wheel), in `jobs` order.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The values of every parameter but the swept one.
    pub base: Params,
    /// The parameter swept.
    pub param: ParamId,
    /// Its unit.
    pub unit: &'static str,
    /// The friction variant.
    pub variant: Variant,
    /// (parameter value, wheel) of each record.
    pub jobs: Vec<(f64, Wheel)>,
    /// One record per job.
    pub records: Vec<WheelRecord>,
    /// Hopf points located between neighbouring values, both wheels.
    pub hopf: Vec<HopfPoint>,
}

/// Classifies both wheels at every value of `param` (other parameters from `base`), in parallel
/// on the current rayon pool, and locates the Hopf points.
pub fn sweep(
    base: &Params,
    param: ParamId,
    values: &[f64],
    variant: Variant,
    opts: &ClassifierOptions,
) -> Sweep {
    let jobs: Vec<(f64, Wheel)> = values
        .iter()
        .flat_map(|&x| Wheel::BOTH.map(|w| (x, w)))
        .collect();
    let record = |i: usize| {
        let (x, wheel) = jobs[i];
        let mut p = *base;
        p[param] = x;
        evaluate::solve_wheel(p, variant, wheel, opts).record
    };
    let records: Vec<WheelRecord> = ensemble::solve(jobs.len(), record, &Control::QUIET).all();
    let hopf = locate_hopf(base, param, &jobs, &records, variant);
    Sweep {
        base: *base,
        param,
        unit: param.spec().unit,
        variant,
        jobs,
        records,
        hopf,
    }
}

/// Evenly spaced values from `from` to `to`.
pub fn linspace(from: f64, to: f64, steps: usize) -> Vec<f64> {
    (0..steps)
        .map(|i| from + (to - from) * i as f64 / (steps.max(2) - 1) as f64)
        .collect()
}

/// Real part of the leading eigenvalue with `param` set to `x` (NaN where no model exists).
pub fn eig_re(p: &Params, param: ParamId, x: f64, wheel: Wheel, variant: Variant) -> f64 {
    let mut q = *p;
    q[param] = x;
    WheelModel::build(&q, wheel, variant).map_or(f64::NAN, |m| m.ode.linear_stability().eig_re_max)
}

/// A located Hopf point.
#[derive(Debug, Clone, Copy)]
pub struct HopfPoint {
    /// The wheel.
    pub wheel: Wheel,
    /// The parameter's value at the Hopf point, located by root-finding on Re λ.
    pub value: f64,
    /// True when the equilibrium loses stability as the parameter increases.
    pub destabilizing: bool,
    /// First Lyapunov coefficient there (Kuznetsov eq. 3.20, see [`crate::chart`]): negative
    /// for a soft (supercritical) onset, positive for a hard (subcritical) one; NaN where it
    /// cannot be computed.
    pub l1: f64,
}

/// l1 at the Hopf point where `param` = `x` (NaN where no model or no complex pair exists).
pub(crate) fn l1_at(p: &Params, param: ParamId, x: f64, wheel: Wheel, variant: Variant) -> f64 {
    let mut q = *p;
    q[param] = x;
    let Ok(m) = WheelModel::build(&q, wheel, variant) else {
        return f64::NAN;
    };
    // The located point is a Hopf point to Brent's tolerance: l1 with the pair's ω there.
    let sys = polywear_core::model::jet::TreadSystem(m.ode);
    let x0 = nalgebra::DVector::from_column_slice(&m.ode.equilibrium());
    let omega = m.ode.linear_stability().leading.im.abs();
    let jac = polywear_core::continuation::OdeWithJacobian::jacobian(&sys, &x0);
    polywear_core::continuation::hopf::first_lyapunov(&sys, &x0, &jac, omega).unwrap_or(f64::NAN)
}

/// Brent on Re λ between neighbouring sweep values whose signs differ, to 1e-6 relative.
pub(crate) fn locate_hopf(
    base: &Params,
    param: ParamId,
    jobs: &[(f64, Wheel)],
    records: &[WheelRecord],
    variant: Variant,
) -> Vec<HopfPoint> {
    let mut out = Vec::new();
    for wheel in Wheel::BOTH {
        let pts: Vec<(f64, f64)> = jobs
            .iter()
            .zip(records)
            .filter(|(j, _)| j.1 == wheel)
            .map(|(j, r)| (j.0, r.eig_re_max))
            .collect();
        let crossings = sign_change_roots(
            pts,
            |x| eig_re(base, param, x, wheel, variant),
            |x0, x1| 1e-7 * x0.abs().max(x1.abs()),
            200,
        );
        for c in crossings {
            if let Some(x) = c.root {
                out.push(HopfPoint {
                    wheel,
                    value: x,
                    destabilizing: c.rising_with_x(),
                    l1: l1_at(base, param, x, wheel, variant),
                });
            }
        }
    }
    out
}

impl Sweep {
    /// The sweep's table: the swept value in a column of its own (the parameter may also be a
    /// record column), then every record's columns, one row per (value, wheel).
    pub fn columns(&self) -> Vec<Column> {
        let spec = self.param.spec();
        let values = self.jobs.iter().map(|j| j.0).collect();
        let mut cols = vec![Column::f64("sweep_value", spec.unit, values)];
        cols.extend(record_columns(&self.records));
        cols
    }

    /// The table's metadata: the run's (version, command, parameters, variant), the swept
    /// parameter, and the Hopf points as JSON with each onset's criticality
    /// (MODEL.md#step-8-linear-stability), so that a reader of the file alone has them.
    pub fn metadata(&self) -> Vec<(String, String)> {
        let mut meta = crate::provenance::run_metadata(&self.base, self.variant);
        meta.push(("sweep_param".into(), self.param.spec().name.into()));
        let hopf: Vec<serde_json::Value> = self
            .hopf
            .iter()
            .map(|h| serde_json::json!({"wheel": h.wheel.as_str(), "value": h.value, "destabilizing": h.destabilizing, "l1": h.l1, "criticality": crate::chart::criticality(h.l1)}))
            .collect();
        let hopf = serde_json::Value::from(hopf).to_string();
        meta.push(("hopf_points".into(), hopf));
        meta
    }

    /// The operating point held fixed while the parameter is swept, and every other parameter
    /// that differs from its default: "speed 120 km/h, load 4000 N, pressure 240 kPa".
    pub fn held_fixed(&self) -> String {
        held_fixed(&self.base, self.param)
    }

    /// One plain sentence per wheel and window of vibration, e.g. "follower vibrates for
    /// toe-in 0.0812°–0.427°" (the equilibrium is unstable there: between Hopf points or a
    /// Hopf point and the sweep's end), or that the wheel is stable over the whole sweep.
    pub fn windows_in_words(&self, wheel: Wheel) -> Vec<String> {
        let what = self.param.label().to_lowercase();
        let (first, last) = match (self.jobs.first(), self.jobs.last()) {
            (Some(a), Some(b)) => (a.0.min(b.0), a.0.max(b.0)),
            _ => return vec![],
        };
        // "0.081°–0.427°", but "95–143 km/h".
        let span = |a: f64, b: f64| {
            let (lo, hi) = (a.min(b), a.max(b));
            if self.unit == "deg" {
                format!(
                    "{}–{}",
                    value_with_unit(lo, "deg"),
                    value_with_unit(hi, "deg")
                )
            } else {
                format!("{}–{}", plain(lo, 3), value_with_unit(hi, self.unit))
            }
        };
        let ranges = self.unstable_ranges(wheel);
        if ranges.is_empty() {
            return vec![format!(
                "{wheel} is stable over the whole sweep ({what} {})",
                span(first, last)
            )];
        }
        ranges
            .iter()
            .map(|&(a, b)| {
                if a.min(b) <= first && a.max(b) >= last {
                    format!(
                        "{wheel} vibrates over the whole sweep ({what} {})",
                        span(a, b)
                    )
                } else {
                    format!("{wheel} vibrates for {what} {}", span(a, b))
                }
            })
            .collect()
    }

    /// Intervals of the parameter where the wheel's equilibrium is unstable, from the Hopf points
    /// and the sweep's ends: the ranges where self-excited vibration occurs (the paper's Table 3).
    pub fn unstable_ranges(&self, wheel: Wheel) -> Vec<(f64, f64)> {
        let pts: Vec<(f64, f64)> = self
            .jobs
            .iter()
            .zip(&self.records)
            .filter(|(j, _)| j.1 == wheel)
            .map(|(j, r)| (j.0, r.eig_re_max))
            .collect();
        let Some(first) = pts.first() else {
            return vec![];
        };
        let last = pts[pts.len() - 1];
        let mut ranges = Vec::new();
        let mut start = if first.1 > 0.0 { Some(first.0) } else { None };
        for h in self.hopf.iter().filter(|h| h.wheel == wheel) {
            if h.destabilizing {
                start = Some(h.value);
            } else if let Some(s) = start.take() {
                ranges.push((s, h.value));
            }
        }
        if let Some(s) = start {
            ranges.push((s, last.0));
        }
        ranges
    }
}

/// A value and its unit as written in a sentence: `0.081°`, `120 km/h`, `0.9` (no unit).
fn value_with_unit(v: f64, unit: &str) -> String {
    let v = plain(v, 3);
    match unit {
        "deg" => format!("{v}°"),
        "" | "-" => v,
        u => format!("{v} {u}"),
    }
}

/// See [`Sweep::held_fixed`].
pub fn held_fixed(base: &Params, swept: ParamId) -> String {
    let defaults = Params::default();
    let mut parts: Vec<String> = ParamId::ALL
        .iter()
        .filter(|&&id| id != swept)
        .filter(|&&id| {
            id.spec().group == polywear_core::params::Group::OperatingPoint
                || base.differs(&defaults, id)
        })
        .map(|&id| {
            let (s, v) = (id.spec(), base[id]);
            let name = match s.group {
                polywear_core::params::Group::OperatingPoint => id.label().to_lowercase(),
                _ => s.name.to_string(),
            };
            format!("{name} {}", value_with_unit(v, s.unit))
        })
        .collect();
    if parts.is_empty() {
        parts.push("all other parameters at their defaults".into());
    }
    parts.join(", ")
}
