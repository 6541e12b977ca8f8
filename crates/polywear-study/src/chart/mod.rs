//! Stability charts: every Hopf curve of both wheels in the plane of any two parameters, with
//! the frequency, the first Lyapunov coefficient and the criticality of the onset at each point
//! (MODEL.md#first-lyapunov-coefficient; MODEL.md#step-1-deflection to #step-8-linear-stability
//! for the model; [`polywear_core::continuation`] for the numerics).
//!
//! The tread ODE's coefficients depend on the two parameters through steps 1–5 (contact patch,
//! tread block, slip ratio, friction levels), so the family rebuilds the [`WheelModel`] at each
//! parameter point; the continuation differentiates that in the parameters by differences and
//! in the state exactly ([`polywear_core::model::jet`]).

pub mod band;
pub mod files;

use nalgebra::DVector;
use polywear_core::ensemble::{self, Control};

use crate::parquet_out::Column;
use polywear_core::continuation::trace::{trace_all, HopfCurves, SpecialKind, TraceOptions};
use polywear_core::continuation::{ParamBox, TwoParameterFamily};
use polywear_core::model::TreadSystem;
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::params::{ParamId, Params};

/// The tread ODE of one wheel as a function of two named parameters, the others from `base`.
#[derive(Debug, Clone, Copy)]
pub struct TireFamily {
    /// The parameters not on the axes.
    pub base: Params,
    /// Which wheel's tread ODE (MODEL.md#operating-point-and-wheels).
    pub wheel: Wheel,
    /// The friction variant (MODEL.md#variants).
    pub variant: Variant,
    /// The x and y parameters.
    pub axes: [ParamId; 2],
}

impl TireFamily {
    /// The parameters at p.
    pub fn params(&self, p: [f64; 2]) -> Params {
        let mut q = self.base;
        for (&id, v) in self.axes.iter().zip(p) {
            q[id] = v;
        }
        q
    }
}

impl TwoParameterFamily for TireFamily {
    type System = TreadSystem;
    fn at(&self, p: [f64; 2]) -> Option<TreadSystem> {
        WheelModel::build(&self.params(p), self.wheel, self.variant)
            .ok()
            .map(|m| TreadSystem(m.ode))
    }
    fn state_scale(&self) -> DVector<f64> {
        // z and y are millimetres, v is zero at the equilibrium: components below a nanometre
        // (per second) count as zero.
        DVector::from_element(3, 1e-9)
    }
}

/// What a chart is asked for.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct ChartRequest {
    /// The parameters not on the axes, and the nominal point marked on the chart.
    pub base: Params,
    /// The friction variant (MODEL.md#variants).
    pub variant: Variant,
    /// The wheels to trace, each independently.
    pub wheels: Vec<Wheel>,
    /// The parameter on the x axis.
    pub x: ParamId,
    /// The parameter on the y axis.
    pub y: ParamId,
    /// The box in the parameters' own units (x range, y range).
    pub bounds: ParamBox,
}

impl ChartRequest {
    /// The chart's metadata: the base parameters, axes, box, wheels and the conventions of l1.
    pub fn metadata(&self, opts: &TraceOptions) -> Vec<(String, String)> {
        let req = self;
        let mut meta = crate::provenance::run_metadata(&req.base, req.variant);
        meta.push(("chart_x".into(), req.x.name().into()));
        meta.push(("chart_y".into(), req.y.name().into()));
        meta.push((
            "chart_box".into(),
            serde_json::json!({
                req.x.name(): [req.bounds.lo[0], req.bounds.hi[0]],
                req.y.name(): [req.bounds.lo[1], req.bounds.hi[1]],
            })
            .to_string(),
        ));
        let wheels: Vec<&str> = req.wheels.iter().map(|w| w.as_str()).collect();
        meta.push(("wheels".into(), wheels.join(",")));
        meta.push((
            "l1_convention".into(),
            "Kuznetsov eq. 3.20; A q = i w q, A^T p = -i w p, <q,q> = 1, <p,q> = 1; state (z [m], y [m], v [m/s])".into(),
        ));
        meta.push((
            "re_lambda_bound".into(),
            format!("|re_lambda_per_s| <= {RE_LAMBDA_BOUND:e} * 2 pi freq_hz at every point"),
        ));
        meta.push(("trace_options".into(), format!("{opts:?}")));
        meta
    }
}

/// Why a chart cannot be drawn, refused before any work.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ChartError {
    /// Both axes name one parameter.
    #[error("both axes are `{0}`; a chart needs two different parameters")]
    SameAxes(ParamId),
    /// An axis end outside its parameter's accepted range, or an empty or inverted range.
    #[error("the range {lo} to {hi} of `{param}`: {reason}")]
    Range {
        /// The axis's parameter.
        param: ParamId,
        /// Its lower end.
        lo: f64,
        /// Its upper end.
        hi: f64,
        /// What is wrong with it.
        reason: String,
    },
    /// A corner of the box is not a valid parameter set (a rule tying several parameters).
    #[error("the corner {x} = {x_value}, {y} = {y_value}: {reason}")]
    Corner {
        /// The x parameter.
        x: ParamId,
        /// Its value at the corner.
        x_value: f64,
        /// The y parameter.
        y: ParamId,
        /// Its value at the corner.
        y_value: f64,
        /// Which rule it breaks.
        reason: String,
    },
    /// No wheel asked for.
    #[error("no wheel to trace")]
    NoWheels,
}

impl ChartRequest {
    /// A chart whose axes differ, whose ranges are accepted values with the lower end below the
    /// upper, and whose four corners are valid parameter sets; checked before any work.
    pub fn new(
        base: Params,
        variant: Variant,
        wheels: Vec<Wheel>,
        (x, y): (ParamId, ParamId),
        bounds: ParamBox,
    ) -> Result<ChartRequest, ChartError> {
        if x == y {
            return Err(ChartError::SameAxes(x));
        }
        if wheels.is_empty() {
            return Err(ChartError::NoWheels);
        }
        for (k, param) in [x, y].into_iter().enumerate() {
            let (lo, hi) = (bounds.lo[k], bounds.hi[k]);
            let refuse = |reason: String| ChartError::Range {
                param,
                lo,
                hi,
                reason,
            };
            for v in [lo, hi] {
                param.spec().check(v).map_err(|e| refuse(e.to_string()))?;
            }
            if lo >= hi {
                return Err(refuse("the range is empty or inverted".into()));
            }
        }
        for x_value in [bounds.lo[0], bounds.hi[0]] {
            for y_value in [bounds.lo[1], bounds.hi[1]] {
                let mut p = base;
                p[x] = x_value;
                p[y] = y_value;
                p.validate().map_err(|e| ChartError::Corner {
                    x,
                    x_value,
                    y,
                    y_value,
                    reason: e.to_string(),
                })?;
            }
        }
        Ok(ChartRequest {
            base,
            variant,
            wheels,
            x,
            y,
            bounds,
        })
    }
}

/// Every Hopf curve of one wheel.
#[derive(Debug, Clone)]
pub struct WheelCurves {
    /// The wheel.
    pub wheel: Wheel,
    /// Its Hopf curves and special points in the request's box.
    pub curves: HopfCurves,
}

/// The largest |Re λ| / ω any reported point may have. The corrector stops at box-relative
/// steps of 1e-12; on the tire the critical pair's real part is then about 1e-12 ω.
pub const RE_LAMBDA_BOUND: f64 = 1e-8;

impl ChartRequest {
    /// The family of `wheel`'s tread ODE over the chart's two parameters.
    pub fn family(&self, wheel: Wheel) -> TireFamily {
        TireFamily {
            base: self.base,
            wheel,
            variant: self.variant,
            axes: [self.x, self.y],
        }
    }

    /// The parameters of the operating point the user gave (`base`), on the chart's axes.
    pub fn nominal(&self) -> [f64; 2] {
        [self.base[self.x], self.base[self.y]]
    }

    /// Traces the curves of every wheel (the wheels in parallel).
    pub fn trace(&self, opts: &TraceOptions) -> Vec<WheelCurves> {
        let curves = |k: usize| WheelCurves {
            wheel: self.wheels[k],
            curves: trace_all(&self.family(self.wheels[k]), self.bounds, opts),
        };
        ensemble::solve(self.wheels.len(), curves, &Control::QUIET).all()
    }

    /// Stability on a grid of cell centres (row-major in y, then x): Some(true) where the
    /// equilibrium is unstable (max Re λ > 0), None where the model has no equilibrium.
    pub fn stability_grid(&self, wheel: Wheel, nx: usize, ny: usize) -> Vec<Option<bool>> {
        let fam = self.family(wheel);
        let row = |j: usize| -> Vec<Option<bool>> {
            (0..nx)
                .map(|i| {
                    let s = [(i as f64 + 0.5) / nx as f64, (j as f64 + 0.5) / ny as f64];
                    let p = self.bounds.to_param(s);
                    WheelModel::build(&fam.params(p), wheel, self.variant)
                        .ok()
                        .map(|m| m.ode.linear_stability().eig_re_max > 0.0)
                })
                .collect()
        };
        ensemble::solve(ny, row, &Control::QUIET)
            .all()
            .into_iter()
            .flatten()
            .collect()
    }

    /// [`ChartRequest::stability_grid`] of every wheel traced, `cells` × `cells`, in the
    /// wheels' order: the chart's shading.
    pub fn stability_grids(&self, cells: usize) -> Vec<Vec<Option<bool>>> {
        self.wheels
            .iter()
            .map(|&w| self.stability_grid(w, cells, cells))
            .collect()
    }
}

/// The Hopf curves of a study's nominal tire (every drawn parameter not on the axes at its
/// median, the fixed ones as the study sets them) over the box spanned by `x_edges` and
/// `y_edges`: the overlay of `analyze`'s risk maps. None where the axes are no parameters or
/// the box is empty.
pub fn nominal_curves(
    study: &crate::study::Study,
    variant: Variant,
    x: &str,
    y: &str,
    x_edges: &[f64],
    y_edges: &[f64],
) -> Option<Vec<WheelCurves>> {
    let (xs, ys): (ParamId, ParamId) = (x.parse().ok()?, y.parse().ok()?);
    let (x0, x1) = (*x_edges.first()?, *x_edges.last()?);
    let (y0, y1) = (*y_edges.first()?, *y_edges.last()?);
    if !(x0 < x1 && y0 < y1) {
        return None;
    }
    let mut base = study.base;
    for d in &study.drawn {
        if d.param != xs && d.param != ys {
            base[d.param] = d.dist.quantile(0.5);
        }
    }
    let req = ChartRequest {
        base,
        variant,
        wheels: Wheel::BOTH.to_vec(),
        x: xs,
        y: ys,
        bounds: ParamBox {
            lo: [x0, y0],
            hi: [x1, y1],
        },
    };
    Some(req.trace(&TraceOptions::default()))
}

/// `supercritical` (l1 < 0: a small cycle grows from the boundary, soft onset) or `subcritical`
/// (l1 > 0: a large cycle appears at once and persists outside the unstable region: hard onset,
/// hysteresis); `degenerate` where l1 is exactly zero, `unknown` where it could not be computed.
pub fn criticality(l1: f64) -> &'static str {
    if l1.is_nan() {
        "unknown"
    } else if l1 < 0.0 {
        "supercritical"
    } else if l1 > 0.0 {
        "subcritical"
    } else {
        "degenerate"
    }
}

/// The curve table: one row per curve point, columns `wheel, variant, curve, <P>, <Q>,
/// freq_hz, l1, criticality`, then the critical pair's real part (the accuracy of the point).
pub fn curve_columns(req: &ChartRequest, charts: &[WheelCurves]) -> Vec<Column> {
    let rows: Vec<(Wheel, usize, &polywear_core::continuation::hopf::HopfData)> = charts
        .iter()
        .flat_map(|c| {
            c.curves
                .curves
                .iter()
                .enumerate()
                .flat_map(move |(k, curve)| curve.points.iter().map(move |d| (c.wheel, k, d)))
        })
        .collect();
    vec![
        Column::str("wheel", rows.iter().map(|r| r.0.as_str().into()).collect()),
        Column::str("variant", vec![req.variant.as_str().into(); rows.len()]),
        Column::i64("curve", "", rows.iter().map(|r| r.1 as i64).collect()),
        Column::f64(
            req.x.name(),
            req.x.spec().unit,
            rows.iter().map(|r| r.2.p[0]).collect(),
        ),
        Column::f64(
            req.y.name(),
            req.y.spec().unit,
            rows.iter().map(|r| r.2.p[1]).collect(),
        ),
        Column::f64(
            "freq_hz",
            "Hz",
            rows.iter().map(|r| freq_hz(r.2.omega)).collect(),
        ),
        Column::f64("l1", "", rows.iter().map(|r| r.2.l1).collect()),
        Column::str(
            "criticality",
            rows.iter().map(|r| criticality(r.2.l1).into()).collect(),
        ),
        Column::f64(
            "re_lambda_per_s",
            "1/s",
            rows.iter().map(|r| r.2.re_lambda).collect(),
        ),
    ]
}

/// The special-point table: Bautin points, curve ends on the box, and any flags.
pub fn special_columns(req: &ChartRequest, charts: &[WheelCurves]) -> Vec<Column> {
    let rows: Vec<(Wheel, &polywear_core::continuation::trace::SpecialPoint)> = charts
        .iter()
        .flat_map(|c| c.curves.special.iter().map(move |s| (c.wheel, s)))
        .collect();
    vec![
        Column::str("wheel", rows.iter().map(|r| r.0.as_str().into()).collect()),
        Column::str("variant", vec![req.variant.as_str().into(); rows.len()]),
        Column::i64("curve", "", rows.iter().map(|r| r.1.curve as i64).collect()),
        Column::str(
            "kind",
            rows.iter().map(|r| r.1.kind.as_str().into()).collect(),
        ),
        Column::f64(
            req.x.name(),
            req.x.spec().unit,
            rows.iter().map(|r| r.1.p[0]).collect(),
        ),
        Column::f64(
            req.y.name(),
            req.y.spec().unit,
            rows.iter().map(|r| r.1.p[1]).collect(),
        ),
        Column::f64(
            "freq_hz",
            "Hz",
            rows.iter().map(|r| freq_hz(r.1.omega)).collect(),
        ),
        Column::f64("l1", "", rows.iter().map(|r| r.1.l1).collect()),
    ]
}

/// The band table: per grid cell and wheel, the share of drawn structures that are unstable.
pub fn band_columns(req: &ChartRequest, band: &band::StructureBand) -> Vec<Column> {
    let n = band.cells;
    let mut cols = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (wheel, shares) in &band.shares {
        for (c, share) in shares.iter().enumerate() {
            let s = [
                ((c % n) as f64 + 0.5) / n as f64,
                ((c / n) as f64 + 0.5) / n as f64,
            ];
            let p = req.bounds.to_param(s);
            cols.0.push(wheel.as_str().to_string());
            cols.1.push(p[0]);
            cols.2.push(p[1]);
            cols.3.push(*share);
        }
    }
    let rows = cols.0.len();
    vec![
        Column::str("wheel", cols.0),
        Column::str("variant", vec![req.variant.as_str().into(); rows]),
        Column::f64(req.x.name(), req.x.spec().unit, cols.1),
        Column::f64(req.y.name(), req.y.spec().unit, cols.2),
        Column::f64("unstable_share", "", cols.3),
    ]
}

/// Linear frequency \[Hz\] of an angular frequency ω \[rad/s\].
pub fn freq_hz(omega: f64) -> f64 {
    omega / (2.0 * std::f64::consts::PI)
}

/// One line per wheel for the console: curves, points, criticality, special points.
pub fn summary(req: &ChartRequest, charts: &[WheelCurves]) -> Vec<String> {
    let mut out = Vec::new();
    for c in charts {
        let n_pts: usize = c.curves.curves.iter().map(|k| k.points.len()).sum();
        let closed = c.curves.curves.iter().filter(|k| k.closed).count();
        let count = |kind| c.curves.special.iter().filter(|s| s.kind == kind).count();
        out.push(format!(
            "{:>9}: {} Hopf curve(s) ({} closed), {} points, {} Bautin point(s), {} end(s) on the box",
            c.wheel,
            c.curves.curves.len(),
            closed,
            n_pts,
            count(SpecialKind::Bautin),
            count(SpecialKind::BoxEnd)
        ));
        for (k, curve) in c.curves.curves.iter().enumerate() {
            let sub = curve.points.iter().filter(|d| d.l1 > 0.0).count();
            let f: Vec<f64> = curve.points.iter().map(|d| freq_hz(d.omega)).collect();
            let (fmin, fmax) = f
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            let (xmin, xmax) = span(curve.points.iter().map(|d| d.p[0]));
            let (ymin, ymax) = span(curve.points.iter().map(|d| d.p[1]));
            out.push(format!(
                "           curve {k}: {} points, {} {:.4}..{:.4} {}, {} {:.4}..{:.4} {}, {:.1}..{:.1} Hz, {}",
                curve.points.len(),
                req.x.name(),
                xmin,
                xmax,
                req.x.spec().unit,
                req.y.name(),
                ymin,
                ymax,
                req.y.spec().unit,
                fmin,
                fmax,
                if sub == 0 {
                    "supercritical throughout".to_string()
                } else if sub == curve.points.len() {
                    "subcritical throughout".to_string()
                } else {
                    format!("subcritical at {sub} of {} points", curve.points.len())
                }
            ));
        }
        for s in &c.curves.special {
            if s.kind != SpecialKind::BoxEnd {
                out.push(format!(
                    "           {} on curve {} at {} = {:.6}, {} = {:.6}",
                    s.kind.as_str(),
                    s.curve,
                    req.x.name(),
                    s.p[0],
                    req.y.name(),
                    s.p[1]
                ));
            }
        }
    }
    out
}

fn span(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chart_request_is_checked_before_any_work() {
        let new = |x: ParamId, y: ParamId, lo: [f64; 2], hi: [f64; 2]| {
            ChartRequest::new(
                Params::default(),
                Variant::DEFAULT,
                Wheel::BOTH.to_vec(),
                (x, y),
                ParamBox { lo, hi },
            )
        };
        let (speed, toe, mu_s) = (ParamId::SpeedKmh, ParamId::ToeDeg, ParamId::MuS);
        assert!(new(speed, toe, [60.0, 0.05], [250.0, 0.6]).is_ok());
        assert_eq!(
            new(toe, toe, [0.05, 0.05], [0.6, 0.6]).unwrap_err(),
            ChartError::SameAxes(toe)
        );
        let inverted = new(speed, toe, [250.0, 0.05], [60.0, 0.6]).unwrap_err();
        assert!(matches!(inverted, ChartError::Range { param, .. } if param == speed));
        let outside = new(speed, toe, [-5.0, 0.05], [250.0, 0.6]).unwrap_err();
        assert!(matches!(outside, ChartError::Range { .. }), "{outside}");
        // mu_s above the default mu_m at the box's upper end breaks a rule of two parameters.
        let mu_m = Params::default().mu_m;
        let corner = new(speed, mu_s, [60.0, 0.1], [250.0, mu_m + 0.1]).unwrap_err();
        assert!(matches!(corner, ChartError::Corner { .. }), "{corner}");
    }
}
