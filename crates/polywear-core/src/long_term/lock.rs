//! Lock-in and the averaging that keeps an unlocked print from adding up
//! (MODEL.md#the-long-term-loop). A cycle of ρ periods per revolution prints its k-th harmonic
//! 2πkρ further round the tyre each revolution; over many revolutions those prints cancel
//! (MODEL.md#step-11-wear-zone), and only what is fixed to the tyre (the even wear, the response
//! at whole multiples of the rotation) wears on. The long-term loop scales one window's mean
//! revolution by thousands of revolutions, so its mean must cancel the drifting prints exactly,
//! not merely average them down: `revolution_weights` are the weights of smallest norm that
//! sum to 1 and annihilate the drifts e^{i2πkρj} of the first few harmonics.

use nalgebra::{DMatrix, DVector};

/// ρ within this of a whole number over the window: locked.
pub(crate) const LOCK_TOLERANCE: f64 = 1e-3;

/// Harmonics of the cycle whose drifting prints the weights annihilate.
pub(crate) const DRIFT_HARMONICS: usize = 3;

/// Fewest and most measured revolutions of a window.
pub(crate) const WINDOW_REVS: (usize, usize) = (3, 40);

/// The rotation number ρ: cycle periods (upward crossings of v = 0, `crossings_s`) per
/// revolution of period `t_rev_s`, from the first crossing to the last; NaN with fewer than
/// two crossings (no cycle).
pub fn rotation_number(crossings_s: &[f64], t_rev_s: f64) -> f64 {
    match (crossings_s.first(), crossings_s.last()) {
        (Some(first), Some(last)) if crossings_s.len() >= 2 && last > first => {
            (crossings_s.len() - 1) as f64 * t_rev_s / (last - first)
        }
        _ => f64::NAN,
    }
}

/// Whether ρ is a whole number to `LOCK_TOLERANCE` (false for NaN).
pub fn is_locked(rho: f64) -> bool {
    (rho - rho.round()).abs() < LOCK_TOLERANCE
}

/// The distance of x from the nearest whole number, in (−½, ½\].
pub fn detuning(x: f64) -> f64 {
    x - x.round()
}

/// Measured revolutions of a window for a cycle of ρ periods per revolution (NaN: no cycle):
/// long enough that the slowest drift among the first [`DRIFT_HARMONICS`] harmonics turns
/// twice, ⌈2/min_k |δ(kρ)|⌉, and at least 2K + 1 so that K drifts can be annihilated. A
/// harmonic whose drift the longest window could not turn twice (|δ(kρ)| < 2/40) counts as
/// fixed to the tyre: locked, or so near lock that its print does add up over that stretch. A
/// tread without a cycle takes the fewest revolutions, one locked or near lock the most.
pub(crate) fn window_revs(rho: f64) -> usize {
    let (lo, hi) = WINDOW_REVS;
    if rho.is_nan() {
        return lo;
    }
    let resolvable = 2.0 / hi as f64;
    let slowest = (1..=DRIFT_HARMONICS)
        .map(|k| detuning(k as f64 * rho).abs())
        .filter(|d| *d >= resolvable)
        .fold(f64::INFINITY, f64::min);
    if is_locked(rho) || slowest.is_infinite() {
        return hi;
    }
    // (Less a rounding's worth, so that a drift of exactly 2/N takes N revolutions.)
    ((2.0 / slowest - 1e-9).ceil() as usize).clamp((2 * DRIFT_HARMONICS + 1).max(lo), hi)
}

/// Weights w_j of the `revs` measured revolutions: Σ w_j = 1, and Σ w_j e^{±i2πkρj} = 0 for
/// every harmonic k ≤ [`DRIFT_HARMONICS`] whose drift the window resolves (|δ(kρ)|·revs ≥ ½), of
/// least Σ w_j². Uniform (1/revs) for a locked cycle or none (ρ NaN): every print is fixed to
/// the tyre then.
pub(crate) fn revolution_weights(revs: usize, rho: f64) -> Vec<f64> {
    let uniform = vec![1.0 / revs as f64; revs];
    if rho.is_nan() || is_locked(rho) {
        return uniform;
    }
    let mut rows: Vec<Vec<f64>> = vec![vec![1.0; revs]];
    let mut drifts: Vec<f64> = Vec::new();
    for k in 1..=DRIFT_HARMONICS {
        let d = detuning(k as f64 * rho);
        // Two harmonics with the same drift (or opposite ones) share their rows.
        let seen = drifts.iter().any(|e| (e.abs() - d.abs()).abs() < 1e-9);
        if d.abs() * revs as f64 >= 0.5 && !seen {
            drifts.push(d);
            let phase = |j: usize| std::f64::consts::TAU * d * j as f64;
            rows.push((0..revs).map(|j| phase(j).cos()).collect());
            // At a drift of exactly half a turn the sine row vanishes: nothing to annihilate.
            let sine: Vec<f64> = (0..revs).map(|j| phase(j).sin()).collect();
            if sine.iter().map(|s| s * s).sum::<f64>() > 1e-6 * revs as f64 {
                rows.push(sine);
            }
        }
    }
    if rows.len() > revs {
        return uniform;
    }
    let a = DMatrix::from_fn(rows.len(), revs, |i, j| rows[i][j]);
    let mut b = DVector::zeros(rows.len());
    b[0] = 1.0;
    // w = Aᵀ (A Aᵀ)⁻¹ b, the least-norm solution.
    let gram = &a * a.transpose();
    match gram.cholesky() {
        Some(c) => {
            let w = a.transpose() * c.solve(&b);
            w.iter().copied().collect()
        }
        None => uniform,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weights sum to one and cancel the first harmonics' drifts exactly; a drifting print
    /// averaged by them is gone, where the plain mean leaves C_N(δ) of it.
    #[test]
    fn weights_annihilate_the_drifting_prints() {
        for rho in [19.36, 19.5, 20.64, 13.1, 27.77] {
            let revs = window_revs(rho);
            let w = revolution_weights(revs, rho);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{rho}");
            for k in 1..=DRIFT_HARMONICS {
                let d = detuning(k as f64 * rho);
                if d.abs() * (revs as f64) < 0.5 {
                    continue; // fixed to the tyre over the window: kept, not cancelled
                }
                let (mut re, mut im) = (0.0, 0.0);
                for (j, wj) in w.iter().enumerate() {
                    re += wj * (std::f64::consts::TAU * d * j as f64).cos();
                    im += wj * (std::f64::consts::TAU * d * j as f64).sin();
                }
                assert!(re.hypot(im) < 1e-12, "{rho} k {k}: {re} {im}");
            }
            // The plain mean leaves the first harmonic's coherence factor.
            let d = detuning(rho);
            let plain: f64 = ((std::f64::consts::PI * revs as f64 * d).sin()
                / (revs as f64 * (std::f64::consts::PI * d).sin()))
            .abs();
            let whole_turns = (revs as f64 * d).round() == revs as f64 * d
                || ((revs as f64 * d) - (revs as f64 * d).round()).abs() < 1e-9;
            assert!(plain > 1e-3 || whole_turns, "{rho}: {plain}");
        }
        assert_eq!(revolution_weights(5, 19.0002), vec![0.2; 5]);
        assert_eq!(revolution_weights(4, f64::NAN), vec![0.25; 4]);
    }

    #[test]
    fn rotation_number_and_window_length() {
        // 19.36 periods per revolution of 0.1 s.
        let t: Vec<f64> = (0..50).map(|k| 0.013 + k as f64 * 0.1 / 19.36).collect();
        let rho = rotation_number(&t, 0.1);
        assert!((rho - 19.36).abs() < 1e-12, "{rho}");
        assert!(!is_locked(rho) && is_locked(19.0004) && !is_locked(f64::NAN));
        assert!(rotation_number(&t[..1], 0.1).is_nan());
        // δ = 0.36, 2δ → −0.28, 3δ → 0.08: the third harmonic sets 25 revolutions.
        assert_eq!(window_revs(19.36), 25);
        assert_eq!(window_revs(19.1), 20);
        assert_eq!(window_revs(19.5), 7);
        assert_eq!(window_revs(19.0), WINDOW_REVS.1);
        assert_eq!(window_revs(f64::NAN), WINDOW_REVS.0);
    }
}
