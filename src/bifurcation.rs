//! One-parameter sweeps for both wheels (the paper's bifurcation diagrams, Figs. 6, 7, 12, 14,
//! 16, 18, 20, 22, 23): every value classified in parallel, and the Hopf points located by
//! Brent's method on the real part of the leading eigenvalue.

use crate::classify::ClassifierOptions;
use crate::ensemble::{self, Control};
use crate::evaluate;
use crate::model::{Variant, Wheel, WheelModel};
use crate::numeric::sign_change_roots;
use crate::params::{ParamId, Params};
use crate::plot::{self, FigureFile, PlotError, Series};
use crate::records::WheelRecord;
use crate::wording::plain;

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
    let sys = crate::chart::derivatives::TreadSystem(m.ode);
    let x0 = nalgebra::DVector::from_column_slice(&m.ode.equilibrium());
    let omega = m.ode.linear_stability().leading.im.abs();
    let jac = crate::continuation::OdeWithJacobian::jacobian(&sys, &x0);
    crate::continuation::hopf::first_lyapunov(&sys, &x0, &jac, omega).unwrap_or(f64::NAN)
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
    /// Draws the paper's two views: Re λ against the parameter (in full, and zoomed on zero
    /// where the Hopf points are), and the limit-cycle envelope, into `file`.
    pub fn draw(&self, file: &FigureFile) -> Result<(), PlotError> {
        draw(file, self)
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
            id.spec().group == crate::params::Group::OperatingPoint || base[id] != defaults[id]
        })
        .map(|&id| {
            let (s, v) = (id.spec(), base[id]);
            let name = match s.group {
                crate::params::Group::OperatingPoint => id.label().to_lowercase(),
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

/// Half-height of the zoomed eigenvalue panel: twice the largest |Re λ| at the sweep values
/// next to a sign change (so each crossing is seen with its neighbours), or twice the smallest
/// |Re λ| when there is none (how close the sweep comes to a Hopf point).
fn zoom_half_height(pts: &[(Wheel, Vec<(f64, f64)>)]) -> f64 {
    let mut near = 0.0f64;
    let mut closest = f64::INFINITY;
    for (_, p) in pts {
        for w in p.windows(2) {
            let (a, b) = (w[0].1, w[1].1);
            if a.is_finite() && b.is_finite() && (a < 0.0) != (b < 0.0) {
                near = near.max(a.abs()).max(b.abs());
            }
        }
        for q in p.iter().filter(|q| q.1.is_finite()) {
            closest = closest.min(q.1.abs());
        }
    }
    let h = if near > 0.0 { near } else { closest };
    if h.is_finite() && h > 0.0 {
        2.0 * h
    } else {
        1.0
    }
}

/// Points drawn for one sweep value and its record.
type PointsOf = dyn Fn(f64, &WheelRecord) -> Vec<(f64, f64)>;

fn draw(file: &FigureFile, sw: &Sweep) -> Result<(), PlotError> {
    let (name, unit, variant) = (sw.param.name(), sw.unit, sw.variant);
    let (jobs, records) = (&sw.jobs, &sw.records);
    let per_wheel = |f: &PointsOf| -> Vec<(Wheel, Vec<(f64, f64)>)> {
        Wheel::BOTH
            .iter()
            .map(|&w| {
                let pts = jobs
                    .iter()
                    .zip(records)
                    .filter(|(j, _)| j.1 == w)
                    .flat_map(|(j, r)| f(j.0, r))
                    .collect();
                (w, pts)
            })
            .collect()
    };
    let eig = per_wheel(&|x, r| vec![(x, r.eig_re_max)]);
    let amp = per_wheel(&|x, r| vec![(x, r.amp_y_m * 1e3), (x, -r.amp_y_m * 1e3)]);
    let zoom = zoom_half_height(&eig);
    let windows: Vec<String> = Wheel::BOTH
        .iter()
        .flat_map(|&w| sw.windows_in_words(w))
        .collect();
    let title = format!(
        "{} sweep at {} ({variant} variant)",
        sw.param.label(),
        sw.held_fixed(),
    );
    let zoom_title = format!("Zoomed on zero: {}", windows.join("; "));
    let x_label = crate::params::axis_label(name, unit);
    plot::panels(file, (1400, 1500), (3, 1), &title, |i, area| {
        let (data, title, y, points, range) = match i {
            0 => (
                &eig,
                "Growth rate of a disturbance: real part of the leading eigenvalue (above 0: vibrates)",
                "max Re(lambda) [1/s]",
                false,
                None,
            ),
            1 => (
                &eig,
                zoom_title.as_str(),
                "max Re(lambda) [1/s]",
                false,
                Some((-zoom, zoom)),
            ),
            _ => (
                &amp,
                "Limit-cycle envelope of y - y0 (Figs. 7, 12, 14, 16)",
                "+/- amplitude of y [mm]",
                true,
                None,
            ),
        };
        let series: Vec<Series<'_>> = data
            .iter()
            .map(|(w, pts)| Series {
                label: w.as_str(),
                points: pts.clone(),
            })
            .collect();
        plot::line_panel_with(area, title, &x_label, y, &series, points, range, i < 2)
    })
}
