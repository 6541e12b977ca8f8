//! Levenberg–Marquardt for the calibration's least squares.
//!
//! Our own 60 lines rather than the `levenberg-marquardt` crate (5 more crates, 1.1 CPU-s of
//! release build on top of our nalgebra): the crate's MINPACK trust region takes other steps,
//! so the shipped fitted constants would no longer be reproduced, and it has no rejected
//! step for a parameter set the model refuses (our residuals return `None` there).

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Levenberg–Marquardt on a residual vector, with central-difference Jacobians.
/// Returns (x, cost = Σ r², evaluations).
pub fn levenberg_marquardt(
    f: impl Fn(&[f64]) -> Option<Vec<f64>>,
    x0: &[f64],
    max_iter: usize,
) -> (Vec<f64>, f64, usize) {
    let n = x0.len();
    let mut x = x0.to_vec();
    let mut r = f(&x).expect("the starting point is valid");
    let mut cost = sum_sq(&r);
    let mut evals = 1;
    let mut lambda = 1e-3;
    let h = 1e-5;
    for _ in 0..max_iter {
        let mut jac = nalgebra::DMatrix::<f64>::zeros(r.len(), n);
        for j in 0..n {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[j] += h;
            xm[j] -= h;
            evals += 2;
            if let (Some(rp), Some(rm)) = (f(&xp), f(&xm)) {
                for i in 0..r.len() {
                    jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * h);
                }
            }
        }
        let jt = jac.transpose();
        let jtj = &jt * &jac;
        let g = &jt * nalgebra::DVector::from_column_slice(&r);
        let mut improved = false;
        for _ in 0..20 {
            let mut a = jtj.clone();
            for k in 0..n {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(step) = a.lu().solve(&(-&g)) else {
                lambda *= 10.0;
                continue;
            };
            let xn: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            evals += 1;
            match f(&xn) {
                Some(rn) if sum_sq(&rn) < cost => {
                    x = xn;
                    r = rn;
                    cost = sum_sq(&r);
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = true;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !improved || cost < 1e-24 || g.norm() < 1e-14 {
            break;
        }
    }
    (x, cost, evals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levenberg_marquardt_finds_the_rosenbrock_minimum() {
        let f = |x: &[f64]| Some(vec![1.0 - x[0], 10.0 * (x[1] - x[0] * x[0])]);
        let (x, fx, _) = levenberg_marquardt(f, &[-1.2, 1.0], 500);
        assert!(
            fx < 1e-16 && (x[0] - 1.0).abs() < 1e-7 && (x[1] - 1.0).abs() < 1e-7,
            "{x:?} {fx}"
        );
    }
}
