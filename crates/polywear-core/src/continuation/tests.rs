//! The continuation code on systems with known answers.

use nalgebra::{Complex, DVector};

use super::hopf::{analyse, equilibrium};
use super::textbook::{BautinFamily, Brusselator, BrusselatorFamily, NormalForm, RingFamily};
use super::trace::{trace_all, SpecialKind, TraceOptions};
use super::{complexify, CVector, OdeWithJacobian, ParamBox, TwoParameterFamily};

fn cvec(v: &[(f64, f64)]) -> CVector {
    DVector::from_iterator(v.len(), v.iter().map(|&(r, i)| Complex::new(r, i)))
}

/// B against differences of the Jacobian, C against differences of B, the Jacobian against
/// differences of f: the checks every [`OdeWithJacobian`] must pass.
pub(crate) fn check_derivatives<S: OdeWithJacobian>(
    sys: &S,
    x: &DVector<f64>,
    h: &DVector<f64>,
    rtol: f64,
) {
    let n = sys.dim();
    let u = cvec(&[(0.3, -0.7), (1.1, 0.4), (-0.5, 0.9)][..n]);
    let v = cvec(&[(-0.8, 0.2), (0.6, -1.3), (0.25, 0.5)][..n]);
    let w = cvec(&[(0.9, 0.1), (-0.4, 0.6), (0.7, -0.2)][..n]);
    let scaled = |c: &CVector| c.component_mul(&complexify(h));
    let (u, v, w) = (scaled(&u), scaled(&v), scaled(&w));
    let close = |a: &CVector, b: &CVector, what: &str| {
        let err = (a - b).norm();
        assert!(
            err <= rtol * b.norm().max(1e-300),
            "{what}: {a} vs {b} (error {err:e})"
        );
    };
    // Directional derivative along a complex direction d of a function of x that is linear in
    // complex arguments: real and imaginary parts of d separately.
    let eps = 1e-5;
    let along = |d: &CVector, f: &dyn Fn(&DVector<f64>) -> CVector| -> CVector {
        let re = d.map(|c| c.re);
        let im = d.map(|c| c.im);
        let diff = |e: &DVector<f64>| {
            (f(&(x + e * eps)) - f(&(x - e * eps))) / Complex::new(2.0 * eps, 0.0)
        };
        diff(&re) + diff(&im) * Complex::new(0.0, 1.0)
    };
    // Jacobian against f.
    let jv = sys.jacobian(x).map(|a| Complex::new(a, 0.0)) * &v;
    close(
        &jv,
        &along(&v, &|y| complexify(&sys.rhs(y))),
        "A v vs differences of f",
    );
    // B(u, v) against differences of A v.
    let b = sys.second(x, &u, &v);
    close(
        &b,
        &along(&u, &|y| sys.jacobian(y).map(|a| Complex::new(a, 0.0)) * &v),
        "B(u,v)",
    );
    // Symmetry of B.
    close(&sys.second(x, &v, &u), &b, "B symmetric");
    // C(u, v, w) against differences of B(v, w).
    let c = sys.third(x, &u, &v, &w);
    close(&c, &along(&u, &|y| sys.second(y, &v, &w)), "C(u,v,w)");
    close(&sys.third(x, &w, &u, &v), &c, "C symmetric");
}

#[test]
fn textbook_derivatives_match_differences() {
    let b = Brusselator { a: 1.3, b: 2.9 };
    let x = DVector::from_vec(vec![1.2, 2.1]);
    check_derivatives(&b, &x, &DVector::from_element(2, 1.0), 1e-7);
    let nf = NormalForm {
        mu: 0.1,
        cubic: -0.7,
    };
    let x = DVector::from_vec(vec![0.4, -0.3]);
    check_derivatives(&nf, &x, &DVector::from_element(2, 1.0), 1e-7);
}

#[test]
fn brusselator_curve_is_b_equals_one_plus_a_squared_with_closed_form_l1() {
    let bounds = ParamBox {
        lo: [0.5, 1.0],
        hi: [2.0, 6.0],
    };
    let out = trace_all(&BrusselatorFamily, bounds, &TraceOptions::default());
    assert_eq!(out.curves.len(), 1, "{:?}", out.special);
    let c = &out.curves[0];
    assert!(!c.closed);
    assert!(c.points.len() > 50);
    for d in &c.points {
        let [a, b] = d.p;
        assert!((b - (1.0 + a * a)).abs() < 1e-9, "({a}, {b}) off the curve");
        assert!((d.omega - a).abs() < 1e-8, "omega {} at a = {a}", d.omega);
        let exact = Brusselator::l1_on_hopf_curve(a);
        assert!(
            (d.l1 - exact).abs() < 1e-7 * exact.abs(),
            "l1 {} vs {exact}",
            d.l1
        );
        assert!(d.re_lambda.abs() < 1e-9 * d.omega);
    }
    // It enters through the bottom edge at a = 0.5 (b = 1.25) and leaves through the right
    // edge a = 2 at b = 5.
    let ends: Vec<[f64; 2]> = out
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::BoxEnd)
        .map(|s| s.p)
        .collect();
    assert_eq!(ends.len(), 2, "{ends:?}");
    let has = |p: [f64; 2]| {
        ends.iter()
            .any(|e| (e[0] - p[0]).abs() + (e[1] - p[1]).abs() < 1e-9)
    };
    assert!(has([0.5, 1.25]) && has([2.0, 5.0]), "{ends:?}");
    assert!(out.special.iter().all(|s| s.kind == SpecialKind::BoxEnd));
}

#[test]
fn bautin_normal_form_changes_criticality_at_the_origin() {
    let bounds = ParamBox {
        lo: [-0.5, -1.0],
        hi: [0.7, 0.8],
    };
    let out = trace_all(&BautinFamily, bounds, &TraceOptions::default());
    assert_eq!(out.curves.len(), 1);
    for d in &out.curves[0].points {
        assert!(
            d.p[0].abs() < 1e-10,
            "Hopf curve is beta1 = 0, got {:?}",
            d.p
        );
        assert!(
            (d.l1 - 2.0 * d.p[1]).abs() < 1e-8,
            "l1 = 2 beta2: {} at {:?}",
            d.l1,
            d.p
        );
        assert!((d.omega - 1.0).abs() < 1e-10);
    }
    let bautin: Vec<_> = out
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Bautin)
        .collect();
    assert_eq!(bautin.len(), 1, "{:?}", out.special);
    assert!(
        bautin[0].p[0].abs() < 1e-10 && bautin[0].p[1].abs() < 1e-10,
        "{:?}",
        bautin[0]
    );
}

#[test]
fn closed_curve_closes_and_has_two_bautin_points() {
    let bounds = ParamBox {
        lo: [-1.0, -1.0],
        hi: [1.0, 1.0],
    };
    let out = trace_all(&RingFamily, bounds, &TraceOptions::default());
    assert_eq!(out.curves.len(), 1, "{:?}", out.special);
    let c = &out.curves[0];
    assert!(c.closed);
    assert_eq!(c.points.first().unwrap().p, c.points.last().unwrap().p);
    for d in &c.points {
        let r = d.p[0].hypot(d.p[1]);
        assert!((r - 0.5).abs() < 1e-10, "radius {r}");
        assert!((d.l1 - 2.0 * d.p[0]).abs() < 1e-8);
    }
    // The polyline goes once around: its winding angle is ±2π.
    let angle: f64 = c
        .points
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0].p, w[1].p);
            (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1])
        })
        .sum();
    assert!(
        (angle.abs() - std::f64::consts::TAU).abs() < 1e-6,
        "winding {angle}"
    );
    let mut bautin: Vec<[f64; 2]> = out
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Bautin)
        .map(|s| s.p)
        .collect();
    bautin.sort_by(|a, b| a[1].total_cmp(&b[1]));
    assert_eq!(bautin.len(), 2, "{:?}", out.special);
    for (p, y) in bautin.iter().zip([-0.5, 0.5]) {
        assert!(p[0].abs() < 1e-9 && (p[1] - y).abs() < 1e-9, "{p:?}");
    }
}

#[test]
fn a_box_without_hopf_points_gives_no_curve() {
    let bounds = ParamBox {
        lo: [0.5, 4.0],
        hi: [1.0, 6.0],
    };
    let out = trace_all(&BrusselatorFamily, bounds, &TraceOptions::default());
    assert!(out.curves.is_empty() && out.special.is_empty());
}

#[test]
fn analysis_finds_the_pair_and_l1_at_a_brusselator_hopf_point() {
    let a = 1.7;
    let sys = BrusselatorFamily.at([a, 1.0 + a * a]).unwrap();
    let x = equilibrium(&sys, &BrusselatorFamily.state_scale()).unwrap();
    let d = analyse(&sys, &x, [a, 1.0 + a * a]).unwrap();
    assert!((d.omega - a).abs() < 1e-10);
    assert!((d.l1 - Brusselator::l1_on_hopf_curve(a)).abs() < 1e-10);
}

#[test]
fn hopf_curve_ending_where_the_pair_turns_real_is_flagged() {
    use super::textbook::{BogdanovTakens, BogdanovTakensFamily};
    let bt = BogdanovTakens {
        beta1: -0.02,
        beta2: -0.3,
    };
    check_derivatives(
        &bt,
        &DVector::from_vec(vec![0.2, 0.1]),
        &DVector::from_element(2, 1.0),
        1e-7,
    );
    let bounds = ParamBox {
        lo: [-0.1, -1.0],
        hi: [0.1, 0.5],
    };
    let out = trace_all(&BogdanovTakensFamily, bounds, &TraceOptions::default());
    assert_eq!(out.curves.len(), 1, "{:?}", out.special);
    for d in &out.curves[0].points {
        assert!(d.p[0].abs() < 1e-10 && d.p[1] < 0.0, "{:?}", d.p);
        assert!((d.omega - (-d.p[1]).sqrt()).abs() < 1e-8);
    }
    let real: Vec<_> = out
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::PairTurnsReal)
        .collect();
    assert_eq!(real.len(), 1, "{:?}", out.special);
    assert!(real[0].p[1].abs() < 1e-3, "{:?}", real[0]);
}
