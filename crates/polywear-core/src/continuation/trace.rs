//! Every Hopf curve of a family in a box: seeds where scan lines (the box's edges among them)
//! cross a curve, then pseudo-arclength continuation from each seed in both directions until
//! the curve closes, leaves the box, or cannot be continued. Bautin points (l1 = 0) are located
//! by Brent's method along the curve.

use nalgebra::DVector;

use super::hopf::{analyse, equilibrium, HopfData, HopfSystem, NotHopf, Solution};
use super::{OdeWithJacobian, ParamBox, TwoParameterFamily};
use crate::numeric::{brent, sign_change_roots};

/// How finely the box is searched and the curves are stepped (box-relative units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceOptions {
    /// Scan lines per direction inside the box (the four edges are scanned as well): closed
    /// curves narrower than 1/(lines+1) of the box in both directions can be missed.
    pub scan_lines: usize,
    /// Samples per scan line.
    pub scan_samples: usize,
    /// Largest arclength step (box-relative).
    pub h_max: f64,
    /// Smallest arclength step (box-relative): below it the curve ends as `Stopped`.
    pub h_min: f64,
    /// Most points per curve.
    pub max_points: usize,
}

impl Default for TraceOptions {
    fn default() -> Self {
        TraceOptions {
            scan_lines: 127,
            scan_samples: 160,
            h_max: 0.005,
            h_min: 1e-7,
            max_points: 20_000,
        }
    }
}

/// What a special point is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SpecialKind {
    /// Generalised Hopf point: l1 = 0, the onset changes between soft and hard.
    Bautin,
    /// The curve leaves the box here.
    BoxEnd,
    /// The complex pair turns real (the test function's zero becomes a neutral saddle).
    PairTurnsReal,
    /// A real eigenvalue crosses zero along the curve (det A changes sign).
    RealEigenvalueZero,
    /// The continuation cannot go on: the model has no equilibrium beyond (e.g. a driving wheel
    /// without traction) or the step fell below its minimum.
    Stopped,
}

impl SpecialKind {
    /// The kind's name in output tables (`bautin`, `box_end`, ...).
    pub fn as_str(self) -> &'static str {
        match self {
            SpecialKind::Bautin => "bautin",
            SpecialKind::BoxEnd => "box_end",
            SpecialKind::PairTurnsReal => "pair_turns_real",
            SpecialKind::RealEigenvalueZero => "real_eigenvalue_zero",
            SpecialKind::Stopped => "stopped",
        }
    }
}

/// A special point on curve `curve`.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecialPoint {
    /// What the point is.
    pub kind: SpecialKind,
    /// Index of the curve it lies on in [`HopfCurves::curves`].
    pub curve: usize,
    /// The parameters (P, Q) in their own units.
    pub p: [f64; 2],
    /// Angular frequency ω of the critical pair \[rad/s\] (for the tire; 1/time in general).
    pub omega: f64,
    /// First Lyapunov coefficient there (MODEL.md#first-lyapunov-coefficient).
    pub l1: f64,
}

/// One Hopf curve: its points in order; a closed curve repeats its first point at the end.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The Hopf points in order along the curve.
    pub points: Vec<HopfData>,
    /// Whether the curve closes on itself inside the box.
    pub closed: bool,
}

/// Every Hopf curve in the box, with the special points on them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HopfCurves {
    /// The curves; a curve's number is its index here.
    pub curves: Vec<Curve>,
    /// The special points on them.
    pub special: Vec<SpecialPoint>,
}

struct Traced {
    sol: Solution,
    data: HopfData,
    tangent: [f64; 2],
    dxdt: DVector<f64>,
}

/// Traces every Hopf curve of `family` in `bounds`.
pub fn trace_all<F: TwoParameterFamily>(
    family: &F,
    bounds: ParamBox,
    opts: &TraceOptions,
) -> HopfCurves {
    let sys = HopfSystem::new(family, bounds);
    let seeds = find_seeds(&sys, opts);
    let mut out = HopfCurves::default();
    for seed in seeds {
        let covered = out
            .curves
            .iter()
            .any(|c| near_curve(&bounds, c, seed.sol.s, 1e-3));
        if covered {
            continue;
        }
        let index = out.curves.len();
        let mut special = Vec::new();
        let (fwd, closed) = branch(&sys, &seed, 1.0, opts, index, &mut special);
        let points = if closed {
            fwd
        } else {
            let (bwd, _) = branch(&sys, &seed, -1.0, opts, index, &mut special);
            bwd.into_iter()
                .rev()
                .chain(fwd.into_iter().skip(1))
                .collect()
        };
        out.special.extend(special);
        out.curves.push(Curve { points, closed });
    }
    out
}

/// Distance test of box-relative point s against a curve's polyline.
fn near_curve(bounds: &ParamBox, c: &Curve, s: [f64; 2], tol: f64) -> bool {
    let pts: Vec<[f64; 2]> = c.points.iter().map(|d| bounds.to_unit(d.p)).collect();
    if pts.len() == 1 {
        return dist(pts[0], s) < tol;
    }
    pts.windows(2)
        .any(|w| segment_distance(s, w[0], w[1]) < tol)
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn segment_distance(s: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((s[0] - a[0]) * d[0] + (s[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(s, [a[0] + t * d[0], a[1] + t * d[1]])
}

/// Hopf points on the scan lines: the test function's sign changes between samples, refined by
/// Brent's method and Newton's method on the line, kept where the critical pair is complex.
fn find_seeds<F: TwoParameterFamily>(sys: &HopfSystem<'_, F>, opts: &TraceOptions) -> Vec<Traced> {
    let k = opts.scan_lines + 1;
    // (axis held fixed, its value): edges first, then the interior lines.
    let mut lines: Vec<(usize, f64)> = vec![(0, 0.0), (0, 1.0), (1, 0.0), (1, 1.0)];
    for axis in 0..2 {
        lines.extend((1..k).map(|i| (axis, i as f64 / k as f64)));
    }
    let m = opts.scan_samples.max(2);
    let at = |axis: usize, c: f64, t: f64| if axis == 0 { [c, t] } else { [t, c] };
    let line = |k: usize| {
        let (axis, c) = lines[k];
        let mut seeds = Vec::new();
        let samples = (0..m).map(|i| {
            let t = i as f64 / (m - 1) as f64;
            (t, sys.scan_value(at(axis, c, t)))
        });
        let crossings = sign_change_roots(
            samples,
            |t| sys.scan_value(at(axis, c, t)),
            |_, _| 1e-13,
            200,
        );
        for crossing in crossings {
            let Some(t) = crossing.root else {
                continue;
            };
            let s = at(axis, c, t);
            let Some(x) = sys.system(s).and_then(|f| equilibrium(&f, &sys.scale)) else {
                continue;
            };
            let mut cons = [0.0; 2];
            cons[axis] = 1.0;
            if let Some(traced) = sys
                .correct(x, s, cons, c)
                .and_then(|sol| complete(sys, sol))
                .and_then(Result::ok)
            {
                seeds.push(traced);
            }
        }
        seeds
    };
    let found = crate::ensemble::solve(lines.len(), line, &crate::ensemble::Control::QUIET).all();
    found.into_iter().flatten().collect()
}

/// The analysis and tangent of a converged solution; Err where it is no Hopf point.
fn complete<F: TwoParameterFamily>(
    sys: &HopfSystem<'_, F>,
    sol: Solution,
) -> Option<Result<Traced, NotHopf>> {
    let f = sys.system(sol.s)?;
    let p = sys.bounds.to_param(sol.s);
    let data = match analyse(&f, &sol.x, p) {
        Ok(d) => d,
        Err(e) => return Some(Err(e)),
    };
    let (tangent, dxdt) = sys.tangent(&sol)?;
    Some(Ok(Traced {
        sol,
        data,
        tangent,
        dxdt,
    }))
}

fn outside(s: [f64; 2]) -> bool {
    const EPS: f64 = 1e-12;
    s.iter().any(|&v| !(-EPS..=1.0 + EPS).contains(&v))
}

/// A corrected point `sigma` along the tangent from `from`.
fn step_from<F: TwoParameterFamily>(
    sys: &HopfSystem<'_, F>,
    from: &Traced,
    t: [f64; 2],
    dxdt: &DVector<f64>,
    sigma: f64,
) -> Option<Solution> {
    let s = [from.sol.s[0] + sigma * t[0], from.sol.s[1] + sigma * t[1]];
    let x = &from.sol.x + dxdt * sigma;
    sys.correct(x, s, t, t[0] * s[0] + t[1] * s[1])
}

/// Continues from `seed` in direction `dir` (±1 along its tangent); returns the points (seed
/// first) and whether the curve closed.
fn branch<F: TwoParameterFamily>(
    sys: &HopfSystem<'_, F>,
    seed: &Traced,
    dir: f64,
    opts: &TraceOptions,
    curve: usize,
    special: &mut Vec<SpecialPoint>,
) -> (Vec<HopfData>, bool) {
    let mut pts = vec![seed.data.clone()];
    let mut cur = Traced {
        sol: seed.sol.clone(),
        data: seed.data.clone(),
        tangent: [dir * seed.tangent[0], dir * seed.tangent[1]],
        dxdt: &seed.dxdt * dir,
    };
    let mark = |kind, d: &HopfData| SpecialPoint {
        kind,
        curve,
        p: d.p,
        omega: d.omega,
        l1: d.l1,
    };
    let mut h = (opts.h_max * 0.25).max(opts.h_min);
    let mut travelled = 0.0;
    loop {
        if pts.len() >= opts.max_points {
            special.push(mark(SpecialKind::Stopped, &cur.data));
            return (pts, false);
        }
        let t = cur.tangent;
        let next = step_from(sys, &cur, t, &cur.dxdt, h).and_then(|sol| complete(sys, sol));
        let mut next = match next {
            Some(Ok(n)) => n,
            Some(Err(NotHopf::NeutralSaddle)) if h <= 4.0 * opts.h_min => {
                special.push(mark(SpecialKind::PairTurnsReal, &cur.data));
                return (pts, false);
            }
            _ => {
                h *= 0.5;
                if h < opts.h_min {
                    special.push(mark(end_kind(sys, &cur), &cur.data));
                    return (pts, false);
                }
                continue;
            }
        };
        if next.tangent[0] * t[0] + next.tangent[1] * t[1] < 0.0 {
            next.tangent = [-next.tangent[0], -next.tangent[1]];
            next.dxdt = -next.dxdt;
        }
        let turn = next.tangent[0] * t[0] + next.tangent[1] * t[1];
        if turn < 0.2f64.cos() && h > opts.h_min * 2.0 {
            h *= 0.5;
            continue;
        }
        if outside(next.sol.s) {
            let exit = box_exit(sys, &cur, &next).filter(|e| dist(e.sol.s, cur.sol.s) > 1e-9);
            if let Some(end) = exit {
                special.push(mark(SpecialKind::BoxEnd, &end.data));
                check_between(sys, &cur, &end, curve, special);
                pts.push(end.data);
            } else {
                special.push(mark(SpecialKind::BoxEnd, &cur.data));
            }
            return (pts, false);
        }
        let seg = dist(cur.sol.s, next.sol.s);
        travelled += seg;
        if pts.len() >= 4
            && travelled > 4.0 * seg
            && segment_distance(seed.sol.s, cur.sol.s, next.sol.s) < 0.1 * seg + 1e-9
        {
            // Closed: back at the seed.
            check_between(sys, &cur, seed, curve, special);
            pts.push(seed.data.clone());
            return (pts, true);
        }
        check_between(sys, &cur, &next, curve, special);
        pts.push(next.data.clone());
        if next.sol.iterations <= 3 {
            h = (h * 1.5).min(opts.h_max);
        }
        cur = next;
    }
}

/// Why a curve cannot be continued past `cur`, read off the equilibrium a little further along
/// the tangent: the eigenvalue pair whose sum vanishes has turned real (a Bogdanov–Takens-like
/// end), a real eigenvalue has crossed zero (det A changed sign), or neither (the model ends).
fn end_kind<F: TwoParameterFamily>(sys: &HopfSystem<'_, F>, cur: &Traced) -> SpecialKind {
    const PROBE: f64 = 1e-3;
    let s = [
        cur.sol.s[0] + PROBE * cur.tangent[0],
        cur.sol.s[1] + PROBE * cur.tangent[1],
    ];
    let Some(f) = sys.system(s) else {
        return SpecialKind::Stopped;
    };
    // The equilibrium branch of the curve: Newton from the last point's state.
    let mut x = cur.sol.x.clone();
    for _ in 0..50 {
        match f.jacobian(&x).lu().solve(&f.rhs(&x)) {
            Some(dx) if dx.iter().all(|v| v.is_finite()) => x -= dx,
            _ => return SpecialKind::Stopped,
        }
    }
    if f.rhs(&x).iter().any(|v| !v.is_finite()) {
        return SpecialKind::Stopped;
    }
    let a = f.jacobian(&x);
    let Some(ev) = super::linalg::eigenvalues(&a) else {
        return SpecialKind::Stopped;
    };
    let scale = ev.iter().map(|e| e.norm()).fold(0.0, f64::max);
    let mut best = (f64::INFINITY, false);
    for i in 0..ev.len() {
        for j in 0..i {
            let sum = (ev[i] + ev[j]).norm();
            if sum < best.0 {
                best = (
                    sum,
                    ev[i].im.abs() <= 1e-9 * scale && ev[j].im.abs() <= 1e-9 * scale,
                );
            }
        }
    }
    if best.1 {
        SpecialKind::PairTurnsReal
    } else if (a.determinant() < 0.0) != (cur.data.det_a < 0.0) {
        SpecialKind::RealEigenvalueZero
    } else {
        SpecialKind::Stopped
    }
}

/// Special points between two neighbouring points: a Bautin point where l1 changes sign
/// (located by Brent's method on the arclength from `a`), a real eigenvalue crossing zero where
/// det A does (linearly interpolated).
fn check_between<F: TwoParameterFamily>(
    sys: &HopfSystem<'_, F>,
    a: &Traced,
    b: &Traced,
    curve: usize,
    special: &mut Vec<SpecialPoint>,
) {
    let (la, lb) = (a.data.l1, b.data.l1);
    if (la < 0.0) != (lb < 0.0) {
        let sigma_b =
            (b.sol.s[0] - a.sol.s[0]) * a.tangent[0] + (b.sol.s[1] - a.sol.s[1]) * a.tangent[1];
        let l1_at = |sigma: f64| {
            step_from(sys, a, a.tangent, &a.dxdt, sigma)
                .and_then(|sol| complete(sys, sol))
                .and_then(Result::ok)
                .map_or(f64::NAN, |t| t.data.l1)
        };
        let located = brent(l1_at, 0.0, sigma_b, 1e-12, 100)
            .and_then(|sigma| step_from(sys, a, a.tangent, &a.dxdt, sigma))
            .and_then(|sol| complete(sys, sol))
            .and_then(Result::ok);
        let d = located.map_or_else(|| interpolate(&a.data, &b.data, la / (la - lb)), |t| t.data);
        special.push(SpecialPoint {
            kind: SpecialKind::Bautin,
            curve,
            p: d.p,
            omega: d.omega,
            l1: d.l1,
        });
    }
    let (da, db) = (a.data.det_a, b.data.det_a);
    if (da < 0.0) != (db < 0.0) {
        let d = interpolate(&a.data, &b.data, da / (da - db));
        special.push(SpecialPoint {
            kind: SpecialKind::RealEigenvalueZero,
            curve,
            p: d.p,
            omega: d.omega,
            l1: d.l1,
        });
    }
}

fn interpolate(a: &HopfData, b: &HopfData, t: f64) -> HopfData {
    let mix = |u: f64, v: f64| u + t * (v - u);
    HopfData {
        p: [mix(a.p[0], b.p[0]), mix(a.p[1], b.p[1])],
        x: a.x.iter().zip(&b.x).map(|(u, v)| mix(*u, *v)).collect(),
        omega: mix(a.omega, b.omega),
        re_lambda: 0.0,
        l1: mix(a.l1, b.l1),
        det_a: mix(a.det_a, b.det_a),
    }
}

/// The point where the curve leaves the box between `cur` (inside) and `next` (outside): Newton
/// on the Hopf system with the crossed edge held fixed.
fn box_exit<F: TwoParameterFamily>(
    sys: &HopfSystem<'_, F>,
    cur: &Traced,
    next: &Traced,
) -> Option<Traced> {
    let (a, b) = (cur.sol.s, next.sol.s);
    let mut best: Option<(f64, usize, f64)> = None;
    for axis in 0..2 {
        for edge in [0.0, 1.0] {
            let crosses = (b[axis] - edge) * (a[axis] - edge) < 0.0 || a[axis] == edge;
            if crosses && b[axis] != a[axis] {
                let t = ((edge - a[axis]) / (b[axis] - a[axis])).clamp(0.0, 1.0);
                if best.is_none_or(|(bt, _, _)| t < bt) {
                    best = Some((t, axis, edge));
                }
            }
        }
    }
    let (t, axis, edge) = best?;
    let s = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    let x = &cur.sol.x + (&next.sol.x - &cur.sol.x) * t;
    let mut c = [0.0; 2];
    c[axis] = 1.0;
    let sol = sys.correct(x, s, c, edge)?;
    complete(sys, sol).and_then(Result::ok)
}
