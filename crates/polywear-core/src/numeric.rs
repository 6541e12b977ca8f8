//! Small numerical helpers shared by the stages: a bracketing root finder, and the one way the
//! stages locate a sign change (a Hopf point where Re λ or the test function crosses zero) on a
//! scan: [`sign_change_roots`].
//!
//! Brent's method is our own 70 lines, measured against the crates: `argmin` costs 29 crates
//! and 10.4 CPU-s of release build, `roots` 2 crates and 0.6 CPU-s, but its stopping rules
//! differ from this iteration's, and every Hopf point, chart seed and calibration result is
//! pinned to this iteration bit for bit.

/// Complex numbers of the wear stage's transfers and profiles (nalgebra's, which the
/// eigenvalues already use).
pub type Complex64 = nalgebra::Complex<f64>;

/// Brent's method for a root of `f` in `[a, b]`, where `f(a)` and `f(b)` differ in sign.
/// Converges to `xtol` absolute plus a few ulps relative. Returns `None` without a sign change.
pub(crate) fn brent(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    xtol: f64,
    max_iter: usize,
) -> Option<f64> {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a), f(b));
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa.signum() == fb.signum() || !fa.is_finite() || !fb.is_finite() {
        return None;
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..max_iter {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Some(b);
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
    }
    Some(b)
}

/// A root located between two neighbouring scan samples whose signs differ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// The sample before the sign change, (x, f(x)).
    pub lo: (f64, f64),
    /// The sample after it, (x, f(x)).
    pub hi: (f64, f64),
    /// Brent's root in `[lo.0, hi.0]`; `None` only where `f` does not reproduce the samples'
    /// signs.
    pub root: Option<f64>,
}

impl Crossing {
    /// Whether f goes from negative to non-negative as x increases (for Re λ: the equilibrium
    /// loses stability with increasing x).
    pub fn rising_with_x(&self) -> bool {
        (self.hi.1 > self.lo.1) == (self.hi.0 > self.lo.0)
    }
}

/// Every sign change of `f` along a scan, located by `brent`: `samples` are (x, f(x)) in scan
/// order (evaluated lazily, so a caller wanting the first root stops the scan there); a pair of
/// neighbours brackets a root where both values are finite and one is negative while the other
/// is not. Each bracket is refined to `xtol(lo_x, hi_x)` absolute, in at most `max_iter`
/// iterations. Bifurcation sweeps, calibration targets and the chart's scan lines all locate
/// their Hopf points through this one function.
pub fn sign_change_roots<I, F, T>(
    samples: I,
    mut f: F,
    xtol: T,
    max_iter: usize,
) -> impl Iterator<Item = Crossing>
where
    I: IntoIterator<Item = (f64, f64)>,
    F: FnMut(f64) -> f64,
    T: Fn(f64, f64) -> f64,
{
    let mut prev: Option<(f64, f64)> = None;
    samples.into_iter().filter_map(move |cur| {
        let before = prev.replace(cur)?;
        let ((x0, f0), (x1, f1)) = (before, cur);
        if !(f0.is_finite() && f1.is_finite()) || (f0 < 0.0) == (f1 < 0.0) {
            return None;
        }
        Some(Crossing {
            lo: before,
            hi: cur,
            root: brent(&mut f, x0, x1, xtol(x0, x1), max_iter),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_roots_and_rejects_no_bracket() {
        let r = brent(|x| x * x - 2.0, 0.0, 2.0, 1e-15, 100).unwrap();
        assert!((r - 2f64.sqrt()).abs() < 1e-14);
        let r = brent(|x| x.cos() - x, 0.0, 1.0, 1e-15, 100).unwrap();
        assert!((r.cos() - r).abs() < 1e-14);
        assert!(brent(|x| x * x + 1.0, -1.0, 1.0, 1e-12, 100).is_none());
    }

    #[test]
    fn sign_change_roots_finds_each_crossing_in_order_and_skips_non_finite_pairs() {
        let f = |x: f64| x.sin();
        let xs = (0..=20).map(|i| 0.5 + 0.5 * i as f64);
        let found: Vec<Crossing> =
            sign_change_roots(xs.map(|x| (x, f(x))), f, |_, _| 1e-14, 100).collect();
        let roots: Vec<f64> = found.iter().map(|c| c.root.unwrap()).collect();
        assert_eq!(roots.len(), 3);
        for (k, r) in roots.iter().enumerate() {
            assert!(
                (r - std::f64::consts::PI * (k + 1) as f64).abs() < 1e-13,
                "{r}"
            );
        }
        assert!(!found[0].rising_with_x() && found[1].rising_with_x());
        // A NaN sample breaks the bracket on both of its sides.
        let samples = [(0.0, -1.0), (1.0, f64::NAN), (2.0, 1.0), (3.0, -1.0)];
        let got: Vec<Crossing> =
            sign_change_roots(samples, |x| 2.5 - x, |_, _| 1e-12, 100).collect();
        assert_eq!(got.len(), 1);
        assert_eq!(got[0].lo.0, 2.0);
    }
}
