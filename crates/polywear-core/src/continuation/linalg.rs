//! Small dense linear algebra for the Hopf system: the bialternate product, the adjugate (for
//! the exact gradient of a determinant that vanishes on the curve), eigenvalues and null vectors.

use nalgebra::{Complex, DMatrix, DVector};

use super::CVector;

/// The bialternate product 2A⊙I (Kuznetsov §10.2.2, eq. 10.48): an m×m matrix, m = n(n−1)/2,
/// whose eigenvalues are the sums λ_i + λ_j (i < j) of A's eigenvalues. Its determinant vanishes
/// where a pair of eigenvalues sums to zero: at a Hopf point (±iω) or a neutral saddle (±κ).
/// Rows and columns are indexed by the pairs (p, q), p > q, in lexicographic order.
pub(crate) fn bialternate(a: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    let pairs: Vec<(usize, usize)> = (1..n).flat_map(|p| (0..p).map(move |q| (p, q))).collect();
    let m = pairs.len();
    DMatrix::from_fn(m, m, |row, col| {
        let (p, q) = pairs[row];
        let (r, s) = pairs[col];
        if r == p && s == q {
            a[(p, p)] + a[(q, q)]
        } else if r == q {
            -a[(p, s)]
        } else if r != p && s == q {
            a[(p, r)]
        } else if r == p && s != q {
            a[(q, s)]
        } else if s == p {
            -a[(q, r)]
        } else {
            0.0
        }
    })
}

/// The adjugate adj(M) (transposed cofactors): d det(M) = tr(adj(M) dM) holds also where M is
/// singular, which is exactly where the Hopf test function is differentiated.
pub(crate) fn adjugate(m: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    if n == 1 {
        return DMatrix::from_element(1, 1, 1.0);
    }
    DMatrix::from_fn(n, n, |i, j| {
        // Cofactor of (j, i): delete row j and column i.
        let minor = m.clone().remove_row(j).remove_column(i);
        let sign = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
        sign * minor.determinant()
    })
}

/// Eigenvalues of a real square matrix; `None` where the Schur iteration does not converge.
pub fn eigenvalues(a: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    let schur = a.clone().try_schur(f64::EPSILON, 10_000)?;
    Some(schur.complex_eigenvalues().iter().copied().collect())
}

/// A unit null vector of the (nearly) singular complex matrix m: the right singular vector of
/// its smallest singular value.
pub(crate) fn null_vector(m: &DMatrix<Complex<f64>>) -> Option<CVector> {
    let svd = m.clone().try_svd(false, true, f64::EPSILON, 10_000)?;
    let v_t = svd.v_t?;
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))?
        .0;
    // m = U Σ Vᴴ: the k-th right singular vector is the conjugated k-th row of Vᴴ.
    let v: CVector = v_t.row(k).transpose().map(|c| c.conj());
    let norm = v.norm();
    (norm > 0.0).then(|| v / Complex::new(norm, 0.0))
}

/// ⟨p, q⟩ = p̄ᵀ q (Kuznetsov's scalar product).
pub(crate) fn dot(p: &CVector, q: &CVector) -> Complex<f64> {
    p.iter().zip(q.iter()).map(|(a, b)| a.conj() * b).sum()
}

/// Solves a real linear system after scaling each row to unit largest entry (the Hopf system
/// mixes equations of very different sizes: m/s, m/s², and a determinant in 1/s³).
pub(crate) fn solve_equilibrated(
    mut j: DMatrix<f64>,
    mut rhs: DVector<f64>,
) -> Option<DVector<f64>> {
    for i in 0..j.nrows() {
        let s = j.row(i).amax();
        if s > 0.0 && s.is_finite() {
            j.row_mut(i).scale_mut(1.0 / s);
            rhs[i] /= s;
        }
    }
    let x = j.lu().solve(&rhs)?;
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bialternate_eigenvalues_are_pairwise_sums() {
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, 2.0, 0.5, -1.0, //
                -3.0, 0.2, 1.0, 0.0, //
                0.3, -0.7, -2.0, 1.5, //
                1.0, 0.0, 0.4, 0.9,
            ],
        );
        let ev = eigenvalues(&a).unwrap();
        let mut sums: Vec<Complex<f64>> = Vec::new();
        for i in 0..4 {
            for j in 0..i {
                sums.push(ev[i] + ev[j]);
            }
        }
        let b = bialternate(&a);
        assert_eq!(b.nrows(), 6);
        let eb = eigenvalues(&b).unwrap();
        for s in &sums {
            let nearest = eb
                .iter()
                .map(|e| (e - s).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-9, "sum {s} not among {eb:?}");
        }
        let prod: Complex<f64> = sums.iter().product();
        assert!((b.determinant() - prod.re).abs() < 1e-9 * prod.norm());
    }

    #[test]
    fn adjugate_gives_the_determinants_derivative() {
        let m = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 3.0, 0.5, -1.0, 2.0, 4.0, 0.1, 1.0]);
        let dm = DMatrix::from_row_slice(3, 3, &[0.3, -0.2, 0.1, 1.0, 0.0, 0.5, -0.4, 0.7, 0.2]);
        let h = 1e-6;
        let fd = ((&m + &dm * h).determinant() - (&m - &dm * h).determinant()) / (2.0 * h);
        let exact = (adjugate(&m) * &dm).trace();
        assert!((fd - exact).abs() < 1e-7 * exact.abs().max(1.0));
        // Singular matrices too.
        let s = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        assert_eq!(
            adjugate(&s),
            DMatrix::from_row_slice(2, 2, &[4.0, -2.0, -2.0, 1.0])
        );
    }
}
