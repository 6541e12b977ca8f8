//! The drift of the tread frequency over the tread's life (MODEL.md#the-ageing-tread): f₀/f as
//! the tread wears, and the worn depth as a polynomial in it.

use super::*;

/// f₀/f(h₀ − w) over the worn depth w ∈ \[0, usable\]: the new tread's undamped frequency
/// √(K_s/m) over the worn one's (MODEL.md#the-ageing-tread; `worn_tread_block`).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TreadDrift {
    pub(super) usable_m: f64,
    pub(super) ratio: Vec<f64>,
    /// The worn depth as a polynomial in r − 1, r = f₀/f: w(r) = Σ_k worn_poly\[k−1\] (r − 1)^k
    /// \[m\] (k = 1 … [`WORN_DEGREE`]; w(1) = 0), least squares through the table read
    /// backwards. Every node of every order reads it, and its derivative in x = n r weighs Ḡ
    /// in the distance.
    pub(super) worn_poly: [f64; WORN_DEGREE],
}

impl TreadDrift {
    pub(super) fn of(p: &Params, patch: &ContactPatch) -> Self {
        let usable_m = p.usable_wear_m().clamp(0.0, p.tread_height);
        let frequency = |h: f64| {
            let b = worn_tread_block(p, patch, h);
            (b.stiffness_n_per_m / b.mass_kg).sqrt()
        };
        let new = frequency(p.tread_height);
        let worn = |k: usize| usable_m * k as f64 / (DRIFT_POINTS - 1) as f64;
        let ratio = (0..DRIFT_POINTS)
            .map(|k| {
                if k == 0 {
                    1.0
                } else {
                    new / frequency(p.tread_height - worn(k))
                }
            })
            .collect::<Vec<f64>>();
        let span = 1.0 - ratio[DRIFT_POINTS - 1];
        let mut worn_poly = [0.0; WORN_DEGREE];
        if span > 0.0 && usable_m > 0.0 {
            // Least squares in v = (r − 1)/span ∈ [−1, 0] (normal equations: a 5×5 system
            // whose monomials on [−1, 0] are conditioned well enough), then unscaled.
            type Square = nalgebra::SMatrix<f64, WORN_DEGREE, WORN_DEGREE>;
            type Column = nalgebra::SVector<f64, WORN_DEGREE>;
            let (mut gram, mut rhs) = (Square::zeros(), Column::zeros());
            for (k, &r) in ratio.iter().enumerate() {
                let v = (r - 1.0) / span;
                let basis = Column::from_fn(|j, _| v.powi(j as i32 + 1));
                gram += basis * basis.transpose();
                rhs += basis * (worn(k) / usable_m);
            }
            if let Some(solution) = gram.cholesky().map(|c| c.solve(&rhs)) {
                let mut scale = usable_m;
                for (j, w) in worn_poly.iter_mut().enumerate() {
                    scale /= span;
                    *w = solution[j] * scale;
                }
            }
        }
        TreadDrift {
            usable_m,
            ratio,
            worn_poly,
        }
    }

    /// The worn depth at which f₀/f is `ratio` \[m\] (the ratio falls as the tread wears), from
    /// its polynomial; 0 above 1 and the usable depth below the end's.
    pub(super) fn worn_at(&self, ratio: f64) -> f64 {
        if ratio >= 1.0 {
            return 0.0;
        }
        if ratio <= self.at_end() {
            return self.usable_m;
        }
        let v = ratio - 1.0;
        let inner = self.worn_poly.iter().rev().fold(0.0, |acc, &b| acc * v + b);
        (inner * v).clamp(0.0, self.usable_m)
    }

    /// e_m such that the worn depth's slope along order n's path is
    /// dw(x/n)/dx = Σ_m e_m x^m / n^{m+1} (m < [`WORN_DEGREE`]): w′(r) = Σ_k k b_k (r − 1)^{k−1}
    /// expanded in powers of r = x/n.
    pub(super) fn slope_coefficients(&self) -> [f64; WORN_DEGREE] {
        let mut e = [0.0; WORN_DEGREE];
        for (k1, &b) in self.worn_poly.iter().enumerate() {
            // Term k = k1 + 1: k b_k (r − 1)^{k1} = k b_k Σ_m C(k1, m) r^m (−1)^{k1−m}.
            let mut binomial = 1.0;
            for (m, em) in e.iter_mut().enumerate().take(k1 + 1) {
                let sign = if (k1 - m) % 2 == 0 { 1.0 } else { -1.0 };
                *em += (k1 + 1) as f64 * b * binomial * sign;
                binomial = binomial * (k1 - m) as f64 / (m + 1) as f64;
            }
        }
        e
    }

    /// f₀/f at the worn depth `worn_m` \[m\]: [`TreadDrift::worn_at`] inverted by bisection
    /// (it falls with the ratio), so that a grid of depths and the integrals' weights read one
    /// polynomial; 1 at no wear and the end's ratio at the usable depth and beyond.
    pub(super) fn ratio_at(&self, worn_m: f64) -> f64 {
        let end = self.at_end();
        if worn_m <= 0.0 || end >= 1.0 {
            return 1.0;
        }
        if worn_m >= self.usable_m {
            return end;
        }
        let (mut lo, mut hi) = (end, 1.0);
        // 52 halvings take the bracket below an ulp of 1.
        for _ in 0..52 {
            let mid = 0.5 * (lo + hi);
            if self.worn_at(mid) > worn_m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// f₀/f of the worn-out tire.
    pub(super) fn at_end(&self) -> f64 {
        self.ratio[DRIFT_POINTS - 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tire::contact_patch;

    /// The table's end is the ageing law's f/f₀ ≈ √((h₀/h)/(c + (1 − c) h/h₀)) (the bending
    /// term under 0.6%), for the carcass shares of its bound and the 1/h law (c = 0); a new
    /// tread does not drift; the worn depth read from its polynomial is within 10⁻⁶ of the
    /// usable depth of the ageing law's own (measured: 2.5·10⁻⁷ at c = 0.3) (at depths between the table's points too), and the
    /// slope the orders' integrals weigh Ḡ with is its derivative.
    #[test]
    fn the_drift_follows_the_ageing_tread() {
        for (c, mu) in [
            (0.0, 0.0),
            (0.3, 0.0),
            (0.5, 0.0),
            (0.7, 0.0),
            (0.5, 0.3),
            (0.3, 0.7),
        ] {
            let p = Params {
                carcass_share: c,
                belt_mass_share: mu,
                ..crate::wear::physics::fitted::pinned_params()
            };
            let patch = contact_patch(&p).unwrap();
            let drift = TreadDrift::of(&p, &patch);
            let usable = p.usable_wear_m();
            let h = (p.tread_height - usable) / p.tread_height;
            // The mass's fall (the belt's share of it not wearing) over the compliance's.
            let law = ((1.0 / (mu + (1.0 - mu) * h)) / (c + (1.0 - c) * h)).sqrt();
            let end = 1.0 / drift.at_end();
            assert!(
                (end / law - 1.0).abs() < 0.01,
                "c = {c}: {end} against {law}"
            );
            assert_eq!(drift.ratio[0], 1.0);
            // Monotone: the tread only stiffens and lightens as it wears.
            assert!(drift.ratio.windows(2).all(|w| w[1] < w[0]), "c = {c}");
            // f₀/f at the worn depth w, from the ageing law itself.
            let frequency = |h: f64| {
                let b = worn_tread_block(&p, &patch, h);
                (b.stiffness_n_per_m / b.mass_kg).sqrt()
            };
            let ratio = |w: f64| frequency(p.tread_height) / frequency(p.tread_height - w);
            let mut worst: f64 = 0.0;
            for k in 0..=100 {
                let w = usable * k as f64 / 100.0;
                worst = worst.max((drift.worn_at(ratio(w)) - w).abs() / usable);
            }
            assert!(worst < 1e-6, "c = {c}: {worst}");
            assert_eq!(drift.worn_at(1.5), 0.0);
            assert_eq!(drift.worn_at(0.5 * drift.at_end()), usable);
            // dw(x/n)/dx = Σ e_m x^m/n^{m+1} against a central difference, at n = 20.
            let (e, n) = (drift.slope_coefficients(), 20.0);
            for k in 1..10 {
                let x = n * (1.0 - (1.0 - drift.at_end()) * k as f64 / 10.0);
                let step = 1e-4;
                let difference =
                    (drift.worn_at((x + step) / n) - drift.worn_at((x - step) / n)) / (2.0 * step);
                let series: f64 = (0..WORN_DEGREE)
                    .map(|m| e[m] * x.powi(m as i32) / n.powi(m as i32 + 1))
                    .sum();
                assert!(
                    (series / difference - 1.0).abs() < 1e-6,
                    "c = {c}, x = {x}: {series} {difference}"
                );
            }
        }
    }
}
